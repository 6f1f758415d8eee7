"""``wearjoint.exudyn.add_clearance_joint``: the wearing joint in any exudyn mechanism
(docs/reference/exudyn.md §8).

References independent of the helper: ``ClearanceJoint.evaluate`` on the same kinematics (the
forces exudyn is given, bit for bit), the statics of a bar hung through the joint (its weight
carried by the normal force), and joints that see different loads keeping different profiles.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D,
)

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.exudyn import (  # noqa: E402
    HISTORY_COLUMNS, add_clearance_joint, check_step, contact_stiffness_bound, set_post_step, simulation_settings,
)
from wearjoint.parameters import ParameterError  # noqa: E402

BAR_LENGTH, BAR_MASS = 0.2, 0.5                  # [m], [kg]
BAR_INERTIA = BAR_MASS * BAR_LENGTH ** 2 / 12.0  # about its centre [kg m^2]
GRAVITY = 9.81


def new_system():
    system_container = exu.SystemContainer()
    return system_container, system_container.AddSystem()


def rigid_body(mbs, position, velocity=(0.0, 0.0, 0.0), mass=BAR_MASS, inertia=BAR_INERTIA, gravity=True):
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=list(position), initialVelocities=list(velocity)))
    body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=mass, inertia=inertia))
    if gravity:
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                         loadVector=[0.0, -GRAVITY, 0.0]))
    return body


def hung_bar(mbs, pivot=(0.0, 0.0), angle=0.0, mass=BAR_MASS, sag=0.0, **joint):
    """A bar of BAR_LENGTH and ``mass`` whose upper end's bushing hangs on a ground pin at ``pivot``,
    the bar at ``angle`` from the vertical, the bushing centre ``sag`` [m] below the pin's (0:
    centred); returns (bar, handle)."""
    s, c = math.sin(angle), math.cos(angle)
    centre = (pivot[0] + (0.5 * BAR_LENGTH + sag) * s, pivot[1] - (0.5 * BAR_LENGTH + sag) * c, angle)
    bar = rigid_body(mbs, centre, mass=mass, inertia=mass * BAR_LENGTH ** 2 / 12.0)
    ground = mbs.AddObject(ObjectGround(referencePosition=[pivot[0], pivot[1], 0.0]))
    params = JointParameters(bushing_offset_m=(0.0, 0.5 * BAR_LENGTH), **joint)
    return bar, add_clearance_joint(mbs, ground, bar, params)


def solve(mbs, end_time, step, explicit=False):
    settings = simulation_settings(end_time, step)
    if explicit:
        exu.SolveDynamic(mbs, settings, solverType=exu.DynamicSolverType.RK44)
    else:
        exu.SolveDynamic(mbs, settings)


# ------------------------------------------------------------------ the forces exudyn is given
def test_the_forces_exudyn_applies_are_the_joints_bit_for_bit():
    """The GenericODE2 force user function at arbitrary coordinates equals ClearanceJoint.evaluate
    on the kinematics they mean: (Fx, Fy, T) on the pin body's node, then on the bushing body's."""
    _, mbs = new_system()
    params = JointParameters(pin_offset_m=(0.03, 0.01), bushing_offset_m=(-0.05, 0.002))
    pin_ref, bushing_ref = np.array([0.1, 0.2, 0.3]), np.array([0.18, 0.19, 0.25])
    pin = rigid_body(mbs, pin_ref, gravity=False)
    bushing = rigid_body(mbs, bushing_ref, gravity=False)
    # place the bushing centre on the pin centre at the start
    handle = add_clearance_joint(mbs, pin, bushing, params.replace(
        bushing_offset_m=_offset_placing_bushing_on_pin(pin_ref, bushing_ref, params)))
    force_function = handle.generalized_force          # the GenericODE2's force user function
    rng = np.random.default_rng(7)
    reference = ClearanceJoint(handle.joint.params)
    contacts = 0
    for _ in range(200):
        q = rng.normal(0.0, 4e-5, 6)
        q[2] = rng.normal(0.0, 5e-4)
        q[5] = q[2] + rng.normal(0.0, 2e-4)     # the centres stay within ~0.1 mm: contact and gap
        q_t = rng.normal(0.0, 0.5, 6)
        applied = np.array(force_function(mbs, 0.0, handle.object_number, q, q_t))
        expected = reference.evaluate(np.r_[pin_ref + q[:3], q_t[:3]], np.r_[bushing_ref + q[3:], q_t[3:]])
        assert np.array_equal(applied, np.r_[expected.pin_force, expected.bushing_force])
        contacts += expected.in_contact
    assert 20 < contacts < 180          # both sides of the contact were exercised


def central_jacobian(forces, x, v, a, b, step_x=1e-9, step_v=1e-7):
    """-(a dF/dx + b dF/dv) of ``forces(x, v)`` by central differences, each divided by the step the
    floats actually took ((x + h) - (x - h), not 2h: at |x| ~ 0.1 m the rounding of x +- h would
    otherwise be a 1e-7 error).  Truncation (h/delta)^2 and round-off eps delta/h leave ~1e-8 of
    the largest entry at h = 1 nm for penetrations delta of microns."""
    n = x.size
    jacobian = np.zeros((n, n))
    for k in range(n):
        for which, step, factor in ((0, step_x, a), (1, step_v, b)):
            plus, minus = [x.copy(), v.copy()], [x.copy(), v.copy()]
            plus[which][k] += step
            minus[which][k] -= step
            jacobian[:, k] -= factor * (forces(*plus) - forces(*minus)) / (plus[which][k] - minus[which][k])
    return jacobian


A, B = 3e-11, 6e-6                 # exudyn's factors a, b at a 10 us generalized-alpha step
EXACT = 1e-6                       # the Jacobian is exact: 100x the differences' own error (above)


def test_the_jacobian_exudyn_is_given_is_the_derivative_of_those_forces():
    """The GenericODE2 Jacobian user function returns exudyn's left-hand-side Jacobian,
    -(a dF/dq + b dF/dq_t), of the forces F = ClearanceJoint.evaluate: against central differences
    of ClearanceJoint.evaluate, in contact (the pin 20 um into the bushing, sliding) and in the gap
    (zero), for a body hung from ground; it leaves the joint's state as it was."""
    _, mbs = new_system()
    bar, handle = hung_bar(mbs)
    reference = ClearanceJoint(handle.joint.params)
    centre = np.array([0.0, -0.5 * BAR_LENGTH, 0.0])

    def forces(x, v):
        return np.array(reference.evaluate(np.zeros(6), np.r_[x, v]).bushing_force)
    state = handle.joint.state_to_bytes()
    for depth, in_contact in ((1.2e-4, True), (0.5e-4, False)):
        q, q_t = np.array([2e-5, -depth, 1e-3]), np.array([0.05, -0.02, 0.3])
        jacobian = np.array(handle.generalized_jacobian(mbs, 0.0, handle.object_number, q, q_t, A, B))
        expected = central_jacobian(forces, centre + q, q_t, A, B)
        if in_contact:
            assert np.abs(expected).max() > 0.0
            np.testing.assert_allclose(jacobian, expected, rtol=0.0, atol=EXACT * np.abs(expected).max())
        else:
            assert not np.any(jacobian) and not np.any(expected)
    assert handle.joint.state_to_bytes() == state


@pytest.mark.parametrize("worn", [False, True], ids=["unworn", "two-arc-groove"])
def test_the_jacobian_between_two_bodies_is_the_derivative_of_the_forces_on_both(worn):
    """Both sides rigid bodies, turned (so the chain runs through both angles) and moving (the pin
    approaching at 0.19 m/s, sliding at 0.036 m/s): the 6 x 6 Jacobian equals central differences
    of ClearanceJoint.evaluate's forces on both bodies, on the unworn bushing and on one with a 30 um
    groove under the pin, which then touches the bushing in two separate arcs."""
    _, mbs = new_system()
    params = JointParameters(pin_offset_m=(0.03, 0.01), bushing_offset_m=(-0.05, 0.002))
    pin_ref, bushing_ref = np.array([0.1, 0.2, 0.3]), np.array([0.18, 0.19, 0.25])
    pin, bushing = rigid_body(mbs, pin_ref, gravity=False), rigid_body(mbs, bushing_ref, gravity=False)
    handle = add_clearance_joint(mbs, pin, bushing, params.replace(
        bushing_offset_m=_offset_placing_bushing_on_pin(pin_ref, bushing_ref, params)))
    reference = ClearanceJoint(handle.joint.params)
    p, phi = reference.params, np.radians(reference.phi_deg)
    toward = math.radians(250.0)                  # the pin pressed 5 um into the bushing at 250 deg
    if worn:
        off = np.angle(np.exp(1j * (phi - toward)))
        groove = np.where(np.abs(off) < math.radians(4.0), 30e-6 * np.cos(off * 90.0 / 4.0) ** 2, 0.0)
        handle.joint.set_wear_profile(groove)
        reference.set_wear_profile(groove)
    e = (p.clearance_m + 5e-6) * np.array([math.cos(toward), math.sin(toward)])     # bushing frame
    c, s = math.cos(bushing_ref[2]), math.sin(bushing_ref[2])
    q = np.array([0.0, 0.0, 0.0, -(c * e[0] - s * e[1]), -(s * e[0] + c * e[1]), 0.0])
    q_t = np.array([0.01, -0.02, 0.5, 0.005, 0.01, -3.0])
    rho = p.bushing_radius_m + reference.wear_depth
    overlapping = p.pin_radius_m > np.hypot(rho * np.cos(phi) - e[0], rho * np.sin(phi) - e[1])
    assert np.count_nonzero(overlapping & ~np.roll(overlapping, 1)) == (2 if worn else 1)   # arcs in contact

    def forces(x, v):
        r = reference.evaluate(np.r_[x[:3], v[:3]], np.r_[x[3:], v[3:]])
        return np.r_[r.pin_force, r.bushing_force]
    jacobian = np.array(handle.generalized_jacobian(mbs, 0.0, handle.object_number, q, q_t, A, B))
    expected = central_jacobian(forces, np.r_[pin_ref, bushing_ref] + q, q_t, A, B)
    assert reference.evaluate(np.r_[pin_ref, q_t[:3]], np.r_[bushing_ref + q[3:], q_t[3:]]).normal_force_N > 100.0
    np.testing.assert_allclose(jacobian, expected, rtol=0.0, atol=EXACT * np.abs(expected).max())


@pytest.mark.parametrize("model", ["foundation", "deepest"])
def test_the_stiffness_bound_holds_on_worn_conforming_bushings(model):
    """contact_stiffness_bound (Newton's round-off floor, simulation_settings) bounds the force's
    derivative in the pin's position, central differences of ClearanceJoint.evaluate, with the pin
    pressed 1 um into the unworn bushing and into bushings worn to fit it over an arc (the pin's own
    circle cut 50-200 um into the bushing), where the foundation is several times stiffer than
    unworn and approaches the bound."""
    p = JointParameters(contact_model=model)
    bound = contact_stiffness_bound(p)
    phi = np.radians(ClearanceJoint(p).phi_deg)
    stiffness = []
    for cut in (0.0, 50e-6, 100e-6, 200e-6):
        joint = ClearanceJoint(p)
        centre = p.clearance_m + cut                                  # the pin centre, straight down
        reach = -centre * np.sin(phi) + np.sqrt(p.pin_radius_m ** 2 - (centre * np.cos(phi)) ** 2)
        joint.set_wear_profile(np.maximum(reach - p.bushing_radius_m, 0.0))
        e = centre + 1e-6

        def forces(x, v):
            return np.array(joint.evaluate(np.r_[x, 0.0, v, 0.0], np.zeros(6)).pin_force[:2])
        derivative = central_jacobian(forces, np.array([0.0, -e]), np.zeros(2), 1.0, 0.0)
        stiffness.append(np.abs(derivative).max())
    assert max(stiffness) < bound
    if model == "foundation":
        assert stiffness[-1] > 4.0 * stiffness[0] and stiffness[-1] > 0.3 * bound


def _offset_placing_bushing_on_pin(pin_ref, bushing_ref, params):
    c, s = math.cos(pin_ref[2]), math.sin(pin_ref[2])
    px = pin_ref[0] + c * params.pin_offset_m[0] - s * params.pin_offset_m[1]
    py = pin_ref[1] + s * params.pin_offset_m[0] + c * params.pin_offset_m[1]
    c, s = math.cos(bushing_ref[2]), math.sin(bushing_ref[2])
    dx, dy = px - bushing_ref[0], py - bushing_ref[1]
    return (c * dx + s * dy, -s * dx + c * dy)


def test_a_ground_side_gets_no_force_and_the_body_gets_the_bushings():
    _, mbs = new_system()
    bar, handle = hung_bar(mbs)
    force_function = handle.generalized_force          # the GenericODE2's force user function
    q, q_t = np.array([0.0, -2e-4, 0.0]), np.array([0.0, -0.3, 0.0])     # 0.1 mm into the pin, falling
    applied = np.array(force_function(mbs, 0.0, handle.object_number, q, q_t))
    reference = ClearanceJoint(handle.joint.params).evaluate(
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0], np.r_[np.array([0.0, -0.5 * BAR_LENGTH, 0.0]) + q, q_t])
    assert applied.shape == (3,) and np.array_equal(applied, np.array(reference.bushing_force))
    assert applied[1] > 0.0                                              # the pin pushes the bar up


# ------------------------------------------------------------------ statics, wear, several joints
@pytest.mark.parametrize("explicit", [True, False], ids=["explicit-RK4", "generalized-alpha"])
def test_a_hung_bar_comes_to_rest_on_its_normal_force(explicit):
    """The bar drops through the clearance, bounces and settles: the normal force carries its
    weight, m g, and the pin sits c + delta below the bushing centre (delta: Hertz, Eq. 16).  With
    the Lankarani-Nikravesh damping, whose 1 mm/s floor damps the bounces: Hunt-Crossley's restitution
    tends to 1 as the bounces slow (docs/reference/model.md §3.5), so the bar still bounces at 0.12 s."""
    _, mbs = new_system()
    bar, handle = hung_bar(mbs, wear_factor=0.0, contact_damping="lankarani-nikravesh")
    mbs.Assemble()
    solve(mbs, 0.12, 1e-5, explicit)
    h = handle.history()
    assert set(h) == set(HISTORY_COLUMNS) and h["time_s"][-1] == pytest.approx(0.12)
    late = h["time_s"] > 0.1
    weight = BAR_MASS * GRAVITY
    assert np.mean(h["normal_force_N"][late]) == pytest.approx(weight, rel=2e-3)
    p = handle.joint.params
    delta = (weight / p.stiffness_N_m1_5) ** (1.0 / p.contact_exponent)     # Eq. (16) at rest
    assert np.mean(h["penetration_m"][late]) == pytest.approx(delta, rel=0.05)
    assert np.mean(np.hypot(h["eccentricity_x_m"], h["eccentricity_y_m"])[late]) == pytest.approx(
        p.clearance_m + delta, rel=1e-3)
    assert handle.result().in_contact and handle.joint.max_wear_depth_m == 0.0


@pytest.mark.parametrize("wear_factor", [0.0, 100.0], ids=["no-wear", "wear"])
@pytest.mark.parametrize("mass", [0.1, 1.0, 10.0])
def test_a_body_resting_in_the_joint_converges_and_carries_its_weight(mass, wear_factor):
    """A bar hung from ground, started at rest at its static sag c + delta (Hertz, K delta^1.5 = m g),
    runs 0.5 s at the helper's settings without exudyn cutting a single step (every Newton iteration
    converged: with exudyn's absolute tolerance, 1e-10 N, a resting 1 kg bar stalled at a residual
    of 8e-10 N, one rounding step of its position times the contact stiffness, in 1 step of ~500),
    and the normal force carries the weight m g: on average over the run (momentum: the mean of
    F_N - m g is m v(T)/T) and at every step of the last 0.1 s, to 1e-5 of m g: Newton's absolute
    tolerance, 3.3e-6 N with these settings, is 3.4e-6 of the lightest weight, 0.98 N.  With the
    Lankarani-Nikravesh damping: Hunt-Crossley's leaves the contact's micro-oscillation (2e-5 of m g from
    the start's rounding) a damping ratio of ~0.002 (docs/reference/model.md §3.5)."""
    _, mbs = new_system()
    p = JointParameters(contact_damping="lankarani-nikravesh")
    weight = mass * GRAVITY
    delta = (weight / p.stiffness_N_m1_5) ** (1.0 / p.contact_exponent)
    bar, handle = hung_bar(mbs, mass=mass, sag=p.clearance_m + delta, wear_factor=wear_factor,
                           contact_damping=p.contact_damping)
    mbs.Assemble()
    end_time, step = 0.5, 1e-5
    solve(mbs, end_time, step)
    assert handle.accepted_steps == round(end_time / step)          # no step was cut
    h = handle.history()
    assert h["time_s"][-1] == pytest.approx(end_time)
    velocity = mbs.GetNodeOutput(mbs.GetObject(bar)["nodeNumber"], exu.OutputVariableType.Velocity)[1]
    assert np.mean(h["normal_force_N"]) == pytest.approx(weight + mass * velocity / end_time, rel=1e-5)
    late = h["time_s"] > end_time - 0.1
    np.testing.assert_allclose(h["normal_force_N"][late], weight, rtol=1e-5)


@pytest.mark.parametrize("explicit", [True, False], ids=["explicit-RK4", "generalized-alpha"])
def test_a_loaded_spinning_bushing_wears_archards_volume_with_either_solver(explicit):
    """A 1 kg disc whose bushing rests on a ground pin under 100 N, spinning at 20 rad/s, wear factor 100 (a step's
    share 0.64 of the penetration at 1e-5 s): the worn volume is Archard's, k_w F R_j phi (F the normal load
    100 N / sqrt(1 + mu^2), phi the disc's rotation), within 2 % with either solver.  Generalized-alpha applies the
    force at the step's end: with the trapezoid of the start force, on the freshly worn profile, and the end force
    it wore 22 % short; RK4 evaluates it inside the step too, where the trapezoid is its mean."""
    _, mbs = new_system()
    p = JointParameters(wear_factor=100.0)
    load = 100.0
    disc = rigid_body(mbs, (0.0, -p.clearance_m, 0.0), velocity=(0.0, 0.0, 20.0), mass=1.0, inertia=1e-3,
                      gravity=False)
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=disc)),
                                     loadVector=[0.0, -load, 0.0]))
    handle = add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), disc, p)
    mbs.Assemble()
    solve(mbs, 0.03, 1e-5, explicit)
    rotation = mbs.GetNodeOutput(mbs.GetObject(disc)["nodeNumber"], exu.OutputVariableType.Coordinates)[2]
    archard = (p.wear_coefficient_m2_N * p.wear_factor * load / math.hypot(1.0, p.friction_coefficient)
               * p.bushing_radius_m * abs(rotation))
    assert rotation > 0.5 and handle.joint.worn_volume_m3 == pytest.approx(archard, rel=0.02)


def test_two_joints_keep_their_own_profiles_and_states():
    """Two bars swinging side by side from 3 degrees, one three times as heavy and wearing twice as
    fast: each joint wears where its own bar pulls (the bushing's top, 90 deg in the bar's frame,
    within the swing), by its own load and wear factor."""
    _, mbs = new_system()
    light_bar, light = hung_bar(mbs, pivot=(0.0, 0.0), angle=math.radians(3.0), wear_factor=1e3)
    heavy_bar, heavy = hung_bar(mbs, pivot=(0.5, 0.0), angle=math.radians(3.0), mass=3.0 * BAR_MASS, wear_factor=2e3)
    seen = []
    set_post_step(mbs, lambda mbs_, t: seen.append(t) or True)
    mbs.Assemble()
    solve(mbs, 0.05, 1e-5, explicit=True)
    assert len(seen) - 1 == light.accepted_steps == heavy.accepted_steps == 5000   # seen: also the start
    for handle in (light, heavy):
        assert 80.0 < handle.joint.max_wear_angle_deg < 100.0
    assert light.joint.worn_volume_m3 > 0.0
    assert heavy.joint.worn_volume_m3 > 3.0 * light.joint.worn_volume_m3
    assert not np.array_equal(light.joint.wear_depth, heavy.joint.wear_depth)


def test_a_finished_system_is_freed_with_its_joints():
    """The joint's handle holds no reference to the system (exudyn's C++ side keeps the handle's
    functions, a cycle Python's collector cannot see): once the user drops the system container,
    the joint and its arrays go with it instead of living until the interpreter exits."""
    import gc
    import weakref

    system_container, mbs = new_system()
    _, handle = hung_bar(mbs, angle=math.radians(3.0), wear_factor=1e3)
    mbs.Assemble()
    solve(mbs, 1e-3, 1e-5)
    assert handle.accepted_steps == 100
    handle_alive, joint_alive = weakref.ref(handle), weakref.ref(handle.joint)
    del system_container, mbs, handle
    gc.collect()
    assert handle_alive() is None and joint_alive() is None


# ------------------------------------------------------------------ errors
def test_bad_bodies_offsets_and_steps_are_refused_naming_the_argument():
    _, mbs = new_system()
    bar = rigid_body(mbs, (0.0, -0.1, 0.0))
    ground, other_ground = mbs.AddObject(ObjectGround()), mbs.AddObject(ObjectGround())
    twin = mbs.AddObject(ObjectRigidBody2D(nodeNumber=mbs.GetObject(bar)["nodeNumber"], mass=1.0, inertia=1e-3))
    params = JointParameters(bushing_offset_m=(0.0, 0.1))
    marker = mbs.AddMarker(MarkerBodyMass(bodyNumber=bar))
    with pytest.raises(ParameterError, match=r"^mbs=None is invalid: allowed an exudyn MainSystem"):
        add_clearance_joint(None, ground, bar, params)
    with pytest.raises(ParameterError, match=r"^mbs=<a SystemContainer> is invalid: allowed an exudyn MainSystem"):
        add_clearance_joint(exu.SystemContainer(), ground, bar, params)     # its repr spans lines: one line here
    cases = [((ground, 99, params), "bushing_body=99 is invalid: not an object of this system"),
             ((twin, bar, params), f"bushing_body={bar} is invalid: it moves with node 0, pin_body's"),
             ((ground, bar, "paper"), "parameters='paper' is invalid"),
             ((bar, bar, params), f"bushing_body={bar} is invalid: it is pin_body too"),
             ((ground, other_ground, params), "pin_body is ground too"),
             ((ground, mbs.GetObject(bar)["nodeNumber"], params),    # node 0: object 0 exists (the bar)
              "bushing_body=0 is invalid: it is an exudyn NodeIndex, not an object's"),
             ((marker, bar, params), f"pin_body={int(marker)} is invalid: it is an exudyn MarkerIndex"),
             ((ground, bar, JointParameters(bushing_offset_m=(0.0, 0.13))),
              "put the pin centre 0.03 m from the bushing centre at the initial configuration, outside the "
              "bushing: allowed at most the clearance and the admissible penetration, 0.0001 . 0.0002 m"),
             ((ground, bar, JointParameters(bushing_offset_m=(0.0, 0.101))),     # 1 mm off: a 0.9 mm overlap
              "put the pin centre 0.001 m from the bushing centre at the initial configuration, deeper in its wall "
              "than any contact reaches: allowed at most the clearance and the admissible penetration")]
    for args, message in cases:
        with pytest.raises(ParameterError, match=message.replace("(", r"\(").replace(")", r"\)")):
            add_clearance_joint(mbs, *args)
    handle = add_clearance_joint(mbs, ground, bar, params)
    with pytest.raises(ParameterError, match=r"step_s=4e-05 is invalid with wear: allowed at most 3e-05 s"):
        check_step(4e-5, [handle])
    check_step(3e-5, [handle])
    with pytest.raises(ParameterError, match=r"coordinate_scale_m=0.0 is invalid: allowed a finite length > 0 m"):
        simulation_settings(0.1, 1e-5, [handle], coordinate_scale_m=0.0)


def _hung_bar(wear_factor):
    """A 1 kg bar hung from ground through the joint (the helper's own test system, small)."""
    import exudyn as exu
    from exudyn.itemInterface import MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D, LoadMassProportional

    from wearjoint import JointParameters
    from wearjoint.exudyn import add_clearance_joint

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    p = JointParameters(pin_offset_m=(0.0, 0.0), bushing_offset_m=(0.0, 0.1), wear_factor=wear_factor)
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, -0.1 - p.clearance_m, 0.0]))
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=1.0, inertia=1e-3))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)),
                                     loadVector=[0.0, -9.81, 0.0]))
    handle = add_clearance_joint(mbs, ground, bar, p)
    mbs.Assemble()
    return sc, mbs, handle


def test_solving_with_a_step_too_long_for_wear_stops_naming_the_step():
    """exudyn's default step (0.1 ms here) with a wearing joint: the joints' post-step function refuses
    the step when the system is solved, with no call by the user; without wear the same run completes."""
    import exudyn as exu

    sc, mbs, handle = _hung_bar(wear_factor=1.0)
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = 0.01
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    with pytest.raises(Exception, match=r"solver's step 0\.0001 s .* invalid with wear: allowed at most 3e-05 s"):
        exu.SolveDynamic(mbs, settings)
    sc, mbs, handle = _hung_bar(wear_factor=0.0)
    assert exu.SolveDynamic(mbs, settings)
    assert handle.accepted_steps > 0


@pytest.mark.parametrize("end_time", [0.05, 1e-5 * 12345.4, 1.4e-5, 2.5e-6])
def test_the_helpers_steps_never_exceed_the_step_asked_for(end_time):
    """simulation_settings takes the fewest whole steps of at most step_s: an end time that is no multiple
    of the wear-step limit used to round to a step just over it, which the joints' check then refused;
    a multiple keeps its count (0.05 s: 5000 steps)."""
    import exudyn as exu

    settings = simulation_settings(end_time, 1e-5)
    n = settings.timeIntegration.numberOfSteps
    assert end_time / n <= 1e-5 and (n == 1 or end_time / (n - 1) > 1e-5)
    if end_time == 0.05:
        assert n == 5000
    if end_time < 1e-3:                            # a whole run only where it is short
        sc, mbs, handle = _hung_bar(wear_factor=1.0)
        settings = simulation_settings(end_time, 1e-5, [handle])
        assert exu.SolveDynamic(mbs, settings)


def test_sensors_keep_working_with_the_helpers_settings():
    import exudyn as exu
    from exudyn.itemInterface import SensorNode

    from wearjoint.exudyn import simulation_settings

    sc, mbs, handle = _hung_bar(wear_factor=0.0)
    mbs.AddSensor(SensorNode(nodeNumber=0, storeInternal=True, outputVariableType=exu.OutputVariableType.Position,
                             writeToFile=False))
    mbs.Assemble()
    exu.SolveDynamic(mbs, simulation_settings(0.002, 1e-5, (handle,)))
    data = mbs.GetSensorStoredData(0)
    assert data.shape[1] == 4 and np.all(np.isfinite(data))   # was (0, 0): sensors off
    # every step (200 of 1e-5 s) and the start, where exudyn's default samples every 0.01 s: an impact unseen
    assert data.shape[0] >= 200 and np.allclose(np.diff(data[:, 0]), 1e-5)


@pytest.mark.parametrize("wear_factor, warned", [(10.0, False), (1e4, False), (1e5, True)])
def test_a_step_wearing_too_much_of_the_penetration_is_a_warning_once(wear_factor, warned):
    """A swinging bar's bushing slides ~0.03 m/s on the pin: at 1e-5 s a step's share k_f k_w F v dt of the
    penetration is ~1e-3 at wear factor 10, ~1 at 1e4 (within the relaxed update's limit of 4) and ~10 at 1e5
    (docs/reference/model.md §7)."""
    import warnings

    sc, mbs = new_system()
    _, handle = hung_bar(mbs, angle=0.4, sag=JointParameters().clearance_m, wear_factor=wear_factor)
    mbs.Assemble()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solve(mbs, 0.02, 1e-5)
    said = [w for w in caught if "of the contact's penetration" in str(w.message)]
    assert len(said) == (1 if warned else 0)
    assert handle.accepted_steps >= 2000


def test_solve_dynamic_keeps_exudyns_allocation_warning_off_and_restores_its_threshold(capfd):
    """exudyn counts the joint's per-call arrays and warns on every solve ("memory allocations"): harmless, so
    solve_dynamic lifts exudyn's threshold for the call, and puts it back; exudyn's own call still warns."""
    import exudyn.solver

    from wearjoint.exudyn import solve_dynamic

    threshold = exudyn.solver.solverCheckMemoryAllocationsThreshold
    outputs = []
    for run in (exu.SolveDynamic, solve_dynamic):
        _, mbs = new_system()
        hung_bar(mbs, wear_factor=0.0)
        mbs.Assemble()
        capfd.readouterr()
        run(mbs, simulation_settings(0.2, 1e-5))          # 20 000 steps: past exudyn's 1e5 allocations
        outputs.append(capfd.readouterr())
    said = [out.out + out.err for out in outputs]
    assert "memory allocations" in said[0] and "memory allocations" not in said[1]
    assert exudyn.solver.solverCheckMemoryAllocationsThreshold == threshold
