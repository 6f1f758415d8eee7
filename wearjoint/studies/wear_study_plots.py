"""The wear study's figures beyond the profiles: Fig. 8 (slider acceleration at each snapshot) and the
growth curve against the experiment's shape, and that shape in numbers
(:mod:`wearjoint.studies.wear_study`)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from wearjoint.profile_metrics import growth_exponent
from wearjoint.slider_crank import SliderCrank

EXPERIMENT_REVOLUTIONS = (200_000, 400_000)
EXPERIMENT_MAX_DEPTH_M = (0.19e-3, 0.55e-3)
def growth_assessment(growth: np.ndarray, paper: bool = True) -> dict:
    """Does the growth accelerate?  With ``paper`` (the paper's mechanism and joint,
    :func:`wearjoint.parameters.is_paper_case`) compared with its experiment (0.19 mm at 200k,
    0.55 mm at 400k); other mechanisms have no experiment to compare with."""
    r, d = growth[:, 0], growth[:, 1]
    half = float(np.interp(r[-1] / 2.0, r, d))
    ratio = float(d[-1] / half) if half > 0 else float("nan")
    out = {"depth_ratio_full_to_half": ratio,
           "growth_exponent": growth_exponent(r, d),
           "late_rate_m_per_1000_rev": float((d[-1] - half) / (r[-1] / 2.0) * 1000.0) if r[-1] > 0 else None}
    if paper:
        exp_ratio = EXPERIMENT_MAX_DEPTH_M[1] / EXPERIMENT_MAX_DEPTH_M[0]
        out.update({"experiment_depth_ratio_full_to_half": exp_ratio,
                    "experiment_growth_exponent": math.log(exp_ratio) / math.log(2.0)})
    note = "depth ~ revolutions**p; p > 1 (ratio > 2) means the growth accelerates"
    return {**out, "accelerates": bool(ratio > 2.0), "note": note + (", as in the experiment" if paper else "")}


def plot_study(phi_deg: np.ndarray, snaps: list, growth: np.ndarray, config, out: Path, paper: bool = True) -> list:
    """The study's figures (those its snapshots and growth allow: a diverged study may have neither;
    the experiment's growth only on the paper's mechanism, ``paper``); returns their file names."""
    from wearjoint.plots import plot_wear_profiles

    figures = []
    if snaps:
        plot_wear_profiles(phi_deg, {f"{s['revolution']} rev": s["wear_depth_m"] for s in snaps},
                           out / "fig7_wear_profiles.png", config.mechanism.clearance_joint,
                           title="Fig. 7: worn bushing profile")
        plot_fig8(snaps, config, out / "fig8_slider_acceleration.png")
        figures += ["fig7_wear_profiles.png", "fig8_slider_acceleration.png"]
    if len(growth) > 1:
        plot_growth(growth, out / "wear_growth.png", paper)
        figures.append("wear_growth.png")
    return figures


def plot_fig8(snaps: list, config, path: Path) -> None:
    """Slider acceleration over the simulated revolution ending at each snapshot, impact events shaded."""
    from wearjoint.plots import crank_rotation_deg, plt, save_figure

    period = config.mechanism.period_s
    grid = np.linspace(0.0, period, 721)
    ideal = SliderCrank(config.mechanism).closed_form(grid)["slider_a_m_s2"]
    fig, axes = plt.subplots(len(snaps), 1, figsize=(8, 2.2 * len(snaps) + 0.6), sharex=True, squeeze=False)
    for ax, s in zip(axes[:, 0], snaps):
        ax.plot(crank_rotation_deg(s["time_s"], period), s["slider_a_m_s2"], ".", ms=1.0)
        ax.plot(crank_rotation_deg(grid, period)[:-1], ideal[:-1], "k-", lw=1.2)
        for e in s["impact_event_list"]:
            a, b = crank_rotation_deg(np.array([e["start_s"], e["end_s"]]), period)
            spans = [(a, b)] if b >= a else [(a, 360.0), (0.0, b)]
            for lo, hi in spans:
                ax.axvspan(lo, max(hi, lo + 1.0), color="red", alpha=0.15)
        ax.set_title(f"after {s['revolution']} rev: {s['impact_events']} impact events, "
                     f"largest |a - a_ideal| = {s['impact_peak_max_m_s2']:.0f} m/s$^2$", fontsize=9)
        ax.set_ylabel("a [m/s$^2$]")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("crank rotation [deg] (simulated revolution ending at the snapshot; black: ideal joint)")
    axes[-1, 0].set_xlim(0, 360)
    fig.suptitle("Fig. 8: slider acceleration at each wear level (red: impact events)", fontsize=10)
    save_figure(fig, path)


def plot_growth(growth: np.ndarray, path: Path, paper: bool = True) -> None:
    """Max depth vs revolutions, and its shape (normalised; ``paper``: against the experiment)."""
    from wearjoint.plots import plt, save_figure

    r, d = growth[:, 0], growth[:, 1]
    fig, (ax, ax_n) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax.plot(r, d * 1e3, "-")
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [mm]")
    ax.set_title("clearance growth (simulation)", fontsize=10)
    ax.grid(alpha=0.3)
    ax_n.plot(r / r[-1], d / d[-1], "-", label="simulation")
    if paper:
        er, ed = np.array(EXPERIMENT_REVOLUTIONS, float), np.array(EXPERIMENT_MAX_DEPTH_M)
        ax_n.plot(np.r_[0.0, er / er[-1]], np.r_[0.0, ed / ed[-1]], "o--", label="experiment (200k, 400k rev)")
    ax_n.plot([0, 1], [0, 1], "k:", lw=1, label="linear growth")
    ax_n.set_xlabel("revolutions / final revolutions")
    ax_n.set_ylabel("max depth / final max depth")
    ax_n.set_title("shape of the growth", fontsize=10)
    ax_n.legend(fontsize=8)
    ax_n.grid(alpha=0.3)
    save_figure(fig, path)


__all__ = ["growth_assessment", "plot_study", "plot_fig8", "plot_growth", "EXPERIMENT_REVOLUTIONS",
           "EXPERIMENT_MAX_DEPTH_M"]
