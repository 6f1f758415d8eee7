"""Sweeps under faults (slow): a Dask worker killed in the middle of the sweep, and the client killed
mid-sweep then resumed.  Every process here is started by the test and ended by its id."""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

from test_sweep import _free_port, read_csv

# cases of ~0.5 s each (RK4 at 1 us, 0.4 s simulated): the sweep is still running when the first is done
CASES = ("--revolutions", "1", "--integrator", "rk4", "--step", "1e-6", "--no-plots",
         "--vary", "restitution=0.5,0.6,0.7,0.8", "--seeds", "2")


def _finished(out) -> list:
    return sorted((out / "cases").glob("*/case.json")) if (out / "cases").exists() else []


def _wait_for(condition, timeout, what):
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            pytest.fail(f"timed out waiting for {what}")
        time.sleep(0.2)


def _fingerprints(paths) -> dict:
    """Content hash and modification time of every file of each finished case's folder."""
    return {f: (hashlib.sha256(f.read_bytes()).hexdigest(), f.stat().st_mtime_ns)
            for case in paths for f in sorted(case.parent.rglob("*")) if f.is_file()}


def _stop(procs):
    for p in procs:
        if p.poll() is None:
            p.terminate()
    for p in procs:
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


@pytest.mark.slow
def test_a_worker_killed_during_the_sweep_leaves_its_case_to_another(tmp_path):
    dask = shutil.which("dask") or pytest.skip("no dask command")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = open(tmp_path / "dask.log", "w")
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                              stdout=logs, stderr=logs)]
    try:
        time.sleep(3)
        workers = [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-dashboard", "--no-nanny",
                                     "--name", f"w{k}"], stdout=logs, stderr=logs) for k in range(2)]
        procs += workers
        time.sleep(3)
        out = tmp_path / "out"
        client = subprocess.Popen([sys.executable, "-m", "wearjoint.cli", "sweep", "simulate", *CASES,
                                   "--scheduler", address, "--out", str(out), "--quiet"],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        procs.append(client)
        _wait_for(lambda: len(_finished(out)) >= 1 or client.poll() is not None, 600, "a first finished case")
        before = _fingerprints(_finished(out))
        assert 1 <= len(before) and len(_finished(out)) < 8, "the sweep finished before the kill"
        os.kill(workers[0].pid, signal.SIGKILL)           # w0 is in the middle of its next case
        time.sleep(2)                                     # a result w0 sent just before still lands
        done_at_kill = {path.parent.name for path in _finished(out) if path.name == "case.json"}
        _, stderr = client.communicate(timeout=1200)
        assert client.returncode == 0, stderr
        rows = read_csv(out / "sweep.csv")
        assert len(rows) == 8 and all(r["status"] == "ok" for r in rows)
        after = _fingerprints(_finished(out))
        assert {f: after[f] for f in before} == before    # nothing finished was run or written again
        assert json.loads((out / "sweep_summary.json").read_text())["cases_run"] == 8
        later = [r for r in rows if r["case_id"] not in done_at_kill]
        assert later and all(r["worker"].endswith(f":{workers[1].pid}") for r in later)   # the survivor ran them
    finally:
        _stop(procs)
        logs.close()


@pytest.mark.slow
def test_a_client_killed_mid_sweep_is_completed_by_resume(tmp_path):
    out = tmp_path / "out"
    client = subprocess.Popen([sys.executable, "-m", "wearjoint.cli", "sweep", "simulate", *CASES, "--workers", "2",
                               "--out", str(out), "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    try:
        _wait_for(lambda: len(_finished(out)) >= 2 or client.poll() is not None, 900, "two finished cases")
        os.killpg(client.pid, signal.SIGKILL)                # the client and its LocalCluster's workers
        client.wait(timeout=60)
    finally:
        if client.poll() is None:
            os.killpg(client.pid, signal.SIGKILL)
            client.wait()
    finished = _finished(out)
    assert 2 <= len(finished) < 8, "the sweep finished before the kill"
    before = _fingerprints(finished)
    done = subprocess.run([sys.executable, "-m", "wearjoint.cli", "sweep", "simulate", *CASES, "--workers", "2",
                           "--out", str(out), "--quiet", "--resume"], capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "sweep_summary.json").read_text())
    assert summary["skipped_as_done"] == len(finished) and summary["cases_run"] == 8 - len(finished)
    after = _fingerprints(_finished(out))
    assert {f: after[f] for f in before} == before        # finished cases untouched, byte for byte
    assert [r["status"] for r in read_csv(out / "sweep.csv")] == ["ok"] * 8
