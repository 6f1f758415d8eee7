"""Build a native FMU: a model's numba kernels compiled ahead of time (:mod:`wearjoint.fmu.aot`)
linked with the generic C FMI layer of ``fmu_src/`` and the model's C part into one shared
library per platform that needs only the system C runtime: FMI 2.0 (default) or FMI 3.0,
Co-Simulation and Model Exchange, for linux64, win64 and aarch64-linux
(:mod:`wearjoint.fmu.platforms`).  The models (:data:`MODELS`): ``joint`` builds
``ClearanceWearJoint.fmu``, ``slider-crank`` ``SliderCrank.fmu`` (:mod:`wearjoint.fmu.slider_crank`).

Steps: (1) the model's kernels as LLVM IR for a generic CPU (:mod:`wearjoint.fmu.kernel_ir`): the
IR an earlier build left in the user cache, else the IR the package ships for these kernels and this
numba, else compiled by numba in fresh processes and kept in the user cache; (2) llvmlite turns that IR into objects for each platform (only the target
triple and data layout change); (3) the model's variable table becomes ``model_variables.h``
(value references, start values, allowed ranges, where each value comes from), and each
platform's C compiler links the FMI layer (``fmi2Functions.c`` or ``fmi3Functions.c`` and their
``fmi2_*``/``fmi3_*`` parts, :data:`GLUE_C_SOURCES_BY_VERSION`, the same for every model), ``fmu_model.c``, ``fmu_state.c``, the model's C files (``joint_model.c``,
``joint_variables.c``, ``joint_state.c``; ``slider_crank_model.c``) and the objects, exporting only the ``fmi2*``
(``fmi3*``) functions and refusing any undefined symbol outside the C runtime; (4) the FMU gets
the generated ``modelDescription.xml`` and ``sources/`` (C layer, generated header, kernel IR,
each platform's objects, ``build.sh PLATFORM``), so a user with a C compiler can relink it.

FMI 3.0: the number of bushing points is the structural parameter ``n_points`` (the build's
``n_points`` is its start value; a host sets another in Configuration Mode) and the wear profile
one ``Float64`` array ``wear_depth`` of that size.
"""
from __future__ import annotations

import hashlib
import json
import subprocess
import tempfile
import uuid
import zipfile
from pathlib import Path

from collections.abc import Callable
from dataclasses import dataclass

from .. import __version__
from ..core import layout
from ..parameters import N_POINTS_MAX, N_POINTS_MIN, JointParameters, ParameterError
from . import slider_crank as sc
from . import variables as fv
from . import platforms
from .kernel_ir import IR_SOURCES, compile_kernel_ir, emit_objects
from .build_common import (FMU_SOURCE_DIR, PACKAGE_DIR, copy_kept_build, current_build, existing_build_key,
                           fmi2_headers, keep_build_in_cache, replaced_whole, source_digest, user_cache_dir)
from .c_tables import c_string as _c_string
from .c_tables import parameter_rows, state_problem_tables
from .model_description import (
    TIME_NAME, WEAR_DEPTH_NAME, fmi3_value_references, interfaces, model_description_fmi3_xml, model_description_xml,
)

FMI_VERSIONS = (2, 3)
DEFAULT_FMI_VERSION = 2
# the FMI layer, every model's (fmu_src/fmi/): its files and the header they share
GLUE_C_SOURCES_BY_VERSION = {
    2: ("fmi2Functions.c", "fmi2_values.c", "fmi2_cosimulation.c", "fmi2_model_exchange.c", "fmi2_instance.h"),
    3: ("fmi3Functions.c", "fmi3_values.c", "fmi3_not_provided.c", "fmi3_cosimulation.c", "fmi3_model_exchange.c",
        "fmi3_instance.h"),
}
COMMON_C_SOURCES = ("fmu_model.c", "fmu_state.c", "fmu_model_defaults.c", "fmu_model.h", "fmi_checks.h",
                    "fmi_state_functions.h", "state_format.h")
FMI_LAYER_FOLDER = "fmi"
N_EVENT_INDICATORS = 1   # the joint's Model Exchange: the signed penetration
# the modules the parameters' allowed rules and their messages come from (the FMUs' checks are generated from them)
RULE_MODULES = ("checks.py", "joint_fields.py", "mechanism_parameters.py")
# the wearjoint modules of every model's build
BUILD_MODULES = ("core/layout.py", "core/jit.py", "parameters.py", "fmu/aot.py", "fmu/model_description.py",
                 "fmu/variables.py", "fmu/c_tables.py", "fmu/build_native.py", "fmu/kernel_ir.py", "fmu/platforms.py")


@dataclass(frozen=True)
class NativeModel:
    """One model of the native FMUs: its C part (besides the FMI layer and fmu_model.c), its kernels'
    header and Python modules (the AOT entry points: :data:`aot.ENTRY_POINTS` [name]), and the generators
    of its ``model_variables.h`` and ``modelDescription.xml``."""

    name: str                  # build_fmu's ``model``
    identifier: str            # modelIdentifier: the binary's and the .fmu's name
    folder: str                # its C part's folder in fmu_src/
    c_sources: tuple
    kernel_header: str
    modules: tuple             # the wearjoint modules whose content decides this model's FMU (with BUILD_MODULES)
    ir_modules: tuple          # what its kernels' IR depends on (with kernel_ir.IR_SOURCES)
    fixed_size: bool           # n_points does not apply (no bushing)
    header: Callable[..., str]             # (guid, n_points, starts, profile_stride) -> model_variables.h
    model_description: Callable[..., bytes]   # (fmi_version, n_points, token, tool, starts, profile_stride, note)

    @property
    def file_name(self) -> str:
        return f"{self.identifier}.fmu"


def _joint_header(guid: str, n_points: int, starts: dict | None, profile_stride: int) -> str:
    return model_variables_header(n_points, guid, starts, profile_stride)


def _joint_model_description(fmi_version: int, n_points: int, token: str, tool: str, starts: dict | None,
                             profile_stride: int, note: str = "") -> bytes:
    cosimulation, model_exchange = interfaces(fmi_version, fv.MODEL_NAME, completed_integrator_step=True)
    if fmi_version == 2:
        return model_description_xml(n_points, token, tool, cosimulation, model_exchange, N_EVENT_INDICATORS,
                                     starts=starts, profile_stride=profile_stride, note=note)
    return model_description_fmi3_xml(n_points, token, tool, cosimulation, model_exchange, starts=starts, note=note)


def _slider_crank_header(guid: str, n_points: int, starts: dict | None, profile_stride: int) -> str:
    return sc.model_variables_header(guid, starts)


def _slider_crank_model_description(fmi_version: int, n_points: int, token: str, tool: str, starts: dict | None,
                                    profile_stride: int, note: str = "") -> bytes:
    return sc.model_description(fmi_version, token, tool, starts)


MODELS = {m.name: m for m in (
    NativeModel("joint", fv.MODEL_NAME, "joint", ("joint_model.c", "joint_variables.c", "joint_state.c",
                                                   "joint_model.h", "joint_kernels.h"), "joint_kernels.h",
                ("core/geometry.py", "core/pressure.py", "core/contact.py", "core/foundation_wear.py", "core/wear.py",
                 "core/state_format.py", "joint.py", "fmu/joint_entry_points.py",
                 "fmu/state_entry_points.py"),
                ("fmu/joint_entry_points.py", "fmu/state_entry_points.py"),
                False, _joint_header, _joint_model_description),
    NativeModel("slider-crank", sc.MODEL_IDENTIFIER, "slider_crank", ("slider_crank_model.c", "slider_crank_kernels.h"),
                "slider_crank_kernels.h", ("core/slider_crank.py", "core/integrators.py", "core/trig.py", "core/state_format.py",
                                           "fmu/slider_crank.py", "fmu/slider_crank_entry_points.py",
                                           "fmu/state_entry_points.py"),
                ("fmu/slider_crank_entry_points.py", "fmu/state_entry_points.py"), True,
                _slider_crank_header, _slider_crank_model_description),
)}
DEFAULT_MODEL = "joint"


def native_model(model) -> NativeModel:
    """``model`` (a name of :data:`MODELS`) checked; ParameterError naming it otherwise."""
    if model not in MODELS:
        raise ParameterError(f"parameter model={model!r} is invalid: allowed one of {', '.join(MODELS)}")
    return MODELS[model]


def c_sources(fmi_version: int, model: str = DEFAULT_MODEL) -> tuple:
    """The C files of ``model``'s binary (and headers) for ``fmi_version``: their names in the FMU's sources
    folder, which holds them side by side."""
    return (*GLUE_C_SOURCES_BY_VERSION[fmi_version], *COMMON_C_SOURCES, *native_model(model).c_sources)


def source_file(name: str, model: str = DEFAULT_MODEL) -> Path:
    """Where :func:`c_sources`' file ``name`` of ``model`` is: fmu_src/ the model's folder for its C part,
    fmu_src/fmi/ for the FMI layer."""
    spec = native_model(model)
    return FMU_SOURCE_DIR / (spec.folder if name in spec.c_sources else FMI_LAYER_FOLDER) / name
FMI_HEADERS_BY_VERSION = {2: ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
                          3: ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")}
EXPORTS_MAP_BY_VERSION = {v: f"{{\n  global: fmi{v}*;\n  local: *;\n}};\n" for v in FMI_VERSIONS}   # ELF platforms


def check_fmi_version(fmi_version) -> int:
    """``fmi_version`` as 2 or 3; ParameterError naming it otherwise."""
    if isinstance(fmi_version, bool) or fmi_version not in FMI_VERSIONS:
        raise ParameterError(f"parameter fmi_version={fmi_version!r} is invalid: allowed one of 2, 3")
    return int(fmi_version)


def shipped_sources(fmi_version: int = DEFAULT_FMI_VERSION, model: str = DEFAULT_MODEL) -> list[Path]:
    """The files whose content decides a build of ``model``: its C sources, the build's modules, the model's, and
    what its kernels' IR and its parameters' rules come from (a new restitution range or damping kernel served a
    cached FMU of the old ones)."""
    spec = native_model(model)
    modules = dict.fromkeys((*BUILD_MODULES, *spec.modules, *IR_SOURCES, *spec.ir_modules, *RULE_MODULES))
    return [*(source_file(name, model) for name in c_sources(check_fmi_version(fmi_version), model)),
            *(PACKAGE_DIR / name for name in modules)]


def model_key(n_points: int, fmi_version: int = DEFAULT_FMI_VERSION, model: str = DEFAULT_MODEL,
              starts: dict | None = None, profile_stride: int = 1, note: str = "") -> str:
    """Identifies the model a native build implements (its GUID): wearjoint version, the model (the
    joint: n_points), FMI version, numba version, hash of the sources, and of the parameters' start
    values where ``starts`` changes them (with the description's ``note``, where one is given)."""
    from importlib.metadata import version   # not numba.__version__: a co-simulation imports no numba

    spec = native_model(model)
    digest = source_digest(shipped_sources(fmi_version, model), PACKAGE_DIR.parent)
    size = spec.name if spec.fixed_size else f"n{n_points}"
    values = ("-p" + hashlib.sha256(json.dumps([sorted(starts.items()), note] if note else sorted(starts.items()))
                                    .encode()).hexdigest()[:12]) if starts or note else ""
    stride = f"-s{profile_stride}" if profile_stride != 1 else ""
    return (f"{__version__}-{size}{stride}-native-fmi{check_fmi_version(fmi_version)}-numba{version('numba')}-"
            f"{digest}{values}")


def build_key(n_points: int, fmi_version: int = DEFAULT_FMI_VERSION, platform_names=("linux64",),
              model: str = DEFAULT_MODEL, starts: dict | None = None, profile_stride: int = 1, note: str = "") -> str:
    """Identifies a native build: the model (with its start values, note and profile outputs) and the platforms
    it carries binaries for."""
    return f"{model_key(n_points, fmi_version, model, starts, profile_stride, note)}-{'+'.join(platform_names)}"


def default_fmu_path(n_points: int = JointParameters.n_points, fmi_version: int = DEFAULT_FMI_VERSION,
                     platform_names=None, model: str = DEFAULT_MODEL, starts: dict | None = None,
                     profile_stride: int = 1, note: str = "") -> Path:
    """Cache location of the build for ``platform_names`` (default: what :func:`platforms.select` picks)."""
    if platform_names is None:
        platform_names = [p.name for p in platforms.select()[0]]
    return (user_cache_dir() / "fmu" / build_key(n_points, fmi_version, platform_names, model, starts, profile_stride,
                                                 note) / native_model(model).file_name)


def check_profile_stride(profile_stride, fmi_version: int, model: str, n_points: int) -> int:
    """ParameterError unless ``profile_stride`` is an integer in [0, n_points], and 1 unless the joint's FMI 2.0
    build (FMI 3.0 has the profile as one array; the slider-crank has none)."""
    if isinstance(profile_stride, bool) or not isinstance(profile_stride, int) or not 0 <= profile_stride <= n_points:
        raise ParameterError(f"parameter profile_stride={profile_stride!r} is invalid: allowed an integer in "
                             f"[0, n_points = {n_points}] (1: every point, 0: none)")
    if profile_stride != 1 and (fmi_version != 2 or native_model(model).fixed_size):
        raise ParameterError(f"parameter profile_stride={profile_stride!r} is invalid with FMI {fmi_version}.0 and "
                             f"model={model!r}: allowed 1 (only the joint's FMI 2.0 build has scalar profile outputs)")
    return profile_stride


def model_guid(key: str) -> str:
    """A GUID fixed by the build key: the same sources give the same GUID."""
    return "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, f"wearjoint:{key}")) + "}"


def model_variables_header(n_points: int, guid: str, starts: dict | None = None, profile_stride: int = 1) -> str:
    """``model_variables.h``: the variable table as the C layer reads it (generated, not edited), the
    parameters' start values from ``starts`` where given there, the FMI 2.0 profile outputs every
    ``profile_stride``-th point (:func:`~wearjoint.fmu.variables.profile_points`)."""
    from ..core import state_format   # numba's kernels (and the wear's constants): a co-simulation imports none
    from ..core.wear import STEP_INADMISSIBLE, STEP_OVERSHOT

    variables = fv.fmu_variables(n_points, profile_stride=profile_stride)
    n_profile = len(fv.profile_points(n_points, profile_stride))
    vr = {v.name: i for i, v in enumerate(variables)}
    parameter_index = {p.variable.name: i for i, p in enumerate(fv.PARAMETERS)}
    rows = parameter_rows([(p.variable.name, p.slot, fv.parameter_variable(p, starts).start,
                            len(p.choices or ()), p.allowed,
                            parameter_index[p.allowed.above] if p.allowed.above else -1, p.allowed_text())
                           for p in fv.PARAMETERS])
    outputs = []
    wear_summary = {"max_wear_depth": "OUTPUT_MAX_WEAR_DEPTH", "worn_volume": "OUTPUT_WORN_VOLUME"}
    scalar_outputs = (*fv.SCALAR_OUTPUTS, *fv.LINEARISATION_OUTPUTS)
    for v in scalar_outputs:
        if v.name in fv.RESULT_SLOTS:
            outputs.append(f"    {{{_c_string(v.name)}, OUTPUT_FROM_RESULT, {fv.RESULT_SLOTS[v.name]}}},")
        elif v.name in fv.JACOBIAN_SLOTS:
            row, column = fv.JACOBIAN_SLOTS[v.name]
            outputs.append(f"    {{{_c_string(v.name)}, OUTPUT_FROM_JACOBIAN, {row * len(fv.INPUTS) + column}}},")
        elif v.name in fv.EVALUATED_INPUTS:
            outputs.append(f"    {{{_c_string(v.name)}, OUTPUT_FROM_INPUT, {fv.EVALUATED_INPUTS[v.name]}}},")
        elif v.name in wear_summary:
            outputs.append(f"    {{{_c_string(v.name)}, {wear_summary[v.name]}, 0}},")
        else:   # each output names its source: a new one without a result slot or a wear figure is a build error
            raise RuntimeError(f"scalar output {v.name!r} has no source: neither a result slot "
                               "(fmu.variables.RESULT_SLOTS), a derivative, an input nor max_wear_depth / worn_volume")
    first_output = vr[scalar_outputs[0].name]
    first_wear = len(variables) - n_profile
    derivatives = list(fv.JACOBIAN_SLOTS)        # their value references in one run: the getter's fast path
    first_derivative = vr[derivatives[0]]
    checks = [[vr[name] for name in derivatives] == list(range(first_derivative, first_derivative + len(derivatives))),
              list(vr)[:len(fv.INPUTS)] == [v.name for v in fv.INPUTS],
              [vr[p.variable.name] for p in fv.PARAMETERS] == list(range(len(fv.INPUTS), len(fv.INPUTS) + len(fv.PARAMETERS))),
              [vr[v.name] for v in scalar_outputs] == list(range(first_output, first_output + len(scalar_outputs))),
              first_wear == first_output + len(scalar_outputs)]
    if not all(checks):
        raise RuntimeError("the FMU variable table is not in the order the C layer expects "
                           "(inputs, parameters, n_points, scalar outputs, wear depths)")
    inputs = ", ".join(_c_string(v.name) for v in fv.INPUTS)
    parameter_of_slot = {p.slot: i for i, p in enumerate(fv.PARAMETERS)}
    vr3 = fmi3_value_references()
    if any(vr3[name] != vr[name] for name in (*(v.name for v in fv.INPUTS), *(p.variable.name for p in fv.PARAMETERS),
                                              fv.N_POINTS_NAME, *(v.name for v in scalar_outputs))):
        raise RuntimeError("the FMI 3.0 value references of the scalars must be their FMI 2.0 ones")
    return f"""/* Generated by wearjoint/fmu/build_native.py from wearjoint/fmu/variables.py: do not edit. */
#ifndef WEARJOINT_MODEL_VARIABLES_H
#define WEARJOINT_MODEL_VARIABLES_H

#include "fmu_model.h"

/* the optional parts of fmu_model.h this model provides (else fmu_src/fmi/fmu_model_defaults.c) */
#define MODEL_HAS_INTEGERS 1
#define MODEL_HAS_STRUCTURAL_PARAMETERS 1
#define MODEL_HAS_DIRECTIONAL_DERIVATIVES 1

#define MODEL_GUID {_c_string(guid)}
#define N_CONTINUOUS_STATES 0
#define N_POINTS {n_points}
#define BLOCK_SIZE {layout.BLOCK_SIZE}
#define N_JOINT_PARAMETERS {layout.N_JOINT_PARAMETERS}
#define N_MEMORY {layout.N_MEMORY}
#define M_START_FORCE {layout.M_START_FORCE}
#define NO_START_FORCE {layout.NO_START_FORCE!r}
#define N_RESULT {layout.N_RESULT}
#define R_NORMAL_FORCE {layout.R_NORMAL_FORCE}
#define R_PENETRATION {layout.R_PENETRATION}
#define R_ECCENTRICITY_X {layout.R_ECCENTRICITY_X}
#define R_ECCENTRICITY_Y {layout.R_ECCENTRICITY_Y}
#define P_BUSHING_RADIUS {layout.P_BUSHING_RADIUS}
#define P_PIN_OFFSET_X {layout.P_PIN_OFFSET_X}
#define P_PIN_OFFSET_Y {layout.P_PIN_OFFSET_Y}
#define P_BUSHING_OFFSET_X {layout.P_BUSHING_OFFSET_X}
#define P_BUSHING_OFFSET_Y {layout.P_BUSHING_OFFSET_Y}
#define STEP_OVERSHOT {STEP_OVERSHOT}
#define STEP_INADMISSIBLE {STEP_INADMISSIBLE}
#define HELD_LINEARISED {layout.HELD_LINEARISED}
#define ADMISSIBLE_SHARE_TEXT "{layout.ADMISSIBLE_PENETRATION_SHARE:g} times"
#define MAX_WEAR_STEP_S {layout.MAX_WEAR_STEP_S!r}
#define WEAR_STEP_SHARE {layout.WEAR_STEP_SHARE!r}
#define WEAR_STEP_SHARE_EXPLICIT {layout.WEAR_STEP_SHARE_EXPLICIT!r}
#define N_EVENT_INDICATORS {N_EVENT_INDICATORS}
#define N_INPUTS {len(fv.INPUTS)}
#define N_PARAMETERS {len(fv.PARAMETERS)}
#define N_SCALAR_OUTPUTS {len(scalar_outputs)}   /* the results, the wear summary, the linearisation */
#define VR_FIRST_PARAMETER {len(fv.INPUTS)}
#define VR_N_POINTS {vr[fv.N_POINTS_NAME]}
#define VR_FIRST_OUTPUT {first_output}
#define VR_FIRST_WEAR_DEPTH {first_wear}
#define VR_FIRST_DERIVATIVE {first_derivative}   /* the published derivatives d_*_d_*: N_DERIVATIVE_OUTPUTS in a run */
#define N_DERIVATIVE_OUTPUTS {len(derivatives)}
#define N_PROFILE_OUTPUTS {n_profile}   /* FMI 2.0: wear_depth[1 + k PROFILE_STRIDE], k < N_PROFILE_OUTPUTS */
#define PROFILE_STRIDE {max(1, profile_stride)}

/* The state format (wearjoint/core/state_format.py): an FMU state's contents kind, its head (time,
 * initialised flag, inputs, parameters), the parameters that bound its values, and the message
 * of each problem a check reports (printf formats of the values as text, of the kinds d, g, x). */
#define STATE_CONTENTS_FMU {state_format.CONTENTS_FMU}
#define STATE_N_HEAD {fv.STATE_HEAD_SIZE}
#define STATE_PARAMETER_BUSHING_RADIUS {parameter_of_slot[layout.P_BUSHING_RADIUS]}
#define STATE_PARAMETER_VELOCITY_FLOOR {parameter_of_slot[layout.P_VELOCITY_FLOOR]}
{state_problem_tables()}

/* FMI 3.0: the scalars keep their FMI 2.0 value references; the wear profile is one Float64 array
 * sized by the structural parameter n_points (UInt64), then the independent time. */
#define FMI3_VR_FIRST_PARAMETER {vr3[fv.PARAMETERS[0].variable.name]}
#define FMI3_VR_N_POINTS {vr3[fv.N_POINTS_NAME]}
#define FMI3_VR_FIRST_OUTPUT {vr3[fv.SCALAR_OUTPUTS[0].name]}
#define FMI3_VR_WEAR_DEPTH {vr3[WEAR_DEPTH_NAME]}
#define FMI3_VR_TIME {vr3[TIME_NAME]}
#define FMI3_N_VALUE_REFERENCES {len(vr3)}
#define FMI3_N_POINTS_START {n_points}
#define FMI3_N_POINTS_MIN {N_POINTS_MIN}
#define FMI3_N_POINTS_MAX {N_POINTS_MAX}

enum {{ OUTPUT_FROM_RESULT, OUTPUT_MAX_WEAR_DEPTH, OUTPUT_WORN_VOLUME, OUTPUT_FROM_JACOBIAN, OUTPUT_FROM_INPUT }};

typedef struct {{
    const char *name;
    int source;
    int index;           /* OUTPUT_FROM_RESULT: index in the kernels' result array (layout.R_*); OUTPUT_FROM_JACOBIAN:
                          * in the Jacobian (row R_* times N_INPUTS plus the input); OUTPUT_FROM_INPUT: the input */
}} OutputInfo;

static const char *const INPUT_NAMES[N_INPUTS] = {{{inputs}}};

/* slot: index in the kernels' joint parameter vector (layout.P_*) */
static const ParameterInfo PARAMETERS[N_PARAMETERS] = {{
{chr(10).join(rows)}
}};

static const OutputInfo OUTPUTS[N_SCALAR_OUTPUTS] = {{
{chr(10).join(outputs)}
}};

#endif
"""


def link_arguments(target: platforms.Platform, fmi_version: int, objects, model: str = DEFAULT_MODEL,
                   output: str | None = None) -> list[str]:
    """The C compiler's arguments that link ``target``'s binary of ``model`` in the sources folder (into
    ``output``, by default the model identifier with the platform's extension)."""
    c_files = [name for name in c_sources(fmi_version, model) if name.endswith(".c")]
    return [*platforms.COMMON_C_FLAGS, *target.link_flags, *target.exports_flag(fmi_version), "-I.", *c_files,
            *objects, "-lm", "-o", output or f"{native_model(model).identifier}{target.extension}"]


def _build_script(targets, fmi_version: int, objects_by_platform: dict, model: str) -> str:
    """``build.sh PLATFORM``: relinks one platform's binary into the sources folder (``$CC`` overrides
    its compiler)."""
    # each platform by either name: an FMI 3.0 FMU's binaries/ folder has the tuple (x86_64-linux)
    aliases = {t.name: (t.name,) if t.name == t.fmi3_folder else (t.name, t.fmi3_folder) for t in targets}
    names = " ".join(a[0] if len(a) == 1 else f"{a[0]} ({a[1]})" for a in aliases.values())
    cases = "".join(
        f"  {'|'.join(aliases[t.name])}) cc=${{CC:-{'gcc' if t.name == 'linux64' else t.cross_compiler or 'cc'}}}; "
        f"args='{' '.join(link_arguments(t, fmi_version, objects_by_platform[t.name], model))}' ;;\n" for t in targets)
    return ("#!/bin/sh\n# Relink this FMU's binary for one platform from these sources: sh build.sh PLATFORM\n"
            f"# (one of: {names}; default {targets[0].name}).  The kernels' objects are kernels/PLATFORM/*.o, all\n"
            "# compiled from the IR kernels/*.ll.  CC overrides the C compiler.\n"
            f"set -e\ncd \"$(dirname \"$0\")\"\nplatform=${{1:-{targets[0].name}}}\ncase \"$platform\" in\n{cases}"
            f"  *) echo \"build.sh: unknown platform '$platform' (this FMU carries: {names})\" >&2; exit 2 ;;\n"
            "esac\n$cc $args\n")


def fmi_headers(fmi_version: int) -> Path:
    """The folder with the FMI headers of ``fmi_version`` (fmpy/c-code); RuntimeError if missing."""
    headers = fmi2_headers()
    missing = [name for name in FMI_HEADERS_BY_VERSION[fmi_version] if not (headers / name).is_file()]
    if missing:
        raise RuntimeError(f"building the FMI {fmi_version}.0 FMU needs the headers {', '.join(missing)} "
                           f"(shipped with fmpy in {headers})")
    return headers


def build_fmu(out_dir, n_points: int = JointParameters.n_points, force: bool = False,
              fmi_version: int = DEFAULT_FMI_VERSION, platform_names=None, model: str = DEFAULT_MODEL,
              starts: dict | None = None, profile_stride: int = 1, note: str = "") -> Path:
    """Build ``model``'s native FMU (:data:`MODELS`: ``joint`` -> ``out_dir/ClearanceWearJoint.fmu``,
    ``slider-crank`` -> ``out_dir/SliderCrank.fmu``), FMI ``fmi_version`` 2 or 3; return its path.

    ``platform_names``: the platforms to carry binaries for (:func:`platforms.parse_platforms`);
    None builds this machine's plus every cross platform whose compiler is installed.  The joint's
    ``n_points``: FMI 2.0 fixes it in the FMU; FMI 3.0 makes it the start value of the structural
    parameter ``n_points`` (a host may set another in Configuration Mode); the slider-crank has no
    bushing and ignores it.  ``starts``: the parameters' start values where not the defaults
    (:func:`~wearjoint.fmu.variables.parameter_starts`, :func:`~wearjoint.fmu.slider_crank.parameter_starts`);
    ``note``: a sentence the joint's model description adds to its description (where a start value came from).
    ``profile_stride`` (the joint, FMI 2.0): every how many bushing points a ``wear_depth[z]`` output is
    (1: all, 0: none; :func:`~wearjoint.fmu.variables.profile_points`), the profile whole in the FMU's state.
    An FMU there built from the same sources, model, start values, n_points, FMI version
    and platforms is kept, and one the user cache keeps (:func:`default_fmu_path`: each build leaves a copy there, the
    :data:`~.build_common.FMU_BUILDS_KEPT` most recently used kept) is
    copied, unless ``force`` (which also recompiles the kernels).  Raises
    ParameterError for a bad argument, RuntimeError when the build cannot run (naming what to
    install).
    """
    fmi_version = check_fmi_version(fmi_version)
    spec = native_model(model)
    JointParameters(n_points=n_points)  # validates n_points, names it in the error
    check_profile_stride(profile_stride, fmi_version, model, n_points)
    if not spec.fixed_size and fmi_version == 3 and not N_POINTS_MIN <= n_points <= N_POINTS_MAX:
        raise ParameterError(f"parameter n_points={n_points!r} is invalid: allowed an integer in "
                             f"[{N_POINTS_MIN}, {N_POINTS_MAX}] for FMI 3.0")
    targets, _ = platforms.select(platform_names)
    key = build_key(n_points, fmi_version, [t.name for t in targets], model, starts, profile_stride, note)
    target_path, current = current_build(out_dir, key, force, spec.file_name)
    if current:
        return target_path
    kept = default_fmu_path(n_points, fmi_version, [t.name for t in targets], model, starts, profile_stride, note)
    if not force and kept.resolve() != target_path.resolve() and existing_build_key(kept) == key:
        copy_kept_build(kept, target_path)      # the same build, kept by an earlier one
        return target_path
    out_dir = Path(out_dir)
    headers = fmi_headers(fmi_version)
    guid = model_guid(model_key(n_points, fmi_version, model, starts, profile_stride, note))
    header = spec.header(guid, n_points, starts, profile_stride)
    with tempfile.TemporaryDirectory(prefix="wearjoint_native_") as tmp:
        sources = Path(tmp) / "sources"
        modules = compile_kernel_ir(sources / "kernels", spec, reuse=not force)
        for name in c_sources(fmi_version, model):
            (sources / name).write_bytes(source_file(name, model).read_bytes())
        for name in FMI_HEADERS_BY_VERSION[fmi_version]:
            (sources / name).write_bytes((headers / name).read_bytes())
        (sources / "model_variables.h").write_text(header)
        (sources / "exports.map").write_text(EXPORTS_MAP_BY_VERSION[fmi_version])
        objects, links = {}, {}
        # each platform's compiler starts once its objects are written, each binary in its own folder
        for t, paths in emit_objects(sources / "kernels", modules, targets, reuse=not force):
            objects[t.name] = paths
            links[t.name] = subprocess.Popen(
                [platforms.compiler(t), *link_arguments(t, fmi_version, objects[t.name], model,
                                                        f"kernels/{t.name}/{spec.identifier}{t.extension}")],
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=sources)
        outputs = {name: link.communicate()[0] for name, link in links.items()}   # all done before any error
        (sources / "build.sh").write_text(_build_script(targets, fmi_version, objects, model))
        binaries = {}
        for t in targets:
            if links[t.name].returncode != 0:
                raise RuntimeError(f"linking the native FMU for {t.name} failed:\n{outputs[t.name].strip()[-3000:]}")
            binary = sources / "kernels" / t.name / f"{spec.identifier}{t.extension}"
            binaries[t.binary_arcname(fmi_version, spec.identifier)] = binary.read_bytes()
            binary.unlink()
        out_dir.mkdir(parents=True, exist_ok=True)
        with replaced_whole(target_path) as partial, zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as fmu:
            fmu.writestr("modelDescription.xml", spec.model_description(
                fmi_version, n_points, guid, f"wearjoint {__version__} (native)", starts, profile_stride, note))
            for arcname, data in binaries.items():
                fmu.writestr(arcname, data)
            configuration = {"model": model} if spec.fixed_size else {"n_points": n_points,
                                                                      "profile_stride": profile_stride}
            fmu.writestr(f"resources/{fv.BUILD_CONFIG_FILE}",
                         json.dumps({**configuration, "build_key": key, "backend": "native",
                                     "fmi_version": fmi_version, "platforms": [t.name for t in targets]}))
            for path in sorted(sources.rglob("*")):
                if path.is_file():
                    fmu.write(path, f"sources/{path.relative_to(sources).as_posix()}")
    keep_build_in_cache(kept, target_path)
    return target_path
