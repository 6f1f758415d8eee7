"""`wearjoint wear-study`: thousands of crank revolutions of bushing wear (paper Figs. 7-8).

Reaching thousands of revolutions (a simulated revolution of a worn bushing costs ~0.3 s with
the default RK4, ~1 s with DOPRI):

* **wear acceleration** -- the joint's ``wear_factor`` F multiplies k_w, so one
  simulated revolution stands for F crank revolutions; the snapshot at
  revolution R is taken after R/F simulated revolutions;
* **cycle jumping** (``--cycle-jump M,J``) -- after every block of M simulated
  revolutions the block's wear increment is scaled by J (profile set through
  the engine), so a block stands for M*F*J revolutions.

The final revolution count is always a snapshot.  At each snapshot the study
keeps the worn profile and the slider acceleration of the simulated revolution
ending there (Fig. 8).  An **impact event** is a cluster of samples with
|a - a_ideal| > ``impact_threshold_m_s2`` (a_ideal: closed-form ideal
slider-crank); clusters closer than ``impact_merge_deg`` of crank rotation are
one event; its size is the cluster's peak |a - a_ideal|.

Nothing is lost: every ``checkpoint_every_revolutions`` simulated revolutions
the engine state (``checkpoint()``), the study's progress and the snapshots so
far go atomically to ``DIR/wear_study_checkpoint.pkl``; ``--resume`` continues
bit-identically.  Also here: the factor-convergence study (``--convergence``)
and the calibration of an effective k_w to a target depth (``--calibrate-max-depth-m``).
"""
from __future__ import annotations

import csv
import dataclasses
import math
import os
import pickle
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wearjoint.cli_options import add_model_arguments, model_from_args
from wearjoint.core import layout as L
from wearjoint.core.contact import bushing_point_angles
from wearjoint.mechanism import SliderCrank
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters
from wearjoint.progress import Progress
from wearjoint.results import RunRecord, write_json_atomic, write_results
from wearjoint.simulate import Simulation, SimulationOptions

ENGINES = ("monolithic", "cosim")
STUDY_INTEGRATORS = ("rk4", "dopri")
DEFAULT_STUDY_INTEGRATOR = "rk4"       # fixed 1e-5 s steps with located contact onsets (README "Reproducing the paper")
DEFAULT_WEAR_FACTOR = 100.0             # chosen from the convergence study (README "Reproducing the paper")
PRINTED_WEAR_COEFFICIENT_M2_N = JointParameters().wear_coefficient_m2_N
PAPER_MAX_DEPTH_M = 0.58e-3             # Fig. 7, after 4000 revolutions
EXPERIMENT_REVOLUTIONS = (200_000, 400_000)
EXPERIMENT_MAX_DEPTH_M = (0.19e-3, 0.55e-3)
CONVERGENCE_TOLERANCE = 0.15            # max-depth and RMS profile difference, relative to the reference max depth
CHECKPOINT_NAME = "wear_study_checkpoint.pkl"
CHECKPOINT_FORMAT = 1
ARRAY_KEYS = ("wear_depth_m", "time_s", "slider_a_m_s2", "samples")   # snapshot arrays (not in summary.json)


# ----------------------------------------------------------------------------- configuration
@dataclass(frozen=True)
class WearStudyConfig:
    """One wear study.  The acceleration factor F is ``joint.wear_factor``."""

    joint: JointParameters
    mechanism: SliderCrankParameters
    revolutions: int = 4000
    snapshots: tuple = (1000, 2000, 3000, 4000)
    jump_revolutions: int = 0               # M: simulated revolutions per cycle-jump block (0: no jumping)
    jump_factor: float = 1.0                # J: the block's wear increment is scaled by J
    engine: str = "monolithic"
    integrator: str = DEFAULT_STUDY_INTEGRATOR
    max_step_s: float = 1e-5                # MODEL.md 7: wear runs need <= 1e-5 s
    chunks_per_revolution: int = 8
    checkpoint_every_revolutions: float = 1.0   # simulated revolutions between checkpoints
    impact_threshold_m_s2: float = 100.0
    impact_merge_deg: float = 15.0

    def __post_init__(self):
        _check_int("revolutions", self.revolutions, 1)
        snaps = tuple(self.snapshots)
        for s in snaps:
            _check_int("snapshots", s, 1)
            if s > self.revolutions:
                raise ParameterError(f"snapshot {s} is beyond --revolutions {self.revolutions}")
        snaps = tuple(sorted(set(snaps) | {self.revolutions}))
        object.__setattr__(self, "snapshots", snaps)
        if not self.joint.wear_factor > 0.0 or not self.joint.wear_coefficient_m2_N > 0.0:
            raise ParameterError(f"a wear study needs wear on: wear_factor={self.joint.wear_factor!r} and "
                                 f"wear_coefficient_m2_N={self.joint.wear_coefficient_m2_N!r} must be > 0")
        _check_int("jump_revolutions", self.jump_revolutions, 0)
        if not (math.isfinite(self.jump_factor) and self.jump_factor >= 1.0):
            raise ParameterError(f"cycle-jump factor J={self.jump_factor!r} is invalid: allowed a finite J >= 1")
        if self.jump_revolutions > 0:
            block = self.jump_revolutions * self.revolutions_per_simulated_revolution
            for s in snaps:
                if abs(s / block - round(s / block)) > 1e-9:
                    raise ParameterError(f"snapshot {s} is not at the end of a cycle-jump block "
                                         f"({block:g} revolutions each: M*F*J)")
        if self.engine not in ENGINES:
            raise ParameterError(f"engine {self.engine!r} is invalid: allowed one of {', '.join(ENGINES)}")
        if self.engine == "cosim" and self.jump_revolutions > 0:
            raise ParameterError("cycle jumping is not available with --engine cosim (the FMU's wear profile "
                                 "cannot be set); use --wear-factor")
        if self.integrator not in STUDY_INTEGRATORS:
            raise ParameterError(f"integrator {self.integrator!r} is invalid: allowed one of "
                                 f"{', '.join(STUDY_INTEGRATORS)}")
        for name in ("max_step_s", "checkpoint_every_revolutions", "impact_threshold_m_s2", "impact_merge_deg"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ParameterError(f"{name}={value!r} is invalid: allowed a finite value > 0")
        _check_int("chunks_per_revolution", self.chunks_per_revolution, 1)

    @property
    def revolutions_per_simulated_revolution(self) -> float:
        """F*J with cycle jumping, else F."""
        jump = self.jump_factor if self.jump_revolutions > 0 else 1.0
        return self.joint.wear_factor * jump

    @property
    def simulated_revolutions(self) -> float:
        return self.revolutions / self.revolutions_per_simulated_revolution

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        d["joint"] = self.joint.to_dict()
        d["mechanism"] = self.mechanism.to_dict()
        d["snapshots"] = list(self.snapshots)
        d["revolutions_per_simulated_revolution"] = self.revolutions_per_simulated_revolution
        return d

    def replace(self, **changes) -> "WearStudyConfig":
        return dataclasses.replace(self, **changes)


def _check_int(name, value, minimum) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ParameterError(f"{name}={value!r} is invalid: allowed an integer >= {minimum}")


def parse_int_list(name: str, text: str) -> tuple:
    """'1000,2000' -> (1000, 2000); a clear ParameterError for anything else."""
    values = []
    for item in str(text).split(","):
        item = item.strip()
        try:
            values.append(int(item))
        except ValueError:
            raise ParameterError(f"{name}: {item!r} is not an integer (expected e.g. 1000,2000)") from None
    return tuple(values)


def parse_float_list(name: str, text: str) -> tuple:
    values = []
    for item in str(text).split(","):
        try:
            values.append(float(item))
        except ValueError:
            raise ParameterError(f"{name}: {item.strip()!r} is not a number (expected e.g. 1,10,50)") from None
    return tuple(values)


# ----------------------------------------------------------------------------- engines
def make_engine(config: WearStudyConfig):
    """The simulation engine of ``config.engine``: ``Simulation`` or ``CoSimulation``
    (``advance_to``, ``checkpoint``/``restore``, ``wear_profile``, ``set_wear_profile``, ``close``)."""
    revolutions = math.ceil(config.simulated_revolutions - 1e-9)
    if config.engine == "monolithic":
        return Simulation(config.joint, config.mechanism,
                          SimulationOptions(revolutions=revolutions, integrator=config.integrator,
                                            step_s=config.max_step_s, max_step_s=config.max_step_s,
                                            sample_dt_s=1e-5))
    from wearjoint.cosim import CoSimulation, CoSimulationOptions
    return CoSimulation(config.joint, config.mechanism,
                        CoSimulationOptions(revolutions=revolutions, max_step_s=config.max_step_s, sample_dt_s=1e-5))


# ----------------------------------------------------------------------------- analysis
def profile_angles_deg(n_points: int) -> np.ndarray:
    """Rod-frame angles of the bushing points [deg], (0, 360]."""
    return np.degrees(bushing_point_angles(n_points))


def profile_features(phi_deg: np.ndarray, depth_m: np.ndarray) -> dict:
    """Max depth and its angle, the two lobes (|phi| < 90 deg and the rest), depth at 90/270 deg."""
    signed = (phi_deg + 180.0) % 360.0 - 180.0          # [-180, 180)
    near0 = np.abs(signed) < 90.0
    i0 = np.flatnonzero(near0)[np.argmax(depth_m[near0])]
    i180 = np.flatnonzero(~near0)[np.argmax(depth_m[~near0])]
    deepest = int(np.argmax(depth_m))
    return {"max_wear_depth_m": float(depth_m[deepest]),
            "max_wear_angle_deg": float(phi_deg[deepest] % 360.0),
            "lobe_0_angle_deg": float(signed[i0]), "lobe_0_depth_m": float(depth_m[i0]),
            "lobe_180_angle_deg": float(phi_deg[i180] % 360.0), "lobe_180_depth_m": float(depth_m[i180]),
            "depth_at_90_deg_m": float(np.interp(90.0, phi_deg, depth_m)),
            "depth_at_270_deg_m": float(np.interp(270.0, phi_deg, depth_m))}


def impact_events(time_s, slider_a_m_s2, mechanism: SliderCrankParameters,
                  threshold_m_s2: float, merge_deg: float) -> list[dict]:
    """Clusters of |a - a_ideal| > threshold; clusters closer than merge_deg of crank rotation merge.

    Returns one dict per event: start/end time [s], crank rotation at the peak [deg], peak |a - a_ideal|.
    """
    t = np.asarray(time_s)
    deviation = np.abs(np.asarray(slider_a_m_s2) - SliderCrank(mechanism).closed_form(t)["slider_a_m_s2"])
    above = np.flatnonzero(deviation > threshold_m_s2)
    if above.size == 0:
        return []
    merge_s = merge_deg / 360.0 * mechanism.period_s
    splits = np.flatnonzero(np.diff(t[above]) > merge_s) + 1
    events = []
    for cluster in np.split(above, splits):
        peak = cluster[np.argmax(deviation[cluster])]
        events.append({"start_s": float(t[cluster[0]]), "end_s": float(t[cluster[-1]]),
                       "peak_crank_rotation_deg": float((t[peak] / mechanism.period_s * 360.0) % 360.0),
                       "peak_deviation_m_s2": float(deviation[peak])})
    return events


def growth_exponent(revolutions, depth_m) -> float:
    """p of depth ~ revolutions**p, least squares in log-log over the points with depth > 0."""
    r, d = np.asarray(revolutions, float), np.asarray(depth_m, float)
    ok = (r > 0) & (d > 0)
    return float(np.polyfit(np.log(r[ok]), np.log(d[ok]), 1)[0]) if ok.sum() >= 2 else float("nan")


# ----------------------------------------------------------------------------- the study
def _stops(config: WearStudyConfig) -> list[tuple[float, int | None, bool]]:
    """(simulated revolution, snapshot revolution or None, cycle-jump block end) for every stop, in order."""
    n_sim = config.simulated_revolutions
    per = config.revolutions_per_simulated_revolution
    marks = {}
    for k in range(1, int(math.floor(n_sim * config.chunks_per_revolution + 1e-9)) + 1):
        marks[k / config.chunks_per_revolution] = None
    for s in config.snapshots:
        x = s / per
        near = [m for m in marks if abs(m - x) <= 1e-9 * max(1.0, x)]
        marks[near[0] if near else x] = s
    stops = []
    for x in sorted(marks):
        block_end = config.jump_revolutions > 0 and abs(x / config.jump_revolutions - round(x / config.jump_revolutions)) < 1e-9
        stops.append((x, marks[x], block_end))
    return stops


def _write_checkpoint_atomic(path: Path, state: dict) -> None:
    tmp = path.with_suffix(path.suffix + ".tmp")
    with open(tmp, "wb") as f:
        pickle.dump(state, f, protocol=pickle.HIGHEST_PROTOCOL)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def _load_checkpoint(path: Path, config: WearStudyConfig) -> dict:
    try:
        with open(path, "rb") as f:
            state = pickle.load(f)
    except (OSError, pickle.UnpicklingError, EOFError) as exc:
        raise ParameterError(f"cannot read checkpoint {path}: {exc}") from None
    if state.get("format") != CHECKPOINT_FORMAT:
        raise ParameterError(f"checkpoint {path} has an unknown format")
    if state["config"] != config.to_dict():
        old, new = state["config"], config.to_dict()
        diff = sorted(k for k in new if old.get(k) != new[k])
        raise ParameterError(f"checkpoint {path} belongs to a study with other settings ({', '.join(diff)}); "
                             "use the same options or another --out")
    return state


def run_wear_study(config: WearStudyConfig, out_dir, resume: bool = False, progress: bool = True,
                   plots: bool = True, stop_after_checkpoints: int | None = None) -> dict:
    """Run (or with ``resume`` continue) the study into ``out_dir``; returns summary.json's content.

    ``stop_after_checkpoints`` stops right after that many checkpoints were written
    in this call, as if the process were killed (tests); the result then is
    ``{"finished": False, ...}``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    ckpt_path = out / CHECKPOINT_NAME
    if ckpt_path.exists() and not resume:
        raise ParameterError(f"{out} already holds a wear study ({CHECKPOINT_NAME}); pass --resume to continue "
                             "it or choose another --out")
    state = _load_checkpoint(ckpt_path, config) if resume and ckpt_path.exists() else None
    engine = make_engine(config)
    try:
        if state is None:
            state = {"format": CHECKPOINT_FORMAT, "config": config.to_dict(), "next_stop": 0,
                     "block_start_depth_m": engine.wear_profile()[1], "snapshots": [], "pending_samples": {},
                     "growth": [], "wall_time_s": 0.0, "last_checkpoint_revolution": 0.0, "finished": False}
        else:
            engine.restore(state["engine"])
        return _advance_study(config, state, engine, out, ckpt_path, progress, plots, stop_after_checkpoints)
    finally:
        engine.close()


def _advance_study(config, state, engine, out, ckpt_path, progress, plots, stop_after_checkpoints) -> dict:
    """The study's loop over its stops (see :func:`run_wear_study`)."""
    period = config.mechanism.period_s
    stops = _stops(config)
    phi_deg = profile_angles_deg(config.joint.n_points)
    buffer = np.zeros((int(period / config.chunks_per_revolution / 1e-5) + 64, L.N_SAMPLE_COLUMNS))
    per = config.revolutions_per_simulated_revolution
    done_at_start = stops[state["next_stop"] - 1][0] * per if state["next_stop"] > 0 else 0.0
    bar = Progress(config.revolutions - done_at_start, "wear-study" + (" (resumed)" if done_at_start else ""),
                   enabled=progress, unit="rev")
    written = 0
    wall0 = time.perf_counter()
    wall_before = state["wall_time_s"]
    for i in range(state["next_stop"], len(stops)):
        sim_rev, snapshot, block_end = stops[i]
        t_stop = sim_rev * period
        n = engine.advance_to(t_stop, buffer)
        _keep_window_samples(state["pending_samples"], config, buffer[:n], period)
        _, depth, volume = engine.wear_profile()
        if block_end:
            start = state["block_start_depth_m"]
            engine.set_wear_profile(start + config.jump_factor * (depth - start))
            _, depth, volume = engine.wear_profile()
            state["block_start_depth_m"] = depth
        if config.jump_revolutions == 0 or block_end:
            state["growth"].append((sim_rev * per, float(depth.max()), volume))
        if snapshot is not None:
            samples = np.concatenate(state["pending_samples"].pop(snapshot, [np.zeros((0, L.N_SAMPLE_COLUMNS))]))
            state["snapshots"].append(_snapshot(config, snapshot, sim_rev, phi_deg, depth, volume, samples,
                                                wall_before + time.perf_counter() - wall0))
        state["next_stop"] = i + 1
        final = i + 1 == len(stops)
        if final or sim_rev - state["last_checkpoint_revolution"] >= config.checkpoint_every_revolutions - 1e-9:
            state["finished"] = final
            state["last_checkpoint_revolution"] = sim_rev
            state["wall_time_s"] = wall_before + time.perf_counter() - wall0
            state["engine"] = engine.checkpoint()
            _write_checkpoint_atomic(ckpt_path, state)
            written += 1
            if stop_after_checkpoints is not None and written >= stop_after_checkpoints and not final:
                bar.close()
                return {"finished": False, "checkpoint": str(ckpt_path)}
        bar.update(sim_rev * per - done_at_start)
    bar.close()
    return write_study_outputs(config, state, engine, out, plots)


def _keep_window_samples(pending: dict, config: WearStudyConfig, samples: np.ndarray, period: float) -> None:
    """Keep the samples inside the simulated revolution ending at each snapshot (for Fig. 8)."""
    if samples.size == 0:
        return
    t = samples[:, L.T_TIME]
    for s in config.snapshots:
        t_snap = s / config.revolutions_per_simulated_revolution * period
        inside = (t > t_snap - period * (1 + 1e-12)) & (t <= t_snap * (1 + 1e-12))
        if inside.any():
            pending.setdefault(s, []).append(samples[inside].copy())


def _snapshot(config, revolution, sim_rev, phi_deg, depth, volume, samples, wall_s) -> dict:
    events = impact_events(samples[:, L.T_TIME], samples[:, L.T_SLIDER_A], config.mechanism,
                           config.impact_threshold_m_s2, config.impact_merge_deg)
    peaks = [e["peak_deviation_m_s2"] for e in events]
    acc = samples[:, L.T_SLIDER_A]
    return {"revolution": revolution, "simulated_revolutions": sim_rev, "wall_time_s": wall_s,
            **profile_features(phi_deg, depth), "worn_volume_m3": volume,
            "impact_events": len(events), "impact_peak_max_m_s2": max(peaks, default=0.0),
            "impact_peak_mean_m_s2": float(np.mean(peaks)) if peaks else 0.0, "impact_event_list": events,
            "slider_acc_max_m_s2": float(acc.max()) if acc.size else None,
            "slider_acc_min_m_s2": float(acc.min()) if acc.size else None,
            "contact_fraction_samples": float(samples[:, L.T_CONTACT].mean()) if acc.size else None,
            "wear_depth_m": depth, "time_s": samples[:, L.T_TIME].copy(), "slider_a_m_s2": acc.copy(),
            "samples": samples if revolution == config.revolutions else None}


def _growth_assessment(growth: np.ndarray) -> dict:
    """Does the growth accelerate?  Compared with the experiment (0.19 mm at 200k, 0.55 mm at 400k)."""
    r, d = growth[:, 0], growth[:, 1]
    half = float(np.interp(r[-1] / 2.0, r, d))
    exp_ratio = EXPERIMENT_MAX_DEPTH_M[1] / EXPERIMENT_MAX_DEPTH_M[0]
    ratio = float(d[-1] / half) if half > 0 else float("nan")
    return {"depth_ratio_full_to_half": ratio,
            "growth_exponent": growth_exponent(r, d),
            "experiment_depth_ratio_full_to_half": exp_ratio,
            "experiment_growth_exponent": math.log(exp_ratio) / math.log(2.0),
            "accelerates": bool(ratio > 2.0),
            "note": "depth ~ revolutions**p; p > 1 (ratio > 2) means the growth accelerates, as in the experiment"}


def write_study_outputs(config: WearStudyConfig, state: dict, engine, out: Path, plots: bool = True) -> dict:
    """Profiles, growth curve, figures and summary.json (MODEL.md 6 keys for the final state + the study)."""
    period = config.mechanism.period_s
    phi_deg = profile_angles_deg(config.joint.n_points)
    snaps = state["snapshots"]
    for s in snaps:
        np.savetxt(out / f"profile_rev{s['revolution']}.csv", np.column_stack([phi_deg, s["wear_depth_m"]]),
                   delimiter=",", header="phi_deg,wear_depth_m", comments="", fmt="%.17g")
    growth = np.asarray(state["growth"])
    np.savetxt(out / "wear_growth.csv", growth, delimiter=",", header="revolutions,max_wear_depth_m,worn_volume_m3",
               comments="", fmt="%.10g")
    n_complete = max(1, int(config.simulated_revolutions + 1e-9))
    final = snaps[-1]
    per = config.revolutions_per_simulated_revolution
    at_sim_rev_ends = [g[1] for g in state["growth"] if abs(g[0] / per - round(g[0] / per)) < 1e-9]
    record = RunRecord(
        samples=final["samples"], revolution_stats=engine.revolution_stats[:n_complete],
        wear_growth_m=np.asarray(at_sim_rev_ends), phi_deg=phi_deg, wear_depth_m=final["wear_depth_m"],
        worn_volume_m3=final["worn_volume_m3"], simulated_time_s=config.simulated_revolutions * period,
        wall_time_s=state["wall_time_s"], revolutions=float(config.revolutions), period_s=period,
        clearance_m=config.joint.clearance_m,
        parameters={"joint": config.joint.to_dict(), "mechanism": config.mechanism.to_dict(),
                    "study": {k: v for k, v in config.to_dict().items() if k not in ("joint", "mechanism")},
                    "engine": config.engine})
    summary = write_results(record, out, plots=plots)
    summary.update({
        "simulated_revolutions": config.simulated_revolutions,
        "revolutions_per_simulated_revolution": per,
        "wear_factor": config.joint.wear_factor,
        "effective_wear_coefficient_m2_N": config.joint.wear_coefficient_m2_N,
        "printed_wear_coefficient_m2_N": PRINTED_WEAR_COEFFICIENT_M2_N,
        "wear_coefficient_ratio_to_printed": config.joint.wear_coefficient_m2_N / PRINTED_WEAR_COEFFICIENT_M2_N,
        "impact_event_definition": (f"cluster of samples with |a - a_ideal| > {config.impact_threshold_m_s2:g} m/s^2; "
                                    f"clusters closer than {config.impact_merge_deg:g} deg of crank rotation merge; "
                                    "size = the cluster's peak |a - a_ideal|"),
        "snapshots": [{k: v for k, v in s.items() if k not in ARRAY_KEYS} for s in snaps],
        "growth": _growth_assessment(growth),
        "paper_max_depth_at_4000_rev_m": PAPER_MAX_DEPTH_M,
        "experiment": {"revolutions": list(EXPERIMENT_REVOLUTIONS), "max_wear_depth_m": list(EXPERIMENT_MAX_DEPTH_M)},
        "finished": True,
    })
    if plots:
        figures = {"fig7": "fig7_wear_profiles.png", "fig8": "fig8_slider_acceleration.png",
                   "growth": "wear_growth.png"}
        from wearjoint.plots import plot_wear_profiles
        plot_wear_profiles(phi_deg, {f"{s['revolution']} rev": s["wear_depth_m"] for s in snaps},
                           out / figures["fig7"], title="Fig. 7: worn bushing profile (rod frame)")
        plot_fig8(snaps, config, out / figures["fig8"])
        plot_growth(growth, out / figures["growth"])
        summary["figures"] = summary.get("figures", []) + list(figures.values())
    write_json_atomic(out / "summary.json", summary)
    return summary


# ----------------------------------------------------------------------------- figures
def plot_fig8(snaps: list, config: WearStudyConfig, path: Path) -> None:
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


def plot_growth(growth: np.ndarray, path: Path) -> None:
    """Max depth vs revolutions, and its shape (normalised) against the experiment."""
    from wearjoint.plots import plt, save_figure

    r, d = growth[:, 0], growth[:, 1]
    fig, (ax, ax_n) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax.plot(r, d * 1e3, "-")
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [mm]")
    ax.set_title("clearance growth (simulation)", fontsize=10)
    ax.grid(alpha=0.3)
    ax_n.plot(r / r[-1], d / d[-1], "-", label="simulation")
    er, ed = np.array(EXPERIMENT_REVOLUTIONS, float), np.array(EXPERIMENT_MAX_DEPTH_M)
    ax_n.plot(np.r_[0.0, er / er[-1]], np.r_[0.0, ed / ed[-1]], "o--", label="experiment (200k, 400k rev)")
    ax_n.plot([0, 1], [0, 1], "k:", lw=1, label="linear growth")
    ax_n.set_xlabel("revolutions / final revolutions")
    ax_n.set_ylabel("max depth / final max depth")
    ax_n.set_title("shape of the growth", fontsize=10)
    ax_n.legend(fontsize=8)
    ax_n.grid(alpha=0.3)
    save_figure(fig, path)


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
    runs = {f"F={f:g}": config.replace(joint=config.joint.replace(wear_factor=f)) for f in factors}
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
            scale = ref.max()
            rows.append({"run": label, "revolution": s, "max_wear_depth_m": float(h.max()),
                         "reference_max_wear_depth_m": float(scale),
                         "max_depth_rel_diff": float(h.max() / scale - 1.0),
                         "rms_profile_diff_rel": float(np.sqrt(np.mean((h - ref) ** 2)) / scale),
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
                         jump_revolutions=0, jump_factor=1.0)
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


# ----------------------------------------------------------------------------- command line
def cli_arguments(parser) -> None:
    parser.add_argument("--out", type=Path, required=True, help="results folder (created)")
    parser.add_argument("--revolutions", default="4000", help="crank revolutions to reach (integer)")
    parser.add_argument("--snapshots", default=None,
                        help="revolutions at which to keep the profile, comma separated (default: quarters)")
    parser.add_argument("--engine", choices=ENGINES, default="monolithic", help="simulation engine")
    parser.add_argument("--cycle-jump", default=None, metavar="M,J",
                        help="after every M simulated revolutions scale their wear increment by J "
                             "(wear factor 1 unless --wear-factor is given)")
    parser.add_argument("--integrator", choices=STUDY_INTEGRATORS, default=DEFAULT_STUDY_INTEGRATOR,
                        help="rk4: fixed steps of --max-step (default); dopri: adaptive, at most --max-step")
    parser.add_argument("--max-step", type=float, default=1e-5, help="largest integration step [s] (RK4: the step)")
    parser.add_argument("--checkpoint-every", type=float, default=1.0,
                        help="simulated revolutions between checkpoints")
    parser.add_argument("--impact-threshold-m-s2", type=float, default=100.0,
                        help="impact event: |a - a_ideal| above this [m/s^2]")
    parser.add_argument("--resume", action="store_true", help="continue the study checkpointed in --out")
    parser.add_argument("--no-plots", action="store_true", help="skip the PNG figures")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    task = parser.add_argument_group("other tasks")
    task.add_argument("--convergence", default=None, metavar="F1,F2,...",
                      help="convergence study of the acceleration factors (first = reference, normally 1)")
    task.add_argument("--calibrate-max-depth-m", type=float, default=None,
                      help="find the effective k_w whose study ends at this max depth (e.g. 0.58e-3)")
    add_model_arguments(parser)


def config_from_args(args) -> WearStudyConfig:
    joint, mechanism = model_from_args(args)
    revolutions = parse_int_list("--revolutions", args.revolutions)
    if len(revolutions) != 1:
        raise ParameterError("--revolutions takes one integer")
    revolutions = revolutions[0]
    if args.snapshots is not None:
        snapshots = parse_int_list("--snapshots", args.snapshots)
    else:
        snapshots = tuple(sorted({max(1, revolutions * q // 4) for q in (1, 2, 3, 4)}))
    jump_m, jump_j = 0, 1.0
    if args.cycle_jump is not None:
        parts = args.cycle_jump.split(",")
        if len(parts) != 2:
            raise ParameterError(f"--cycle-jump {args.cycle_jump!r}: expected M,J (e.g. 2,10)")
        jump_m = parse_int_list("--cycle-jump M", parts[0])[0]
        jump_j = parse_float_list("--cycle-jump J", parts[1])[0]
        if jump_m < 1:
            raise ParameterError(f"--cycle-jump M={jump_m} is invalid: allowed an integer >= 1")
    if args.wear_factor is None and not args.no_wear:
        joint = joint.replace(wear_factor=1.0 if args.cycle_jump is not None else DEFAULT_WEAR_FACTOR)
    return WearStudyConfig(joint=joint, mechanism=mechanism, revolutions=revolutions, snapshots=snapshots,
                           jump_revolutions=jump_m, jump_factor=jump_j, engine=args.engine,
                           integrator=args.integrator, max_step_s=args.max_step,
                           checkpoint_every_revolutions=args.checkpoint_every,
                           impact_threshold_m_s2=args.impact_threshold_m_s2)


def cli_run(args) -> int:
    from wearjoint.cosim import CoSimulationError

    config = config_from_args(args)
    try:
        if args.convergence is not None:
            factors = parse_float_list("--convergence", args.convergence)
            for f in factors:
                if not (math.isfinite(f) and f > 0):
                    raise ParameterError(f"--convergence: factor {f!r} is invalid: allowed > 0")
            result = run_convergence(config, factors, args.out, resume=args.resume, progress=not args.quiet)
            for row in result["rows"]:
                print(f"  {row['run']:14s} rev {row['revolution']:6d}  max depth {row['max_wear_depth_m'] * 1e6:9.2f} µm"
                      f"  rel diff {row['max_depth_rel_diff']:+.3f}  rms rel {row['rms_profile_diff_rel']:.3f}")
            print(f"largest factor within {result['tolerance_rel']:.0%}: {result['largest_factor_within_tolerance']}")
        elif args.calibrate_max_depth_m is not None:
            result = calibrate_wear_coefficient(config, args.calibrate_max_depth_m, args.out, resume=args.resume,
                                                progress=not args.quiet)
            print(f"  printed k_w {PRINTED_WEAR_COEFFICIENT_M2_N:.3g} m^2/N wears "
                  f"{result['printed_rate']['mean_depth_per_revolution_m'] * 1e6:.3g} µm per revolution")
            print(f"  effective k_w {result['effective_wear_coefficient_m2_N']:.4g} m^2/N "
                  f"(ratio to printed {result['ratio_to_printed']:.4g}) reaches "
                  f"{result['reached_max_depth_m'] * 1e3:.4g} mm after {config.revolutions} revolutions")
        else:
            summary = run_wear_study(config, args.out, resume=args.resume, progress=not args.quiet,
                                     plots=not args.no_plots)
            for s in summary["snapshots"]:
                print(f"  rev {s['revolution']:6d}  max depth {s['max_wear_depth_m'] * 1e3:.4f} mm at "
                      f"{s['max_wear_angle_deg']:.1f} deg  lobes {s['lobe_0_angle_deg']:.1f}/"
                      f"{s['lobe_180_angle_deg']:.1f} deg  impact events {s['impact_events']}")
            print(f"  wall time {summary['wall_time_s']:.1f} s")
    except KeyboardInterrupt:
        print(f"wearjoint wear-study: interrupted; finished work is checkpointed in {args.out} "
              "(continue with --resume)", file=sys.stderr)
        return 130
    except CoSimulationError as exc:
        print(f"wearjoint wear-study: error: {exc}\nfinished work is checkpointed in {args.out}", file=sys.stderr)
        return 1
    print(f"results in {args.out}")
    return 0


__all__ = ["WearStudyConfig", "run_wear_study", "run_convergence", "calibrate_wear_coefficient",
           "printed_wear_rate", "impact_events", "profile_features", "make_engine", "cli_arguments", "cli_run"]
