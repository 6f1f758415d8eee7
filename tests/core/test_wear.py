"""Hertz patch (Eqs. 29-32), the elastic-foundation placement and the Archard update (Eqs. 28, 33)."""
import math
import re

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, ParameterError
from wearjoint.parameters import MAX_WEAR_STEP_S
from wearjoint.core.wear import equivalent_radius, hertz_half_width

C = JointParameters().clearance_m
STEP_S = MAX_WEAR_STEP_S   # a step of the whole wear interval: the foundation applies its wear at once (§3.11)


def contact_state(params, delta=4e-6, pin_omega=-15.7, rod_omega=3.6, pin_v=(0.0, 0.0)):
    """Pin pressed along +x of the bushing (rod angle 0) by delta, bodies spinning."""
    pin_centre = np.array(params.pin_offset_m)
    bushing = pin_centre - np.array([params.clearance_m + delta, 0.0]) - np.array(params.bushing_offset_m)
    return [0.0, 0.0, 0.0, pin_v[0], pin_v[1], pin_omega], [bushing[0], bushing[1], 0.0, 0.0, 0.0, rod_omega]


def test_hertz_half_width_by_hand():
    p = JointParameters()
    rho = equivalent_radius(p.pin_radius_m, p.bushing_radius_m, 0)
    assert rho == pytest.approx(0.01 * 0.0101 / 0.0001)
    assert equivalent_radius(p.pin_radius_m, p.bushing_radius_m, 1) == pytest.approx(0.01 * 0.0101 / 0.0201)
    b = hertz_half_width(500.0, rho, p.contact_length_m, p.effective_modulus_Pa)
    assert b == pytest.approx(math.sqrt(4 * 500.0 * rho / (math.pi * 0.006 * p.effective_modulus_Pa)))


@pytest.mark.parametrize("rho_mode", ["conformal", "paper"])
def test_archard_volume_over_one_step_in_patch_mode(rho_mode):
    params = JointParameters(rho_mode=rho_mode, wear_placement="patch")
    joint = ClearanceJoint(params)
    pin, bushing = contact_state(params)
    dt = 1e-5
    before = joint.worn_volume_m3
    r = joint.advance(pin, bushing, dt)
    assert r.in_contact
    slide = params.bushing_radius_m * abs(pin[5] - bushing[5]) * dt        # Eq. 33, rotation mode
    expected = params.wear_coefficient_m2_N * r.normal_force_N * slide     # Eq. 24: V = k_w F_N s
    assert joint.worn_volume_m3 - before == pytest.approx(expected, rel=1e-5)


def test_patch_width_follows_hertz_and_wear_is_centred_on_the_contact():
    params = JointParameters(wear_placement="patch")
    joint = ClearanceJoint(params)
    pin, bushing = contact_state(params)
    r = joint.advance(pin, bushing, 1e-5)
    worn = np.nonzero(joint.wear_depth > 0)[0]
    b = hertz_half_width(r.normal_force_N, equivalent_radius(0.01, 0.0101, 0), 0.006, params.effective_modulus_Pa)
    arc = (params.bushing_radius_m * 2 * math.pi / params.n_points)
    assert abs(worn.size * arc - 2 * b) <= 3 * arc
    # contact at 0 deg of the bushing: the depth-weighted mean direction of the wear is 0 deg
    phi = joint.phi_rad
    centre = math.degrees(math.atan2(np.sum(joint.wear_depth * np.sin(phi)), np.sum(joint.wear_depth * np.cos(phi))))
    assert abs(centre) < 0.3
    # depth at the centre = k_w p_max ds with the peak of the semi-elliptical Hertz line-contact
    # pressure, p_max = 2 F_N / (pi b L) = (4/pi) times the mean pressure of Eqs. 25, 29
    p_max = 2 * r.normal_force_N / (math.pi * b * params.contact_length_m)
    ds = params.bushing_radius_m * abs(pin[5] - bushing[5]) * 1e-5
    assert joint.max_wear_depth_m == pytest.approx(params.wear_coefficient_m2_N * p_max * ds, rel=5e-3)
    # and the profile follows the ellipse: at half the patch width the depth is sqrt(3)/2 of the peak
    half = np.abs(np.degrees(np.angle(np.exp(1j * phi))) - 0.5 * math.degrees(b / params.bushing_radius_m)).argmin()
    assert joint.wear_depth[half] / joint.max_wear_depth_m == pytest.approx(math.sqrt(3) / 2, abs=0.03)


@pytest.mark.parametrize("n_points", [628, 1257, 5028])
def test_foundation_keeps_archards_volume_and_follows_the_overlap(n_points):
    """Default placement: pressure proportional to the local overlap R_i - |d| of each point's arc
    cell (the pin circle crosses the circular bushing at cos phi = c/(c + delta)); the volume is
    k_w F_N ds whatever N_d."""
    params = JointParameters(n_points=n_points, wear_interval_s=1e-5)     # a short step's wear, applied at once
    assert params.wear_placement == "foundation"
    joint = ClearanceJoint(params)
    pin, bushing = contact_state(params, delta=3e-6)
    dt = 1e-5
    r = joint.advance(pin, bushing, dt)
    slide = params.bushing_radius_m * abs(pin[5] - bushing[5]) * dt
    assert joint.worn_volume_m3 == pytest.approx(params.wear_coefficient_m2_N * r.normal_force_N * slide, rel=1e-5)
    phi = np.angle(np.exp(1j * joint.phi_rad))
    e = params.clearance_m + 3e-6
    edge = math.acos(params.clearance_m / e)              # the pin circle crosses the bushing (to O(e/R))
    worn = np.abs(phi[joint.wear_depth > 0])
    assert worn.max() <= edge + 2 * math.pi / n_points
    # inside the arc the depth follows the overlap R_i - |R_j u - e| (linear foundation)
    inner = np.abs(phi) < 0.8 * edge
    r_j = params.bushing_radius_m
    overlap = params.pin_radius_m - np.sqrt(r_j ** 2 + e ** 2 - 2 * r_j * e * np.cos(phi[inner]))
    ratio = joint.wear_depth[inner] / overlap
    assert np.ptp(ratio) < 0.005 * ratio.mean()


def test_foundation_increment_does_not_depend_on_the_point_spacing():
    """The same contact worn at N_d = 628 and 5028: the same depth at the same angle."""
    depths = []
    for n in (628, 5028):
        params = JointParameters(n_points=n)
        joint = ClearanceJoint(params)
        joint.advance(*contact_state(params, delta=3e-6), STEP_S)
        phi = np.angle(np.exp(1j * joint.phi_rad))
        order = np.argsort(phi)
        depths.append(np.interp(np.radians([-10.0, -5.0, 0.0, 3.0, 8.0]), phi[order], joint.wear_depth[order]))
    assert depths[0].max() > 0.0
    np.testing.assert_allclose(depths[0], depths[1], rtol=2e-3)


def test_tangential_sliding_distance_uses_the_contact_velocity():
    params = JointParameters(sliding_distance="tangential")
    joint = ClearanceJoint(params)
    pin, bushing = contact_state(params, pin_omega=0.0, rod_omega=0.0, pin_v=(0.0, 0.2))
    r = joint.advance(pin, bushing, STEP_S)
    expected = params.wear_coefficient_m2_N * r.normal_force_N * abs(r.tangential_velocity_m_s) * STEP_S
    assert abs(r.tangential_velocity_m_s) == pytest.approx(0.2, rel=1e-9)
    assert joint.worn_volume_m3 == pytest.approx(expected, rel=1e-5)


def test_penetration_mode_gives_every_penetrating_point_the_full_increment():
    params = JointParameters(wear_placement="penetration")
    joint = ClearanceJoint(params)
    pin, bushing = contact_state(params)
    r = joint.evaluate(pin, bushing)
    # penetrating points, computed here independently from the geometry
    e = np.array(r.eccentricity_m)
    pts = params.bushing_radius_m * np.c_[joint.cos_phi, joint.sin_phi]
    inside = np.linalg.norm(pts - e, axis=1) <= params.pin_radius_m
    joint.advance(pin, bushing, 1e-5)
    assert np.array_equal(joint.wear_depth > 0, inside)
    assert np.ptp(joint.wear_depth[inside]) < 1e-12 * joint.max_wear_depth_m + 1e-30


def test_no_wear_without_contact_or_with_zero_factor():
    params = JointParameters(wear_factor=0.0)
    joint = ClearanceJoint(params)
    joint.advance(*contact_state(params), STEP_S)
    assert joint.max_wear_depth_m == 0.0
    joint = ClearanceJoint(JointParameters())
    pin, bushing = contact_state(JointParameters(), delta=-5e-5)
    assert not joint.advance(pin, bushing, STEP_S).in_contact
    assert joint.max_wear_depth_m == 0.0


def test_wear_factor_scales_the_increment():
    base = ClearanceJoint(JointParameters())
    fast = ClearanceJoint(JointParameters(wear_factor=10.0))
    for j in (base, fast):
        j.advance(*contact_state(j.params), STEP_S)
    assert fast.worn_volume_m3 == pytest.approx(10 * base.worn_volume_m3, rel=1e-9) and base.worn_volume_m3 > 0.0


@pytest.mark.parametrize("placement", ["foundation", "patch", "penetration"])
def test_a_step_whose_wear_exceeds_the_bushing_radius_is_refused(placement):
    """Archard's increment over h = 1e300 s in contact (~1e297 m) is no wear a bushing can take:
    advance refuses it naming dt, and nothing changes (profile, onset memory); 30 us then wears."""
    joint = ClearanceJoint(JointParameters(wear_placement=placement))
    pin, bushing = [0.0, 0.0, 0.0, 0.0, 0.0, -15.7], [-0.00011, 0.0, 0.0, 0.0, 0.0, 0.0]
    before = joint.state_to_bytes()
    for dt in (1e300, 1e200):
        with pytest.raises(ParameterError, match=re.escape(f"dt={dt!r} is invalid here: the step would wear the bushing")):
            joint.advance(pin, bushing, dt)
        assert joint.state_to_bytes() == before
    joint.advance(pin, bushing, STEP_S)
    assert 0.0 < joint.max_wear_depth_m < 1e-6
