"""Build ``ClearanceWearJoint.fmu`` with either backend, and where built FMUs are cached.

Backends (docs/model.md, "The FMU"):

* ``native`` -- the joint's numba kernels compiled ahead of time and a C FMI layer
  (``fmu_src/``), one shared library needing only libc and libm
  (:mod:`wearjoint.fmu.build_native`);
* ``pythonfmu`` -- the Python slave ``fmu_src/ClearanceWearJoint.py`` behind a C
  status shim; the host needs Python with numpy and numba
  (:mod:`wearjoint.fmu.build_pythonfmu`).
"""
from __future__ import annotations

import importlib
from pathlib import Path

from ..parameters import JointParameters, ParameterError

BACKENDS = ("native", "pythonfmu")
DEFAULT_BACKEND = "native"
_MODULES = {"native": "wearjoint.fmu.build_native", "pythonfmu": "wearjoint.fmu.build_pythonfmu"}


def _backend_module(backend: str):
    if backend not in BACKENDS:
        raise ParameterError(f"parameter backend={backend!r} is invalid: allowed one of {', '.join(BACKENDS)}")
    return importlib.import_module(_MODULES[backend])


def default_fmu_path(n_points: int = JointParameters.n_points, backend: str = DEFAULT_BACKEND) -> Path:
    """Cache location of the FMU for this source tree, ``n_points`` and ``backend``."""
    return _backend_module(backend).default_fmu_path(n_points)


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False,
              backend: str = DEFAULT_BACKEND) -> Path:
    """Build ``out_dir/ClearanceWearJoint.fmu``; return its path (an identical existing build is kept
    unless ``force``).  Raises ParameterError for a bad argument, RuntimeError when the build
    cannot run (no C compiler, unsupported platform)."""
    return _backend_module(backend).build_fmu(out_dir, n_points=n_points, force=force)
