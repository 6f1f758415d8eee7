"""The contact damping (docs/model.md §3.5): Hunt-Crossley by default, Lankarani-Nikravesh as an option.

Hand cases of the force law, its independence of the contact memory, and free impacts integrated
through the joint's own forces against the restitution of the closed form's dimensionless impact.
"""
import math

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, ParameterError
from wearjoint.core import layout as L
from wearjoint.parameters import hysteresis_restitution

# K delta^1.5 exactly, centres at the bodies; N_d divisible by 4 puts a bushing point at 90 deg
DEEPEST = JointParameters(contact_model="deepest", wear_factor=0.0, n_points=1256)
CHI = 0.75 * (1.0 - DEEPEST.restitution ** 2)


def _pin_at(ey, vy):
    """Pin body at (0, ey) moving at (0, vy), bushing body fixed at the origin."""
    return [0.0, ey, 0.0, 0.0, vy, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("model", ["foundation", "deepest"])
@pytest.mark.parametrize("rate", [-0.03, 0.004, 0.02, 0.2])
def test_hunt_crossley_scales_the_elastic_force_by_one_plus_alpha_times_the_rate(model, rate):
    p = DEEPEST.replace(contact_model=model)
    joint = ClearanceJoint(p)
    delta = 3e-6
    elastic = joint.evaluate(*_pin_at(p.clearance_m + delta, 0.0)).normal_force_N
    r = joint.evaluate(*_pin_at(p.clearance_m + delta, rate))
    assert r.penetration_rate_m_s == pytest.approx(rate, rel=1e-12)
    assert r.normal_force_N == pytest.approx(elastic * max(0.0, 1.0 + CHI * rate / p.restitution_speed_m_s), rel=1e-12)


def test_hunt_crossley_never_pulls_and_forgets_the_onset():
    """No adhesion: zero force while the pin leaves faster than v_r / chi; and the force is the same
    whatever the contact memory holds (a stored onset at 1 mm/s or none)."""
    p = DEEPEST
    joint = ClearanceJoint(p)
    y = p.clearance_m + 3e-6
    assert joint.evaluate(*_pin_at(y, -1.01 * p.restitution_speed_m_s / CHI)).normal_force_N == 0.0
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


@pytest.mark.parametrize("damping", [0.0, 1e-3, 1e-2])
def test_restitution_of_a_weakly_damped_impact_is_hunt_and_crossleys(damping):
    """1 - e^2 = (4/3) a to first order in a = alpha v: e = 1 - (2/3) a, to O(a^2)."""
    assert hysteresis_restitution(damping) == pytest.approx(1.0 - 2.0 / 3.0 * damping, abs=2e-9 + damping ** 2)


def test_restitution_is_bounded_by_the_inverse_damping_and_falls_with_it():
    values = [hysteresis_restitution(a) for a in (0.1, 0.5, 1.0, 2.0, 5.0, 20.0)]
    assert all(b < a for a, b in zip(values, values[1:]))
    assert all(e <= 1.0 / a for e, a in zip(values[1:], (0.5, 1.0, 2.0, 5.0, 20.0)))


def _impact(p: JointParameters, speed: float, mass: float = 1.0, step: float = 5e-8) -> float:
    """A free pin body of ``mass`` [kg] fired from the bushing centre at ``speed`` [m/s] onto the wall, the
    joint's force integrated by velocity Verlet with each accepted step given to ``advance`` (onsets
    stored): its rebound speed over its impact speed."""
    joint = ClearanceJoint(p)
    y = p.clearance_m - 0.5 * speed * step          # first contact within the first step
    v = speed
    force = joint.evaluate(*_pin_at(y, v)).pin_force[1]
    while v > -speed or joint.evaluate(*_pin_at(y, v)).in_contact:
        v_half = v + 0.5 * step * force / mass
        y += step * v_half
        force = joint.evaluate(*_pin_at(y, v_half)).pin_force[1]
        v = v_half + 0.5 * step * force / mass
        force = joint.evaluate(*_pin_at(y, v)).pin_force[1]
        joint.advance(*_pin_at(y, v), step)
        if y < p.clearance_m - 1e-7:
            return -v / speed
    raise AssertionError("the pin went through the wall")


@pytest.mark.parametrize("damping, speed", [("hunt-crossley", 0.01), ("hunt-crossley", 0.05), ("hunt-crossley", 0.2),
                                            ("lankarani-nikravesh", 0.05)])
def test_a_free_impact_through_the_joint_rebounds_at_the_closed_forms_restitution(damping, speed):
    """The kernels' force integrated over one impact gives JointParameters.restitution_at(speed): the
    same restitution at v_r for both laws, more for a slower impact and less for a faster one under
    Hunt-Crossley."""
    p = DEEPEST.replace(contact_damping=damping, friction_coefficient=0.0)
    assert _impact(p, speed) == pytest.approx(p.restitution_at(speed), abs=2e-3)


def test_restitution_at_names_a_bad_speed():
    with pytest.raises(ParameterError, match="impact_speed_m_s=-1"):
        DEEPEST.restitution_at(-1.0)
    with pytest.raises(ParameterError, match="restitution_speed_m_s=0"):
        DEEPEST.replace(restitution_speed_m_s=0.0)
    with pytest.raises(ParameterError, match="contact_damping='hunt'"):
        DEEPEST.replace(contact_damping="hunt")
    assert math.isfinite(DEEPEST.restitution_at(1e-6)) and np.isclose(DEEPEST.restitution_at(1e-6), 1.0, atol=1e-5)
