"""The variables of the ``SliderCrank`` FMU: the paper's rigid slider-crank with the crank-rod joint
open (Sec. 6.1, Eqs. 38-44), the system around a ``ClearanceWearJoint`` FMU.

The clearance joint sits where the parameter ``clearance_joint`` says (0 crank-rod, 1 rod-slider, 2
crank-ground; core.joint_location), the other joints ideal.  Inputs are the joint's loads on its pin body and on
its bushing body, named like the joint FMU's outputs, and ``slider_force``, a load on the slider added to the
parameters'; outputs are the 12 kinematic quantities the joint FMU takes (named like its inputs: the pin body's
and the bushing body's reference points at their centres of mass, global frame; the ground's are zero), the
crank angle and the slider's position, velocity and acceleration.  Parameters: one
per row of :data:`wearjoint.mechanism_parameters.MECHANISM_FIELDS` (its FMU name, unit, rule; rpm and
degrees as there; gravity's two components, the slider-load table's rows) and ``max_internal_step``, the
longest RK4 step of a Co-Simulation step.  Model Exchange: the 18 continuous states are the coordinates
and velocities q, q_dot (Eq. 38), declared on the variables that hold them; their derivatives are
the velocities and the accelerations (Eq. 44).

One value reference per variable, the same in FMI 2.0 and 3.0 (position in :data:`VARIABLES`);
FMI 3.0 adds the independent ``time`` after them.  This module generates the C model's table
(``model_variables.h``) and both model descriptions.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from xml.etree import ElementTree as ET

from ..core import layout
from .. import mechanism_parameters as mp
from ..checks import POSITIVE, Allowed
from ..parameters import SliderCrankParameters
from . import variables as fv
from .c_tables import c_string, parameter_rows, state_problem_tables
from .model_description import LOG_CATEGORIES, allowed_bounds, interfaces, root_with_interfaces_and_units

MODEL_IDENTIFIER = "SliderCrank"
DESCRIPTION = ("The rigid slider-crank of Sec. 6.1 (Eqs. 38-44, Baumgarte stabilisation), crank driven "
               "clockwise, with the revolute joint named by clearance_joint open: inputs are that joint's loads on "
               "its pin body and bushing body, outputs their kinematics (the inputs of a ClearanceWearJoint FMU) "
               "and the slider's motion.")
MAX_INTERNAL_STEP_NAME = "max_internal_step"
MAX_INTERNAL_STEP_START = 1e-5
LOAD_COUPLING_NAME = "load_coupling"
LOAD_COUPLINGS = ("hold", "linearised")     # load_coupling's values by code
LOAD_COUPLING_HOLD, LOAD_COUPLING_LINEARISED = range(len(LOAD_COUPLINGS))
TIME_NAME = "time"
# kind of a variable's value in the C model: an input, a parameter, y[index] or dy[index]
# or the clearance joint's kinematic input[index] (core.joint_location.joint_kinematics)
INPUT, PARAMETER, STATE, DERIVATIVE, JOINT = (
    "SOURCE_INPUT", "SOURCE_PARAMETER", "SOURCE_STATE", "SOURCE_DERIVATIVE", "SOURCE_JOINT")


@dataclass(frozen=True)
class Variable:
    """One variable: its FMI description and where the C model finds its value."""

    name: str
    causality: str
    unit: str
    description: str
    source: str
    index: int
    start: float | None = None
    allowed: Allowed | None = None   # parameters
    choices: tuple[str, ...] = ()       # a parameter taking the values 0 .. len(choices) - 1 (an enumeration)

    @property
    def n_choices(self) -> int:
        return len(self.choices)


# the FMU's check of each mechanism parameter's rule: wearjoint.mechanism_parameters.RULES
_ALLOWED = mp.RULES
_DEFAULTS = mp.field_vector(SliderCrankParameters())

_BODIES = (("pin", "pin body (the crank at the crank-rod and crank-ground joints, the slider at the rod-slider "
                   "joint)"),
           ("bushing", "bushing body (the rod, or the ground at the crank-ground joint: ignored)"))
SLIDER_FORCE_NAME = "slider_force"
LOAD_INPUTS = tuple(Variable(f"{body}_{name}", fv.INPUT, unit, f"load of the clearance joint on the {text}: {what}",
                             INPUT, 3 * b + k, 0.0)
                    for b, (body, text) in enumerate(_BODIES)
                    for k, (name, unit, what) in enumerate((("force_x", "N", "force x, global frame"),
                                                            ("force_y", "N", "force y, global frame"),
                                                            ("torque", "N.m", "torque about its centre of mass")))) + (
    Variable(SLIDER_FORCE_NAME, fv.INPUT, "N", "load on the slider along its axis, positive towards the crank's "
             "pivot: added to slider_force_constant and the slider-load table", INPUT,
             layout.MECHANISM_INPUT_SLIDER_FORCE, 0.0),)
INPUTS = LOAD_INPUTS + (
    Variable("normal_force", fv.INPUT, "N", "load_coupling 1: the joint's normal force at the evaluated inputs (the "
             "linearised loads vanish where its linearisation reaches 0)", INPUT, layout.MECHANISM_INPUT_NORMAL_FORCE,
             0.0),)
# load_coupling 1: the linearisation a ClearanceWearJoint FMU publishes, named as its outputs
LINEARISATION_INPUTS = tuple(
    Variable(v.name, fv.INPUT, v.unit, f"load_coupling 1: {v.description}", INPUT, index, 0.0)
    for index, v in enumerate(fv.LINEARISATION_OUTPUTS, start=layout.MECHANISM_INPUT_DERIVATIVES))
INPUTS += LINEARISATION_INPUTS
_LINEARISED_LOADS = (*(v.name for v in LOAD_INPUTS[:6]), "normal_force")   # the rows of layout.LIN_LOADS
if ([_LINEARISED_LOADS[k] for k in layout.PUBLISHED_LINEARISED_LOADS] != list(fv.LINEARISED_ROWS)
        or [v.index for v in INPUTS] != list(range(layout.N_MECHANISM_INPUTS))):
    raise RuntimeError("the SliderCrank's inputs and the joint's published linearisation (core/layout.py) disagree")
PARAMETERS = tuple(
    Variable(f.fmu_name, fv.PARAMETER, f.unit, f.text, PARAMETER, i, float(_DEFAULTS[i]), _ALLOWED[f.rule],
             tuple(f.choices or ()))
    for i, f in enumerate(mp.MECHANISM_FIELDS)) + (
    Variable(MAX_INTERNAL_STEP_NAME, fv.PARAMETER, "s",
             "Co-Simulation: longest internal RK4 step; a communication step h is taken in ceil(h / max_internal_step) "
             "equal steps with the inputs held", PARAMETER, len(mp.MECHANISM_FIELDS), MAX_INTERNAL_STEP_START,
             POSITIVE),
    Variable(LOAD_COUPLING_NAME, fv.PARAMETER, "1",
             "Co-Simulation: how a communication step takes the joint's loads (0 = hold: the load inputs held; "
             "1 = linearised: F0 + J (u - u0) from the linearisation inputs, a ClearanceWearJoint FMU's d_*_d_* and "
             "evaluated_* outputs, u the joint's kinematics along the step; a zero-order-hold master then stays "
             "accurate at several times the step)", PARAMETER, len(mp.MECHANISM_FIELDS) + 1, 0.0,
             Allowed(0.0, high=1.0), LOAD_COUPLINGS),)

# y = [q, q_dot] (Eq. 38): the variable holding each, its unit and what it is
_BODY_OF = (("crank", "crank"), ("rod", "rod"), ("slider", "slider"))
_POSITION = (("x", "m", "x of the centre of mass"), ("y", "m", "y of the centre of mass"),
             ("angle", "rad", "rotation angle, counter-clockwise"))
_VELOCITY = (("vx", "m/s", "x velocity of the centre of mass"), ("vy", "m/s", "y velocity of the centre of mass"),
             ("omega", "rad/s", "angular velocity, counter-clockwise"))
_ACCELERATION = (("ax", "m/s2", "x acceleration of the centre of mass"),
                 ("ay", "m/s2", "y acceleration of the centre of mass"),
                 ("alpha", "rad/s2", "angular acceleration, counter-clockwise"))
# the slider's names: its x quantities are the outputs slider_x, slider_v, slider_a
_SLIDER_NAMES = {"x": "slider_x", "vx": "slider_v", "ax": "slider_a", "y": "slider_y", "angle": "slider_angle",
                 "vy": "slider_vy", "omega": "slider_omega", "ay": "slider_ay", "alpha": "slider_alpha"}
_OUTPUT_SLIDER = frozenset({"slider_x", "slider_v", "slider_a"})
CRANK_ANGLE_NAME = "crank_angle"          # the crank's angle state, an output too
CRANK_ANGLE_TEXT = "crank angle theta1 = theta0 - omega t (driven, Eq. 39)"


def _motion(rows, source: str, offset: int) -> tuple[Variable, ...]:
    out = []
    for b, (prefix, body) in enumerate(_BODY_OF):
        for k, (suffix, unit, text) in enumerate(rows):
            name = _SLIDER_NAMES[suffix] if prefix == "slider" else f"{prefix}_{suffix}"
            causality = fv.OUTPUT if name in _OUTPUT_SLIDER or name == CRANK_ANGLE_NAME else fv.LOCAL
            description = (CRANK_ANGLE_TEXT if name == CRANK_ANGLE_NAME and source == STATE
                           else f"{body}: {text}, global frame")
            out.append(Variable(name, causality, unit, description, source, offset + 3 * b + k))
    return tuple(out)


N = layout.N_COORDINATES
POSITIONS = _motion(_POSITION, STATE, 0)
VELOCITIES = _motion(_VELOCITY, STATE, N)
ACCELERATIONS = tuple(dataclasses.replace(v, causality=fv.OUTPUT if v.name in _OUTPUT_SLIDER else fv.LOCAL)
                      for v in _motion(_ACCELERATION, DERIVATIVE, N))
# the clearance joint's kinematics, named like a ClearanceWearJoint FMU's inputs (in its input order)
JOINT_KINEMATICS = tuple(Variable(v.name, fv.OUTPUT, v.unit, f"{v.description.split(':')[0]} of the clearance "
                                  f"joint:{v.description.split(':', 1)[1]}", JOINT, k)
                         for k, v in enumerate(fv.INPUTS))
VARIABLES: tuple[Variable, ...] = (*INPUTS, *PARAMETERS, *POSITIONS, *VELOCITIES, *ACCELERATIONS,
                                   *JOINT_KINEMATICS)
STATES = (*POSITIONS, *VELOCITIES)                 # y[0..17], in order
STATE_DERIVATIVES = (*VELOCITIES, *ACCELERATIONS)   # dy[0..17], in order
VALUE_REFERENCES = {v.name: i for i, v in enumerate(VARIABLES)}
# the FMU state's head (core/state_format.py, CONTENTS_MECHANISM): time, initialised flag, inputs, parameters, y
STATE_HEAD_SIZE = 2 + len(INPUTS) + len(PARAMETERS) + len(STATES)
FMI3_TIME_VALUE_REFERENCE = len(VARIABLES)
# the 12 outputs a ClearanceWearJoint FMU takes as inputs, in its input order
KINEMATIC_OUTPUTS = tuple(v.name for v in fv.INPUTS)
if set(KINEMATIC_OUTPUTS) - {v.name for v in VARIABLES if v.causality == fv.OUTPUT}:
    raise RuntimeError("SliderCrank lacks an output for a ClearanceWearJoint input")

UNIT_DEFINITIONS: dict[str, dict] = {
    "m": {"m": 1}, "m/s": {"m": 1, "s": -1}, "m/s2": {"m": 1, "s": -2}, "rad": {"rad": 1},
    "rad/s": {"rad": 1, "s": -1}, "rad/s2": {"rad": 1, "s": -2}, "N": {"kg": 1, "m": 1, "s": -2},
    "N.m": {"kg": 1, "m": 2, "s": -2}, "kg": {"kg": 1}, "kg.m2": {"kg": 1, "m": 2}, "s": {"s": 1},
    "1/s": {"s": -1}, "1": {}, "rpm": {"rad": 1, "s": -1, "factor": repr(2.0 * math.pi / 60.0)},
    "deg": {"rad": 1, "factor": repr(math.pi / 180.0)},
    **{v.unit: fv.UNIT_DEFINITIONS[v.unit] for v in LINEARISATION_INPUTS},
}


def parameter_values(params: SliderCrankParameters) -> dict[str, float]:
    """FMU parameter values (keyed by FMU name) reproducing ``params``."""
    return {PARAMETERS[i].name: float(value) for i, value in enumerate(mp.field_vector(params))}


def parameter_starts(params: SliderCrankParameters) -> dict[str, float]:
    """The FMU parameter values of ``params`` that differ from the defaults: the start values a build
    for this mechanism writes (empty for the paper's)."""
    defaults = {p.name: p.start for p in PARAMETERS}
    return {name: value for name, value in parameter_values(params).items() if value != defaults[name]}


def variables(starts: dict | None = None) -> tuple[Variable, ...]:
    """:data:`VARIABLES` with the parameters' start values from ``starts`` where given there."""
    starts = starts or {}
    return tuple(dataclasses.replace(v, start=starts[v.name]) if v.causality == fv.PARAMETER and v.name in starts
                 else v for v in VARIABLES)


def _choice_text(choices) -> str:
    """What an enumeration parameter allows, e.g. ``0 (hold), 1 (linearised)``."""
    return ", ".join(f"{code} ({name})" for code, name in enumerate(choices))


def model_variables_header(guid: str, starts: dict | None = None) -> str:
    """``model_variables.h`` of the C model (slider_crank_model.c): generated, not edited; the
    parameters' start values from ``starts`` where given there."""
    from ..core import state_format   # numba's kernels: the package's co-simulation imports none

    parameters = [v for v in variables(starts) if v.causality == fv.PARAMETER]
    names = [p.name for p in parameters]
    rows = parameter_rows([(p.name, p.index, p.start, p.n_choices, p.allowed, names.index(p.allowed.above)
                            if p.allowed.above else -1, _choice_text(p.choices) if p.choices else p.allowed.text())
                           for p in parameters])
    table = "\n".join(f"    {{{c_string(v.name)}, {v.source}, {v.index}}}," for v in VARIABLES)
    load_table_row_base = layout.LOAD_TABLE_ROW_BASE
    return f"""/* Generated by wearjoint/fmu/build_native.py from wearjoint/fmu/slider_crank.py: do not edit. */
#ifndef WEARJOINT_MODEL_VARIABLES_H
#define WEARJOINT_MODEL_VARIABLES_H

#include "fmu_model.h"

#define MODEL_GUID {c_string(guid)}
#define N_CONTINUOUS_STATES {len(STATES)}
#define N_EVENT_INDICATORS 0
#define N_COORDINATES {N}
#define N_MECHANISM_PARAMETERS {layout.N_MECHANISM_PARAMETERS}
#define N_INPUTS {len(INPUTS)}
#define N_PARAMETERS {len(PARAMETERS)}
#define P_MAX_INTERNAL_STEP {names.index(MAX_INTERNAL_STEP_NAME)}
#define P_LOAD_COUPLING {names.index(LOAD_COUPLING_NAME)}
#define P_LOAD_TABLE_ROWS {names.index("slider_force_table_rows")}
#define N_LINEARISATION {layout.N_LINEARISATION}
#define N_VARIABLES {len(VARIABLES)}
#define FMI3_VR_TIME {FMI3_TIME_VALUE_REFERENCE}

/* The state format (wearjoint/core/state_format.py): a SliderCrank state's contents kind and head
 * (time, initialised flag, inputs, parameters, y), the contact memory it writes as zeros, and the
 * message of each problem a check reports. */
/* what is wrong with a slider-load table: slider_crank_parameters returns kind * LOAD_TABLE_ROW_BASE + row
 * (wearjoint/core/slider_load.py, load_table_problem); LOAD_TABLE_PROBLEMS[kind - 1] words it */
#define LOAD_TABLE_ROW_BASE {load_table_row_base}
static const char *const LOAD_TABLE_PROBLEMS[{len(mp.LOAD_TABLE_PROBLEMS)}] = {{{", ".join(c_string(mp.LOAD_TABLE_PROBLEMS[k]) for k in sorted(mp.LOAD_TABLE_PROBLEMS))}}};

#define STATE_CONTENTS_MECHANISM {state_format.CONTENTS_MECHANISM}
#define STATE_N_HEAD {STATE_HEAD_SIZE}
#define STATE_N_MEMORY {layout.N_MEMORY}
{state_problem_tables()}

enum {{ {INPUT}, {PARAMETER}, {STATE}, {DERIVATIVE}, {JOINT} }};

typedef struct {{
    const char *name;
    int source;   /* SOURCE_*: where the value is */
    int index;    /* in inputs, parameters, y = [q, q_dot], dy or the joint's kinematics */
}} VariableInfo;

/* value reference = position (FMI 2.0 and 3.0) */
static const VariableInfo VARIABLES[N_VARIABLES] = {{
{table}
}};

/* the variable holding y[k] = [q, q_dot][k] (Eq. 38) */
static const char *const STATE_NAMES[N_CONTINUOUS_STATES] = {{{", ".join(c_string(v.name) for v in STATES)}}};

/* slot: index in the SliderCrankParameters fields (max_internal_step: the C model's own) */
static const ParameterInfo PARAMETERS[N_PARAMETERS] = {{
{chr(10).join(rows)}
}};

#endif
"""


# ModelStructure: what each unknown depends on (tests/fmu/test_slider_crank_fmu.py checks it by finite
# differences), for any clearance_joint (a parameter).  The pin's torque acts on a body whose rotation is held
# (the crank driven, the slider guided) at every joint: it moves nothing.  The crank translates only with the
# clearance at its pivot, where the bushing is the ground: its accelerations depend on the pin's forces and the
# slider's load alone.  The other loads move the rod's and the slider's x accelerations; the crank's rotation and
# the slider's y and rotation are held.  A state is set by the integration and the joint's kinematics are the
# states': they depend on no input (no direct feed-through), and OMSimulator sees no algebraic loop through the
# joint.  The accelerations depend on the states (conservatively all 18: mass matrix, Baumgarte terms), a
# position's derivative (a velocity) on that velocity state only.
_MOVING_LOADS = tuple(v.name for v in LOAD_INPUTS if v.name != "pin_torque")
_CRANK_LOADS = ("pin_force_x", "pin_force_y", SLIDER_FORCE_NAME)
_LOAD_DRIVEN = {"crank_ax": _CRANK_LOADS, "crank_ay": _CRANK_LOADS, "rod_ax": _MOVING_LOADS, "rod_ay": _MOVING_LOADS,
                "rod_alpha": _MOVING_LOADS, "slider_a": _MOVING_LOADS}
_JOINT_KINEMATICS = frozenset(v.name for v in JOINT_KINEMATICS)
# The assembled initial state (core.slider_crank.initial_state: the ideal mechanism at the initial crank angle, Eq.
# 39, its velocities solving the constraints with the clearance joint's rows open) and so the joint's kinematics
# read off it depend on these parameters alone; its accelerations on every parameter (masses, gravity, loads).
# Declaring every parameter for them too (the load table's 722 entries) made OMSimulator's dependency graph 3x
# larger and its import and initialisation of the package twice as long.
_ASSEMBLY_PARAMETERS = ("crank_length", "rod_length", "crank_speed", "initial_crank_angle", "clearance_joint")


def input_dependencies(name: str) -> tuple[str, ...]:
    """The inputs whose instantaneous value variable ``name`` depends on (direct feed-through)."""
    return _LOAD_DRIVEN.get(name, ())


def _known_dependencies(name: str, kind: str) -> tuple[str, ...]:
    """The knowns ``name`` depends on as an unknown of ``kind``: "output" (the joint's kinematics: the states;
    an acceleration: its inputs and the states), "derivative" (a velocity: itself, the state; an acceleration:
    its inputs and the states) or "initial" (a position, a velocity or the joint's kinematics: the parameters of
    the assembly, :data:`_ASSEMBLY_PARAMETERS`; an acceleration: its inputs and every parameter but the internal
    step)."""
    accelerations = {a.name for a in ACCELERATIONS}
    if kind == "initial" and name not in accelerations:
        return _ASSEMBLY_PARAMETERS
    if kind == "initial":
        return (*input_dependencies(name), *(p.name for p in PARAMETERS if p.name != MAX_INTERNAL_STEP_NAME))
    if name in accelerations:
        return (*input_dependencies(name), *(s.name for s in STATES))
    if name in _JOINT_KINEMATICS:
        return tuple(s.name for s in STATES)
    return (name,) if kind == "derivative" else ()


def _dependencies(name: str, reference: dict[str, int], kind: str) -> str:
    """The ``dependencies`` attribute of ``name``: its knowns (:func:`_known_dependencies`) as FMI 2.0
    indices or FMI 3.0 value references (``reference``), in ascending order."""
    return " ".join(str(i) for i in sorted(reference[k] for k in _known_dependencies(name, kind)))


def _structure_unknowns() -> list[tuple[str, str]]:
    """The model structure's unknowns as (kind, variable name), in FMI order: the outputs, the state
    derivatives, then the initial unknowns (the outputs, states and derivatives, calculated)."""
    outputs = [v.name for v in VARIABLES if v.causality == fv.OUTPUT]
    calculated = {*outputs, *(v.name for v in (*STATES, *STATE_DERIVATIVES))}
    return ([("output", name) for name in outputs] + [("derivative", d.name) for d in STATE_DERIVATIVES]
            + [("initial", v.name) for v in VARIABLES if v.name in calculated])


def _log_categories(root: ET.Element) -> None:
    categories = ET.SubElement(root, "LogCategories")
    for name, text in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=text)


def _fmi2_variables(root: ET.Element, starts: dict | None) -> None:
    model_variables = ET.SubElement(root, "ModelVariables")
    index = {v.name: i + 1 for i, v in enumerate(VARIABLES)}   # 1-based
    derivative_of = {d.name: index[s.name] for s, d in zip(STATES, STATE_DERIVATIVES)}
    for vr, v in enumerate(variables(starts)):
        attributes = {"name": v.name, "valueReference": str(vr), "description": v.description, "causality": v.causality}
        typed = {"unit": v.unit}
        if v.causality == fv.PARAMETER:
            attributes.update(variability="fixed", initial="exact")
            typed.update(start=repr(v.start), **allowed_bounds(v.allowed))
        elif v.causality == fv.INPUT:
            attributes["variability"] = "continuous"
            typed["start"] = repr(v.start)
        else:
            attributes.update(variability="continuous", initial="calculated")
        if v.name in derivative_of:
            typed["derivative"] = str(derivative_of[v.name])
        ET.SubElement(ET.SubElement(model_variables, "ScalarVariable", attributes), "Real", typed)
    structure = ET.SubElement(root, "ModelStructure")
    groups = {kind: ET.SubElement(structure, element) for kind, element in
              (("output", "Outputs"), ("derivative", "Derivatives"), ("initial", "InitialUnknowns"))}
    for kind, name in _structure_unknowns():
        ET.SubElement(groups[kind], "Unknown", index=str(index[name]), dependencies=_dependencies(name, index, kind))


def _fmi3_variables(root: ET.Element, starts: dict | None) -> None:
    model_variables = ET.SubElement(root, "ModelVariables")
    ET.SubElement(model_variables, "Float64", name=TIME_NAME, valueReference=str(FMI3_TIME_VALUE_REFERENCE),
                  description="simulation time", causality="independent", variability="continuous", unit="s")
    derivative_of = {d.name: VALUE_REFERENCES[s.name] for s, d in zip(STATES, STATE_DERIVATIVES)}
    for vr, v in enumerate(variables(starts)):
        attributes = {"name": v.name, "valueReference": str(vr), "description": v.description,
                      "causality": v.causality}
        if v.causality == fv.PARAMETER:
            attributes.update(variability="fixed", initial="exact")
        else:
            attributes["variability"] = "continuous"
            if v.causality != fv.INPUT:
                attributes["initial"] = "calculated"
        if v.name in derivative_of:
            attributes["derivative"] = str(derivative_of[v.name])
        attributes["unit"] = v.unit
        if v.start is not None:
            attributes["start"] = repr(v.start)
        if v.causality == fv.PARAMETER:
            attributes.update(allowed_bounds(v.allowed))
        ET.SubElement(model_variables, "Float64", attributes)
    structure = ET.SubElement(root, "ModelStructure")
    element = {"output": "Output", "derivative": "ContinuousStateDerivative", "initial": "InitialUnknown"}
    for kind, name in _structure_unknowns():
        ET.SubElement(structure, element[kind], valueReference=str(VALUE_REFERENCES[name]),
                      dependencies=_dependencies(name, VALUE_REFERENCES, kind))


def model_description(fmi_version: int, guid: str, tool: str, starts: dict | None = None) -> bytes:
    """modelDescription.xml of the SliderCrank FMU (FMI ``fmi_version``), Co-Simulation and Model Exchange;
    ``starts``: parameter start values other than the defaults (:func:`parameter_starts`)."""
    cosimulation, model_exchange = interfaces(fmi_version, MODEL_IDENTIFIER, completed_integrator_step=False)
    if fmi_version == 2:
        root = root_with_interfaces_and_units(
            {"fmiVersion": "2.0", "guid": guid, "generationTool": tool, "numberOfEventIndicators": "0"},
            cosimulation, model_exchange, UNIT_DEFINITIONS, MODEL_IDENTIFIER, DESCRIPTION)
        _log_categories(root)
        _fmi2_variables(root, starts)
    else:
        root = root_with_interfaces_and_units(
            {"fmiVersion": "3.0", "instantiationToken": guid, "generationTool": tool},
            cosimulation, model_exchange, UNIT_DEFINITIONS, MODEL_IDENTIFIER, DESCRIPTION)
        _log_categories(root)
        _fmi3_variables(root, starts)
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)
