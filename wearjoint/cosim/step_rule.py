"""The communication step a fixed-step master needs for the joint FMU in a slider-crank
(docs/explanation/cosim_study.md, "Choosing the communication step for your own mechanism").

A master holding the joint's loads over a step h feeds a contact force lagging the motion by h/2
(inputs set before the loads are read: "on time") or 3h/2 (loads read first: "one step late"); the
lag pumps energy into a contact faster than the damping takes it out when

    h > 4 ln(1/e_r) / (pi omega)   (on time; one step late: a third of it),
    omega = sqrt(k / m),  k = dF/d delta = 1.5 K^(2/3) F_max^(1/3),

m the smallest effective mass at the pin along a contact direction.  Once wear has worn a groove
the pin conforms to (the foundation contact), the contact is stiffer: pressed delta into a groove of
its own radius, the foundation k_f pushes back over half the circle with the normal force
k_f L R_i delta integral of cos^2 over (-pi/2, pi/2) = (pi/2) k_f L R_i delta (R_i the pin's radius),
so k_groove = (pi/2) k_f L R_i, whatever the force; the rule then takes the stiffer of the two.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..parameters import JointParameters, ParameterError, SliderCrankParameters


@dataclass(frozen=True)
class StepRule:
    """The stability limits of a zero-order-hold master's step [s] and what they rest on."""

    on_time_s: float                # inputs set before the loads are read
    one_step_late_s: float          # loads read before the new inputs are set
    max_force_N: float              # F_max the rule assumes
    effective_mass_kg: float        # the smallest effective mass at the pin
    contact_stiffness_N_m: float    # k = 1.5 K^(2/3) F_max^(1/3)
    restitution: float              # e_r the damping gives (Hunt-Crossley: at its restitution speed)
    groove_stiffness_N_m: float     # (pi/2) k_f L R_i: a conforming groove's (foundation contact; 0 otherwise)
    groove_on_time_s: float         # on_time_s once a groove forms (the stiffer of the two contacts)

    def to_dict(self) -> dict:
        return asdict(self)

    def text(self) -> str:
        """One line for a command's output."""
        return (f"communication step (docs/explanation/cosim_study.md): below {self.on_time_s * 1e6:.2g} us with the inputs set "
                f"before the loads are read, {self.one_step_late_s * 1e6:.2g} us one step late (F_max "
                f"{self.max_force_N:.3g} N, the smallest mass at the pin along a contact direction "
                f"{self.effective_mass_kg:.3g} kg), once wear forms a "
                f"groove {self.groove_on_time_s * 1e6:.2g} us on time (its stiffness "
                f"{self.groove_stiffness_N_m:.3g} N/m); a master inside the monolithic scatter needs about half of it")


def effective_mass_kg(mechanism: SliderCrankParameters) -> float:
    """The smallest effective mass at the clearance joint [kg]: along the rod and across it
    (:attr:`SliderCrankParameters.contact_effective_mass_kg`, :attr:`SliderCrankParameters.rod_across_mass_kg`;
    at the crank-rod joint m2 + m3 and (I2 + m2 l2^2/4) / l2^2, the crank driven)."""
    return min(mechanism.rod_across_mass_kg, mechanism.contact_effective_mass_kg)


def groove_stiffness_N_m(joint: JointParameters) -> float:
    """A conforming groove's contact stiffness [N/m]: (pi/2) k_f L R_i for the foundation contact (module
    docstring), 0 for the deepest-point contact (its Hertz law holds on any profile)."""
    if joint.contact_model != "foundation":
        return 0.0
    return 0.5 * math.pi * joint.foundation_modulus_N_m3 * joint.contact_length_m * joint.pin_radius_m


def estimated_max_force_N(joint: JointParameters, mechanism: SliderCrankParameters) -> float:
    """An upper estimate of the largest contact force [N]: a Hertz impact, F = K^(2/5) (5/4 m v^2)^(3/5), of the
    effective mass at the crank pin's speed v = omega l1 (about 4x the 1000 N measured on the paper's mechanism;
    the rule depends on it as F_max^(-1/6))."""
    v = mechanism.omega_rad_s * mechanism.crank_length_m
    energy = 1.25 * effective_mass_kg(mechanism) * v * v
    return joint.stiffness_N_m1_5 ** 0.4 * energy ** 0.6


def communication_step_rule(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                            max_force_N: float | None = None) -> StepRule:
    """The step limits of :class:`StepRule` for ``joint`` in the slider-crank ``mechanism`` (defaults: the
    paper's); ``max_force_N``: the largest contact force expected (default :func:`estimated_max_force_N`)."""
    mechanism = mechanism or SliderCrankParameters()
    joint = joint or JointParameters()
    force = estimated_max_force_N(joint, mechanism) if max_force_N is None else float(max_force_N)
    if not force > 0.0 or not math.isfinite(force):
        raise ParameterError(f"parameter max_force_N={max_force_N!r} is invalid: allowed a finite value > 0")
    mass = effective_mass_kg(mechanism)
    k = 1.5 * joint.stiffness_N_m1_5 ** (2.0 / 3.0) * force ** (1.0 / 3.0)
    groove = groove_stiffness_N_m(joint)
    on_time = _on_time_s(k, mass, joint.restitution)
    return StepRule(on_time, on_time / 3.0, force, mass, k, joint.restitution, groove,
                    _on_time_s(max(k, groove), mass, joint.restitution))


def _on_time_s(stiffness_N_m: float, mass_kg: float, restitution: float) -> float:
    """4 ln(1/e_r) / (pi omega), omega = sqrt(k/m) [s] (module docstring; 0 without damping)."""
    return (4.0 * math.log(1.0 / restitution) / (math.pi * math.sqrt(stiffness_N_m / mass_kg)) if restitution < 1.0
            else 0.0)


def paper_step_scale(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None) -> float:
    """The factor (<= 1) by which a step measured on the paper's mechanism shrinks for ``joint`` in
    ``mechanism``: the ratio of their on-time limits, and for a joint that wears also of their limits once a
    groove forms, the smaller, never above 1 (a stiffer or lighter joint, or a stiffer groove, needs a smaller
    step; a softer one keeps the paper's measured step)."""
    joint = joint or JointParameters()
    rule, paper = communication_step_rule(joint, mechanism), communication_step_rule()
    scale = rule.on_time_s / paper.on_time_s
    if joint.wear_coefficient_m2_N * joint.wear_factor > 0.0:
        scale = min(scale, rule.groove_on_time_s / paper.groove_on_time_s)
    return min(1.0, scale)


# a given step longer than this many times the package's is an answer no ensemble checked: said so
CHECKED_STEP_FACTOR = 2.0


def unchecked_step_note(step_s: float, load_coupling: str, joint: JointParameters,
                        mechanism: SliderCrankParameters) -> str:
    """'' for a fixed-step master's ``step_s`` [s] within CHECKED_STEP_FACTOR times the step the SSP package asks
    for with ``load_coupling`` (wearjoint.fmu.ssp.package_step_s, scaled by :func:`paper_step_scale`), else a note
    that its answers are not checked (a package at 10 times its step completed with a third of the contact)."""
    from ..fmu.ssp import package_step_s

    package = package_step_s(load_coupling, paper_step_scale(joint, mechanism), math.inf, mechanism.period_s)
    if not step_s > CHECKED_STEP_FACTOR * package:
        return ""
    return (f"--step {step_s:g} s is {step_s / package:.3g} times the checked step of --load-coupling {load_coupling} "
            f"here ({package:.3g} s, whose ensembles sit inside the monolithic scatter): answers at it are not "
            "checked and may be far off or blow up (docs/how-to/choose_step_and_master.md)")


__all__ = ["StepRule", "communication_step_rule", "unchecked_step_note", "effective_mass_kg", "estimated_max_force_N", "groove_stiffness_N_m",
           "paper_step_scale"]
