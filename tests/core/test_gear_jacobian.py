"""The slider-crank's exact Jacobian d(y_dot)/dy (core.slider_crank_jacobian, used by ``--integrator gear``)
against central differences of the right-hand side (core.slider_crank.derivative), at states of the
paper's run in and out of contact, on the unworn and on a worn bushing, for both contact models.

The states are taken where the right-hand side is smooth over the difference stencil: away from the
friction ramp's ends (|v_T| = v0, v1) and, for the ``deepest`` model, from a change of the deepest
point; the foundation contact is C1 in the kinematics (docs/reference/model.md §3.10)."""
import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.core.slider_crank import derivative
from wearjoint.core.slider_crank_jacobian import make_jacobian_workspace, state_jacobian
from wearjoint.parameters import ParameterError, SliderCrankParameters, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions

N2 = 2 * L.N_COORDINATES
# central-difference steps in position [m] and angle [rad]: in contact 1e-3 of the penetration delta
# (the force's curvature scale) and 1e-2 delta for the angles (a lever of ~25 mm between angle and pin
# displacement), in free flight 1e-7 (the rigid mechanism's scale is its lengths); in velocity
# [m/s, rad/s] 1e-7 (the forces are at most quadratic in the velocities)
RELATIVE_POSITION_STEP = 1e-3
RELATIVE_ANGLE_STEP = 1e-2
FREE_POSITION_STEP = 1e-7
VELOCITY_STEP = 1e-7
FREE_GAP = 1e-6     # [m] free-flight states at least this far from the bushing (> the stencil's reach)


def rhs(sim, y):
    dy = np.empty(N2)
    derivative(sim.t, y, sim.mode, sim.mechanism.parameter_vector, sim._joint_arrays, np.zeros(6),
               sim.mechanism.workspace, dy)
    return dy


def steps(sim, contact):
    """The central differences' step per entry of y."""
    step = np.r_[np.full(L.N_COORDINATES, FREE_POSITION_STEP), np.full(L.N_COORDINATES, VELOCITY_STEP)]
    if contact:
        penetration = sim.joint.result[L.R_PENETRATION]
        step[:L.N_COORDINATES] = RELATIVE_POSITION_STEP * penetration
        step[[L.CRANK + 2, L.ROD + 2, L.SLIDER + 2]] = RELATIVE_ANGLE_STEP * penetration
    return step


def central_differences(sim, step):
    """d rhs / dy by central differences, column m with step[m]."""
    jac = np.empty((N2, N2))
    for m in range(N2):
        up, down = sim.y.copy(), sim.y.copy()
        up[m] += step[m]
        down[m] -= step[m]
        jac[:, m] = (rhs(sim, up) - rhs(sim, down)) / (2.0 * step[m])
    return jac


def exact(sim):
    jac = np.full((N2, N2), np.nan)
    state_jacobian(sim.t, sim.y, sim.mechanism.parameter_vector, sim._joint_arrays, make_jacobian_workspace(), jac)
    return jac


def smooth_here(sim) -> bool:
    """The contact's non-smooth places are far from the state, at the stencil's scale."""
    result = sim.joint.result
    rhs(sim, sim.y)
    p = sim.joint.params
    slip = abs(result[L.R_TANGENTIAL_VELOCITY])
    margin = 1e-4        # [m/s]: 1000 velocity steps, far more than a position step moves v_T
    if result[L.R_CONTACT] < 0.5:
        return -result[L.R_PENETRATION] > FREE_GAP
    return (result[L.R_PENETRATION] > 1e-7 and abs(slip - p.friction_v0_m_s) > margin
            and abs(slip - p.friction_v1_m_s) > margin)


def states(joint, profile=None, n_contact=3, n_free=2, t_first=2e-3, dt=2.7e-4):
    """(simulation, in contact) at states of a Dormand-Prince run of ``joint`` (from the bushing worn to
    ``profile`` [m], if given): the first ``n_contact`` smooth in-contact and ``n_free`` free-flight
    states every ``dt`` [s] after ``t_first``."""
    sim = Simulation(joint, options=SimulationOptions(revolutions=1))
    if profile is not None:
        sim.set_wear_profile(profile)
    samples = np.zeros((100000, L.N_SAMPLE_COLUMNS))
    found = {True: 0, False: 0}
    wanted = {True: n_contact, False: n_free}
    t = t_first
    while found[True] < n_contact or found[False] < n_free:
        sim.advance_to(t, samples)
        t += dt
        assert t < 0.4, f"only {found} states found"
        contact = sim.joint.result[L.R_CONTACT] > 0.5
        if found[contact] < wanted[contact] and smooth_here(sim):
            found[contact] += 1
            yield sim, contact
            rhs(sim, sim.y)          # the contact at the state again in the joint's result (the search hint)


def check(sim, contact):
    step = steps(sim, contact)
    approx, jac = central_differences(sim, step), exact(sim)
    assert sim.joint.result[L.R_CONTACT] == (1.0 if contact else 0.0)
    # d q / dt = q_dot
    assert np.array_equal(jac[:L.N_COORDINATES], np.eye(N2)[L.N_COORDINATES:])
    # central differences' truncation (1e-6 of the column's largest entry) and round-off (100 ulp of the
    # largest |y_dot| over the step)
    allowed = 1e-6 * np.abs(approx).max(axis=0) + 100.0 * np.finfo(float).eps * np.abs(rhs(sim, sim.y)).max() / step
    error = np.abs(jac - approx)
    assert np.all(error <= allowed), (error / allowed).max(axis=0)
    contact_columns = [L.CRANK, L.CRANK + 1, L.CRANK + 2, L.ROD, L.ROD + 1, L.ROD + 2]
    rod_rows = slice(L.N_COORDINATES + L.ROD, L.N_COORDINATES + L.ROD + 3)
    stiff = np.abs(jac[rod_rows, contact_columns]).max()
    if contact:                                      # the contact stiffness (~1e8 N/m at 1 um) over the rod mass
        assert stiff > 1e7
    else:                                            # only the rigid mechanism's
        assert stiff < 1e5


@pytest.mark.parametrize("contact_model", ["foundation", "deepest"])
def test_unworn_jacobian_matches_central_differences(contact_model):
    seen = set()
    for sim, contact in states(paper_joint(wear_factor=0.0, contact_model=contact_model)):
        check(sim, contact)
        seen.add(contact)
    assert seen == {True, False}


def worn_profile():
    """The profile [m] a run at wear factor 100 leaves after 20 ms (~54 um deep, ~110 deg wide)."""
    sim = Simulation(paper_joint(wear_factor=100.0), options=SimulationOptions(revolutions=1))
    sim.advance_to(0.02, np.zeros((10000, L.N_SAMPLE_COLUMNS)))
    return sim.joint.wear_depth.copy()


@pytest.mark.parametrize("contact_model", ["foundation", "deepest"])
def test_worn_jacobian_matches_central_differences(contact_model):
    """On a worn profile, held (wear factor 0: the bushing wears only at accepted points, never inside
    the right-hand side, so the wear rate does not enter the Jacobian)."""
    profile = worn_profile()
    assert profile.max() > 2e-5
    seen, worn_depths = set(), []
    for sim, contact in states(paper_joint(wear_factor=0.0, contact_model=contact_model), profile):
        check(sim, contact)
        seen.add(contact)
        if contact:
            worn_depths.append(profile[int(sim.joint.result[L.R_CONTACT_INDEX])])
    assert seen == {True, False}
    assert max(worn_depths) > 1e-7                   # a contact on the worn part of the bushing


def test_jacobian_leaves_the_joint_state_alone():
    sim, _ = next(states(paper_joint(wear_factor=100.0), n_contact=1, n_free=0, t_first=0.02))
    before = sim.joint.state_to_bytes()
    exact(sim)
    assert sim.joint.state_to_bytes() == before


@pytest.mark.parametrize("location", ["rod-slider", "crank-ground"])
def test_the_exact_jacobian_is_the_crank_rod_joints_and_refused_elsewhere_in_one_line(location):
    """The exact Jacobian differentiates the crank-rod joint's closed-form solve: with the clearance at another
    joint ``gear`` runs on the solver's finite differences by default (a new user's default was refused there), and
    asking for ``exact`` there is refused."""
    mechanism = SliderCrankParameters(clearance_joint=location)
    with pytest.raises(ParameterError, match=r"^parameter gear_jacobian='exact' is invalid: allowed 'numerical' "
                                             rf"with clearance_joint='{location}'"):
        Simulation(paper_joint(mechanism), mechanism, SimulationOptions(integrator="gear", gear_jacobian="exact",
                                                                        revolutions=0.01))
    for options in (SimulationOptions(integrator="gear", revolutions=0.01),
                    SimulationOptions(integrator="gear", gear_jacobian="numerical", revolutions=0.01)):
        assert Simulation(paper_joint(mechanism), mechanism, options).options.gear_jacobian == "numerical"
    crank_rod = SliderCrankParameters()
    default = Simulation(paper_joint(crank_rod), crank_rod, SimulationOptions(integrator="gear", revolutions=0.01))
    assert default.options.gear_jacobian == "exact"
