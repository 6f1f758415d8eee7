"""The variables of the ``ClearanceWearJoint`` FMU: names, order, units, descriptions, defaults.

This table is the single definition shared by the pythonfmu slave
(``fmu_src/pythonfmu/ClearanceWearJoint.py``), the build step (units, ModelStructure) and
co-simulation masters (value references looked up by name).  The slave
registers the variables in exactly the order of :func:`fmu_variables`, so
value reference = position in that list; masters should still look them up
from the modelDescription with :func:`value_references`.

Imports only the standard library, :mod:`wearjoint.parameters` and :mod:`wearjoint.core.layout`.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..core import layout
from ..parameters import (
    CONTACT_DAMPINGS, CONTACT_MODELS, RHO_MODES, SLIDING_DISTANCES, WEAR_PLACEMENTS, JointParameters, ParameterError,
)

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
}
WEAR_SUMMARY_NAMES = ("max_wear_depth", "worn_volume")

# Names of the outputs that depend directly on the inputs (the rest change only in doStep).
FEED_THROUGH_OUTPUTS = frozenset(RESULT_SLOTS)
# The inputs each feed-through output depends on (ModelStructure): the contact geometry on the positions and
# angles alone, the forces on the velocities too (damping, friction).
POSITION_INPUTS = tuple(v.name for v in INPUTS if v.unit in ("m", "rad"))
GEOMETRY_OUTPUTS = frozenset({"penetration", "contact", "contact_angle", "eccentricity_x", "eccentricity_y"})
OUTPUT_DEPENDENCIES: dict[str, tuple[str, ...]] = {
    name: POSITION_INPUTS if name in GEOMETRY_OUTPUTS else tuple(v.name for v in INPUTS) for name in RESULT_SLOTS}


@dataclass(frozen=True)
class Allowed:
    """The allowed values of a Real parameter: finite, within (or on) ``low`` / ``high`` where
    given, greater than the parameter named ``above``, and ``equal`` where a parameter of ``when`` =
    ((its name, value, label), ...) has that value (the same rules as :class:`JointParameters`; the
    native FMU checks them from this table)."""

    low: float | None = None
    low_open: bool = False
    high: float | None = None
    high_open: bool = False
    above: str | None = None
    equal: float | None = None
    when: tuple[tuple[str, float, str], ...] = ()

    def text(self) -> str:
        """The rule as :class:`ParameterError` messages state it, e.g. ``> 0`` or ``in (0, 1]``."""
        if self.low is not None and self.high is not None:
            rule = f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"
        elif self.low is not None:
            rule = f"{'>' if self.low_open else '>='} {self.low:g}"
        else:
            rule = "a finite real number"
        for other, value, label in self.when:
            rule += f", and {self.equal!r} with {other}={value:g} ({label})"
        return rule + (f" and > {self.above}" if self.above else "")


ANY, POSITIVE, NON_NEGATIVE = Allowed(), Allowed(0.0, True), Allowed(0.0)


@dataclass(frozen=True)
class ParameterField:
    """How an FMU parameter maps onto a :class:`JointParameters` field."""

    variable: FmuVariable
    field: str
    component: int | None = None               # index into a (x, y) field
    choices: tuple[str, ...] | None = None     # Integer enumeration: value = index into choices
    allowed: Allowed = ANY                     # Real parameters: the allowed values

    def allowed_text(self) -> str:
        if self.choices is not None:
            return "one of " + ", ".join(f"{i} ({c})" for i, c in enumerate(self.choices))
        return self.allowed.text()


def _fmi_real(value) -> float:
    """A Real parameter's FMU value: an unset contact stiffness (None: from the materials) is 0."""
    return 0.0 if value is None else float(value)


def _real(name, unit, field, text, component=None, allowed=ANY) -> ParameterField:
    default = getattr(JointParameters, field)
    start = default if component is None else default[component]
    return ParameterField(FmuVariable(name, PARAMETER, REAL, unit, text, _fmi_real(start)), field, component,
                          allowed=allowed)


def _choice(name, field, choices, text) -> ParameterField:
    listed = ", ".join(f"{i} = {c}" for i, c in enumerate(choices))
    start = choices.index(getattr(JointParameters, field))
    return ParameterField(FmuVariable(name, PARAMETER, INTEGER, "", f"{text} ({listed})", start), field, choices=choices)


PARAMETERS: tuple[ParameterField, ...] = (
    _real("pin_radius", "m", "pin_radius_m", "pin radius R_i", allowed=POSITIVE),
    _real("bushing_radius", "m", "bushing_radius_m", "unworn bushing radius R_j (> pin_radius)",
          allowed=Allowed(0.0, True, above="pin_radius")),
    _real("pin_offset_x", "m", "pin_offset_m", "pin centre in the pin body frame, x", 0),
    _real("pin_offset_y", "m", "pin_offset_m", "pin centre in the pin body frame, y", 1),
    _real("bushing_offset_x", "m", "bushing_offset_m", "bushing centre in the bushing body frame, x", 0),
    _real("bushing_offset_y", "m", "bushing_offset_m", "bushing centre in the bushing body frame, y", 1),
    _real("contact_length", "m", "contact_length_m", "axial contact length L", allowed=POSITIVE),
    _real("pin_youngs_modulus", "Pa", "pin_youngs_modulus_Pa", "Young's modulus of the pin", allowed=POSITIVE),
    _real("pin_poisson_ratio", "1", "pin_poisson_ratio", "Poisson ratio of the pin",
          allowed=Allowed(0.0, True, 0.5, True)),
    _real("bushing_youngs_modulus", "Pa", "bushing_youngs_modulus_Pa", "Young's modulus of the bushing",
          allowed=POSITIVE),
    _real("bushing_poisson_ratio", "1", "bushing_poisson_ratio", "Poisson ratio of the bushing",
          allowed=Allowed(0.0, True, 0.5, True)),
    _real("contact_stiffness", "N/m1.5", "contact_stiffness_N_m1_5",
          "contact stiffness K of F = K delta^n (unit N/m^n with n = contact_exponent); 0: from the radii and "
          "materials, 4 E* sqrt(R_i R_j / (R_j - R_i)) / 3 (Eqs. 16-17)", allowed=NON_NEGATIVE),
    _real("contact_exponent", "1", "contact_exponent",
          "exponent n of the contact law (1.5 with the foundation contact: a linear foundation on a circle)",
          allowed=Allowed(0.0, True, equal=1.5, when=(
              ("contact_model", CONTACT_MODELS.index("foundation"), "foundation"),
              ("contact_stiffness", 0.0, "K from the materials")))),
    _real("restitution", "1", "restitution", "coefficient of restitution e_r in (0, 1]",
          allowed=Allowed(0.0, True, 1.0)),
    _real("friction_coefficient", "1", "friction_coefficient", "Coulomb friction coefficient mu",
          allowed=NON_NEGATIVE),
    _real("friction_v0", "m/s", "friction_v0_m_s", "friction tolerance velocity v0 (stick below)",
          allowed=NON_NEGATIVE),
    _real("friction_v1", "m/s", "friction_v1_m_s", "friction tolerance velocity v1 (> friction_v0, full slip above)",
          allowed=Allowed(0.0, True, above="friction_v0")),
    _real("wear_coefficient", "m2/N", "wear_coefficient_m2_N", "Archard wear coefficient k_w", allowed=NON_NEGATIVE),
    _real("wear_factor", "1", "wear_factor", "wear acceleration factor multiplying k_w",
          allowed=NON_NEGATIVE),
    _real("impact_velocity_floor", "m/s", "impact_velocity_floor_m_s",
          "Lankarani-Nikravesh damping: floor on the stored impact velocity", allowed=POSITIVE),
    _choice("rho_mode", "rho_mode", RHO_MODES, "equivalent radius of the Hertz half-width"),
    _choice("wear_placement", "wear_placement", WEAR_PLACEMENTS, "bushing points receiving the wear increment"),
    _choice("sliding_distance", "sliding_distance", SLIDING_DISTANCES, "sliding distance of the Archard update"),
    _choice("contact_model", "contact_model", CONTACT_MODELS,
            "contact force: elastic-foundation pressure over the worn bushing, or the deepest bushing point"),
    _choice("contact_damping", "contact_damping", CONTACT_DAMPINGS,
            "contact damping: Hunt-Crossley (restitution e_r at restitution_speed), the paper's Lankarani-Nikravesh "
            "(chi = 3(1 - e_r^2)/4 over the stored impact velocity: restitution 0.913 for e_r 0.9), or Tsuji "
            "(restitution e_r at every speed for a body of effective_mass)"),
    _real("restitution_speed", "m/s", "restitution_speed_m_s",
          "impact speed at which the Hunt-Crossley damping gives the restitution e_r", allowed=POSITIVE),
    _real("effective_mass", "kg", "effective_mass_kg",
          "Tsuji damping: the mass the contact decelerates along its normal (the restitution is e_r for it)",
          allowed=POSITIVE),
    _real("wear_interval", "s", "wear_interval_s",
          "the foundation's wear is applied once per this much contact time (and when a contact ends; "
          "0: at every accepted step)", allowed=Allowed(0.0, False, layout.MAX_WEAR_STEP_S)),
)
# an FMU state's head values (the state format, docs/model.md): time, initialised flag, inputs, parameters
STATE_HEAD_SIZE = 2 + len(INPUTS) + len(PARAMETERS)

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
            *SCALAR_OUTPUTS, *wear_depth_outputs(n_points, profile_stride)]


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
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < len(p.choices):
                allowed = ", ".join(f"{i} ({c})" for i, c in enumerate(p.choices))
                raise ParameterError(f"parameter {p.variable.name}={value!r} is invalid: allowed {allowed}")
            changes[p.field] = p.choices[value]
        elif p.component is not None:
            pair = list(changes.get(p.field, getattr(JointParameters, p.field)))
            pair[p.component] = value
            changes[p.field] = tuple(pair)
        elif p.field == "contact_stiffness_N_m1_5" and value == 0.0:
            changes[p.field] = None      # 0: from the radii and materials
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
    out: dict[str, float | int] = {}
    for p in PARAMETERS:
        value = getattr(params, p.field)
        if p.choices is not None:
            out[p.variable.name] = p.choices.index(value)
        elif p.component is not None:
            out[p.variable.name] = float(value[p.component])
        else:
            out[p.variable.name] = _fmi_real(value)
    return out
