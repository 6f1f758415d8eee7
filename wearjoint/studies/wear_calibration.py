"""The calibration of an effective k_w to a target depth on the wear study
(:mod:`wearjoint.studies.wear_study`, ``wearjoint wear-study --calibrate-max-depth-m``); the
convergence of the wear acceleration factor is :mod:`wearjoint.studies.wear_convergence`."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from wearjoint.checks import integer, is_real, require
from wearjoint.core import layout as L
from wearjoint.joint_fields import largest_value
from wearjoint.report import write_report
from wearjoint.results import write_json_atomic
from wearjoint.simulation_options import DEFAULT_WEAR_STEP_SHARE, wear_step_limit_s
from wearjoint.studies.calibration import MAX_BUSHING_RADIUS_M, MIN_DEPTH_M
from wearjoint.studies.wear_study import (
    CHECKPOINT_NAME, PRINTED_WEAR_COEFFICIENT_M2_N, WearStudyConfig, make_engine,
    run_wear_study,
)


# ----------------------------------------------------------------------------- calibration
# the shallowest target [m]: calibration.MIN_DEPTH_M, a nanometre, a few atomic layers, far below a bushing's roughness
# (0.1-1 um) and any measured wear (the secant itself resolves far less: 1e-15 m in 2 revolutions, while 1e-300 wore
# exactly nothing and divided by it)
MIN_TARGET_DEPTH_M = MIN_DEPTH_M
# the largest k_w a trial may take [m^2/N] (the joint's own bound, JointParameters.wear_coefficient_m2_N)
MAX_WEAR_COEFFICIENT_M2_N = largest_value("wear_coefficient_m2_N")


def check_target_depth(target_max_depth_m, bushing_radius_m: float | None = None) -> float:
    """``target_max_depth_m`` as a float where it is a finite depth [m] from :data:`MIN_TARGET_DEPTH_M` to below
    ``bushing_radius_m`` (the bushing wears through there; None: the largest radius the joint admits), else the
    ParameterError naming it."""
    require("target_max_depth_m", target_max_depth_m,
            is_real(target_max_depth_m) and math.isfinite(target_max_depth_m) and target_max_depth_m > 0.0,
            "a finite depth > 0 m")
    require("target_max_depth_m", target_max_depth_m, target_max_depth_m >= MIN_TARGET_DEPTH_M,
            f"a depth of at least {MIN_TARGET_DEPTH_M:g} m (a few atomic layers: the least wear Archard's law describes)")
    radius = MAX_BUSHING_RADIUS_M if bushing_radius_m is None else bushing_radius_m
    require("target_max_depth_m", target_max_depth_m, target_max_depth_m < radius,
            f"a depth below the bushing radius {radius:g} m (the bushing wears through there)"
            if bushing_radius_m is not None else f"a depth below the bushing radius (at most {radius:g} m)")
    return float(target_max_depth_m)


def printed_wear_rate(config: WearStudyConfig, simulated_revolutions: int = 3) -> dict:
    """Max depth after each of the first revolutions with the printed k_w and no acceleration (F = 1)."""
    joint = config.joint.replace(wear_coefficient_m2_N=PRINTED_WEAR_COEFFICIENT_M2_N, wear_factor=1.0)
    cfg = config.replace(joint=joint, revolutions=simulated_revolutions, snapshots=(simulated_revolutions,),
                         jump_tolerance=None)
    engine = make_engine(cfg)
    period = config.mechanism.period_s
    buffer = np.zeros((int(period / 1e-5) + 64, L.N_SAMPLE_COLUMNS))
    depths = []
    for k in range(1, simulated_revolutions + 1):
        engine.advance_to(k * period, buffer)
        depths.append(float(engine.wear_profile()[1].max()))
    return {"rho_mode": joint.rho_mode, "wear_coefficient_m2_N": PRINTED_WEAR_COEFFICIENT_M2_N,
            "max_depth_after_revolution_m": depths, "mean_depth_per_revolution_m": depths[-1] / simulated_revolutions}


def calibrate_wear_coefficient(config: WearStudyConfig, target_max_depth_m: float, out_dir, resume: bool = False,
                               progress: bool = True, rel_tolerance: float = 0.05, max_trials: int = 6,
                               command_line: str | None = None) -> dict:
    """Effective k_w whose study (same acceleration, ``config.revolutions``) ends at the target max depth.

    Start: linear extrapolation of the printed-k_w rate over the first revolutions; then a secant
    on log(depth) vs log(k_w) (depth grows monotonically with k_w), slope clipped to [0.3, 3],
    until |depth/target - 1| <= rel_tolerance.  Every trial is a full study in out_dir/trial_<i>, whose
    summary.json and report name ``command_line`` (the CLI's) with the trial and its k_w.
    """
    target_max_depth_m = check_target_depth(target_max_depth_m, config.joint.bushing_radius_m)
    require("rel_tolerance", rel_tolerance, is_real(rel_tolerance) and 0.0 < rel_tolerance < 1.0, "in (0, 1)")
    max_trials = integer("max_trials", max_trials, 1)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rate = printed_wear_rate(config)
    k = PRINTED_WEAR_COEFFICIENT_M2_N * target_max_depth_m / (rate["mean_depth_per_revolution_m"] * config.revolutions)
    trials = []
    for i in range(max_trials):
        k = min(k, MAX_WEAR_COEFFICIENT_M2_N)
        joint = config.joint.replace(wear_coefficient_m2_N=k)     # a faster wear takes the shorter step it needs
        step = min(config.max_step_s, wear_step_limit_s(joint, config.mechanism, DEFAULT_WEAR_STEP_SHARE))
        cfg = config.replace(joint=joint, snapshots=(config.revolutions,), max_step_s=step)
        sub = out / f"trial_{i}"
        made_by = None if command_line is None else f"{command_line} (its trial {i}: k_w {k:.6g} m^2/N)"
        summary = run_wear_study(cfg, sub, resume=resume and (sub / CHECKPOINT_NAME).exists(), progress=progress,
                                 plots=False, command_line=made_by)
        if made_by is not None:
            write_report(sub, made_by)
        depth = summary["max_wear_depth_m"]
        trials.append({"wear_coefficient_m2_N": k, "max_wear_depth_m": depth, "wall_time_s": summary["wall_time_s"]})
        if abs(depth / target_max_depth_m - 1.0) <= rel_tolerance:
            break
        unreachable(target_max_depth_m, k, depth, config.revolutions, rel_tolerance)
        if len(trials) == 1:
            slope = 1.0
        else:
            a, b = trials[-2], trials[-1]
            slope = (math.log(b["max_wear_depth_m"] / a["max_wear_depth_m"])
                     / math.log(b["wear_coefficient_m2_N"] / a["wear_coefficient_m2_N"]))
            slope = min(3.0, max(0.3, slope)) if math.isfinite(slope) else 1.0
        k = k * (target_max_depth_m / depth) ** (1.0 / slope)
    best = min(trials, key=lambda t: abs(t["max_wear_depth_m"] / target_max_depth_m - 1.0))
    result = {"rho_mode": config.joint.rho_mode, "target_max_depth_m": target_max_depth_m,
              "revolutions": config.revolutions, "wear_factor": config.joint.wear_factor,
              "printed_wear_coefficient_m2_N": PRINTED_WEAR_COEFFICIENT_M2_N, "printed_rate": rate,
              "effective_wear_coefficient_m2_N": best["wear_coefficient_m2_N"],
              "ratio_to_printed": best["wear_coefficient_m2_N"] / PRINTED_WEAR_COEFFICIENT_M2_N,
              "reached_max_depth_m": best["max_wear_depth_m"],
              "converged": abs(best["max_wear_depth_m"] / target_max_depth_m - 1.0) <= rel_tolerance,
              "rel_tolerance": rel_tolerance, "trials": trials,
              "method": "log-secant on k_w, each trial a full accelerated study"}
    write_json_atomic(out / "calibration.json", result)
    return result


def unreachable(target_max_depth_m: float, k: float, depth: float, revolutions, rel_tolerance: float) -> None:
    """The ParameterError naming the target where a trial at the largest k_w the joint admits wore less than it."""
    if k >= MAX_WEAR_COEFFICIENT_M2_N and depth < target_max_depth_m * (1.0 - rel_tolerance):
        require("target_max_depth_m", target_max_depth_m, False,
                f"a depth the study reaches with k_w at most {MAX_WEAR_COEFFICIENT_M2_N:g} m2/N: {depth:.4g} m after "
                f"{revolutions:g} revolution{'s' if revolutions != 1 else ''} (more revolutions wear deeper)")


__all__ = ["printed_wear_rate", "calibrate_wear_coefficient", "check_target_depth", "MIN_TARGET_DEPTH_M"]
