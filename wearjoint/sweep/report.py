"""A sweep's ensemble statistics and figures, from the rows of its cases (``SweepFolder.table``).

``ensemble.csv``: one row per grid point -- its swept values, ``n_ok``/``n_failed``/``n_pending``
and, for every summary figure, ``_mean``, ``_std`` (sample standard deviation, n - 1; empty
with one seed), ``_min``, ``_max`` over the point's ``ok`` seeds.  ``bands/pointK_LABEL.csv``:
the worn profile's mean, std, min and max per bushing point (LABEL ``final``, and ``revR`` per
wear-study snapshot).  Figures: ``vs_PARAMETER.png`` (each figure of merit against each swept
parameter, mean with the +-std band and every seed), ``profile_bands_N.png`` (the final worn
profile per grid point), and for wear studies ``fig7_bands_pointK.png`` (paper Fig. 7 with bands).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from .runner import LEAD_COLUMNS, PENDING, TAIL_COLUMNS, write_csv_atomic

FIGURES_OF_MERIT = ("max_wear_depth_m", "worn_volume_m3", "max_contact_force_N", "contact_fraction",
                    "impacts_per_revolution", "slider_acc_min_m_s2", "slider_acc_max_m_s2", "max_eccentricity_m")
PANELS_PER_PAGE = 16
_PROFILE = re.compile(r"^profile(?:_rev(\d+))?\.csv$")


class GridPoint:
    """The rows of one grid point's cases (its seeds) and its swept values (``names`` -> value)."""

    def __init__(self, rows: list[dict], names: list[str]):
        self.rows = rows
        self.values = {name: rows[0][name] for name in names}
        self.ok = [r for r in rows if r["status"] == "ok"]

    @property
    def label(self) -> str:
        return ", ".join(f"{name}={value:g}" if isinstance(value, float) else f"{name}={value}"
                         for name, value in self.values.items()) or "base case"


def grid_points(rows: list[dict], names: list[str]) -> list[GridPoint]:
    """The rows grouped by grid point (equal values in the columns ``names``), in design order."""
    groups = {}
    for row in rows:
        groups.setdefault(tuple(row[name] for name in names), []).append(row)
    return [GridPoint(members, names) for members in groups.values()]


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def ensemble_rows(points: list[GridPoint]) -> list[dict]:
    """ensemble.csv's rows (see the module docstring)."""
    out = []
    for k, point in enumerate(points):
        ok = point.ok
        pending = sum(r["status"] == PENDING for r in point.rows)
        skip = set(LEAD_COLUMNS) | set(TAIL_COLUMNS) | set(point.values)
        row = {"point": k, **point.values, "n_ok": len(ok), "n_failed": len(point.rows) - len(ok) - pending,
               "n_pending": pending}
        columns = dict.fromkeys(c for r in ok for c, v in r.items() if c not in skip and _number(v))
        for column in columns:
            values = np.array([r[column] for r in ok if _number(r.get(column))], dtype=float)
            values = values[np.isfinite(values)]
            if values.size == 0:
                continue
            row[f"{column}_mean"] = float(values.mean())
            row[f"{column}_std"] = float(values.std(ddof=1)) if values.size > 1 else ""
            row[f"{column}_min"] = float(values.min())
            row[f"{column}_max"] = float(values.max())
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
    """profile_bands_N.png: the final worn profile (mean +- std over seeds, min-max shaded light)
    of each grid point, up to PANELS_PER_PAGE panels a page."""
    from ..plots import plt, save_figure

    keys = [k for k in range(len(points)) if "final" in bands.get(k, {})]
    names = []
    for page, start in enumerate(range(0, len(keys), PANELS_PER_PAGE), start=1):
        chunk = keys[start:start + PANELS_PER_PAGE]
        ncols = min(4, len(chunk))
        nrows = math.ceil(len(chunk) / ncols)
        fig, axes = plt.subplots(nrows, ncols, figsize=(3.6 * ncols + 0.8, 2.8 * nrows + 0.6), squeeze=False,
                                 sharex=True)
        for ax, k in zip(axes.ravel(), chunk):
            phi, depth = bands[k]["final"]
            ax.fill_between(phi, depth.min(axis=0) * 1e6, depth.max(axis=0) * 1e6, color="0.85", lw=0)
            _band(ax, phi, depth, 1e6)
            ax.set_title(f"{points[k].label} ({len(depth)} seeds)", fontsize=8)
            ax.set_xlim(0, 360)
            ax.set_xticks(range(0, 361, 90))
            ax.grid(alpha=0.3)
        for ax in axes.ravel()[len(chunk):]:
            ax.set_visible(False)
        for ax in axes[:, 0]:
            ax.set_ylabel("wear depth [µm]")
        for ax in axes[-1]:
            ax.set_xlabel("rod-frame angle [deg]")
        fig.suptitle("worn profile: mean ± std over seeds (grey: min-max)", fontsize=10)
        names.append(f"profile_bands_{page}.png")
        save_figure(fig, out / names[-1])
    return names


def plot_fig7_bands(out: Path, points, bands: dict) -> list[str]:
    """fig7_bands_pointK.png: the wear-study snapshots' profiles, mean +- std over seeds."""
    from ..plots import plt, save_figure

    names = []
    for k, by_label in bands.items():
        snaps = sorted((int(label[3:]), label) for label in by_label if label.startswith("rev"))
        if not snaps:
            continue
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for revolution, label in snaps:
            phi, depth = by_label[label]
            _band(ax, phi, depth, 1e6, label=f"{revolution} rev")
        ax.set_xlabel("angle in the rod frame [deg] (0 = towards the slider)")
        ax.set_ylabel("wear depth [µm]")
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 45))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        n = len(by_label[snaps[0][1]][1])
        ax.set_title(f"Fig. 7 with bands: mean ± std over {n} seeds ({points[k].label})", fontsize=10)
        names.append(f"fig7_bands_point{k}.png")
        save_figure(fig, out / names[-1])
    return names


def plot_against_parameters(out: Path, points: list[GridPoint]) -> list[str]:
    """vs_PARAMETER.png: each figure of merit against each swept parameter; one line per
    combination of the other swept parameters (mean, +-std band, every seed as a dot)."""
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
            for others, members_at in lines.items():
                xs, means, stds = [], [], []
                label = ", ".join(f"{p}={v:g}" if isinstance(v, float) else f"{p}={v}" for p, v in others) or None
                color = None
                for x, point in sorted(members_at, key=lambda item: item[0]):
                    ys = np.array([r[merit] for r in point.ok if _number(r.get(merit))], dtype=float)
                    if ys.size == 0:
                        continue
                    dots = ax.plot(np.full(ys.size, x), ys, ".", ms=3, alpha=0.5, color=color)
                    color = dots[0].get_color()
                    xs.append(x)
                    means.append(ys.mean())
                    stds.append(ys.std(ddof=1) if ys.size > 1 else 0.0)
                if xs:
                    xs, means, stds = map(np.asarray, (xs, means, stds))
                    ax.plot(xs, means, "-", color=color, lw=1.2, label=label)
                    ax.fill_between(xs, means - stds, means + stds, color=color, alpha=0.2, lw=0)
            ax.set_title(merit, fontsize=9)
            ax.set_xlabel(param, fontsize=8)
            if not numeric:
                ax.set_xticks(range(len(values)), [str(v) for v in values])
            ax.grid(alpha=0.3)
        for ax in axes.ravel()[len(merits):]:
            ax.set_visible(False)
        if any(label for label in lines) and len(lines) > 1:
            axes[0, 0].legend(fontsize=6)
        fig.suptitle(f"figures of merit against {param}: mean ± std over seeds (dots: seeds)", fontsize=10)
        names.append(f"vs_{param}.png")
        save_figure(fig, out / names[-1])
    return names


def write_reports(out: Path, rows: list[dict], names: list[str], plots: bool = True) -> dict:
    """ensemble.csv, the profile bands and (``plots``) the figures from ``rows`` (every case's, in
    design order; ``names``: the swept values' columns); returns their file names."""
    out = Path(out)
    points = grid_points(rows, names)
    ensemble = ensemble_rows(points)
    write_csv_atomic(out / "ensemble.csv", ensemble, lead=("point", *names, "n_ok", "n_failed", "n_pending"))
    bands = profile_bands(out, points)
    figures = []
    if plots and any(point.ok for point in points):
        figures = (plot_against_parameters(out, points) + plot_profile_bands(out, points, bands)
                   + plot_fig7_bands(out, points, bands))
    return {"ensemble": ensemble, "figures": figures}


__all__ = ["write_reports", "ensemble_rows", "grid_points", "profile_bands", "GridPoint", "FIGURES_OF_MERIT"]
