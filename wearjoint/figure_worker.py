"""A run's figures drawn by a second process that starts with the command (``python -m wearjoint.figure_worker``).

matplotlib's import and the four figures of a run cost about as much wall time as a short run itself.  The
second process, started as the command starts, imports them while the first simulates, then draws the record
the first sends it (pickled on its stdin by a thread while the first writes its CSV and NPZ files, with the
ideal joint's closed form the first has its kernels loaded for) and names the files it wrote on its stdout.  The
figures are the same :func:`wearjoint.plots.plot_run` draws.  On one core, or when the second process cannot
start or fails, :func:`wearjoint.results.write_results` draws them itself.
"""
from __future__ import annotations

import atexit
import json
import pickle
import subprocess
import sys
import threading

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
        self._sender = None
        if _cores() < 2:
            return
        try:
            self.process = subprocess.Popen(_command(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            stderr=subprocess.DEVNULL)
        except OSError:
            return
        atexit.register(self.close)

    def send(self, record, out) -> bool:
        """Hand the record to the worker (a thread writes it: the worker may still be importing); False if there
        is no worker."""
        if self.process is None:
            return False
        from .slider_crank import SliderCrank

        ideal = SliderCrank(record.parameters.mechanism).ideal_slider_acceleration()
        self._sender = threading.Thread(target=self._write, args=((record, str(out), ideal),), daemon=True)
        self._sender.start()
        return True

    def _write(self, message) -> None:
        try:
            pickle.dump(message, self.process.stdin, protocol=pickle.HIGHEST_PROTOCOL)
            self.process.stdin.close()
        except (OSError, ValueError, pickle.PicklingError, AttributeError, TypeError):
            pass                            # the worker is gone: names() says so

    def names(self) -> list[str] | None:
        """The figures' file names once the worker wrote them, None if it failed."""
        if self.process is None:
            return None
        if self._sender is not None:
            self._sender.join(TIMEOUT_S)
        self.process.stdin = None               # sent and closed: communicate() only reads the answer
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
    from wearjoint.plots import plot_run       # imported before the record arrives: what the first does not wait for

    record, out, ideal = pickle.load(sys.stdin.buffer)
    print(json.dumps(plot_run(record, out, ideal)))


if __name__ == "__main__":
    _draw()
