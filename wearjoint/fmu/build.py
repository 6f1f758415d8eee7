"""Build ``ClearanceWearJoint.fmu`` with either backend, and where built FMUs are cached.

Backends (docs/model.md, "The FMU"):

* ``native`` -- the joint's numba kernels compiled ahead of time and a C FMI layer
  (``fmu_src/``), one shared library per platform needing only the system C runtime
  (:mod:`wearjoint.fmu.build_native`; linux64, win64, aarch64-linux:
  :mod:`wearjoint.fmu.platforms`); FMI 2.0 (default) or FMI 3.0 (``fmi_version=3``);
* ``pythonfmu`` -- the Python slave ``fmu_src/ClearanceWearJoint.py`` behind a C
  status shim; the host needs Python with numpy and numba
  (:mod:`wearjoint.fmu.build_pythonfmu`); FMI 2.0, linux64 only.
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.util
import json
import os
import platform
import shutil
import sys
import zipfile
from pathlib import Path

from ..parameters import JointParameters, ParameterError
from . import variables as fv

BACKENDS = ("native", "pythonfmu")
DEFAULT_BACKEND = "native"
_MODULES = {"native": "wearjoint.fmu.build_native", "pythonfmu": "wearjoint.fmu.build_pythonfmu"}
FMU_FILE_NAME = f"{fv.MODEL_NAME}.fmu"
BINARY_ARCNAME = f"binaries/linux64/{fv.MODEL_NAME}.so"
PACKAGE_DIR = Path(__file__).resolve().parent.parent   # wearjoint/
# fmu_src is the package wearjoint.fmu_src (the folder fmu_src/ in the source tree)
FMU_SOURCE_DIR = Path(importlib.util.find_spec("wearjoint.fmu_src").origin).resolve().parent


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


def default_fmu_path(n_points: int = JointParameters.n_points, backend: str = DEFAULT_BACKEND,
                     fmi_version: int = DEFAULT_FMI_VERSION, platforms=None, model: str = "joint") -> Path:
    """Cache location of the FMU for this source tree, ``n_points``, ``backend``, ``fmi_version``,
    ``platforms`` (native; None: this machine's plus every cross platform installed) and ``model``."""
    module = _backend_module(backend)
    fmi_version = _check_fmi_version(fmi_version, backend)
    names = _check_platforms(platforms, backend)
    model = _check_model(model, backend)
    if backend != "native":
        return module.default_fmu_path(n_points)
    return module.default_fmu_path(n_points, fmi_version=fmi_version, platform_names=names, model=model)


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False,
              backend: str = DEFAULT_BACKEND, fmi_version: int = DEFAULT_FMI_VERSION, platforms=None,
              model: str = "joint") -> Path:
    """Build ``out_dir/ClearanceWearJoint.fmu`` (``model="joint"``) or ``out_dir/SliderCrank.fmu``
    (``model="slider-crank"``, native only, ``n_points`` unused); return its path (an identical
    existing build is kept unless ``force``).  ``fmi_version``: 2 (default) or 3 (native backend
    only; the joint's ``n_points`` is then the start value of the structural parameter
    ``n_points``).  ``platforms`` (native): a comma-separated text or list of linux64, win64,
    aarch64-linux, ...; None builds this machine's plus every cross platform whose compiler is
    installed.  Raises ParameterError for a bad argument, RuntimeError when the build cannot run
    (no C compiler, a missing cross toolchain)."""
    module = _backend_module(backend)
    fmi_version = _check_fmi_version(fmi_version, backend)
    names = _check_platforms(platforms, backend)
    model = _check_model(model, backend)
    if backend != "native":
        return module.build_fmu(out_dir, n_points=n_points, force=force)
    return module.build_fmu(out_dir, n_points=n_points, force=force, fmi_version=fmi_version, platform_names=names,
                            model=model)


# ------------------------------------------------------------- shared by the backends
def user_cache_dir() -> Path:
    """wearjoint's folder in the user's cache (built FMUs live below it, keyed by their sources)."""
    if sys.platform == "win32":
        return Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local")) / "wearjoint" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "wearjoint"
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "wearjoint"


def source_digest(paths, root: Path) -> str:
    """Hash of the files (their paths relative to ``root`` and contents): part of a build key."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).relative_to(root).as_posix().encode() + b"\0" + Path(path).read_bytes())
    return digest.hexdigest()[:16]


def current_build(out_dir, key: str, force: bool, file_name: str = FMU_FILE_NAME) -> tuple[Path, bool]:
    """``out_dir``'s FMU file ``file_name``, and whether it already is the build ``key`` (and no ``force``)."""
    target = Path(out_dir) / file_name
    return target, not force and existing_build_key(target) == key


def existing_build_key(fmu_path: Path) -> str | None:
    """The build key an FMU was built with (resources/wearjoint_fmu.json), None if unreadable."""
    try:
        with zipfile.ZipFile(fmu_path) as zf:
            return json.loads(zf.read(f"resources/{fv.BUILD_CONFIG_FILE}"))["build_key"]
    except (OSError, KeyError, ValueError, zipfile.BadZipFile):
        return None


def c_compiler(purpose: str) -> str:
    """The C compiler (``$CC``, default gcc) on Linux x86_64; RuntimeError naming ``purpose`` otherwise."""
    if not sys.platform.startswith("linux") or platform.machine() != "x86_64":
        raise RuntimeError(f"{purpose} is built for binaries/linux64 only; this is {sys.platform} "
                           f"{platform.machine()} (build the FMU on Linux x86_64)")
    compiler = os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        raise RuntimeError(f"{purpose} needs a C compiler: {compiler!r} not found (install gcc or set CC)")
    return compiler


def fmi2_headers() -> Path:
    """The FMI 2.0 headers shipped with fmpy (fmpy/c-code); RuntimeError if missing."""
    fmpy = importlib.util.find_spec("fmpy")
    headers = Path(next(iter(fmpy.submodule_search_locations))) / "c-code" if fmpy else None
    if headers is None or not (headers / "fmi2Functions.h").is_file():
        raise RuntimeError("building the FMU needs the FMI 2.0 headers shipped with fmpy (fmpy/c-code/fmi2Functions.h)")
    return headers
