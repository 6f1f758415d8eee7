"""The convergence of the wear acceleration factor (``wearjoint wear-study --convergence F1,F2,...``): one
wear study (:mod:`wearjoint.studies.wear_study`) per factor given, exactly those, the first the reference
(normally 1), compared at the matched snapshots.  ``jump`` in the list stands for the default route
(error-controlled cycle jumping, within about 1 % of brute force on the paper's case, its own error estimate in
its summary): ``--convergence jump,100`` measures F = 100's bias for any mechanism and horizon at a fraction of
brute force's cost.  A run that diverges is marked (its message in
convergence.json, its rows "diverged"); the others and the table of what finished are written all the same.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from wearjoint.profile_metrics import profile_convergence
from wearjoint.parameters import ParameterError
from wearjoint.results import write_json_atomic

from .wear_study import CHECKPOINT_NAME, CONVERGENCE_TOLERANCE, WearStudyConfig, profile_angles_deg, run_wear_study
from .cycle_jump import DEFAULT_JUMP_TOLERANCE
from .wear_study_recovery import StudyDiverged

JUMP = "jump"                   # the cycle-jumping route in a --convergence list
ROW_KEYS = ("run", "status", "revolution", "max_wear_depth_m", "reference_max_wear_depth_m", "max_depth_rel_diff",
            "rms_profile_diff_rel", "wall_time_s")


def convergence_runs(config: WearStudyConfig, factors) -> dict:
    """label -> the study of each factor (the wear-factor route; a step left at its default is the default of
    each factor's wear: the wear-step limit falls with the factor) or of :data:`JUMP` (the cycle-jumping route
    at wear factor 1 with ``config``'s tolerance, or the default one).  Every config is validated here, before
    any run: a factor that leaves less than one simulated revolution is refused in one line."""
    factors = [f if f == JUMP else float(f) for f in factors]
    if not factors:
        raise ParameterError(f"--convergence: no factor given (expected e.g. 1,10,50 or {JUMP},100)")
    if len(set(factors)) != len(factors):
        raise ParameterError(f"--convergence: {','.join(_label_text(f) for f in factors)} repeats one: allowed "
                             "distinct factors")
    default_step = config.max_step_s == config.replace(max_step_s=None).max_step_s
    step = {"max_step_s": None} if default_step else {}
    runs = {}
    for f in factors:
        try:
            if f == JUMP:
                runs[JUMP] = config.replace(joint=config.joint.replace(wear_factor=1.0),
                                            jump_tolerance=config.jump_tolerance or DEFAULT_JUMP_TOLERANCE, **step)
            else:
                runs[f"F={f:g}"] = config.replace(joint=config.joint.replace(wear_factor=f), jump_tolerance=None,
                                                  **step)
        except ParameterError as exc:
            raise ParameterError(f"--convergence: factor {_label_text(f)}: {exc}") from None
    return runs


def _label_text(factor) -> str:
    return factor if factor == JUMP else f"{factor:g}"


def run_convergence(config: WearStudyConfig, factors, out_dir, resume: bool = False, progress: bool = True,
                    tolerance: float = CONVERGENCE_TOLERANCE) -> dict:
    """Run the study once per factor in ``factors`` (the first is the reference) and compare the profiles at
    the matched snapshots.  Writes convergence.csv/json/png into out_dir (each run in out_dir/F<f>)."""
    out = Path(out_dir)
    runs = convergence_runs(config, factors)
    out.mkdir(parents=True, exist_ok=True)
    folders = {label: out / label.replace("=", "") for label in runs}
    results, diverged = {}, {}
    for label, cfg in runs.items():
        try:
            results[label] = run_wear_study(cfg, folders[label], progress=progress, plots=False,
                                            resume=resume or (folders[label] / CHECKPOINT_NAME).exists())
        except StudyDiverged as exc:
            results[label], diverged[label] = exc.summary, str(exc)
    reference = next(iter(runs))
    profiles = {label: {s: _read_profile(folders[label] / f"profile_rev{s}.csv") for s in config.snapshots}
                for label in runs}
    rows = []
    for label in runs:
        for s, h in profiles[label].items():
            if h is None:
                continue
            ref = profiles[reference][s]
            compared = profile_convergence(h, ref) if ref is not None else {"max_depth_rel_diff": None,
                                                                            "rms_profile_diff_rel": None}
            rows.append({"run": label, "status": "diverged" if label in diverged else "finished", "revolution": s,
                         "max_wear_depth_m": float(h.max()),
                         "reference_max_wear_depth_m": float(ref.max()) if ref is not None else None, **compared,
                         "wall_time_s": results[label]["wall_time_s"]})
    verdict = {}
    for label in runs:
        mine = [r for r in rows if r["run"] == label]
        comparable = reference not in diverged and label not in diverged and len(mine) == len(config.snapshots)
        verdict[label] = (bool(all(abs(r["max_depth_rel_diff"]) <= tolerance and r["rms_profile_diff_rel"] <= tolerance
                                   for r in mine)) if comparable else None)
    passing = [cfg.joint.wear_factor for label, cfg in runs.items() if verdict[label] and label != JUMP]
    with open(out / "convergence.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(ROW_KEYS))
        writer.writeheader()
        writer.writerows(rows)
    summary = {"reference": reference, "tolerance_rel": tolerance,
               "criterion": "at every matched revolution count: |max depth / reference - 1| <= tol and "
                            "RMS(profile - reference) / reference max depth <= tol",
               "runs": {label: "diverged" if label in diverged else "finished" for label in runs},
               "diverged": diverged, "within_tolerance": verdict,
               "largest_factor_within_tolerance": max(passing) if passing else None,
               "rows": rows, "parameters": config.to_dict()}
    if reference == JUMP and reference not in diverged:
        summary["reference_error_estimate_rel"] = \
            results[JUMP]["cycle_jumping"]["error_estimate_summed_rel_to_final_depth"]
    summary["figures"] = _plot(out, folders, profiles, config)
    write_json_atomic(out / "convergence.json", summary)
    return summary


def _read_profile(path: Path) -> np.ndarray | None:
    return np.loadtxt(path, delimiter=",", skiprows=1)[:, 1] if path.is_file() else None


def _plot(out: Path, folders: dict, profiles: dict, config: WearStudyConfig) -> list:
    from wearjoint.plots import plot_wear_profiles, plt, save_figure

    last = config.snapshots[-1]
    reached = {label: p[last] for label, p in profiles.items() if p[last] is not None}
    figures = []
    if reached:
        plot_wear_profiles(profile_angles_deg(config.joint.n_points), reached, out / "convergence_profiles.png",
                           config.mechanism.clearance_joint,
                           title=f"acceleration factors at matched revolutions ({last} rev)")
        figures.append("convergence_profiles.png")
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for label, folder in folders.items():
        if (folder / "wear_growth.csv").is_file():
            g = np.loadtxt(folder / "wear_growth.csv", delimiter=",", skiprows=1, ndmin=2)
            if len(g):
                ax.plot(g[:, 0], g[:, 1] * 1e6, ".-" if len(g) < 40 else "-", ms=3, label=label)
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [µm]")
    ax.set_title("max depth vs revolutions for each acceleration factor", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save_figure(fig, out / "convergence_growth.png")
    return figures + ["convergence_growth.png"]


__all__ = ["run_convergence", "convergence_runs", "JUMP"]
