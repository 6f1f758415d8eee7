"""Ctrl-C and a run's results: during the run it stops the run (which keeps what it finished); once the run is over,
while its results are built and written, it waits for them.

A run ended by Ctrl-C while its results were written (3.5 s after 100 revolutions) kept a CSV and a figure, and no
summary.json; one ended between its last chunk and the writing kept nothing.  :func:`results_kept` holds such an
interrupt until its block ends, then raises it; :func:`writing_results` says, from inside the run, that the run is
over.  In any thread but the main one, or where SIGINT is not Python's default handler (a sweep's workers ignore it),
both do nothing.
"""
from __future__ import annotations

import contextlib
import signal
import sys
import threading

INTERRUPTED = "interrupted (Ctrl-C)"      # how a record's failure starts when Ctrl-C stopped its run

_held = {"active": False, "writing": False, "pending": False}


def _handler(signum, frame) -> None:
    if not _held["writing"]:
        raise KeyboardInterrupt
    if not _held["pending"]:
        print("wearjoint: Ctrl-C: the run is over, its results are being written; then it stops", file=sys.stderr,
              flush=True)
    _held["pending"] = True


@contextlib.contextmanager
def results_kept():
    """Within the block Ctrl-C raises KeyboardInterrupt as usual until :func:`writing_results`; after it, the
    interrupt is held until the block ends, and raised there."""
    if (threading.current_thread() is not threading.main_thread() or _held["active"]
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    previous = signal.signal(signal.SIGINT, _handler)
    _held.update(active=True, writing=False, pending=False)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        pending = _held["pending"]
        _held.update(active=False, writing=False, pending=False)
    if pending:
        raise KeyboardInterrupt


def stopped_by_ctrl_c(record) -> bool:
    """Whether Ctrl-C stopped the run of ``record`` (a RunRecord; its failure says so, or, from a record of an older
    version, it did not complete and says no failure)."""
    return not record.completed and (not record.failure or record.failure.startswith(INTERRUPTED))


def writing_results() -> None:
    """The run is over: a Ctrl-C from now until :func:`results_kept`'s block ends waits for the results."""
    if _held["active"]:
        _held["writing"] = True
