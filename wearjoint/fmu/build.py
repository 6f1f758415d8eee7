"""Build ``ClearanceWearJoint.fmu`` with either backend, or ``SliderCrank.fmu`` (native only: ``model``
``slider-crank``).  What the backends share (where the sources
are, the user cache where built FMUs live, the build keys, the C compiler and the FMI headers) is
:mod:`wearjoint.fmu.build_common`, importable from here too.

Backends (docs/reference/fmu.md, "The FMU"):

* ``native`` -- the joint's numba kernels compiled ahead of time and a C FMI layer
  (``fmu_src/``), one shared library per platform needing only the system C runtime
  (:mod:`wearjoint.fmu.build_native`; linux64, win64, aarch64-linux:
  :mod:`wearjoint.fmu.platforms`); FMI 2.0 (default) or FMI 3.0 (``fmi_version=3``);
* ``pythonfmu`` -- the Python slave ``fmu_src/pythonfmu/ClearanceWearJoint.py`` behind a C
  status shim; the host needs Python with numpy and numba
  (:mod:`wearjoint.fmu.build_pythonfmu`); FMI 2.0, linux64 only.
"""
from __future__ import annotations

import importlib
from pathlib import Path

from ..parameters import JointParameters, ParameterError
from . import variables as fv
from .fmi import BACKENDS, DEFAULT_BACKEND

_MODULES = {"native": "wearjoint.fmu.build_native", "pythonfmu": "wearjoint.fmu.build_pythonfmu"}
BINARY_ARCNAME = f"binaries/linux64/{fv.MODEL_NAME}.so"


def _backend_module(backend: str):
    if backend not in BACKENDS:
        raise ParameterError(f"parameter backend={backend!r} is invalid: allowed one of {', '.join(BACKENDS)}")
    return importlib.import_module(_MODULES[backend])


FMI_VERSIONS = (2, 3)
DEFAULT_FMI_VERSION = 2


def _check_fmi_version(fmi_version, backend: str) -> int:
    if isinstance(fmi_version, bool) or fmi_version not in FMI_VERSIONS:
        raise ParameterError(f"parameter fmi_version={fmi_version!r} is invalid: allowed one of 2, 3")
    if fmi_version != 2 and backend != "native":
        raise ParameterError(f"parameter fmi_version={fmi_version!r} is invalid for backend={backend!r}: "
                             "the pythonfmu backend builds FMI 2.0 only (use backend='native' for FMI 3.0)")
    return int(fmi_version)


def _check_platforms(platform_names, backend: str):
    """``platform_names`` parsed (None = automatic); the pythonfmu backend builds linux64 only."""
    from .platforms import parse_platforms

    names = parse_platforms(platform_names)
    if backend != "native" and names not in (None, ("linux64",)):
        raise ParameterError(f"parameter platforms={platform_names!r} is invalid for backend={backend!r}: "
                             "the pythonfmu backend builds linux64 only (use backend='native')")
    return names


def _check_model(model: str, backend: str) -> str:
    """``model`` checked against the backend: the pythonfmu backend builds the joint only."""
    from .build_native import native_model

    native_model(model)
    if model != "joint" and backend != "native":
        raise ParameterError(f"parameter model={model!r} is invalid for backend={backend!r}: the pythonfmu backend "
                             "builds the joint only (use backend='native')")
    return model


def _check_starts(starts, backend: str, profile_stride: int = 1) -> dict:
    """Start values other than the defaults, and profile outputs other than all, need the native backend (the
    pythonfmu slave starts from the defaults and outputs every point)."""
    if starts and backend != "native":
        raise ParameterError(f"parameter backend={backend!r} is invalid with start values other than the defaults "
                             f"({', '.join(sorted(starts))}): allowed 'native' (or set them in the host)")
    if profile_stride != 1 and backend != "native":
        raise ParameterError(f"parameter backend={backend!r} is invalid with profile_stride={profile_stride!r}: "
                             "allowed 'native'")
    return dict(starts or {})


def _checked(backend: str, fmi_version, platforms, model, starts, profile_stride: int) -> tuple:
    """The backend's module and the checked FMI version, platform names, model and start values (ParameterError
    naming a bad one)."""
    return (_backend_module(backend), _check_fmi_version(fmi_version, backend), _check_platforms(platforms, backend),
            _check_model(model, backend), _check_starts(starts, backend, profile_stride))


def default_fmu_path(n_points: int = JointParameters.n_points, backend: str = DEFAULT_BACKEND,
                     fmi_version: int = DEFAULT_FMI_VERSION, platforms=None, model: str = "joint",
                     starts: dict | None = None, profile_stride: int = 1, note: str = "") -> Path:
    """Cache location of the FMU for this source tree, ``n_points``, ``backend``, ``fmi_version``,
    ``platforms`` (native; None: this machine's plus every cross platform installed), ``model`` and
    its parameters' ``starts`` and the description's ``note`` (native)."""
    module, fmi_version, names, model, starts = _checked(backend, fmi_version, platforms, model, starts,
                                                         profile_stride)
    if backend != "native":
        return module.default_fmu_path(n_points)
    return module.default_fmu_path(n_points, fmi_version=fmi_version, platform_names=names, model=model,
                                   starts=starts, profile_stride=profile_stride, note=note)


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False,
              backend: str = DEFAULT_BACKEND, fmi_version: int = DEFAULT_FMI_VERSION, platforms=None,
              model: str = "joint", starts: dict | None = None, profile_stride: int = 1, note: str = "") -> Path:
    """Build ``out_dir/ClearanceWearJoint.fmu`` (``model="joint"``) or ``out_dir/SliderCrank.fmu``
    (``model="slider-crank"``, native only, ``n_points`` unused); return its path (an identical
    existing build is kept unless ``force``).  ``fmi_version``: 2 (default) or 3 (native backend
    only; the joint's ``n_points`` is then the start value of the structural parameter
    ``n_points``).  ``platforms`` (native): a comma-separated text or list of linux64, win64,
    aarch64-linux, ...; None builds this machine's plus every cross platform whose compiler is
    installed.  ``starts`` (native): the parameters' start values where not the defaults, FMU name ->
    value (:func:`wearjoint.fmu.variables.parameter_starts` of a joint,
    :func:`wearjoint.fmu.slider_crank.parameter_starts` of a mechanism); ``note`` (native): a sentence the model
    description adds (where a start value came from: ``build-fmu --calibration``).  ``profile_stride`` (native, the
    joint's FMI 2.0 build): every how many bushing points a ``wear_depth[z]`` output is (1: all, 0: none; the
    whole profile stays in the FMU's state and in FMI 3.0's array).  Raises ParameterError for a
    bad argument, RuntimeError when the build cannot run (no C compiler, a missing cross toolchain)."""
    module, fmi_version, names, model, starts = _checked(backend, fmi_version, platforms, model, starts,
                                                         profile_stride)
    if backend != "native":
        return module.build_fmu(out_dir, n_points=n_points, force=force)
    return module.build_fmu(out_dir, n_points=n_points, force=force, fmi_version=fmi_version, platform_names=names,
                            model=model, starts=starts, profile_stride=profile_stride, note=note)

