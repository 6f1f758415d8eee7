"""The clearance joint's parameters: one table (:data:`JOINT_FIELDS`), as :data:`MECHANISM_FIELDS
<wearjoint.mechanism_parameters.MECHANISM_FIELDS>` is the slider-crank's.

Each row is one value the kernels read (a slot of the joint's parameter vector, ``core.layout.P_*``): its
:class:`~wearjoint.parameters.JointParameters` field (and component, for the offsets' pairs), the joint FMU's
parameter name, unit, what it is (the FMU's description and the command line's help), the allowed rule, and for
a choice its (name, code) pairs (``core.layout.CHOICES``).  The dataclass checks (:func:`check_joint_fields`),
the packed vector (:func:`coded_values`, ``joint.pack_joint_parameters``), the FMU's parameters and checks
(:mod:`wearjoint.fmu.variables`, the native FMU's generated table) and the command line's help come from it.
A new choice of a parameter is one pair in ``core.layout.CHOICES`` and its kernel branch; a new parameter one
row here and its slot.  The rows' order is the FMU's value-reference order.
"""
from __future__ import annotations

from dataclasses import dataclass

from .checks import ANY, Allowed, finite, require
from .core import layout as L


@dataclass(frozen=True)
class JointField:
    """One slot of the kernels' joint parameters: where its value comes from and how it is named."""

    fmu_name: str               # the joint FMU's parameter
    field: str                  # the JointParameters field
    unit: str                   # SI ("1" for none)
    text: str                   # what it is (FMU description, CLI help)
    slot: int                   # core.layout.P_*
    allowed: Allowed = ANY      # the rule on the coded value (a choice: its codes)
    component: int | None = None  # the element of a pair (x, y)
    unset_is_zero: bool = False   # None ("not given") is coded as 0 (the contact stiffness: from the materials)
    read_by: tuple[str, ...] = ()  # the contact_damping laws that read it (empty: every law)

    @property
    def choices(self) -> tuple[tuple[str, int], ...] | None:
        """A choice's (name, code) pairs, None for a real value."""
        return L.CHOICES.get(self.field)


_OPEN_HALF = Allowed(0.0, True, 0.5, True)
# bounds no joint passes, so that no value the rules admit overflows the contact's arithmetic (K, k_f, the forces, the
# Hertz half-width stay finite): radii from a micrometre (MEMS hinges) to 100 m, a contact at least a micrometre long,
# moduli up to ten times diamond's, a given K up to 1e20 N/m^n (the paper's: 7.95e10 N/m^1.5).  Moduli from foam
# rubber's: 71.7 (GPa written as Pa) had passed, and the run failed later, blaming its step
_MODULUS = Allowed(1e5, False, 1e13, note="Pa, from foam rubber's 1e5 Pa to 10x diamond's 1.2e12 Pa")
# a body frame's point within a kilometre of its origin [m] (1e300 passed, and its contact said "penetration -inf")
_OFFSET = Allowed(-1e3, False, 1e3)
# a speed of the contact [m/s]: a hundred metres a second, beyond any joint's sliding or impact
_SPEED = Allowed(0.0, False, 100.0)
# a restitution from 1e-3, below any material's: at 1e-4 the paper's joint chattered (83-1234 impacts a revolution
# against 11-22 from 1e-3 up) and from 1e-8 the first impact's damping force passed the admissible force
_RESTITUTION = Allowed(1e-3, False, 1.0)
JOINT_FIELDS: tuple[JointField, ...] = (
    JointField("pin_radius", "pin_radius_m", "m", "pin radius R_i", L.P_PIN_RADIUS,
               Allowed(1e-6, False, 100.0, note="m")),
    JointField("bushing_radius", "bushing_radius_m", "m", "unworn bushing radius R_j (> pin_radius)",
               L.P_BUSHING_RADIUS, Allowed(0.0, True, 100.0, above="pin_radius", note="m")),
    JointField("pin_offset_x", "pin_offset_m", "m", "pin centre in the pin body frame, x", L.P_PIN_OFFSET_X,
               _OFFSET, component=0),
    JointField("pin_offset_y", "pin_offset_m", "m", "pin centre in the pin body frame, y", L.P_PIN_OFFSET_Y,
               _OFFSET, component=1),
    JointField("bushing_offset_x", "bushing_offset_m", "m", "bushing centre in the bushing body frame, x",
               L.P_BUSHING_OFFSET_X, _OFFSET, component=0),
    JointField("bushing_offset_y", "bushing_offset_m", "m", "bushing centre in the bushing body frame, y",
               L.P_BUSHING_OFFSET_Y, _OFFSET, component=1),
    JointField("contact_length", "contact_length_m", "m", "axial contact length L", L.P_CONTACT_LENGTH,
               Allowed(1e-6, False, 100.0, note="m")),
    JointField("pin_youngs_modulus", "pin_youngs_modulus_Pa", "Pa", "Young's modulus of the pin",
               L.P_PIN_YOUNGS_MODULUS, _MODULUS),
    JointField("pin_poisson_ratio", "pin_poisson_ratio", "1", "Poisson ratio of the pin", L.P_PIN_POISSON_RATIO,
               _OPEN_HALF),
    JointField("bushing_youngs_modulus", "bushing_youngs_modulus_Pa", "Pa", "Young's modulus of the bushing",
               L.P_BUSHING_YOUNGS_MODULUS, _MODULUS),
    JointField("bushing_poisson_ratio", "bushing_poisson_ratio", "1", "Poisson ratio of the bushing",
               L.P_BUSHING_POISSON_RATIO, _OPEN_HALF),
    JointField("contact_stiffness", "contact_stiffness_N_m1_5", "N/m1.5",
               "contact stiffness K of F = K delta^n (unit N/m^n with n = contact_exponent); 0: from the radii and "
               "materials, 4 E* sqrt(R_i R_j / (R_j - R_i)) / 3 (Eqs. 16-17)", L.P_STIFFNESS,
               Allowed(0.0, False, 1e20, note="N/m^n; 0: from the materials"),
               unset_is_zero=True),
    JointField("contact_exponent", "contact_exponent", "1",
               "exponent n of the contact law (1.5 with the foundation contact: a linear foundation on a circle)",
               L.P_EXPONENT, Allowed(0.0, True, equal=1.5, when=(
                   ("contact_model", L.CONTACT_FOUNDATION, "foundation", "contact_model='foundation' (other "
                                                                         "exponents need contact_model='deepest')"),
                   ("contact_stiffness", 0.0, "K from the materials",
                    "no contact_stiffness_N_m1_5 given (K from the materials)")))),
    JointField("restitution", "restitution", "1", "coefficient of restitution e_r in [0.001, 1]: a single impact's "
               "rebound (hunt-crossley: at restitution_speed; tsuji, lankarani-nikravesh-exact: at any speed)",
               L.P_RESTITUTION, _RESTITUTION),
    JointField("friction_coefficient", "friction_coefficient", "1", "Coulomb friction coefficient mu", L.P_FRICTION,
               Allowed(0.0, False, 10.0)),
    JointField("friction_v0", "friction_v0_m_s", "m/s", "friction tolerance velocity v0 (stick below)", L.P_V0,
               _SPEED),
    JointField("friction_v1", "friction_v1_m_s", "m/s", "friction tolerance velocity v1 (> friction_v0, full slip "
               "above)", L.P_V1, Allowed(0.0, True, _SPEED.high, above="friction_v0")),
    JointField("wear_coefficient", "wear_coefficient_m2_N", "m2/N", "Archard wear coefficient k_w",
               L.P_ARCHARD_COEFFICIENT, Allowed(0.0, False, 1e-6, note="m2/N, 2000 times the paper's printed 5.05e-10")),
    JointField("wear_factor", "wear_factor", "1", "wear acceleration factor multiplying k_w", L.P_WEAR_FACTOR,
               Allowed(0.0, False, 1e6, note="times; 1: the real rate")),
    JointField("impact_velocity_floor", "impact_velocity_floor_m_s", "m/s",
               "Lankarani-Nikravesh damping: floor on the stored impact velocity", L.P_VELOCITY_FLOOR,
               Allowed(0.0, True, _SPEED.high),
               read_by=("lankarani-nikravesh", "lankarani-nikravesh-exact")),
    JointField("rho_mode", "rho_mode", "", "equivalent radius of the Hertz half-width (docs/reference/model.md §3.2)",
               L.P_RHO_MODE),
    JointField("wear_placement", "wear_placement", "", "bushing points receiving the wear increment "
               "(docs/reference/model.md §3.7)", L.P_WEAR_PLACEMENT),
    JointField("sliding_distance", "sliding_distance", "", "sliding distance of the Archard update, Eq. 33 "
               "(docs/reference/model.md §3.8)", L.P_SLIDING),
    JointField("contact_model", "contact_model", "",
               "contact force: elastic-foundation pressure over the worn bushing, or the paper's deepest bushing "
               "point (docs/reference/model.md §3.10)", L.P_CONTACT_MODEL),
    JointField("contact_damping", "contact_damping", "",
               "contact damping: Hunt-Crossley (restitution e_r at restitution_speed), the paper's "
               "Lankarani-Nikravesh (chi = 3(1 - e_r^2)/4 over the stored impact velocity: restitution 0.913 for "
               "e_r 0.9), Tsuji (restitution e_r at every speed for a body of effective_mass), or "
               "Lankarani-Nikravesh exact (e_r at every speed above impact_velocity_floor) (docs/reference/model.md §3.5)",
               L.P_CONTACT_DAMPING),
    JointField("restitution_speed", "restitution_speed_m_s", "m/s",
               "impact speed at which the Hunt-Crossley damping gives the restitution e_r", L.P_RESTITUTION_SPEED,
               Allowed(0.0, True, _SPEED.high), read_by=("hunt-crossley",)),
    JointField("effective_mass", "effective_mass_kg", "kg",
               "Tsuji damping: the mass the contact decelerates along its normal (the restitution is e_r for it)",
               L.P_EFFECTIVE_MASS, Allowed(1e-6, False, 1e6, note="kg"), read_by=("tsuji",)),
    JointField("wear_interval", "wear_interval_s", "s",
               "the foundation's wear is applied once per this much contact time (and when a contact ends; "
               "0: at every accepted step; docs/reference/model.md §3.11)", L.P_WEAR_INTERVAL,
               Allowed(0.0, False, L.MAX_WEAR_STEP_S)),
)
FIELD_NAMES = {f.fmu_name: f.field for f in JOINT_FIELDS}     # the rules' names as the parameter set spells them
if sorted(f.slot for f in JOINT_FIELDS) != sorted(set(f.slot for f in JOINT_FIELDS)):
    raise RuntimeError("JOINT_FIELDS gives a kernel slot twice")


def coded_value(f: JointField, value) -> float:
    """A field's value as the kernels and the FMU take it: a choice's code, a pair's component, an unset value of a
    row ``unset_is_zero`` (the contact stiffness: None, from the materials) 0."""
    if f.choices is not None:
        return L.choice_code(f.field, value)
    if f.component is not None:
        return float(value[f.component])
    return 0.0 if value is None and f.unset_is_zero else float(value)


def coded_values(params) -> dict[str, float]:
    """FMU parameter name -> coded value (:func:`coded_value`) of a :class:`JointParameters`."""
    return {f.fmu_name: coded_value(f, getattr(params, f.field)) for f in JOINT_FIELDS}


def allowed_text(f: JointField, names=None, values=None) -> str:
    """A row's allowed values as the error messages state them (``names``, ``values``: :meth:`Allowed.text`'s)."""
    if f.choices is not None:
        if names:
            return "one of " + ", ".join(name for name, _ in f.choices)
        return "one of " + ", ".join(f"{code} ({name})" for name, code in f.choices)
    return f.allowed.text(names, values)


def largest_value(field: str) -> float:
    """The largest value the rules admit for the JointParameters field ``field`` (its row's ``high``)."""
    return next(f.allowed.high for f in JOINT_FIELDS if f.field == field)


def real_field_values(params) -> dict[str, float]:
    """The real values of ``params`` (a JointParameters; the pairs and an unset value of a row ``unset_is_zero``
    aside) as floats by field name; ParameterError naming the first that is no finite real number
    (:func:`~wearjoint.checks.finite`), stating its row's rule."""
    return {f.field: finite(f.field, getattr(params, f.field), "" if f.allowed == ANY else allowed_text(f, FIELD_NAMES))
            for f in JOINT_FIELDS if f.choices is None and f.component is None
            and not (f.unset_is_zero and getattr(params, f.field) is None)}


def unread_by(contact_damping: str, fields) -> list[JointField]:
    """The rows of ``fields`` (JointParameters field names) that the damping law ``contact_damping`` does not read
    (:attr:`JointField.read_by`): a value given for one of them changes nothing."""
    return [f for f in JOINT_FIELDS if f.field in set(fields) and f.read_by and contact_damping not in f.read_by]


def check_joint_fields(params) -> None:
    """ParameterError naming the first field of ``params`` (a JointParameters, its real values finite floats:
    :func:`real_field_values`) outside its row's rule, with the value of the field the rule compares it to (the
    value the user set may be that one: a pin radius past the default bushing's)."""
    for f in JOINT_FIELDS:
        if f.choices is not None:
            value = getattr(params, f.field)
            require(f.field, value, isinstance(value, str) and value in dict(f.choices), allowed_text(f, FIELD_NAMES))
    values = coded_values(params)
    for f in JOINT_FIELDS:
        if f.choices is None and not f.allowed.admits(values[f.fmu_name], values):
            other = FIELD_NAMES.get(f.allowed.above)
            compared = f" ({other} = {getattr(params, other)!r})" if other else ""
            require(f.field, getattr(params, f.field), False, allowed_text(f, FIELD_NAMES, values) + compared)


__all__ = ["JointField", "JOINT_FIELDS", "FIELD_NAMES", "coded_value", "coded_values", "allowed_text",
           "real_field_values", "check_joint_fields", "unread_by", "largest_value"]
