"""The contact damping laws (docs/reference/model.md §3.5): Hunt-Crossley, the paper's Lankarani-Nikravesh and its exact
form, Tsuji.

Hand cases of each force law, and free impacts integrated through the joint's own forces against
the closed-form rebound of F_e max(0, 1 + a delta_dot / v) (-a e - ln(1 - a e) = a - ln(1 + a), solved
here with scipy) and against the speed independence of Tsuji's law: `restitution` is the restitution
of a single impact at the law's speed, for masses from 0.05 to 10 kg, for either contact model.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from wearjoint import ClearanceJoint, JointParameters, ParameterError
from wearjoint.core import damping
from wearjoint.core import layout as L

# K delta^1.5 exactly, centres at the bodies; N_d divisible by 4 puts a bushing point at 90 deg
DEEPEST = JointParameters(contact_model="deepest", wear_factor=0.0, n_points=1256)
CHI = 0.75 * (1.0 - DEEPEST.restitution ** 2)


def closed_form_restitution(a: float) -> float:
    """e of -a e - ln(1 - a e) = a - ln(1 + a) (Hunt and Crossley's force with a = alpha v), by brentq."""
    if a == 0.0:
        return 1.0
    return brentq(lambda e: a * e + math.log(1.0 - a * e) + a - math.log(1.0 + a), 0.0, min(1.0, 1.0 / a) * (1 - 1e-15),
                  xtol=1e-15)


def closed_form_damping(e: float) -> float:
    """a at which that impact rebounds at e."""
    return brentq(lambda a: closed_form_restitution(a) - e, 0.0, 1.0 / e * (1 - 1e-12), xtol=1e-15)


def _pin_at(ey, vy):
    """Pin body at (0, ey) moving at (0, vy), bushing body fixed at the origin."""
    return [0.0, ey, 0.0, 0.0, vy, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("e", [0.05, 0.3, 0.6, 0.9, 0.99])
def test_hunt_crossley_damping_solves_the_closed_form_rebound(e):
    assert damping.hunt_crossley_damping(e) == pytest.approx(closed_form_damping(e), rel=1e-9)
    assert damping.hunt_crossley_restitution(closed_form_damping(e)) == pytest.approx(e, rel=1e-9)


@pytest.mark.parametrize("a", [1e-3, 1e-2])
def test_a_weakly_damped_impact_restitutes_hunt_and_crossleys_first_order(a):
    """1 - e = (2/3) a to first order in a = alpha v (Hunt and Crossley 1975)."""
    assert damping.hunt_crossley_restitution(a) == pytest.approx(1.0 - 2.0 / 3.0 * a, abs=a * a)


def test_tsuji_restitution_falls_with_gamma_and_is_one_undamped():
    values = [damping.tsuji_restitution(g, 1.5) for g in (0.0, 0.05, 0.2, 1.0, 5.0)]
    assert values[0] == pytest.approx(1.0, abs=1e-9)
    assert all(b < a for a, b in zip(values, values[1:]))
    for e in (0.1, 0.5, 0.9):
        assert damping.tsuji_restitution(damping.tsuji_damping(e, 1.5), 1.5) == pytest.approx(e, rel=1e-6)


@pytest.mark.parametrize("model", ["foundation", "deepest"])
@pytest.mark.parametrize("rate", [-0.03, 0.004, 0.02, 0.2])
def test_hunt_crossley_scales_the_elastic_force_by_one_plus_alpha_times_the_rate(model, rate):
    p = DEEPEST.replace(contact_model=model)
    alpha = closed_form_damping(p.restitution) / p.restitution_speed_m_s
    joint = ClearanceJoint(p)
    delta = 3e-6
    elastic = joint.evaluate(*_pin_at(p.clearance_m + delta, 0.0)).normal_force_N
    r = joint.evaluate(*_pin_at(p.clearance_m + delta, rate))
    assert r.penetration_rate_m_s == pytest.approx(rate, rel=1e-12)
    assert r.normal_force_N == pytest.approx(elastic * max(0.0, 1.0 + alpha * rate), rel=1e-9)


@pytest.mark.parametrize("rate", [-0.03, 0.004, 0.2])
def test_tsuji_adds_gamma_sqrt_of_mass_times_secant_stiffness_times_the_rate(rate):
    """With K delta^1.5: F_N = K delta^1.5 + gamma sqrt(m K) delta^(1/4) delta_dot (Tsuji et al. 1992)."""
    p = DEEPEST.replace(contact_damping="tsuji", effective_mass_kg=2.5)
    joint = ClearanceJoint(p)
    delta = 3e-6
    k = p.stiffness_N_m1_5
    gamma = damping.tsuji_damping(p.restitution, 1.5)
    r = joint.evaluate(*_pin_at(p.clearance_m + delta, rate))
    expected = k * delta ** 1.5 + gamma * math.sqrt(2.5 * k) * delta ** 0.25 * rate
    assert r.normal_force_N == pytest.approx(max(0.0, expected), rel=1e-6)


def test_hunt_crossley_never_pulls_and_forgets_the_onset():
    """No adhesion: zero force while the pin leaves faster than 1 / alpha; and the force is the same
    whatever the contact memory holds (a stored onset at 1 mm/s or none)."""
    p = DEEPEST
    alpha = closed_form_damping(p.restitution) / p.restitution_speed_m_s
    joint = ClearanceJoint(p)
    y = p.clearance_m + 3e-6
    assert joint.evaluate(*_pin_at(y, -1.01 / alpha)).normal_force_N == 0.0
    free = joint.evaluate(*_pin_at(y, 0.01)).normal_force_N
    joint.advance(*_pin_at(p.clearance_m + 1e-9, 1e-4), 1e-6)      # a gentle onset stored
    assert joint.memory[L.M_ACTIVE] == 1.0 and joint.memory[L.M_IMPACT_VELOCITY] == p.impact_velocity_floor_m_s
    assert joint.evaluate(*_pin_at(y, 0.01)).normal_force_N == free


def test_lankarani_nikravesh_divides_by_the_stored_onset_velocity():
    p = DEEPEST.replace(contact_damping="lankarani-nikravesh")
    joint = ClearanceJoint(p)
    y = p.clearance_m + 3e-6
    elastic = joint.evaluate(*_pin_at(y, 0.0)).normal_force_N
    # no contact stored: the approach velocity stands in for delta_dot^-
    assert joint.evaluate(*_pin_at(y, 0.02)).normal_force_N == pytest.approx(elastic * (1.0 + CHI), rel=1e-12)
    joint.advance(*_pin_at(p.clearance_m + 1e-9, 1e-4), 1e-6)       # onset at 0.1 mm/s: the 1 mm/s floor is stored
    assert joint.evaluate(*_pin_at(y, 0.02)).normal_force_N == pytest.approx(elastic * (1.0 + CHI * 20.0), rel=1e-12)


def impact_restitution(p: JointParameters, speed: float, mass: float) -> float:
    """A free pin body of ``mass`` [kg] fired from inside the clearance at ``speed`` [m/s] onto the wall, the
    joint's force integrated by velocity Verlet at 1/400 of the impact's time scale (delta*/v,
    delta* = (m v^2 / K)^0.4), each accepted step given to ``advance`` (onsets stored): its rebound speed
    over its impact speed (measured on every case below: within 2.5e-4 of the same at 1/1000)."""
    scale = (mass * speed ** 2 / p.stiffness_N_m1_5) ** 0.4 / speed
    step = scale / 400.0
    joint = ClearanceJoint(p)
    y, v = p.clearance_m - 0.5 * speed * step, speed       # first contact within the first step
    force = joint.evaluate(*_pin_at(y, v)).pin_force[1]
    for _ in range(100_000):
        v_half = v + 0.5 * step * force / mass
        y += step * v_half
        force = joint.evaluate(*_pin_at(y, v_half)).pin_force[1]
        v = v_half + 0.5 * step * force / mass
        result = joint.evaluate(*_pin_at(y, v))
        force = result.pin_force[1]
        joint.advance(*_pin_at(y, v), step)
        if v < 0.0 and not result.in_contact:
            return -v / speed
    raise AssertionError("the impact did not end")


LAWS = [("hunt-crossley", 0.9), ("hunt-crossley", 0.3), ("tsuji", 0.9), ("tsuji", 0.3),
        ("lankarani-nikravesh-exact", 0.9), ("lankarani-nikravesh-exact", 0.3)]


@pytest.mark.parametrize("model", ["deepest", "foundation"])
@pytest.mark.parametrize("law, e", LAWS)
@pytest.mark.parametrize("mass", [0.05, 1.0, 10.0])
def test_a_single_impact_rebounds_at_the_asked_restitution_at_the_laws_speed(model, law, e, mass):
    """Within 0.5 %, at v_r = 50 mm/s, any mass (Tsuji's effective mass set to the body's)."""
    p = DEEPEST.replace(contact_model=model, contact_damping=law, restitution=e, friction_coefficient=0.0,
                        effective_mass_kg=mass)
    assert impact_restitution(p, p.restitution_speed_m_s, mass) == pytest.approx(e, rel=5e-3)


@pytest.mark.parametrize("speed", [0.005, 0.2])
def test_tsuji_and_onset_laws_restitute_the_same_at_every_speed_and_hunt_crossley_does_not(speed):
    p = DEEPEST.replace(restitution=0.6, friction_coefficient=0.0, effective_mass_kg=0.5)
    for law in ("tsuji", "lankarani-nikravesh-exact"):
        assert impact_restitution(p.replace(contact_damping=law), speed, 0.5) == pytest.approx(0.6, rel=5e-3)
    hunt = impact_restitution(p, speed, 0.5)
    a = closed_form_damping(0.6) * speed / p.restitution_speed_m_s
    assert hunt == pytest.approx(closed_form_restitution(a), rel=5e-3)
    assert abs(hunt - 0.6) > 0.1
    assert p.restitution_at(speed) == pytest.approx(closed_form_restitution(a), rel=1e-9)


@pytest.mark.parametrize("e, expected", [(0.3, 0.684), (0.6, 0.756), (0.9, 0.913)])
def test_lankarani_nikravesh_rebounds_at_its_own_value_not_the_asked_one(e, expected):
    """The paper's chi = 3(1 - e^2)/4 is the small-damping approximation: whatever the speed, it rebounds at
    the closed form's e(chi) (0.684 for an asked 0.3), and restitution_at says so."""
    p = DEEPEST.replace(contact_damping="lankarani-nikravesh", restitution=e, friction_coefficient=0.0)
    own = closed_form_restitution(0.75 * (1.0 - e * e))
    assert own == pytest.approx(expected, abs=5e-4)
    assert p.restitution_at(0.05) == pytest.approx(own, rel=1e-9)
    assert impact_restitution(p, 0.05, 1.0) == pytest.approx(own, rel=5e-3)


@pytest.mark.parametrize("law, e, expected", [("tsuji", 0.3, 0.2957), ("tsuji", 0.9, 0.8983),
                                               ("hunt-crossley", 0.3, None), ("lankarani-nikravesh-exact", 0.3, None)])
def test_only_tsujis_restitution_reads_the_shape_of_the_foundations_force(law, e, expected):
    """At 1 m/s, deep into the wall (docs/reference/model.md §3.5, `contact-law`'s note): the laws that multiply the
    elastic force rebound as their closed form whatever its shape; Tsuji's, reading its secant stiffness, a little
    lower with the foundation's resultant than with K delta^1.5, which it is solved for."""
    p = JointParameters(wear_factor=0.0, contact_damping=law, restitution=e, effective_mass_kg=0.89)
    foundation = impact_restitution(p, 1.0, 0.89)
    assert impact_restitution(p.replace(contact_model="deepest"), 1.0, 0.89) == pytest.approx(p.restitution_at(1.0),
                                                                                                rel=1e-3)
    if expected is None:
        assert foundation == pytest.approx(p.restitution_at(1.0), rel=1e-3)
    else:
        assert foundation < e and foundation == pytest.approx(expected, abs=3e-4)


def test_damping_parameters_are_named_when_bad():
    with pytest.raises(ParameterError, match="impact_speed_m_s=-1"):
        DEEPEST.restitution_at(-1.0)
    with pytest.raises(ParameterError, match="restitution_speed_m_s=0"):
        DEEPEST.replace(restitution_speed_m_s=0.0)
    with pytest.raises(ParameterError, match="effective_mass_kg=-2"):
        DEEPEST.replace(effective_mass_kg=-2.0)
    with pytest.raises(ParameterError, match="contact_damping='hunt'"):
        DEEPEST.replace(contact_damping="hunt")
    assert math.isfinite(DEEPEST.restitution_at(1e-6)) and np.isclose(DEEPEST.restitution_at(1e-6), 1.0, atol=1e-5)


def test_the_law_names_and_the_kernels_codes_agree():
    """Each law's name packs to the code its kernel branch reads (the FMU's Integer takes the same)."""
    from wearjoint.joint import pack_joint_parameters

    for name, code in (("hunt-crossley", L.DAMPING_HUNT_CROSSLEY),
                       ("lankarani-nikravesh", L.DAMPING_LANKARANI_NIKRAVESH), ("tsuji", L.DAMPING_TSUJI),
                       ("lankarani-nikravesh-exact", L.DAMPING_LANKARANI_NIKRAVESH_EXACT)):
        assert pack_joint_parameters(JointParameters(contact_damping=name))[L.P_CONTACT_DAMPING] == code


def test_the_joints_default_effective_mass_is_the_paper_slider_cranks():
    """JointParameters' default m_eff (the joint alone, the FMU) is what the paper's slider-crank sets: rod + slider."""
    from wearjoint import SliderCrankParameters, paper_joint

    mechanism = SliderCrankParameters()
    assert JointParameters().effective_mass_kg == mechanism.rod_mass_kg + mechanism.slider_mass_kg
    assert paper_joint(mechanism).effective_mass_kg == JointParameters().effective_mass_kg
    heavy = mechanism.replace(slider_mass_kg=30.0)
    assert paper_joint(heavy).effective_mass_kg == pytest.approx(30.19)
    assert paper_joint(heavy, effective_mass_kg=2.0).effective_mass_kg == 2.0
