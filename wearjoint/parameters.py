"""Parameter sets of the clearance/wear joint, and of the slider-crank (:mod:`wearjoint.mechanism_parameters`,
re-exported here with its load table).

All values are SI; field names carry their unit.  Defaults are the paper's
Tables 1 and 2 (see docs/reference/model.md §2).  Every constructor validates
its values and raises :class:`ParameterError` naming the parameter, its value
and the allowed range.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .checks import ParameterError, finite, finite_pair, integer, non_negative, of_type, positive, require
from .joint_fields import JOINT_FIELDS, check_joint_fields, real_field_values
from .mechanism_parameters import SliderCrankParameters, SliderForceTable
from .core.layout import (   # the wear-step limit, the wear batches, admissible states (docs/reference/model.md §3.11, §3.14, §7)
    ADMISSIBLE_PENETRATION_SHARE, MAX_WEAR_STEP_S, WEAR_BATCH_SHARE, WEAR_STEP_SHARE, WEAR_STEP_SHARE_EXPLICIT,
    choice_names,
)

# the bushing's points (n_points): fewer do not resolve a contact arc; more than a million (some 50 MB of profile
# arrays, the FMI 3.0 FMU's structural parameter's range) only exhaust the memory (1e9 points were the OOM killer's)
N_POINTS_MIN = 8
N_POINTS_MAX = 1_000_000

# the values of the choice fields (their codes: core.layout.CHOICES)
RHO_MODES = choice_names("rho_mode")
WEAR_PLACEMENTS = choice_names("wear_placement")
SLIDING_DISTANCES = choice_names("sliding_distance")
CONTACT_MODELS = choice_names("contact_model")
CONTACT_DAMPINGS = choice_names("contact_damping")
# the effective k_w [m^2/N] that reproduces the paper's 0.58 mm after 4000 revolutions with the defaults
# (conformal rho*, foundation contact and placement; `wear-study --calibrate-max-depth-m 0.58e-3`, docs/explanation/wear_study.md)
PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N = 5.576e-11
# the impact speed [m/s] at which the Hunt-Crossley damping restitutes `restitution`: the energy-weighted mean onset
# speed of the paper's slider-crank under its own law (docs/reference/model.md §3.5)
RESTITUTION_SPEED_M_S = 0.05
# the mass [kg] the Tsuji damping's restitution is exact for: the paper's slider-crank's rod and slider, the mass
# the crank-rod joint decelerates along the rod at the dead centres (SliderCrankParameters.contact_effective_mass_kg)
PAPER_EFFECTIVE_MASS_KG = 0.19 + 0.70
# the JointParameters fields that take one of a few names (the kernels and the FMU get the code)
OPTION_CHOICES = {f.field: choice_names(f.field) for f in JOINT_FIELDS if f.choices is not None}


def contact_stiffness(pin_radius_m: float, bushing_radius_m: float,
                      pin_youngs_modulus_Pa: float, pin_poisson_ratio: float,
                      bushing_youngs_modulus_Pa: float, bushing_poisson_ratio: float,
                      form: str = "internal") -> float:
    """Contact stiffness K [N/m^1.5], paper Eqs. (16)-(17): 4 E* sqrt(R) / 3.

    ``form="internal"`` (default, pin inside a bushing; the joint's default K,
    :func:`wearjoint.core.wear.materials_contact_stiffness`) uses the radius term
    R_i R_j / (R_j - R_i); it gives 7.951e10 for Table 2's values (printed 7.95e10).
    ``form="external"`` is the sum form printed in Eq. (16), R_i R_j / (R_i + R_j)
    (~5.6e9 for the paper's values; docs/reference/model.md §3.1).
    """
    from .kernel_calls import materials_contact_stiffness

    modulus = effective_modulus(pin_youngs_modulus_Pa, pin_poisson_ratio, bushing_youngs_modulus_Pa,
                                bushing_poisson_ratio)
    if form == "internal":
        return materials_contact_stiffness(pin_radius_m, bushing_radius_m, modulus)
    if form == "external":
        return 4.0 / 3.0 * modulus * math.sqrt(pin_radius_m * bushing_radius_m / (bushing_radius_m + pin_radius_m))
    raise ParameterError(f"parameter form={form!r} is invalid: allowed one of internal, external")


def effective_modulus(pin_youngs_modulus_Pa: float, pin_poisson_ratio: float,
                      bushing_youngs_modulus_Pa: float, bushing_poisson_ratio: float) -> float:
    """Composite modulus E* [Pa] of Eq. (32) (:func:`wearjoint.core.wear.effective_modulus`)."""
    from .kernel_calls import effective_modulus as kernel

    return kernel(pin_youngs_modulus_Pa, pin_poisson_ratio, bushing_youngs_modulus_Pa, bushing_poisson_ratio)


def restitution_of_law(law: str, restitution: float, impact_speed_m_s: float, restitution_speed_m_s: float,
                       exponent: float = 1.5, velocity_floor_m_s: float = 0.0) -> float:
    """Coefficient of restitution [-] of a free impact at normal speed ``impact_speed_m_s`` under damping law
    ``law`` asked for ``restitution`` (docs/reference/model.md §3.5, :mod:`wearjoint.core.damping`): Hunt-Crossley's
    closed form at a = alpha v (exact e_r at ``restitution_speed_m_s``); the Lankarani-Nikravesh laws' at
    a = chi v / max(v, floor) (chi = 3(1 - e_r^2)/4 for the paper's, exact e_r for ``-exact``, above the
    ``velocity_floor_m_s`` on the stored onset speed); Tsuji's e_r at every speed."""
    from .core import damping

    if law == "hunt-crossley":
        a = damping.hunt_crossley_damping(restitution) * impact_speed_m_s / restitution_speed_m_s
        return float(damping.hunt_crossley_restitution(a))
    if law == "tsuji":
        return float(damping.tsuji_restitution(damping.tsuji_damping(restitution, exponent), exponent))
    chi = (0.75 * (1.0 - restitution ** 2) if law == "lankarani-nikravesh"
           else damping.hunt_crossley_damping(restitution))
    return float(damping.hunt_crossley_restitution(chi * impact_speed_m_s / max(impact_speed_m_s, velocity_floor_m_s)))


@dataclass(frozen=True)
class JointParameters:
    """The clearance revolute joint with a wearing bushing (paper Secs. 2-5).

    The pin (hard, body i) is a circle of radius ``pin_radius_m`` centred at
    ``pin_offset_m`` in the pin body's frame; the bushing (soft, body j) is
    ``n_points`` discrete points at radius ``bushing_radius_m`` + wear depth
    around ``bushing_offset_m`` in the bushing body's frame (Eqs. 2-3, 34-35).

    The defaults are the joint's own: the paper's Table 2 values with the pin and bushing
    centres at the two bodies' reference points (offsets zero).  The slider-crank's offsets
    (crank tip, rod end) belong to the mechanism: :func:`paper_joint`.  The contact stiffness
    follows the radii and materials (Eqs. 16-17: 7.951e10 N/m^1.5 for Table 2) unless
    ``contact_stiffness_N_m1_5`` gives it (:attr:`stiffness_N_m1_5` is the one used).
    """

    pin_radius_m: float = 0.0100
    bushing_radius_m: float = 0.0101
    pin_offset_m: tuple[float, float] = (0.0, 0.0)
    bushing_offset_m: tuple[float, float] = (0.0, 0.0)
    contact_length_m: float = 0.006
    pin_youngs_modulus_Pa: float = 207e9
    pin_poisson_ratio: float = 0.29
    bushing_youngs_modulus_Pa: float = 71.7e9
    bushing_poisson_ratio: float = 0.33
    contact_stiffness_N_m1_5: float | None = None
    contact_exponent: float = 1.5
    restitution: float = 0.9
    friction_coefficient: float = 0.1
    friction_v0_m_s: float = 1e-3
    friction_v1_m_s: float = 1e-2
    wear_coefficient_m2_N: float = 5.05e-10           # PAPER_PRINTED_WEAR_COEFFICIENT_M2_N
    wear_factor: float = 1.0
    n_points: int = 1257
    rho_mode: str = "conformal"
    wear_placement: str = "foundation"
    sliding_distance: str = "rotation"
    impact_velocity_floor_m_s: float = 1e-3
    contact_model: str = "foundation"
    contact_damping: str = "hunt-crossley"
    restitution_speed_m_s: float = RESTITUTION_SPEED_M_S
    effective_mass_kg: float = PAPER_EFFECTIVE_MASS_KG
    wear_interval_s: float = MAX_WEAR_STEP_S

    def __post_init__(self):
        """The rules of :data:`~wearjoint.joint_fields.JOINT_FIELDS` (the FMU's too): a real value an int, a float or
        a numpy real scalar (kept as a float), a pair two of them, ``n_points`` an integer from N_POINTS_MIN to
        N_POINTS_MAX; a contact stiffness of 0 means "from the materials" (None)."""
        for name in ("pin_offset_m", "bushing_offset_m"):
            object.__setattr__(self, name, finite_pair(name, getattr(self, name),
                                                       "a pair (x, y) of finite lengths in metres"))
        object.__setattr__(self, "n_points", integer("n_points", self.n_points, N_POINTS_MIN, N_POINTS_MAX))
        for name, value in real_field_values(self).items():
            object.__setattr__(self, name, value)
        if self.contact_stiffness_N_m1_5 == 0.0:
            object.__setattr__(self, "contact_stiffness_N_m1_5", None)
        check_joint_fields(self)

    def restitution_at(self, impact_speed_m_s: float) -> float:
        """Coefficient of restitution [-] of a free impact at normal speed ``impact_speed_m_s`` under this joint's
        damping law (:func:`restitution_of_law`, docs/reference/model.md §3.5): ``restitution`` at ``restitution_speed_m_s``
        for Hunt-Crossley, at every speed for Tsuji and (above the velocity floor) Lankarani-Nikravesh exact;
        the paper's Lankarani-Nikravesh its own value (0.913 for 0.9)."""
        speed = finite("impact_speed_m_s", impact_speed_m_s)
        require("impact_speed_m_s", impact_speed_m_s, speed > 0.0, "> 0")
        return restitution_of_law(self.contact_damping, self.restitution, speed, self.restitution_speed_m_s,
                                  self.contact_exponent, self.impact_velocity_floor_m_s)

    @property
    def clearance_m(self) -> float:
        """Radial clearance c = R_j - R_i [m]."""
        return self.bushing_radius_m - self.pin_radius_m

    @property
    def admissible_penetration_m(self) -> float:
        """The deepest the pin may be in the bushing wall [m], ADMISSIBLE_PENETRATION_SHARE R_i: beyond it a state
        is no contact of these materials (docs/reference/model.md §3.14)."""
        return ADMISSIBLE_PENETRATION_SHARE * self.pin_radius_m

    @property
    def admissible_force_N(self) -> float:
        """The largest normal force a contact of this joint carries [N]: K delta_adm^n, the Hertz law's elastic force
        at :attr:`admissible_penetration_m` (docs/reference/model.md §3.14)."""
        return self.stiffness_N_m1_5 * self.admissible_penetration_m ** self.contact_exponent

    @property
    def foundation_modulus_N_m3(self) -> float:
        """k_f = 3 K sqrt(c) / (4 sqrt(2) L sqrt(R_i R_j)) [N/m^3] of the foundation contact (docs/reference/model.md §3.10)."""
        return (3.0 * self.stiffness_N_m1_5 * math.sqrt(self.clearance_m)
                / (4.0 * math.sqrt(2.0) * self.contact_length_m * math.sqrt(self.pin_radius_m * self.bushing_radius_m)))

    @property
    def wear_step_share(self) -> float:
        """The largest share k_f k_w F v dt of a step: WEAR_STEP_SHARE for the relaxed ``foundation`` update,
        WEAR_STEP_SHARE_EXPLICIT for the explicit placements (docs/reference/model.md §7)."""
        return WEAR_STEP_SHARE if self.wear_placement == "foundation" else WEAR_STEP_SHARE_EXPLICIT

    def max_wear_step_s(self, sliding_speed_m_s: float, share: float | None = None) -> float:
        """Longest accepted step [s] with wear: MAX_WEAR_STEP_S, or shorter where the step's share
        k_f k_w F v dt of a conforming contact sliding at ``sliding_speed_m_s`` (the share of its penetration
        an explicit step would wear: the mean overlap is p / k_f and such a step wears k_w F p v dt) passes
        ``share`` (default :attr:`wear_step_share`, the limit; docs/reference/model.md §7); inf without wear."""
        speed = non_negative("sliding_speed_m_s", sliding_speed_m_s)
        rate = self.foundation_modulus_N_m3 * self.wear_coefficient_m2_N * self.wear_factor * speed
        share = self.wear_step_share if share is None else min(positive("share", share), self.wear_step_share)
        return min(MAX_WEAR_STEP_S, share / rate) if rate > 0.0 else math.inf

    @property
    def effective_modulus_Pa(self) -> float:
        return effective_modulus(self.pin_youngs_modulus_Pa, self.pin_poisson_ratio,
                                 self.bushing_youngs_modulus_Pa, self.bushing_poisson_ratio)

    @property
    def stiffness_N_m1_5(self) -> float:
        """The contact stiffness K [N/m^n] the joint uses: ``contact_stiffness_N_m1_5`` where given, else
        :meth:`stiffness_from_materials` (Eqs. 16-17, docs/reference/model.md §3.1)."""
        given = self.contact_stiffness_N_m1_5
        return float(given) if given is not None else self.stiffness_from_materials()

    def stiffness_from_materials(self, form: str = "internal") -> float:
        """K [N/m^1.5] from this joint's radii and materials (Eqs. 16-17)."""
        return contact_stiffness(self.pin_radius_m, self.bushing_radius_m,
                                 self.pin_youngs_modulus_Pa, self.pin_poisson_ratio,
                                 self.bushing_youngs_modulus_Pa, self.bushing_poisson_ratio, form)

    def replace(self, **changes) -> "JointParameters":
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["pin_offset_m"] = list(self.pin_offset_m)
        d["bushing_offset_m"] = list(self.bushing_offset_m)
        return d


def paper_joint(mechanism: SliderCrankParameters | None = None, **changes) -> JointParameters:
    """Joint parameters of the paper with the offsets and the effective mass of ``mechanism``
    (:meth:`SliderCrankParameters.joint_defaults`) unless ``changes`` gives them."""
    mechanism = of_type("mechanism", mechanism, SliderCrankParameters, "the paper's") or SliderCrankParameters()
    return JointParameters(**{**mechanism.joint_defaults(), **changes})


def check_joint_fits_mechanism(joint: JointParameters, mechanism: SliderCrankParameters) -> None:
    """Raise if the joint's body-frame offsets do not sit at the clearance joint's centres
    (:meth:`SliderCrankParameters.joint_offsets`)."""
    expected = mechanism.joint_offsets()
    for name, value in expected.items():
        got = getattr(joint, name)
        require(name, got, all(abs(a - b) <= 1e-12 for a, b in zip(got, value)),
                f"{tuple(value)} for this slider-crank's {mechanism.clearance_joint} joint")


PAPER_JOINT_GEOMETRY = ("pin_radius_m", "bushing_radius_m", "contact_length_m")


def is_paper_case(joint: JointParameters, mechanism: SliderCrankParameters) -> bool:
    """The paper's mechanism (SliderCrankParameters(); the start angle, which a seed moves, aside) and joint
    geometry (radii, clearance, length; the wear coefficient, the wear factor and the rest may differ): the
    only case the paper's depth and its experiment describe, so the only one whose summary (and growth
    figure) carries them."""
    paper = JointParameters()
    return (mechanism.replace(initial_crank_angle_deg=0.0) == SliderCrankParameters()
            and all(getattr(joint, name) == getattr(paper, name) for name in PAPER_JOINT_GEOMETRY))


def joint_size_note(joint: JointParameters, mechanism: SliderCrankParameters) -> dict:
    """``joint_size_note`` (summary.json): a line where a length of the joint (its radii, its contact length) is longer
    than the mechanism's crank and rod both, as a length given in millimetres where metres are asked is (10 for a
    10 mm pin: every range check passes it); None otherwise."""
    reach = max(mechanism.crank_length_m, mechanism.rod_length_m)
    for name in PAPER_JOINT_GEOMETRY:
        value = getattr(joint, name)
        if value > reach:
            return {"joint_size_note": f"{name}={value:g} is longer than the mechanism's crank and rod "
                                       f"({mechanism.crank_length_m:g} m, {mechanism.rod_length_m:g} m): the joint's "
                                       "lengths are in metres"}
    return {"joint_size_note": None}


PAPER_PRINTED_WEAR_COEFFICIENT_M2_N = 5.05e-10    # the paper's Table 2 (the JointParameters default)


def wear_coefficient_source(joint: JointParameters, mechanism: SliderCrankParameters | None) -> dict:
    """Where the run's k_w came from (summary.json): ``wear_coefficient_source`` "paper printed" (Table 2's
    5.05e-10 m^2/N, the default), "paper calibrated" (5.576e-11, the paper's 0.58 mm after 4000 revolutions) or
    "given", and ``wear_coefficient_note``: a line where a mechanism or joint other than the paper's runs on the
    paper's coefficient (None otherwise; ``mechanism`` None: any machine's, as a joint FMU goes into any host)."""
    k_w = joint.wear_coefficient_m2_N
    source = {PAPER_PRINTED_WEAR_COEFFICIENT_M2_N: "paper printed",
              PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N: "paper calibrated"}.get(k_w, "given")
    note = None
    if source != "given" and joint.wear_factor > 0.0 and (mechanism is None or not is_paper_case(joint, mechanism)):
        note = (f"k_w = {k_w:g} m^2/N is the paper's ({source}: its aluminium bushing, steel pin, load and "
                "speed); for this machine give its own (--wear-coefficient-m2-N) or fit one to measured depths "
                "(wearjoint calibrate on a wear study of it, docs/how-to/calibrate.md)")
    return {"wear_coefficient_source": source, "wear_coefficient_note": note}


__all__ = ["JointParameters", "SliderCrankParameters", "SliderForceTable", "ParameterError", "require", "finite",
           "contact_stiffness", "is_paper_case", "PAPER_JOINT_GEOMETRY", "effective_modulus", "paper_joint",
           "check_joint_fits_mechanism", "RHO_MODES", "WEAR_PLACEMENTS", "SLIDING_DISTANCES", "CONTACT_MODELS",
           "CONTACT_DAMPINGS", "OPTION_CHOICES", "restitution_of_law", "RESTITUTION_SPEED_M_S", "PAPER_EFFECTIVE_MASS_KG",
           "PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N", "PAPER_PRINTED_WEAR_COEFFICIENT_M2_N", "wear_coefficient_source",
           "WEAR_STEP_SHARE", "WEAR_STEP_SHARE_EXPLICIT", "MAX_WEAR_STEP_S", "WEAR_BATCH_SHARE"]
