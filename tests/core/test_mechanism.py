"""Slider-crank (Eqs. 38-44): constraint derivatives, the ideal closed form, the 1 um clearance limit."""
import numpy as np
import pytest

from wearjoint import SliderCrankParameters
from wearjoint.core import layout as L
from wearjoint.core.slider_crank import (
    N_CONSTRAINTS, OPEN_ROWS, accelerations, constraints, open_joint_accelerations_rotated,
)
from wearjoint.slider_crank import SliderCrank
from wearjoint.parameters import JointParameters, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions, run_simulation


def _constraint_values(mech, t, q, qd):
    n = L.N_COORDINATES
    jac, phi, phi_dot, gamma = np.zeros((n, n)), np.zeros(n), np.zeros(n), np.zeros(n)
    constraints(t, q, qd, mech.parameter_vector, jac, phi, phi_dot, gamma)
    return jac, phi, phi_dot, gamma


def test_jacobian_and_gamma_match_finite_differences():
    mech = SliderCrank()
    rng = np.random.default_rng(0)
    q, qd = rng.normal(0, 0.3, 9), rng.normal(0, 2.0, 9)
    t = 0.013
    jac, phi, phi_dot, gamma = _constraint_values(mech, t, q, qd)
    eps = 1e-7
    for c in range(9):
        dq = np.zeros(9)
        dq[c] = eps
        fd = (_constraint_values(mech, t, q + dq, qd)[1] - _constraint_values(mech, t, q - dq, qd)[1]) / (2 * eps)
        assert np.allclose(jac[:, c], fd, atol=1e-7)
    # Phi_dot = C q_dot + Phi_t, and gamma = -(d/dt C) q_dot (Eq. 41): differentiate Phi_dot along the motion
    phi_t = (_constraint_values(mech, t + eps, q, qd)[1] - _constraint_values(mech, t - eps, q, qd)[1]) / (2 * eps)
    assert np.allclose(phi_dot, jac @ qd + phi_t, atol=1e-9)
    h = 1e-6
    jac_next = _constraint_values(mech, t, q + h * qd, qd)[0]
    jac_prev = _constraint_values(mech, t, q - h * qd, qd)[0]
    assert np.allclose(-(jac_next - jac_prev) / (2 * h) @ qd, gamma, rtol=1e-5, atol=1e-6)


def test_closed_form_open_joint_solve_matches_the_general_schur_solve():
    """The hot path's hand-reduced solve of Eq. (44) (crank and slider rows decoupled, 2x2
    Schur for the rod-slider revolute) against the general Schur complement with the
    seven rows of the open crank-rod joint, at random states (off the constraint
    manifold, so the Baumgarte terms count) and random contact loads."""
    mech = SliderCrank()
    rng = np.random.default_rng(3)
    for _ in range(200):
        y = mech.initial_state() + rng.normal(size=18) * np.r_[np.full(9, 1e-3), np.full(9, 1.0)]
        loads = rng.normal(0.0, 500.0, 6)
        t = rng.uniform(0.0, 1.0)
        general, reduced = np.empty(9), np.full(18, np.nan)
        accelerations(t, y[:9], y[9:], mech.parameter_vector, False, loads, mech.workspace, general)
        open_joint_accelerations_rotated(t, y, mech.parameter_vector, loads, np.cos(y[L.CRANK + 2]),
                                         np.sin(y[L.CRANK + 2]), np.cos(y[L.ROD + 2]), np.sin(y[L.ROD + 2]), reduced)
        np.testing.assert_allclose(reduced[9:], general, rtol=1e-9, atol=1e-9 * np.abs(general).max())


def test_initial_state_satisfies_the_ideal_constraints():
    for angle in (0.0, 37.0, 180.0, 291.0):
        mech = SliderCrank(SliderCrankParameters(initial_crank_angle_deg=angle))
        y = mech.initial_state()
        jac, phi, phi_dot, _ = _constraint_values(mech, 0.0, y[:9], y[9:])
        assert np.abs(phi[:N_CONSTRAINTS]).max() < 1e-15
        assert np.abs(phi_dot[:N_CONSTRAINTS]).max() < 1e-12
        assert y[9 + 2] == pytest.approx(-mech.params.omega_rad_s)


def test_ideal_mechanism_matches_the_closed_form():
    rec = run_simulation(options=SimulationOptions(revolutions=1, integrator="rk4", step_s=1e-5, ideal=True),
                         progress=False)
    s = rec.samples
    closed = SliderCrank().closed_form(s[:, L.T_TIME])
    assert np.abs(closed["slider_x_m"] - s[:, L.T_SLIDER_X]).max() < 1e-9
    assert np.abs(closed["slider_v_m_s"] - s[:, L.T_SLIDER_V]).max() < 1e-8
    assert np.abs(closed["slider_a_m_s2"] - s[:, L.T_SLIDER_A]).max() < 1e-6
    # the paper's ideal peak: l1 w^2 (1 + l1/l2) = 15.1 m/s^2 at 150 rpm
    assert np.abs(s[:, L.T_SLIDER_A]).max() == pytest.approx(15.14, abs=0.01)
    # the joint's force is the ideal revolute's reaction (tests/cli/test_own_mechanism.py checks it by Newton-Euler)
    reaction = np.hypot(s[:, L.T_PIN_FX], s[:, L.T_PIN_FY])
    summary = rec.summary()
    assert reaction.min() > 0.0 and summary["max_contact_force_N"] == pytest.approx(reaction.max(), rel=1e-3)
    # an ideal joint has no contact: its run had said 0.99999 in contact, 1 impact, the deepest wear at 0.29 deg
    assert all(summary[name] is None for name in ("contact_fraction", "impacts_per_revolution", "max_wear_angle_deg",
                                                  "regime", "clearance_m", "contact_stiffness_N_m1_5"))
    assert summary["max_wear_depth_m"] == 0.0 and summary["worn_volume_m3"] == 0.0


@pytest.mark.parametrize("location", L.CLEARANCE_JOINTS)
def test_the_open_joints_solve_keeps_the_other_joints_and_balances_the_loads(location):
    """The general solve with the clearance joint at ``location`` open, at random states off the constraint
    manifold and random loads on the joint's bodies: the kept rows' accelerations are Baumgarte's,
    C q_dd = gamma - 2 alpha Phi_dot - beta^2 Phi (Eq. 44), and M q_dd - Q_applied lies in the kept rows'
    span (the constraint forces are C^T lambda: nothing else acts)."""
    mech = SliderCrank(SliderCrankParameters(clearance_joint=location, slider_force_N=300.0))
    mp = mech.parameter_vector
    kept = OPEN_ROWS[L.CLEARANCE_JOINTS.index(location)]
    rng = np.random.default_rng(5)
    for _ in range(50):
        y = mech.initial_state() + rng.normal(size=18) * np.r_[np.full(9, 1e-3), np.full(9, 1.0)]
        loads = rng.normal(0.0, 500.0, 6)
        t = rng.uniform(0.0, 1.0)
        qdd = np.empty(9)
        accelerations(t, y[:9], y[9:], mp, False, loads, mech.workspace, qdd)
        jac, phi, phi_dot, gamma = _constraint_values(mech, t, y[:9], y[9:])
        alpha, beta = mp[L.MP_ALPHA], mp[L.MP_BETA]
        np.testing.assert_allclose((jac @ qdd)[kept], (gamma - 2 * alpha * phi_dot - beta ** 2 * phi)[kept],
                                   atol=1e-8 * np.abs(qdd).max())
        p = mech.params
        masses = (p.crank_mass_kg, p.rod_mass_kg, p.slider_mass_kg)
        inertias = (p.crank_inertia_kg_m2, p.rod_inertia_kg_m2, p.slider_inertia_kg_m2)
        mass = np.array([value for m, i in zip(masses, inertias) for value in (m, m, i)])
        applied = np.zeros(9)                                     # gravity -9.81 y, the slider's load -x
        applied[[1, 4, 7]] = -9.81 * np.array(masses)
        applied[6] -= 300.0
        pin, bushing = {"crank-rod": (0, 3), "rod-slider": (6, 3), "crank-ground": (0, None)}[location]
        applied[pin:pin + 3] += loads[:3]
        if bushing is not None:
            applied[bushing:bushing + 3] += loads[3:]
        constraint_force = mass * qdd - applied
        multipliers = np.linalg.lstsq(jac[kept].T, constraint_force, rcond=None)[0]
        np.testing.assert_allclose(jac[kept].T @ multipliers, constraint_force,
                                   atol=1e-9 * np.abs(constraint_force).max())


@pytest.mark.parametrize("location", L.CLEARANCE_JOINTS)
def test_one_micrometre_clearance_follows_the_ideal_kinematics(location):
    """At the crank-ground joint without friction: with it the driven journal rolls round its 1 um bushing (dry
    backward whirl, docs/reference/model.md §1), pressed at 6-8 kN instead of the ideal pivot's 47 N."""
    mechanism = SliderCrankParameters(clearance_joint=location)
    friction = 0.0 if location == "crank-ground" else JointParameters().friction_coefficient
    joint = paper_joint(mechanism, bushing_radius_m=0.010001, wear_factor=0.0, friction_coefficient=friction)
    sim = Simulation(joint, mechanism, options=SimulationOptions(revolutions=1))
    mech = sim.mechanism
    buf = np.zeros((50000, L.N_SAMPLE_COLUMNS))
    worst_x = worst_rod = 0.0
    for k in range(1, 41):
        t = k * mech.params.period_s / 40
        n = sim.advance_to(t, buf)
        closed = mech.closed_form(buf[:n, L.T_TIME])
        worst_x = max(worst_x, np.abs(closed["slider_x_m"] - buf[:n, L.T_SLIDER_X]).max())
        worst_rod = max(worst_rod, abs(mech.closed_form(t)["rod_angle_rad"] - sim.y[L.ROD + 2]))
    assert worst_x < 3e-6            # clearance 1 um plus contact deflection
    assert worst_rod < 3e-6 / 0.22   # the same over the rod length, in rad
