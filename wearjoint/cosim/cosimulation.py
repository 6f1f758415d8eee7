"""The co-simulation driver: :class:`CoSimulation` (the slider-crank with its crank-rod
joint open and one joint FMU instance, stepped by :func:`.master_loop.master_loop`),
its options and :func:`run_cosimulation`, a whole run into a :class:`RunRecord`."""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from ..core import layout as L
from ..fmu.ensure import ensure_fmu, start_fmu_build
from ..fmu.fmi import BACKENDS, DEFAULT_BACKEND, FmuError
from ..fmu.instance import N_INPUTS, FmuInstance, OwnsFmuInstance
from ..kernel_calls import bushing_point_angles
from ..slider_crank import SliderCrank
from ..checks import RunDiverged, RunStopped, choice, finite, non_negative, positive
from ..parameters import (
    JointParameters, ParameterError, SliderCrankParameters, require, check_joint_fits_mechanism, paper_joint,
)
from ..simulation_options import check_run_arguments, check_run_span, check_wear_step
from ..results import RunParameters, RunRecord, new_revolution_stats, new_track
from ..runner import overload_advice, run_engine
from .master_layout import (
    N_STATE, ADAPTIVE_SCHEMES, B_EXTRAPOLATE, B_INPUT, B_LINEARISE, B_LINEARISED_AT, B_MP, B_OUTPUT, B_ROLLBACK_END,
    B_STATS, B_TRACK, B_Y, C_ADAPTIVE, C_LINEARISE, C_MAX_STEP, C_MIN_STEP, C_ONSET, C_REUSE_STATE, C_STEP,
    C_TOLERANCE, FMI_CALLS, G_CONTACT_STEP, G_FAILED_CALL, G_FAILED_TIME, G_FMI_TIME, G_FREE_STEPS, G_MISS_COUNT,
    G_MISS_MAX, G_MISS_SQ_SUM, G_PREVIOUS_PENETRATION, G_ROLLBACKS, G_SHRUNK_STEPS, G_STEPS, G_T,
    MASTER_DERIVATIVE_OUTPUTS, N_OUTPUTS, N_REGISTER, N_SETTINGS, OUTPUT_NAMES, SCHEMES, buffer_views, monotonic_clock,
)
from .native_master import native_master

CoSimulationError = FmuError   # an FMI call failed; the message carries the FMU's log


# the defaults that depend on the scheme: the contact step (linearised: the largest one the tolerance may take) and
# the coupling tolerance (docs/explanation/cosim_study.md, "Ensembles on worn grooves")
DEFAULT_SCHEME = "linearised"
DEFAULT_CONTACT_STEP_S = {"zoh": 5e-6, "extrapolation": 5e-6, "adaptive": 5e-6, "linearised": 1e-5}
DEFAULT_COUPLING_TOLERANCE = {"zoh": 0.0, "extrapolation": 0.0, "adaptive": 0.0, "linearised": 0.003}


@dataclass(frozen=True)
class CoSimulationOptions:
    """How to co-simulate (``scheme``: :data:`SCHEMES`, described in :mod:`wearjoint.cosim`). ``step_s``: communication
    step [s] (``zoh``, ``extrapolation``: always; ``adaptive``, ``linearised``: while in contact; None: the
    scheme's :data:`DEFAULT_CONTACT_STEP_S`; with wear at most the wear-step limit, checked when the run is built:
    :func:`~wearjoint.simulation_options.check_wear_step`). ``max_step_s`` / ``min_step_s``: bounds of the adaptive
    step [s]; ``onset_penetration_m``: how deep past a contact onset an adaptive step may end [m].  ``sample_dt_s``:
    spacing of the time series [s]. ``coupling_tolerance`` (adaptive, linearised; None: the scheme's
    :data:`DEFAULT_COUPLING_TOLERANCE`, 0.003 for linearised): the relative miss of the predicted contact force
    the contact step aims at, between step_s / 8 and step_s, a linearised contact starting at step_s / 4 (0:
    the fixed rule, the step halved where the miss passes 0.3 and grown back to step_s).  Force jumps (friction
    reversing, the deepest point moving on) miss at any step: the run's miss can stay above it."""

    revolutions: float = 2.0
    scheme: str = DEFAULT_SCHEME
    step_s: float | None = None
    max_step_s: float = 1e-4
    min_step_s: float = 1e-9
    onset_penetration_m: float = 1e-8
    sample_dt_s: float = 1e-5
    coupling_tolerance: float | None = None

    def __post_init__(self):
        """Every value checked (a real one an int, a float or a numpy real scalar, kept as a float)."""
        choice("scheme", self.scheme, SCHEMES)
        if self.step_s is None:
            object.__setattr__(self, "step_s", DEFAULT_CONTACT_STEP_S[self.scheme])
        if self.coupling_tolerance is None:
            object.__setattr__(self, "coupling_tolerance", DEFAULT_COUPLING_TOLERANCE[self.scheme])
        for name in ("revolutions", "step_s", "max_step_s", "min_step_s", "onset_penetration_m", "sample_dt_s"):
            object.__setattr__(self, name, positive(name, getattr(self, name)))
        require("min_step_s", self.min_step_s, self.min_step_s <= self.step_s, f"<= step_s = {self.step_s!r}")
        require("max_step_s", self.max_step_s, self.max_step_s >= self.step_s, f">= step_s = {self.step_s!r}")
        tolerance = non_negative("coupling_tolerance", self.coupling_tolerance)
        require("coupling_tolerance", tolerance, tolerance == 0.0 or self.scheme in ADAPTIVE_SCHEMES,
                "0 unless scheme is adaptive or linearised")
        require("coupling_tolerance", tolerance, tolerance <= 1.0, "in [0, 1] (a force's miss relative to the force)")
        object.__setattr__(self, "coupling_tolerance", tolerance)

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


# ------------------------------------------------------------------ the master
class CoSimulation(OwnsFmuInstance):
    """The slider-crank (crank-rod joint open) and one joint FMU instance, with the
    same stepping interface as :class:`wearjoint.simulate.Simulation`.  Call
    :meth:`~wearjoint.fmu.instance.OwnsFmuInstance.close` (or use ``with``) to free the FMU instance.

    ``fmu_path``: the FMU to load; None takes the cached build of ``fmu_backend``
    (``wearjoint.fmu.build.BACKENDS``), built if missing.  With an explicit
    ``fmu_path``, ``fmu_backend`` should name the backend it was built with (it is
    recorded in the run's parameters)."""

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 options: CoSimulationOptions | None = None, fmu_path=None, fmu_backend: str = DEFAULT_BACKEND,
                 initial_profile_m=None):
        check_run_arguments(joint, mechanism, options, CoSimulationOptions, fmu_path)
        self.options = options or CoSimulationOptions()
        mechanism = mechanism or SliderCrankParameters()
        self.joint = joint or paper_joint(mechanism)
        check_joint_fits_mechanism(self.joint, mechanism)
        check_wear_step("step_s", self.options.step_s, self.joint, mechanism)   # every wearing step is at most step_s
        check_run_span(self.options, self.joint, mechanism)
        require("fmu_backend", fmu_backend, fmu_backend in BACKENDS, "one of " + ", ".join(BACKENDS))
        self.fmu_backend = fmu_backend
        self._instance = None
        build = start_fmu_build(self.joint.n_points, fmu_path, fmu_backend)
        try:   # the master's library is built (first use) while a missing FMU builds; the mechanism's kernels run there
            native = native_master()
            self.mechanism = SliderCrank(mechanism)
        except BaseException:
            if build is not None:
                build.wait()
            raise
        n_rev = int(math.ceil(self.options.revolutions)) + 1
        self.buf = np.zeros(B_STATS + n_rev * L.N_STATS)
        b = self.buf
        b[B_MP:B_MP + L.N_MECHANISM_PARAMETERS] = self.mechanism.parameter_vector
        b[B_EXTRAPOLATE] = 1.0 if self.options.scheme in ("extrapolation", "adaptive") else 0.0
        b[B_LINEARISE] = 1.0 if self.options.scheme == "linearised" else 0.0
        b[B_LINEARISED_AT] = -1.0
        b[B_TRACK:B_TRACK + L.N_TRACK] = new_track(self.options.sample_dt_s)
        b[B_STATS:] = new_revolution_stats(n_rev).ravel()
        self.revolution_stats = b[B_STATS:].reshape((n_rev, L.N_STATS))
        self.y = b[B_Y:B_Y + N_STATE]
        self.outputs = b[B_OUTPUT:B_OUTPUT + N_OUTPUTS]
        self.y[:] = self.mechanism.initial_state()
        self.t = 0.0
        self.communication_steps = 0
        self.rollbacks = 0
        self.free_steps = 0      # communication steps that started in free flight
        self.shrunk_steps = 0    # steps in contact shorter than step_s (adaptive)
        self.miss_sq_sum = 0.0   # the predicted contact force's relative misses (master_loop.G_MISS_*)
        self.miss_max = 0.0
        self.miss_count = 0
        self.fmi_time_s = 0.0
        self.master_time_s = 0.0
        self._saved = np.empty(B_ROLLBACK_END)   # y and outputs at the start of a step (rollback)
        self._register = np.zeros(N_REGISTER)
        self._register[G_PREVIOUS_PENETRATION] = -math.inf   # none yet
        o = self.options
        self._settings = np.zeros(N_SETTINGS)
        self._settings[[C_ADAPTIVE, C_STEP, C_MAX_STEP, C_MIN_STEP, C_ONSET, C_REUSE_STATE, C_TOLERANCE,
                        C_LINEARISE]] = (
            1.0 if o.scheme in ADAPTIVE_SCHEMES else 0.0, o.step_s, o.max_step_s, o.min_step_s, o.onset_penetration_m,
            1.0 if fmu_backend == "native" else 0.0, o.coupling_tolerance, 1.0 if o.scheme == "linearised" else 0.0)
        self._clock = monotonic_clock()
        self._views = buffer_views(b)     # the per-revolution statistics and the RK4 scratch in buf
        self._timespec = np.zeros(2, dtype=np.int64)
        try:   # numba's kernels compile where there is no library, while a missing FMU builds
            if native is None:   # numba's: the FMU's inputs at the start (start_point), compiling the step
                from .master_loop import communication_step, master_loop

                self._master_loop = master_loop
                communication_step(0.0, 0.0, False, b, *self._views, self.mechanism.workspace,
                                   np.zeros((0, L.N_SAMPLE_COLUMNS)))
            else:
                self._master_loop = native.master_loop
                native.start_point(b)
        finally:
            if build is not None:
                build.wait()
        self.fmu_path = ensure_fmu(self.joint.n_points, fmu_path, backend=fmu_backend)
        self._instance = FmuInstance(self.fmu_path, self.joint, b[B_INPUT:B_INPUT + N_INPUTS],
                                     b[B_OUTPUT:B_OUTPUT + N_OUTPUTS], OUTPUT_NAMES)
        try:
            if initial_profile_m is not None:
                self._instance.set_wear_profile(initial_profile_m, 0.0)
            self._instance.exchange(0.0)
            self._published = self._published_linearisation()
        except BaseException:
            self.close()
            raise

    def _published_linearisation(self) -> tuple[np.ndarray, np.ndarray]:
        """(value references, scratch) of the linearisation the FMU publishes (scheme linearised; else empty)."""
        names = MASTER_DERIVATIVE_OUTPUTS if self.options.scheme == "linearised" else ()
        missing = [name for name in names if name not in self._instance.vr]
        if missing:
            raise ParameterError(f"parameter scheme='linearised' is invalid for the FMU {self.fmu_path}: it publishes "
                                 f"no {missing[0]} (built before the joint published its derivatives): allowed "
                                 "zoh, extrapolation, adaptive, or an FMU from this version (wearjoint build-fmu)")
        return (np.array([self._instance.vr[name] for name in names], dtype=np.uint32), np.zeros(len(names)))

    @property
    def fmu_log(self) -> list[tuple[int, str]]:
        """The FMU's log messages as (FMI status, text)."""
        return [] if self._instance is None else list(self._instance.log)

    def _live_instance(self) -> FmuInstance:
        if self._instance is None:
            raise CoSimulationError("the FMU instance of this co-simulation has been freed (close() was called)")
        return self._instance

    # -- stepping
    def warm_up(self) -> None:
        """Load the master's loop (or compile numba's) without advancing: a call over zero time."""
        register = self._register.copy()
        register[G_T] = self.t
        self._master_loop(self.t, register, self._settings, self.buf, *self._views, self._saved,
                          np.zeros((0, L.N_SAMPLE_COLUMNS)), self.mechanism.workspace,
                          self._live_instance().loop_functions, self._published, self._clock, self._timespec)

    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        """Co-simulate to t_end [s], writing samples into ``samples`` (a C-contiguous, writeable float64 array of
        layout.N_SAMPLE_COLUMNS columns; the compiled loop writes it by address); returns how many.
        An FMU error raises CoSimulationError (the instance stays allocated until close())."""
        ok = (isinstance(samples, np.ndarray) and samples.dtype == np.float64 and samples.ndim == 2
              and samples.shape[1] == L.N_SAMPLE_COLUMNS and samples.flags.c_contiguous and samples.flags.writeable)
        require("samples", getattr(samples, "shape", type(samples).__name__), ok,
                f"a C-contiguous, writeable float64 array of shape (n, {L.N_SAMPLE_COLUMNS})")
        t_end = finite("t_end", t_end)
        slave = self._live_instance()
        register = self._register
        register[G_T] = self.t
        register[G_STEPS:] = 0.0
        self.buf[B_TRACK + L.K_N_SAMPLES] = 0
        wall0 = time.perf_counter()
        try:
            failed = self._master_loop(t_end, register, self._settings, self.buf, *self._views, self._saved, samples,
                                       self.mechanism.workspace, slave.loop_functions, self._published, self._clock,
                                       self._timespec)
        finally:
            self.t = float(register[G_T])
            self.communication_steps += int(register[G_STEPS])
            self.rollbacks += int(register[G_ROLLBACKS])
            self.free_steps += int(register[G_FREE_STEPS])
            self.shrunk_steps += int(register[G_SHRUNK_STEPS])
            self.miss_sq_sum += float(register[G_MISS_SQ_SUM])
            self.miss_max = max(self.miss_max, float(register[G_MISS_MAX]))
            self.miss_count += int(register[G_MISS_COUNT])
            # the FMI time is estimated from a sample of the iterations: over a few steps it can pass the wall time
            wall = time.perf_counter() - wall0
            fmi = min(register[G_FMI_TIME], wall)
            self.fmi_time_s += fmi
            self.master_time_s += wall - fmi
        written = int(self.buf[B_TRACK + L.K_N_SAMPLES])
        if failed:   # a doStep the joint refused (its inputs through the wall, non-finite): the run diverged
            try:
                slave.check_recorded(register[G_FAILED_CALL:G_FAILED_TIME + 1], FMI_CALLS)
            except RunDiverged as exc:       # where the machine's loads are beyond the joint, no step helps
                advice = overload_advice(self.joint, self.mechanism)
                raise RunDiverged(f"{exc} ({advice})" if advice else str(exc), written) from None
            except FmuError as exc:          # another call failed: the run stops there, what came before is kept
                raise RunStopped(str(exc), written) from None
        return written

    # -- checkpoints
    def checkpoint(self) -> dict:
        """Everything needed to continue bit-identically: the master's buffer (mechanism
        state, outputs at t, statistics, recorder), the FMU state (serializeFMUstate
        bytes) and the counters.  Picklable."""
        slave = self._live_instance()
        return {"t": self.t, "buffer": self.buf.copy(), "fmu_state": slave.serialize(self.t),
                "previous_penetration": float(self._register[G_PREVIOUS_PENETRATION]),
                "contact_step": float(self._register[G_CONTACT_STEP]),
                "communication_steps": self.communication_steps, "rollbacks": self.rollbacks,
                "free_steps": self.free_steps, "shrunk_steps": self.shrunk_steps, "fmi_time_s": self.fmi_time_s,
                "master_time_s": self.master_time_s,
                "force_miss": (self.miss_sq_sum, self.miss_max, self.miss_count)}

    def restore(self, checkpoint: dict) -> None:
        """Continue from :meth:`checkpoint` (same parameters and options)."""
        slave = self._live_instance()
        buffer = np.asarray(checkpoint["buffer"], dtype=float)
        if buffer.shape != self.buf.shape:
            raise ParameterError(f"checkpoint buffer has {buffer.size} values, this co-simulation "
                                 f"{self.buf.size} (different revolutions or version)")
        slave.deserialize(bytes(checkpoint["fmu_state"]), float(checkpoint["t"]))
        self.buf[:] = buffer
        self.t = float(checkpoint["t"])
        self._register[G_PREVIOUS_PENETRATION] = float(checkpoint["previous_penetration"])
        self._register[G_CONTACT_STEP] = float(checkpoint["contact_step"])
        self.communication_steps = int(checkpoint["communication_steps"])
        self.rollbacks = int(checkpoint["rollbacks"])
        self.free_steps = int(checkpoint.get("free_steps", 0))
        self.shrunk_steps = int(checkpoint.get("shrunk_steps", 0))
        self.miss_sq_sum, self.miss_max, count = checkpoint.get("force_miss", (0.0, 0.0, 0))
        self.miss_count = int(count)
        self.fmi_time_s = float(checkpoint["fmi_time_s"])
        self.master_time_s = float(checkpoint["master_time_s"])

    # -- results
    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) read from the FMU (the bushing frame)."""
        values = self._live_instance().wear(self.t)
        n = self.joint.n_points
        return np.degrees(bushing_point_angles(n)), values[:n], float(values[n + 1])

    def max_wear_depth_m(self) -> float:
        return self._live_instance().max_wear_depth(self.t)

    @property
    def joint_parameters(self) -> JointParameters:
        return self.joint

    def describe(self) -> tuple[RunParameters, dict]:
        """The run record's parameters and the communication statistics (:class:`wearjoint.runner.Engine`)."""
        parameters = RunParameters("cosim", self.joint, self.mechanism.params, "cosimulation", self.options,
                                   {"fmu": str(self.fmu_path), "fmu_backend": self.fmu_backend})
        extra = {"communication_steps": self.communication_steps, "rollbacks": self.rollbacks,
                 "free_steps": self.free_steps, "shrunk_steps": self.shrunk_steps,
                 "fmi_time_s": self.fmi_time_s, "master_time_s": self.master_time_s}
        if self.options.scheme in ADAPTIVE_SCHEMES:
            # the coupling's error estimate: the relative miss of the extrapolated contact force, over the steps
            # in contact (master_loop._contact_step_after)
            extra["coupling_force_miss_rms"] = (math.sqrt(self.miss_sq_sum / self.miss_count) if self.miss_count
                                                else 0.0)
            extra["coupling_force_miss_max"] = self.miss_max
            extra["coupling_controlled_steps"] = self.miss_count
        return parameters, extra

    def set_wear_profile(self, depth_m) -> None:
        """Not available: the FMU has no input or parameter that sets its wear profile."""
        raise ParameterError("the joint FMU offers no way to set its wear profile (cycle jumping); "
                             "use --wear-factor with --engine cosim")


def run_cosimulation(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                     options: CoSimulationOptions | None = None, fmu_path=None, progress: bool = True,
                     chunks_per_revolution: int = 8, fmu_backend: str = DEFAULT_BACKEND,
                     initial_profile_m=None) -> RunRecord:
    """Co-simulate ``options.revolutions`` crank revolutions with the joint FMU from the bushing's
    ``initial_profile_m`` (default: unworn); the run's record.

    Runs through :func:`wearjoint.runner.run_engine` like
    :func:`wearjoint.simulate.run_simulation` (progress bar; loading the FMU and compiling
    the master count as ``compile_time_s``, apart from the simulation's wall time; Ctrl-C
    keeps the finished chunks with ``completed = False``).  The FMU instance is always
    freed.  ``extra`` holds the communication statistics.
    """
    check_run_arguments(joint, mechanism, options, CoSimulationOptions, fmu_path, chunks_per_revolution)
    o = options or CoSimulationOptions()
    return run_engine(lambda: CoSimulation(joint, mechanism, o, fmu_path, fmu_backend, initial_profile_m),
                      o.revolutions, (mechanism or SliderCrankParameters()).period_s, o.sample_dt_s, "cosim",
                      progress, chunks_per_revolution)
