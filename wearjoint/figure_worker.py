"""A run's figures drawn by a second process that starts with the command (``python -m wearjoint.figure_worker``).

matplotlib's import and the four figures of a run cost about as much wall time as a short run itself.  The
second process, started as the command starts (before numba loads), imports matplotlib while the first
simulates (0.23 s: the record is there when it is done; a dummy figure drawn first to load the fonts cost 0.05-0.07
s and saved the first figure 0.01 s).  Then it draws the record the first hands it, pickled into
a temporary file with the ideal joint's closed form (the first has its kernels loaded): through a pipe, a
writing thread and the first process's CSV loops took turns on the GIL, 0.25 s for a revolution's samples.
Half the figures are drawn by a forked child on the core the waiting first process leaves free; the files'
names go to stdout.  The figures are the same :func:`wearjoint.plots.plot_run` draws.  On one core, or when
the second process cannot start or fails, :func:`wearjoint.results.write_results` draws them itself.
"""
from __future__ import annotations

import atexit
import json
import os
import pickle
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass

TIMEOUT_S = 300.0       # a figure worker that has not answered by then is stopped (the first process draws)
CHILD_FIGURES = (2, 3)  # the figures (indices of wearjoint.plots.run_figures) the worker's forked child draws


def _cores() -> int:
    from ._compile.prefetch import usable_cores

    return usable_cores()


def _command() -> list[str]:
    return [sys.executable, "-m", __name__]


@dataclass(frozen=True)
class FigureData:
    """What :func:`wearjoint.plots.plot_run` reads of a :class:`wearjoint.results.RunRecord`: arrays and numbers,
    which unpickle without importing the package's kernels (the record's classes would load numba, 0.25 s)."""

    samples: object               # (n, layout.N_SAMPLE_COLUMNS) array
    period_s: float
    clearance_m: float
    phi_deg: object               # bushing point angles [deg]
    wear_depth_m: object          # [m] at phi_deg
    revolutions: float
    last_revolution_index: int
    clearance_joint: str          # the joint that wears (its bushing's frame: the profile's angles)

    @classmethod
    def of(cls, record) -> "FigureData":
        return cls(record.samples, record.period_s, record.clearance_m, record.phi_deg, record.wear_depth_m,
                   record.revolutions, record.last_revolution(), record.clearance_joint)

    def last_revolution(self) -> int:
        return self.last_revolution_index


class FigureWorker:
    """The second process: :meth:`send` a record and its folder, then :meth:`names` waits for the figures."""

    def __init__(self):
        self.process = None
        self._record_file = None
        if _cores() < 2:
            return
        try:
            self.process = subprocess.Popen(_command(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            stderr=subprocess.DEVNULL)
        except OSError:
            return
        atexit.register(self.close)

    def send(self, record, out) -> bool:
        """Hand the record to the worker (its file's name on the worker's stdin); False if there is no worker."""
        if self.process is None:
            return False
        from .slider_crank import SliderCrank

        ideal = SliderCrank(record.parameters.mechanism).ideal_slider_acceleration()
        try:
            descriptor, self._record_file = tempfile.mkstemp(prefix="wearjoint-figures-", suffix=".pickle")
            with os.fdopen(descriptor, "wb") as file:
                pickle.dump((FigureData.of(record), str(out), ideal), file, protocol=pickle.HIGHEST_PROTOCOL)
            self.process.stdin.write(self._record_file.encode() + b"\n")
            self.process.stdin.close()
        except (OSError, ValueError, pickle.PicklingError, AttributeError, TypeError):
            pass                            # the worker is gone (or the file could not be written): names() says so
        return True

    def names(self) -> list[str] | None:
        """The figures' file names once the worker wrote them, None if it failed."""
        if self.process is None:
            return None
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
        self._remove_record_file()
        return names if isinstance(names, list) else None

    def close(self) -> None:
        """Stop the worker if it still runs."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.process = None
        self._remove_record_file()

    def _remove_record_file(self) -> None:
        if self._record_file is not None:
            try:
                os.unlink(self._record_file)
            except OSError:
                pass
            self._record_file = None


def _draw() -> None:
    # Ctrl-C reaches the whole process group: the first process decides (it keeps a finished run's results and stops
    # this one itself), so a figure is not cut off while it waits for them
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    from wearjoint import plots     # imported while the first process simulates

    with open(sys.stdin.readline().rstrip("\n"), "rb") as file:
        record, out, ideal = pickle.load(file)
    names = [name for name, _ in plots.run_figures(record)]
    # the first process waits for this one, its core is free: a forked child draws the contact force and the polar
    # profile (0.18 s warm) while this one draws the slider's acceleration and the pin's orbit (0.15 s)
    child = os.fork() if hasattr(os, "fork") else -1
    if child == 0:
        status = 1
        try:
            plots.plot_run(record, out, ideal, only=CHILD_FIGURES)
            status = 0
        finally:
            os._exit(status)
    plots.plot_run(record, out, ideal, only=None if child < 0 else
                   [k for k in range(len(names)) if k not in CHILD_FIGURES])
    if child > 0 and os.waitpid(child, 0)[1] != 0:
        sys.exit(1)
    print(json.dumps(names), flush=True)
    os._exit(0)     # the first process waits for the exit: skip the interpreter's teardown (~0.2 s)


if __name__ == "__main__":
    _draw()
