"""`wearjoint sensitivity` whose runs fail: exit status 1 with one line on stderr saying how many failed and where each
is listed (it said nothing there: the failures went to stdout only), and a summary.json without NaN."""
import contextlib
import json
import os
import socket
import subprocess
import sys

import pytest


@contextlib.contextmanager
def _port_in_use(port: int):
    """``port`` of this machine taken while the block runs (by this socket, or already by another process)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as held:
        with contextlib.suppress(OSError):
            held.bind(("", port))
            held.listen()
        yield


def test_a_study_whose_runs_fail_says_so_on_stderr_in_one_line(tmp_path):
    """A slider load far too large: every run's pin goes through the bushing wall (diverged).  With Dask's default
    dashboard port taken (another study running) the line is still the only one: the local cluster said "UserWarning:
    Port 8787 is already in use" on stderr."""
    out, temporary = tmp_path / "s", tmp_path / "tmp"
    temporary.mkdir()
    with _port_in_use(8787):
        done = subprocess.run([sys.executable, "-m", "wearjoint", "sensitivity", "simulate", "--workers", "1", "--samples",
                               "2", "--no-law-spread", "--revolutions", "0.02", "--param",
                               "slider-force-N=1e7,1e8,log", "--out", str(out), "--no-plots", "--quiet"],
                              capture_output=True, text=True, timeout=600, env={**os.environ, "TMPDIR": str(temporary)})
    assert done.returncode == 1, done.stderr
    # the workers' scratch space goes with the cluster (Dask's default left TMPDIR/dask-scratch-space behind)
    assert [p.name for p in temporary.iterdir() if "dask" in p.name] == []
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert lines[0].startswith("wearjoint sensitivity: error: 4 of 4 runs failed (each with its error: "
                               f"{out / 'samples.csv'}, summary.json's failures; the first: the run diverged at t = ")
    summary = json.loads((out / "summary.json").read_text(), parse_constant=lambda c: pytest.fail(f"{c} in JSON"))
    assert summary["failed"] == 4 and len(summary["failures"]) == 4
    assert all(value is None for value in summary["widest_interval"].values())


def test_the_failure_line_counts_invalid_runs_and_failed_law_variants():
    from wearjoint.cli.sensitivity import failure_line

    summary = {"failed": 0, "invalid": 2, "cases": 6, "failures": [{"case_id": "a", "error": "its pin went through; "
                                                                                             "more"}],
               "law_spread": {"failed": 1, "variants": [{}, {}, {}]}}
    assert failure_line(summary, "D") == (
        "wearjoint sensitivity: error: 0 of 6 runs failed, 2 gave numbers that are not physical (each with its error: "
        "D/samples.csv, summary.json's failures; the first: its pin went through); 1 of 3 contact law variants failed "
        "or are not physical (each with its error: D/law_spread.csv)")
    assert failure_line({**summary, "invalid": 0, "failures": [], "law_spread": None}, "D") == ""
