"""The run pipeline every engine goes through: :class:`Engine`, the chunked run loop and the run's record.

The engines: :class:`wearjoint.simulate.Simulation` (monolithic), :class:`wearjoint.cosim.CoSimulation`
(the joint FMU's co-simulation) and :class:`wearjoint.cosim.model_exchange.ModelExchangeSimulation` (its
Model Exchange); each ``run_*`` function is :func:`run_engine` on one of them.
"""
from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np

from . import analysis
from .core import layout as L
from .checks import RunStopped, require, worn_through_message
from .interrupts import INTERRUPTED, writing_results
from .parameters import JointParameters
from .progress import Progress
from .results import RunParameters, RunRecord


class Engine(Protocol):
    """What :func:`run_engine` runs."""
    t: float                           # the engine's time [s]
    revolution_stats: np.ndarray       # (revolutions + 1, layout.N_STATS), filled as it advances

    @property
    def joint_parameters(self) -> JointParameters: ...

    def warm_up(self) -> None:
        """Compile what :meth:`advance_to` runs, without advancing."""

    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        """Advance to ``t_end`` [s], writing rows (layout.T_*) into ``samples``; returns how many."""

    def max_wear_depth_m(self) -> float: ...

    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) of the bushing, copies."""

    def describe(self) -> tuple[RunParameters, dict]:
        """The run record's ``parameters`` (what ran) and ``extra`` (its counters)."""

    def close(self) -> None:
        """Free what the engine holds (an FMU instance)."""


class CheckpointingEngine(Engine, Protocol):
    """An :class:`Engine` the wear study drives through its own loop of stops (snapshots, checkpoints, cycle
    jumps: :mod:`wearjoint.studies.wear_study`): the monolithic and the co-simulation engine."""

    def checkpoint(self) -> dict:
        """Everything needed to continue bit-identically (picklable)."""

    def restore(self, checkpoint: dict) -> None: ...

    def set_wear_profile(self, depth_m) -> None:
        """Replace the bushing's wear depths [m] (a cycle jump); ParameterError where the engine cannot."""


@dataclass
class ChunkedRun:
    engine: Any                  # the engine that ran (the caller closes it)
    samples: np.ndarray          # (n, layout.N_SAMPLE_COLUMNS)
    wear_growth_m: np.ndarray    # max wear depth after each complete revolution
    wall_time_s: float           # the simulation itself, compilation excluded
    compile_time_s: float        # building the engine (FMU load and instantiation) and JIT compilation
    completed: bool              # False if Ctrl-C stopped the run, or it diverged
    failure: str = ""            # why the run stopped early ('' if it completed)


def run_engine(make_engine: Callable[[], Engine], revolutions: float, period_s: float, sample_dt_s: float,
               label: str, progress: bool = True, chunks_per_revolution: int = 8) -> RunRecord:
    """Run the engine ``make_engine()`` builds for ``revolutions`` crank revolutions (:func:`run_in_chunks`),
    its record (:func:`record_run`, with the engine's :meth:`~Engine.describe`); the engine is closed."""
    run = run_in_chunks(make_engine, revolutions, period_s, sample_dt_s, label, progress, chunks_per_revolution)
    try:
        parameters, extra = run.engine.describe()
        return record_run(run, run.engine.revolution_stats, revolutions, period_s, run.engine.joint_parameters,
                          parameters, extra)
    finally:
        run.engine.close()


# the share of this machine's memory a run's time series may take: run_in_chunks keeps it whole, and its final
# concatenation holds it twice
TIME_SERIES_MEMORY_SHARE = 0.25


def check_time_series_fits(revolutions: float, period_s: float, row_dt_s: float,
                           row_doubles: int = L.N_SAMPLE_COLUMNS, rows: str = "sample_dt_s",
                           remedy: str = "a longer sample_dt_s (--sample-dt), or wear-study for thousands of "
                                         "revolutions") -> None:
    """ParameterError naming ``revolutions`` where the time series of that many revolutions (``row_doubles``
    doubles every ``row_dt_s``: ``rows`` says what sets it) would take more than TIME_SERIES_MEMORY_SHARE of this
    machine's memory: a clear refusal before the run, instead of a failed allocation or the machine's swap hours
    in.  No check where the memory cannot be read (os.sysconf)."""
    try:
        memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return
    per_revolution = (period_s / row_dt_s + 1.0) * row_doubles * 8.0
    most = TIME_SERIES_MEMORY_SHARE * memory / per_revolution
    require("revolutions", revolutions, revolutions <= most,
            f"<= {most:.4g} with a row every {row_dt_s:g} s ({rows}) on this machine (the time series takes "
            f"{per_revolution / 1e6:.3g} MB a revolution, at most {TIME_SERIES_MEMORY_SHARE:g} of its "
            f"{memory / 1e9:.3g} GB memory): {remedy}")


def run_in_chunks(make_engine: Callable[[], Any], revolutions: float, period_s: float, sample_dt_s: float,
                  label: str, progress: bool = True, chunks_per_revolution: int = 8,
                  joint: JointParameters | None = None) -> ChunkedRun:
    """Build the engine (``make_engine()``), compile it (``engine.warm_up()``), then advance
    it by ``revolutions`` crank revolutions in chunks of 1/chunks_per_revolution revolution,
    collecting samples and the wear growth.

    Building and compiling are timed apart (``compile_time_s``) from the simulation
    (``wall_time_s``), so that the real-time factor measures the simulation alone.  A
    progress bar on stderr (its description says "compiling" until the first chunk);
    Ctrl-C during the chunks stops after the current one and keeps what was finished, and so
    does a chunk after which the run has diverged (:func:`divergence` against ``joint``, by
    default the engine's joint's; ``failure`` says why).
    If anything raises, the engine is closed before the error propagates.  A time series that would not fit in
    memory is refused first (:func:`check_time_series_fits`).
    """
    check_time_series_fits(revolutions, period_s, sample_dt_s)
    t_final = revolutions * period_s
    chunk = period_s / chunks_per_revolution
    bar = Progress(t_final, label, enabled=progress, compiling=True)
    engine = None
    try:
        start = time.perf_counter()
        engine = make_engine()
        engine.warm_up()
        compile_time = time.perf_counter() - start
        bar.compiled()
        if joint is None:
            joint = engine.joint_parameters
        buffer = np.zeros((int(chunk / sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
        samples, growth = [], []
        completed, failure = True, ""
        wall0 = time.perf_counter()
        try:
            for i in range(int(math.ceil(revolutions * chunks_per_revolution - 1e-9))):
                n = engine.advance_to(min(t_final, (i + 1) * chunk), buffer)
                samples.append(buffer[:n].copy())
                if (i + 1) % chunks_per_revolution == 0:
                    growth.append(engine.max_wear_depth_m())
                bar.update(engine.t)
                failure = divergence(engine, buffer[:n], joint)
                if failure:
                    completed, failure = False, failure + "; the results up to there are written"
                    break
        except RunStopped as exc:   # an inadmissible state refused (docs/reference/model.md §3.14), or a failed call
            samples.append(buffer[:exc.samples_written].copy())     # the chunk's samples before it
            completed, failure = False, f"{exc}; the results before it are written"
        except KeyboardInterrupt:
            completed, failure = False, (f"{INTERRUPTED} at t = {engine.t:.6g} s of {t_final:.6g} s; the results up "
                                         "to there are written")
        writing_results()           # a Ctrl-C from here on waits for the results (interrupts.results_kept)
        wall = time.perf_counter() - wall0
    except BaseException:
        if engine is not None:
            engine.close()
        raise
    finally:
        bar.close()
    return ChunkedRun(engine, np.concatenate(samples) if samples else np.zeros((0, L.N_SAMPLE_COLUMNS)),
                      np.asarray(growth), wall, compile_time, completed, failure)


def record_run(run: ChunkedRun, revolution_stats: np.ndarray, revolutions: float, period_s: float, joint_params,
               parameters: RunParameters, extra: dict) -> RunRecord:
    """The :class:`RunRecord` of a chunked run: the engine's wear profile (read now),
    statistics of the requested revolutions, times and counters."""
    phi_deg, wear_depth, worn_volume = run.engine.wear_profile()
    t = run.engine.t
    reached = t / period_s        # the revolutions asked for where the run reached them (not 3.0000000000000004)
    reached = revolutions if run.completed and math.isclose(reached, revolutions, rel_tol=1e-9) else reached
    return RunRecord(
        samples=run.samples, revolution_stats=revolution_stats[:int(math.ceil(revolutions))].copy(),
        wear_growth_m=run.wear_growth_m, phi_deg=phi_deg, wear_depth_m=wear_depth, worn_volume_m3=worn_volume,
        simulated_time_s=t, wall_time_s=run.wall_time_s, compile_time_s=run.compile_time_s,
        revolutions=reached, period_s=period_s, clearance_m=joint_params.clearance_m,
        contact_stiffness_N_m1_5=joint_params.stiffness_N_m1_5, parameters=parameters, extra=extra, completed=run.completed, failure=run.failure)


def divergence(engine, samples: np.ndarray, joint: JointParameters) -> str:
    """'' while the run is physical, else why not: the engine's latest ``samples`` or its per-revolution largest
    eccentricity (every accepted point) put the pin further into the bushing wall than ``joint`` admits, or are
    not finite (:func:`wearjoint.analysis.pin_left_bushing`); the time named is the first such sample's, else the
    engine's."""
    depth = engine.max_wear_depth_m()
    stats = engine.revolution_stats[analysis.covered(engine.revolution_stats)]
    largest = max(analysis.sample_eccentricity_max(samples), float(stats[:, L.S_ECC_MAX].max()) if stats.size else 0.0)
    force = max(float(samples[:, L.T_NORMAL_FORCE].max()) if samples.shape[0] else 0.0,
                float(stats[:, L.S_FORCE_MAX].max()) if stats.size else 0.0)
    if not math.isfinite(float(stats[:, [L.S_ECC_MAX, L.S_FORCE_MAX]].sum())):
        largest = math.nan
    reason = analysis.pin_left_bushing(largest, joint.clearance_m, depth, joint.admissible_penetration_m, force,
                                       joint.admissible_force_N)
    if not reason:
        return ""
    over = np.flatnonzero(analysis.past_admissible(np.hypot(samples[:, L.T_ECC_X], samples[:, L.T_ECC_Y]), depth,
                                                   samples[:, L.T_NORMAL_FORCE], joint.clearance_m,
                                                   joint.admissible_penetration_m, joint.admissible_force_N))
    when = f"at t = {samples[over[0], L.T_TIME]:.6g} s" if over.size else f"by t = {engine.t:.6g} s"
    mechanism = getattr(engine, "mechanism", None)      # the engines' SliderCrank
    advice = (overload_advice(joint, mechanism) if mechanism is not None else None) or \
        "take a shorter step, an adaptive integrator or a smaller wear factor"
    return (f"the run diverged {when}: {reason}; nothing after this is physical ({advice}; "
            "docs/reference/model.md §3.14)")


IDEAL_FORCE_POINTS = 720      # the ideal joint's reaction over a revolution, every half degree


def overload_advice(joint: JointParameters, mechanism) -> str | None:
    """Where the machine's own loads put more on the ideal joint (``mechanism``: a
    :class:`~wearjoint.slider_crank.SliderCrank`; its reaction over a revolution) than ``joint`` admits
    (:attr:`JointParameters.admissible_force_N`): what a run that diverged should change, which no step does; else
    None."""
    t = np.linspace(0.0, mechanism.params.period_s, IDEAL_FORCE_POINTS, endpoint=False)
    ideal = float(np.max(mechanism.ideal_joint_force(t)))
    if not ideal > joint.admissible_force_N:
        return None
    return (f"no step helps: the machine's own loads put up to {ideal:.3g} N on the ideal joint, beyond the "
            f"{joint.admissible_force_N:.3g} N this joint admits; a larger or stiffer joint, or smaller loads")


def inadmissible_message(t: float, overlap_m: float, force_N: float, joint: JointParameters, where: str,
                         max_depth_m: float, advice: str = "take a shorter step or an adaptive integrator") -> str:
    """Why a run stopped at an inadmissible state (core.admissibility): at time ``t`` [s] ``where`` put the pin
    ``overlap_m`` [m] into the bushing wall with a normal force ``force_N`` [N], beyond what ``joint`` admits, or
    the bushing, ``max_depth_m`` [m] deep at most, wore through; ``advice``: what to do about a step that did."""
    if not (math.isfinite(overlap_m) and math.isfinite(force_N)):
        return (f"the run diverged at t = {t:.6g} s: {where} left the joint's state not finite (NaN or infinite "
                "eccentricity or force: a load, gravity or parameter too large for double precision, or a step far "
                "too long); nothing after it is physical (docs/reference/model.md §3.14)")
    if not max_depth_m <= joint.bushing_radius_m:
        return (worn_through_message(f"at t = {t:.6g} s", max_depth_m, joint.bushing_radius_m)
                + " (a real bushing's wall is thinner: a smaller wear coefficient, wear factor or run; "
                "docs/reference/model.md §3.14)")
    if overlap_m > joint.bushing_radius_m:     # the joint came apart: its contact law has no meaning there
        return (f"the run diverged at t = {t:.6g} s: {where} put the pin {overlap_m:.3g} m past the bushing wall, "
                f"more than the bushing's radius {joint.bushing_radius_m:g} m: the joint came apart (the contact law, "
                f"which gave {force_N:.3g} N there, has no meaning so far out; admissible "
                f"{joint.admissible_penetration_m:.3g} m); nothing after it is physical ({advice}; "
                "docs/reference/model.md §3.14)")
    return (f"the run diverged at t = {t:.6g} s: {where} put the pin {overlap_m:.3g} m into the bushing wall (admissible "
            f"{joint.admissible_penetration_m:.3g} m, {L.ADMISSIBLE_PENETRATION_SHARE:g} times the pin radius) with a "
            f"normal force of {force_N:.3g} N (admissible {joint.admissible_force_N:.3g} N): no contact of this joint "
            f"reaches it; nothing after it is physical ({advice}; docs/reference/model.md §3.14)")
