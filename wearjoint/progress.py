"""Progress of long runs on stderr: a bar on a terminal, plain lines in a log.

On a terminal (tqdm: elapsed, ETA, rate) the bar appears once a run has taken ``delay_s`` seconds and
redraws in place.  When the stream is not a terminal (stdout/stderr redirected to a file, pipes, CI),
where a bar would write nothing readable, one plain line is written every ``LOG_INTERVAL_S`` seconds of
wall time -- ``LABEL: 12.5% (500/4000 rev), elapsed 0:01:10, ETA 0:08:10`` -- and a last one when a run
that wrote any ends; a run shorter than the interval writes none.  tqdm is imported only when a bar is
shown.
"""
from __future__ import annotations

import math
import sys
import time

# n and total formatted short: simulated seconds or revolutions are not integers
_FORMAT = "{desc}: {percentage:5.1f}%|{bar}| {n:.4g}/{total:.4g} {unit} [{elapsed}<{remaining}, {rate_fmt}]"
# a run whose caller estimates its ETA (not proportional to the amount done): the ETA as postfix
_FORMAT_CALLER_ETA = "{desc}: {percentage:5.1f}%|{bar}| {n:.4g}/{total:.4g} {unit} [{elapsed}, {rate_fmt}{postfix}]"
LOG_INTERVAL_S = 15.0        # wall seconds between two lines of a redirected log


def _now() -> float:
    """The wall clock of the log lines (monotonic; a module function so that tests can set it)."""
    return time.monotonic()


def is_terminal(stream) -> bool:
    """Whether ``stream`` is a terminal (False for files, pipes and streams without ``isatty``)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):       # no isatty, or a closed stream
        return False


def clock_text(seconds: float) -> str:
    """``H:MM:SS`` of a duration (``?`` when not finite)."""
    if not math.isfinite(seconds):
        return "?"
    s = round(max(seconds, 0.0))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class _LogLines:
    """The plain lines of a non-terminal stream (see the module docstring)."""

    def __init__(self, total: float, label: str, unit: str, stream, interval_s: float):
        self.total, self.label, self.unit, self.stream, self.interval_s = total, label, unit, stream, interval_s
        self.start = self.last = _now()
        self.rate_from = (self.start, 0.0)      # (time, done) the ETA's rate is measured from: after compiling
        self.done = 0.0
        self.eta_s = None                       # the caller's ETA, if it gives one
        self.compiling = False
        self.written = 0

    def line(self, now: float) -> str:
        t0, d0 = self.rate_from
        rate = (self.done - d0) / (now - t0) if now > t0 and self.done > d0 else 0.0
        eta = self.eta_s if self.eta_s is not None else (self.total - self.done) / rate if rate > 0.0 else float("nan")
        label = f"{self.label} (compiling)" if self.compiling else self.label
        return (f"{label}: {100.0 * self.done / self.total:5.1f}% ({self.done:.4g}/{self.total:.4g} {self.unit}), "
                f"elapsed {clock_text(now - self.start)}, ETA {'~' if self.eta_s is not None else ''}{clock_text(eta)}")

    def write(self, text: str) -> None:
        try:
            print(text, file=self.stream, flush=True)
        except (OSError, ValueError):            # a closed or full log: progress is not worth failing a run
            pass
        self.written += 1

    def update(self, done: float, eta_s: float | None) -> None:
        self.done = done
        self.eta_s = eta_s
        now = _now()
        if now - self.last >= self.interval_s:
            self.last = now
            self.write(self.line(now))

    def compiled(self) -> None:
        self.compiling = False
        self.rate_from = (_now(), self.done)

    def close(self) -> None:
        if self.written:
            now = _now()
            self.write(self.line(now) if self.done < self.total else
                       f"{self.label}: 100.0% ({self.total:.4g} {self.unit}) in {clock_text(now - self.start)}")


class Progress:
    """``update(done)`` takes the amount done so far (absolute, in ``unit``).  With
    ``compiling=True`` the description reads "LABEL (compiling)" until :meth:`compiled`
    is called (numba compiles the kernels before the first chunk).  ``stream``: where it
    writes (default stderr); ``interval_s``: the seconds between the lines of a log.  ``caller_eta``:
    the caller passes the ETA to :meth:`update` (a run whose pace is not proportional to the amount
    done, such as cycle jumping's growing jumps) instead of the rate's."""

    def __init__(self, total: float, label: str, enabled: bool = True, unit: str = "s",
                 compiling: bool = False, delay_s: float = 2.0, stream=None, interval_s: float = LOG_INTERVAL_S,
                 caller_eta: bool = False):
        self.label = label
        self.total = float(total)
        self._bar = None
        self._log = None
        stream = sys.stderr if stream is None else stream
        if not (enabled and self.total > 0.0):
            return
        if not is_terminal(stream):
            self._log = _LogLines(self.total, label, unit, stream, interval_s)
            self._log.compiling = compiling
            return
        from tqdm import tqdm

        self._bar = tqdm(total=self.total, desc=f"{label} (compiling)" if compiling else label, unit=unit,
                         bar_format=_FORMAT_CALLER_ETA if caller_eta else _FORMAT, disable=None, delay=delay_s, mininterval=0.5,
                         dynamic_ncols=True, file=stream, leave=False)

    def compiled(self) -> None:
        """Compilation is over: the description becomes the plain label (and the bar of the
        compilations, :mod:`wearjoint._compile.notice`, closes)."""
        notice = sys.modules.get("wearjoint._compile.notice")   # loaded by the CLI
        if notice is not None:
            notice.compiled()
        if self._bar is not None:
            self._bar.set_description_str(self.label, refresh=False)
        if self._log is not None:
            self._log.compiled()

    def set_total(self, total: float) -> None:
        """The amount the bar counts to, changed (a count whose end is not known in advance)."""
        self.total = float(total)
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.refresh()
        if self._log is not None:
            self._log.total = self.total

    def update(self, done: float, eta_s: float | None = None) -> None:
        """``done`` so far; ``eta_s`` the caller's estimate of the seconds left (with ``caller_eta``)."""
        if self._bar is not None:
            if eta_s is not None:
                self._bar.set_postfix_str(f"ETA ~{clock_text(eta_s)}", refresh=False)
            step = min(float(done), self.total) - self._bar.n
            if step > 0.0:
                self._bar.update(step)
            else:                                   # nothing more done: the elapsed time still moves
                self._bar.refresh()
        if self._log is not None:
            self._log.update(min(float(done), self.total), eta_s)

    def close(self, final_line: bool = True) -> None:
        """Close; a log writes its last line unless ``final_line`` is False (a count nobody waits for any more)."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        if self._log is not None:
            if final_line:
                self._log.close()
            self._log = None
