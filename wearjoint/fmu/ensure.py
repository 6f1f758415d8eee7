"""The joint FMU a master runs, built if missing: the one bridge from running an FMU to building one.

* :func:`ensure_fmu`: the given file, else the cached build for the number of profile points and the backend
  (:func:`wearjoint.fmu.build.default_fmu_path`), built now if missing.
* :func:`start_fmu_build` (``python -m wearjoint.fmu.ensure N_POINTS BACKEND``): that build in a second
  process, started while the master's kernels compile in the first (a cold co-simulation's second core).
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from .._compile.user_cache import mark_used
from ..parameters import ParameterError
from .fmi import DEFAULT_BACKEND, FmuError


def ensure_fmu(n_points: int, fmu_path=None, backend: str = DEFAULT_BACKEND) -> Path:
    """The FMU to use: ``fmu_path`` if given (must exist), else the cached build of ``backend``
    for ``n_points`` (built now if missing, see :mod:`wearjoint.fmu.build`)."""
    from .build import build_fmu, default_fmu_path

    if fmu_path is not None:
        path = Path(fmu_path)
        if not path.is_file():
            raise ParameterError(f"parameter fmu_path={str(path)!r} is invalid: allowed an existing .fmu file")
        return path
    path = default_fmu_path(n_points, backend)
    if path.is_file():
        mark_used(path.parent)
        return path
    try:
        return build_fmu(path.parent, n_points=n_points, backend=backend)
    except (OSError, RuntimeError) as exc:
        raise FmuError(f"building the FMU into {path.parent} failed: {exc}") from None


def start_fmu_build(n_points: int, fmu_path, backend: str) -> subprocess.Popen | None:
    """A process building the cached joint FMU (:func:`ensure_fmu`) if it is missing, else None (``fmu_path``
    given, or the FMU already built).  It says what it compiles; its progress bar is off (the first process
    shows its own), and if it fails, ``ensure_fmu`` builds again in the first process and says why."""
    from .build import default_fmu_path

    if fmu_path is not None or default_fmu_path(n_points, backend).is_file():
        return None
    return subprocess.Popen([sys.executable, "-m", __name__, str(int(n_points)), backend],
                            stdout=subprocess.DEVNULL, env={**os.environ, "TQDM_DISABLE": "1"})


if __name__ == "__main__":
    try:
        ensure_fmu(int(sys.argv[1]), None, backend=sys.argv[2])
    except Exception:      # the first process builds again and reports the error
        pass
