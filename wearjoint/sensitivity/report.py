"""A sensitivity study's outputs, its systematic uncertainty and its files.

Outputs are numbers of the runs' summary.json (docs/reference/results.md §6; a wear study's ``revR_...`` per
snapshot and ``growth_exponent``) plus ``slider_acc_peak_m_s2``, max(|slider_acc_max_m_s2|,
|slider_acc_min_m_s2|): the peak slider acceleration of the last revolution.  Files: ``samples.csv``
(one row per design row: its group, parameter values, case and outputs), ``indices.csv`` (per output
and parameter, ranked by effect: the method's indices, their 95 % intervals, the output's wear-factor
bias) and ``sensitivity_OUTPUT.png`` (bars with interval whiskers, parameters sorted by effect).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..against_ideal import SUMMARY_KEYS
from ..analysis import pin_left_bushing
from ..parameters import ParameterError
from ..sweep.bias import Bias, common_bias, summary_biases
from ..sweep.report import FIGURES_OF_MERIT
from ..sweep.runner import SNAPSHOT_FIGURES, write_csv_atomic
from ..targets import RECORD_NAME, read_record, target
from .analyse import COLUMNS, EFFECT

PEAK = "slider_acc_peak_m_s2"
DEFAULT_OUTPUTS = ("max_wear_depth_m", "worn_volume_m3", "max_contact_force_N", "impacts_per_revolution", PEAK)
# the other numbers of every run's summary.json (docs/reference/results.md §6)
OTHER_OUTPUTS = ("max_wear_angle_deg", "wall_time_s", "realtime_factor", PEAK, *SUMMARY_KEYS,
                 "impact_events_per_revolution", "chattering_revolution_share", "whirl_fraction")
BIAS_EFFECT = ("a relative bias b shared by every run scales each run's output by 1 + b: the Sobol' indices and the "
               "ranking are unchanged, Morris mu*, sigma and mu scale by 1 + b; a bias that varies across the ranges "
               "changes them by an amount nobody measured")


def allowed_outputs(command: str, base: dict) -> list:
    """The outputs a study of ``command`` with options ``base`` can analyse."""
    names = [*FIGURES_OF_MERIT, *OTHER_OUTPUTS]
    snapshots = target(command).snapshots(base)      # a wear study's: its figures per snapshot, its growth
    if snapshots:
        names += [f"rev{r}_{key}" for r in snapshots for key in SNAPSHOT_FIGURES] + ["growth_exponent"]
    if base.get("life_depth_m") is not None:      # a wear study's life to that depth (per hour: the speed counts)
        names += ["life_revolutions", "life_hours"]
    return names


def parse_outputs(command: str, base: dict, text) -> list:
    """``--outputs A,B,...`` (or a list; None: the defaults) -> names; a one-line ParameterError naming the unknown one."""
    items = text.split(",") if isinstance(text, str) else (text or ())
    names = [n.strip() for n in items if n.strip()] or list(DEFAULT_OUTPUTS)
    allowed = allowed_outputs(command, base)
    for name in names:
        if name not in allowed:
            raise ParameterError(f"--outputs {name!r} is invalid: allowed (comma separated) " + ", ".join(allowed))
    return list(dict.fromkeys(names))


def invalid_reason(row: dict | None) -> str:
    """Why an ok run's numbers are not physical, '' when they may be (:func:`wearjoint.analysis.pin_left_bushing`
    of its max eccentricity; the engines now stop such runs, results written before them may hold one)."""
    if row is None or row.get("status") != "ok":
        return ""
    e, c, h = (row.get(k) for k in ("max_eccentricity_m", "clearance_m", "max_wear_depth_m"))
    p = row.get("admissible_penetration_m", c)       # a row written before summary.json had it: the clearance
    force, admissible = row.get("max_contact_force_N"), row.get("admissible_force_N", math.inf)
    if all(isinstance(v, (int, float)) for v in (e, c, h, p)):
        return pin_left_bushing(e, c, h, p, *((force, admissible) if isinstance(force, (int, float))
                                              and isinstance(admissible, (int, float)) else ()))
    return ""


def output_value(row: dict | None, name: str) -> float:
    """Output ``name`` of a case's row (sweep.csv's columns); NaN when the case has none (failed, pending) or
    its numbers are not physical (:func:`invalid_reason`)."""
    if row is None or row.get("status") != "ok" or invalid_reason(row):
        return math.nan
    if name == PEAK:
        values = [row.get("slider_acc_max_m_s2"), row.get("slider_acc_min_m_s2")]
        return max(abs(float(v)) for v in values) if all(isinstance(v, (int, float)) for v in values) else math.nan
    value = row.get(name)
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else math.nan


def output_biases(out: Path, rows: list, outputs: list) -> dict:
    """{output: Bias}: the wear factor's bias of each output, the same for every ok run or unknown.  The bias
    is measured for the max depth only; the others carry 0 where the runs have no wear-factor bias."""
    found = {name: set() for name in outputs}
    for row in rows:
        folder = Path(out) / row["folder"]
        if row["status"] != "ok" or not (folder / RECORD_NAME).is_file():
            continue
        biases = summary_biases(read_record(folder))
        depth = biases["max_wear_depth_m"]
        for name in outputs:
            bias = biases.get(name) or (depth if depth.rel == 0.0 else
                                        Bias(None, "unknown: the wear factor's bias is measured for the max depth only"))
            found[name].add(bias)
    return {name: common_bias(b) if b else Bias(None, "unknown: no run finished") for name, b in found.items()}


def write_samples(out: Path, problem, x_rows: list, group: int, ids: list, rows: dict, outputs: list) -> None:
    """samples.csv: one row per design row (rows of one Morris grid point share a case); status ``invalid`` and
    the reason in ``error`` for an ok run whose numbers are not physical."""
    table = []
    for i, (point, cid) in enumerate(zip(x_rows, ids)):
        row, invalid = rows.get(cid), invalid_reason(rows.get(cid))
        status = "invalid" if invalid else row["status"] if row else "pending"
        table.append({"sample": i, "group": i // group, **{p.dest: point[p.name] for p in problem.parameters},
                      "case_id": cid, "status": status, "error": invalid or (row["error"] if row else ""),
                      **{name: output_value(row, name) for name in outputs}})
    write_csv_atomic(Path(out) / "samples.csv", table)


def ranked(method: str, result: dict) -> list:
    """The output's index rows, largest effect first."""
    return sorted(result["indices"], key=lambda r: -r[EFFECT[method]])


# indices that are never negative (a mean of absolute changes, shares of a variance): their intervals stop at 0
NON_NEGATIVE = ("mu_star", "S1", "ST")
SHARES = ("S1", "ST")          # shares of the output's variance: at most 1


def interval(row: dict, index: str) -> tuple[float, float]:
    """(low, high): ``row[index]`` -/+ its 95 % half-interval ``row[index + "_conf"]`` (SALib's), the low end at least
    0 for an index that cannot be negative (μ* = 3.8e-8 with a half-interval of 1.2e-7 gave -7.9e-8), the high end
    at most 1 for a share of the variance (S1's 1.73 at N = 8)."""
    low, high = row[index] - row[f"{index}_conf"], row[index] + row[f"{index}_conf"]
    return (max(low, 0.0) if index in NON_NEGATIVE else low), (min(high, 1.0) if index in SHARES else high)


def write_indices(out: Path, method: str, results: dict, biases: dict) -> None:
    """indices.csv: per output and parameter (ranked by effect): the indices, each interval's low and high ends,
    the complete groups used and the output's wear-factor bias."""
    table = []
    for output, result in results.items():
        for rank, r in enumerate(ranked(method, result), start=1):
            ends = {}
            for c in (c for c in COLUMNS[method] if f"{c}_conf" in r):
                ends[f"{c}_low"], ends[f"{c}_high"] = interval(r, c)
            table.append({"output": output, "rank": rank, **r, **ends, "groups": result["groups"],
                          "bias_rel": biases[output].csv})
    write_csv_atomic(Path(out) / "indices.csv", table, lead=("output", "rank", "parameter", "api_name"))


def plot_indices(out: Path, method: str, output: str, result: dict, title: str) -> str:
    """sensitivity_OUTPUT.png: horizontal bars, largest effect on top, 95 % interval whiskers."""
    from ..plots import plt, save_figure

    rows = ranked(method, result)[::-1]
    y = np.arange(len(rows))
    fig, ax = plt.subplots(figsize=(7.5, 1.2 + 0.45 * len(rows)))
    if method == "sobol":
        for key, shift, color in (("ST", 0.2, "tab:orange"), ("S1", -0.2, "tab:blue")):
            ax.barh(y + shift, [r[key] for r in rows], height=0.38, xerr=_whiskers(rows, key), color=color,
                    capsize=3, label=f"{key} ± 95 % interval")
        ax.axvline(0.0, color="k", lw=0.6)
        ax.set_xlabel("Sobol' index (share of the output's variance)")
    else:
        top = max([r["mu_star"] for r in rows] + [r["sigma"] for r in rows])
        scale = 10.0 ** math.floor(math.log10(top)) if top > 0.0 else 1.0
        ax.barh(y, [r["mu_star"] / scale for r in rows], height=0.6, xerr=_whiskers(rows, "mu_star", scale),
                capsize=3, color="tab:blue", label="μ* ± 95 % interval")
        ax.plot([r["sigma"] / scale for r in rows], y, "kx", label="σ")
        ax.set_xlabel(f"Morris μ* / {scale:.0e}: mean |change of {output}| over a parameter's range")
    ax.set_yticks(y, [r["parameter"] for r in rows])
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8, loc="lower right")
    name = f"sensitivity_{output}.png"
    save_figure(fig, Path(out) / name)
    return name


def _whiskers(rows: list, index: str, scale: float = 1.0) -> list:
    """matplotlib's xerr of the bars of ``index``: each row's :func:`interval` below and above its value."""
    ends = [interval(r, index) for r in rows]
    return [[max(r[index] - low, 0.0) / scale for r, (low, _) in zip(rows, ends)],   # an estimate below 0: none
            [max(high - r[index], 0.0) / scale for r, (_, high) in zip(rows, ends)]]   # a share above 1: none


__all__ = ["DEFAULT_OUTPUTS", "PEAK", "BIAS_EFFECT", "allowed_outputs", "parse_outputs", "output_value", "invalid_reason",
           "output_biases", "write_samples", "interval", "write_indices", "plot_indices", "ranked"]
