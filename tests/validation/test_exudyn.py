"""The exudyn slider-crank (validation/exudyn_model.py) against closed forms, the
monolithic engine and the contact physics; exudyn's own contact (contact="native") against
our kernels' deepest-point law."""
import math
import subprocess
import sys

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, JointState, ParameterError, SliderCrankParameters, paper_joint
from wearjoint.core import layout as L
from wearjoint.core.contact import ambrosio_friction_factor
from wearjoint.core.slider_crank import derivative
from wearjoint.slider_crank import SliderCrank
from wearjoint.simulate import SimulationOptions, run_simulation

em = pytest.importorskip("wearjoint.validation.exudyn_model")
from wearjoint.exudyn import set_post_step  # noqa: E402
from wearjoint.validation.exudyn_native import native_contact_parameters, native_law  # noqa: E402

NO_WEAR = paper_joint(wear_factor=0.0)
# exudyn's own contact (ObjectContactSphereSphere in a hollow sphere) is the paper's K delta^n along the line
# of centres with a stored impact velocity floored at v_r: the discrete form it is compared with is
# contact_model="deepest" with Lankarani-Nikravesh damping floored there (exudyn_native.native_law)
DEEPEST = NO_WEAR.replace(**native_law(NO_WEAR))
V_REG = native_contact_parameters(NO_WEAR)["frictionProportionalZone"]   # exudyn's friction zone [m/s]


def _angle_distance(a, b):
    """Smallest absolute difference of angles a and b [rad]."""
    return np.abs((np.asarray(a) - b + math.pi) % (2.0 * math.pi) - math.pi)


def test_importing_wearjoint_does_not_import_exudyn():
    code = ("import sys, wearjoint, wearjoint.simulate, wearjoint.validation; "
            "sys.exit(1 if 'exudyn' in sys.modules else 0)")
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0


# ---------------------------------------------------------------- ideal mechanism
def test_ideal_slider_follows_the_closed_form():
    rec = em.run_exudyn(None, None, 1.0, step_s=5e-5, ideal=True, progress=False)
    s = rec.samples
    exact = SliderCrank().closed_form(s[:, L.T_TIME])
    assert rec.parameters.engine == "exudyn"
    assert rec.simulated_time_s == pytest.approx(SliderCrankParameters().period_s, rel=1e-9)
    assert s[-1, L.T_TIME] == pytest.approx(rec.simulated_time_s)
    np.testing.assert_allclose(s[:, L.T_CRANK_ANGLE], exact["crank_angle_rad"], atol=1e-9)   # driver sign
    np.testing.assert_allclose(s[:, L.T_SLIDER_X], exact["slider_x_m"], atol=2e-6)
    np.testing.assert_allclose(s[:, L.T_SLIDER_V], exact["slider_v_m_s"], atol=1e-4)
    np.testing.assert_allclose(s[:, L.T_SLIDER_A], exact["slider_a_m_s2"], atol=0.02)
    dense = SliderCrank().closed_form(np.linspace(0.0, rec.period_s, 200001))["slider_a_m_s2"]
    peak = np.abs(s[:, L.T_SLIDER_A]).max()
    assert peak == pytest.approx(np.abs(dense).max(), rel=2e-3)
    assert 15.0 < peak < 15.2                                            # docs/reference/model.md §7: ideal peak 15.1 m/s^2
    assert rec.summary()["max_contact_force_N"] == 0.0


# ---------------------------------------------------------------- contact geometry
def _random_kinematics(rng, joint_params, penetration_m):
    """Crank and rod kinematics (6 each) with the pin centre at |e| = c + penetration
    from the bushing centre in a random direction; random velocities."""
    p = joint_params
    th_i, th_j = rng.uniform(-math.pi, math.pi, 2)
    pos_i = np.array([*rng.uniform(-0.05, 0.05, 2), th_i])
    ci, si = math.cos(th_i), math.sin(th_i)
    pin = pos_i[:2] + [ci * p.pin_offset_m[0] - si * p.pin_offset_m[1], si * p.pin_offset_m[0] + ci * p.pin_offset_m[1]]
    direction = rng.uniform(0.0, 2.0 * math.pi)
    bushing = pin - (p.clearance_m + penetration_m) * np.array([math.cos(direction), math.sin(direction)])
    cj, sj = math.cos(th_j), math.sin(th_j)
    pos_j = np.array([*(bushing - [cj * p.bushing_offset_m[0] - sj * p.bushing_offset_m[1],
                                  sj * p.bushing_offset_m[0] + cj * p.bushing_offset_m[1]]), th_j])
    vel_i = np.array([*rng.uniform(-1.0, 1.0, 2), rng.uniform(-20.0, 20.0)])
    vel_j = np.array([*rng.uniform(-1.0, 1.0, 2), rng.uniform(-5.0, 5.0)])
    return np.r_[pos_i, vel_i], np.r_[pos_j, vel_j]


def _friction_law_difference(p: JointParameters, v_t, d_velocity):
    """Largest |c_d(v) - min(1, v/v_reg)| over |v - |v_t|| <= d_velocity: Ambrosio's ramp (ours) against
    exudyn's proportional zone (its documented law, ObjectContactSphereSphere)."""
    v = np.linspace(max(0.0, abs(v_t) - d_velocity), abs(v_t) + d_velocity, 201)
    ours = np.array([ambrosio_friction_factor(x, p.friction_v0_m_s, p.friction_v1_m_s) for x in v])
    return float(np.abs(ours - np.minimum(1.0, v / V_REG)).max())


def _discretisation_bounds(p: JointParameters, r, pin_kin, bushing_kin, impact_velocity):
    """First-order bounds of |F_discrete - F_native| [N] and of the torque differences
    [N m] for an unworn bushing of N_d points on the true circle.

    The point nearest the pin centre lies at most dphi = pi/N_d off the direction of e.
    Its depth deficit is |e|(1 - cos dphi) R_j/(R_j - |e|) (<= R_j(1 - cos dphi) ~ 3e-8 m,
    the sagitta of the chord), the normal turns by at most beta = dphi R_j/(R_j - |e|),
    and the bushing contact point moves along the circle by R_j dphi.  exudyn applies both
    forces, and takes both velocities, at the middle of the overlap (delta/2 from ours), and
    regularises friction by its proportional zone instead of Ambrosio's ramp, and does not clip F_N at 0.
    """
    dphi = math.pi / p.n_points
    e = math.hypot(r[L.R_ECCENTRICITY_X], r[L.R_ECCENTRICITY_Y])
    rj, ri = p.bushing_radius_m, p.pin_radius_m
    beta = dphi * rj / (rj - e)
    d_depth = e * (1.0 - math.cos(dphi)) * rj / (rj - e)
    w_i, w_j = abs(pin_kin[5]), abs(bushing_kin[5])
    rel_speed = math.hypot(r[L.R_PENETRATION_RATE], r[L.R_TANGENTIAL_VELOCITY])
    half_overlap = 0.5 * max(r[L.R_PENETRATION], 0.0) + d_depth
    d_velocity = rel_speed * beta + w_i * ri * beta + w_j * rj * dphi + (w_i + w_j) * half_overlap   # rate, v_t
    k, n, a = p.stiffness_N_m1_5, p.contact_exponent, 0.75 * (1.0 - p.restitution ** 2)
    delta = r[L.R_PENETRATION] + d_depth
    hysteresis = 1.0 + a * (abs(r[L.R_PENETRATION_RATE]) + d_velocity) / impact_velocity
    d_normal = n * k * delta ** (n - 1.0) * d_depth * hysteresis + k * delta ** n * a * d_velocity / impact_velocity
    # exudyn does not clip Eq. (15) at 0: separating faster than delta_dot^-/a, its damping pulls
    d_normal += k * delta ** n * max(0.0, a * (-r[L.R_PENETRATION_RATE] + d_velocity) / impact_velocity - 1.0)
    f_n = r[L.R_NORMAL_FORCE] + d_normal
    mu = p.friction_coefficient
    v_t = abs(r[L.R_TANGENTIAL_VELOCITY])
    d_ramp = _friction_law_difference(p, v_t, d_velocity)   # change of mu's factor c_d (Eq. 19) and the law
    if v_t - d_velocity < p.friction_v1_m_s and v_t + d_velocity > p.friction_v0_m_s:
        d_ramp += d_velocity / (p.friction_v1_m_s - p.friction_v0_m_s)
    if v_t <= d_velocity:                                   # friction direction undecided
        d_ramp = 2.0
    d_force = (1.0 + mu) * (d_normal + f_n * beta) + mu * f_n * d_ramp
    f = (1.0 + mu) * f_n
    arm_i = math.hypot(*p.pin_offset_m) + ri
    arm_j = math.hypot(*p.bushing_offset_m) + rj
    return (2.0 * d_force, 2.0 * (arm_i * d_force + f * ri * beta + f * half_overlap),
            2.0 * (arm_j * d_force + f * rj * dphi + f * half_overlap))


def _active_contact_joint(p, impact_velocity):
    joint = ClearanceJoint(p)
    memory = np.zeros(L.N_MEMORY)
    memory[L.M_ACTIVE] = 1.0
    memory[L.M_IMPACT_VELOCITY] = impact_velocity
    joint.set_state(JointState(np.zeros(p.n_points), memory))
    return joint


def test_discrete_and_native_contact_agree_to_the_discretisation_error():
    """Our deepest-point kernel and exudyn's own contact (its C++ code) on random unworn cases."""
    p = DEEPEST
    impact_velocity = 0.5       # 1 + chi delta_dot / delta_dot^- > 0 over the random rates (|rate| < 2.4 m/s): exudyn does not clip
    joint = _active_contact_joint(p, impact_velocity)
    rng = np.random.default_rng(7)
    relative_bounds = []
    for _ in range(300):
        pin_kin, bushing_kin = _random_kinematics(rng, p, rng.uniform(0.2e-6, 8e-6))
        discrete = em.contact_forces(joint, pin_kin, bushing_kin, "discrete")
        classical = em.contact_forces(joint, pin_kin, bushing_kin, "native")
        assert discrete[L.R_CONTACT] == classical[L.R_CONTACT] == 1.0
        tol_force, tol_torque_i, tol_torque_j = _discretisation_bounds(p, discrete, pin_kin, bushing_kin,
                                                                       impact_velocity)
        elastic = p.stiffness_N_m1_5 * discrete[L.R_PENETRATION] ** p.contact_exponent
        relative_bounds.append(tol_force / elastic)
        d_force = np.hypot(discrete[L.R_PIN_FX] - classical[L.R_PIN_FX], discrete[L.R_PIN_FY] - classical[L.R_PIN_FY])
        assert d_force <= tol_force
        assert abs(discrete[L.R_PIN_TORQUE] - classical[L.R_PIN_TORQUE]) <= tol_torque_i
        assert abs(discrete[L.R_BUSHING_TORQUE] - classical[L.R_BUSHING_TORQUE]) <= tol_torque_j
        np.testing.assert_allclose(discrete[[L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y]],
                                   classical[[L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y]], rtol=0, atol=1e-15)
        assert abs(discrete[L.R_PENETRATION] - classical[L.R_PENETRATION]) <= 1e-9
    assert np.median(relative_bounds) < 0.02                               # the bound is not vacuous


def test_contact_forms_coincide_when_e_points_at_a_bushing_point():
    """With e along a discrete point's direction the two geometries are the same; sliding fast, both
    frictions are mu F_N; exudyn's point of application (and of the velocities) is delta/2 inside ours."""
    p = DEEPEST
    joint = _active_contact_joint(p, 0.2)
    phi = 2.0 * math.pi * 200 / p.n_points            # bushing point z = 200 (rod at angle 0)
    e = p.clearance_m + 3e-6
    pos_j = np.array([0.3, 0.1, 0.0])
    bushing = pos_j[:2] + p.bushing_offset_m
    pin = bushing + e * np.array([math.cos(phi), math.sin(phi)])
    pin_kin = np.r_[pin - p.pin_offset_m, 0.0, 0.3, -0.2, -15.0]
    bushing_kin = np.r_[pos_j, 0.1, 0.4, 2.0]
    discrete = em.contact_forces(joint, pin_kin, bushing_kin, "discrete")
    classical = em.contact_forces(joint, pin_kin, bushing_kin, "native")
    assert discrete[L.R_CONTACT_INDEX] == 199
    assert abs(discrete[L.R_TANGENTIAL_VELOCITY]) > 10.0 * V_REG                # saturated friction in both laws
    half = 0.5 * discrete[L.R_PENETRATION]
    d_velocity = (abs(pin_kin[5]) + abs(bushing_kin[5])) * half                # exudyn's point, delta/2 inside
    for slot in (L.R_PENETRATION_RATE, L.R_TANGENTIAL_VELOCITY):
        assert classical[slot] == pytest.approx(discrete[slot], abs=1e-12 + d_velocity)
    hysteresis = 0.75 * (1.0 - p.restitution ** 2) / 0.2                         # dF_N / d(delta_dot) / (K delta^n)
    d_normal = p.stiffness_N_m1_5 * discrete[L.R_PENETRATION] ** 1.5 * hysteresis * d_velocity
    forces = [L.R_PIN_FX, L.R_PIN_FY, L.R_BUSHING_FX, L.R_BUSHING_FY, L.R_NORMAL_FORCE, L.R_FRICTION_FORCE]
    np.testing.assert_allclose(classical[forces], discrete[forces], rtol=1e-9, atol=1.2 * d_normal)
    np.testing.assert_allclose(classical[[L.R_PENETRATION, L.R_CONTACT, L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y]],
                               discrete[[L.R_PENETRATION, L.R_CONTACT, L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y]],
                               rtol=1e-9, atol=1e-15)
    for slot, offset, radius in ((L.R_PIN_TORQUE, p.pin_offset_m, p.pin_radius_m),
                                 (L.R_BUSHING_TORQUE, p.bushing_offset_m, p.bushing_radius_m)):
        arm = math.hypot(*offset) + radius
        lever = half * abs(discrete[L.R_FRICTION_FORCE]) + arm * 1.2 * d_normal   # m x N
        assert classical[slot] == pytest.approx(discrete[slot], rel=1e-9, abs=lever)


@pytest.mark.parametrize("contact", em.CONTACT_FORMULATIONS)
def test_contact_pushes_the_pin_back_with_an_equal_and_opposite_pair(contact):
    p = DEEPEST
    rng = np.random.default_rng(11)
    joint = ClearanceJoint(p)
    pushed = 0
    for _ in range(100):
        pin_kin, bushing_kin = _random_kinematics(rng, p, rng.uniform(0.1e-6, 5e-6))
        r = em.contact_forces(joint, pin_kin, bushing_kin, contact)
        assert r[L.R_CONTACT] == 1.0
        f_pin = np.array([r[L.R_PIN_FX], r[L.R_PIN_FY]])
        f_bushing = np.array([r[L.R_BUSHING_FX], r[L.R_BUSHING_FY]])
        if r[L.R_NORMAL_FORCE] <= 0.0:          # separating fast: Eq. (15) clipped at 0, no friction either;
            assert r[L.R_PENETRATION_RATE] < 0.0  # exudyn's Hunt-Crossley is not clipped: it pulls
            assert contact == "native" or not np.any(r[:L.R_FRICTION_FORCE + 1])
            continue
        pushed += 1
        c, s = math.cos(bushing_kin[2]), math.sin(bushing_kin[2])
        e_global = np.array([c * r[L.R_ECCENTRICITY_X] - s * r[L.R_ECCENTRICITY_Y],
                             s * r[L.R_ECCENTRICITY_X] + c * r[L.R_ECCENTRICITY_Y]])
        # normal force towards the bushing centre, friction at most mu of it
        assert f_pin @ e_global / np.linalg.norm(e_global) < -0.99 * r[L.R_NORMAL_FORCE] < 0.0
        assert np.linalg.norm(f_pin) <= math.hypot(1.0, p.friction_coefficient) * r[L.R_NORMAL_FORCE] * (1 + 1e-12)
        np.testing.assert_array_equal(f_bushing, -f_pin)
        # the pair's net moment about the origin is the friction couple over the normal gap between
        # the two contact points: penetration * friction force (exudyn: both at one point, none)
        moment = (r[L.R_PIN_TORQUE] + pin_kin[0] * f_pin[1] - pin_kin[1] * f_pin[0]
                  + r[L.R_BUSHING_TORQUE] + bushing_kin[0] * f_bushing[1] - bushing_kin[1] * f_bushing[0])
        couple = r[L.R_PENETRATION] * r[L.R_FRICTION_FORCE] if contact == "discrete" else 0.0
        assert moment == pytest.approx(couple, abs=1e-12 * np.linalg.norm(f_pin))
        # a pin inside the clearance feels nothing
        centred = em.contact_forces(joint, pin_kin, bushing_kin + np.r_[e_global * 0.5, 0.0, 0.0, 0.0, 0.0], contact)
        assert centred[L.R_CONTACT] == 0.0 and not np.any(centred[:L.R_PENETRATION])
    assert pushed > 30


def test_contact_forces_rejects_bad_input():
    joint = ClearanceJoint(NO_WEAR)
    with pytest.raises(ParameterError, match="contact"):
        em.contact_forces(joint, np.zeros(6), np.zeros(6), "hertz")
    with pytest.raises(ParameterError, match="pin_kinematics"):
        em.contact_forces(joint, [0.0, math.nan, 0, 0, 0, 0], np.zeros(6))
    with pytest.raises(ParameterError, match="bushing_kinematics"):
        em.contact_forces(joint, np.zeros(6), np.zeros(5))


# ---------------------------------------------------------------- exudyn GenericODE2 sign
def test_generic_ode2_applies_the_contact_pair_with_the_right_sign():
    """Rod and slider shifted +X by c + 2 um (theta1 = 0): the pin presses into the bushing
    at 180 deg.  After one exudyn step (1 us: long enough for the index-3 accelerations to be
    well conditioned) the accelerations must be the monolithic model's (Schur-complement
    dynamics of Eq. 44) under the joint's forces at that state: rod and slider pushed to -X."""
    mechanism = SliderCrank()
    y0 = mechanism.initial_state()
    shift = NO_WEAR.clearance_m + 2e-6
    y0[L.ROD] += shift
    y0[L.SLIDER] += shift
    model = em.ExudynSliderCrank(NO_WEAR, initial_state=y0)
    model.simulate(1e-6, 1e-6)
    y = model.y
    n = L.N_COORDINATES
    joint = ClearanceJoint(NO_WEAR)
    contact = joint.evaluate(np.r_[y[L.CRANK:L.CRANK + 3], y[n + L.CRANK:n + L.CRANK + 3]],
                             np.r_[y[L.ROD:L.ROD + 3], y[n + L.ROD:n + L.ROD + 3]])
    assert contact.in_contact and contact.normal_force_N > 100.0
    arrays = joint.arrays

    def monolithic_accelerations(body_forces):       # MODE_EXTERNAL: loads as given, joint unused
        dy = np.empty_like(y)
        derivative(model.t, y, L.MODE_EXTERNAL, mechanism.parameter_vector, arrays, np.asarray(body_forces),
                   mechanism.workspace, dy)
        return dy[n:]

    expected = monolithic_accelerations(np.r_[contact.pin_force, contact.bushing_force])
    flipped = monolithic_accelerations(-np.r_[contact.pin_force, contact.bushing_force])
    got = model.dy[n:]
    assert got[L.ROD] < -100.0 and got[L.SLIDER] < -100.0
    assert expected[L.ROD] * flipped[L.ROD] < 0.0                       # the test can tell the signs apart
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-5 * np.abs(expected).max())


# ---------------------------------------------------------------- clearance run vs monolithic
@pytest.fixture(scope="module")
def monolithic_15ms():
    """contact -> the monolithic RK4 run of the law it implements over the first 15 ms."""
    revolutions = 0.015 / SliderCrankParameters().period_s
    return {contact: run_simulation(joint, None, SimulationOptions(revolutions=revolutions, integrator="rk4",
                                                                   step_s=1e-6, sample_dt_s=1e-5), progress=False)
            for contact, joint in (("discrete", NO_WEAR), ("native", DEEPEST))}


def _largest_eccentricity_difference(rec, ref):
    a, b = rec.samples, ref.samples
    inside = (b[:, L.T_TIME] >= a[0, L.T_TIME]) & (b[:, L.T_TIME] <= a[-1, L.T_TIME])
    t = b[inside, L.T_TIME]
    return max(np.abs(np.interp(t, a[:, L.T_TIME], a[:, col]) - b[inside, col]).max()
               for col in (L.T_ECC_X, L.T_ECC_Y))


@pytest.mark.parametrize("contact", em.CONTACT_FORMULATIONS)
def test_clearance_run_matches_the_monolithic_engine_through_the_first_impacts(monolithic_15ms, contact):
    """Before the motion turns chaotic (~20 ms, docs/reference/model.md §7) two correct simulators agree.

    The discrete normal jumps by 0.29 deg whenever the deepest bushing point changes and
    every contact onset is non-smooth, so fixed-step methods converge only to first order
    here (measured: RK4 1 us vs 0.1 us differ by 1e-7 m at 15 ms; generalized-alpha at
    10/2/1 us by 2.4/0.7/0.3 um).  Hence: at 1 us the eccentricities agree within 1 % of the
    clearance, and a 4x larger step at least doubles the difference (convergence, not luck).
    exudyn's own contact (K delta^n, measured 0.56 um from our deepest law at 1 us, 1.8 um at 4 us)
    is compared with the monolithic run of that law.
    """
    ref = monolithic_15ms[contact]
    revolutions = ref.simulated_time_s / ref.period_s
    joint = NO_WEAR if contact == "discrete" else DEEPEST
    fine = em.run_exudyn(joint, None, revolutions, step_s=1e-6, contact=contact, progress=False)
    coarse = em.run_exudyn(joint, None, revolutions, step_s=4e-6, contact=contact, progress=False)
    c = NO_WEAR.clearance_m
    s = fine.samples
    eccentricity = np.hypot(s[:, L.T_ECC_X], s[:, L.T_ECC_Y])
    assert c < eccentricity.max() <= c + 10e-6                          # impacts, a few um deep
    assert 1e-7 < s[:, L.T_PENETRATION].max() <= 10e-6
    assert 50.0 < s[:, L.T_NORMAL_FORCE].max() < 1500.0                  # hundreds of N
    assert np.all(s[:, L.T_CONTACT][eccentricity < c] == 0.0)
    fine_error = _largest_eccentricity_difference(fine, ref)
    coarse_error = _largest_eccentricity_difference(coarse, ref)
    assert fine_error <= 0.01 * c
    assert fine_error <= 0.5 * coarse_error

    def onsets(samples):
        contact = samples[:, L.T_CONTACT] > 0.5
        return samples[1:, L.T_TIME][contact[1:] & ~contact[:-1]]

    mine, theirs = onsets(s), onsets(ref.samples)
    assert len(mine) >= 3 and len(mine) == len(theirs)
    np.testing.assert_allclose(mine, theirs, atol=3e-5)


# ---------------------------------------------------------------- wear, post-step bookkeeping
def test_wear_lands_at_the_contact_angles_once_per_accepted_step():
    joint = paper_joint(wear_factor=10.0)
    model = em.ExudynSliderCrank(joint)
    post_times, pre_calls = [], [0]

    def counting_post_step(mbs, t):
        post_times.append(t)
        return model.post_step(mbs, t)

    def counting_pre_step(mbs, t):
        pre_calls[0] += 1
        return True

    set_post_step(model.mbs, counting_post_step)      # after the joint's own bookkeeping
    model.mbs.SetPreStepUserFunction(counting_pre_step)
    end, step = 0.008, 1e-5
    model.simulate(end, step, sample_dt_s=step)
    times = np.array(post_times[1:])                                   # [0] is exudyn's call at t = 0
    assert post_times[0] == 0.0
    assert np.all(np.diff(times) > 0.0) and times[-1] == pytest.approx(end)
    assert model.accepted_steps == len(times) >= round(end / step)
    assert pre_calls[0] >= model.accepted_steps
    assert model.revolution_stats[:, L.S_TIME].sum() == pytest.approx(end, rel=1e-12)
    assert abs(model.y[L.SLIDER + 1]) < 1e-12 and abs(model.y[L.SLIDER + 2]) < 1e-12   # prismatic, no rotation

    s = model.samples
    in_contact = s[:, L.T_CONTACT] > 0.5
    assert in_contact.any()
    contact_angles = np.arctan2(s[in_contact, L.T_ECC_Y], s[in_contact, L.T_ECC_X])
    h = model.joint.wear_depth
    phi = model.joint.phi_rad
    assert h.max() > 1e-9
    nearest = np.array([_angle_distance(contact_angles, a).min() for a in phi])
    assert nearest[np.argmax(h)] < math.radians(1.0)
    assert np.all(h[nearest > math.radians(15.0)] == 0.0)               # Hertz patch ~ +-10 deg


def test_run_exudyn_validates_its_arguments():
    with pytest.raises(ParameterError, match="contact"):
        em.run_exudyn(NO_WEAR, None, 0.01, contact="hertz", progress=False)
    with pytest.raises(ParameterError, match="revolutions"):
        em.run_exudyn(NO_WEAR, None, -1.0, progress=False)
    with pytest.raises(ParameterError, match="step_s"):
        em.run_exudyn(NO_WEAR, None, 0.01, step_s=0.0, progress=False)
    with pytest.raises(ParameterError, match="ideal"):
        em.run_exudyn(NO_WEAR, None, 0.01, ideal="yes", progress=False)
    with pytest.raises(ParameterError, match="native"):
        em.run_exudyn(paper_joint(), None, 0.01, contact="native", progress=False)
    with pytest.raises(ParameterError, match="pin_offset_m"):
        em.run_exudyn(JointParameters(wear_factor=0.0, pin_offset_m=(0.03, 0.0)), None, 0.01, progress=False)
