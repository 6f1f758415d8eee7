"""Cycle jumping (wearjoint.studies.cycle_jump, core.cycle_jump): the replay of a loading against
Archard's volume and against a simulated revolution, the jump controller, a jump study's accounts."""
import math
from pathlib import Path

import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.core.cycle_jump import LOAD_DURATION, LOAD_NORMAL_FORCE, LOAD_RELATIVE_OMEGA, N_LOAD_COLUMNS
from wearjoint.joint import ClearanceJoint
from wearjoint.parameters import ParameterError, SliderCrankParameters, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions
from wearjoint.studies.cycle_jump import (
    JUMP_GROWTH, jump_error, jump_summary, loading_from_samples, next_jump, remaining_wall_s, replay_volume_warning,
)
from wearjoint.studies.wear_study import WearStudyConfig, run_wear_study


def constant_load(joint: ClearanceJoint, force_n: float, angle_rad: float, relative_omega: float, duration: float):
    """One loading row: the pin pressed towards ``angle_rad`` (bushing frame) by ``force_n``, its
    penetration the one the joint's contact gives for that force on the unworn bushing."""
    p = joint.params
    row = np.zeros((1, N_LOAD_COLUMNS))
    lo, hi = 0.0, 1e-4                              # penetration of the unworn bushing that carries force_n
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        e = p.clearance_m + mid
        pin = [e * math.cos(angle_rad) - p.pin_offset_m[0], e * math.sin(angle_rad) - p.pin_offset_m[1], 0, 0, 0, 0]
        bushing = [-p.bushing_offset_m[0], -p.bushing_offset_m[1], 0, 0, 0, 0]
        lo, hi = (mid, hi) if joint.evaluate(pin, bushing).normal_force_N < force_n else (lo, mid)
    e = p.clearance_m + lo
    row[0] = [e * math.cos(angle_rad), e * math.sin(angle_rad), lo, force_n, relative_omega, 0.0, duration]
    return row


@pytest.mark.parametrize("scale", [1.0, 1e3, 1e5])
def test_replay_removes_archards_volume_at_any_scale_without_ripple(scale):
    """A load F in a fixed direction, sliding at R_j |omega| for t * scale: the worn volume is Archard's
    k_w F R_j |omega| t scale (Eq. 24), up to the worn radius R_j + h at which the points slide and whose
    area they remove (a factor between 1 and 1 + 2 h_max / R_j), the increment is a single smooth groove
    centred on the load's direction, for scales that remove from
    a fraction of the penetration (1) to 30 times the clearance's worth of wear (1e5)."""
    p = paper_joint(wear_factor=1.0)
    joint = ClearanceJoint(p)
    force, omega, t, angle = 400.0, 30.0, 1e-4, 0.7
    row = constant_load(joint, force, angle, omega, t)
    joint.replay_wear(row, scale)
    archard = p.wear_coefficient_m2_N * force * p.bushing_radius_m * omega * t * scale
    h = joint.wear_depth
    assert archard * (1 - 1e-9) <= joint.worn_volume_m3 <= archard * (1 + 2 * h.max() / p.bushing_radius_m)
    deepest = joint.phi_rad[np.argmax(h)] % (2 * math.pi)
    assert abs(deepest - angle) <= 2 * (2 * math.pi / h.size)
    around = np.roll(h, h.size // 2 - int(np.argmax(h)))          # the groove in the middle
    rising, falling = np.diff(around[: h.size // 2 + 1]), np.diff(around[h.size // 2:])
    assert np.all(rising >= -1e-12 * h.max()) and np.all(falling <= 1e-12 * h.max())   # one groove, no ripple


@pytest.mark.parametrize("flank_deg", [0.0, 10.0, 14.0])
def test_replay_keeps_archards_volume_on_the_flank_of_a_groove_deeper_than_the_clearance(flank_deg):
    """A bushing worn into a groove 0.4 mm deep (four clearances c; the bore shifted by d: r(phi) =
    d cos(phi) + sqrt(R_j^2 - d^2 sin^2(phi))) and a load towards phi on its flank (|phi| < asin(c/d) = 14.5 deg):
    the pin touches the groove where |e u - d x| = c + p, so moving it along u changes its penetration p by
    the cosine of a steep angle (about 0.25 at 14 deg).  Recorded 20 um shallower (a profile the jump has worn
    since),
    the pin must still be placed at its recorded penetration and the row remove Archard's volume
    k_w F R_j |omega| t, up to the worn radius (a factor between 1 and 1 + 2 h_max / R_j, as above)."""
    p = paper_joint(wear_factor=1.0)
    joint = ClearanceJoint(p)
    d, radius, c = 0.4e-3, p.bushing_radius_m, p.clearance_m
    phi = joint.phi_rad
    joint.set_wear_profile(np.maximum(0.0, d * np.cos(phi) + np.sqrt(radius ** 2 - (d * np.sin(phi)) ** 2) - radius))
    force, omega, t, angle, penetration = 300.0, 30.0, 1e-4, math.radians(flank_deg), 0.1e-6
    touching = d * math.cos(angle) + math.sqrt((c + penetration) ** 2 - (d * math.sin(angle)) ** 2)
    e = touching - 20e-6
    row = np.zeros((1, N_LOAD_COLUMNS))
    row[0] = [e * math.cos(angle), e * math.sin(angle), penetration, force, omega, 0.0, t]
    before = joint.worn_volume_m3
    joint.replay_wear(row, 1.0)
    archard = p.wear_coefficient_m2_N * force * omega * t
    removed = joint.worn_volume_m3 - before
    assert archard * radius <= removed <= archard * (radius + 2 * d), (removed, archard * radius)


def test_replay_places_a_pin_that_touches_only_the_shoulder_of_a_groove_deepened_since_its_row():
    """A row of the paper's default wear study (printed k_w, revolution ~1100: tests/data/deep_groove_row.npz, its
    profile the one the jump had worn by then, 1.85 mm deep): at its recorded eccentricity the pin sits 0.09 mm
    short of the groove's bottom, its nearest point the shoulder 80 degrees off, whose gap moving the pin changes by
    a hundredth of the move.  The placement must still reach the recorded penetration and the row remove Archard's
    volume k_w F R_j |omega| t up to the worn radius (the secant steps alone fell micrometres short: nothing)."""
    data = np.load(Path(__file__).parents[1] / "data" / "deep_groove_row.npz")
    p = paper_joint(wear_factor=1.0)
    joint = ClearanceJoint(p)
    joint.set_wear_profile(data["wear_depth_m"])
    row = data["row"][None, :]
    before = joint.worn_volume_m3
    joint.replay_wear(row, 1.0)
    archard = (p.wear_coefficient_m2_N * row[0, LOAD_NORMAL_FORCE] * abs(row[0, LOAD_RELATIVE_OMEGA])
               * row[0, LOAD_DURATION])
    removed = joint.worn_volume_m3 - before
    depth = data["wear_depth_m"].max()
    assert archard * p.bushing_radius_m <= removed <= archard * (p.bushing_radius_m + 2 * depth), removed


def test_replay_refuses_bad_loading_and_absurd_wear_leaving_the_joint_unchanged():
    p = paper_joint(wear_factor=1.0)
    joint = ClearanceJoint(p)
    row = constant_load(joint, 400.0, 0.0, 30.0, 1e-4)
    with pytest.raises(ParameterError, match=r"loading of shape \(1, 6\) is invalid"):
        joint.replay_wear(row[:, :6], 1.0)
    with pytest.raises(ParameterError, match="scale=-1.0 is invalid"):
        joint.replay_wear(row, -1.0)
    with pytest.raises(ParameterError, match="would exceed the bushing radius"):
        joint.replay_wear(row, 1e15)
    assert not joint.wear_depth.any()


def test_a_replayed_revolution_wears_as_the_simulated_one():
    """The loading of the second simulated revolution (its samples in contact), replayed once on the profile
    it began with, wears that revolution's volume within 2 % and its profile within 2 % RMS of its deepest
    increment (measured: 0.06 % and 0.34 %; the samples are every RK4 step here)."""
    mech = SliderCrankParameters()
    joint = paper_joint(wear_factor=1.0)
    sim = Simulation(joint, mech, SimulationOptions(revolutions=2, integrator="rk4", step_s=1e-5, max_step_s=1e-5,
                                                    sample_dt_s=1e-5))
    period = mech.period_s
    buffer = np.zeros((int(period / 1e-5) + 64, L.N_SAMPLE_COLUMNS))
    sim.advance_to(period, buffer)
    _, before, volume_before = sim.wear_profile()
    n = sim.advance_to(2 * period, buffer)
    _, after, volume_after = sim.wear_profile()
    replay = ClearanceJoint(joint)
    replay.set_wear_profile(before)
    replay.replay_wear(loading_from_samples(buffer[:n], 1e-5), 1.0)
    assert replay.worn_volume_m3 - volume_before == pytest.approx(volume_after - volume_before, rel=0.02)
    simulated, replayed = after - before, replay.wear_depth - before
    assert np.sqrt(np.mean((replayed - simulated) ** 2)) <= 0.02 * simulated.max()


def test_jump_error_is_half_the_jump_times_the_rate_change():
    before = np.full(100, 1e-7)
    assert jump_error(50, before, before, 1e-4) == 0.0
    assert jump_error(50, before, before + 2e-8, 1e-4) == pytest.approx(0.5 * 50 * 2e-8 / 1e-4)
    assert jump_error(0, before, before + 2e-8, 1e-4) == 0.0


@pytest.mark.parametrize("error", [0.0, 1e-6, 0.005, 0.01, 0.02, 0.5, 10.0])
def test_next_jump_follows_a_first_order_error_within_its_limits(error):
    jump, tolerance = 100, 0.01
    proposed = next_jump(jump, error, tolerance)
    lo, hi = JUMP_GROWTH
    assert int(jump * lo) <= proposed <= int(jump * hi)
    if error > 0:
        expected = min(hi, max(lo, 0.9 * math.sqrt(tolerance / error)))
        assert proposed == int(jump * expected)
    assert next_jump(1, 10.0, tolerance) == 1


@pytest.mark.parametrize("q", [0.05, 0.3, 1.0])
def test_the_eta_counts_the_cycles_of_jumps_that_keep_their_share(q):
    """Jumps of q times the revolutions reached plus a block of 2: the ETA is the cycles up to the total times a
    cycle's wall, counted by stepping the same growth (the total put where a cycle ends)."""
    r, cycles = 40.0, 0
    while cycles < 25:
        r, cycles = (1.0 + q) * r + 2.0, cycles + 1
    assert remaining_wall_s(40, r, 2, q * 40, 0.7) == pytest.approx(cycles * 0.7, rel=1e-9)
    assert remaining_wall_s(r, r, 2, q * r, 0.7) == 0.0


def test_the_eta_of_the_first_block_of_a_long_study_is_not_hours():
    """The paper's experiment, 400 000 revolutions, took 195 cycles of 0.7 s (137 s): after its first block and
    jump (4 revolutions, the next jump proposed at 2) the ETA is a few minutes at most, where the rate of
    revolutions done said 542 hours; it cannot see the error control's slowing, so it is low early."""
    first = remaining_wall_s(4, 400_000, 2, 2, 0.7)
    assert 10.0 < first < 600.0
    assert remaining_wall_s(4, 400_000, 2, 0, 0.7) != remaining_wall_s(4, 400_000, 2, 0, 0.7)   # NaN: no jump yet


def jump_config(**changes) -> WearStudyConfig:
    return WearStudyConfig(**{**dict(joint=paper_joint(wear_factor=1.0), mechanism=SliderCrankParameters(),
                                     revolutions=10, snapshots=(5, 10)), **changes})


def test_a_jump_study_accounts_every_revolution_and_reports_its_jumps(tmp_path):
    """(Its resume after a kill: test_wear_study.py.)"""
    whole = run_wear_study(jump_config(), tmp_path, progress=False, plots=False)
    jumps = whole["cycle_jumping"]
    history = jumps["jump_history"]
    assert jumps["simulated_revolutions"] + jumps["jumped_revolutions"] == 10
    assert whole["simulated_revolutions"] == jumps["simulated_revolutions"] < 10
    for earlier, later in zip(history, history[1:]):
        assert earlier["start_revolution"] + earlier["revolutions"] < later["start_revolution"]   # a block between
    growth = np.loadtxt(tmp_path / "wear_growth.csv", delimiter=",", skiprows=1)
    assert np.all(np.diff(growth[:, 0]) > 0) and np.all(np.diff(growth[:, 1]) >= 0.0)
    assert [s["revolution"] for s in whole["snapshots"]] == [5, 10]
    low, high = jumps["replay_volume_ratio_range"]       # each jump wore the block's volume per revolution times N
    # times the growth of what the block's loading wears as the profile deepens (the worn radius it slides at)
    assert all(1.0 <= j["replay_volume_growth"] < 1.001 for j in history)
    assert 0.99 <= low <= high <= 1.01, (low, high)
    assert jumps["replay_volume_outside"] == [] and replay_volume_warning(jumps) is None
    # revolutions.csv: a row per simulated revolution, named by the revolution it is (jumped ones have none), its
    # depth at its end; a block's last revolution ends where wear_growth.csv's block entry is
    rows = np.loadtxt(tmp_path / "revolutions.csv", delimiter=",", skiprows=1, ndmin=2)
    assert len(rows) == jumps["simulated_revolutions"] and np.all(np.diff(rows[:, 0]) >= 1)
    assert rows[-1, 0] == 9 and set(rows[:, 0]).isdisjoint(
        r for j in history for r in range(j["start_revolution"], j["start_revolution"] + j["revolutions"]))
    assert np.all(np.isfinite(rows[:, 7])) and np.all(np.diff(rows[:, 7]) >= 0.0)
    ends = {revolution: depth for revolution, depth, _ in growth}
    blocks_ending = [k for k, r in enumerate(rows[:, 0]) if r + 1 in ends]
    assert blocks_ending and all(rows[k, 7] == ends[rows[k, 0] + 1] for k in blocks_ending)


def test_a_jump_whose_replay_lost_volume_is_named_with_a_warning():
    """0.943 of the block's volume (what the replay's old placement gave on a deep groove): the jump is listed
    and the warning names the band and how to check."""
    state = {"jump": {"jumps": [{"start_revolution": 4, "revolutions": 8, "passes": 1, "error_estimate_rel": 0.001,
                                 "error_estimate_m": 1e-9, "replay_volume_ratio": 0.943},
                                {"start_revolution": 14, "revolutions": 16, "passes": 1, "error_estimate_rel": None,
                                 "error_estimate_m": None, "replay_volume_ratio": 1.002}],
                      "simulated_revolutions": 8},
             "growth": [(30, 1e-5, 1e-10)]}
    summary = jump_summary(jump_config(), state)
    assert summary["replay_volume_outside"] == [4] and summary["replay_volume_ratio_allowed"] == [0.99, 1.01]
    warning = replay_volume_warning(summary)
    assert "1 jump(s) (from revolution 4) replayed 0.943-1" in warning and "outside 0.99-1.01" in warning


def test_the_jumps_whose_estimate_passed_the_tolerance_are_listed():
    """A jump is not redone (its estimate follows the next block): the summary names those over the tolerance."""
    estimates = (0.044, None, 0.003, 0.0031, 0.001)     # None: the last jump, no block after it
    state = {"jump": {"jumps": [{"start_revolution": 10 * k, "revolutions": 4, "passes": 1, "error_estimate_rel": e,
                                 "error_estimate_m": None if e is None else e * 1e-4, "replay_volume_ratio": 1.0}
                                for k, e in enumerate(estimates)], "simulated_revolutions": 10},
             "growth": [(50, 1e-4, 1e-10)]}
    summary = jump_summary(jump_config(), state)
    assert summary["tolerance_rel"] == 0.003 and summary["jumps_over_tolerance"] == [0, 30]
    assert summary["largest_error_estimate_rel"] == 0.044


@pytest.mark.parametrize("changes, message", [
    (dict(jump_tolerance=0.0), "tolerance=0.0 is invalid"),
    (dict(jump_tolerance=1.5), "tolerance=1.5 is invalid"),
    (dict(joint=paper_joint(wear_factor=10.0)), "jump_tolerance=0.003 is invalid with wear_factor=10.0: allowed "
                                                "only at wear factor 1"),
    (dict(jump_block_revolutions=0), "jump_block_revolutions=0 is invalid"),
    (dict(engine="cosim"), "engine=.cosim. is invalid with cycle jumping"),
])
def test_jump_settings_are_checked(changes, message):
    with pytest.raises(ParameterError, match=message):
        jump_config(**changes)


@pytest.mark.slow
def test_cycle_jumping_matches_brute_force_through_running_in(tmp_path):
    """40 revolutions of running-in (the rate falls fastest there) by jumps and by simulating every revolution
    at wear factor 1: max depth and worn volume within 5 % (measured at tol 0.01: +1.5 % and +2.5 %, in 22
    simulated revolutions); the 4000-revolution comparison is in docs/explanation/wear_study.md."""
    brute = run_wear_study(jump_config(revolutions=40, snapshots=(40,), jump_tolerance=None), tmp_path / "brute",
                           progress=False, plots=False)
    jumped = run_wear_study(jump_config(revolutions=40, snapshots=(40,)), tmp_path / "jump", progress=False,
                            plots=False)
    assert jumped["simulated_revolutions"] < 40 == brute["simulated_revolutions"]
    assert jumped["max_wear_depth_m"] == pytest.approx(brute["max_wear_depth_m"], rel=0.05)
    assert jumped["worn_volume_m3"] == pytest.approx(brute["worn_volume_m3"], rel=0.05)
