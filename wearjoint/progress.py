"""A dependency-free progress line with ETA on stderr."""
from __future__ import annotations

import sys
import time


class Progress:
    """Shows ``label: 42.0 % (t/total) elapsed, ETA`` once a run has taken
    ``quiet_s`` seconds; redraws in place on a terminal, else prints a line
    every 10 %."""

    def __init__(self, total: float, label: str, enabled: bool = True, quiet_s: float = 2.0, unit: str = "s"):
        self.total = float(total)
        self.label = label
        self.enabled = enabled
        self.quiet_s = quiet_s
        self.unit = unit
        self.start = time.perf_counter()
        self.last_draw = 0.0
        self.last_decile = -1
        self.tty = sys.stderr.isatty()
        self.drawn = False

    def update(self, done: float) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        elapsed = now - self.start
        if elapsed < self.quiet_s or self.total <= 0:
            return
        frac = min(1.0, done / self.total)
        decile = int(frac * 10)
        if self.tty and now - self.last_draw < 0.5 and frac < 1.0:
            return
        if not self.tty and decile == self.last_decile:
            return
        self.last_draw = now
        self.last_decile = decile
        eta = elapsed * (1.0 - frac) / frac if frac > 0 else float("nan")
        line = (f"{self.label}: {100 * frac:5.1f} % ({done:.4g}/{self.total:.4g} {self.unit}) "
                f"elapsed {elapsed:6.1f} s, ETA {eta:6.1f} s")
        sys.stderr.write(("\r" + line) if self.tty else (line + "\n"))
        sys.stderr.flush()
        self.drawn = True

    def close(self) -> None:
        if self.enabled and self.drawn and self.tty:
            sys.stderr.write("\n")
            sys.stderr.flush()
