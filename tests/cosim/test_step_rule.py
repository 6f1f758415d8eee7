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
