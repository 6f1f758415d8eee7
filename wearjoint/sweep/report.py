"""A sweep's ensemble statistics and figures, from the rows of its cases (``SweepFolder.table``).

``ensemble.csv``: one row per grid point -- its swept values, ``n_ok``/``n_failed``/``n_pending``
and, for every summary figure, ``_mean``, ``_std`` (sample standard deviation, n - 1; empty
with one seed), ``_min``, ``_max`` over the point's ``ok`` seeds; the systematic uncertainty the
run can state beside them (:mod:`.bias`): ``max_wear_depth_m_bias_rel`` (and ``revR_..._bias_rel``
per wear-study snapshot), the wear factor's relative bias or ``unknown``, and
``wear_factor_bias_note``; the regimes of the point's starts (each ok case's summary ``regime``,
:func:`wearjoint.analysis.regime`): ``regime_<name>_fraction`` per regime met in the sweep (e.g.
``regime_backward_whirl_fraction``, over the ok cases that name one), ``regimes`` (e.g.
``backward whirl 2/8, impacting 6/8``) and ``mixed_regimes`` (1 where the point's means average
over more than one regime).  ``bands/pointK_LABEL.csv``: the worn profile's mean, std, min and max
per bushing point (LABEL ``final``, and ``revR`` per wear-study snapshot).  Figures:
``vs_PARAMETER.png`` (each figure of merit against each swept parameter as the change from the
first grid point in %, mean with the +-std band, every seed, and the wear factor's bias band),
``profile_bands_N.png`` (the final worn profiles of up to PROFILES_PER_PANEL grid points overlaid),
and for wear studies ``fig7_bands_pointK.png`` (paper Fig. 7 with bands).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..targets import RECORD_NAME, read_record
from .bias import Bias, summary_biases
from .runner import LEAD_COLUMNS, PENDING, TAIL_COLUMNS, write_csv_atomic

FIGURES_OF_MERIT = ("max_wear_depth_m", "worn_volume_m3", "max_contact_force_N", "contact_fraction",
                    "impacts_per_revolution", "slider_acc_min_m_s2", "slider_acc_max_m_s2", "max_eccentricity_m")
PROFILES_PER_PANEL = 10
BIAS_NOTE = "wear_factor_bias_note"
_PROFILE = re.compile(r"^profile(?:_rev(\d+))?\.csv$")


class GridPoint:
    """The rows of one grid point's cases (its seeds) and its swept values (``names`` -> value)."""

    def __init__(self, rows: list[dict], names: list[str]):
        self.rows = rows
        self.values = {name: rows[0][name] for name in names}
        self.ok = [r for r in rows if r["status"] == "ok"]
        self.bias: dict[str, Bias] = {}      # figure column -> the wear factor's bias (:func:`read_run_facts`)
        self.clearance_joint: str | None = None     # the joint that wears (its bushing's frame: the profiles' axis)

    @property
    def label(self) -> str:
        return values_label(self.values.items()) or "base case"


def values_label(pairs) -> str:
    """``name=value, ...`` (floats in %g) of (name, value) pairs."""
    return ", ".join(f"{name}={value:g}" if isinstance(value, float) else f"{name}={value}" for name, value in pairs)


def read_run_facts(out: Path, point: GridPoint) -> None:
    """The point's wear-factor biases ({figure column: Bias}) and clearance joint, from its first ok case's
    summary.json (the seeds share them)."""
    for row in point.ok:
        folder = out / row["folder"]
        if (folder / RECORD_NAME).is_file():
            summary = read_record(folder)
            point.bias = summary_biases(summary)
            point.clearance_joint = summary.get("parameters", {}).get("mechanism", {}).get("clearance_joint")
            return


PARAMETER_SECTIONS = ("joint", "mechanism")       # the sections of a case's parameters the report tables
SHOWN_VALUES = 12                                  # a parameter that takes more values over the cases: its range


def _distinct(values) -> list:
    """``values`` without repeats, in their order (lists among them: no hashing)."""
    kept = []
    for value in values:
        if value not in kept:
            kept.append(value)
    return kept


def parameter_spread(out: Path, rows: list[dict], names: list[str], varied_by: str = "swept (--vary)"
                     ) -> tuple[dict, dict]:
    """(the joint and mechanism parameters of the sweep's first ok case, {section: {name: value}} as its summary.json
    has them; {name: [its values, where they came from]} of each that differs between them: ``varied_by`` for
    ``names``, the design's (every case's value, a failed one's too), the seeds' start angles, or an option of the
    design it follows; more than SHOWN_VALUES numbers as ``from MIN to MAX, N values``); ({}, {}) before a case
    finished."""
    first, seen = {}, {}
    for row in rows:
        folder = out / row["folder"] if row["status"] == "ok" else None
        if folder is None or not (folder / RECORD_NAME).is_file():
            continue
        parameters = read_record(folder).get("parameters", {})
        first = first or {section: parameters[section] for section in PARAMETER_SECTIONS if section in parameters}
        for section in PARAMETER_SECTIONS:
            for name, value in (parameters.get(section) or {}).items():
                seen[name] = _distinct([*seen.get(name, []), value])
    for name in names:                     # a swept parameter: every grid point's value, a failed one's too
        if name in seen:
            seen[name] = _distinct(row[name] for row in rows if name in row)
    spread = {}
    for name, values in seen.items():
        if len(values) > 1 or name in names:
            numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
            shown = (values if len(values) <= SHOWN_VALUES or not numbers
                     else f"from {min(values):g} to {max(values):g}, {len(values)} values")
            spread[name] = [shown, varied_by if name in names else "the seeds' start angles (--seeds)"
                            if name == "initial_crank_angle_deg" else "follows an option of the design"]
    return first, spread


def _bushing_angle_label(points) -> str:
    """The profiles' angle axis of ``points`` (the bushing frame of their clearance joint, if they share one)."""
    from ..plots import bushing_angle_label

    joints = {point.clearance_joint for point in points}
    return bushing_angle_label(joints.pop() if len(joints) == 1 else None).replace("\n", " ")


def bias_label(point: GridPoint, column: str = "max_wear_depth_m") -> str:
    """E.g. ``bias -8.4 %`` (the wear factor's, of ``column``); empty when the point has none."""
    bias = point.bias.get(column)
    return "" if bias is None else f"bias {bias.text}"


def grid_points(rows: list[dict], names: list[str]) -> list[GridPoint]:
    """The rows grouped by grid point (equal values in the columns ``names``), in design order."""
    groups = {}
    for row in rows:
        groups.setdefault(tuple(row[name] for name in names), []).append(row)
    return [GridPoint(members, names) for members in groups.values()]


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def regime_counts(point: GridPoint) -> dict:
    """{regime: number of the point's ok cases in it} (the summaries' ``regime``; cases without one left out)."""
    counts = {}
    for row in point.ok:
        if isinstance(row.get("regime"), str) and row["regime"]:
            counts[row["regime"]] = counts.get(row["regime"], 0) + 1
    return dict(sorted(counts.items()))


def regime_column(name: str) -> str:
    """ensemble.csv's column of the fraction of starts in regime ``name``: ``regime_<name>_fraction``."""
    return "regime_" + re.sub(r"\W+", "_", name.strip().lower()) + "_fraction"


def regime_text(counts: dict) -> str:
    """E.g. ``backward whirl 2/8, impacting 6/8`` (empty without regimes)."""
    total = sum(counts.values())
    return ", ".join(f"{name} {n}/{total}" for name, n in counts.items())


def regime_fields(points: list[GridPoint]) -> list[dict]:
    """Per point: ``regime_<name>_fraction`` for every regime met anywhere in the sweep (0.0 where the point
    has none of it; empty where no case of the point names a regime), ``regimes`` and ``mixed_regimes``."""
    counts = [regime_counts(point) for point in points]
    names = sorted({name for c in counts for name in c})
    out = []
    for c in counts:
        total = sum(c.values())
        fields = {regime_column(name): (c.get(name, 0) / total if total else "") for name in names}
        fields["regimes"] = regime_text(c)
        fields["mixed_regimes"] = int(len(c) > 1) if total else ""
        out.append(fields)
    return out


def circular_mean_std_deg(angles_deg: np.ndarray) -> tuple[float, float]:
    """(circular mean in [0, 360), circular standard deviation sqrt(-2 ln R)) [deg] of angles on the bushing: the
    arithmetic mean of lobes at 8 and 186 deg had said 141 deg, where no lobe is."""
    z = np.exp(1j * np.radians(angles_deg)).mean()
    spread = math.sqrt(max(-2.0 * math.log(min(abs(z), 1.0)), 0.0)) if abs(z) > 0.0 else math.inf
    mean = float(np.degrees(np.angle(z)))
    return (mean + 360.0 if mean < 0.0 else mean), float(np.degrees(spread))


def ensemble_rows(points: list[GridPoint]) -> list[dict]:
    """ensemble.csv's rows (see the module docstring)."""
    out = []
    regimes = regime_fields(points)
    for k, point in enumerate(points):
        ok = point.ok
        pending = sum(r["status"] == PENDING for r in point.rows)
        skip = set(LEAD_COLUMNS) | set(TAIL_COLUMNS) | set(point.values) | {"mixed_regimes"}
        row = {"point": k, **point.values, "n_ok": len(ok), "n_failed": len(point.rows) - len(ok) - pending,
               "n_pending": pending, **regimes[k]}
        columns = dict.fromkeys(c for r in ok for c, v in r.items() if c not in skip and _number(v))
        for column in columns:
            values = np.array([r[column] for r in ok if _number(r.get(column))], dtype=float)
            values = values[np.isfinite(values)]
            if values.size == 0:
                continue
            mean, std = circular_mean_std_deg(values) if column.endswith("_angle_deg") else (
                float(values.mean()), float(values.std(ddof=1)) if values.size > 1 else "")
            row[f"{column}_mean"], row[f"{column}_std"] = mean, (std if values.size > 1 else "")
            row[f"{column}_min"] = float(values.min())
            row[f"{column}_max"] = float(values.max())
            if column in point.bias:                  # the systematic uncertainty next to the answer
                row[f"{column}_bias_rel"] = point.bias[column].csv
        for column, bias in point.bias.items():
            row.setdefault(f"{column}_bias_rel", bias.csv)
        columns_by_note: dict[str, list[str]] = {}       # each note once, naming the figures it is about
        for column, bias in point.bias.items():
            columns_by_note.setdefault(bias.note, []).append(column)
        row[BIAS_NOTE] = " | ".join(f"{', '.join(columns)}: {note}" for note, columns in columns_by_note.items())
        out.append(row)
    return out


def profile_bands(out: Path, points: list[GridPoint]) -> dict:
    """{point k: {label: (phi_deg, depths (n_seeds, N_d))}} from the ok cases' profile CSVs;
    writes bands/pointK_LABEL.csv."""
    bands = {}
    (out / "bands").mkdir(exist_ok=True)
    for k, point in enumerate(points):
        stacks = {}
        for row in point.ok:
            for path in sorted((out / row["folder"]).glob("profile*.csv")):
                match = _PROFILE.match(path.name)
                if match:
                    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
                    stacks.setdefault(f"rev{match[1]}" if match[1] else "final", []).append(data)
        bands[k] = {}
        for label, profiles in stacks.items():
            if len({p.shape for p in profiles}) != 1:
                continue                          # n_points differs between seeds: no band
            phi, depth = profiles[0][:, 0], np.stack([p[:, 1] for p in profiles])
            bands[k][label] = (phi, depth)
            std = depth.std(axis=0, ddof=1) if len(depth) > 1 else np.full(phi.size, np.nan)
            np.savetxt(out / "bands" / f"point{k}_{label}.csv",
                       np.column_stack([phi, depth.mean(axis=0), std, depth.min(axis=0), depth.max(axis=0)]),
                       delimiter=",", header="phi_deg,mean_wear_depth_m,std_wear_depth_m,min_wear_depth_m,"
                       "max_wear_depth_m", comments="", fmt="%.10g")
    return bands


# ------------------------------------------------------------------ figures
def _band(ax, x, values: np.ndarray, scale: float, label=None, color=None):
    """Mean line with its +-std band (values: (n, len(x)))."""
    mean = values.mean(axis=0) * scale
    line, = ax.plot(x, mean, lw=1.2, label=label, color=color)
    if len(values) > 1:
        std = values.std(axis=0, ddof=1) * scale
        ax.fill_between(x, mean - std, mean + std, color=line.get_color(), alpha=0.25, lw=0)
    return line


def plot_profile_bands(out: Path, points, bands: dict) -> list[str]:
    """profile_bands_N.png: the final worn profiles (mean +- std over seeds) of up to
    PROFILES_PER_PANEL grid points overlaid in one panel, the legend naming each point, its seeds
    and the wear factor's bias of its max depth."""
    from ..plots import plt, save_figure

    keys = [k for k in range(len(points)) if "final" in bands.get(k, {})]
    names = []
    for page, start in enumerate(range(0, len(keys), PROFILES_PER_PANEL), start=1):
        fig, ax = plt.subplots(figsize=(9, 5))
        for k in keys[start:start + PROFILES_PER_PANEL]:
            phi, depth = bands[k]["final"]
            details = ", ".join(filter(None, (f"{len(depth)} seeds", bias_label(points[k]))))
            _band(ax, phi, depth, 1e6, label=f"{points[k].label} ({details})")
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.set_xlabel(_bushing_angle_label([points[k] for k in keys[start:start + PROFILES_PER_PANEL]]))
        ax.set_ylabel("wear depth [µm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title("worn profile: mean ± std over seeds (bias: the wear factor's, of the max depth)", fontsize=10)
        names.append(f"profile_bands_{page}.png")
        save_figure(fig, out / names[-1])
    return names


def plot_fig7_bands(out: Path, points, bands: dict) -> list[str]:
    """fig7_bands_pointK.png: the wear-study snapshots' profiles, mean +- std over seeds, each
    labelled with the wear factor's bias of its max depth."""
    from ..plots import plt, save_figure

    names = []
    for k, by_label in bands.items():
        snaps = sorted((int(label[3:]), label) for label in by_label if label.startswith("rev"))
        if not snaps:
            continue
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for revolution, label in snaps:
            phi, depth = by_label[label]
            bias = bias_label(points[k], f"{label}_max_wear_depth_m")
            _band(ax, phi, depth, 1e6, label=f"{revolution} rev" + (f" ({bias})" if bias else ""))
        ax.set_xlabel(_bushing_angle_label([points[k]]))
        ax.set_ylabel("wear depth [µm]")
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, title="bias: the wear factor's, of the max depth", title_fontsize=7)
        n = len(by_label[snaps[0][1]][1])
        ax.set_title(f"Fig. 7 with bands: mean ± std over {n} seeds ({points[k].label})", fontsize=10)
        names.append(f"fig7_bands_point{k}.png")
        save_figure(fig, out / names[-1])
    return names


def _seeds(point: GridPoint, merit: str) -> np.ndarray:
    return np.array([r[merit] for r in point.ok if _number(r.get(merit))], dtype=float)


def _change_panel(ax, merit: str, lines: dict) -> list[float]:
    """One figure of merit: per line (x, point) its seeds, mean and +-std band as the change from the
    line's first point in % (absolute where that point's mean is 0), and the wear factor's bias band
    +-|bias| around no change; returns the lines' reference means (empty when absolute)."""
    relative = True
    series = {}
    for others, members_at in lines.items():
        pts = [(x, point, _seeds(point, merit)) for x, point in sorted(members_at, key=lambda item: item[0])]
        pts = [p for p in pts if p[2].size]
        if pts:
            series[others] = pts
            relative &= bool(math.isfinite(pts[0][2].mean()) and pts[0][2].mean() != 0.0)
    unknown, refs = False, []
    for others, pts in series.items():
        ref = pts[0][2].mean() if relative else 0.0
        refs += [ref] if relative else []
        scale = 100.0 / abs(ref) if relative else 1.0
        xs = np.array([x for x, _, _ in pts], dtype=float)
        biases = [point.bias.get(merit) for _, point, _ in pts]
        unknown |= any(b is not None and b.rel is None for b in biases)
        half = np.array([abs(b.rel) if b is not None and b.rel is not None else np.nan for b in biases])
        if relative and np.any(half > 0):
            band_x = xs if xs.size > 1 else np.array([xs[0] - 0.5, xs[0] + 0.5])
            band = half * 100.0 if xs.size > 1 else np.repeat(half * 100.0, 2)
            ax.fill_between(band_x, -band, band, color="0.85", lw=0, zorder=0,
                            label="wear-factor bias" if others == next(iter(series)) else None)
        means = np.array([(ys.mean() - ref) * scale for _, _, ys in pts])
        stds = np.array([ys.std(ddof=1) * scale if ys.size > 1 else 0.0 for _, _, ys in pts])
        line, = ax.plot(xs, means, "-", lw=1.2, label=values_label(others) or None)
        for x, _, ys in pts:
            ax.plot(np.full(ys.size, x), (ys - ref) * scale, ".", ms=3, alpha=0.5, color=line.get_color())
        ax.fill_between(xs, means - stds, means + stds, color=line.get_color(), alpha=0.2, lw=0)
    if relative:
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel("change from the first point [%]", fontsize=7)
    if unknown:
        ax.text(0.02, 0.96, "wear-factor bias unknown", transform=ax.transAxes, fontsize=6, va="top")
    return refs


MAX_LABELLED_VALUES = 8       # a swept parameter with at most this many values has each labelled on its axis


def _distinct_labels(values) -> list[str]:
    """``values`` written with the fewest significant digits (at least 3) that tell them apart."""
    for digits in range(3, 17):
        labels = [f"{v:.{digits}g}" for v in values]
        if len(set(labels)) == len(labels):
            return labels
    return [repr(v) for v in values]


LOG_AXIS_SPAN = 100.0      # a swept parameter whose values span this factor or more is drawn on a log axis


def plot_against_parameters(out: Path, points: list[GridPoint]) -> list[str]:
    """vs_PARAMETER.png: each figure of merit against each swept parameter, as the change from the
    first grid point in % against the wear factor's bias band (:func:`_change_panel`); one line per
    combination of the other swept parameters."""
    from ..plots import plt, save_figure

    if not points or not points[0].values:
        return []
    names = []
    params = list(points[0].values)
    merits = [m for m in FIGURES_OF_MERIT if any(_number(r.get(m)) for point in points for r in point.ok)]
    for param in params:
        values = list(dict.fromkeys(point.values[param] for point in points))
        numeric = all(_number(v) for v in values)
        position = {v: (v if numeric else i) for i, v in enumerate(values)}
        lines = {}
        for point in points:
            others = tuple((p, point.values[p]) for p in params if p != param)
            lines.setdefault(others, []).append((position[point.values[param]], point))
        ncols = min(4, len(merits))
        nrows = max(1, math.ceil(len(merits) / ncols))
        fig, axes = plt.subplots(nrows, ncols, figsize=(3.8 * ncols + 0.5, 3.0 * nrows + 0.8), squeeze=False)
        for ax, merit in zip(axes.ravel(), merits):
            refs = _change_panel(ax, merit, lines)
            # each line's 0 %, in the legend's order (a second swept parameter: one line per value)
            ax.set_title(merit + (f" (0 % = {' | '.join(f'{ref:.4g}' for ref in refs)})" if refs else ""),
                         fontsize=9)
            ax.set_xlabel(param, fontsize=8)
            if numeric and min(values) > 0.0 and max(values) >= LOG_AXIS_SPAN * min(values):
                ax.set_xscale("log")             # a grid over decades (k_w 1e-12..1e-9 had run together at the left)
                ax.minorticks_off()
            if not numeric:       # a file's name, not its path (a load table's full paths had run into each other)
                names = [Path(str(v)).name or str(v) for v in values]
                ax.set_xticks(range(len(values)), names if len(set(names)) == len(names) else [str(v) for v in values],
                              rotation=15, fontsize=7)
            elif len(values) <= MAX_LABELLED_VALUES:     # each value (the default ran close ones together)
                ax.set_xticks(values, _distinct_labels(values), rotation=30, fontsize=7)
            ax.grid(alpha=0.3)
        for ax in axes.ravel()[len(merits):]:
            ax.set_visible(False)
        if axes[0, 0].get_legend_handles_labels()[0]:
            axes[0, 0].legend(fontsize=6)
        fig.suptitle(f"figures of merit against {param}: change from each line's first point, mean ± std over seeds "
                     "(dots: seeds; grey: the wear factor's bias)", fontsize=10)
        names.append(f"vs_{param}.png")
        save_figure(fig, out / names[-1])
    return names


def write_reports(out: Path, rows: list[dict], names: list[str], plots: bool = True) -> dict:
    """ensemble.csv, the profile bands and (``plots``) the figures from ``rows`` (every case's, in
    design order; ``names``: the swept values' columns); returns the ensemble rows, the figures'
    file names, the notes on the wear factor's bias and the cases' parameters (:func:`parameter_spread`)."""
    out = Path(out)
    points = grid_points(rows, names)
    for point in points:
        read_run_facts(out, point)
    ensemble = ensemble_rows(points)
    write_csv_atomic(out / "ensemble.csv", ensemble, lead=("point", *names, "n_ok", "n_failed", "n_pending"))
    bands = profile_bands(out, points)
    figures = []
    if plots and any(point.ok for point in points):
        figures = (plot_against_parameters(out, points) + plot_profile_bands(out, points, bands)
                   + plot_fig7_bands(out, points, bands))
    notes = list(dict.fromkeys(b.note for point in points for b in point.bias.values()))
    regimes = [{"point": k, "values": point.values, "regimes": regime_counts(point), "text": row["regimes"],
                "mixed": bool(row["mixed_regimes"])} for k, (point, row) in enumerate(zip(points, ensemble))]
    parameters, spread = parameter_spread(out, rows, names)
    return {"ensemble": ensemble, "figures": figures, "wear_factor_bias": notes, "regimes": regimes,
            "case_parameters": parameters, "parameter_spread": spread}


def regime_line(row: dict) -> str:
    """The printed table's regime note of an ensemble.csv row (values as read back: strings): e.g.
    ``regimes: backward whirl 2/8, impacting 6/8 (MIXED: ...)``; empty when the row names no regime."""
    text = row.get("regimes") or ""
    if not text:
        return ""
    mixed = str(row.get("mixed_regimes", "")).strip() in ("1", "True", "true")
    return f"regimes: {text}" + (" (MIXED: the means average over these regimes)" if mixed else "")


__all__ = ["write_reports", "ensemble_rows", "regime_counts", "regime_fields", "regime_line", "regime_text", "grid_points", "profile_bands", "read_run_facts", "GridPoint",
           "FIGURES_OF_MERIT", "BIAS_NOTE"]
