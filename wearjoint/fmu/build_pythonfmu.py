"""Build ``ClearanceWearJoint.fmu`` (FMI 2.0 Co-Simulation) from ``fmu_src/`` with pythonfmu.

The FMU ships the part of the ``wearjoint`` package the slave imports at run
time (:data:`RUNTIME_MODULES`) and a requirements file (numpy, numba) in its
resources; editing any other module (the master, the CLI, plots, ...) leaves
the build key, and so the cached FMU, unchanged.  pythonfmu's
modelDescription.xml is then completed so that ``fmpy.validate_fmu`` reports
no problem: units, ModelStructure dependencies (direct feed-through of the
force outputs on the 12 inputs) and InitialUnknowns.

pythonfmu 0.7 reports every Python exception as fmi2Fatal.  The build therefore
compiles ``fmu_src/pythonfmu/status_shim.c`` (a C compiler is required: ``$CC``, default
gcc; Linux x86_64 only) into the FMU's ``binaries/linux64/ClearanceWearJoint.so``;
pythonfmu's binary becomes ``binaries/linux64/pythonfmu_ClearanceWearJoint.so``
behind it, and errors the slave reports come out as fmi2Error.

pythonfmu is imported only inside :func:`build_fmu` (``import wearjoint`` stays light).
"""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
import zipfile
from importlib.metadata import distribution, version
from pathlib import Path
from xml.etree import ElementTree as ET

from .. import __version__
from ..parameters import JointParameters
from . import variables as fv
from .build import BINARY_ARCNAME
from .build_common import (
    FMU_FILE_NAME, FMU_SOURCE_DIR, PACKAGE_DIR, c_compiler, current_build, fmi2_headers, source_digest,
    user_cache_dir,
)
from .model_description import model_description_xml

SLAVE_SOURCE = FMU_SOURCE_DIR / "pythonfmu" / f"{fv.MODEL_NAME}.py"
SHIM_SOURCE = FMU_SOURCE_DIR / "pythonfmu" / "status_shim.c"
# the shim takes the place of pythonfmu's binary, which it loads from the same folder
SHIM_ARCNAME = BINARY_ARCNAME
WRAPPED_BINARY_NAME = f"pythonfmu_{fv.MODEL_NAME}.so"
REQUIREMENTS = "numpy\nnumba\n"


# The slave's run-time import closure within wearjoint (tests/fmu/test_fmu_build.py checks that
# importing the slave from the FMU's resources loads exactly these).
RUNTIME_MODULES = ("__init__.py", "_compile/__init__.py", "_compile/cache.py", "_compile/user_cache.py", "checks.py",
                   "joint_fields.py",
                   "parameters.py",
                   "mechanism_parameters.py", "joint.py", "fmu/__init__.py", "fmu/variables.py",
                   "core/__init__.py", "core/layout.py", "core/jit.py", "core/geometry.py", "core/pressure.py", "core/damping.py",
                   "core/contact.py",
                   "core/foundation_wear.py", "core/wear.py", "core/state_format.py", "core/joint_access.py",
                   "core/joint_location.py", "core/admissibility.py")


def _package_sources() -> list[Path]:
    """The wearjoint modules shipped in the FMU's resources."""
    return [PACKAGE_DIR / name for name in RUNTIME_MODULES]


def shipped_sources() -> list[Path]:
    """The files that define the FMU: the slave, the status shim and the wearjoint run-time modules."""
    return [SLAVE_SOURCE, SHIM_SOURCE, *_package_sources()]


def build_key(n_points: int) -> str:
    """Identifies an FMU build: wearjoint version, n_points, pythonfmu version, hash of the sources."""
    digest = source_digest(shipped_sources(), PACKAGE_DIR.parent)
    return f"{__version__}-n{n_points}-pythonfmu{version('pythonfmu')}-{digest}"


def default_fmu_path(n_points: int = JointParameters.n_points) -> Path:
    """Cache location of the FMU for this wearjoint source tree and n_points."""
    return user_cache_dir() / "fmu" / build_key(n_points) / FMU_FILE_NAME


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False) -> Path:
    """Build ``out_dir/ClearanceWearJoint.fmu`` with ``n_points`` bushing points; return its path.

    Skipped (the existing file is returned) when the FMU there was built from the
    same sources and n_points, unless ``force``.  Raises ParameterError for a bad
    n_points, RuntimeError when the status shim cannot be built (no C compiler).
    """
    JointParameters(n_points=n_points)  # validates n_points, names it in the error
    key = build_key(n_points)
    target, current = current_build(out_dir, key, force)
    if current:
        return target
    out_dir = Path(out_dir)
    for source in (SLAVE_SOURCE, SHIM_SOURCE):
        if not source.is_file():
            raise FileNotFoundError(f"FMU source {source} not found (wearjoint must be used from its source tree)")
    with tempfile.TemporaryDirectory(prefix="wearjoint_fmu_") as tmp:
        tmp = Path(tmp)
        shim = _compile_status_shim(tmp / "shim.so")
        project_files = _stage_project_files(tmp / "stage", n_points, key)
        raw = _run_pythonfmu(tmp / "raw", project_files)
        out_dir.mkdir(parents=True, exist_ok=True)
        partial = target.with_name(target.name + ".partial")
        _finish_fmu(raw, partial, n_points, shim)
        partial.replace(target)
    return target


def _compile_status_shim(library: Path) -> Path:
    """Compile fmu_src/pythonfmu/status_shim.c into ``library`` (``$CC``, default gcc); RuntimeError if impossible."""
    compiler = c_compiler("the FMU's status shim")
    headers = fmi2_headers()
    command = [compiler, "-shared", "-fPIC", "-O2", "-fvisibility=hidden", f"-I{headers}",
               f'-DWRAPPED_LIBRARY="{WRAPPED_BINARY_NAME}"', str(SHIM_SOURCE), "-o", str(library), "-ldl"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"compiling the FMU's status shim failed ({' '.join(command)}):\n{done.stderr.strip()}")
    return library


def _stage_project_files(stage: Path, n_points: int, key: str) -> list[Path]:
    """Stage the resources: the wearjoint run-time modules (no caches), requirements.txt, build config."""
    package = stage / "wearjoint"
    for path in _package_sources():
        target = package / path.relative_to(PACKAGE_DIR)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(path, target)
    requirements = stage / "requirements.txt"
    requirements.write_text(REQUIREMENTS)
    config = stage / fv.BUILD_CONFIG_FILE
    config.write_text(json.dumps({"n_points": n_points, "build_key": key}))
    return [package, requirements, config]


def _run_pythonfmu(dest: Path, project_files: list[Path]) -> Path:
    """pythonfmu's builder on fmu_src, leaving the caller's sys.path and sys.modules as they were.

    A pythonfmu FMU loaded earlier in this process put its resources on sys.path, with the slave and a copy
    of pythonfmu's modules but not its binaries: the installed pythonfmu (whose builder copies its binary
    into the FMU) and fmu_src's slave go first on sys.path, and the modules of those names are imported
    afresh for the build.
    """
    installed = str(distribution("pythonfmu").locate_file(""))
    saved_path = list(sys.path)
    names = [SLAVE_SOURCE.stem] + [name for name in sys.modules if name == "pythonfmu" or name.startswith("pythonfmu.")]
    saved_modules = {name: sys.modules.pop(name) for name in names if name in sys.modules}
    sys.path[:0] = [str(SLAVE_SOURCE.parent), installed]
    try:
        from pythonfmu.builder import FmuBuilder

        return Path(FmuBuilder.build_FMU(SLAVE_SOURCE, dest=dest, project_files=project_files,
                                         canGetAndSetFMUstate=True, canSerializeFMUstate=True))
    finally:
        sys.path[:] = saved_path
        for name in [name for name in sys.modules if name in names or name.split(".")[0] == "pythonfmu"]:
            sys.modules.pop(name)
        sys.modules.update(saved_modules)


def _finish_fmu(raw: Path, target: Path, n_points: int, shim: Path) -> None:
    """Copy ``raw`` to ``target`` with the completed modelDescription.xml and the status shim
    in place of pythonfmu's linux64 binary (renamed to WRAPPED_BINARY_NAME)."""
    wrapped_arcname = f"{Path(SHIM_ARCNAME).parent.as_posix()}/{WRAPPED_BINARY_NAME}"
    with zipfile.ZipFile(raw) as src:
        if SHIM_ARCNAME not in src.namelist():
            raise RuntimeError(f"pythonfmu wrote no {SHIM_ARCNAME} to wrap")
        with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as dst:
            dst.write(shim, SHIM_ARCNAME)
            for item in src.infolist():
                data = src.read(item.filename)
                if item.filename == "modelDescription.xml":
                    data = complete_model_description(data, n_points)
                dst.writestr(wrapped_arcname if item.filename == SHIM_ARCNAME else item.filename, data)


def complete_model_description(xml: bytes, n_points: int) -> bytes:
    """pythonfmu's modelDescription.xml replaced by the one generated from the variable table
    (:mod:`wearjoint.fmu.model_description`), keeping pythonfmu's GUID, generation tool and
    ``<CoSimulation>`` attributes (with the FMU-state flags set)."""
    root = ET.fromstring(xml)
    names = [sv.get("name") for sv in root.find("ModelVariables").findall("ScalarVariable")]
    if names != [v.name for v in fv.fmu_variables(n_points)]:
        raise RuntimeError("pythonfmu wrote the variables in another order than wearjoint.fmu.variables")
    cosimulation = dict(root.find("CoSimulation").attrib, canGetAndSetFMUstate="true", canSerializeFMUstate="true")
    return model_description_xml(n_points, root.get("guid"), root.get("generationTool"), cosimulation)
