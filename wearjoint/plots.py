"""PNG figures of a run (matplotlib, Agg backend; imported only when figures are written)."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from .core import layout as L  # noqa: E402


# the bushing's frame and where its angle 0 points, per clearance joint (docs/reference/model.md §1): the angle
# axis of every worn-profile figure
BUSHING_FRAMES = {"crank-rod": "rod frame: 0 = towards the slider",
                  "rod-slider": "rod frame: 0 = away from the crank pin",
                  "crank-ground": "ground frame: 0 = along +X"}
# zlib's level for the PNGs: 3 encodes a run's figures in 0.7x the time of PIL's default 6, the files within 20 %
PNG_COMPRESS_LEVEL = 3


def save_figure(fig, path: Path, dpi: int = 120, lay_out: bool = True) -> None:
    """Lay out (unless ``lay_out`` is false: placed by :func:`place_axes`), write as PNG and close ``fig``."""
    if lay_out:
        fig.tight_layout()
    fig.savefig(path, dpi=dpi, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    plt.close(fig)


def place_axes(fig, left: float = 1.0, right: float = 0.25, bottom: float = 0.6, top: float = 0.25,
               wspace: float | None = None) -> None:
    """Margins of ``fig``'s axes [in], room for 7-character tick labels and an axis label: a run's figures are
    placed so, not by tight_layout, whose measuring pass of every text cost a quarter of each figure's time."""
    width, height = fig.get_size_inches()
    fig.subplots_adjust(left=left / width, right=1.0 - right / width, bottom=bottom / height,
                        top=1.0 - top / height, wspace=wspace)


def crank_rotation_deg(t, period_s):
    """Crank rotation travelled since t = 0, wrapped to [0, 360) deg."""
    return (np.asarray(t) / period_s * 360.0) % 360.0


def ideal_slider_acceleration(record) -> tuple[np.ndarray, np.ndarray]:
    """The ideal joint's slider acceleration over one revolution (:meth:`SliderCrank.ideal_slider_acceleration`)."""
    from .slider_crank import SliderCrank

    return SliderCrank(record.parameters.mechanism).ideal_slider_acceleration()


def plot_slider_acceleration(record, path: Path, ideal=None) -> None:
    """``ideal``: :func:`ideal_slider_acceleration` if already computed (a figure worker gets it so)."""
    s = record.samples
    last = s[:, L.T_TIME] > record.last_revolution() * record.period_s
    t = s[last, L.T_TIME]
    grid, ideal_m_s2 = ideal_slider_acceleration(record) if ideal is None else ideal
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(crank_rotation_deg(t, record.period_s), s[last, L.T_SLIDER_A], ".", ms=1.5, label="clearance joint")
    ax.plot(crank_rotation_deg(grid, record.period_s)[:-1], ideal_m_s2[:-1],
            "k-", lw=1.5, label="ideal joint (closed form)")
    ax.set_xlabel("crank rotation [deg] (last revolution)")
    ax.set_ylabel("slider acceleration [m/s²]")
    ax.set_xlim(0, 360)
    ax.legend(loc="upper right")
    ax.grid(alpha=0.3)
    place_axes(fig)
    save_figure(fig, path, lay_out=False)


def plot_pin_orbit(record, path: Path) -> None:
    s = record.samples
    c_um = record.clearance_m * 1e6
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    ax.plot(s[:, L.T_ECC_X] * 1e6, s[:, L.T_ECC_Y] * 1e6, lw=0.4)
    phi = np.radians(record.phi_deg)
    ax.plot((c_um + record.wear_depth_m * 1e6) * np.cos(phi), (c_um + record.wear_depth_m * 1e6) * np.sin(phi),
            "k-", lw=1, label="clearance + wear")
    ax.set_aspect("equal")
    ax.set_xlabel("eccentricity x, bushing frame [µm]")
    ax.set_ylabel("eccentricity y, bushing frame [µm]")
    ax.set_title("pin centre relative to bushing centre", y=1.0)
    ax.legend(loc="upper right", fontsize=8)
    place_axes(fig, top=0.4)
    save_figure(fig, path, lay_out=False)


def plot_contact_force(record, path: Path) -> None:
    s = record.samples
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(s[:, L.T_TIME], s[:, L.T_NORMAL_FORCE], lw=0.6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("normal contact force [N]")
    ax.grid(alpha=0.3)
    place_axes(fig)
    save_figure(fig, path, lay_out=False)


def bushing_angle_label(clearance_joint: str | None) -> str:
    """The worn profile's angle axis: the bushing's frame at ``clearance_joint`` (None: joints that differ)."""
    frame = BUSHING_FRAMES.get(clearance_joint, "each point's own clearance joint")
    return f"angle in the bushing frame [deg]\n({frame})"


def plot_wear_profiles(phi_deg, profiles: dict, path: Path, clearance_joint: str, title: str = "bushing wear") -> None:
    """Paper Fig. 7 layout: (a) polar depth, (b) depth vs bushing-frame angle (the frame of ``clearance_joint``'s
    bushing), one curve per label."""
    fig = plt.figure(figsize=(11, 4.8))
    ax_polar = fig.add_subplot(1, 2, 1, projection="polar")
    ax = fig.add_subplot(1, 2, 2)
    phi = np.radians(phi_deg)
    for label, depth in profiles.items():
        ax_polar.plot(np.r_[phi, phi[:1]], np.r_[depth, depth[:1]] * 1e6, lw=1.2, label=label)
        ax.plot(phi_deg, depth * 1e6, lw=1.2, label=label)
    ax_polar.set_title("(a) wear depth [µm], bushing frame", fontsize=10, y=1.08)
    ax_polar.yaxis.set_major_locator(MaxNLocator(3))       # the depths' labels ran together at sub-µm depths
    ax_polar.tick_params(axis="y", labelsize=7)
    ax.set_xlabel(bushing_angle_label(clearance_joint))
    ax.set_ylabel("wear depth [µm]")
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 45))
    ax.grid(alpha=0.3)
    ax.set_title("(b) wear depth vs angle", fontsize=10, y=1.0)
    ax.legend(fontsize=8)
    fig.suptitle(title)
    place_axes(fig, left=0.5, bottom=0.8, top=0.8, wspace=0.3)
    save_figure(fig, path, lay_out=False)


def run_figures(record, ideal=None) -> list[tuple[str, object]]:
    """The run's standard figures as (file name, function writing it to a path), in :func:`plot_run`'s order; no
    profile figure where the run has no worn profile (a third-party master that does not give it: NaN)."""
    figures = [("slider_acceleration.png", lambda path: plot_slider_acceleration(record, path, ideal)),
               ("pin_orbit.png", lambda path: plot_pin_orbit(record, path)),
               ("contact_force.png", lambda path: plot_contact_force(record, path))]
    if np.isfinite(record.wear_depth_m).all():
        figures.append(("wear_profile.png", lambda path: plot_wear_profiles(
            record.phi_deg, {f"after {record.revolutions:.3g} rev": record.wear_depth_m}, path,
            record.clearance_joint)))
    return figures


def plot_run(record, out: Path, ideal=None, only=None) -> list[str]:
    """Write the run's standard figures into ``out`` (``only``: the indices of :func:`run_figures` to write, those
    the run has); returns their file names (``ideal``: :func:`ideal_slider_acceleration` if already computed)."""
    out = Path(out)
    figures = run_figures(record, ideal)
    chosen = [figures[k] for k in (range(len(figures)) if only is None else only) if k < len(figures)]
    for name, draw in chosen:
        draw(out / name)
    return [name for name, _ in chosen]
