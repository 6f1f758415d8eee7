"""Studies built on the wear study (:mod:`wearjoint.validation.wear_study`): the
convergence of the wear acceleration factor (``wearjoint wear-study --convergence``)
and the calibration of an effective k_w to a target depth (``--calibrate-max-depth-m``)."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from wearjoint.analysis import profile_convergence
from wearjoint.core import layout as L
from wearjoint.parameters import ParameterError
from wearjoint.results import write_json_atomic
from wearjoint.validation.wear_study import (
    CHECKPOINT_NAME, CONVERGENCE_TOLERANCE, PRINTED_WEAR_COEFFICIENT_M2_N, WearStudyConfig, make_engine,
    profile_angles_deg, run_wear_study,
)


# ----------------------------------------------------------------------------- convergence
def run_convergence(config: WearStudyConfig, factors, out_dir, resume: bool = False, progress: bool = True,
                    tolerance: float = CONVERGENCE_TOLERANCE) -> dict:
    """Run the study once per acceleration factor (the first is the reference, normally 1) and a
    repeat of the reference with the other integrator (the chaotic scatter between valid runs);
    compare the profiles at the matched snapshots.  Writes convergence.csv/json/png into out_dir."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    factors = [float(f) for f in factors]
    other = "rk4" if config.integrator == "dopri" else "dopri"
    runs = {f"F={f:g}": config.replace(joint=config.joint.replace(wear_factor=f), jump_tolerance=None) for f in factors}
    runs[f"F={factors[0]:g} {other}"] = runs[f"F={factors[0]:g}"].replace(integrator=other)
    folders = {label: out / label.replace("=", "").replace(" ", "_") for label in runs}
    results = {label: run_wear_study(cfg, folders[label], resume=resume or (folders[label] / CHECKPOINT_NAME).exists(),
                                     progress=progress, plots=False)
               for label, cfg in runs.items()}
    phi_deg = profile_angles_deg(config.joint.n_points)
    profiles = {label: {s: _read_profile(folders[label] / f"profile_rev{s}.csv") for s in config.snapshots}
                for label in runs}
    reference = f"F={factors[0]:g}"
    rows = []
    for label in runs:
        for s in config.snapshots:
            ref, h = profiles[reference][s], profiles[label][s]
            rows.append({"run": label, "revolution": s, "max_wear_depth_m": float(h.max()),
                         "reference_max_wear_depth_m": float(ref.max()), **profile_convergence(h, ref),
                         "wall_time_s": results[label]["wall_time_s"]})
    verdict = {}
    for label in runs:
        mine = [r for r in rows if r["run"] == label]
        verdict[label] = bool(all(abs(r["max_depth_rel_diff"]) <= tolerance and r["rms_profile_diff_rel"] <= tolerance
                                  for r in mine))
    passing = [f for f in factors if verdict[f"F={f:g}"]]
    with open(out / "convergence.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    summary = {"reference": reference, "scatter_run": f"{reference} {other}", "tolerance_rel": tolerance,
               "criterion": "at every matched revolution count: |max depth / reference - 1| <= tol and "
                            "RMS(profile - reference) / reference max depth <= tol",
               "within_tolerance": verdict, "largest_factor_within_tolerance": max(passing) if passing else None,
               "rows": rows, "parameters": config.to_dict()}
    from wearjoint.plots import plot_wear_profiles
    last = config.snapshots[-1]
    plot_wear_profiles(phi_deg, {label: profiles[label][last] for label in runs}, out / "convergence_profiles.png",
                       title=f"acceleration factors at matched revolutions ({last} rev)")
    _plot_convergence_growth(out, folders)
    summary["figures"] = ["convergence_profiles.png", "convergence_growth.png"]
    write_json_atomic(out / "convergence.json", summary)
    return summary


def _read_profile(path: Path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1)[:, 1]


def _plot_convergence_growth(out: Path, folders: dict) -> None:
    from wearjoint.plots import plt, save_figure

    fig, ax = plt.subplots(figsize=(7, 4.2))
    for label, folder in folders.items():
        g = np.loadtxt(folder / "wear_growth.csv", delimiter=",", skiprows=1, ndmin=2)
        ax.plot(g[:, 0], g[:, 1] * 1e6, ".-" if len(g) < 40 else "-", ms=3, label=label)
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [µm]")
    ax.set_title("max depth vs revolutions for each acceleration factor", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, out / "convergence_growth.png")


# ----------------------------------------------------------------------------- calibration
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
                               progress: bool = True, rel_tolerance: float = 0.05, max_trials: int = 6) -> dict:
    """Effective k_w whose study (same acceleration, ``config.revolutions``) ends at the target max depth.

    Start: linear extrapolation of the printed-k_w rate over the first revolutions; then a secant
    on log(depth) vs log(k_w) (depth grows monotonically with k_w), slope clipped to [0.3, 3],
    until |depth/target - 1| <= rel_tolerance.  Every trial is a full study in out_dir/trial_<i>.
    """
    if not (math.isfinite(target_max_depth_m) and target_max_depth_m > 0.0):
        raise ParameterError(f"target max depth {target_max_depth_m!r} m is invalid: allowed > 0")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rate = printed_wear_rate(config)
    k = PRINTED_WEAR_COEFFICIENT_M2_N * target_max_depth_m / (rate["mean_depth_per_revolution_m"] * config.revolutions)
    trials = []
    for i in range(max_trials):
        cfg = config.replace(joint=config.joint.replace(wear_coefficient_m2_N=k), snapshots=(config.revolutions,))
        sub = out / f"trial_{i}"
        summary = run_wear_study(cfg, sub, resume=resume and (sub / CHECKPOINT_NAME).exists(), progress=progress,
                                 plots=False)
        depth = summary["max_wear_depth_m"]
        trials.append({"wear_coefficient_m2_N": k, "max_wear_depth_m": depth, "wall_time_s": summary["wall_time_s"]})
        if abs(depth / target_max_depth_m - 1.0) <= rel_tolerance:
            break
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


__all__ = ["run_convergence", "printed_wear_rate", "calibrate_wear_coefficient"]
