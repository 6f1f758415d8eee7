"""`wearjoint validate`: one slider-crank, several engines, compared on robust quantities.

Engines: the monolithic simulation (:mod:`wearjoint.simulate`; the reference is RK4 at
1 µs), the FMU co-simulation (:mod:`wearjoint.cosim`, Co-Simulation and Model Exchange) and
exudyn (:mod:`wearjoint.validation.exudyn_model`) with our contact through the helper
(``exudyn-discrete``) and with exudyn's own contact law (``exudyn-native``, unworn).  The
clearance dynamics are chaotic (docs/reference/model.md §7): trajectories are compared point by point
only over the first impacts (``window_s``); beyond that, per-revolution statistics as the
means of an ensemble of perturbed starts, and the worn profile of a short wear run (also an
ensemble: one revolution's worn profile scatters by 10 % between starts; none if it wore nothing).

Every tolerance is ``max(k * scatter, floor)`` (see :class:`Rule`) with the scatter measured in the same validation
run between equally valid runs of one simulator: for statistics, the largest difference between the reference
ensemble's mean and the mean of another valid monolithic configuration's ensemble (RK4 at 1/2, 2, 5 and 10 times the
step, DOPRI at five tolerances), or the standard error of the engine-minus-reference difference if larger; for the
profile, the same over the wear ensembles of fewer valid configurations; for the point-wise traces, the monolithic
step refinement (RK4 h vs h/2) plus the engine's own (the same engine at its window step and at twice that step).
Point-wise, every run over the window records each point it computes and is judged there, against the reference
interpolated (:func:`wearjoint.analysis.window_differences`). An engine whose contact law is another member of our
family (``LAW_REFERENCES``: exudyn's own contact is K delta^n along the line of centres with a stored, floored
impact velocity, our ``deepest`` law with Lankarani-Nikravesh damping, :func:`.exudyn_native.native_law`) has its
traces compared with the monolithic reference run with that law, and its statistics with an ensemble of that law;
its differences from the default reference are reported beside (not judged).

Writes ``report.md``, ``summary.json`` and PNG overlays (:mod:`wearjoint.validation.report`);
the exit status is 0 when every metric of the engines that run the project's joint passes, 1 when one fails
(or an engine raised), 3 when an engine is not available; the metrics of a ``LAW_REFERENCES`` engine are
reported per engine, never judged.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass, field

import numpy as np

from wearjoint import analysis, profile_metrics
from wearjoint.analysis import ensemble_statistics, revolution_statistics
from wearjoint.core import layout as L
from wearjoint.fmu.fmi import BACKENDS, DEFAULT_BACKEND
from wearjoint.interrupts import stopped_by_ctrl_c
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters, finite, require
from wearjoint.results import RunRecord
from wearjoint.simulate import SimulationOptions, run_simulation
from wearjoint.sweep.design import perturbed_start

REFERENCE = "monolithic"
ENGINES = ("monolithic", "cosim", "cosim-me", "exudyn-discrete", "exudyn-native")
WEAR_ENGINES = ("monolithic", "cosim", "cosim-me", "exudyn-discrete")     # exudyn's own contact cannot wear


def _exudyn_native_law(joint: JointParameters) -> dict:
    from .exudyn_native import native_law      # imports exudyn

    return native_law(joint)


# engine -> the joint changes that give the monolithic reference the engine's contact law (point-wise traces)
LAW_REFERENCES = {"exudyn-native": _exudyn_native_law}
# The valid monolithic runs besides the reference, whose differences from it are the scatter.  Over one revolution the
# worn volume of eleven valid runs has a 16 % standard deviation (max depth 12 %): four samples underestimated it
# (README "Validation").  h/2 comes first: it is also the point-wise refinement.
RK4_STEP_FACTORS = (0.5, 2.0, 5.0, 10.0)
DOPRI_RTOLS = (1e-6, 3e-7, 1e-7, 3e-8, 1e-8)
# the wear ensembles' valid configurations: fewer than the statistics' nine (chosen, not forced by cost)
WEAR_CONFIGURATIONS = {"RK4 5 us": {"integrator": "rk4", "step_s": 5e-6},
                       "RK4 10 us": {"integrator": "rk4", "step_s": 1e-5},
                       "DOPRI rtol 1e-06 max step 10 us": {"integrator": "dopri", "rtol": 1e-6, "max_step_s": 1e-5}}
# the point-wise window's runs record each step, up to this many rows a run: samples 0.25 us apart fill it in 25 ms
# (the paper's window is 15 ms; it scales with the period, so machines slower than 90 rpm get sparser samples)
WINDOW_ROWS = 100_000
GROUP_STATISTICS = "per-revolution statistics (no wear)"
GROUP_POINTWISE = "first impacts, point-wise"
GROUP_PROFILE = "worn profile"
STANDARD_ERROR = "standard error of the difference"   # a statistics metric's scatter entry


@dataclass(frozen=True)
class ValidationPlan:
    """What ``wearjoint validate`` runs.  Times in s; ``wear_factor`` multiplies k_w in
    the wear run (reduced so that the worn profile stays well inside the clearance)."""

    revolutions: float = 5.0                 # no-wear runs (statistics)
    ensemble: int = 8                        # perturbed starts per engine and valid configuration (statistics)
    window_s: float = 0.015                  # point-wise comparison over [0, window_s]
    wear_revolutions: float = 1.0
    wear_factor: float = 0.5
    reference_step_s: float = 1e-6           # monolithic RK4 reference
    exudyn_step_s: float = 1e-5              # exudyn statistics runs (fixed step)
    exudyn_wear_step_s: float = 2e-6         # exudyn wear runs: the first impacts' wear needs it (docs/explanation/validation.md)
    cosim_step_s: float = 2e-6               # co-simulation statistics and wear runs (largest step in contact)
    window_step_s: float = 1e-6              # exudyn and co-simulation window runs (and twice that)
    sample_dt_s: float = 1e-5
    engines: tuple = ENGINES
    run_wear: bool = True
    fmu_backend: str = DEFAULT_BACKEND       # the co-simulation's FMU (wearjoint.fmu.build.BACKENDS)
    law_spread: bool = True                  # the model-form spread over the contact laws (validation/law_spread.py)

    def __post_init__(self):
        for name in ("revolutions", "window_s", "wear_revolutions", "wear_factor", "reference_step_s",
                     "exudyn_step_s", "exudyn_wear_step_s", "cosim_step_s", "window_step_s", "sample_dt_s"):
            require(name, getattr(self, name), finite(name, getattr(self, name)) > 0.0, "> 0")
        require("ensemble", self.ensemble, not isinstance(self.ensemble, bool) and isinstance(self.ensemble, int)
                 and self.ensemble >= 2, "an integer >= 2 (a spread needs two starts)")
        for name in self.engines:
            require("engines", name, name in ENGINES, "names from " + ", ".join(ENGINES))
        require("engines", ",".join(self.engines), REFERENCE in self.engines,
                 f"a list that includes the reference {REFERENCE!r}")
        require("fmu_backend", self.fmu_backend, self.fmu_backend in BACKENDS, "one of " + ", ".join(BACKENDS))

    def engine_step_s(self, engine: str, wear: bool = False) -> float:
        """The step of an engine's statistics (or ``wear``) runs [s]."""
        if engine == "cosim":
            return self.cosim_step_s
        return self.exudyn_wear_step_s if wear else self.exudyn_step_s


FULL = ValidationPlan()
# the quick wear run stays inside the point-wise window (before chaos the runs agree, so a
# few impacts' worn volume is comparable; after it, 0.1 revolution holds too few impacts to
# estimate their scatter from four runs)
QUICK = ValidationPlan(revolutions=0.1, ensemble=2, wear_revolutions=0.0375, wear_factor=20.0)


@dataclass(frozen=True)
class Rule:
    """tolerance = max(k * scatter, floor, floor_relative * |reference value|, onsets / the runs' span [rev]: a
    count's resolution, one onset in 0.1 revolution is 10 per revolution)."""

    k: float
    floor: float
    floor_relative: float = 0.0
    why_floor: str = ""
    onsets: float = 0.0

    def tolerance(self, scatter: float, reference: float | None, span_revolutions: float = np.inf) -> float:
        return max(self.k * scatter, self.floor, self.floor_relative * abs(reference or 0.0),
                   self.onsets / span_revolutions)


# name -> (unit, rule).  Statistics: chaos makes every valid run a sample of the same
# distribution, so each configuration is an ensemble of perturbed starts judged by its mean;
# k = 2 on the largest difference between the reference's mean and another valid
# configuration's (or the difference's standard error); the floors guard against a chance
# agreement of the valid configurations.
STATISTICS = {
    "impacts_per_revolution": ("1/rev", Rule(2.0, 0.0, 0.05, "5 % of the reference, below the 10-20 % run-to-run "
                                                             "scatter (docs/reference/model.md §7), and one onset in "
                                                             "the runs' span", onsets=1.0)),
    "contact_fraction": ("-", Rule(2.0, 0.02, 0.0, "0.02 (2 % of the time), below the 4-10 % spread "
                                                  "of valid monolithic runs")),
    "slider_acc_max_m_s2": ("m/s²", Rule(2.0, 1.0, 0.05, "5 % of the reference, 1 m/s² (a slider at rest)")),
    "slider_acc_min_m_s2": ("m/s²", Rule(2.0, 1.0, 0.05, "5 % of the reference, 1 m/s² (a slider at rest)")),
    "max_contact_force_N": ("N", Rule(2.0, 1.0, 0.05, "5 % of the reference, at least 1 N")),
    "max_eccentricity_m": ("m", Rule(2.0, 0.1e-6, 0.0, "0.1 µm (0.1 % of the clearance)")),
    "mean_eccentricity_in_contact_m": ("m", Rule(2.0, 0.05e-6, 0.0, "0.05 µm (0.05 % of the clearance)")),
}
# Point-wise maximum differences over the window; scatter = monolithic + engine refinement.
POINTWISE = {
    "eccentricity_max_difference_m": ("m", Rule(2.0, 1e-8, 0.0, "1e-8 m, the agreement of valid runs (docs/reference/model.md §7)")),
    "normal_force_max_difference_N": ("N", Rule(2.0, 1.0, 0.0, "1 N, 0.1 % of the impact peaks")),
    "slider_acc_max_difference_m_s2": ("m/s²", Rule(2.0, 1.0, 0.0, "1 m/s², 0.1 % of the impact peaks")),
}
PROFILE = {
    "max_wear_depth_m": ("m", Rule(2.0, 0.0, 0.05, "5 % of the reference")),
    "worn_volume_m3": ("m³", Rule(2.0, 0.0, 0.05, "5 % of the reference")),
    "lobe_angle_near_0_deg": ("deg", Rule(2.0, 1.0, 0.0, "1 deg (3.5 bushing points)")),
    "lobe_angle_near_180_deg": ("deg", Rule(2.0, 1.0, 0.0, "1 deg (3.5 bushing points)")),
    "profile_decorrelation": ("-", Rule(2.0, 0.01, 0.0, "0.01 (a correlation of 0.99 always passes)")),
}


@dataclass
class Metric:
    """One compared quantity of one engine (difference = engine - reference, or the
    point-wise maximum difference, or 1 - correlation)."""

    group: str
    name: str
    unit: str
    engine: str
    value: float | None
    reference: float | None
    difference: float
    scatter: float
    tolerance: float
    passed: bool
    scatter_values: dict = field(default_factory=dict)    # what the scatter was taken from


@dataclass
class Runs:
    """Every record of one validation.  ``reference_ensemble`` / ``scatter`` / ``engines``:
    the no-wear ensembles (one record per perturbed start, the unperturbed first) of the
    reference, of the other valid monolithic configurations by label and of each engine;
    ``reference``: the reference ensemble's unperturbed run; ``window_reference``: the monolithic RK4 at h and at
    h/2 over the point-wise window, every step recorded (up to WINDOW_ROWS rows); ``window``: engine -> (run at the
    window step, run at twice that step); ``law_window``: engine of ``LAW_REFERENCES`` -> the
    monolithic reference with its law (RK4 at h, at h/2); ``law_ensembles``: engine -> the reference's
    ensemble run with its law; ``wear_reference`` / ``wear_scatter`` / ``wear_engines``: the wear
    ensembles of the reference, of the valid configurations by label and of each engine; ``log``:
    (label, engine, record) of every run in order."""

    reference_ensemble: list
    scatter: dict
    engines: dict
    window: dict
    window_reference: tuple = ()
    law_window: dict = field(default_factory=dict)
    law_changes: dict = field(default_factory=dict)   # engine of law_window -> the joint changes of its law
    law_ensembles: dict = field(default_factory=dict)
    wear_reference: list = field(default_factory=list)
    wear_scatter: dict = field(default_factory=dict)
    wear_engines: dict = field(default_factory=dict)
    gaps: list = field(default_factory=list)       # engines not available (module missing)
    errors: list = field(default_factory=list)     # engines that raised during a run
    log: list = field(default_factory=list)

    @property
    def reference(self) -> RunRecord:
        return self.reference_ensemble[0]


# ---------------------------------------------------------------- running the engines
class RunStoppedShort(RuntimeError):
    """A run that ended before its revolutions (it diverged): the engine fails, a reference ends the validation."""


def _log(progress: bool, message: str) -> None:
    if progress:
        print(f"validate: {message}", file=sys.stderr, flush=True)


def run_monolithic(joint, mechanism, revolutions, sample_dt_s, progress, **options) -> RunRecord:
    """:func:`run_simulation` with ``SimulationOptions(**options)``."""
    return run_simulation(joint, mechanism, SimulationOptions(revolutions=revolutions, sample_dt_s=sample_dt_s,
                                                              **options), progress=progress)


def engine_runner(engine: str, joint: JointParameters, fmu_backend: str = DEFAULT_BACKEND):
    """f(joint, mechanism, revolutions, step_s, sample_dt_s, progress) -> RunRecord for a
    non-reference engine; ``step_s`` is exudyn's fixed step, the co-simulation's
    largest communication step in contact (its default scheme), or the largest step of the Model
    Exchange run (``cosim-me``: the FMU's ME interface in the monolithic Dormand-Prince).  The co-simulation's FMU (for
    ``joint.n_points``, backend ``fmu_backend``) is resolved, and built if missing, here
    once, so that every run of a validation uses the same FMU.  Raises ImportError when
    the engine's module (or the FMU backend) is missing."""
    if engine.startswith("exudyn-"):
        from wearjoint.validation.exudyn_model import run_exudyn
        contact = engine.split("-", 1)[1]
        return lambda j, m, rev, step, dt, progress: run_exudyn(j, m, rev, step_s=step, contact=contact,
                                                                sample_dt_s=dt, progress=progress)
    if engine == "cosim":
        from wearjoint.cosim import CoSimulationOptions, run_cosimulation
        from wearjoint.fmu.ensure import ensure_fmu
        fmu_path = ensure_fmu(joint.n_points, backend=fmu_backend)
        return lambda j, m, rev, step, dt, progress: run_cosimulation(
            j, m, CoSimulationOptions(revolutions=rev, step_s=step, sample_dt_s=dt), fmu_path=fmu_path,
            progress=progress, fmu_backend=fmu_backend)
    if engine == "cosim-me":   # Model Exchange: the native backend's (pythonfmu is co-simulation only)
        from wearjoint.cosim.model_exchange import run_model_exchange
        from wearjoint.fmu.ensure import ensure_fmu
        fmu_path = ensure_fmu(joint.n_points, backend="native")
        return lambda j, m, rev, step, dt, progress: run_model_exchange(
            j, m, SimulationOptions(revolutions=rev, integrator="dopri", max_step_s=step, sample_dt_s=dt),
            fmu_path=fmu_path, progress=progress, fmu_backend="native")
    raise ParameterError(f"engine={engine!r} is invalid: allowed one of " + ", ".join(ENGINES[1:]))


def _us(step_s: float) -> str:
    return f"{step_s * 1e6:g} us"


def run_engines(plan: ValidationPlan, joint: JointParameters, mechanism: SliderCrankParameters,
                engine_joint_changes: dict | None = None, progress: bool = True) -> Runs:
    """Run every simulation of ``plan`` (one progress line per run on stderr);
    ``engine_joint_changes`` (engine -> {parameter: value}) gives one engine a
    different joint: the validation's self-check, which must then fail."""
    changes = engine_joint_changes or {}
    for engine in changes:
        require("perturbed engine", engine, engine in plan.engines and engine != REFERENCE,
                 "an engine of the plan other than the reference " + REFERENCE)
    no_wear = joint.replace(wear_factor=0.0)
    wear = joint.replace(wear_factor=plan.wear_factor)
    dt = plan.sample_dt_s
    available, gaps, errors = {}, [], []

    def failed(engine, exc) -> None:
        errors.append(f"{engine}: failed ({type(exc).__name__}: {exc})")
        _log(progress, errors[-1])

    for engine in plan.engines:
        if engine == REFERENCE:
            continue
        try:
            available[engine] = engine_runner(engine, joint, plan.fmu_backend)
        except ImportError as exc:
            gaps.append(f"{engine}: not run ({type(exc).__name__}: {exc})")
            _log(progress, gaps[-1])
        except Exception as exc:
            failed(engine, exc)
    wear_engines = [e for e in available if e in WEAR_ENGINES] if plan.run_wear else []
    n_monolithic = 1 + len(RK4_STEP_FACTORS) + len(DOPRI_RTOLS)
    law_engines = [e for e in available if e in LAW_REFERENCES]
    total = (plan.ensemble * (n_monolithic + len(available) + len(law_engines)) + 2 + 2 * len(available)
             + 2 * len(law_engines)
             + (plan.ensemble * (1 + len(WEAR_CONFIGURATIONS) + len(wear_engines)) if plan.run_wear else 0))
    log = []

    def run(label, engine, make) -> RunRecord:
        _log(progress, f"[{len(log) + 1}/{total}] {label} ...")
        record = make()
        if not record.completed:        # truncated statistics are judged never: Ctrl-C stops it, a divergence fails
            raise KeyboardInterrupt if stopped_by_ctrl_c(record) else RunStoppedShort(f"{label}: {record.failure}")
        log.append((label, engine, record))
        _log(progress, f"[{len(log)}/{total}] {label}: {record.simulated_time_s:.4g} s simulated in "
                       f"{record.wall_time_s:.1f} s wall")
        return record

    def ensemble(label, engine, make) -> list:
        """One run per perturbed start: ``make(mechanism)``."""
        return [run(f"{label}, start {k + 1}/{plan.ensemble}", engine,
                    lambda m=perturbed_start(mechanism, k): make(m)) for k in range(plan.ensemble)]

    def monolithic(label, j, revolutions, **options):
        """(run label, make(mechanism) -> RunRecord) of a monolithic run."""
        name = f"monolithic {label}, {revolutions:g} rev" + (", no wear" if j.wear_factor == 0.0 else
                                                              f", wear factor {j.wear_factor:g}")
        return name, lambda m: run_monolithic(j, m, revolutions, dt, progress, **options)

    h = plan.reference_step_s
    rev = plan.revolutions
    configurations = {f"RK4 {_us(h)}": {"integrator": "rk4", "step_s": h},
                      **{f"RK4 {_us(h * f)}": {"integrator": "rk4", "step_s": h * f} for f in RK4_STEP_FACTORS},
                      **{f"DOPRI rtol {rtol:g}": {"integrator": "dopri", "rtol": rtol} for rtol in DOPRI_RTOLS}}
    ensembles = {}
    for label, options in configurations.items():
        name, make = monolithic(label, no_wear, rev, **options)
        ensembles[label] = ensemble(name, REFERENCE, make)
    reference_ensemble = ensembles.pop(f"RK4 {_us(h)}")
    engines, window, law_window, law_changes, law_ensembles = {}, {}, {}, {}, {}
    window_rev = plan.window_s * 1.02 / mechanism.period_s
    # below every step (each computed point recorded), at most WINDOW_ROWS rows a run (a slow machine's window)
    window_dt = max(0.25 * min(h, plan.window_step_s), window_rev * mechanism.period_s / WINDOW_ROWS)
    window_text = f"first {plan.window_s * 1e3:g} ms, no wear, samples {window_dt * 1e6:.3g} us apart at least"
    window_reference = tuple(
        run(f"monolithic RK4 {_us(s)}, {window_text}", REFERENCE,
            lambda s=s: run_monolithic(no_wear, mechanism, window_rev, window_dt, progress, integrator="rk4", step_s=s))
        for s in (h, 0.5 * h))
    for engine, runner in list(available.items()):
        j = no_wear.replace(**changes.get(engine, {}))
        step = plan.engine_step_s(engine)
        try:
            members = ensemble(f"{engine} step {_us(step)}, {rev:g} rev, no wear", engine,
                               lambda m: runner(j, m, rev, step, dt, progress))
            window[engine] = tuple(
                run(f"{engine} step {_us(s)}, {window_text}", engine,
                    lambda s=s: runner(j, mechanism, window_rev, s, window_dt, progress))
                for s in (plan.window_step_s, 2.0 * plan.window_step_s))
            if engine in LAW_REFERENCES:
                law_changes[engine] = LAW_REFERENCES[engine](no_wear)
                law = no_wear.replace(**law_changes[engine])
                law_text = ", ".join(f"{k}={v}" for k, v in law_changes[engine].items())
                law_window[engine] = tuple(
                    run(f"monolithic RK4 {_us(s)}, {law_text}, {window_text}", REFERENCE,
                        lambda s=s: run_monolithic(law, mechanism, window_rev, window_dt, progress, integrator="rk4",
                                                   step_s=s))
                    for s in (h, 0.5 * h))
                name, make = monolithic(f"RK4 {_us(h)}, {law_text}", law, rev, integrator="rk4", step_s=h)
                law_ensembles[engine] = ensemble(name, REFERENCE, make)
            engines[engine] = members
        except Exception as exc:       # one broken engine must not hide the others' comparison
            failed(engine, exc)
            del available[engine]
    runs = Runs(reference_ensemble, ensembles, engines, window, window_reference, law_window, law_changes,
                law_ensembles, gaps=gaps, errors=errors, log=log)
    if plan.run_wear:
        wrev = plan.wear_revolutions

        def wear_ensemble(label, **options):
            name, make = monolithic(label, wear, wrev, **options)
            return ensemble(name, REFERENCE, make)

        runs.wear_reference = wear_ensemble(f"RK4 {_us(h)}", integrator="rk4", step_s=h)
        runs.wear_scatter = {label: wear_ensemble(label, **options) for label, options in WEAR_CONFIGURATIONS.items()}
        for engine in [e for e in wear_engines if e in available]:
            j = wear.replace(**changes.get(engine, {}))
            step = plan.engine_step_s(engine, wear=True)
            try:
                runs.wear_engines[engine] = ensemble(
                    f"{engine} step {_us(step)}, {wrev:g} rev, wear factor {plan.wear_factor:g}", engine,
                    lambda m, j=j, step=step, engine=engine: available[engine](j, m, wrev, step, dt, progress))
            except Exception as exc:
                failed(engine, exc)
    return runs


# ---------------------------------------------------------------- quantities compared
# (the definitions are wearjoint.analysis's)
def pointwise_differences(record: RunRecord, reference: RunRecord, window_s: float) -> dict:
    """Largest differences to ``reference`` (interpolated) at ``record``'s own sample times in [0, window_s]: the
    eccentricity vector (bushing frame), the normal force and the slider acceleration."""
    d = analysis.window_differences(record.samples, reference.samples, window_s,
                                    (L.T_ECC_X, L.T_ECC_Y, L.T_NORMAL_FORCE, L.T_SLIDER_A))
    return {
        "eccentricity_max_difference_m": float(np.hypot(d[:, 0], d[:, 1]).max()),
        "normal_force_max_difference_N": float(np.abs(d[:, 2]).max()),
        "slider_acc_max_difference_m_s2": float(np.abs(d[:, 3]).max()),
    }


def profile_quantities(record: RunRecord) -> dict:
    """Max wear depth, worn volume, and the angle of each wear lobe
    (:func:`wearjoint.profile_metrics.lobes`: depth-weighted mean angle within +-90 deg of 0 deg
    and of 180 deg, rod frame; None without wear there)."""
    lobe = profile_metrics.lobes(record.phi_deg, record.wear_depth_m)
    return {"max_wear_depth_m": float(record.wear_depth_m.max()), "worn_volume_m3": float(record.worn_volume_m3),
            **{f"lobe_angle_near_{centre}_deg": lobe[centre]["angle_deg"] for centre in profile_metrics.LOBE_CENTRES_DEG}}


def ensemble_profile(records: list) -> tuple[dict, dict, np.ndarray]:
    """(mean, sample standard deviation) over an ensemble's wear runs of each :func:`profile_quantities`
    quantity (None where a run has no lobe), and the mean profile h(phi) [m]."""
    mean, std = analysis.ensemble_mean_std([profile_quantities(r) for r in records])
    return mean, std, np.mean([r.wear_depth_m for r in records], axis=0)


# ---------------------------------------------------------------- comparison
def _judge(group, name, unit, rule, engine, value, reference, difference, scatter_values,
           scatter_parts=None, span_revolutions=np.inf) -> Metric:
    """The metric with scatter = the largest of ``scatter_values`` and its tolerance."""
    scatter = max(scatter_values.values())
    tolerance = rule.tolerance(scatter, reference, span_revolutions)
    return Metric(group, name, unit, engine, value, reference, difference, scatter, tolerance,
                  bool(abs(difference) <= tolerance), scatter_parts or scatter_values)


def compare(runs: Runs, plan: ValidationPlan) -> list[Metric]:
    """Every metric of every engine against the monolithic reference (see module docstring)."""
    metrics = []
    ref_mean, ref_std = ensemble_statistics(runs.reference_ensemble)
    scatter_means = {label: ensemble_statistics(members)[0] for label, members in runs.scatter.items()}
    for engine, members in runs.engines.items():
        mean, std = ensemble_statistics(members)
        # an engine with a law of its own is judged against that law's ensemble (the valid configurations'
        # differences from the default reference stay its numerical scatter)
        law = runs.law_ensembles.get(engine)
        reference, reference_std = ensemble_statistics(law) if law else (ref_mean, ref_std)
        for name, (unit, rule) in STATISTICS.items():
            scatter = {label: abs(m[name] - ref_mean[name]) for label, m in scatter_means.items()}
            n_reference = len(law or runs.reference_ensemble)
            scatter[STANDARD_ERROR] = float(np.hypot(std[name] / np.sqrt(len(members)),
                                                     reference_std[name] / np.sqrt(n_reference)))
            metrics.append(_judge(GROUP_STATISTICS, name, unit, rule, engine, mean[name], reference[name],
                                  mean[name] - reference[name], scatter, span_revolutions=plan.revolutions))
    # point-wise, the valid monolithic pair is the step refinement (RK4 h vs h/2): DOPRI at
    # rtol 1e-6..1e-7 is already micrometres off over the window (measured), not equally accurate
    refined_label = f"RK4 {_us(0.5 * plan.reference_step_s)}"
    for engine, (fine, coarse) in runs.window.items():
        reference, refined = runs.law_window.get(engine, runs.window_reference)
        mono = pointwise_differences(refined, reference, plan.window_s)
        diff = pointwise_differences(fine, reference, plan.window_s)
        own = pointwise_differences(coarse, fine, plan.window_s)
        for name, (unit, rule) in POINTWISE.items():
            metrics.append(_judge(GROUP_POINTWISE, name, unit, rule, engine, None, None, diff[name],
                                  {f"monolithic RK4 h vs h/2 + {engine} at 2x step": mono[name] + own[name]},
                                  scatter_parts={f"monolithic {refined_label}": mono[name],
                                                 f"{engine} step x2": own[name]}))
    if runs.wear_reference and max(r.wear_depth_m.max() for r in runs.wear_reference) > 0.0:
        ref_profile, ref_profile_std, ref_h = ensemble_profile(runs.wear_reference)
        scatter_profiles = {label: ensemble_profile(members) for label, members in runs.wear_scatter.items()}
        for engine, members in runs.wear_engines.items():
            prof, prof_std, h = ensemble_profile(members)
            for name in ("max_wear_depth_m", "worn_volume_m3", "lobe_angle_near_0_deg", "lobe_angle_near_180_deg"):
                unit, rule = PROFILE[name]
                if prof[name] is None or ref_profile[name] is None or any(
                        p[name] is None for p, _, _ in scatter_profiles.values()):
                    continue            # a half without wear in some run: no lobe to compare
                scatter = {label: abs(_profile_difference(name, p[name], ref_profile[name]))
                           for label, (p, _, _) in scatter_profiles.items()}
                scatter[STANDARD_ERROR] = float(np.hypot(prof_std[name] / np.sqrt(len(members)),
                                                         ref_profile_std[name] / np.sqrt(len(runs.wear_reference))))
                metrics.append(_judge(GROUP_PROFILE, name, unit, rule, engine, prof[name], ref_profile[name],
                                      _profile_difference(name, prof[name], ref_profile[name]), scatter))
            unit, rule = PROFILE["profile_decorrelation"]
            d = profile_metrics.profile_decorrelation(h, ref_h)
            metrics.append(_judge(GROUP_PROFILE, "profile_decorrelation", unit, rule, engine, d, 0.0, d,
                                  {label: profile_metrics.profile_decorrelation(mean_h, ref_h)
                                   for label, (_, _, mean_h) in scatter_profiles.items()}))
    return metrics


def _profile_difference(name: str, value: float, reference: float) -> float:
    return float(profile_metrics.wrap_deg(value - reference)) if name.startswith("lobe") else value - reference


__all__ = ["ValidationPlan", "FULL", "QUICK", "Rule", "Metric", "Runs", "RunStoppedShort", "run_engines", "compare",
           "revolution_statistics", "ensemble_statistics", "pointwise_differences", "profile_quantities",
           "ensemble_profile", "perturbed_start", "engine_runner", "run_monolithic", "ENGINES", "WEAR_ENGINES",
           "LAW_REFERENCES", "REFERENCE"]
