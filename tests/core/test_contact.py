"""Contact search (Eqs. 4-8) and contact forces (Eqs. 9-23) against hand cases."""
import math

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, paper_joint
from wearjoint.core.geometry import angle_near_point, find_deepest_point, find_deepest_point_full, point_nearest_angle

# N_d divisible by 4 puts bushing points exactly at 0, 90, 180 and 270 deg
P = paper_joint(n_points=1256)   # the slider-crank offsets: the torques below are by hand for them
C = P.clearance_m


def bodies_with_eccentricity(ex, ey, pin_velocity=(0.0, 0.0, 0.0), bushing_velocity=(0.0, 0.0, 0.0)):
    """Pin body at the origin (angle 0); rod placed so that pin centre - bushing centre = (ex, ey)."""
    pin_centre = np.array(P.pin_offset_m)
    bushing_body = pin_centre - np.array([ex, ey]) - np.array(P.bushing_offset_m)
    return [0.0, 0.0, 0.0, *pin_velocity], [bushing_body[0], bushing_body[1], 0.0, *bushing_velocity]


def test_no_contact_inside_the_clearance():
    joint = ClearanceJoint(P)
    r = joint.evaluate(*bodies_with_eccentricity(0.3 * C, -0.5 * C))
    assert not r.in_contact and r.normal_force_N == 0.0 and r.pin_force == (0.0, 0.0, 0.0)
    assert r.eccentricity_m == pytest.approx((0.3 * C, -0.5 * C), abs=1e-15)


def test_pin_pressed_outward_is_pushed_back_with_hertz_force_and_hand_torques():
    """The paper's deepest-point contact: K delta^1.5 exactly (the foundation's force is checked
    against its own quadrature in tests/core/test_foundation_contact.py)."""
    delta = 4e-6
    joint = ClearanceJoint(P.replace(contact_model="deepest"))
    r = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta))
    f_expected = P.stiffness_N_m1_5 * delta ** 1.5      # Eq. 15 without approach velocity
    assert r.in_contact and r.penetration_m == pytest.approx(delta, rel=1e-9)
    assert r.contact_angle_rad == pytest.approx(math.pi / 2, abs=1e-12)
    assert r.normal_force_N == pytest.approx(f_expected, rel=1e-8)
    # pushed back: towards -y, the bushing centre
    assert r.pin_force[0] == pytest.approx(0.0, abs=1e-9 * f_expected)
    assert r.pin_force[1] == pytest.approx(-f_expected, rel=1e-8)
    # equal and opposite
    assert r.bushing_force[:2] == pytest.approx((-r.pin_force[0], -r.pin_force[1]), rel=1e-15)
    # torque about the crank's centre of mass (origin): contact point on the pin (0.025, R_i)
    assert r.pin_force[2] == pytest.approx(0.025 * -f_expected, rel=1e-8)
    # torque about the rod's centre: the bushing point lies at (-0.110, R_j) from it, force (0, +F)
    assert r.bushing_force[2] == pytest.approx(-0.110 * f_expected, rel=1e-8)


@pytest.mark.parametrize("model", ["foundation", "deepest"])
def test_approach_velocity_adds_lankarani_nikravesh_hysteresis(model):
    delta, v = 4e-6, 0.03
    joint = ClearanceJoint(P.replace(contact_model=model, contact_damping="lankarani-nikravesh"))
    elastic = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta)).normal_force_N
    # pin moving outward (+y) into the wall: at onset delta_dot = delta_dot^- so the factor is 1 + 3(1-e^2)/4
    r = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta, pin_velocity=(0.0, v, 0.0)))
    assert r.penetration_rate_m_s == pytest.approx(v, rel=1e-12)
    assert r.normal_force_N == pytest.approx(elastic * (1 + 0.75 * (1 - P.restitution ** 2)), rel=1e-12)


@pytest.mark.parametrize("model", ["foundation", "deepest"])
def test_friction_opposes_sliding_and_saturates_above_v1(model):
    delta = 4e-6
    joint = ClearanceJoint(P.replace(contact_model=model))
    # pin body translating +x at 0.1 m/s: the pin surface slides +x over the bushing
    r = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta, pin_velocity=(0.1, 0.0, 0.0)))
    fn = r.normal_force_N
    assert r.pin_force[0] == pytest.approx(-P.friction_coefficient * fn, rel=1e-8)
    assert r.bushing_force[0] == pytest.approx(P.friction_coefficient * fn, rel=1e-8)
    # in the ramp (Eq. 19): c_d = (v - v0)/(v1 - v0)
    v = 0.5 * (P.friction_v0_m_s + P.friction_v1_m_s)
    r = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta, pin_velocity=(v, 0.0, 0.0)))
    assert r.pin_force[0] == pytest.approx(-0.5 * P.friction_coefficient * r.normal_force_N, rel=1e-8)
    # below v0 no friction
    r = joint.evaluate(*bodies_with_eccentricity(0.0, C + delta, pin_velocity=(0.5 * P.friction_v0_m_s, 0, 0)))
    assert r.pin_force[0] == pytest.approx(0.0, abs=1e-12 * r.normal_force_N)   # the normal follows e's round-off


def test_contact_is_invariant_under_a_rigid_rotation_of_both_bodies():
    joint = ClearanceJoint(JointParameters())
    pin, bushing = [0.01, 0.02, 0.3, 0.1, -0.2, 3.0], [0.14, 0.05, -0.2, 0.05, 0.1, -1.0]
    # put the pin centre just past the wall along the current eccentricity (the first pose has it
    # 0.13 m away, outside the bushing: the joint says so)
    with pytest.warns(RuntimeWarning, match="outside the bushing"):
        r0 = joint.evaluate(pin, bushing)
    ex, ey = r0.eccentricity_m
    scale = (JointParameters().clearance_m + 3e-6) / math.hypot(ex, ey)
    c, s = math.cos(bushing[2]), math.sin(bushing[2])
    shift = np.array([c * ex - s * ey, s * ex + c * ey]) * (scale - 1)
    pin[0] += shift[0]
    pin[1] += shift[1]
    r1 = joint.evaluate(pin, bushing)
    assert r1.in_contact
    a = 0.7
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])

    def rotate(k):
        p = rot @ k[:2]
        v = rot @ k[3:5]
        return [p[0], p[1], k[2] + a, v[0], v[1], k[5]]

    r2 = joint.evaluate(rotate(np.array(pin)), rotate(np.array(bushing)))
    assert r2.normal_force_N == pytest.approx(r1.normal_force_N, rel=1e-6)
    assert np.allclose(rot @ np.array(r1.pin_force[:2]), r2.pin_force[:2], rtol=1e-6, atol=1e-9)
    assert r2.pin_force[2] == pytest.approx(r1.pin_force[2], rel=1e-6)
    assert r2.eccentricity_m == pytest.approx(r1.eccentricity_m, rel=1e-6)


def _random_profiles(joint, rng, count):
    phi = joint.phi_rad
    for i in range(count):
        kind = i % 4
        if kind == 0:
            h = np.zeros(phi.size)
        elif kind == 1:
            h = np.abs(rng.normal(0.0, 1e-4, phi.size))
        elif kind == 2:   # two smooth lobes of random place and depth, like real wear
            h = np.zeros(phi.size)
            for _ in range(2):
                centre = rng.uniform(0, 2 * np.pi)
                h += rng.uniform(0, 4e-4) * np.exp(-(np.angle(np.exp(1j * (phi - centre))) / rng.uniform(0.1, 0.6)) ** 2)
        else:             # quantised depths produce exact distance ties
            h = np.round(np.abs(rng.normal(0.0, 5e-5, phi.size)), 5)
        yield h


def test_pruned_search_is_identical_to_the_full_scan_on_random_worn_profiles():
    joint = ClearanceJoint(JointParameters())
    rng = np.random.default_rng(1)
    checked = 0
    for h in _random_profiles(joint, rng, 400):
        joint.set_wear_profile(h)
        for _ in range(10):
            e = rng.normal(0.0, 3e-4, 2) if rng.random() < 0.9 else np.zeros(2)
            full = find_deepest_point_full(e[0], e[1], 0.0101, joint.cos_phi, joint.sin_phi, joint.wear_depth)
            # the hint (previous deepest point) changes the work, never the answer: none, out of range,
            # the answer itself, points the walk to e's direction starts from, a random point
            near = [(full[0] + o) % h.size for o in (-9, -8, -3, -1, 1, 2, 8, 9)]
            for hint in (-1, h.size, full[0], *near, int(rng.integers(h.size))):
                fast = find_deepest_point(e[0], e[1], 0.0101, joint.cos_phi, joint.sin_phi, joint.wear_depth,
                                          joint.block_min, hint)
                assert (fast[0], fast[1]) == (full[0], full[1])
            checked += 1
    assert checked == 4000


def test_full_scan_finds_the_point_nearest_the_pin_centre():
    joint = ClearanceJoint(JointParameters(n_points=64))
    rng = np.random.default_rng(2)
    h = np.abs(rng.normal(0, 1e-4, 64))
    e = np.array([5e-5, -8e-5])
    pts = (0.0101 + h)[:, None] * np.c_[joint.cos_phi, joint.sin_phi]
    k, d2 = find_deepest_point_full(e[0], e[1], 0.0101, joint.cos_phi, joint.sin_phi, h)
    assert k == int(np.argmin(np.sum((pts - e) ** 2, axis=1)))


def test_the_contact_angle_about_a_point_is_atan2s_to_rounding():
    """The angle of a vector computed about bushing point k's direction (the arctangent's series within
    |tan| <= 1/16 of it, atan2 beyond) equals atan2's in [0, 2 pi), across the 0/2 pi seam too."""
    joint = ClearanceJoint(JointParameters(n_points=360))
    n = joint.phi_rad.size
    rng = np.random.default_rng(5)
    series = 0
    for _ in range(20000):
        k = int(rng.integers(n)) if rng.random() < 0.8 else int(rng.choice([0, n - 1]))
        offset = rng.normal(0.0, 0.04) if rng.random() < 0.9 else rng.uniform(-math.pi, math.pi)
        angle = joint.phi_rad[k] + offset
        v = rng.uniform(1e-7, 1.0) * np.array([math.cos(angle), math.sin(angle)])
        expected = math.atan2(v[1], v[0]) % (2 * math.pi)
        got = angle_near_point(v[0], v[1], k, joint.cos_phi, joint.sin_phi)
        assert 0.0 <= got < 2 * math.pi
        assert abs(math.remainder(got - expected, 2 * math.pi)) <= 2e-15
        series += abs(math.tan(offset)) < 0.06
    assert series > 10000


def test_the_point_nearest_an_angle():
    joint = ClearanceJoint(JointParameters(n_points=90))
    n = joint.phi_rad.size
    for angle in np.linspace(0.0, 2 * math.pi, 1001)[:-1]:
        k = point_nearest_angle(angle, n)
        gap = np.abs(np.remainder(joint.phi_rad - angle + math.pi, 2 * math.pi) - math.pi)
        assert gap[k] <= gap.min() + 1e-12
    for outside in (-1e-9, 2 * math.pi, 7.0, math.nan, math.inf):
        assert point_nearest_angle(outside, n) == -1
