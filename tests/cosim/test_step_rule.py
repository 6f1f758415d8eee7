"""The communication-step rule of docs/explanation/cosim_study.md as a function of the mechanism and the joint."""
import math

import pytest

from wearjoint import JointParameters, ParameterError, SliderCrankParameters
from wearjoint.cosim.step_rule import communication_step_rule, effective_mass_kg


def test_the_rule_gives_the_documented_limits_for_the_papers_mechanism():
    """docs/explanation/cosim_study.md: K = 7.95e10, e_r = 0.9, F_max = 1000 N, m = 0.066 kg across the rod -> 2.1 us on
    time, 0.69 us one step late; by hand here."""
    rule = communication_step_rule(JointParameters(contact_stiffness_N_m1_5=7.95e10), max_force_N=1000.0)
    m = (8.8e-4 + 0.19 * 0.22 ** 2 / 4) / 0.22 ** 2
    assert rule.effective_mass_kg == pytest.approx(m, rel=1e-12) and m == pytest.approx(0.066, abs=5e-4)
    k = 1.5 * 7.95e10 ** (2 / 3) * 1000.0 ** (1 / 3)
    assert rule.contact_stiffness_N_m == pytest.approx(2.8e8, rel=0.02)
    assert rule.on_time_s == pytest.approx(4 * math.log(1 / 0.9) / (math.pi * math.sqrt(k / m)), rel=1e-12)
    assert rule.on_time_s == pytest.approx(2.1e-6, rel=0.03)
    assert rule.one_step_late_s == pytest.approx(0.69e-6, rel=0.03)


def test_the_step_scales_with_the_mass_stiffness_and_force():
    base = SliderCrankParameters()
    heavy = base.replace(rod_mass_kg=10 * base.rod_mass_kg, rod_inertia_kg_m2=10 * base.rod_inertia_kg_m2,
                         slider_mass_kg=10 * base.slider_mass_kg)
    assert effective_mass_kg(heavy) == pytest.approx(10 * effective_mass_kg(base), rel=1e-12)
    a = communication_step_rule(mechanism=base, max_force_N=1000.0)
    b = communication_step_rule(mechanism=heavy, max_force_N=1000.0)
    assert b.on_time_s / a.on_time_s == pytest.approx(math.sqrt(10), rel=1e-12)
    stiff = communication_step_rule(JointParameters(contact_stiffness_N_m1_5=8 * JointParameters().stiffness_N_m1_5),
                                    max_force_N=1000.0)
    assert a.on_time_s / stiff.on_time_s == pytest.approx(8 ** (1 / 3), rel=1e-12)
    # the default F_max is a Hertz impact at the crank pin's speed: above the paper's measured 1000 N
    assert communication_step_rule().max_force_N > 1000.0
    with pytest.raises(ParameterError, match="max_force_N"):
        communication_step_rule(max_force_N=-1.0)


@pytest.mark.parametrize("depth_in_clearances", [2.0, 5.7])
def test_a_conforming_grooves_stiffness_is_the_foundations_over_half_the_circle(depth_in_clearances):
    """(pi/2) k_f L R_i against the kernels: the normal force's secant slope of a pin pressed into a groove worn to
    its own circle (no velocity: the elastic force alone), within 1.5 % (the groove conforms over a little less than
    half the circle when it is shallow)."""
    from wearjoint import ClearanceJoint
    from wearjoint.cosim.step_rule import groove_stiffness_N_m
    from wearjoint.studies.coupling_accuracy import conforming_groove

    joint = JointParameters(wear_factor=0.0)
    by_hand = 0.5 * math.pi * (3 * joint.stiffness_N_m1_5 * math.sqrt(joint.clearance_m) / (
        4 * math.sqrt(2) * joint.contact_length_m * math.sqrt(joint.pin_radius_m * joint.bushing_radius_m))) \
        * joint.contact_length_m * joint.pin_radius_m
    assert groove_stiffness_N_m(joint) == pytest.approx(by_hand, rel=1e-12)
    bushing = ClearanceJoint(joint)
    depth = depth_in_clearances * joint.clearance_m
    bushing.set_wear_profile(conforming_groove(joint, depth, 0.5))
    forces = []
    for pressed in (1e-7, 2e-7):
        e = joint.clearance_m + depth + pressed
        forces.append(bushing.evaluate((e * math.cos(0.5), e * math.sin(0.5), 0, 0, 0, 0), (0, 0, 0, 0, 0, 0))
                      .normal_force_N)
    assert (forces[1] - forces[0]) / 1e-7 == pytest.approx(by_hand, rel=0.015)
    assert groove_stiffness_N_m(joint.replace(contact_model="deepest", contact_exponent=1.5)) == 0.0


def test_a_wearing_joint_whose_groove_is_stiffer_gets_a_smaller_step():
    """k_f grows as K, Hertz's contact stiffness at F_max as K^0.8 (F_max ~ K^0.4): eight times the paper's K makes
    the groove 8x stiffer and Hertz's law 8^0.8x; the paper's measured step shrinks by the groove limits' ratio,
    8^-0.5, for a joint that wears and by the unworn limits', 8^-0.4, for one that does not."""
    from wearjoint.cosim.step_rule import paper_step_scale

    paper = JointParameters()
    stiff = paper.replace(contact_stiffness_N_m1_5=8 * paper.stiffness_N_m1_5)
    rule, reference = communication_step_rule(stiff), communication_step_rule(paper)
    assert rule.groove_stiffness_N_m / reference.groove_stiffness_N_m == pytest.approx(8.0, rel=1e-12)
    assert rule.contact_stiffness_N_m / reference.contact_stiffness_N_m == pytest.approx(8 ** 0.8, rel=1e-12)
    assert rule.groove_on_time_s < rule.on_time_s and reference.groove_on_time_s < reference.on_time_s
    assert paper_step_scale(paper) == 1.0
    assert paper_step_scale(stiff) == pytest.approx(8 ** -0.5, rel=1e-12)
    assert paper_step_scale(stiff.replace(wear_factor=0.0)) == pytest.approx(8 ** -0.4, rel=1e-12)


@pytest.mark.parametrize("coupling, scale, limit, on_time, expected_steps", [
    ("linearised", 1.0, math.inf, False, 80_000),            # the paper's 5 us: 80 000 to its 0.4 s revolution
    ("linearised", 1.0, math.inf, True, 40_000),             # OMSimulator's 10 us
    ("hold", 1.0, math.inf, False, 800_000),                 # the held loads' 0.5 us
    ("linearised", 0.655, math.inf, False, 122_138),         # 3.275 us: 122 137.4 steps, so one more
    ("linearised", 1.0, 4.9e-6, False, 81_633),              # within the wear-step limit
])
def test_the_packages_step_divides_the_crank_revolution(coupling, scale, limit, on_time, expected_steps):
    """A step that did not divide the revolution (the scaled 3.2751 us) ended a one-revolution run 3.5e-6 revolutions
    late, a sliver revolution of its own in revolutions.csv: the package's step is the longest at most the scaled one
    that a whole number of steps per revolution gives."""
    from wearjoint.fmu.ssp import DEFAULT_STEP_S, ON_TIME_STEP_S, package_step_s

    period = SliderCrankParameters().period_s
    step = package_step_s(coupling, scale, limit, period, on_time=on_time)
    wanted = min((ON_TIME_STEP_S if on_time else DEFAULT_STEP_S)[coupling] * scale, limit)
    assert period / step == pytest.approx(expected_steps, abs=1e-6) and step <= wanted
    assert period / (expected_steps - 1) > wanted          # one step fewer would be longer than asked
