"""ClearanceJoint state: copy/restore, bytes round trip, profile CSV, input errors."""
import pickle

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, ParameterError, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions


def _drive(joint, steps, seed):
    """Advance a joint along a fixed pseudo-random contact trajectory."""
    rng = np.random.default_rng(seed)
    c = joint.params.clearance_m
    for _ in range(steps):
        angle = rng.uniform(0, 2 * np.pi)
        e = (c + rng.uniform(-2e-6, 6e-6)) * np.array([np.cos(angle), np.sin(angle)])
        pin = [0.0, 0.0, 0.0, *rng.normal(0, 0.05, 2), -15.7]
        centre = np.array(joint.params.pin_offset_m) - e - np.array(joint.params.bushing_offset_m)
        joint.advance(pin, [centre[0], centre[1], 0.0, 0.0, 0.0, 3.0], 1e-5)


def test_copy_restore_and_bytes_round_trip_reproduce_bit_for_bit():
    joint = ClearanceJoint(JointParameters(wear_factor=50.0))
    _drive(joint, 50, seed=3)
    state = joint.get_state()
    blob = joint.state_to_bytes()
    _drive(joint, 80, seed=4)
    reference = joint.wear_depth.copy(), joint.memory.copy()
    assert reference[0].max() > state.wear_depth_m.max()
    joint.set_state(state)
    _drive(joint, 80, seed=4)
    assert np.array_equal(joint.wear_depth, reference[0]) and np.array_equal(joint.memory, reference[1])
    other = ClearanceJoint(JointParameters(wear_factor=50.0))
    other.state_from_bytes(blob)
    _drive(other, 80, seed=4)
    assert np.array_equal(other.wear_depth, reference[0])


def test_state_bytes_reject_a_joint_of_another_size():
    blob = ClearanceJoint(JointParameters()).state_to_bytes()
    with pytest.raises(ParameterError, match="n_points"):
        ClearanceJoint(JointParameters(n_points=100)).state_from_bytes(blob)
    with pytest.raises(ParameterError, match="magic bytes"):
        ClearanceJoint(JointParameters()).state_from_bytes(b"garbage")


def test_simulation_resumed_from_a_copied_state_is_bit_identical():
    opts = SimulationOptions(revolutions=0.1, integrator="dopri", max_step_s=1e-5)
    params = paper_joint(wear_factor=20.0)
    buf = np.zeros((20000, 13))
    a = Simulation(params, options=opts)
    a.advance_to(0.01, buf)
    saved = pickle.dumps(a.checkpoint())
    a.advance_to(0.03, buf)
    b = Simulation(params, options=opts)
    b.restore(pickle.loads(saved))
    b.advance_to(0.03, buf)
    assert a.joint.max_wear_depth_m > 0
    assert np.array_equal(a.y, b.y) and np.array_equal(a.joint.wear_depth, b.joint.wear_depth)
    assert np.array_equal(a.revolution_stats, b.revolution_stats)


def test_profile_csv_round_trip(tmp_path):
    joint = ClearanceJoint(JointParameters(wear_factor=50.0))
    _drive(joint, 40, seed=5)
    path = joint.save_profile(tmp_path / "profile.csv")
    assert path.read_text().splitlines()[0] == "phi_deg,wear_depth_m"
    other = ClearanceJoint(JointParameters())
    other.load_profile(path)
    assert np.array_equal(other.wear_depth, joint.wear_depth)
    assert other.worn_volume_m3 == joint.worn_volume_m3


def test_bad_kinematics_and_profiles_are_rejected():
    joint = ClearanceJoint(JointParameters())
    with pytest.raises(ParameterError, match="non-finite"):
        joint.evaluate([0, 0, 0, 0, 0, float("nan")], [0] * 6)
    with pytest.raises(ParameterError, match="6 numbers"):
        joint.evaluate([0, 0, 0], [0] * 6)
    with pytest.raises(ParameterError, match="dt"):
        joint.advance([0] * 6, [0] * 6, -1e-5)
    with pytest.raises(ParameterError, match=r"is negative: allowed a depth in \[0, "):
        joint.set_wear_profile(-np.ones(1257))


def test_setting_the_wear_profile_updates_the_engine_at_the_current_state():
    from wearjoint.core import layout as L
    sim = Simulation(paper_joint(wear_factor=0.0), options=SimulationOptions(revolutions=0.1))
    buf = np.zeros((20000, 13))
    t = 2e-3
    while sim.joint.result[L.R_PENETRATION] < 0.0:     # integrate until the pin touches the bushing
        t += 2e-4
        sim.advance_to(t, buf)
    before = sim.joint.result[L.R_PENETRATION]
    sim.set_wear_profile(np.full(1257, 2e-6))           # the wall moves 2 um outwards everywhere
    # (radially; the contact normal is radial to within |e|/R_j, a second-order 1e-12 m effect)
    assert sim.joint.result[L.R_PENETRATION] == pytest.approx(before - 2e-6, abs=1e-10)


def test_negative_wear_depths_are_refused_on_every_way_in():
    """The deepest-point search bounds unscanned points with the unworn radius R_j, so a
    profile may only ever deepen: a negative depth must not get into a joint, neither as a
    profile nor through a serialised state."""
    joint = ClearanceJoint(JointParameters())
    profile = np.zeros(joint.wear_depth.size)
    profile[7] = -1e-9
    with pytest.raises(ParameterError, match=r"is negative: allowed a depth in \[0, "):
        joint.set_wear_profile(profile)
    donor = ClearanceJoint(JointParameters())
    donor.wear_depth[7] = -1e-9               # bypasses the API on purpose
    with pytest.raises(ParameterError, match=r"is negative: allowed a depth in \[0, "):
        joint.state_from_bytes(donor.state_to_bytes())
    assert np.all(joint.wear_depth == 0.0)
