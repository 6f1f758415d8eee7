"""Build the native ``ClearanceWearJoint.fmu``: the joint's numba kernels compiled ahead of
time (:mod:`wearjoint.fmu.aot`) linked with the C FMI 2.0 layer of ``fmu_src/`` into
``binaries/linux64/ClearanceWearJoint.so``, which needs only libc and libm.

Steps: (1) a fresh Python process with an empty numba cache compiles the kernels to
objects for a generic x86-64 CPU; (2) the variable table becomes ``model_variables.h``
(value references, start values, allowed ranges, where each output comes from), and
``joint_instance.c`` (the joint's data, FMI-independent) is compiled with the FMI 2.0 layer
(Co-Simulation and Model Exchange);
(3) gcc links the C layer and the objects, exporting only the ``fmi2*`` functions and
refusing any undefined symbol outside libc/libm; (4) the FMU gets the generated
``modelDescription.xml`` and ``sources/`` (C layer, generated header, kernel IR and
objects, ``build.sh``), so a user with a C compiler can relink it.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import uuid
import zipfile
from pathlib import Path

from .. import __version__
from ..core import layout
from ..joint import PARAMETER_SLOTS
from ..parameters import JointParameters
from . import variables as fv
from .build import (
    BINARY_ARCNAME, FMU_FILE_NAME, FMU_SOURCE_DIR, PACKAGE_DIR, c_compiler, existing_build_key, fmi2_headers,
    source_digest, user_cache_dir,
)
from .model_description import model_description_xml

C_SOURCES = ("fmi2Functions.c", "joint_instance.c", "joint_instance.h", "model.h")
C_FILES = tuple(name for name in C_SOURCES if name.endswith(".c"))
N_EVENT_INDICATORS = 1   # Model Exchange: the signed penetration
# the wearjoint modules whose content decides the compiled FMU
KERNEL_MODULES = ("core/layout.py", "core/jit.py", "core/contact.py", "core/wear.py", "joint.py", "parameters.py",
                  "fmu/variables.py", "fmu/entry_points.py", "fmu/aot.py", "fmu/model_description.py",
                  "fmu/build_native.py")
FMI_HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")
GCC_FLAGS = ("-shared", "-fPIC", "-O2", "-std=c11", "-Wall", "-Wextra", "-Wno-unused-parameter", "-Werror", "-Wl,-z,defs",
             "-Wl,--version-script=exports.map")
EXPORTS_MAP = "{\n  global: fmi2*;\n  local: *;\n};\n"
# the process that compiles the kernels: no cached code (it has no IR), a generic x86-64 CPU
AOT_ENVIRONMENT = {"NUMBA_CPU_NAME": "generic", "NUMBA_CPU_FEATURES": "", "NUMBA_DISABLE_JIT": "0"}


def shipped_sources() -> list[Path]:
    return [*(FMU_SOURCE_DIR / name for name in C_SOURCES), *(PACKAGE_DIR / name for name in KERNEL_MODULES)]


def build_key(n_points: int) -> str:
    """Identifies a native build: wearjoint version, n_points, numba version, hash of the sources."""
    import numba

    digest = source_digest(shipped_sources(), PACKAGE_DIR.parent)
    return f"{__version__}-n{n_points}-native-numba{numba.__version__}-{digest}"


def default_fmu_path(n_points: int = JointParameters.n_points) -> Path:
    return user_cache_dir() / "fmu" / build_key(n_points) / FMU_FILE_NAME


def model_guid(key: str) -> str:
    """A GUID fixed by the build key: the same sources give the same GUID."""
    return "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, f"wearjoint:{key}")) + "}"


def _c_string(text: str) -> str:
    return json.dumps(text)   # a valid C string literal for the ASCII texts used here


def _c_double(value: float) -> str:
    return repr(float(value))


def model_variables_header(n_points: int, guid: str) -> str:
    """``model_variables.h``: the variable table as the C layer reads it (generated, not edited)."""
    variables = fv.fmu_variables(n_points)
    vr = {v.name: i for i, v in enumerate(variables)}
    parameter_index = {p.variable.name: i for i, p in enumerate(fv.PARAMETERS)}
    slot_of = {(source if isinstance(source, tuple) else (source, None)): slot
               for slot, source in PARAMETER_SLOTS.items()}
    rows = []
    for p in fv.PARAMETERS:
        a = p.allowed
        rows.append("    {%s, %d, %s, %d, %d, %d, %s, %d, %d, %s, %d, %s}," % (
            _c_string(p.variable.name), slot_of[(p.field, p.component)], _c_double(p.variable.start),
            len(p.choices or ()), a.low is not None, a.low_open, _c_double(a.low or 0.0), a.high is not None,
            a.high_open, _c_double(a.high or 0.0), parameter_index[a.above] if a.above else -1,
            _c_string(p.allowed_text())))
    outputs = []
    for v in fv.SCALAR_OUTPUTS:
        if v.name in fv.RESULT_SLOTS:
            outputs.append(f"    {{{_c_string(v.name)}, OUTPUT_FROM_RESULT, {fv.RESULT_SLOTS[v.name]}}},")
        else:
            source = "OUTPUT_MAX_WEAR_DEPTH" if v.name == "max_wear_depth" else "OUTPUT_WORN_VOLUME"
            outputs.append(f"    {{{_c_string(v.name)}, {source}, 0}},")
    first_output = vr[fv.SCALAR_OUTPUTS[0].name]
    first_wear = vr[fv.wear_depth_name(1)]
    checks = [list(vr)[:len(fv.INPUTS)] == [v.name for v in fv.INPUTS],
              [vr[p.variable.name] for p in fv.PARAMETERS] == list(range(len(fv.INPUTS), len(fv.INPUTS) + len(fv.PARAMETERS))),
              [vr[v.name] for v in fv.SCALAR_OUTPUTS] == list(range(first_output, first_output + len(fv.SCALAR_OUTPUTS))),
              first_wear + n_points == len(variables)]
    if not all(checks):
        raise RuntimeError("the FMU variable table is not in the order the C layer expects "
                           "(inputs, parameters, n_points, scalar outputs, wear depths)")
    inputs = ", ".join(_c_string(v.name) for v in fv.INPUTS)
    return f"""/* Generated by wearjoint/fmu/build_native.py from wearjoint/fmu/variables.py: do not edit. */
#ifndef WEARJOINT_MODEL_VARIABLES_H
#define WEARJOINT_MODEL_VARIABLES_H

#define MODEL_GUID {_c_string(guid)}
#define N_POINTS {n_points}
#define BLOCK_SIZE {layout.BLOCK_SIZE}
#define N_JOINT_PARAMETERS {layout.N_JOINT_PARAMETERS}
#define N_MEMORY {layout.N_MEMORY}
#define N_RESULT {layout.N_RESULT}
#define R_PENETRATION {layout.R_PENETRATION}
#define N_EVENT_INDICATORS {N_EVENT_INDICATORS}
#define N_INPUTS {len(fv.INPUTS)}
#define N_PARAMETERS {len(fv.PARAMETERS)}
#define N_SCALAR_OUTPUTS {len(fv.SCALAR_OUTPUTS)}
#define VR_FIRST_PARAMETER {len(fv.INPUTS)}
#define VR_N_POINTS {vr[fv.N_POINTS_NAME]}
#define VR_FIRST_OUTPUT {first_output}
#define VR_FIRST_WEAR_DEPTH {first_wear}

typedef struct {{
    const char *name;
    int slot;            /* index in the kernels' joint parameter vector (layout.P_*) */
    double start;
    int n_choices;       /* > 0: an Integer enumeration 0 .. n_choices - 1 */
    int has_low, low_open;
    double low;
    int has_high, high_open;
    double high;
    int above;           /* index of a parameter this one must exceed, or -1 */
    const char *allowed; /* the rule as the error message states it */
}} ParameterInfo;

enum {{ OUTPUT_FROM_RESULT, OUTPUT_MAX_WEAR_DEPTH, OUTPUT_WORN_VOLUME }};

typedef struct {{
    const char *name;
    int source;
    int index;           /* OUTPUT_FROM_RESULT: index in the kernels' result array (layout.R_*) */
}} OutputInfo;

static const char *const INPUT_NAMES[N_INPUTS] = {{{inputs}}};

static const ParameterInfo PARAMETERS[N_PARAMETERS] = {{
{chr(10).join(rows)}
}};

static const OutputInfo OUTPUTS[N_SCALAR_OUTPUTS] = {{
{chr(10).join(outputs)}
}};

#endif
"""


def compile_kernels(out_dir: Path) -> dict:
    """Compile the kernels to objects in ``out_dir`` (a fresh process, empty numba cache)."""
    with tempfile.TemporaryDirectory(prefix="wearjoint_numba_") as cache:
        env = {**os.environ, **AOT_ENVIRONMENT, "NUMBA_CACHE_DIR": cache}
        done = subprocess.run([sys.executable, "-m", "wearjoint.fmu.aot", str(out_dir)], capture_output=True,
                              text=True, env=env, cwd=PACKAGE_DIR.parent)
    if done.returncode != 0:
        raise RuntimeError(f"compiling the kernels ahead of time failed:\n{done.stderr.strip()[-3000:]}")
    return json.loads((out_dir / "entry_points.json").read_text())


def _build_script(objects) -> str:
    return ("#!/bin/sh\n# Relink the FMU's binary from these sources (Linux x86_64, any C11 compiler).\n"
            "set -e\ncd \"$(dirname \"$0\")\"\n"
            f"${{CC:-gcc}} {' '.join(GCC_FLAGS)} -I. {' '.join(C_FILES)} {' '.join('kernels/' + o for o in objects)} "
            f"-lm -o {fv.MODEL_NAME}.so\n")


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False) -> Path:
    """Build ``out_dir/ClearanceWearJoint.fmu`` (native backend); return its path.

    An FMU there built from the same sources and n_points is kept unless ``force``.
    Raises ParameterError for a bad n_points, RuntimeError when the build cannot run.
    """
    JointParameters(n_points=n_points)  # validates n_points, names it in the error
    out_dir = Path(out_dir)
    target = out_dir / FMU_FILE_NAME
    key = build_key(n_points)
    if not force and existing_build_key(target) == key:
        return target
    compiler = c_compiler("the native FMU")
    headers = fmi2_headers()
    guid = model_guid(key)
    with tempfile.TemporaryDirectory(prefix="wearjoint_native_") as tmp:
        sources = Path(tmp) / "sources"
        objects = compile_kernels(sources / "kernels")
        for name in C_SOURCES:
            (sources / name).write_bytes((FMU_SOURCE_DIR / name).read_bytes())
        for name in FMI_HEADERS:
            (sources / name).write_bytes((headers / name).read_bytes())
        (sources / "model_variables.h").write_text(model_variables_header(n_points, guid))
        (sources / "exports.map").write_text(EXPORTS_MAP)
        script = sources / "build.sh"
        script.write_text(_build_script(objects.values()))
        done = subprocess.run([compiler, *GCC_FLAGS, "-I.", *C_FILES,
                               *(f"kernels/{o}" for o in objects.values()), "-lm", "-o", f"{fv.MODEL_NAME}.so"],
                              capture_output=True, text=True, cwd=sources)
        if done.returncode != 0:
            raise RuntimeError(f"linking the native FMU failed:\n{done.stderr.strip()[-3000:]}")
        binary = sources / f"{fv.MODEL_NAME}.so"
        common = {"modelIdentifier": fv.MODEL_NAME, "needsExecutionTool": "false",
                  "canBeInstantiatedOnlyOncePerProcess": "false", "canNotUseMemoryManagementFunctions": "false",
                  "canGetAndSetFMUstate": "true", "canSerializeFMUstate": "true"}
        cosimulation = {**common, "canHandleVariableCommunicationStepSize": "true", "canInterpolateInputs": "false"}
        model_exchange = {**common, "completedIntegratorStepNotNeeded": "false"}
        out_dir.mkdir(parents=True, exist_ok=True)
        partial = target.with_name(target.name + ".partial")
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as fmu:
            fmu.writestr("modelDescription.xml",
                         model_description_xml(n_points, guid, f"wearjoint {__version__} (native)", cosimulation,
                                               model_exchange, N_EVENT_INDICATORS))
            fmu.write(binary, BINARY_ARCNAME)
            fmu.writestr(f"resources/{fv.BUILD_CONFIG_FILE}",
                         json.dumps({"n_points": n_points, "build_key": key, "backend": "native"}))
            for path in sorted(sources.rglob("*")):
                if path.is_file() and path != binary:
                    fmu.write(path, f"sources/{path.relative_to(sources).as_posix()}")
        partial.replace(target)
    return target
