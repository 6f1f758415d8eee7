"""Co-simulation master: the rigid slider-crank coupled to the ``ClearanceWearJoint`` FMU.

The crank-rod joint of the mechanism is open (``MODE_EXTERNAL``); its loads come
from the FMU (MODEL.md section 5).  fmpy loads, instantiates and initialises the
FMU (``FMU2Slave``); the communication loop (:func:`master_loop`) is numba code
that calls the FMU's ``fmi2DoStep``/``fmi2SetReal``/``fmi2GetReal`` (and the
FMU-state functions for rollbacks) through their C entry points, with value
references and values in pre-allocated arrays, so the master adds no Python
work per step.  Each communication step [t, t + h]: the FMU already holds the
kinematics at t (crank = pin body, rod = bushing body) and its forces were read;
:func:`communication_step` records the point t and integrates the mechanism over
the step with those forces held (RK4); then ``doStep(t, h)``, ``setReal`` of the
12 inputs at t + h and ``getReal`` of the 12 outputs the master needs.

Schemes (``CoSimulationOptions.scheme``):

* ``zoh`` -- fixed communication step ``step_s``, forces held (zero-order hold).
* ``extrapolation`` -- fixed step; while the contact persists (in contact at t
  and at the point before) the forces are extrapolated linearly from the last
  two points and their mean over the step is held (second order in h).
* ``adaptive`` -- extrapolation, ``step_s`` while the pin touches the bushing; in free flight
  the step grows up to ``max_step_s``, limited by the predicted time to the next
  contact onset (from the FMU's signed penetration and its rate).  A step that
  starts in free flight and ends deeper than ``onset_penetration_m`` is rolled
  back (``getFMUstate``/``setFMUstate`` plus the mechanism state) and retried
  with a step interpolated to the onset, as ``core.integrators.integrate`` does
  for DOPRI.  Free flight carries no joint force, so large steps there cost no
  accuracy.  In contact the step is halved (down to ``step_s``/16) while the force
  at a step's end misses its extrapolation by > 30 %, and grows back otherwise:
  the explicit coupling is unstable at a fixed step in deep or hard-damped contact.  The default (validation/cosim_study.py): ``adaptive`` with 5 us in
  contact.  Zero-order hold is first order in h (pointwise 100x off the
  monolithic run at 1 us) and unstable from ~5 us on (stiff contact).
"""
from __future__ import annotations

import ctypes
import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

from .core import layout as L
from .core.contact import bushing_point_angles
from .core.integrators import onset_retry_step, record_step, rk4_step
from .core.mechanism import derivative
from .mechanism import SliderCrank
from .fmu.instance import INPUT_NAMES, N_INPUTS, FmuError, FmuInstance, c_function, ensure_fmu
from .cli_options import add_model_arguments, model_from_args
from .parameters import (
    JointParameters, ParameterError, SliderCrankParameters, _finite, _require, check_joint_fits_mechanism,
)
from .runner import run_in_chunks
from .results import RunRecord, new_revolution_stats, new_track, write_results

SCHEMES = ("zoh", "extrapolation", "adaptive")
FMI_WARNING = 1

# --- the FMU outputs the master reads, in this order, and where each goes in a result (layout.R_*)
OUTPUT_NAMES = ("pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y",
                "bushing_torque", "normal_force", "friction_force", "penetration", "contact",
                "eccentricity_x", "eccentricity_y")
OUTPUT_RESULT_INDEX = np.array([L.R_PIN_FX, L.R_PIN_FY, L.R_PIN_TORQUE, L.R_BUSHING_FX, L.R_BUSHING_FY,
                                L.R_BUSHING_TORQUE, L.R_NORMAL_FORCE, L.R_FRICTION_FORCE, L.R_PENETRATION,
                                L.R_CONTACT, L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y])
N_OUTPUTS = len(OUTPUT_NAMES)
O_PENETRATION = OUTPUT_NAMES.index("penetration")
O_CONTACT = OUTPUT_NAMES.index("contact")

# --- the master's state buffer: one float64 array, so the per-step kernel takes few arguments.
# Everything a rollback restores is at its start (one copy saves it).
_N_Y = 2 * L.N_COORDINATES
B_Y = 0                                   # mechanism state [q, q_dot]
B_OUTPUT = B_Y + _N_Y                     # FMU outputs at t (OUTPUT_NAMES), aliased by a ctypes array
B_PREVIOUS_FORCES = B_OUTPUT + N_OUTPUTS  # FMU forces at the accepted point before t (extrapolation)
B_PREVIOUS_CONTACT = B_PREVIOUS_FORCES + 6   # 1.0 if the pin touched there
B_LAST_STEP = B_PREVIOUS_CONTACT + 1      # length of the step that ended at t [s]
B_ROLLBACK_END = B_LAST_STEP + 1
B_DY = B_ROLLBACK_END                     # f(t, y) with the held forces
B_INPUT = B_DY + _N_Y                     # FMU inputs at the end of the step, aliased by a ctypes array
B_RESULT = B_INPUT + N_INPUTS             # outputs in the layout.R_* result layout (for record_step)
B_FORCES = B_RESULT + L.N_RESULT          # (Fx, Fy, T) on the crank then the rod
B_STAGES = B_FORCES + 6                   # RK4 stage scratch (4 rows of the state size)
B_TRACK = B_STAGES + 4 * _N_Y             # record_step bookkeeping (samples, previous contact)
B_MP = B_TRACK + L.N_TRACK                # mechanism parameter vector
B_EXTRAPOLATE = B_MP + L.N_MECHANISM_PARAMETERS   # 1.0: extrapolate the forces during contact
B_STATS = B_EXTRAPOLATE + 1               # per-revolution statistics (rows of layout.N_STATS)


# --- master_loop's register: the loop's state between calls, its counters and its failure
G_T = 0                  # time reached [s]
G_PREVIOUS_PENETRATION = 1   # FMU penetration at the accepted point before t [m]
G_STEPS = 2              # communication steps accepted (this call)
G_ROLLBACKS = 3          # rollbacks (this call)
G_FMI_TIME = 4           # wall time in FMI calls (this call) [s]
G_FAILED_CALL = 5        # index into FMI_CALLS of the call that failed, 0 if none
G_FAILED_STATUS = 6      # its fmi2Status
G_FAILED_TIME = 7        # the communication point it was made for [s]
G_CONTACT_STEP = 8       # adaptive: the communication step in contact now [s] (0: step_s)
N_REGISTER = 9
# adaptive contact step: the relative miss of the extrapolated contact force that halves it (else
# it grows back to step_s), and its floor as a share of step_s (force jumps, e.g. friction reversing
# or the deepest bushing point moving on, miss at any step and must not drive it to nothing)
_MISS_SHRINK = 0.3
_SMALLEST_CONTACT_STEP = 1.0 / 16.0
_MISS_FORCE_FLOOR = 100.0     # [N]: light contact (a few N, friction switching) is not stiff
FMI_CALLS = ("", "fmi2DoStep", "fmi2SetReal", "fmi2GetReal", "fmi2GetFMUstate", "fmi2SetFMUstate",
             "fmi2FreeFMUstate")
F_DO_STEP, F_SET_REAL, F_GET_REAL, F_GET_STATE, F_SET_STATE, F_FREE_STATE = range(1, len(FMI_CALLS))
# --- master_loop's settings
C_ADAPTIVE, C_STEP, C_MAX_STEP, C_MIN_STEP, C_ONSET = range(5)


CoSimulationError = FmuError   # an FMI call failed; the message carries the FMU's log


@dataclass(frozen=True)
class CoSimulationOptions:
    """How to co-simulate.  ``step_s``: communication step [s] (``zoh``: always;
    ``adaptive``: while in contact).  ``max_step_s`` / ``min_step_s``: bounds of
    the adaptive step [s]; ``onset_penetration_m``: how deep past a contact onset
    an adaptive step may end [m].  ``sample_dt_s``: spacing of the time series [s]."""

    revolutions: float = 2.0
    scheme: str = "adaptive"
    step_s: float = 5e-6     # default from validation/cosim_study.py (adaptive, 5 us)
    max_step_s: float = 1e-4
    min_step_s: float = 1e-9
    onset_penetration_m: float = 1e-8
    sample_dt_s: float = 1e-5

    def __post_init__(self):
        _require("revolutions", self.revolutions, _finite("revolutions", self.revolutions) > 0.0, "> 0")
        _require("scheme", self.scheme, self.scheme in SCHEMES, "one of " + ", ".join(SCHEMES))
        for name in ("step_s", "max_step_s", "min_step_s", "onset_penetration_m", "sample_dt_s"):
            _require(name, getattr(self, name), _finite(name, getattr(self, name)) > 0.0, "> 0")
        _require("min_step_s", self.min_step_s, self.min_step_s <= self.step_s, f"<= step_s = {self.step_s!r}")
        _require("max_step_s", self.max_step_s, self.max_step_s >= self.step_s, f">= step_s = {self.step_s!r}")

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


@njit(cache=True)
def _extrapolates(buf):
    """True if the next step holds extrapolated forces: the scheme extrapolates and the pin
    touched the bushing at t and at the accepted point before."""
    return (buf[B_EXTRAPOLATE] > 0.5 and buf[B_OUTPUT + O_CONTACT] > 0.5 and buf[B_PREVIOUS_CONTACT] > 0.5
            and buf[B_LAST_STEP] > 0.0)


@njit(cache=True)
def communication_step(t, h, record, buf, ws, samples):
    """One communication step of the master; returns the time reached [s].

    From the FMU outputs at t (``buf[B_OUTPUT:]``) sets the forces and f(t, y);
    if ``record``, accounts the point t (``record_step``, the step that ended
    there being ``buf[B_LAST_STEP]``); if h > 0, integrates y over [t, t + h]
    with one RK4 step (``rk4_step``, MODE_EXTERNAL), the forces held at their value at t or,
    with extrapolation in persisting contact, at the mean of their linear
    extrapolation.  Writes the FMU inputs at the time reached (crank = pin
    body, rod = bushing body).
    """
    n = L.N_COORDINATES
    y = buf[B_Y:B_Y + 2 * n]
    dy = buf[B_DY:B_DY + 2 * n]
    outputs = buf[B_OUTPUT:B_OUTPUT + N_OUTPUTS]
    result = buf[B_RESULT:B_RESULT + L.N_RESULT]
    forces = buf[B_FORCES:B_FORCES + 6]
    mp = buf[B_MP:B_MP + L.N_MECHANISM_PARAMETERS]
    for k in range(N_OUTPUTS):
        result[OUTPUT_RESULT_INDEX[k]] = outputs[k]
    for k in range(6):
        forces[k] = outputs[k]
    # derivative takes a joint tuple of the in-process layout; MODE_EXTERNAL reads none of it
    joint = (mp, mp, mp, mp, mp, mp, np.zeros(0, dtype=np.bool_), result)
    derivative(t, y, L.MODE_EXTERNAL, mp, joint, forces, ws, dy)
    if record:
        stats = buf[B_STATS:].reshape((-1, L.N_STATS))
        record_step(t, buf[B_LAST_STEP], y, dy, result, mp, stats, samples, buf[B_TRACK:B_TRACK + L.N_TRACK])
    previous = buf[B_PREVIOUS_FORCES:B_PREVIOUS_FORCES + 6]
    if h > 0.0:
        if _extrapolates(buf):
            # in contact at t and at the point before: hold the mean over [t, t + h]
            # of the forces' linear extrapolation instead of their value at t
            slope = 0.5 * h / buf[B_LAST_STEP]
            for k in range(6):
                forces[k] = outputs[k] + slope * (outputs[k] - previous[k])
            derivative(t, y, L.MODE_EXTERNAL, mp, joint, forces, ws, dy)
        rk4_step(t, y, h, L.MODE_EXTERNAL, mp, joint, forces, ws, dy,
                 buf[B_STAGES:B_STAGES + 4 * 2 * n].reshape((4, 2 * n)))
        for k in range(6):
            previous[k] = outputs[k]
        buf[B_PREVIOUS_CONTACT] = outputs[O_CONTACT]
        buf[B_LAST_STEP] = h
        t = t + h
    inputs = buf[B_INPUT:B_INPUT + N_INPUTS]
    for k in range(3):
        inputs[k] = y[L.CRANK + k]
        inputs[3 + k] = y[n + L.CRANK + k]
        inputs[6 + k] = y[L.ROD + k]
        inputs[9 + k] = y[n + L.ROD + k]
    return t


@njit(cache=True)
def _seconds(clock, timespec):
    """Monotonic clock [s] through libc's clock_gettime (CLOCK_MONOTONIC)."""
    clock(1, timespec.ctypes.data)
    return timespec[0] + 1e-9 * timespec[1]


@njit(cache=True)
def _failed(register, call, status, t):
    register[G_FAILED_CALL] = call
    register[G_FAILED_STATUS] = status
    register[G_FAILED_TIME] = t


@njit(cache=True)
def master_loop(t_end, register, settings, buf, saved, samples, ws, fmi, clock, timespec):
    """Co-simulate from register[G_T] to t_end; returns 0, or the FMI_CALLS index of a
    call that returned worse than fmi2Warning (details in ``register``).

    ``fmi`` = (component, input value references, output value references, FMU-state
    slot (addresses), doStep, setReal, getReal, getFMUstate, setFMUstate,
    freeFMUstate): the FMU's C functions, called with the buffers' addresses.
    Inputs and outputs are read and written in ``buf`` (B_INPUT, B_OUTPUT).
    Adaptive scheme: see the module docstring; ``saved`` holds buf[:B_ROLLBACK_END]
    at the start of a free-flight step, the FMU state slot the matching FMU state.
    """
    component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state, free_state = fmi
    adaptive = settings[C_ADAPTIVE] > 0.5
    h_contact = settings[C_STEP]
    h_max = settings[C_MAX_STEP]
    h_min = settings[C_MIN_STEP]
    onset = settings[C_ONSET]
    inputs = buf.ctypes.data + B_INPUT * 8
    outputs = buf.ctypes.data + B_OUTPUT * 8
    t = register[G_T]
    pen_before = register[G_PREVIOUS_PENETRATION]
    record = False                    # the point t was accounted when it was accepted
    retry_step = 0.0
    steps = 0
    rollbacks = 0
    fmi_time = 0.0
    failed = 0
    t_stop = t_end * (1.0 - 1e-15)
    h_touching = register[G_CONTACT_STEP] if register[G_CONTACT_STEP] > 0.0 else h_contact
    while t < t_stop:
        pen = buf[B_OUTPUT + O_PENETRATION]
        free = buf[B_OUTPUT + O_CONTACT] < 0.5
        # forces predicted for the step's end where the contact persists (extrapolation)
        extrapolating = adaptive and _extrapolates(buf)
        fx_t = buf[B_OUTPUT]
        fy_t = buf[B_OUTPUT + 1]
        fx_slope = (fx_t - buf[B_PREVIOUS_FORCES]) / buf[B_LAST_STEP] if extrapolating else 0.0
        fy_slope = (fy_t - buf[B_PREVIOUS_FORCES + 1]) / buf[B_LAST_STEP] if extrapolating else 0.0
        if free:
            h_touching = h_contact
        if retry_step > 0.0:
            h = retry_step
        elif adaptive and free:
            h = h_max
            rate = (pen - pen_before) / buf[B_LAST_STEP] if buf[B_LAST_STEP] > 0.0 else 0.0
            if rate > 0.0:                       # approaching the wall: aim just past the onset
                h = min(h_max, max(h_contact, (0.5 * onset - pen) / rate))
            saved[:] = buf[:B_ROLLBACK_END]
            c1 = _seconds(clock, timespec)
            if state_slot[0] != 0:
                status = free_state(component, state_slot.ctypes.data)
                state_slot[0] = 0
                if status > FMI_WARNING:
                    failed = F_FREE_STATE
                    _failed(register, failed, status, t)
                    break
            status = get_state(component, state_slot.ctypes.data)
            fmi_time += _seconds(clock, timespec) - c1
            if status > FMI_WARNING:
                failed = F_GET_STATE
                _failed(register, failed, status, t)
                break
        else:
            h = h_touching if adaptive else h_contact
        h = min(h, t_end - t)
        t_new = communication_step(t, h, record, buf, ws, samples)
        record = False
        c2 = _seconds(clock, timespec)
        status = do_step(component, t, t_new - t, 1)
        if status > FMI_WARNING:
            failed = F_DO_STEP
            _failed(register, failed, status, t)
            break
        status = set_real(component, input_vrs.ctypes.data, N_INPUTS, inputs)
        if status > FMI_WARNING:
            failed = F_SET_REAL
            _failed(register, failed, status, t_new)
            break
        status = get_real(component, output_vrs.ctypes.data, N_OUTPUTS, outputs)
        fmi_time += _seconds(clock, timespec) - c2
        if status > FMI_WARNING:
            failed = F_GET_REAL
            _failed(register, failed, status, t_new)
            break
        retry = onset_retry_step(adaptive and free, pen, buf[B_OUTPUT + O_PENETRATION], onset, h, h_min)
        if retry > 0.0:
            # the step crossed a contact onset too deep: back to t, retry to end just past it
            buf[:B_ROLLBACK_END] = saved
            c1 = _seconds(clock, timespec)
            status = set_state(component, state_slot[0])
            fmi_time += _seconds(clock, timespec) - c1
            if status > FMI_WARNING:
                failed = F_SET_STATE
                _failed(register, failed, status, t)
                break
            retry_step = retry
            rollbacks += 1
            continue
        if extrapolating:
            # stiff contact (deep, or damped hard after a slow onset) makes the explicit
            # coupling unstable at a fixed step: shrink the contact step while the force at
            # the step's end misses its extrapolation, grow it back to step_s once it agrees
            fx_miss = buf[B_OUTPUT] - (fx_t + fx_slope * h)
            fy_miss = buf[B_OUTPUT + 1] - (fy_t + fy_slope * h)
            scale = max(math.hypot(buf[B_OUTPUT], buf[B_OUTPUT + 1]), math.hypot(fx_t, fy_t), _MISS_FORCE_FLOOR)
            miss = math.hypot(fx_miss, fy_miss) / scale
            if miss > _MISS_SHRINK:
                h_touching = max(h_min, _SMALLEST_CONTACT_STEP * h_contact, 0.5 * h)
            else:
                h_touching = min(h_contact, 1.25 * h_touching)
        retry_step = 0.0
        pen_before = pen
        t = t_new
        record = True
        steps += 1
    register[G_CONTACT_STEP] = h_touching
    if record and failed == 0:
        communication_step(t, 0.0, True, buf, ws, samples)
    register[G_T] = t
    register[G_PREVIOUS_PENETRATION] = pen_before
    register[G_STEPS] = steps
    register[G_ROLLBACKS] = rollbacks
    register[G_FMI_TIME] = fmi_time
    return failed


_CLOCK_CALL = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_int, ctypes.c_void_p)


def _monotonic_clock():
    """libc's clock_gettime, for master_loop's split of FMI time and master time."""
    return c_function(ctypes.CDLL(None).clock_gettime, _CLOCK_CALL)


# ------------------------------------------------------------------ the master
class CoSimulation:
    """The slider-crank (crank-rod joint open) and one joint FMU instance, with the
    same stepping interface as :class:`wearjoint.simulate.Simulation`.  Call
    :meth:`close` (or use ``with``) to free the FMU instance."""

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 options: CoSimulationOptions | None = None, fmu_path=None):
        self.options = options or CoSimulationOptions()
        self.mechanism = SliderCrank(mechanism)
        self.joint = joint or JointParameters(**self.mechanism.params.joint_offsets())
        check_joint_fits_mechanism(self.joint, self.mechanism.params)
        self.fmu_path = ensure_fmu(self.joint.n_points, fmu_path)
        n_rev = int(math.ceil(self.options.revolutions)) + 1
        self.buf = np.zeros(B_STATS + n_rev * L.N_STATS)
        b = self.buf
        b[B_MP:B_MP + L.N_MECHANISM_PARAMETERS] = self.mechanism.parameter_vector
        b[B_EXTRAPOLATE] = 1.0 if self.options.scheme in ("extrapolation", "adaptive") else 0.0
        b[B_TRACK:B_TRACK + L.N_TRACK] = new_track(self.options.sample_dt_s)
        b[B_STATS:] = new_revolution_stats(n_rev).ravel()
        self.revolution_stats = b[B_STATS:].reshape((n_rev, L.N_STATS))
        self.y = b[B_Y:B_Y + _N_Y]
        self.outputs = b[B_OUTPUT:B_OUTPUT + N_OUTPUTS]
        self.y[:] = self.mechanism.initial_state()
        self.t = 0.0
        self.communication_steps = 0
        self.rollbacks = 0
        self.fmi_time_s = 0.0
        self.master_time_s = 0.0
        self._saved = np.empty(B_ROLLBACK_END)   # y and outputs at the start of a step (rollback)
        self._register = np.zeros(N_REGISTER)
        self._register[G_PREVIOUS_PENETRATION] = -math.inf   # none yet
        o = self.options
        self._settings = np.zeros(5)
        self._settings[[C_ADAPTIVE, C_STEP, C_MAX_STEP, C_MIN_STEP, C_ONSET]] = (
            1.0 if o.scheme == "adaptive" else 0.0, o.step_s, o.max_step_s, o.min_step_s, o.onset_penetration_m)
        self._clock = _monotonic_clock()
        self._timespec = np.zeros(2, dtype=np.int64)
        self._slave = FmuInstance(self.fmu_path, self.joint, b[B_INPUT:B_INPUT + N_INPUTS],
                                  b[B_OUTPUT:B_OUTPUT + N_OUTPUTS], OUTPUT_NAMES)
        try:
            communication_step(0.0, 0.0, False, b, self.mechanism.workspace, np.zeros((0, L.N_SAMPLE_COLUMNS)))
            self._slave.exchange(0.0)
        except BaseException:
            self.close()
            raise

    # -- lifetime
    def close(self) -> None:
        """Free the FMU instance (idempotent)."""
        if self._slave is not None:
            self._slave.close()
            self._slave = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    @property
    def fmu_log(self) -> list[tuple[int, str]]:
        """The FMU's log messages as (FMI status, text)."""
        return [] if self._slave is None else list(self._slave.log)

    def _live_slave(self) -> FmuInstance:
        if self._slave is None:
            raise CoSimulationError("the FMU instance of this co-simulation has been freed (close() was called)")
        return self._slave

    # -- stepping
    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        """Co-simulate to t_end [s], writing samples into ``samples``; returns how many.
        An FMU error raises CoSimulationError (the instance stays allocated until close())."""
        slave = self._live_slave()
        register = self._register
        register[G_T] = self.t
        register[G_STEPS:G_CONTACT_STEP] = 0.0
        self.buf[B_TRACK + L.K_N_SAMPLES] = 0
        wall0 = time.perf_counter()
        try:
            failed = master_loop(t_end, register, self._settings, self.buf, self._saved, samples,
                                 self.mechanism.workspace, slave.loop_functions, self._clock, self._timespec)
        finally:
            self.t = float(register[G_T])
            self.communication_steps += int(register[G_STEPS])
            self.rollbacks += int(register[G_ROLLBACKS])
            self.fmi_time_s += register[G_FMI_TIME]
            self.master_time_s += time.perf_counter() - wall0 - register[G_FMI_TIME]
        if failed:
            slave.check(int(register[G_FAILED_STATUS]), FMI_CALLS[failed], float(register[G_FAILED_TIME]))
        return int(self.buf[B_TRACK + L.K_N_SAMPLES])

    # -- checkpoints
    def checkpoint(self) -> dict:
        """Everything needed to continue bit-identically: the master's buffer (mechanism
        state, outputs at t, statistics, recorder), the FMU state (serializeFMUstate
        bytes) and the counters.  Picklable."""
        slave = self._live_slave()
        return {"t": self.t, "buffer": self.buf.copy(), "fmu_state": slave.serialize(self.t),
                "previous_penetration": float(self._register[G_PREVIOUS_PENETRATION]),
                "contact_step": float(self._register[G_CONTACT_STEP]),
                "communication_steps": self.communication_steps, "rollbacks": self.rollbacks,
                "fmi_time_s": self.fmi_time_s, "master_time_s": self.master_time_s}

    def restore(self, checkpoint: dict) -> None:
        """Continue from :meth:`checkpoint` (same parameters and options)."""
        slave = self._live_slave()
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
        self.fmi_time_s = float(checkpoint["fmi_time_s"])
        self.master_time_s = float(checkpoint["master_time_s"])

    # -- results
    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) read from the FMU (rod frame)."""
        values = self._live_slave().wear(self.t)
        n = self.joint.n_points
        return np.degrees(bushing_point_angles(n)), values[:n], float(values[n + 1])

    def max_wear_depth_m(self) -> float:
        return self._live_slave().max_wear_depth(self.t)

    def set_wear_profile(self, depth_m) -> None:
        """Not available: the FMU has no input or parameter that sets its wear profile."""
        raise ParameterError("the joint FMU offers no way to set its wear profile (cycle jumping); "
                             "use --wear-factor with --engine cosim")


def run_cosimulation(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                     options: CoSimulationOptions | None = None, fmu_path=None, progress: bool = True,
                     chunks_per_revolution: int = 8) -> RunRecord:
    """Co-simulate ``options.revolutions`` crank revolutions with the joint FMU; the run's record.

    Runs through :func:`wearjoint.runner.run_in_chunks` like
    :func:`wearjoint.simulate.run_simulation` (progress line, Ctrl-C keeps the
    finished chunks with ``completed = False``).  The FMU
    instance is always freed.  ``extra`` holds the communication statistics.
    """
    sim = CoSimulation(joint, mechanism, options, fmu_path)
    try:
        o = sim.options
        period = sim.mechanism.params.period_s
        run = run_in_chunks(sim, o.revolutions, period, o.sample_dt_s, "cosim", progress, chunks_per_revolution)
        phi_deg, wear_depth, worn_volume = sim.wear_profile()
    finally:
        sim.close()
    return RunRecord(
        samples=run.samples, revolution_stats=sim.revolution_stats[:int(math.ceil(o.revolutions))].copy(),
        wear_growth_m=run.wear_growth_m, phi_deg=phi_deg, wear_depth_m=wear_depth,
        worn_volume_m3=worn_volume, simulated_time_s=sim.t, wall_time_s=run.wall_time_s, revolutions=sim.t / period,
        period_s=period, clearance_m=sim.joint.clearance_m,
        parameters={"joint": sim.joint.to_dict(), "mechanism": sim.mechanism.params.to_dict(),
                    "cosimulation": o.to_dict(), "fmu": str(sim.fmu_path), "engine": "cosim"},
        extra={"communication_steps": sim.communication_steps, "rollbacks": sim.rollbacks,
               "fmi_time_s": sim.fmi_time_s, "master_time_s": sim.master_time_s},
        completed=run.completed)


# ------------------------------------------------------------------ CLI (wearjoint cosim)
_DEFAULTS = CoSimulationOptions()


def cli_arguments(parser) -> None:
    """Options of ``wearjoint cosim``: results folder, coupling, and every model parameter."""
    parser.add_argument("--out", type=Path, required=True, help="results folder (created)")
    parser.add_argument("--no-plots", action="store_true", help="skip the PNG figures")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    parser.add_argument("--fmu", type=Path, default=None,
                        help="ClearanceWearJoint.fmu to use (default: the cached build, built if missing)")
    g = parser.add_argument_group("co-simulation")
    g.add_argument("--revolutions", type=float, default=_DEFAULTS.revolutions, help="crank revolutions to simulate")
    g.add_argument("--scheme", choices=SCHEMES, default=_DEFAULTS.scheme,
                   help="zoh: fixed communication step, forces held; extrapolation: fixed step, forces "
                        "extrapolated in contact; adaptive: extrapolation, large steps in free flight, "
                        "rollback to contact onsets (default %(default)s)")
    g.add_argument("--step", type=float, default=_DEFAULTS.step_s,
                   help="communication step [s] (adaptive: in contact) (default %(default)g)")
    g.add_argument("--max-step", type=float, default=_DEFAULTS.max_step_s,
                   help="largest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--min-step", type=float, default=_DEFAULTS.min_step_s,
                   help="smallest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--onset-penetration", type=float, default=_DEFAULTS.onset_penetration_m,
                   help="how deep past a contact onset an adaptive step may end [m] (default %(default)g)")
    g.add_argument("--sample-dt", type=float, default=_DEFAULTS.sample_dt_s, help="time-series spacing [s]")
    add_model_arguments(parser)


def cli_run(args) -> int:
    """Run, write the results folder, print the summary; 1 with a one-line message on an FMU error."""
    import sys

    from .simulate_cli import _print_summary

    joint, mechanism = model_from_args(args)
    options = CoSimulationOptions(revolutions=args.revolutions, scheme=args.scheme, step_s=args.step,
                                  max_step_s=args.max_step, min_step_s=args.min_step,
                                  onset_penetration_m=args.onset_penetration, sample_dt_s=args.sample_dt)
    try:
        record = run_cosimulation(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet)
    except CoSimulationError as exc:
        print(f"wearjoint cosim: error: {exc}", file=sys.stderr)
        return 1
    summary = write_results(record, args.out, plots=not args.no_plots)
    _print_summary(summary, args.out)
    for key in ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s"):
        print(f"  {key:28s} {summary[key]:.6g}")
    return 0 if record.completed else 130


__all__ = ["CoSimulation", "CoSimulationOptions", "CoSimulationError", "run_cosimulation", "ensure_fmu",
           "communication_step", "SCHEMES", "cli_arguments", "cli_run"]
