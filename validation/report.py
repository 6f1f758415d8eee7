"""The outputs of `wearjoint validate` (:mod:`wearjoint.validation.compare`): the PNG
overlays, ``summary.json`` and ``report.md``."""
from __future__ import annotations

import math
from dataclasses import asdict
from pathlib import Path

import numpy as np

from wearjoint.core import layout as L
from wearjoint.parameters import JointParameters, SliderCrankParameters
from wearjoint.results import RunRecord, write_json_atomic
from wearjoint.validation.compare import (
    compare, run_engines,
    GROUP_POINTWISE, GROUP_PROFILE, GROUP_STATISTICS, POINTWISE, PROFILE, REFERENCE,
    LAW_REFERENCES, STATISTICS, WEAR_ENGINES, Metric, Runs, ValidationPlan, _us, ensemble_profile,
    ensemble_statistics,
    pointwise_differences, revolution_statistics,
)
from wearjoint.validation.law_spread import STAGE, law_spread_summary, run_law_spread
from wearjoint.validation.spans import check_spans


# ---------------------------------------------------------------- figures
def write_figures(runs: Runs, plan: ValidationPlan, out: Path) -> list[str]:
    """Overlays: slider acceleration vs crank angle, pin orbits, first-impact traces, the ensembles'
    statistics, worn profiles."""
    from wearjoint.slider_crank import SliderCrank
    from wearjoint.plots import crank_rotation_deg, plot_wear_profiles, plt

    ref = runs.reference
    period = ref.period_s
    no_wear = {f"{REFERENCE} (reference)": ref, **{engine: members[0] for engine, members in runs.engines.items()}}
    names = []

    last = int(math.floor(ref.revolutions + 1e-9)) - 1      # last complete revolution (or the first, partial)
    fig, ax = plt.subplots(figsize=(9, 5))
    for label, record in no_wear.items():
        s = record.samples
        inside = (s[:, L.T_TIME] >= max(last, 0) * period) & (s[:, L.T_TIME] <= (max(last, 0) + 1) * period)
        ax.plot(crank_rotation_deg(s[inside, L.T_TIME], period), s[inside, L.T_SLIDER_A], ".", ms=1.5, label=label)
    grid = np.linspace(0.0, period, 721)
    ax.plot(crank_rotation_deg(grid, period)[:-1], SliderCrank(_mechanism_of(ref)).closed_form(grid)["slider_a_m_s2"][:-1],
            "k-", lw=1.2, label="ideal joint (closed form)")
    ax.set_xlabel(f"crank rotation [deg] (revolution {max(last, 0) + 1})")
    ax.set_ylabel("slider acceleration [m/s$^2$]")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8, markerscale=6)
    names.append(_save(fig, out, "slider_acceleration.png"))

    fig, axes = plt.subplots(1, len(no_wear), figsize=(4.2 * len(no_wear), 4.4), squeeze=False)
    c_um = ref.clearance_m * 1e6
    circle = np.linspace(0.0, 2.0 * math.pi, 361)
    for ax, (label, record) in zip(axes[0], no_wear.items()):
        if record is not ref:
            ax.plot(ref.samples[:, L.T_ECC_X] * 1e6, ref.samples[:, L.T_ECC_Y] * 1e6, color="0.75", lw=0.4,
                    label="reference")
        ax.plot(record.samples[:, L.T_ECC_X] * 1e6, record.samples[:, L.T_ECC_Y] * 1e6, lw=0.4, label=label)
        ax.plot(c_um * np.cos(circle), c_um * np.sin(circle), "k-", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("eccentricity x, bushing frame [µm]")
    axes[0][0].set_ylabel("eccentricity y, bushing frame [µm]")
    names.append(_save(fig, out, "pin_orbits.png"))

    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    traces = {f"{REFERENCE} RK4 {_us(plan.reference_step_s)} (reference)": (runs.window_reference[0], "-"),
              **{f"{REFERENCE} RK4 {_us(plan.reference_step_s)} under {e}'s law (report.md)": (pair[0], "--")
                 for e, pair in runs.law_window.items()},
              **{f"{e} step {_us(plan.window_step_s)}": (pair[0], "-") for e, pair in runs.window.items()}}
    for label, (record, style) in traces.items():
        s = record.samples[record.samples[:, L.T_TIME] <= plan.window_s]
        t_ms = s[:, L.T_TIME] * 1e3
        axes[0].plot(t_ms, np.hypot(s[:, L.T_ECC_X], s[:, L.T_ECC_Y]) * 1e6, style, lw=0.8, label=label)
        axes[1].plot(t_ms, s[:, L.T_NORMAL_FORCE], style, lw=0.8)
        axes[2].plot(t_ms, s[:, L.T_SLIDER_A], style, lw=0.8)
    axes[0].axhline(c_um, color="k", lw=0.6, ls="--")
    for ax, ylabel in zip(axes, ("|eccentricity| [µm]", "normal force $F_N$ [N]", "slider acceleration [m/s$^2$]")):
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    # above the panels, in two columns: inside, the law variants' entries covered the first panel
    axes[0].legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.02), ncol=2, frameon=False)
    axes[2].set_xlabel("time [ms]")
    names.append(_save(fig, out, "first_impacts.png"))

    names.append(_statistics_figure(runs, plan, out, plt))
    if runs.wear_reference:
        profiles = {f"{REFERENCE} RK4 {_us(plan.reference_step_s)} (reference)": runs.wear_reference,
                    **{f"{REFERENCE} {label}": members for label, members in runs.wear_scatter.items()},
                    **runs.wear_engines}
        plot_wear_profiles(runs.wear_reference[0].phi_deg,
                           {label: ensemble_profile(members)[2] for label, members in profiles.items()},
                           out / "worn_profiles.png", runs.wear_reference[0].parameters.mechanism.clearance_joint,
                           title=f"mean worn profile of {plan.ensemble} starts after "
                           f"{plan.wear_revolutions:g} rev, wear factor {plan.wear_factor:g}")
        names.append("worn_profiles.png")
    return names


def _statistics_figure(runs: Runs, plan: ValidationPlan, out: Path, plt) -> str:
    """statistics.png: every start of every ensemble (dots) and its mean (bar), one panel per statistic;
    grey band: the reference's mean ± twice the largest valid configuration's mean difference."""
    groups = {f"{REFERENCE} (ref.)": runs.reference_ensemble, "valid monolithic": None, **runs.engines}
    per_run = {label: [revolution_statistics(r) for r in members]
               for label, members in {REFERENCE: runs.reference_ensemble, **runs.scatter, **runs.engines}.items()}
    ref_mean = ensemble_statistics(runs.reference_ensemble)[0]
    fig, axes = plt.subplots(1, len(STATISTICS), figsize=(2.3 * len(STATISTICS), 4.2))
    for ax, (name, (unit, _)) in zip(axes, STATISTICS.items()):
        scale = _DISPLAY.get(unit, (1.0, unit))[0]
        band = 2.0 * max(abs(np.mean([r[name] for r in per_run[label]]) - ref_mean[name]) for label in runs.scatter)
        ax.axhspan((ref_mean[name] - band) * scale, (ref_mean[name] + band) * scale, color="0.88")
        for x, (label, members) in enumerate(groups.items()):
            labels = list(runs.scatter) if members is None else [REFERENCE if x == 0 else label]
            values = np.array([r[name] for lb in labels for r in per_run[lb]]) * scale
            ax.plot(np.full(values.size, x) + np.linspace(-0.2, 0.2, values.size), values, ".", ms=3, color=f"C{x}")
            ax.plot([x - 0.3, x + 0.3], [values.mean()] * 2, "k-", lw=1.5)
        ax.set_xticks(range(len(groups)), list(groups), rotation=70, fontsize=7)
        ax.set_title(f"{name}\n[{_shown_unit(unit)}]", fontsize=7)
        ax.tick_params(axis="y", labelsize=7)
        ax.grid(alpha=0.3, axis="y")
    fig.suptitle(f"per-revolution statistics, {plan.ensemble} perturbed starts × {plan.revolutions:g} rev per "
                 "configuration (bars: means)", fontsize=9)
    return _save(fig, out, "statistics.png")


def _mechanism_of(record: RunRecord) -> SliderCrankParameters:
    return record.parameters.mechanism


def _save(fig, out: Path, name: str) -> str:
    from wearjoint.plots import save_figure

    save_figure(fig, out / name)
    return name


# ---------------------------------------------------------------- report and summary
_DISPLAY = {"m": (1e6, "µm"), "m³": (1e9, "mm³")}


def _shown(value, unit: str) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—"
    scale, _ = _DISPLAY.get(unit, (1.0, unit))
    return f"{value * scale:.4g}"


def _revolutions(count: float) -> str:
    """``1 revolution``, ``2.5 revolutions``."""
    return f"{count:g} revolution{'' if count == 1 else 's'}"


def _shown_unit(unit: str) -> str:
    return _DISPLAY.get(unit, (1.0, unit))[1]


def judged(metric: Metric) -> bool:
    """True for a metric of an engine that runs the project's joint; an engine of ``LAW_REFERENCES`` (exudyn's own
    contact law) is a reference whose differences are reported, not judged."""
    return metric.engine not in LAW_REFERENCES


def _status(metrics: list[Metric], runs: Runs) -> int:
    """0: every judged metric passes and every engine ran; 1: a judged metric fails or an engine raised;
    3: an engine is not available."""
    if runs.errors or not all(m.passed for m in metrics if judged(m)):
        return 1
    return 3 if runs.gaps else 0


_ROLE_TEXT = {"joint": "the project's joint", "reference law": "its own contact law (a reference: reported, not judged)"}


def engine_verdicts(metrics: list[Metric]) -> dict:
    """engine -> its role (``joint``: runs the project's joint; ``reference law``: a law of its own), its metrics,
    how many are within tolerance, the failed ones and its verdict (``pass``, ``fail``; a reference law
    ``within tolerance`` or ``differs``, never judged)."""
    out = {}
    for engine in dict.fromkeys(m.engine for m in metrics):
        rows = [m for m in metrics if m.engine == engine]
        failed = [m.name for m in rows if not m.passed]
        role = "joint" if judged(rows[0]) else "reference law"
        verdict = ("fail" if failed else "pass") if role == "joint" else ("differs" if failed else "within tolerance")
        out[engine] = {"role": role, "metrics": len(rows), "within_tolerance": len(rows) - len(failed),
                       "failed": failed, "verdict": verdict}
    return out


def _runs_table(runs: Runs) -> list[dict]:
    rows = []
    for label, engine, record in runs.log:
        rows.append({"run": label, "engine": engine, "simulated_time_s": record.simulated_time_s,
                     "wall_time_s": record.wall_time_s,
                     "realtime_factor": record.simulated_time_s / record.wall_time_s if record.wall_time_s > 0 else None})
    return rows


MACHINE_NOTE = ("wall times measured on a 2-core machine shared with other jobs (under load): "
                "compare ratios within one run, not absolute figures")


def build_summary(runs: Runs, plan: ValidationPlan, metrics: list[Metric], joint: JointParameters,
                  mechanism: SliderCrankParameters, changes: dict, figures: list[str]) -> dict:
    """summary.json: every metric with its scatter, tolerance and verdict; the ensembles' means and
    standard deviations; the contact-law differences; run times."""
    def clean(x):
        return None if isinstance(x, float) and not math.isfinite(x) else x

    status = _status(metrics, runs)
    return {
        "passed": status != 1,
        "complete": not (runs.gaps or runs.errors),
        "exit_status": status,
        "metrics_total": sum(judged(m) for m in metrics),
        "metrics_failed": [f"{m.engine}: {m.name}" for m in metrics if judged(m) and not m.passed],
        "engines": engine_verdicts(metrics),
        "reference_law_differences": [f"{m.engine}: {m.name}" for m in metrics if not judged(m) and not m.passed],
        # a lobe on a bushing half no run wore has no angle, a wear run that wore nothing no profile: left out, named
        "metrics_undefined": [f"{engine}: {name}" for engine in runs.wear_engines for name in PROFILE
                              if not any(m.engine == engine and m.name == name for m in metrics)],
        "gaps": runs.gaps,
        "errors": runs.errors,
        "plan": asdict(plan),
        "tolerance_rule": "tolerance = max(k * scatter, floor, floor_relative * |reference|)",
        "rules": {name: {"unit": unit, **asdict(rule)}
                  for table in (STATISTICS, POINTWISE, PROFILE) for name, (unit, rule) in table.items()},
        "reference_statistics": ensemble_statistics(runs.reference_ensemble)[0],
        "scatter_run_statistics": {label: ensemble_statistics(m)[0] for label, m in runs.scatter.items()},
        "ensemble_std": {label: ensemble_statistics(m)[1] for label, m in
                         {REFERENCE: runs.reference_ensemble, **runs.scatter, **runs.engines}.items()},
        "law_references": {e: runs.law_changes[e] for e in runs.law_window},
        "law_statistics": {e: ensemble_statistics(m)[0] for e, m in runs.law_ensembles.items()},
        "law_differences": law_differences(runs, plan.window_s),
        "unworn_engines": [e for e in plan.engines if e not in WEAR_ENGINES],
        "reference_profile": ensemble_profile(runs.wear_reference)[0] if runs.wear_reference else None,
        "scatter_run_profiles": {label: ensemble_profile(m)[0] for label, m in runs.wear_scatter.items()},
        "metrics": [{k: clean(v) for k, v in asdict(m).items()} for m in metrics],
        "runs": _runs_table(runs),
        "machine_note": MACHINE_NOTE,
        "engine_joint_changes": changes,
        "parameters": {"joint": joint.to_dict(), "mechanism": mechanism.to_dict()},
        "figures": figures,
    }


def law_differences(runs: Runs, window_s: float) -> dict:
    """engine of ``LAW_REFERENCES`` -> {"engine": its trace's, "law": its law's monolithic reference's}
    largest point-wise differences from the default reference: what the contact law alone changes."""
    reference = runs.window_reference[0]
    return {engine: {"engine": pointwise_differences(runs.window[engine][0], reference, window_s),
                     "law": pointwise_differences(law_reference, reference, window_s)}
            for engine, (law_reference, _) in runs.law_window.items() if engine in runs.window}


def _law_statistics_lines(summary: dict) -> list[str]:
    """The statistics' notes on engines judged against an ensemble of their own contact law."""
    lines = []
    for engine, stats in summary["law_statistics"].items():
        law = ", ".join(f"`{k}={v}`" for k, v in summary["law_references"][engine].items())
        lines += [f"{engine} is judged against the reference's ensemble run with its contact law ({law}); that "
                  "ensemble's means differ from the default reference's by (not judged): "
                  + ", ".join(f"{name} {_shown(stats[name] - summary['reference_statistics'][name], unit)} "
                              f"{_shown_unit(unit)}" for name, (unit, _) in STATISTICS.items()) + ".", ""]
    return lines


def _law_lines(summary: dict) -> list[str]:
    """The point-wise notes on engines compared with a monolithic reference of their own contact law."""
    lines = []
    for engine, change in summary["law_references"].items():
        law = ", ".join(f"`{k}={v}`" for k, v in change.items())
        d = summary["law_differences"][engine]
        lines += ["", f"{engine}'s traces are compared with the monolithic reference run with its contact law ({law}). Against "
                  "the default reference (not judged): eccentricity "
                  f"{_shown(d['engine']['eccentricity_max_difference_m'], 'm')} µm, normal force "
                  f"{_shown(d['engine']['normal_force_max_difference_N'], 'N')} N, slider acceleration "
                  f"{_shown(d['engine']['slider_acc_max_difference_m_s2'], 'm/s²')} m/s²; the monolithic run with "
                  f"{law} "
                  f"alone differs from it by {_shown(d['law']['eccentricity_max_difference_m'], 'm')} µm, "
                  f"{_shown(d['law']['normal_force_max_difference_N'], 'N')} N, "
                  f"{_shown(d['law']['slider_acc_max_difference_m_s2'], 'm/s²')} m/s² (what the law alone changes)."]
    return lines


def _machine_lines(mechanism: dict, plan: dict, reference_std: dict) -> list[str]:
    """report.md's lines on the machine compared (where the clearance is, gravity, the slider's load) and the two
    cases whose verdicts say less than they seem to: a load table the no-wear runs' crank angles never reach (a
    quick run of a press covered 360 to 324 deg, where its table is 0 N), an ensemble whose starts did not spread
    (its scatter 0, the tolerances their floors)."""
    table, gx_gy = mechanism.get("slider_force_table"), mechanism["gravity_m_s2"]
    load = (f"{table.get('source') or 'a load table'} (up to {max(abs(f) for f in table['force_N']):.4g} N)"
            if table else f"a constant {mechanism['slider_force_N']:g} N")
    lines = [f"Machine: the clearance at the {mechanism['clearance_joint']} joint, {mechanism['crank_speed_rpm']:g} "
             f"rpm, gravity ({gx_gy[0]:g}, {gx_gy[1]:g}) m/s², the slider's load: {load}.", ""]
    if table and any(table["force_N"]):
        span = min(360.0 * plan["revolutions"], 360.0)        # the crank turns backwards: theta0 - omega t
        covered = (mechanism["initial_crank_angle_deg"] - np.linspace(0.0, span, 721)) % 360.0
        if not np.any(np.interp(covered, table["crank_angle_deg"], table["force_N"])):
            start = mechanism["initial_crank_angle_deg"] % 360.0
            lines += [f"**Note**: the no-wear runs' crank angles ({start:g}° back to {(start - span) % 360.0:g}°) "
                      "never reach the load table's load: the comparison is of the unloaded machine (more "
                      "--revolutions, or --initial-crank-angle-deg, cover it).", ""]
    if plan["ensemble"] > 1 and reference_std.get("impacts_per_revolution") == 0.0:
        lines += [f"**Note**: the reference's {plan['ensemble']} perturbed starts did not spread (standard deviation "
                  "0 of its impacts per revolution): over these revolutions the motion is not chaotic here, no "
                  "scatter is measured, and the statistics' tolerances are the configurations' differences and the "
                  "floors.", ""]
    return lines


def build_report(summary: dict, metrics: list[Metric]) -> str:
    """report.md: verdict, tolerance rules, one table per group, run times, gaps."""
    from wearjoint.cosim.cosimulation import DEFAULT_SCHEME   # the co-simulation's modules load with its engine
    plan = summary["plan"]
    failed = summary["metrics_failed"]
    verdict = "PASS" if summary["passed"] else "FAIL"
    lines = [
        "# wearjoint validate: monolithic vs co-simulation vs exudyn", "",
        f"**{verdict}**: {summary['metrics_total'] - len(failed)} of {summary['metrics_total']} metrics of the "
        "engines that run the project's joint within tolerance"
        + ("" if summary["complete"] else "; **incomplete**: engines missing or failed (see Gaps and errors)")
        + ".", "",
        "| engine | runs | metrics within tolerance | verdict | outside tolerance |", "|---|---|---|---|---|",
        *(f"| {engine} | {_ROLE_TEXT[v['role']]} | {v['within_tolerance']} of {v['metrics']} | {v['verdict']} | "
          f"{', '.join(v['failed']) or '—'} |" for engine, v in summary["engines"].items()), "",
        f"No-wear runs: {_revolutions(plan['revolutions'])}, {plan['ensemble']} perturbed starts per engine and "
        "configuration (initial crank angle + k × 1e-6°); point-wise window: first "
        f"{plan['window_s'] * 1e3:g} ms; "
        f"wear run: {_revolutions(plan['wear_revolutions'])} at wear factor {plan['wear_factor']:g}"
        + ("" if plan["run_wear"] else " (skipped)") + ". Reference: monolithic RK4 at "
        f"{_us(plan['reference_step_s'])}. exudyn (generalized-alpha) at {_us(plan['exudyn_step_s'])}, "
        f"co-simulation ({DEFAULT_SCHEME}, {plan['fmu_backend']} FMU) at most {_us(plan['cosim_step_s'])} in "
        f"contact; both at {_us(plan['window_step_s'])} and twice that over the window, every point they compute "
        "compared with the reference's trace there.", "",
    ]
    lines += _machine_lines(summary["parameters"]["mechanism"], plan, summary["ensemble_std"].get(REFERENCE, {}))
    if summary["engine_joint_changes"]:
        lines += [f"**Self-check**: engines given a different joint: `{summary['engine_joint_changes']}` "
                  "(the comparison must fail).", ""]
    lines += [
        "## Tolerances", "",
        "tolerance = max(k × scatter, floor, floor_rel × |reference|). The scatter is measured in this run "
        "between equally valid runs of one simulator:", "",
        "- per-revolution statistics: each engine and each valid monolithic configuration (RK4 at 1/2, 2, 5 "
        "and 10 times the step; DOPRI at rtol 1e-6 to 1e-8) runs an ensemble of perturbed starts, judged by its "
        "mean. The motion is chaotic, so each run is a sample of the same statistics; the scatter is the largest "
        "difference between the reference's mean and a valid configuration's, or the standard error of the "
        "engine-minus-reference difference if larger; k = 2; every revolution each run covers counts, the first "
        "(the start-up: the pin starts centred at full speed) in every engine alike, so the means compare like "
        "with like but are not `simulate`'s settled values;",
        "- the worn profile: the same for the wear ensembles' means (the mean profile for the decorrelation), "
        "with three valid configurations (RK4 at 5 and 10 µs, DOPRI rtol 1e-6); k = 2;",
        "- point-wise traces: the monolithic step refinement (RK4 h vs h/2) plus the engine's own (its window "
        "step vs twice it), an estimate of the two engines' discretisation errors (both first order at "
        "contact onsets). DOPRI is not used here: over the window it is already micrometres off.", "",
        "| metric | unit | k | floor | floor_rel | why the floor |", "|---|---|---|---|---|---|",
    ]
    for name, rule in summary["rules"].items():
        lines.append(f"| {name} | {_shown_unit(rule['unit'])} | {rule['k']:g} | {_shown(rule['floor'], rule['unit'])} "
                     f"| {rule['floor_relative']:g} | {rule['why_floor']} |")
    for group in (GROUP_STATISTICS, GROUP_POINTWISE, GROUP_PROFILE):
        rows = [m for m in metrics if m.group == group]
        if not rows:
            continue
        lines += ["", f"## {group[0].upper()}{group[1:]}", ""]
        if group == GROUP_STATISTICS:
            labels = list(summary["scatter_run_statistics"])
            spread = summary["ensemble_std"]
            lines += [f"Means of the reference's and the valid monolithic configurations' ensembles "
                      f"({plan['ensemble']} starts × {plan['revolutions']:g} rev; extremes are means of the "
                      "per-revolution extremes), the reference's ± one standard deviation of its starts:", "",
                      "| metric | unit | reference | " + " | ".join(labels) + " |",
                      "|---|---|---|" + "---|" * len(labels)]
            for name, (unit, _) in STATISTICS.items():
                lines.append(f"| {name} | {_shown_unit(unit)} | {_shown(summary['reference_statistics'][name], unit)} "
                             f"± {_shown(spread[REFERENCE][name], unit)} | "
                             + " | ".join(_shown(summary["scatter_run_statistics"][lb][name], unit) for lb in labels)
                             + " |")
            lines += ["", "Engines: value = the mean of the engine's ensemble (± its standard deviation in "
                      "summary.json `ensemble_std`).", ""] + _law_statistics_lines(summary)
        if group == GROUP_PROFILE and summary["reference_profile"]:
            labels = list(summary["scatter_run_profiles"])
            lines += ["Reference and valid monolithic wear runs:", "",
                      "| quantity | unit | reference | " + " | ".join(labels) + " |",
                      "|---|---|---|" + "---|" * len(labels)]
            for name, value in summary["reference_profile"].items():
                unit = PROFILE[name][0]
                lines.append(f"| {name} | {_shown_unit(unit)} | {_shown(value, unit)} | "
                             + " | ".join(_shown(summary["scatter_run_profiles"][lb][name], unit) for lb in labels)
                             + " |")
            lines.append("")
        if group == GROUP_POINTWISE:
            lines += ["| metric | unit | engine | max abs difference to reference | monolithic scatter | engine "
                      "scatter | scatter | tolerance | result |", "|---|---|---|---|---|---|---|---|---|"]
            for m in rows:
                parts = list(m.scatter_values.values())
                lines.append(f"| {m.name} | {_shown_unit(m.unit)} | {m.engine} | {_shown(m.difference, m.unit)} | "
                             f"{_shown(parts[0], m.unit)} | {_shown(parts[1], m.unit)} | {_shown(m.scatter, m.unit)} | "
                             f"{_shown(m.tolerance, m.unit)} | {'pass' if m.passed else '**FAIL**'} |")
            lines += _law_lines(summary)
        else:
            lines += ["| metric | unit | engine | value | reference | difference | scatter | tolerance | result |",
                      "|---|---|---|---|---|---|---|---|---|"]
            for m in rows:
                lines.append(f"| {m.name} | {_shown_unit(m.unit)} | {m.engine} | {_shown(m.value, m.unit)} | "
                             f"{_shown(m.reference, m.unit)} | {_shown(m.difference, m.unit)} | "
                             f"{_shown(m.scatter, m.unit)} | {_shown(m.tolerance, m.unit)} | "
                             f"{'pass' if m.passed else '**FAIL**'} |")
    lines += ["", "profile_decorrelation = 1 − Pearson correlation of h(φ) with the reference profile. Lobe angles: "
              "depth-weighted mean angle of the wear within ±90° of 0° and of 180° (rod frame).", ""]
    lines += _law_spread_lines(summary["law_spread"]) if summary.get("law_spread") else []
    lines += ["## Runs", "", f"{MACHINE_NOTE}.", "",
              "| run | simulated [s] | wall [s] | simulated s per wall s |", "|---|---|---|---|"]
    for row in summary["runs"]:
        rate = row["realtime_factor"]
        lines.append(f"| {row['run']} | {row['simulated_time_s']:.4g} | {row['wall_time_s']:.1f} | "
                     + (f"{rate:.3g}" if rate else "—") + " |")
    lines += ["", "## Figures", ""] + [f"![{name}]({name})" for name in summary["figures"]]
    unworn = [e for e in summary["unworn_engines"] if e in {m.engine for m in metrics}]
    notes = [f"- {e}: no wear run (exudyn's own contact cannot wear); judged on statistics and traces only"
             for e in unworn] + [f"- {u}: undefined, not judged ({_undefined_why(u)})"
                                 for u in summary.get("metrics_undefined", [])]
    lines += ["", "## Gaps and errors", ""] + ([f"- {g}" for g in summary["gaps"] + summary["errors"]] + notes
                                               or ["none"])
    return "\n".join(lines) + "\n"


def _law_spread_lines(spread: dict) -> list[str]:
    """The model-form spread's section: one row per contact-law variant, then the spread, the sampling spread
    and their ratio, one column per answer."""
    answers = spread["answers"]
    no_wear, wear = spread["no_wear_runs"], spread["wear_run"]
    lines = [f"## {STAGE[0].upper()}{STAGE[1:]}", "",
             "Informs, never judged: the exit status is the engine comparisons'. The mechanism and joint above under "
             "each contact damping law and each law's free parameter at the ends of its plausible range "
             "(`wearjoint.contact_laws.contact_law_variants`), monolithic DOPRI (rtol "
             f"{no_wear['options']['rtol']:g}): means of {no_wear['ensemble']} perturbed starts × "
             f"{no_wear['revolutions']:g} rev without wear"
             + (f"; max wear depth after one {wear['revolutions']:g} rev run at wear factor {wear['wear_factor']:g}"
                if wear else "") + ". slider_acc_error_max: the largest |a − a_ideal| of the slider over the counted "
             "revolutions after the start-up, as summary.json's slider_acc_error_max_m_s2 (a_ideal: the ideal "
             "joint's closed form). Spread = max − min over the variants; sampling "
             f"spread = {spread['sampling_spread']}; ratio = spread / sampling spread (above 1: the choice of law "
             "moves the answer more than equally valid runs of one law do).", "",
             "| variant | " + " | ".join(f"{name} [{_shown_unit(a['unit'])}]" for name, a in answers.items()) + " |",
             "|---|" + "---|" * len(answers)]
    for k, label in enumerate(spread["variants"]):
        lines.append(f"| {label} | " + " | ".join(_shown(a["values"][k], a["unit"]) for a in answers.values()) + " |")
    for row, key in (("**spread** (max − min)", "spread"), ("sampling spread", "sampling_spread")):
        lines.append(f"| {row} | " + " | ".join(_shown(a[key], a["unit"]) for a in answers.values()) + " |")
    lines.append("| ratio | " + " | ".join("—" if a["ratio"] is None else f"{a['ratio']:.3g}"
                                            for a in answers.values()) + " |")
    lines += ["", f"{spread['runs']} runs in {spread['wall_time_s']:.1f} s wall (compilation included)."]
    lines += [f"- error: {e}" for e in spread["errors"]]
    return lines + [""]


def _undefined_why(metric: str) -> str:
    """Why a profile metric (``"engine: name"``) is undefined."""
    if ": lobe_angle" in metric:
        return "a bushing half that a run did not wear has no lobe angle to compare"
    return "the reference's wear runs wore nothing, ending before the first contact: no profile to compare"


__all__ = ["write_figures", "build_summary", "build_report"]


def run_validation(plan: ValidationPlan, out_dir, joint: JointParameters | None = None,
                   mechanism: SliderCrankParameters | None = None, engine_joint_changes: dict | None = None,
                   progress: bool = True) -> dict:
    """Run, compare, (``plan.law_spread``) run the model-form spread over the contact laws, and write
    ``report.md``, ``summary.json`` and the PNG overlays into ``out_dir``; returns the summary
    (``exit_status``: 0 pass, 1 a metric of an engine running the project's joint failed or an engine raised, 3 an
    engine is not available; a reference law's metrics and the law spread never change it)."""
    mechanism = mechanism or SliderCrankParameters()
    joint = joint or JointParameters(**mechanism.joint_defaults())
    check_spans(plan, mechanism)      # a window of every engine's points within the no-wear runs, a wear run that fits
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    runs = run_engines(plan, joint, mechanism, engine_joint_changes, progress)
    metrics = compare(runs, plan)
    spread = run_law_spread(plan, joint, mechanism, progress) if plan.law_spread else None
    figures = write_figures(runs, plan, out)
    summary = build_summary(runs, plan, metrics, joint, mechanism, engine_joint_changes or {}, figures)
    if spread is not None:      # informs only: the exit status stays the comparisons'
        summary["law_spread"] = law_spread_summary(spread, runs, plan)
    (out / "report.md").write_text(build_report(summary, metrics))
    write_json_atomic(out / "summary.json", summary)
    return summary
