"""A run's figures drawn by a second process that starts with the command (``python -m wearjoint.figure_worker``).

matplotlib's import and the four figures of a run cost about as much wall time as a short run itself.  The
second process imports them while the first simulates, then draws the record the first sends it (pickled on
its stdin, before the first writes its CSV and NPZ files) and names the files it wrote on its stdout.  The
figures are the same :func:`wearjoint.plots.plot_run` draws.  On one core, or when the second process cannot
start or fails, :func:`wearjoint.results.write_results` draws them itself.
"""
from __future__ import annotations

import atexit
import json
import pickle
import subprocess
import sys

TIMEOUT_S = 300.0       # a figure worker that has not answered by then is stopped (the first process draws)


def _cores() -> int:
    from ._compile.prefetch import usable_cores

    return usable_cores()


def _command() -> list[str]:
    return [sys.executable, "-m", __name__]


class FigureWorker:
    """The second process: :meth:`send` a record and its folder, then :meth:`names` waits for the figures."""

    def __init__(self):
        self.process = None
        if _cores() < 2:
            return
        try:
            self.process = subprocess.Popen(_command(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            stderr=subprocess.DEVNULL)
        except OSError:
            return
        atexit.register(self.close)

    def send(self, record, out) -> bool:
        """Hand the record to the worker; False (and the worker stopped) if it cannot take it."""
        if self.process is None:
            return False
        try:
            pickle.dump((record, str(out)), self.process.stdin, protocol=pickle.HIGHEST_PROTOCOL)
            self.process.stdin.close()
            return True
        except (OSError, pickle.PicklingError, AttributeError, TypeError):
            self.close()
            return False

    def names(self) -> list[str] | None:
        """The figures' file names once the worker wrote them, None if it failed."""
        if self.process is None:
            return None
        try:
            stdout, _ = self.process.communicate(timeout=TIMEOUT_S)
        except (OSError, subprocess.TimeoutExpired, ValueError):
            self.close()
            return None
        try:
            names = json.loads(stdout) if self.process.returncode == 0 else None
        except ValueError:
            names = None
        self.process = None
        return names if isinstance(names, list) else None

    def close(self) -> None:
        """Stop the worker if it still runs."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.process = None


def _draw() -> None:
    import numpy as np

    from wearjoint.mechanism import SliderCrank
    from wearjoint.parameters import SliderCrankParameters
    from wearjoint.plots import plot_run       # imported before the record arrives: what the first does not wait for

    SliderCrank(SliderCrankParameters()).closed_form(np.zeros(2))   # its kernels loaded too (numba's first load)
    record, out = pickle.load(sys.stdin.buffer)
    print(json.dumps(plot_run(record, out)))


if __name__ == "__main__":
    _draw()
