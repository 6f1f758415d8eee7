"""`wearjoint wear-study`: thousands of crank revolutions of bushing wear (paper Figs. 7-8).

Reaching thousands of revolutions (a simulated revolution of a worn bushing costs ~0.3 s with the default RK4, ~1 s
with DOPRI):

* **wear acceleration** -- the joint's ``wear_factor`` F multiplies k_w, so one simulated revolution stands for F crank
  revolutions; the snapshot at revolution R is taken after R/F simulated revolutions (at least one revolution is
  simulated: F <= the revolutions);
* **cycle jumping** (the default; :mod:`wearjoint.studies.cycle_jump`) -- blocks of simulated revolutions at the real
  wear rate, each followed by a jump that replays the block's loading through the relaxed wear update, its length
  chosen from an error estimate (``--cycle-jump-tolerance``).

The final revolution count is always a snapshot.  At each snapshot the study keeps the worn profile and the slider
acceleration of the simulated revolution ending there (Fig. 8).  An **impact event** is a cluster of samples with
|a - a_ideal| > ``impact_threshold_m_s2`` (a_ideal: closed-form ideal slider-crank); clusters closer than
``impact_merge_deg`` of crank rotation are one event; its size is the cluster's peak |a - a_ideal|.  With
``life_depth_m`` the summary states the life to that max depth at the study's k_w (``life``: revolutions and hours).

Nothing is lost: every ``checkpoint_every_revolutions`` simulated revolutions the engine state (``checkpoint()``),
the study's progress and the snapshots so far go atomically to ``DIR/wear_study_checkpoint.pkl``; ``--resume``
continues bit-identically, or with other numerical settings (integrator, max step, ...) but the same physical ones.
Each snapshot's files are written as it is reached; a study that diverges writes what finished and says where to
continue from (:mod:`wearjoint.studies.wear_study_recovery`).  The factor-convergence study (``--convergence``) is in
:mod:`wearjoint.studies.wear_convergence`, the calibration of an effective k_w to a target depth
(``--calibrate-max-depth-m``) in :mod:`wearjoint.studies.wear_calibration`.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wearjoint.analysis import (IMPACT_EVENT_MERGE_DEG, IMPACT_EVENT_THRESHOLD_M_S2, impact_events,
                                revolution_row, sample_statistics)
from wearjoint.checks import RunDiverged, RunStopped, choice, finite, require, worn_through_message
from wearjoint.profile_metrics import profile_features
from wearjoint.core import layout as L
from wearjoint.core.geometry import bushing_point_angles
from wearjoint.fmu.fmi import BACKENDS, DEFAULT_BACKEND
from wearjoint.joint import StateError
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters, is_paper_case
from wearjoint.progress import Progress
from wearjoint.results import RunParameters, RunRecord, write_json_atomic, write_results
from wearjoint.runner import CheckpointingEngine, divergence
from wearjoint.simulate import DEFAULT_WEAR_STEP_SHARE, Simulation, SimulationOptions, wear_step_limit_s
from wearjoint.simulation_options import check_wear_step

from .cycle_jump import (DEFAULT_JUMP_TOLERANCE, advance_jump_study, check_route, jump_summary, new_jump_state,
                         simulated_revolution_rows, warm_up_replay)
from .wear_study_plots import EXPERIMENT_MAX_DEPTH_M, EXPERIMENT_REVOLUTIONS, growth_assessment
from .wear_study_recovery import (
    ARRAY_KEYS, CHECKPOINT_FORMAT, CHECKPOINT_NAME, StudyDiverged, checkpoint_revolution, continue_segments,
    divergence_reason, diverged_message, extend_segment, load_checkpoint, read_checkpoint, snapshot_entry,
    write_checkpoint_atomic, write_profile_csv, write_snapshot, write_snapshot_index,
)

ENGINES = ("monolithic", "cosim")
STUDY_INTEGRATORS = ("rk4", "dopri")
DEFAULT_STUDY_INTEGRATOR = "rk4"       # fixed steps (the wear-step limit) with located contact onsets
STUDY_STEP_S = 1e-5                     # RK4's step, or shorter where the wear's default share needs it
DEFAULT_WEAR_FACTOR = 1.0               # cycle jumping's blocks run at the real wear rate
PRINTED_WEAR_COEFFICIENT_M2_N = JointParameters().wear_coefficient_m2_N
PAPER_MAX_DEPTH_M = 0.58e-3             # Fig. 7, after 4000 revolutions
CONVERGENCE_TOLERANCE = 0.15            # max-depth and RMS profile difference, relative to the reference max depth
MAX_JUMP_ROUTE_STATISTICS = 5000      # simulated revolutions of a cycle-jumping study with per-revolution statistics


# ----------------------------------------------------------------------------- configuration
@dataclass(frozen=True)
class WearStudyConfig:
    """One wear study.  The acceleration factor F is ``joint.wear_factor``."""

    joint: JointParameters
    mechanism: SliderCrankParameters
    revolutions: int = 4000
    snapshots: tuple = (1000, 2000, 3000, 4000)
    jump_tolerance: float | None = DEFAULT_JUMP_TOLERANCE   # cycle jumping's local error; None: the wear factor only
    jump_block_revolutions: int = 2         # simulated revolutions of a cycle-jump block
    engine: str = "monolithic"
    integrator: str = DEFAULT_STUDY_INTEGRATOR
    max_step_s: float | None = None         # None: the wear-step limit (docs/reference/model.md §7), RK4's step
    rtol: float = SimulationOptions.rtol    # DOPRI's relative tolerance (monolithic engine)
    chunks_per_revolution: int = 8
    checkpoint_every_revolutions: float = 1.0   # simulated revolutions between checkpoints
    impact_threshold_m_s2: float = IMPACT_EVENT_THRESHOLD_M_S2
    impact_merge_deg: float = IMPACT_EVENT_MERGE_DEG
    fmu_backend: str = DEFAULT_BACKEND      # engine "cosim": the joint FMU's backend
    life_depth_m: float | None = None       # the max depth [m] whose life the summary states (None: none)

    def __post_init__(self):
        require("joint", self.joint, isinstance(self.joint, JointParameters), "a JointParameters")
        require("mechanism", self.mechanism, isinstance(self.mechanism, SliderCrankParameters),
                "a SliderCrankParameters")
        _check_int("revolutions", self.revolutions, 1)
        snaps = tuple(self.snapshots)
        for s in snaps:
            _check_int("snapshots", s, 1)
            if s > self.revolutions:
                raise ParameterError(f"parameter snapshots={s!r} is invalid: allowed <= revolutions={self.revolutions} "
                                     "(not beyond the study's end)")
        snaps = tuple(sorted(set(snaps) | {self.revolutions}))
        object.__setattr__(self, "snapshots", snaps)
        if not self.joint.wear_factor > 0.0 or not self.joint.wear_coefficient_m2_N > 0.0:
            raise ParameterError(f"a wear study needs wear on: wear_factor={self.joint.wear_factor!r} and "
                                 f"wear_coefficient_m2_N={self.joint.wear_coefficient_m2_N!r} must be > 0")
        _check_int("jump_block_revolutions", self.jump_block_revolutions, 1)
        choice("engine", self.engine, ENGINES)
        check_route(self.revolutions, self.joint.wear_factor, self.jump_tolerance, self.engine)
        choice("fmu_backend", self.fmu_backend, BACKENDS)
        choice("integrator", self.integrator, STUDY_INTEGRATORS)
        if self.max_step_s is None:     # the wear-step limit of the wear actually applied
            limit = min(STUDY_STEP_S, wear_step_limit_s(self.joint, self.mechanism, DEFAULT_WEAR_STEP_SHARE))
            if self.engine == "cosim":  # the communication step in contact: at most the adaptive scheme's default
                from wearjoint.cosim.cosimulation import DEFAULT_CONTACT_STEP_S
                limit = min(limit, DEFAULT_CONTACT_STEP_S["adaptive"])   # the scheme --engine cosim runs
            object.__setattr__(self, "max_step_s", limit)
        for name in ("max_step_s", "rtol", "checkpoint_every_revolutions", "impact_threshold_m_s2", "impact_merge_deg",
                     "life_depth_m"):
            value = getattr(self, name)
            bound = self.joint.bushing_radius_m if name == "life_depth_m" else math.inf   # worn through there
            rule = "> 0" + (f" below the bushing radius {bound:g} m" if bound < math.inf else "")
            if value is not None or name != "life_depth_m":
                require(name, value, 0.0 < finite(name, value, rule) < bound, f"a finite real number {rule}")
        _check_int("chunks_per_revolution", self.chunks_per_revolution, 1)
        check_wear_step("max_step_s", self.max_step_s, self.joint, self.mechanism)   # as the study names it

    @property
    def revolutions_per_simulated_revolution(self) -> float:
        """The wear factor F (1 with cycle jumping, whose simulated revolutions the jumps decide)."""
        return self.joint.wear_factor

    @property
    def simulated_revolutions(self) -> float:
        return self.revolutions / self.revolutions_per_simulated_revolution

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        return d | {"joint": self.joint.to_dict(), "mechanism": self.mechanism.to_dict(), "snapshots": list(self.snapshots),
                    "revolutions_per_simulated_revolution": self.revolutions_per_simulated_revolution}

    def replace(self, **changes) -> "WearStudyConfig":
        return dataclasses.replace(self, **changes)


def _check_int(name, value, minimum) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ParameterError(f"parameter {name}={value!r} is invalid: allowed an integer >= {minimum}")


# ----------------------------------------------------------------------------- engines
def make_engine(config: WearStudyConfig) -> CheckpointingEngine:
    """The simulation engine of ``config.engine``: ``Simulation`` or ``CoSimulation``."""
    revolutions = math.ceil(config.simulated_revolutions - 1e-9)
    if config.jump_tolerance is not None:     # the jumps decide how many are simulated: statistics of the first
        revolutions = min(revolutions, MAX_JUMP_ROUTE_STATISTICS)
    if config.engine == "monolithic":
        return Simulation(config.joint, config.mechanism,
                          SimulationOptions(revolutions=revolutions, integrator=config.integrator, rtol=config.rtol,
                                            step_s=config.max_step_s, max_step_s=config.max_step_s,
                                            sample_dt_s=1e-5))
    from wearjoint.cosim import CoSimulation, CoSimulationOptions
    # the communication step in contact: by default the adaptive scheme's 5 us (at the monolithic study's
    # 10 us the study through the FMU ended 4.4 % deeper after 4000 revolutions, at 5 us 0.12 %;
    # docs/explanation/wear_study.md)
    return CoSimulation(config.joint, config.mechanism,
                        CoSimulationOptions(revolutions=revolutions, scheme="adaptive", step_s=config.max_step_s,
                                            max_step_s=config.max_step_s, sample_dt_s=1e-5),
                        fmu_backend=config.fmu_backend)


def profile_angles_deg(n_points: int) -> np.ndarray:
    """Rod-frame angles of the bushing points [deg], (0, 360]."""
    return np.degrees(bushing_point_angles(n_points))


# ----------------------------------------------------------------------------- the study
def _stops(config: WearStudyConfig) -> list[tuple[float, int | None]]:
    """(simulated revolution, snapshot revolution or None) for every stop of the wear-factor route, in order."""
    n_sim = config.simulated_revolutions
    per = config.revolutions_per_simulated_revolution
    marks = {}
    for k in range(1, int(math.floor(n_sim * config.chunks_per_revolution + 1e-9)) + 1):
        marks[k / config.chunks_per_revolution] = None
    for s in config.snapshots:
        x = s / per
        near = [m for m in marks if abs(m - x) <= 1e-9 * max(1.0, x)]
        marks[near[0] if near else x] = s
    return [(x, marks[x]) for x in sorted(marks)]


def run_wear_study(config: WearStudyConfig, out_dir, resume: bool = False, progress: bool = True,
                   plots: bool = True, stop_after_checkpoints: int | None = None, command_line: str | None = None) -> dict:
    """Run (or with ``resume`` continue) the study into ``out_dir``; returns summary.json's content.  Its
    ``command_line`` (the CLI's) is kept in the checkpoint: summary.json names the one that started the study, and
    ``resumed_by`` those that continued it.

    ``resume`` may change the numerical settings (:data:`wear_study_recovery.NUMERICAL`), not the physical
    ones.  A study that diverges writes its outputs for what finished (``"status": "diverged"``) and raises
    :class:`StudyDiverged` (a :class:`RunDiverged`) saying where to continue from.
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
    state, changed = load_checkpoint(ckpt_path, config) if resume and ckpt_path.exists() else (None, [])
    if state is not None and state["finished"] and changed:     # nothing left to compute with other settings
        config, changed = config.replace(**{k: state["config"][k] for k in changed}), []
    start = time.perf_counter()
    engine = make_engine(config)
    try:
        engine.warm_up()                       # JIT compilation, timed apart from the simulation
        if config.jump_tolerance is not None:
            warm_up_replay(config.joint)
        compile_time_s = time.perf_counter() - start
        if state is None:
            state = {"format": CHECKPOINT_FORMAT, "config": config.to_dict(), "next_stop": 0, "snapshots": [],
                     "pending_samples": {}, "growth": [], "wall_time_s": 0.0, "last_checkpoint_revolution": 0.0,
                     "finished": False, "command_line": command_line}
            if config.jump_tolerance is not None:
                state["jump"] = new_jump_state(config)
        else:
            _restore(engine, state["engine"], keep_numerics=bool({"integrator", "max_step_s", "rtol"} & {*changed}))
            if command_line is not None:
                state["resumed_by"] = [*state.get("resumed_by", []), command_line]
        if not state["finished"]:
            state["config"] = config.to_dict()     # the settings it continues with (the segments keep the history)
            continue_segments(state, state["config"])
            write_snapshot_index(out, config, state, "running")
        advance = _advance_jump_route if config.jump_tolerance is not None else _advance_study
        try:
            return advance(config, state, engine, out, ckpt_path, progress, plots, stop_after_checkpoints,
                           compile_time_s)
        except (RunStopped, StateError) as exc:     # StateError: a profile out of range (set by a jump)
            failure = str(exc) if isinstance(exc, RunStopped) else (
                f"the bushing wore through ({exc})" if "deeper than the bushing radius" in str(exc) else
                f"the state left its range ({exc})")
            raise _diverged(config, state, engine, out, ckpt_path, plots, compile_time_s, failure) from None
    finally:
        engine.close()


def _restore(engine, checkpoint: dict, keep_numerics: bool) -> None:
    """Restore the engine's state; with other numerical settings, keep the step control of this engine's
    (the checkpoint's holds the other integrator's step)."""
    control = getattr(engine, "control", None)
    fresh = control.copy() if control is not None else None
    engine.restore(checkpoint)
    if keep_numerics and fresh is not None:
        engine.control[:] = fresh


def _advance_study(config, state, engine, out, ckpt_path, progress, plots, stop_after_checkpoints,
                   compile_time_s) -> dict:
    """The wear-factor route's loop over its stops (see :func:`run_wear_study`)."""
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
    try:
        for i in range(state["next_stop"], len(stops)):
            sim_rev, snapshot = stops[i]
            t_stop = sim_rev * period
            n = engine.advance_to(t_stop, buffer)
            failure = divergence(engine, buffer[:n], config.joint)
            if failure:
                raise RunDiverged(failure)
            _keep_window_samples(state["pending_samples"], config, buffer[:n], period)
            _, depth, volume = engine.wear_profile()
            _check_not_worn_through(config, float(depth.max()), sim_rev * per)
            state["growth"].append((sim_rev * per, float(depth.max()), volume))
            if snapshot is not None:
                samples = np.concatenate(state["pending_samples"].pop(snapshot, [np.zeros((0, L.N_SAMPLE_COLUMNS))]))
                _keep_snapshot(config, state, out, phi_deg, _snapshot(
                    config, snapshot, sim_rev, phi_deg, depth, volume, samples,
                    wall_before + time.perf_counter() - wall0, engine.revolution_stats), sim_rev * per)
            state["next_stop"] = i + 1
            final = i + 1 == len(stops)
            if final or sim_rev - state["last_checkpoint_revolution"] >= config.checkpoint_every_revolutions - 1e-9:
                state["finished"] = final
                state["last_checkpoint_revolution"] = sim_rev
                state["wall_time_s"] = wall_before + time.perf_counter() - wall0
                state["engine"] = engine.checkpoint()
                extend_segment(state, sim_rev * per)
                write_checkpoint_atomic(ckpt_path, state)
                write_snapshot_index(out, config, state, "running", checkpointed_revolution=sim_rev * per)
                written += 1
                if stop_after_checkpoints is not None and written >= stop_after_checkpoints and not final:
                    return {"finished": False, "checkpoint": str(ckpt_path)}
            bar.update(sim_rev * per - done_at_start)
    finally:
        bar.close()
    return write_study_outputs(config, state, engine, out, plots, compile_time_s)


def _advance_jump_route(config, state, engine, out, ckpt_path, progress, plots, stop_after_checkpoints,
                        compile_time_s) -> dict:
    """The cycle-jumping route (:func:`wearjoint.studies.cycle_jump.advance_jump_study`), checkpointed after
    every block and its jump."""
    phi_deg = profile_angles_deg(config.joint.n_points)
    wall0, wall_before = time.perf_counter(), state["wall_time_s"]
    written = []

    def keep_snapshot(revolution, simulated, samples):
        _, depth, volume = engine.wear_profile()
        _keep_snapshot(config, state, out, phi_deg, _snapshot(config, revolution, simulated, phi_deg, depth, volume,
                                                              samples, wall_before + time.perf_counter() - wall0,
                                                              engine.revolution_stats), revolution)

    def checkpoint() -> bool:
        _check_not_worn_through(config, engine.max_wear_depth_m(), state["jump"]["revolution"])
        state["finished"] = state["jump"]["revolution"] >= config.revolutions
        state["wall_time_s"] = wall_before + time.perf_counter() - wall0
        state["engine"] = engine.checkpoint()
        extend_segment(state, state["jump"]["revolution"])
        write_checkpoint_atomic(ckpt_path, state)
        write_snapshot_index(out, config, state, "running", checkpointed_revolution=state["jump"]["revolution"])
        written.append(1)
        return state["finished"] or stop_after_checkpoints is None or len(written) < stop_after_checkpoints

    if not advance_jump_study(config, state, engine, keep_snapshot, checkpoint, progress):
        return {"finished": False, "checkpoint": str(ckpt_path)}
    return write_study_outputs(config, state, engine, out, plots, compile_time_s)


def _keep_snapshot(config, state, out, phi_deg, snapshot: dict, revolution: float) -> None:
    """A snapshot into the state, and its files and entry on disk now (a study killed later keeps them)."""
    state["snapshots"].append(snapshot)
    extend_segment(state, revolution)
    write_snapshot(out, phi_deg, snapshot)
    write_snapshot_index(out, config, state, "running")


def _check_not_worn_through(config, max_depth_m: float, revolution: float) -> None:
    """A profile deeper than the bushing's radius is no state to go on from (nor to checkpoint)."""
    if not max_depth_m < config.joint.bushing_radius_m:
        raise RunDiverged(worn_through_message(f"by revolution {revolution:.6g}", max_depth_m,
                                               config.joint.bushing_radius_m))


def _diverged(config, state, engine, out, ckpt_path, plots, compile_time_s, failure: str) -> StudyDiverged:
    """Write the outputs of what finished: the snapshots and growth reached, the final-state files at the last
    good checkpoint (the engine restored to it); the error to raise, one line."""
    period = config.mechanism.period_s
    reached_time = float(engine.t)
    good = read_checkpoint(ckpt_path) if ckpt_path.exists() else None
    try:
        if good is not None:
            engine.restore(good["engine"])
    except StateError:          # a checkpoint of an earlier version, worn through: none to continue from
        good = None
    final = engine if good is not None else make_engine(config)   # no checkpoint: the final state is the start
    last_good = checkpoint_revolution(good) if good is not None else None
    if config.jump_tolerance is None:
        reached = reached_time / period * config.revolutions_per_simulated_revolution
    else:   # checkpoints follow every block and its jump: the failing block started at the last one
        base = good["jump"] if good is not None else new_jump_state(config)
        reached = base["revolution"] + reached_time / period - base["simulated_revolutions"]
    reached = round(reached, 9)
    message = diverged_message(config, out, reached, reached_time, divergence_reason(failure), last_good)
    ending = {"status": "worn through" if "wore through" in message else "diverged", "failure": message,
              "reached_revolution": reached, "reached_simulated_time_s": reached_time,
              "last_good_checkpoint_revolution": last_good, "final_state_revolution": last_good or 0.0}
    try:
        summary = write_study_outputs(config, state, final, out, plots, compile_time_s, ending)
    finally:
        if final is not engine:
            final.close()
    return StudyDiverged(message, summary)


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


def snapshot_statistics(stats: np.ndarray, sim_rev: float) -> dict:
    """A snapshot's slider acceleration extremes: those of revolutions.csv's row of the last simulated
    revolution complete at the snapshot (the one ending there; ``statistics_revolution``, its ``revolution``
    column), over every accepted step as the per-revolution statistics take them (the samples, every
    1e-5 s, miss the peaks of impacts); None where the run keeps no statistics of that revolution (the
    cycle-jumping route beyond MAX_JUMP_ROUTE_STATISTICS simulated revolutions)."""
    index = math.floor(sim_rev + 1e-9) - 1
    row = revolution_row(stats, index)
    return {"statistics_revolution": index if row else None,
            "slider_acc_max_m_s2": row.get("slider_acc_max_m_s2"), "slider_acc_min_m_s2": row.get("slider_acc_min_m_s2")}


def _snapshot(config, revolution, sim_rev, phi_deg, depth, volume, samples, wall_s, stats) -> dict:
    events = impact_events(samples[:, L.T_TIME], samples[:, L.T_SLIDER_A], config.mechanism,
                           config.impact_threshold_m_s2, config.impact_merge_deg)
    peaks = [e["peak_deviation_m_s2"] for e in events]
    return {"revolution": revolution, "simulated_revolutions": sim_rev, "wall_time_s": wall_s,
            **profile_features(phi_deg, depth), "worn_volume_m3": volume,
            "impact_events": len(events), "impact_peak_max_m_s2": max(peaks, default=0.0),
            "impact_peak_mean_m_s2": float(np.mean(peaks)) if peaks else 0.0, "impact_event_list": events,
            "contact_fraction_samples": sample_statistics(samples)["contact_fraction_samples"],
            **snapshot_statistics(stats, sim_rev),
            "wear_depth_m": depth, "time_s": samples[:, L.T_TIME].copy(),
            "slider_a_m_s2": samples[:, L.T_SLIDER_A].copy(),
            "samples": samples if revolution == config.revolutions else None}


def write_study_outputs(config: WearStudyConfig, state: dict, engine, out: Path, plots: bool = True,
                        compile_time_s: float = 0.0, ending: dict | None = None) -> dict:
    """Profiles, growth curve, figures and summary.json (docs/reference/results.md §6 keys for the final state + the study).

    ``ending`` (a diverged study, :func:`_diverged`): its status and where it stopped; the final state is then
    the engine's (restored to the last good checkpoint), the snapshots and growth those reached."""
    period = config.mechanism.period_s
    phi_deg = profile_angles_deg(config.joint.n_points)
    snaps = state["snapshots"]
    for s in snaps:
        write_profile_csv(out / f"profile_rev{s['revolution']}.csv", phi_deg, s["wear_depth_m"])
    growth = np.asarray(state["growth"], dtype=float).reshape(-1, 3)
    np.savetxt(out / "wear_growth.csv", growth, delimiter=",", header="revolutions,max_wear_depth_m,worn_volume_m3",
               comments="", fmt="%.10g")
    jumping = "jump" in state
    if ending is None:
        simulated = state["jump"]["simulated_revolutions"] if jumping else config.simulated_revolutions
        revolutions, samples = float(config.revolutions), snaps[-1]["samples"]
        depth, volume = snaps[-1]["wear_depth_m"], snaps[-1]["worn_volume_m3"]
    else:
        simulated = engine.t / period
        revolutions, samples = ending["final_state_revolution"], np.zeros((0, L.N_SAMPLE_COLUMNS))
        _, depth, volume = engine.wear_profile()
    n_complete = max(1, int(simulated + 1e-9))
    per = config.revolutions_per_simulated_revolution if not jumping else revolutions / max(simulated, 1e-300)
    numbers, at_sim_rev_ends = simulated_revolution_rows(state, per, n_complete)     # revolutions.csv's
    record = RunRecord(
        samples=samples, revolution_stats=engine.revolution_stats[:n_complete], revolution_numbers=numbers,
        wear_growth_m=np.asarray(at_sim_rev_ends), phi_deg=phi_deg, wear_depth_m=depth,
        worn_volume_m3=volume, simulated_time_s=simulated * period,
        wall_time_s=state["wall_time_s"], compile_time_s=compile_time_s, revolutions=revolutions,
        period_s=period,
        clearance_m=config.joint.clearance_m, contact_stiffness_N_m1_5=config.joint.stiffness_N_m1_5,
        parameters=RunParameters(config.engine, config.joint, config.mechanism, "study",
                                 {k: v for k, v in config.to_dict().items() if k not in ("joint", "mechanism")}),
        completed=ending is None, failure=ending["failure"] if ending else "",
        left_out_rows=tuple(range(1, n_complete - 1)),    # the final state's extremes: its last revolution's
        impact_threshold_m_s2=config.impact_threshold_m_s2, impact_merge_deg=config.impact_merge_deg)
    summary = write_results(record, out, plots=plots and ending is None)
    from .calibration import study_life      # its fits import scipy's optimize and stats: not at the study's import
    status, paper = ending["status"] if ending else "finished", is_paper_case(config.joint, config.mechanism)
    summary.update({
        "status": status,
        "simulated_revolutions": simulated,
        "revolutions_per_simulated_revolution": per,
        "wear_factor": config.joint.wear_factor,
        "effective_wear_coefficient_m2_N": config.joint.wear_coefficient_m2_N,
        "printed_wear_coefficient_m2_N": PRINTED_WEAR_COEFFICIENT_M2_N,
        "wear_coefficient_ratio_to_printed": config.joint.wear_coefficient_m2_N / PRINTED_WEAR_COEFFICIENT_M2_N,
        "snapshots": [snapshot_entry(s) for s in snaps],
        "growth": growth_assessment(growth, paper) if len(growth) > 1 else None,
        **study_life(growth, config.joint.wear_coefficient_m2_N, config.life_depth_m, config.mechanism.crank_speed_rpm),
        "numerical_settings": state["numerical_settings"],
        **({"command_line": state.get("command_line"), "resumed_by": state["resumed_by"]}   # absent through the API
           if state.get("resumed_by") else {}),
        **({"paper_max_depth_at_4000_rev_m": PAPER_MAX_DEPTH_M,      # the paper's mechanism only
            "experiment": {"revolutions": list(EXPERIMENT_REVOLUTIONS),
                           "max_wear_depth_m": list(EXPERIMENT_MAX_DEPTH_M)}} if paper else {}),
        "finished": ending is None,
        **({k: v for k, v in ending.items() if k not in ("status", "failure")} if ending else {}),
    })
    if jumping:
        summary["cycle_jumping"] = jump_summary(config, state)
    if plots:
        from .wear_study_plots import plot_study
        summary["figures"] = summary.get("figures", []) + plot_study(phi_deg, snaps, growth, config, out, paper)
    write_json_atomic(out / "summary.json", summary)
    write_snapshot_index(out, config, state, status)
    return summary


__all__ = ["WearStudyConfig", "run_wear_study", "snapshot_statistics", "make_engine", "profile_angles_deg", "write_study_outputs",
           "StudyDiverged", "CHECKPOINT_NAME", "CHECKPOINT_FORMAT", "ARRAY_KEYS"]
