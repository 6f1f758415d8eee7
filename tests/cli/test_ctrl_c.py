"""Ctrl-C and a run's results (wearjoint.interrupts): during the run it stops the run, which writes what it finished
and says so; once the run is over it waits for the results.  A new user's Ctrl-C while `cosim` wrote its results kept
a CSV and one figure and no summary.json, and an interrupted `simulate` said `failure: null`.

Each case runs the command in a process of its own session, where SIGINT goes to the whole process group as a
terminal's Ctrl-C does (the figure worker included).  An interrupted wear study says how far its checkpoint reached."""
import json
import signal
import subprocess
import sys
import textwrap

import pytest

from terminal_signals import default_sigint
from wearjoint.interrupts import INTERRUPTED, results_kept, writing_results

SCRIPT = textwrap.dedent("""
    import os, signal, sys
    import wearjoint.cli.{module} as command
    import wearjoint.runner as runner
    from wearjoint.cli import main

    def ctrl_c():
        os.killpg(os.getpgid(0), signal.SIGINT)        # as a terminal sends it: every process of the group

    if {while_writing}:
        write = command.write_results
        def interrupted_while_writing(*args, **kwargs):
            ctrl_c()
            return write(*args, **kwargs)
        command.write_results = interrupted_while_writing
    else:
        chunks, divergence = [], runner.divergence
        def interrupted_in_the_third_chunk(*args):
            chunks.append(1)
            if len(chunks) == 3:
                ctrl_c()
            return divergence(*args)
        runner.divergence = interrupted_in_the_third_chunk
    sys.exit(main(["{command}", "--revolutions", "0.5", "--out", sys.argv[1]]))
""")
FIGURES = {"slider_acceleration.png", "pin_orbit.png", "contact_force.png", "wear_profile.png"}


def _interrupted(tmp_path, command: str, while_writing: bool):
    out = tmp_path / "run"
    script = SCRIPT.format(module=command, command=command, while_writing=while_writing)
    done = subprocess.run([sys.executable, "-c", script, str(out)], capture_output=True, text=True, timeout=600,
                          start_new_session=True, preexec_fn=default_sigint)
    return done, out


@pytest.mark.parametrize("command", ["simulate", "cosim"])
def test_ctrl_c_while_the_results_are_written_waits_for_them(tmp_path, command):
    done, out = _interrupted(tmp_path, command, while_writing=True)
    assert done.returncode == 130, done.stderr
    assert "the run is over, its results are being written" in done.stderr
    assert done.stderr.rstrip().endswith(f"wearjoint {command}: interrupted"), done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is True and summary["failure"] is None
    written = {p.name for p in out.iterdir()}
    assert FIGURES <= written and {"profile.csv", "revolutions.csv", "report.html"} <= written, written


def test_ctrl_c_during_the_run_stops_it_and_says_so_in_the_summary(tmp_path):
    done, out = _interrupted(tmp_path, "simulate", while_writing=False)
    assert done.returncode == 130, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False
    assert summary["failure"].startswith(f"{INTERRUPTED} at t = ") and "of 0.2 s" in summary["failure"]
    assert 0.0 < summary["simulated_time_s"] < 0.2
    assert FIGURES <= {p.name for p in out.iterdir()}       # the figure worker ignored the Ctrl-C and drew them


def test_an_interrupt_is_held_only_once_the_run_is_over():
    """In this process (the main thread, Python's handler for SIGINT): raised at once before writing_results, held
    until the block ends after it."""
    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        pytest.skip("SIGINT is not Python's default handler here (a test worker's)")
    with pytest.raises(KeyboardInterrupt), results_kept():
        signal.raise_signal(signal.SIGINT)
        pytest.fail("not raised at once during the run")
    held = []
    with pytest.raises(KeyboardInterrupt), results_kept():
        writing_results()
        signal.raise_signal(signal.SIGINT)
        held.append("went on")
    assert held == ["went on"] and signal.getsignal(signal.SIGINT) is signal.default_int_handler


STUDY_SCRIPT = textwrap.dedent("""
    import os, signal, sys
    import wearjoint.studies.wear_study as study
    from wearjoint.cli import main

    written, write = [], study.write_checkpoint_atomic
    def interrupted_after_the_third_checkpoint(*args):
        write(*args)
        written.append(1)
        if len(written) == 3:
            os.kill(os.getpid(), signal.SIGINT)
    study.write_checkpoint_atomic = interrupted_after_the_third_checkpoint
    sys.exit(main(["wear-study", "--revolutions", "40", "--snapshots", "20,40", "--quiet", "--no-plots",
                   "--out", sys.argv[1]]))
""")


def test_an_interrupted_wear_study_says_how_far_its_checkpoint_reached(tmp_path):
    """It said "finished work is checkpointed in D" and nothing on disk said how far (snapshots.json's last
    revolution is the last snapshot's)."""
    from wearjoint.studies.wear_study_recovery import CHECKPOINT_NAME, checkpoint_revolution, read_checkpoint

    out = tmp_path / "study"
    done = subprocess.run([sys.executable, "-c", STUDY_SCRIPT, str(out)], capture_output=True, text=True, timeout=600,
                          preexec_fn=default_sigint)
    assert done.returncode == 130, done.stderr
    reached = checkpoint_revolution(read_checkpoint(out / CHECKPOINT_NAME))
    assert 0 < reached < 40
    assert done.stderr.strip().endswith(f"interrupted; finished work is checkpointed in {out} up to revolution "
                                        f"{reached:.6g} (continue with --resume)"), done.stderr
