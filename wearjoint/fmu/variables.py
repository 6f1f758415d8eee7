"""The variables of the ``ClearanceWearJoint`` FMU: names, order, units, descriptions, defaults.

This table is the single definition shared by the pythonfmu slave
(``fmu_src/pythonfmu/ClearanceWearJoint.py``), the build step (units, ModelStructure) and
co-simulation masters (value references looked up by name).  The slave
registers the variables in exactly the order of :func:`fmu_variables`, so
value reference = position in that list; masters should still look them up
from the modelDescription with :func:`value_references`.

The parameters are the rows of :data:`wearjoint.joint_fields.JOINT_FIELDS`.  Imports only the standard library,
:mod:`wearjoint.joint_fields`, :mod:`wearjoint.parameters` and :mod:`wearjoint.core.layout`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..core import layout
from ..joint_fields import JOINT_FIELDS, JointField, allowed_text, coded_value, coded_values
from ..parameters import JointParameters, ParameterError

MODEL_NAME = "ClearanceWearJoint"
# JSON file in the FMU's resources written by the build: {"n_points": N_d, "build_key": ...}
BUILD_CONFIG_FILE = "wearjoint_fmu.json"

# causality / variability / type labels as written in modelDescription.xml
INPUT, OUTPUT, PARAMETER, LOCAL = "input", "output", "parameter", "local"
REAL, INTEGER = "Real", "Integer"


@dataclass(frozen=True)
class FmuVariable:
    """One FMI scalar variable.  ``unit`` is '' for Integer variables (FMI 2 gives them no unit)."""

    name: str
    causality: str
    type: str
    unit: str
    description: str
    start: float | int | None = None


def _kinematics(body: str, frame_note: str) -> tuple[FmuVariable, ...]:
    rows = (("x", "m", "x of the reference point"), ("y", "m", "y of the reference point"),
            ("angle", "rad", "rotation angle, counter-clockwise"),
            ("vx", "m/s", "x velocity of the reference point"), ("vy", "m/s", "y velocity of the reference point"),
            ("omega", "rad/s", "angular velocity, counter-clockwise"))
    return tuple(FmuVariable(f"{body}_{suffix}", INPUT, REAL, unit, f"{body} body ({frame_note}): {text}, global frame", 0.0)
                 for suffix, unit, text in rows)


INPUTS: tuple[FmuVariable, ...] = (_kinematics("pin", "carries the pin, paper body i")
                                   + _kinematics("bushing", "carries the wearing bushing, paper body j"))

# Scalar outputs; the slave maps each name to the joint's result (layout.R_*) or wear summary.
SCALAR_OUTPUTS: tuple[FmuVariable, ...] = tuple(FmuVariable(name, OUTPUT, REAL, unit, text) for name, unit, text in (
    ("pin_force_x", "N", "contact force on the pin body, x, global frame"),
    ("pin_force_y", "N", "contact force on the pin body, y, global frame"),
    ("pin_torque", "N.m", "contact torque on the pin body about its reference point"),
    ("bushing_force_x", "N", "contact force on the bushing body, x, global frame"),
    ("bushing_force_y", "N", "contact force on the bushing body, y, global frame"),
    ("bushing_torque", "N.m", "contact torque on the bushing body about its reference point"),
    ("normal_force", "N", "normal contact force F_N >= 0"),
    ("friction_force", "N", "friction force on the pin along the contact tangent (signed)"),
    ("penetration", "m", "signed penetration R_i - |d| of the deepest bushing point: > 0 in contact, negative = the gap"),
    ("contact", "1", "contact flag: 1 in contact, 0 otherwise"),
    ("contact_angle", "rad", "angle of the contact point (of the eccentricity without contact), bushing frame, 0..2 pi"),
    ("eccentricity_x", "m", "pin centre minus bushing centre, x, bushing frame"),
    ("eccentricity_y", "m", "pin centre minus bushing centre, y, bushing frame"),
    ("tangential_velocity", "m/s", "sliding velocity v_T of the pin's contact point relative to the bushing's, along the "
                                   "contact tangent (Eq. 14; 0 out of contact)"),
    ("max_wear_depth", "m", "largest wear depth of the bushing profile"),
    ("worn_volume", "m3", "volume removed from the bushing: contact length times worn area"),
))

# Where each joint output is in the kernels' result array (layout.R_*); the other scalar
# outputs are the wear summary.
RESULT_SLOTS: dict[str, int] = {
    "pin_force_x": layout.R_PIN_FX, "pin_force_y": layout.R_PIN_FY, "pin_torque": layout.R_PIN_TORQUE,
    "bushing_force_x": layout.R_BUSHING_FX, "bushing_force_y": layout.R_BUSHING_FY,
    "bushing_torque": layout.R_BUSHING_TORQUE, "normal_force": layout.R_NORMAL_FORCE,
    "friction_force": layout.R_FRICTION_FORCE, "penetration": layout.R_PENETRATION,
    "contact": layout.R_CONTACT, "contact_angle": layout.R_CONTACT_ANGLE,
    "eccentricity_x": layout.R_ECCENTRICITY_X, "eccentricity_y": layout.R_ECCENTRICITY_Y,
    "tangential_velocity": layout.R_TANGENTIAL_VELOCITY,
}
WEAR_SUMMARY_NAMES = ("max_wear_depth", "worn_volume")

# The loads' linearisation (docs/reference/fmu.md §5, "The published linearisation"): the derivatives of the loads
# a mechanism integrates with respect to the 12 inputs, and the inputs they were evaluated at, so that a master
# holding the outputs over a step lets the mechanism integrate F0 + J (u - u0) (core/linearisation.py) whatever the
# order it moves values in.  The bushing body's force is minus the pin body's (Eq. 22): its rows are not outputs.
LINEARISED_ROWS = ("pin_force_x", "pin_force_y", "pin_torque", "bushing_torque", "normal_force")
_DENOMINATOR = {"m": "/m", "rad": "/rad", "m/s": ".s/m", "rad/s": ".s/rad"}


def derivative_name(output: str, input_name: str) -> str:
    """The output holding d ``output`` / d ``input_name``, e.g. ``d_pin_force_x_d_pin_vx``."""
    return f"d_{output}_d_{input_name}"


def evaluated_input_name(input_name: str) -> str:
    """The output holding the value of ``input_name`` the loads were evaluated at, e.g. ``evaluated_pin_x``."""
    return f"evaluated_{input_name}"


def _derivative_output(row: FmuVariable, column: FmuVariable) -> FmuVariable:
    return FmuVariable(derivative_name(row.name, column.name), OUTPUT, REAL, row.unit + _DENOMINATOR[column.unit],
                       f"d {row.name} / d {column.name} at the evaluated inputs: the exact derivative of the contact "
                       "kernels (0 out of contact; one-sided where the force is not differentiable)")


_ROWS = {v.name: v for v in SCALAR_OUTPUTS}
LINEARISATION_OUTPUTS: tuple[FmuVariable, ...] = tuple(
    _derivative_output(_ROWS[row], column) for row in LINEARISED_ROWS for column in INPUTS) + tuple(
    FmuVariable(evaluated_input_name(v.name), OUTPUT, REAL, v.unit,
                f"the input {v.name} the loads and their derivatives were evaluated at (equal to it: a master that "
                "reads outputs before it sets inputs passes the mechanism the point its loads belong to)")
    for v in INPUTS)
# where each linearisation output comes from: (its row in the kernels' Jacobian, layout.R_*, and its input), or the
# input it repeats
JACOBIAN_SLOTS: dict[str, tuple[int, int]] = {derivative_name(row, column.name): (RESULT_SLOTS[row], m)
                                              for row in LINEARISED_ROWS for m, column in enumerate(INPUTS)}
EVALUATED_INPUTS: dict[str, int] = {evaluated_input_name(v.name): m for m, v in enumerate(INPUTS)}

# The inputs each feed-through output depends on (ModelStructure): the contact geometry on the positions and
# angles alone, the forces on the velocities too (damping, friction).
POSITION_INPUTS = tuple(v.name for v in INPUTS if v.unit in ("m", "rad"))
GEOMETRY_OUTPUTS = frozenset({"penetration", "contact", "contact_angle", "eccentricity_x", "eccentricity_y"})
OUTPUT_DEPENDENCIES: dict[str, tuple[str, ...]] = {
    **{name: POSITION_INPUTS if name in GEOMETRY_OUTPUTS else tuple(v.name for v in INPUTS) for name in RESULT_SLOTS},
    **{name: tuple(v.name for v in INPUTS) for name in JACOBIAN_SLOTS},
    **{name: (INPUTS[m].name,) for name, m in EVALUATED_INPUTS.items()}}
# Names of the outputs that depend directly on the inputs (the rest change only in doStep).
FEED_THROUGH_OUTPUTS = frozenset(OUTPUT_DEPENDENCIES)


@dataclass(frozen=True)
class ParameterField:
    """An FMU parameter: its variable and the row of :data:`~wearjoint.joint_fields.JOINT_FIELDS` it comes from."""

    variable: FmuVariable
    row: JointField

    field = property(lambda self: self.row.field)
    component = property(lambda self: self.row.component)
    choices = property(lambda self: self.row.choices)       # (name, code) pairs of an Integer enumeration
    allowed = property(lambda self: self.row.allowed)
    slot = property(lambda self: self.row.slot)

    def allowed_text(self) -> str:
        return allowed_text(self.row)


def _parameter(row: JointField) -> ParameterField:
    """A row's FMU variable: an Integer enumeration for a choice (its codes listed), else a Real; the start value
    the parameter set's default."""
    start = coded_value(row, getattr(JointParameters, row.field))
    if row.choices is None:
        return ParameterField(FmuVariable(row.fmu_name, PARAMETER, REAL, row.unit, row.text, start), row)
    listed = ", ".join(f"{code} = {name}" for name, code in row.choices)
    return ParameterField(FmuVariable(row.fmu_name, PARAMETER, INTEGER, "", f"{row.text} ({listed})", int(start)),
                          row)


PARAMETERS: tuple[ParameterField, ...] = tuple(_parameter(row) for row in JOINT_FIELDS)
# an FMU state's head values (the state format, docs/reference/fmu.md): time, initialised flag, inputs, parameters,
# then the two flags the host's calls leave for the next step: derivatives read (a linearising host), onsets accepted
STATE_HEAD_SIZE = 2 + len(INPUTS) + len(PARAMETERS) + 2

N_POINTS_NAME = "n_points"


def n_points_variable(n_points: int) -> FmuVariable:
    """The read-only Integer fixing the number of bushing points (chosen when the FMU is built)."""
    return FmuVariable(N_POINTS_NAME, LOCAL, INTEGER, "",
                       "number of bushing points N_d, fixed when the FMU is built "
                       "(wearjoint build-fmu --n-points); not settable", n_points)


def wear_depth_name(point: int) -> str:
    """FMI structured name of the wear depth of bushing point ``point`` (1-based)."""
    return f"wear_depth[{point}]"


def profile_points(n_points: int, profile_stride: int = 1) -> range:
    """The bushing points (1-based) an FMI 2.0 build exposes as ``wear_depth[z]`` outputs: every
    ``profile_stride``-th from 1 (1: all; 0: none; the whole profile stays in the FMU's state)."""
    return range(1, n_points + 1, profile_stride) if profile_stride > 0 else range(0)


def wear_depth_outputs(n_points: int, profile_stride: int = 1) -> tuple[FmuVariable, ...]:
    """``wear_depth[z]`` of :func:`profile_points`: point z sits at bushing-frame angle z 2 pi / N_d."""
    return tuple(FmuVariable(wear_depth_name(z), OUTPUT, REAL, "m",
                             f"wear depth of bushing point {z} at angle {z}*2*pi/{n_points} rad, bushing frame")
                 for z in profile_points(n_points, profile_stride))


def fmu_variables(n_points: int, starts: dict | None = None, profile_stride: int = 1) -> list[FmuVariable]:
    """Every variable of the FMU in value-reference order; ``starts`` (FMU parameter name -> value,
    :func:`parameter_starts`) replaces the parameters' default start values; ``profile_stride``: which
    profile points are outputs (:func:`profile_points`)."""
    return [*INPUTS, *(parameter_variable(p, starts) for p in PARAMETERS), n_points_variable(n_points),
            *SCALAR_OUTPUTS, *LINEARISATION_OUTPUTS, *wear_depth_outputs(n_points, profile_stride)]


def parameter_variable(p: ParameterField, starts: dict | None = None) -> FmuVariable:
    """``p``'s variable with its start value from ``starts`` where given there."""
    if not starts or p.variable.name not in starts:
        return p.variable
    return dataclasses.replace(p.variable, start=starts[p.variable.name])


def parameter_starts(params: JointParameters) -> dict[str, float | int]:
    """The FMU parameter values of ``params`` that differ from the FMU's defaults: the start values a
    build for this joint writes (empty for the defaults)."""
    return {name: value for name, value in fmi_parameter_values(params).items()
            if value != next(p.variable.start for p in PARAMETERS if p.variable.name == name)}


UNIT_DEFINITIONS: dict[str, dict[str, int]] = {
    # unit name -> SI base-unit exponents (FMI 2 BaseUnit attributes); N/m1.5 has a
    # non-integer exponent of m and is declared without BaseUnit.
    "m": {"m": 1}, "m/s": {"m": 1, "s": -1}, "rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1},
    "N": {"kg": 1, "m": 1, "s": -2}, "N.m": {"kg": 1, "m": 2, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2},
    "N/m1.5": {}, "m2/N": {"kg": -1, "m": 1, "s": 2}, "m3": {"m": 3}, "s": {"s": 1}, "kg": {"kg": 1}, "1": {},
}


def _quotient(numerator: str, denominator: str) -> dict[str, int]:
    exponents = dict(UNIT_DEFINITIONS[numerator])
    for base, power in UNIT_DEFINITIONS[denominator].items():
        exponents[base] = exponents.get(base, 0) - power
    return {base: power for base, power in exponents.items() if power != 0}


UNIT_DEFINITIONS.update({row.unit + _DENOMINATOR[column.unit]: _quotient(row.unit, column.unit)
                         for row in (_ROWS[name] for name in LINEARISED_ROWS) for column in INPUTS})


def value_references(model_description) -> dict[str, int]:
    """Name -> value reference from a parsed modelDescription (e.g. ``fmpy.read_model_description``)."""
    return {v.name: v.valueReference for v in model_description.modelVariables}


def joint_parameters_from_fmi(values: dict, n_points: int) -> JointParameters:
    """Build :class:`JointParameters` from FMU parameter values keyed by FMU name.

    Missing names take the defaults; raises :class:`ParameterError` naming the parameter.
    """
    unknown = sorted(set(values) - {p.variable.name for p in PARAMETERS})
    if unknown:
        raise ParameterError(f"unknown FMU parameter(s) {', '.join(unknown)}")
    changes: dict = {"n_points": n_points}
    for p in PARAMETERS:
        if p.variable.name not in values:
            continue
        value = values[p.variable.name]
        if p.choices is not None:
            names = {code: name for name, code in p.choices}
            if isinstance(value, bool) or not isinstance(value, int) or value not in names:
                raise ParameterError(f"parameter {p.variable.name}={value!r} is invalid: allowed {p.allowed_text()[7:]}")
            changes[p.field] = names[value]
        elif p.component is not None:
            pair = list(changes.get(p.field, getattr(JointParameters, p.field)))
            pair[p.component] = value
            changes[p.field] = tuple(pair)
        else:
            changes[p.field] = value
    return JointParameters(**changes)


def fmi_parameter_values_by_type(params: JointParameters) -> tuple[dict[str, float], dict[str, int]]:
    """:func:`fmi_parameter_values` as (the Real parameters, the Integer ones: the options)."""
    values = fmi_parameter_values(params)
    integers = {p.variable.name for p in PARAMETERS if p.variable.type == INTEGER}
    return ({k: v for k, v in values.items() if k not in integers}, {k: v for k, v in values.items() if k in integers})


def fmi_parameter_values(params: JointParameters) -> dict[str, float | int]:
    """FMU parameter values (keyed by FMU name) reproducing ``params`` (n_points excluded: fixed at build)."""
    values = coded_values(params)
    return {p.variable.name: int(values[p.variable.name]) if p.choices is not None else values[p.variable.name]
            for p in PARAMETERS}
