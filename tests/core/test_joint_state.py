"""ClearanceJoint state: copy/restore, bytes round trip, profile CSV, input errors."""
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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
        ClearanceJoint(JointParameters()).state_from_bytes(b"garbage" * 10)


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


# ------------------------------------------------------------- the state format
def test_crc32c_gives_the_published_check_values():
    """CRC-32C check value of "123456789" (0xE3069283) and the RFC 3720 B.4 vectors (32 bytes)."""
    from wearjoint.core.state_format import crc32c

    vectors = {b"123456789": 0xE3069283, bytes(32): 0x8A9136AA, b"\xff" * 32: 0x62A8AB43,
               bytes(range(32)): 0x46DD794E, bytes(range(31, -1, -1)): 0x113FDB5C}
    for data, expected in vectors.items():
        assert crc32c(np.frombuffer(data, dtype=np.uint8), len(data)) == expected, data


def test_state_layout_is_the_documented_one():
    """docs/reference/fmu.md: magic, version 4, contents 1, n_points, payload bytes; float64 memory (active flag,
    onset velocity, start force, the wear batch's seven values) and depths; CRC-32C of everything before it (little-endian throughout)."""
    import struct

    from wearjoint.core.state_format import crc32c

    joint = ClearanceJoint(JointParameters(n_points=16, wear_factor=50.0))
    joint.wear_depth[3] = 1.5e-6
    memory = [1.0, 0.25, 12.5, 2e-5, 1e-3, 2e-6, 3e-2, 1e-4, -2e-5, 7.0]
    joint.memory[:] = memory
    data = joint.state_to_bytes()
    assert data[:8] == b"WJSTATE\0"
    assert struct.unpack_from("<4I", data, 8) == (4, 1, 16, 8 * 26)
    assert struct.unpack_from("<26d", data, 24) == (*memory, *joint.wear_depth)
    assert len(data) == 24 + 8 * 26 + 4
    assert struct.unpack_from("<I", data, len(data) - 4)[0] == crc32c(np.frombuffer(data, np.uint8), len(data) - 4)


def _restore_refused(data, joint=None):
    """The message of the refusal; the joint (default n_points) unchanged."""
    joint = joint or ClearanceJoint(JointParameters())
    before = joint.state_to_bytes()
    with pytest.raises(ParameterError) as refused:
        joint.state_from_bytes(data)
    assert joint.state_to_bytes() == before
    return str(refused.value)


def test_each_refusal_names_the_check_and_the_two_things_compared():
    from wearjoint.core.state_format import CONTENTS_FMU
    from wearjoint.joint import state_bytes

    joint = ClearanceJoint(JointParameters())
    _drive(joint, 20, seed=6)
    good = joint.state_to_bytes()
    n = joint.wear_depth.size
    assert _restore_refused(good[:-8]) == (f"the state has {len(good) - 8} bytes, its header declares {len(good)} "
                                           f"(a payload of {8 * (n + 10)} bytes)")
    assert _restore_refused(good[:10]) == "the state has 10 bytes, fewer than the 28 of its header and checksum"
    flipped = bytearray(good)
    flipped[100] ^= 4
    assert "CRC-32C is 0x" in _restore_refused(bytes(flipped)) and "the bytes are corrupted" in _restore_refused(
        bytes(flipped))
    newer = bytearray(good)
    newer[8] = 5
    assert _restore_refused(bytes(newer)) == "the state has format version 5, this build reads version 4"
    assert _restore_refused(good, ClearanceJoint(JointParameters(n_points=100))) == (
        f"the state holds {n} bushing points, this joint has n_points=100")
    fmu_state = state_bytes(CONTENTS_FMU, [0.0, 1.0], joint.memory, joint.wear_depth)
    assert _restore_refused(fmu_state) == ("the state's contents are kind 2, expected kind 1 (1: a joint's, "
                                           "2: a joint FMU instance's, 3: a SliderCrank FMU instance's)")
    for k, depth, words in [(5, float("nan"), "is not finite"), (6, -1e-9, "is negative"),
                            (7, 0.0102, "is deeper than the bushing radius")]:
        bad = joint.wear_depth.copy()
        bad[k] = depth
        message = _restore_refused(state_bytes(1, (), joint.memory, bad))
        assert message == f"state: wear_depth[{k + 1}]={depth!r} m {words}: allowed a depth in [0, 0.0101] m"
    for memory, shown in [([0.5, 0.0, 0.0], "active flag=0.5"), ([1.0, float("inf"), 0.0], "onset velocity=inf m/s"),
                          ([0.0, 0.2, 0.0], "onset velocity=0.2 m/s"), ([1.0, 1e-4, 0.0], "onset velocity=0.0001 m/s"),
                          ([0.0, 0.0, -0.5], "start force=-0.5 N"), ([0.0, 0.0, float("nan")], "start force=nan N")]:
        assert shown in _restore_refused(state_bytes(1, (), memory, joint.wear_depth))


def test_profile_files_are_checked_like_states(tmp_path):
    joint = ClearanceJoint(JointParameters(n_points=16))
    path = joint.save_profile(tmp_path / "p.csv")
    rows = path.read_text().splitlines()
    (tmp_path / "short.csv").write_text("\n".join(rows[:-1]) + "\n")
    with pytest.raises(ParameterError, match="has 15 rows \\(bushing points\\), this joint has n_points=16"):
        joint.load_profile(tmp_path / "short.csv")
    (tmp_path / "deep.csv").write_text("\n".join([*rows[:-1], rows[-1].split(",")[0] + ",1.0"]) + "\n")
    with pytest.raises(ParameterError, match=r"wear_depth\[16\]=1.0 m is deeper than the bushing radius"):
        joint.load_profile(tmp_path / "deep.csv")
    assert np.all(joint.wear_depth == 0.0)


@settings(max_examples=60, deadline=None)
@given(flips=st.lists(st.integers(0, 8 * (24 + 8 * 18 + 4) - 1), min_size=1, max_size=8),
       planted=st.sampled_from([float("nan"), float("inf"), -float("inf"), 1e300]), at=st.integers(24, 24 + 8 * 17))
def test_corrupted_joint_states_are_refused_or_exact(flips, planted, at):
    """Flipped bits and planted values: refused, or (flips that cancel) the very same state."""
    joint = ClearanceJoint(JointParameters(n_points=16))
    joint.wear_depth[:] = np.linspace(0.0, 2e-6, 16)
    good = joint.state_to_bytes()
    flipped = bytearray(good)
    for bit in flips:
        flipped[bit // 8] ^= 1 << (bit % 8)
    planted_state = bytearray(good)
    planted_state[at:at + 8] = np.float64(planted).tobytes()
    for data in (bytes(flipped), bytes(planted_state)):
        other = ClearanceJoint(JointParameters(n_points=16))
        try:
            other.state_from_bytes(data)
        except ParameterError:
            assert np.all(other.wear_depth == 0.0)
        else:
            assert data == good and other.state_to_bytes() == good
