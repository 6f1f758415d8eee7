"""The contact on the fitted bushing profile (docs/model.md §3.10, issue 25): continuous in the pin's
position, exact for the unworn circle, and what it changes for a body resting in the joint and for
exudyn's implicit solver.  ``contact_point="deepest"`` (the paper's deepest bushing point) is the
comparison each test shows failing."""
import math

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters

ROUND_OFF_M = 2e-17                # ~10 ulp of the bushing radius


def pin_at(e, angle):
    """Pin body kinematics putting the pin centre at eccentricity e [m], bushing-frame angle [rad]
    (bushing body at the origin, at rest; offsets zero)."""
    return [e * math.cos(angle), e * math.sin(angle), 0.0, 0.0, 0.0, 0.0]


BUSHING = [0.0] * 6


@pytest.mark.parametrize("n_points", [8, 13, 1257, 5028])
def test_unworn_penetration_is_the_closed_form_at_any_pin_position(n_points):
    """delta = |e| - c (the pin in a circle) and the normal along e, wherever the pin sits between points."""
    p = JointParameters(n_points=n_points)
    joint = ClearanceJoint(p)
    rng = np.random.default_rng(n_points)
    for _ in range(300):
        angle = rng.uniform(0.0, 2.0 * math.pi)
        e = p.clearance_m + rng.uniform(-2e-6, 8e-6)
        r = joint.evaluate(pin_at(e, angle), BUSHING)
        ex, ey = r.eccentricity_m
        assert r.penetration_m == pytest.approx(math.hypot(ex, ey) - p.clearance_m, abs=ROUND_OFF_M)
        if r.normal_force_N > 0.0:          # no velocity, no friction: the force is -F_N along e
            assert abs(math.remainder(math.atan2(-r.pin_force[1], -r.pin_force[0]) - angle, 2 * math.pi)) < 1e-13
            assert abs(math.remainder(r.contact_angle_rad - angle, 2 * math.pi)) < 1e-13


def test_the_deepest_point_option_keeps_the_distance_to_the_nearest_point():
    """contact_point='deepest': |d| to the bushing point, sqrt(R^2 + e^2 - 2 R e cos(offset)) (Eq. 6)."""
    p = JointParameters(contact_point="deepest")
    joint = ClearanceJoint(p)
    dphi = 2.0 * math.pi / p.n_points
    e = p.clearance_m + 3e-6
    for offset in (0.1, 0.25, 0.45):                     # of the spacing, from point z = 100
        r = joint.evaluate(pin_at(e, (100 + offset) * dphi), BUSHING)
        d = math.sqrt(p.bushing_radius_m ** 2 + e * e - 2 * p.bushing_radius_m * e * math.cos(offset * dphi))
        assert r.penetration_m == pytest.approx(p.pin_radius_m - d, rel=1e-9)
        assert r.penetration_m < e - p.clearance_m - 1e-12         # short of the circle's |e| - c


def _direction_sweep(params, profile, first, last, count):
    """The pin swept over bushing-frame angles first..last [rad] at a fixed |e| [m] that keeps it in contact:
    (angles, |e|, force directions on the pin, contact angles), the last two unwrapped [rad]."""
    joint = ClearanceJoint(params)
    joint.set_wear_profile(profile)
    e = params.clearance_m + profile.max() + 2e-6
    angles = np.linspace(first, last, count)
    direction, contact = [], []
    for a in angles:
        r = joint.evaluate(pin_at(e, a), BUSHING)
        assert r.normal_force_N > 0.0
        direction.append(math.atan2(-r.pin_force[1], -r.pin_force[0]))
        contact.append(r.contact_angle_rad)
    return angles, e, np.unwrap(direction), np.unwrap(contact)


def test_force_direction_is_continuous_across_a_bushing_point():
    """A pin swept over bushing points and the gaps between them (where the deepest point changes) on a
    smoothly worn profile h (a lobe, closed form).  The contact point moves at most e/(e - max h'') times
    the pin's angular step (twice that allowed; the nearest point of a surface that curves less than the
    pin's path), and between samples the force turns by at most the contact point's step times
    (1 + 2 max |beta'|), beta = atan(h'/(R_j + h)) the worn surface's tilt: the profile's own slope
    change.  The deepest-point option jumps by the point spacing."""
    p = JointParameters()
    dphi = 2.0 * math.pi / p.n_points
    phi = ClearanceJoint(p).phi_rad
    centre, width, depth = 100.3 * dphi, 0.6, 5e-6
    profile = depth * np.exp(-((phi - centre) / width) ** 2)
    x = np.linspace(centre - 4 * width, centre + 4 * width, 20001)
    h = depth * np.exp(-((x - centre) / width) ** 2)
    h1 = -2 * (x - centre) / width ** 2 * h
    h2 = (4 * (x - centre) ** 2 / width ** 4 - 2 / width ** 2) * h
    rho = p.bushing_radius_m + h
    tilt_rate = np.abs((h2 * rho - h1 * h1) / (rho * rho + h1 * h1)).max()
    first, last = 92.4 * dphi, 108.6 * dphi        # the contact point crosses several points and gaps
    angles, e, direction, contact = _direction_sweep(p, profile, first, last, 8001)
    step = angles[1] - angles[0]
    contact_step = np.abs(np.diff(contact))
    assert contact_step.max() <= 2.0 * step * e / (e - h2.max())
    assert np.all(np.abs(np.diff(direction)) <= contact_step * (1.0 + 2.0 * tilt_rate) + 1e-13)
    assert np.ptp(contact) > 10 * dphi                                   # it did cross points
    _, _, deepest, deepest_contact = _direction_sweep(p.replace(contact_point="deepest"), profile, first, last, 8001)
    assert np.abs(np.diff(deepest)).max() > 0.5 * dphi
    assert np.abs(np.diff(deepest_contact)).max() > 0.99 * dphi


def test_heavy_wear_keeps_the_default_adaptive_step_below_the_wear_limit():
    """Half a crank revolution at wear factor 2000: with a 0.1 ms step each accepted step cuts a
    groove deeper than the penetration and the fitted contact ran away (437 kN, 8 mm of wear;
    docs/performance.md).  The default adaptive step with wear is 1e-5 s (docs/model.md §7): the
    contact force stays that of the mechanism's load (the deepest-point contact and RK4 at 10 us
    give 40 N), and an explicit larger step is refused naming it."""
    from wearjoint import paper_joint
    from wearjoint.parameters import ParameterError
    from wearjoint.simulate import MAX_WEAR_STEP_S, SimulationOptions, run_simulation

    joint = paper_joint(wear_factor=2000.0, wear_coefficient_m2_N=5.614e-11)
    record = run_simulation(joint, options=SimulationOptions(revolutions=0.5), progress=False)
    summary = record.summary()
    assert summary["parameters"]["simulation"]["max_step_s"] == MAX_WEAR_STEP_S
    assert summary["max_contact_force_N"] < 100.0
    assert 1e-4 < summary["max_wear_depth_m"] < 3e-4
    with pytest.raises(ParameterError, match=r"max_step_s=0\.0001 is invalid with wear"):
        run_simulation(joint, options=SimulationOptions(revolutions=0.5, max_step_s=1e-4), progress=False)


exudyn_pendulum = pytest.importorskip("wearjoint.validation.exudyn_pendulum")


@pytest.mark.parametrize("contact_point", ["fitted", "deepest"])
def test_a_body_loaded_against_the_bushing_comes_to_rest_without_rocking_or_wear(contact_point):
    """The bar hanging in the joint, released touching at its equilibrium angle (the contact at the bushing
    top, a quarter spacing from a point for N_d = 1257), wear on with the rotation sliding distance: it
    settles on the Hertz penetration (m g / K)^(2/3), does not turn and wears nothing.  The deepest point's
    tilted normal makes it rock and wear."""
    p = exudyn_pendulum.pendulum_joint(contact_point=contact_point)
    r = exudyn_pendulum.run_pendulum(p, 0.0, 0.02)
    assert r["completed"]
    weight = exudyn_pendulum.BAR_MASS_KG * exudyn_pendulum.GRAVITY_M_S2
    hertz = (weight / p.contact_stiffness_N_m1_5) ** (1.0 / p.contact_exponent)
    rocks = r["late_max_abs_omega_rad_s"] > 1e-9 or r["max_wear_depth_m"] > 1e-20
    assert rocks == (contact_point == "deepest")
    if contact_point == "fitted":
        assert r["final_penetration_m"] == pytest.approx(hertz, rel=1e-4)
        assert r["final_speed_m_s"] < 1e-8


@pytest.mark.parametrize("contact_point", ["fitted", "deepest"])
def test_exudyn_generalized_alpha_completes_a_swinging_pendulum(contact_point):
    """Released at 6 deg, 0.5 s at exudyn's default Newton tolerances and a 10 us step: with the fitted
    contact every step converges at the nominal step or its half; on the deepest point's jumps Newton
    fails repeatedly and the step is halved again and again."""
    p = exudyn_pendulum.pendulum_joint(contact_point=contact_point, wear_factor=0.0)
    r = exudyn_pendulum.run_pendulum(p, 6.0, 0.5, step_s=1e-5)
    smooth = r["completed"] and r["min_step_s"] >= 0.5e-5 * (1.0 - 1e-6)
    assert smooth == (contact_point == "fitted")
