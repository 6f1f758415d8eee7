"""Error-controlled cycle jumping, the wear study's default route to long horizons (docs/explanation/wear_study.md,
docs/reference/model.md §3.11).

The study alternates **blocks** and **jumps**.  A block simulates ``jump_block_revolutions`` crank
revolutions at the real wear rate (wear factor 1) and measures their wear rate w(phi) [m per revolution]
and their loading (the contact of every sample: :func:`loading_from_samples`).  A jump of N revolutions
then replays that loading N times over through the relaxed wear update
(:meth:`wearjoint.joint.ClearanceJoint.replay_wear`), which is stable for any N, in passes that each wear
at most PASS_INCREMENT_SHARE of the max depth (the replay's order error, docs/explanation/wear_study.md).

Error estimate of a jump: the jump held the rate it started with; the next block measures the rate it
ended with, so the jump's error is about half its length times the change of the rate (the difference of
Euler's and Heun's steps), which also contains the rate's sampling noise of the chaotic dynamics:
e = N/2 RMS(w_after - w_before), relative to the max depth.  The next jump is N * 0.9 (tol / e)^(1/2),
between 0.2 and 2 times N (a first-order method's local error grows with N^2).  Every jump's length,
passes and estimate go to summary.json, with a check the estimate cannot make: the volume the replay wore
over the block's volume per revolution times N and times the mean growth, over the jump, of the volume one
replay of the block's loading wears (the points slide at the worn radius, Eq. 33: ``replay_volume_growth``, that
volume from the jump's last profile over its first); ``replay_volume_ratio``, 1 where the jump's wear is the block's.
"""
from __future__ import annotations

import math
import time

import numpy as np

from wearjoint.core import layout as L
from wearjoint.core.cycle_jump import N_LOAD_COLUMNS
from wearjoint.joint import ClearanceJoint
from wearjoint.progress import Progress
from wearjoint.runner import divergence
from wearjoint.checks import ParameterError, RunDiverged, finite, require, worn_through_message

DEFAULT_JUMP_TOLERANCE = 0.003          # local error of a jump, relative to the max depth (docs/explanation/wear_study.md)
PASS_INCREMENT_SHARE = 0.05             # one replay pass wears at most this share of the max depth (explicit bound)
FIRST_JUMP_BLOCKS = 1                   # the first jump is as long as a block
JUMP_GROWTH = (0.2, 2.0)                # limits of the next jump's factor
SAFETY = 0.9
# a jump's replayed volume over its block's volume per revolution times its length and the mean growth over the jump
# (replay_volume_growth): the default study's within 0.9998-1.0095 (docs/explanation/wear_study.md); outside 1 -/+
# this, the jump's wear is not the block's
REPLAY_VOLUME_TOLERANCE = 0.01
# the growth of a block's volume over a jump is measured on every this-many-th row of its loading (the same rows on
# the jump's first and last profile: a ratio; all rows doubled the default study's replay time)
GROWTH_ROW_STRIDE = 16
MAX_SIMULATED_REVOLUTIONS = 1e6       # a study without jumps (about 100 h of simulation; its per-revolution table 56 MB)
MAX_JUMPED_REVOLUTIONS = 1e12         # a cycle-jumping study's span (its simulated revolutions: the jumps decide)


def check_route(revolutions: int, wear_factor: float, jump_tolerance: float | None, engine: str) -> None:
    """ParameterError unless a study's route holds: cycle jumping (``jump_tolerance`` in (0, 1)) at wear factor 1
    on the monolithic engine over at most MAX_JUMPED_REVOLUTIONS (it simulates what the jumps need: 150 revolutions
    for 2.1e6); without it revolutions / wear factor simulated revolutions, from 1 to MAX_SIMULATED_REVOLUTIONS."""
    if jump_tolerance is not None:
        require("jump_tolerance", jump_tolerance, 0.0 < finite("jump_tolerance", jump_tolerance, "in (0, 1)") < 1.0,
                "in (0, 1)")
        if wear_factor != 1.0:
            raise ParameterError(f"parameter jump_tolerance={jump_tolerance!r} is invalid with wear_factor="
                                 f"{wear_factor!r}: allowed only at wear factor 1 (cycle jumping's blocks run at the "
                                 "real wear rate); a wear factor is a route of its own")
        if revolutions > MAX_JUMPED_REVOLUTIONS:
            raise ParameterError(f"parameter revolutions={revolutions!r} is invalid: allowed at most "
                                 f"{MAX_JUMPED_REVOLUTIONS:g} with cycle jumping")
        if engine == "cosim":
            raise ParameterError(f"parameter engine='cosim' is invalid with cycle jumping (jump_tolerance="
                                 f"{jump_tolerance!r}): allowed only with a wear factor instead (--wear-factor F: the "
                                 "FMU's wear profile cannot be set, so a co-simulated study cannot jump)")
        return
    simulated = revolutions / wear_factor
    if not 1.0 - 1e-9 <= simulated <= MAX_SIMULATED_REVOLUTIONS:   # at least one; a 1e-300 factor allocated 1e302
        raise ParameterError(f"--wear-factor={wear_factor!r} (wear_factor) is invalid with --revolutions {revolutions}: "
                             f"allowed {revolutions / MAX_SIMULATED_REVOLUTIONS:.3g} <= wear factor <= {revolutions} "
                             f"({simulated:.3g} simulated revolutions; from 1 to 1e6)")


def loading_from_samples(samples: np.ndarray, sample_dt_s: float) -> np.ndarray:
    """The loading rows (core.cycle_jump LOAD_* columns) of the samples in contact: eccentricity, penetration,
    normal force, relative angular velocity, tangential velocity and the time since the previous sample."""
    if samples.shape[0] == 0:
        return np.zeros((0, N_LOAD_COLUMNS))
    t = samples[:, L.T_TIME]
    duration = np.diff(t, prepend=t[0] - sample_dt_s)
    rows = np.column_stack([samples[:, L.T_ECC_X], samples[:, L.T_ECC_Y], samples[:, L.T_PENETRATION],
                            samples[:, L.T_NORMAL_FORCE], samples[:, L.T_RELATIVE_OMEGA],
                            samples[:, L.T_TANGENTIAL_VELOCITY], duration])
    return rows[samples[:, L.T_CONTACT] > 0.5]


def jump_error(jump: float, rate_before: np.ndarray, rate_after: np.ndarray, max_depth_m: float) -> float:
    """N/2 RMS(w_after - w_before) / max depth [-]: a jump's error estimate."""
    if jump <= 0 or max_depth_m <= 0.0:
        return 0.0
    return 0.5 * jump * float(np.sqrt(np.mean((rate_after - rate_before) ** 2))) / max_depth_m


def next_jump(jump: int, error: float, tolerance: float) -> int:
    """The next jump's length [revolutions] after a jump of ``jump`` with estimate ``error``."""
    lo, hi = JUMP_GROWTH
    factor = hi if error <= 0.0 else min(hi, max(lo, SAFETY * math.sqrt(tolerance / error)))
    return max(1, int(jump * factor))


def remaining_wall_s(revolution: int, total: int, block: int, proposed_jump: int, wall_per_cycle_s: float) -> float:
    """The wear study's ETA [s]: the cycles (a block and a jump) left if every next jump keeps the proposed
    jump's share q of the revolutions reached (r_{k+1} = (1 + q) r_k + block, the geometric growth the error
    control settles into), times the wall of one cycle.  The rate of revolutions done is no estimate: the
    jumps grow, so the first block's rate put 400 000 revolutions hundreds of hours away."""
    if revolution >= total:
        return 0.0
    if revolution <= 0 or proposed_jump <= 0:
        return float("nan")
    q = proposed_jump / revolution
    offset = block / q
    cycles = math.log((total + offset) / (revolution + offset)) / math.log1p(q)
    return max(cycles, 1.0) * wall_per_cycle_s


def replay_passes(jump: int, rate: np.ndarray, max_depth_m: float) -> int:
    """Passes of the replay: each wears at most PASS_INCREMENT_SHARE of the max depth by the explicit bound."""
    if max_depth_m <= 0.0:
        return 1
    return max(1, math.ceil(jump * float(rate.max()) / (PASS_INCREMENT_SHARE * max_depth_m)))


def warm_up_replay(joint) -> None:
    """Compile the replay's kernel (numba) before the study's clock starts: an empty loading replayed."""
    ClearanceJoint(joint).replay_wear(np.zeros((0, N_LOAD_COLUMNS)), 0.0)


def _next_snapshot(config, revolution: int) -> int:
    return next(s for s in config.snapshots if s > revolution)


def new_jump_state(config) -> dict:
    """The jump route's part of the study's checkpointed state."""
    return {"revolution": 0, "simulated_revolutions": 0, "simulated": [],
            "proposed_jump": FIRST_JUMP_BLOCKS * config.jump_block_revolutions, "rate": None,
            "pending_jump": None, "jumps": [], "loading": None, "block_length": 0}


def advance_jump_study(config, state: dict, engine, keep_snapshot, checkpoint, progress: bool) -> bool:
    """Blocks and jumps until ``config.revolutions`` (``state`` from :func:`new_jump_state` inside the study's
    state); ``keep_snapshot(revolution, simulated_revolutions, samples)`` at each snapshot, ``checkpoint()``
    after every block and its jump, which returns False to stop (tests).  Returns True when finished."""
    jump_state = state["jump"]
    period = config.mechanism.period_s
    sample_dt = engine.options.sample_dt_s
    buffer = np.zeros((int(period / sample_dt) + 64, L.N_SAMPLE_COLUMNS))
    replayer = ClearanceJoint(config.joint)
    bar = Progress(config.revolutions - jump_state["revolution"], "wear-study (cycle jumping)", enabled=progress,
                   unit="rev", caller_eta=True)
    done_at_start = jump_state["revolution"]
    wall0, cycles = time.perf_counter(), 0
    try:
        while jump_state["revolution"] < config.revolutions:
            _block(config, state, engine, buffer, period, sample_dt, keep_snapshot)
            _jump(config, state, engine, replayer)
            cycles += 1
            bar.update(jump_state["revolution"] - done_at_start, remaining_wall_s(
                jump_state["revolution"], config.revolutions, config.jump_block_revolutions,
                jump_state["proposed_jump"], (time.perf_counter() - wall0) / cycles))
            if not checkpoint():
                return False
    finally:
        bar.close()
    return True


def _block(config, state, engine, buffer, period, sample_dt, keep_snapshot) -> None:
    """Simulate the next block (cut short at the next snapshot), measure its rate and loading, account the
    previous jump's error and propose the next jump."""
    js = state["jump"]
    revolution = js["revolution"]
    length = min(config.jump_block_revolutions, _next_snapshot(config, revolution) - revolution)
    _, start_depth, start_volume = engine.wear_profile()
    loads, last = [], None
    for k in range(length):
        js["simulated_revolutions"] += 1
        n = engine.advance_to(js["simulated_revolutions"] * period, buffer)
        failure = divergence(engine, buffer[:n], config.joint)
        if failure:
            raise RunDiverged(failure)
        loads.append(loading_from_samples(buffer[:n], sample_dt))
        last = buffer[:n].copy()
        # the revolution this simulated one is (from 0) and the max depth at its end: revolutions.csv's rows
        js.setdefault("simulated", []).append((revolution + k, float(engine.wear_profile()[1].max())))
    _, depth, volume = engine.wear_profile()
    rate = (depth - start_depth) / length
    js["volume_rate"] = (volume - start_volume) / length
    js["revolution"] = revolution + length
    js["loading"] = np.concatenate(loads)
    js["block_length"] = length
    state["growth"].append((js["revolution"], float(depth.max()), volume))
    if js["pending_jump"] is not None and js["rate"] is not None:
        record = js["jumps"][js["pending_jump"]]
        record["error_estimate_rel"] = jump_error(record["revolutions"], js["rate"], rate, float(depth.max()))
        record["error_estimate_m"] = record["error_estimate_rel"] * float(depth.max())
        js["proposed_jump"] = next_jump(record["revolutions"], record["error_estimate_rel"], config.jump_tolerance)
        js["pending_jump"] = None
    js["rate"] = rate
    if js["revolution"] in config.snapshots:
        keep_snapshot(js["revolution"], js["simulated_revolutions"], last)


def _jump(config, state, engine, replayer) -> None:
    """Jump by the proposed length, cut so that a whole block ends at the next snapshot."""
    js = state["jump"]
    revolution = js["revolution"]
    if revolution >= config.revolutions:
        return
    gap = _next_snapshot(config, revolution) - revolution
    jump = 0 if gap <= config.jump_block_revolutions else min(js["proposed_jump"],
                                                               gap - config.jump_block_revolutions)
    if jump <= 0:
        return
    _, depth, volume_before = engine.wear_profile()
    passes = replay_passes(jump, js["rate"], float(depth.max()))
    start = time.perf_counter()
    first_block_volume = block_replay_volume(replayer, js["loading"], depth)
    replayer.set_wear_profile(depth)
    replayer.replay_wear(js["loading"], jump / js["block_length"], passes)
    radius = config.joint.bushing_radius_m
    if not replayer.wear_depth.max() < radius:
        raise RunDiverged(worn_through_message(f"in the jump from revolution {revolution} by {jump} revolutions",
                                               replayer.wear_depth.max(), radius)
                          + " (lower --wear-coefficient-m2-N or --revolutions)")
    engine.set_wear_profile(replayer.wear_depth)
    _, depth, volume = engine.wear_profile()
    # the volume a block's loading wears grows with the worn radius the points slide at (Eq. 33): the jump's
    # expected volume is the block's times the mean of that growth over the jump (linear in the depth: trapezoidal)
    growth = block_replay_volume(replayer, js["loading"], depth) / first_block_volume if first_block_volume > 0 else 1.0
    expected = js.get("volume_rate", 0.0) * jump * 0.5 * (1.0 + growth)
    js["jumps"].append({"start_revolution": revolution, "revolutions": int(jump), "passes": passes,
                        "replay_wall_time_s": time.perf_counter() - start, "error_estimate_rel": None,
                        "error_estimate_m": None, "replay_volume_growth": growth,
                        "replay_volume_ratio": (volume - volume_before) / expected if expected > 0 else None})
    js["pending_jump"] = len(js["jumps"]) - 1
    js["revolution"] = revolution + jump
    state["growth"].append((js["revolution"], float(depth.max()), volume))


def block_replay_volume(replayer, loading, depth) -> float:
    """The volume [m^3] one replay of a block's ``loading`` wears from the profile ``depth`` [m], estimated from every
    GROWTH_ROW_STRIDE-th row (the replayer is left worn by it)."""
    replayer.set_wear_profile(depth)
    before = replayer.worn_volume_m3
    replayer.replay_wear(loading[::GROWTH_ROW_STRIDE], float(GROWTH_ROW_STRIDE), 1)
    return replayer.worn_volume_m3 - before


def simulated_revolution_rows(state: dict, per: float, n: int) -> tuple:
    """(the revolution each of a study's first ``n`` simulated revolutions is, from 0, or None for 0, 1, ...; the max
    depth [m] at its end): with cycle jumping the blocks' own (unknown, NaN, from a checkpoint written before they
    were kept), at wear factor ``per`` simulated revolution i is revolutions i per .. (i + 1) per - 1."""
    if "jump" in state:
        rows = state["jump"].get("simulated", [])[:n]
        return ([r for r, _ in rows] if rows else None), [d for _, d in rows]
    return (per * np.arange(n) if per != 1.0 else None,
            [g[1] for g in state["growth"] if abs(g[0] / per - round(g[0] / per)) < 1e-9])


def jump_summary(config, state: dict) -> dict:
    """summary.json's "cycle_jumping": the settings, every jump, and the estimates."""
    js = state["jump"]
    estimates = [j["error_estimate_rel"] for j in js["jumps"] if j["error_estimate_rel"] is not None]
    ratios = [j["replay_volume_ratio"] for j in js["jumps"] if j.get("replay_volume_ratio") is not None]
    depth = state["growth"][-1][1] if state["growth"] else 0.0
    summed = sum(j["error_estimate_m"] for j in js["jumps"] if j["error_estimate_rel"] is not None)
    return {"tolerance_rel": config.jump_tolerance, "block_revolutions": config.jump_block_revolutions,
            "simulated_revolutions": js["simulated_revolutions"], "jumps": len(js["jumps"]),
            "jumped_revolutions": int(sum(j["revolutions"] for j in js["jumps"])),
            "largest_jump_revolutions": max((j["revolutions"] for j in js["jumps"]), default=0),
            "largest_error_estimate_rel": max(estimates, default=0.0),
            "jumps_over_tolerance": [j["start_revolution"] for j in js["jumps"]
                                     if j["error_estimate_rel"] is not None
                                     and j["error_estimate_rel"] > config.jump_tolerance],
            "error_estimate_summed_rel_to_final_depth": float(summed / depth) if depth > 0.0 else 0.0,
            "replay_volume_ratio_range": [min(ratios), max(ratios)] if ratios else None,
            "replay_volume_ratio_allowed": [1.0 - REPLAY_VOLUME_TOLERANCE, 1.0 + REPLAY_VOLUME_TOLERANCE],
            "replay_volume_outside": [j["start_revolution"] for j in js["jumps"]
                                      if j.get("replay_volume_ratio") is not None
                                      and abs(j["replay_volume_ratio"] - 1.0) > REPLAY_VOLUME_TOLERANCE],
            "jump_history": js["jumps"]}


def replay_volume_warning(cycle_jumping: dict) -> str | None:
    """One line where a jump's replayed volume left the allowed band (summary.json's ``cycle_jumping``), else None."""
    outside = cycle_jumping.get("replay_volume_outside") or []
    if not outside:
        return None
    low, high = cycle_jumping["replay_volume_ratio_range"]
    allowed_low, allowed_high = cycle_jumping["replay_volume_ratio_allowed"]
    return (f"{len(outside)} jump(s) (from revolution {outside[0]}) replayed {low:.3g}-{high:.3g} of their blocks' "
            f"volume, outside {allowed_low:g}-{allowed_high:g}: their wear is not the blocks' (docs/explanation/wear_study.md); "
            "check against --cycle-jump-tolerance 0.001 or a --convergence jump,1 study")


__all__ = ["DEFAULT_JUMP_TOLERANCE", "REPLAY_VOLUME_TOLERANCE", "warm_up_replay", "loading_from_samples",
           "jump_error", "next_jump", "replay_passes", "replay_volume_warning", "block_replay_volume",
           "new_jump_state", "advance_jump_study", "jump_summary", "simulated_revolution_rows"]
