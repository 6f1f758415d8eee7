"""Progress bar of long runs on stderr (tqdm: elapsed, ETA, rate).

On a terminal the bar appears once a run has taken ``delay_s`` seconds and redraws
in place; when stderr is not a terminal (logs, pipes, CI) it stays silent
(``disable=None``).  tqdm is imported only when a bar is shown.
"""
from __future__ import annotations

import sys

# n and total formatted short: simulated seconds or revolutions are not integers
_FORMAT = "{desc}: {percentage:5.1f}%|{bar}| {n:.4g}/{total:.4g} {unit} [{elapsed}<{remaining}, {rate_fmt}]"


class Progress:
    """``update(done)`` takes the amount done so far (absolute, in ``unit``).  With
    ``compiling=True`` the description reads "LABEL (compiling)" until :meth:`compiled`
    is called (numba compiles the kernels before the first chunk)."""

    def __init__(self, total: float, label: str, enabled: bool = True, unit: str = "s",
                 compiling: bool = False, delay_s: float = 2.0):
        self.label = label
        self.total = float(total)
        self._bar = None
        if enabled and self.total > 0.0:
            from tqdm import tqdm

            self._bar = tqdm(total=self.total, desc=f"{label} (compiling)" if compiling else label, unit=unit,
                             bar_format=_FORMAT, disable=None, delay=delay_s, mininterval=0.5,
                             dynamic_ncols=True, file=sys.stderr, leave=False)

    def compiled(self) -> None:
        """Compilation is over: the description becomes the plain label (and the bar of the
        compilations, :mod:`wearjoint.compile_notice`, closes)."""
        notice = sys.modules.get("wearjoint.compile_notice")   # loaded by the CLI
        if notice is not None:
            notice.compiled()
        if self._bar is not None:
            self._bar.set_description_str(self.label, refresh=False)

    def update(self, done: float) -> None:
        if self._bar is not None:
            step = min(float(done), self.total) - self._bar.n
            if step > 0.0:
                self._bar.update(step)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
