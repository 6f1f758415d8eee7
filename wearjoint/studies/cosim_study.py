"""Co-simulation error versus communication step and coupling scheme.

The reference is the monolithic run of the same model (``wearjoint.simulate``,
adaptive Dormand-Prince).  The motion is chaotic, so the co-simulation is
judged like any other valid integration: per-revolution statistics (impacts,
contact fraction, slider acceleration extremes, max contact force, max
eccentricity) and the worn profile after a few revolutions (reduced
wear_factor) must differ from the reference by no more than equally valid
monolithic runs differ from it (RK4 1 us, DOPRI at a tighter tolerance);
pointwise agreement is checked only over the first 15 ms (of the paper's 0.4 s crank period).

    wearjoint cosim-study --out DIR [--revolutions 2] [--steps ...] [--fmu PATH] [--fmu-backend B] [model options]

Any slider-crank and joint (the model options of ``simulate``): the default steps are the paper's
1, 2, 5 and 10 us scaled by the communication-step rule (:func:`wearjoint.cosim.step_rule.paper_step_scale`)
and the point-wise window is the paper's 15 ms scaled with the crank period.

Writes ``cosim_study.md`` (the table), ``cosim_study.json`` and ``cosim_study.png``; a co-simulation that failed or
diverged is a row that says so, without numbers.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from wearjoint import analysis, profile_metrics
from wearjoint.core import layout as L
from wearjoint.checks import RunDiverged
from wearjoint.cosim import CoSimulationError, CoSimulationOptions, run_cosimulation
from wearjoint.fmu.fmi import DEFAULT_BACKEND
from wearjoint.cosim.step_rule import paper_step_scale
from wearjoint.parameters import JointParameters, SliderCrankParameters, paper_joint
from wearjoint.results import RunRecord
from wearjoint.simulate import SimulationOptions, run_simulation
from wearjoint.simulation_options import check_run_arguments, check_wear_step

POINTWISE_WINDOW_S = 0.015     # on the paper's mechanism (a 0.4 s crank period); scaled with the period
PAPER_STEPS_S = (1e-6, 2e-6, 5e-6, 1e-5)
WEAR_FACTOR = 0.01          # reduced wear: ~0.4 um per revolution, no effect on the dynamics
COMMUNICATION_KEYS = ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s")   # a co-simulation's
STATISTICS = (              # (key, wearjoint.analysis.mean_revolution_statistics key, label)
    ("impacts", "impacts_per_revolution", "impacts / rev"),
    ("contact_fraction", "contact_fraction", "contact fraction"),
    ("acc_max", "slider_acc_max_m_s2", "slider acc. max [m/s^2]"),
    ("acc_min", "slider_acc_min_m_s2", "slider acc. min [m/s^2]"),
    ("force_max", "max_contact_force_N", "max contact force [N]"),
    ("ecc_max", "max_eccentricity_m", "max eccentricity [m]"),
)


def revolution_statistics(record: RunRecord) -> dict:
    """Each statistic of STATISTICS, averaged over the revolutions
    (:func:`wearjoint.analysis.mean_revolution_statistics`)."""
    stats = analysis.mean_revolution_statistics(record.revolution_stats, record.period_s)
    return {key: stats[name] for key, name, _ in STATISTICS}


def pointwise_window_s(mechanism: SliderCrankParameters) -> float:
    """The point-wise window [s]: POINTWISE_WINDOW_S of the paper's crank period, scaled with this one's."""
    return POINTWISE_WINDOW_S * mechanism.period_s / SliderCrankParameters().period_s


def default_steps_s(joint: JointParameters, mechanism: SliderCrankParameters) -> list:
    """PAPER_STEPS_S scaled by the communication-step rule for ``joint`` in ``mechanism``."""
    scale = paper_step_scale(joint, mechanism)
    return [float(f"{step * scale:.3g}") for step in PAPER_STEPS_S]


def pointwise_deviation(record: RunRecord, reference: RunRecord, window_s: float = POINTWISE_WINDOW_S) -> dict:
    """Max |difference| over the first ``window_s`` of slider position [m] and
    eccentricity [m], at the record's own sample times (the reference interpolated there)."""
    keys = {"slider_x_m": L.T_SLIDER_X, "eccentricity_x_m": L.T_ECC_X, "eccentricity_y_m": L.T_ECC_Y}
    d = analysis.window_differences(record.samples, reference.samples, window_s, keys.values())
    return {key: float(np.max(np.abs(d[:, k]))) for k, key in enumerate(keys)}


def compare(record: RunRecord, reference: RunRecord, window_s: float = POINTWISE_WINDOW_S) -> dict:
    """Deviation of ``record`` from ``reference``: relative per statistic, pointwise over ``window_s``, profile."""
    stats, ref = revolution_statistics(record), revolution_statistics(reference)
    out = {f"{k}_rel": abs(stats[k] - ref[k]) / max(abs(ref[k]), 1e-300) for k in stats}
    out.update({f"pointwise_{k}": v for k, v in pointwise_deviation(record, reference, window_s).items()})
    out["profile_rel"] = profile_metrics.profile_relative_l2(record.wear_depth_m, reference.wear_depth_m)
    out["statistics"] = stats
    return out


def study_plan(revolutions: float, steps, schemes, fmu_path=None, joint: JointParameters | None = None,
               mechanism: SliderCrankParameters | None = None) -> dict:
    """The study's model (``joint`` at WEAR_FACTOR in ``mechanism``, defaults: the paper's), its steps (None:
    :func:`default_steps_s`), co-simulations' options and FMU, checked before any run: ParameterError naming the
    first bad value (a step ``step_s``, within the wear-step limit; a scheme ``scheme``; the FMU ``fmu_path``)."""
    mechanism = mechanism or SliderCrankParameters()
    joint = (joint or paper_joint(mechanism)).replace(wear_factor=WEAR_FACTOR)
    steps = default_steps_s(joint, mechanism) if steps is None else list(steps)
    cosims = [CoSimulationOptions(revolutions=revolutions, scheme=scheme, step_s=step,
                                  max_step_s=max(step, CoSimulationOptions.max_step_s))
              for scheme in schemes for step in steps]
    for options in cosims[:len(steps)]:
        check_wear_step("step_s", options.step_s, joint, mechanism)
    check_run_arguments(joint, mechanism, None, CoSimulationOptions, fmu_path)   # a given FMU is an FMU file
    return {"joint": joint, "mechanism": mechanism, "steps": steps, "cosims": cosims, "fmu_path": fmu_path}


def run_study(revolutions: float, steps, schemes, fmu_path=None, log=print,
              fmu_backend: str = DEFAULT_BACKEND, joint: JointParameters | None = None,
              mechanism: SliderCrankParameters | None = None) -> dict:
    """All runs and their comparison (see module docstring) for ``joint`` (its wear factor set to WEAR_FACTOR)
    in ``mechanism`` (defaults: the paper's); ``steps`` None: :func:`default_steps_s`.  Every value is checked
    before any run (:func:`study_plan`).  A co-simulation that failed or diverged is a row with ``completed``
    false and ``failed`` (why), without numbers; a monolithic run that diverged leaves nothing to compare with:
    RunDiverged."""
    plan = study_plan(revolutions, steps, schemes, fmu_path, joint, mechanism)
    joint, mechanism, steps, fmu_path = plan["joint"], plan["mechanism"], plan["steps"], plan["fmu_path"]
    window = pointwise_window_s(mechanism)
    monolithic = {
        "dopri (reference)": SimulationOptions(revolutions=revolutions, integrator="dopri", max_step_s=1e-5),
        "rk4 1 us": SimulationOptions(revolutions=revolutions, integrator="rk4", step_s=1e-6),
        "dopri rtol 1e-7": SimulationOptions(revolutions=revolutions, integrator="dopri", max_step_s=1e-5, rtol=1e-7),
    }
    records = {}
    for name, options in monolithic.items():
        records[name] = run_simulation(joint, mechanism, options, progress=False)
        if records[name].failure:
            raise RunDiverged(f"the monolithic run {name} failed, so the study has nothing to compare with: "
                              f"{records[name].failure}")
        log(f"monolithic {name}: {records[name].wall_time_s:.1f} s")
    reference = records["dopri (reference)"]
    rows = []
    for name in list(monolithic)[1:]:
        rows.append({"engine": "monolithic", "run": name, "completed": True, "wall_time_s": records[name].wall_time_s,
                     "realtime_factor": records[name].summary()["realtime_factor"],
                     **compare(records[name], reference, window)})
    scatter = {k: max(r[k] for r in rows) for k in rows[0] if k.endswith("_rel") or k.startswith("pointwise_")}
    for options in plan["cosims"]:
        run = {"engine": "cosim", "run": f"{options.scheme} {options.step_s:g}", "scheme": options.scheme,
               "step_s": options.step_s}
        try:
            record = run_cosimulation(joint, mechanism, options, fmu_path=fmu_path, progress=False,
                                      fmu_backend=fmu_backend)
            failure = record.failure
        except CoSimulationError as exc:
            failure = str(exc)
        if failure:
            log(f"cosim {run['run']}: failed ({failure})")
            rows.append({**run, "completed": False, "failed": failure})
            continue
        rows.append({**run, "completed": True, "wall_time_s": record.wall_time_s,
                     "realtime_factor": record.summary()["realtime_factor"],
                     **{k: record.extra[k] for k in COMMUNICATION_KEYS},
                     **compare(record, reference, window)})
        log(f"cosim {run['run']}: {record.wall_time_s:.1f} s")
    return {"revolutions": revolutions, "wear_factor": WEAR_FACTOR, "pointwise_window_s": window,
            "fmu_backend": fmu_backend, "steps_s": steps,
            "parameters": {"joint": joint.to_dict(), "mechanism": mechanism.to_dict()},
            "reference": revolution_statistics(reference), "scatter": scatter, "rows": rows}


def failed_runs(study: dict) -> list[dict]:
    """The rows of the study's runs that failed or diverged (no numbers of theirs in the table)."""
    return [r for r in study["rows"] if "failed" in r]


def markdown_table(study: dict) -> str:
    """The study as a markdown table: relative deviations from the monolithic reference."""
    keys = [f"{k}_rel" for k, _, _ in STATISTICS] + ["profile_rel"]
    head = ["run", "comm. steps", "rollbacks", "real-time factor"] + [k[:-4] for k in keys] + \
           [f"slider x, {study['pointwise_window_s'] * 1e3:.3g} ms [m]", "inside scatter"]
    scatter = study["scatter"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in study["rows"]:
        if "failed" in r:
            lines.append(f"| cosim {r['run']} | failed, no results: {r['failed'].split(';')[0]} |"
                         + " |" * (len(head) - 2))
            continue
        cells = [f"{r['engine']} {r['run']}", str(r.get("communication_steps", "")), str(r.get("rollbacks", "")),
                 f"{r['realtime_factor']:.3g}"]
        cells += [f"{r[k]:.3f}" for k in keys]
        inside = "-" if r["engine"] == "monolithic" else \
            f"{sum(r[k] <= scatter[k] for k in keys)}/{len(keys)}"
        cells += [f"{r['pointwise_slider_x_m']:.2e}", inside]
        lines.append("| " + " | ".join(cells) + " |")
    s = study["scatter"]
    lines.append("| **monolithic scatter** | | | | " + " | ".join(f"{s[k]:.3f}" for k in keys)
                 + f" | {s['pointwise_slider_x_m']:.2e} | |")
    ref = study["reference"]
    lines.append("")
    lines.append(f"Deviations are relative to the monolithic reference (DOPRI, max step 1e-5 s) over "
                 f"{study['revolutions']:g} revolutions, wear_factor {study['wear_factor']:g}; reference means per "
                 "revolution: " + ", ".join(f"{k} {v:.4g}" for k, v in ref.items()) + ".  "
                 "'inside scatter': how many of the relative deviations are <= the largest deviation of "
                 "the other monolithic runs (RK4 1 us, DOPRI rtol 1e-7).")
    return "\n".join(lines) + "\n"


def plot_study(study: dict, path: Path) -> None:
    from wearjoint.plots import plt, save_figure

    keys = [(f"{k}_rel", label) for k, _, label in STATISTICS] + [("profile_rel", "worn profile (L2)")]
    fig, axes = plt.subplots(2, 4, figsize=(15, 7))
    rows = [r for r in study["rows"] if r["engine"] == "cosim" and "failed" not in r]
    schemes = sorted({r["scheme"] for r in rows})
    for ax, (key, label) in zip(axes.flat, keys + [("realtime_factor", "real-time factor")]):
        for scheme in schemes:
            rs = sorted((r for r in rows if r["scheme"] == scheme), key=lambda r: r["step_s"])
            ax.loglog([r["step_s"] for r in rs], [max(r[key], 1e-6) for r in rs], "o-", label=scheme)
        if key in study["scatter"]:
            ax.axhline(study["scatter"][key], color="k", ls="--", label="monolithic scatter")
        ax.set_title(label if key == "realtime_factor" else f"rel. deviation: {label}", fontsize=9)
        ax.set_xlabel("communication step [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    save_figure(fig, path, dpi=110)


def write_study(study: dict, out: Path) -> str:
    """cosim_study.json, cosim_study.md and cosim_study.png into ``out``; returns the table."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "cosim_study.json").write_text(json.dumps(study, indent=2, default=str))
    table = markdown_table(study)
    (out / "cosim_study.md").write_text(table)
    plot_study(study, out / "cosim_study.png")
    return table

