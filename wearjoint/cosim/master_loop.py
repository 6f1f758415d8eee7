"""The co-simulation master's communication loop, compiled with numba.

One float64 buffer holds the master's state (layout ``B_*``): the mechanism state,
the FMU outputs at t and inputs at the step's end (aliased by the ctypes arrays the
FMI calls read and write), the forces held over a step, the RK4 scratch, the
recorder and the per-revolution statistics.  :func:`communication_step` advances
the mechanism over one communication step; :func:`master_loop` runs the steps,
calling the FMU's ``fmi2DoStep``/``fmi2SetReal``/``fmi2GetReal`` (and the FMU-state
functions for rollbacks) through their C entry points, so the master adds no
Python work per step.  The schemes are described in :mod:`wearjoint.cosim`, the buffer's, the register's and the
settings' layout in :mod:`.master_layout`.
"""
from __future__ import annotations

import math

from ..core import layout as L
from ..core.integrators import onset_retry_step, record_step, rk4_step
from ..core.jit import kernel
from ..core.layout import MODE_EXTERNAL, MODE_LINEARISED
from ..core.joint_location import body_angle, joint_bodies, joint_kinematics
from ..core.linearisation import linearisation_from_published
from ..core.slider_crank import angle_trig, derivative_rotated, no_joint
from ..core.trig import rotated_trig
from ..fmu.loop_calls import call_clock, call_do_step, call_real_values, call_with_state, failed_call
from ..fmu.instance import N_INPUTS
from .master_layout import (
    B_DY, B_EXTRAPOLATE, B_FORCES, B_INPUT, B_LAST_STEP, B_LINEARISATION, B_LINEARISE, B_LINEARISED_AT, B_MP,
    B_OUTPUT, B_PREVIOUS_CONTACT, B_PREVIOUS_FORCES, B_RESULT, B_ROLLBACK_END, B_TRACK, B_TRIG, B_Y, C_ADAPTIVE,
    C_LINEARISE, C_MAX_STEP, C_MIN_STEP, C_ONSET, C_REUSE_STATE, C_STEP, C_TOLERANCE, F_DO_STEP,
    F_FREE_STATE, F_GET_REAL, F_GET_STATE, F_SET_REAL, F_SET_STATE, G_CONTACT_STEP, G_FAILED_CALL, G_FMI_TIME,
    G_FREE_STEPS, G_MISS_COUNT, G_MISS_MAX, G_MISS_SQ_SUM, G_PREVIOUS_PENETRATION, G_ROLLBACKS, G_SHRUNK_STEPS,
    G_STEPS, G_T, N_OUTPUTS, N_STATE, OUTPUT_RESULT_INDEX, O_CONTACT, O_NORMAL_FORCE, O_PENETRATION,
)

# the loop times the FMI calls of one iteration in this many and scales them by it: a prime, so that a periodic
# pattern of costly steps (the FMU applies its wear batch every few steps) is sampled at every phase (with 16 a
# batch every 6 steps was sampled at half its phases: the FMI estimate passed the wall time)
FMI_TIMING_EVERY = 17
# adaptive contact step: the relative miss of the extrapolated contact force that halves it (else
# it grows back to step_s), and its floor as a share of step_s (force jumps, e.g. friction reversing
# or the deepest bushing point moving on, miss at any step and must not drive it to nothing)
_MISS_SHRINK = 0.3
_SMALLEST_CONTACT_STEP = 1.0 / 16.0
_MISS_FORCE_FLOOR = 100.0     # [N]: light contact (a few N, friction switching) is not stiff
# linearised under a tolerance, the share of step_s a contact starts with: the linearisation at an onset knows
# nothing of the stiffening ahead, and a step is not redone (tolerance 0.003, step_s 10 us: from the full step_s the
# paper's first 15 ms left the monolithic path by 4.2e-5 m, from a quarter by 4.6e-7; the control grows it at most 2x
# a step).  The extrapolating scheme keeps step_s (from a quarter its first 20 ms ended 10x further off)
_FIRST_CONTROLLED_STEP_SHARE = 0.25
# error-controlled contact step: h_next = h * SAFETY * sqrt(tolerance / miss) (the miss of a linear extrapolation
# is of second order in h), within [1/2, 2] times h, and not below this share of step_s: what misses at a shorter step
# is not the coupling's error (force jumps; the wear of a step, which the linearisation does not predict: at 500x the
# paper's k_w the floor step_s / 16 took 8x the steps of the adaptive scheme, an eighth halves that).  An eighth kept
# the four ensembles of docs/performance.md inside the monolithic scatter (a quarter, with the path of the paper's
# first 15 ms 3x closer, put the worn paper joint's contact fraction 2.4 standard errors off) and that path at 4.6e-7 m
_SMALLEST_CONTROLLED_STEP_SHARE = 0.125
_CONTROL_SAFETY = 0.9
_CONTROL_SHRINK_LIMIT = 0.5
_CONTROL_GROW_LIMIT = 2.0


@kernel(inline='always')
def _linearises(buf, t):
    """True if the step from t integrates the linearised loads: the scheme linearises and the FMU's loads were
    linearised at t (in contact there)."""
    return buf[B_LINEARISE] > 0.5 and buf[B_LINEARISED_AT] == t


@kernel(inline='always')
def _extrapolates(buf, h):
    """True if the step h from t holds extrapolated forces: the scheme extrapolates, the pin touched the bushing
    at t and at the accepted point before, and that point lies at least h / 2 before t (a step shortened to end
    a call's span, 1e-12 s say, leaves a slope of rounding noise, which extrapolating over h would amplify)."""
    return (buf[B_EXTRAPOLATE] > 0.5 and buf[B_OUTPUT + O_CONTACT] > 0.5 and buf[B_PREVIOUS_CONTACT] > 0.5
            and buf[B_LAST_STEP] >= 0.5 * h)


# the cos/sin of the step's angles are rotated from the last step's (core/trig.py) this many
# times after each libm call: at most ~2 ulp per rotation, so ~64 ulp (1.4e-14) of drift at most
_TRIG_ROTATIONS = 31


@kernel(inline='always')
def _step_trig(buf, y, mp):
    """``angle_trig(y, mp)``, rotated from the last call's (``buf[B_TRIG:]``) but every
    _TRIG_ROTATIONS + 1-th call, which calls libm; stores it for the next call."""
    trig = buf[B_TRIG:B_TRIG + 7]
    pin, bushing = joint_bodies(mp)
    pin_angle = body_angle(y, pin)
    bushing_angle = body_angle(y, bushing)
    if trig[6] > 0.5:
        cos1, sin1 = rotated_trig(trig[1], trig[2], trig[0], pin_angle)
        cos2, sin2 = rotated_trig(trig[4], trig[5], trig[3], bushing_angle)
        trig[6] -= 1.0
    else:
        cos1, sin1, cos2, sin2 = angle_trig(y, mp)
        trig[6] = _TRIG_ROTATIONS
    trig[0], trig[1], trig[2], trig[3], trig[4], trig[5] = pin_angle, cos1, sin1, bushing_angle, cos2, sin2
    return cos1, sin1, cos2, sin2


@kernel   # not inlined: the other schemes' step keeps its one RK4 call
def _linearised_step(t, y, h, trig, mp, buf, forces, ws, dy, stages):
    """The RK4 step from t in contact with the loads F0 + J (u - u0), J the FMU's at t (B_LINEARISATION)."""
    linearisation = buf[B_LINEARISATION:B_LINEARISATION + L.N_LINEARISATION]
    rk4_step(t, y, h, trig, MODE_LINEARISED, mp, linearisation, forces, ws, dy, stages)


@kernel
def communication_step(t, h, record, buf, stats, stages, ws, samples):
    """One communication step of the master; returns the time reached [s].  ``stats``, ``stages``:
    :func:`~.master_layout.buffer_views` (buf), made once by the caller (a reshape per step costs a call).

    From the FMU outputs at t (``buf[B_OUTPUT:]``) sets the forces and f(t, y);
    if ``record``, accounts the point t (``record_step``, the step that ended
    there being ``buf[B_LAST_STEP]``); if h > 0, integrates y over [t, t + h]
    with one RK4 step (``rk4_step``, MODE_EXTERNAL), the forces held at their value at t or,
    with extrapolation in persisting contact, at the mean of their linear
    extrapolation.  Writes the FMU inputs at the time reached (the clearance joint's
    pin body's and bushing body's kinematics, core.joint_location).
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
    joint = no_joint(mp)                        # MODE_EXTERNAL reads none of the joint's arrays
    trig = _step_trig(buf, y, mp)
    # MODE_EXTERNAL by name, not as L.MODE_EXTERNAL: numba prunes the other modes' branches only for a constant
    # it sees as one (else this compiles the ideal mechanism's solve, which it never runs)
    derivative_rotated(t, y, trig, MODE_EXTERNAL, mp, joint, forces, ws, dy)
    if record:
        record_step(t, buf[B_LAST_STEP], y, dy, result, mp, stats, samples, buf[B_TRACK:B_TRACK + L.N_TRACK])
    previous = buf[B_PREVIOUS_FORCES:B_PREVIOUS_FORCES + 6]
    if h > 0.0:
        if _linearises(buf, t):
            _linearised_step(t, y, h, trig, mp, buf, forces, ws, dy, stages)
        else:
            if _extrapolates(buf, h):
                # in contact at t and at the point before: hold the mean over [t, t + h]
                # of the forces' linear extrapolation instead of their value at t
                slope = 0.5 * h / buf[B_LAST_STEP]
                for k in range(6):
                    forces[k] = outputs[k] + slope * (outputs[k] - previous[k])
                derivative_rotated(t, y, trig, MODE_EXTERNAL, mp, joint, forces, ws, dy)
            rk4_step(t, y, h, trig, MODE_EXTERNAL, mp, joint, forces, ws, dy, stages)
        for k in range(6):
            previous[k] = outputs[k]
        buf[B_PREVIOUS_CONTACT] = outputs[O_CONTACT]
        buf[B_LAST_STEP] = h
        t = t + h
    joint_kinematics(y, mp, buf[B_INPUT:B_INPUT + N_INPUTS])
    return t


@kernel
def start_point(buf):
    """What :func:`communication_step` leaves at the master's first point besides what the first step overwrites:
    the trigonometry of the state (B_TRIG: libm's, the rotations restarted) and the FMU inputs there (B_INPUT)."""
    y = buf[B_Y:B_Y + N_STATE]
    mp = buf[B_MP:B_MP + L.N_MECHANISM_PARAMETERS]
    _step_trig(buf, y, mp)
    joint_kinematics(y, mp, buf[B_INPUT:B_INPUT + N_INPUTS])


@kernel
def _seconds(clock, timespec):
    """Monotonic clock [s] through libc's clock_gettime (CLOCK_MONOTONIC)."""
    call_clock(clock, 1, timespec.ctypes.data)
    return timespec[0] + 1e-9 * timespec[1]


@kernel(inline='always')
def _fmi_seconds(timed, clock, timespec, start):
    """The FMI calls' wall time since ``start`` scaled to every iteration (FMI_TIMING_EVERY), 0 if not ``timed``."""
    return FMI_TIMING_EVERY * (_seconds(clock, timespec) - start) if timed else 0.0


@kernel(inline='always')
def _outcome(register, call, status, t, seconds):
    """A step's last FMI call checked: (``call``, its master_layout.FMI_CALLS index, if it failed (recorded in ``register``) else
    0, ``seconds``)."""
    return (call if failed_call(register, G_FAILED_CALL, call, status, t) else 0), seconds


@kernel(inline='always')
def _free_flight_step(buf, pen, pen_before, h_max, h_contact, onset):
    """An adaptive step that starts in free flight [s]: h_max, or shorter to end just past the contact onset the
    penetration's rate approaches."""
    rate = (pen - pen_before) / buf[B_LAST_STEP] if buf[B_LAST_STEP] > 0.0 else 0.0
    if rate > 0.0:                       # approaching the wall: aim just past the onset
        return min(h_max, max(h_contact, (0.5 * onset - pen) / rate))
    return h_max


@kernel(inline='always')
def _save_rollback_point(buf, saved, fmi, register, t, reuse_state, timed, clock, timespec):
    """The state a free-flight step may come back to: ``buf`` up to B_ROLLBACK_END into ``saved`` and the FMU's
    state (the previous one freed unless the FMU reuses it).  Returns (the master_layout.FMI_CALLS index of a failed call or 0,
    the FMI seconds if ``timed``)."""
    component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state, free_state = fmi
    for i in range(B_ROLLBACK_END):      # element by element: a slice copy needs numba's NRT
        saved[i] = buf[i]
    c1 = _seconds(clock, timespec) if timed else 0.0
    if state_slot[0] != 0 and not reuse_state:
        status = call_with_state(free_state, component, state_slot.ctypes.data)
        state_slot[0] = 0
        if failed_call(register, G_FAILED_CALL, F_FREE_STATE, status, t):
            return F_FREE_STATE, 0.0
    status = call_with_state(get_state, component, state_slot.ctypes.data)
    return _outcome(register, F_GET_STATE, status, t, _fmi_seconds(timed, clock, timespec, c1))


@kernel(inline='always')
def _exchange(fmi, inputs, outputs, register, t, t_new, timed, clock, timespec):
    """The FMU's step from t to t_new, then the inputs at t_new set and its outputs read.  Returns (the FMI_CALLS
    index of a failed call or 0, the FMI seconds if ``timed``)."""
    component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state, free_state = fmi
    c2 = _seconds(clock, timespec) if timed else 0.0
    status = call_do_step(do_step, component, t, t_new - t, 1)
    if failed_call(register, G_FAILED_CALL, F_DO_STEP, status, t):
        return F_DO_STEP, 0.0
    status = call_real_values(set_real, component, input_vrs.ctypes.data, N_INPUTS, inputs)
    if failed_call(register, G_FAILED_CALL, F_SET_REAL, status, t_new):
        return F_SET_REAL, 0.0
    status = call_real_values(get_real, component, output_vrs.ctypes.data, N_OUTPUTS, outputs)
    return _outcome(register, F_GET_REAL, status, t_new, _fmi_seconds(timed, clock, timespec, c2))


@kernel(inline='always')
def _roll_back(buf, saved, fmi, register, t, timed, clock, timespec):
    """Back to the rollback point: ``buf`` from ``saved`` and the FMU's state set.  Returns (the master_layout.FMI_CALLS index of
    a failed call or 0, the FMI seconds if ``timed``)."""
    component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state, free_state = fmi
    for i in range(B_ROLLBACK_END):
        buf[i] = saved[i]
    c1 = _seconds(clock, timespec) if timed else 0.0
    status = call_with_state(set_state, component, state_slot[0])
    return _outcome(register, F_SET_STATE, status, t, _fmi_seconds(timed, clock, timespec, c1))


@kernel(inline='always')
def _contact_step_after(buf, fx_predicted, fy_predicted, fx_t, fy_t, h, h_min, h_contact, h_touching, tolerance):
    """(the next contact step, the relative miss) after a step h whose forces were extrapolated or linearised; the
    miss is |F(t + h) - F_predicted(t + h)| / max(|F(t + h)|, |F(t)|, 100 N).  Stiff contact (deep, or damped hard
    after a slow onset) makes the explicit coupling unstable at a fixed step.  The fixed rule (``tolerance`` 0): the step halves
    while the miss passes _MISS_SHRINK and grows back to step_s once it agrees.  With a tolerance: the step that
    would miss by ``tolerance`` (second order in h), between step_s / 8 and step_s (longer steps than step_s
    leave the explicit coupling's stability region before the miss shows it)."""
    fx_miss = buf[B_OUTPUT] - fx_predicted
    fy_miss = buf[B_OUTPUT + 1] - fy_predicted
    fx_new = buf[B_OUTPUT]
    fy_new = buf[B_OUTPUT + 1]
    scale_sq = max(fx_new * fx_new + fy_new * fy_new, fx_t * fx_t + fy_t * fy_t, _MISS_FORCE_FLOOR ** 2)
    miss_sq = fx_miss * fx_miss + fy_miss * fy_miss
    miss = math.sqrt(miss_sq / scale_sq)
    if tolerance > 0.0:
        factor = _CONTROL_GROW_LIMIT if miss <= 0.0 else _CONTROL_SAFETY * math.sqrt(tolerance / miss)
        factor = min(_CONTROL_GROW_LIMIT, max(_CONTROL_SHRINK_LIMIT, factor))
        return min(h_contact, max(h_min, _SMALLEST_CONTROLLED_STEP_SHARE * h_contact, factor * h)), miss
    if miss_sq > _MISS_SHRINK ** 2 * scale_sq:
        return max(h_min, _SMALLEST_CONTACT_STEP * h_contact, 0.5 * h), miss
    return min(h_contact, 1.25 * h_touching), miss


@kernel   # not inlined: only the linearised scheme calls it (the others' loop stays as small as it was)
def _linearised_force(buf, r):
    """The linearisation's load r (layout.LIN_LOADS) at the inputs B_INPUT: F0[r] + J[r] (u - u0)."""
    lin = B_LINEARISATION
    value = buf[lin + L.LIN_LOADS + r]
    for m in range(N_INPUTS):
        value += buf[lin + L.LIN_JACOBIAN + N_INPUTS * r + m] * (buf[B_INPUT + m] - buf[lin + L.LIN_INPUTS + m])
    return value


@kernel   # not inlined: only the linearised scheme calls it (the others' loop stays as small as it was)
def _linearise(buf, fmi, published, register, t, timed, clock, timespec):
    """The FMU's loads at t (its outputs) and the linearisation it publishes there (one fmi2GetReal of the 40 of
    its 60 d_*_d_* outputs that master_layout.MASTER_DERIVATIVE_OUTPUTS names, the others minus their partners',
    layout.TRANSLATION_PAIRS) into B_LINEARISATION, its time B_LINEARISED_AT.  ``published``
    = (their value references, scratch for their values).  Returns (the master_layout.FMI_CALLS index of a failed call or 0, the
    FMI seconds if ``timed``)."""
    component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state, free_state = fmi
    derivative_vrs, derivatives = published
    c1 = _seconds(clock, timespec) if timed else 0.0
    status = call_real_values(get_real, component, derivative_vrs.ctypes.data, derivative_vrs.shape[0],
                              derivatives.ctypes.data)
    if failed_call(register, G_FAILED_CALL, F_GET_REAL, status, t):
        buf[B_LINEARISED_AT] = -1.0
        return F_GET_REAL, 0.0
    linearisation_from_published(buf[B_OUTPUT:B_OUTPUT + 6], buf[B_OUTPUT + O_NORMAL_FORCE], derivatives,
                                 L.RELATIVE_COLUMNS, buf[B_INPUT:B_INPUT + N_INPUTS],
                                 buf[B_LINEARISATION:B_LINEARISATION + L.N_LINEARISATION])
    buf[B_LINEARISED_AT] = t
    return 0, _fmi_seconds(timed, clock, timespec, c1)


@kernel
def master_loop(t_end, register, settings, buf, stats, stages, saved, samples, ws, fmi, published, clock, timespec):
    """Co-simulate from register[G_T] to t_end; returns 0, or the master_layout.FMI_CALLS index of a
    call that returned worse than fmi2Warning (details in ``register``).

    ``fmi`` = (component (address), input value references, output value references, FMU-state
    slot, then the addresses of doStep, setReal, getReal, getFMUstate, setFMUstate,
    freeFMUstate): the FMU's C functions, called with the buffers' addresses; ``clock``: clock_gettime's
    address (:func:`~.master_layout.monotonic_clock`); ``published``: what
    :func:`_linearise` reads (scheme linearised).
    Inputs and outputs are read and written in ``buf`` (B_INPUT, B_OUTPUT); ``stats``, ``stages``:
    :func:`~.master_layout.buffer_views` (buf).
    Adaptive scheme: see the module docstring; ``saved`` holds buf[:B_ROLLBACK_END]
    at the start of a free-flight step, the FMU state slot the matching FMU state.
    Each iteration: the step's length, a rollback point in free flight (:func:`_save_rollback_point`), the
    master's step (:func:`communication_step`), the FMU's (:func:`_exchange`), back to the onset where the step
    crossed it too deep (:func:`_roll_back`), the next contact step (:func:`_contact_step_after`).
    """
    adaptive = settings[C_ADAPTIVE] > 0.5
    h_contact = settings[C_STEP]
    h_max = settings[C_MAX_STEP]
    h_min = settings[C_MIN_STEP]
    onset = settings[C_ONSET]
    reuse_state = settings[C_REUSE_STATE] > 0.5
    tolerance = settings[C_TOLERANCE]
    linearise = settings[C_LINEARISE] > 0.5
    inputs = buf.ctypes.data + B_INPUT * 8
    outputs = buf.ctypes.data + B_OUTPUT * 8
    t = register[G_T]
    pen_before = register[G_PREVIOUS_PENETRATION]
    record = False                    # the point t was accounted when it was accepted
    retry_step = 0.0
    steps = 0
    rollbacks = 0
    free_steps = 0
    shrunk_steps = 0
    fmi_time = 0.0
    iteration = 0
    failed = 0
    t_stop = t_end * (1.0 - 1e-15)
    h_touching = register[G_CONTACT_STEP] if register[G_CONTACT_STEP] > 0.0 else h_contact
    while t < t_stop:
        timed = iteration % FMI_TIMING_EVERY == 0   # clock_gettime costs ~20 ns: time a sample of the calls
        iteration += 1
        pen = buf[B_OUTPUT + O_PENETRATION]
        free = buf[B_OUTPUT + O_CONTACT] < 0.5
        linearising = linearise and _linearises(buf, t)
        fx_t = buf[B_OUTPUT]
        fy_t = buf[B_OUTPUT + 1]
        if free:     # a contact starts at step_s, or linearised under a tolerance at a quarter of it
            h_touching = (max(h_min, _FIRST_CONTROLLED_STEP_SHARE * h_contact) if linearise and tolerance > 0.0
                          else h_contact)
        if retry_step > 0.0:
            h = retry_step
        elif adaptive and free:
            h = _free_flight_step(buf, pen, pen_before, h_max, h_contact, onset)
            failed, seconds = _save_rollback_point(buf, saved, fmi, register, t, reuse_state, timed, clock,
                                                   timespec)
            fmi_time += seconds
            if failed:
                break
        else:
            h = h_touching if adaptive else h_contact
        h = min(h, t_end - t)
        # forces predicted for the step's end where the contact persists (extrapolation)
        extrapolating = adaptive and _extrapolates(buf, h)
        fx_slope = (fx_t - buf[B_PREVIOUS_FORCES]) / buf[B_LAST_STEP] if extrapolating else 0.0
        fy_slope = (fy_t - buf[B_PREVIOUS_FORCES + 1]) / buf[B_LAST_STEP] if extrapolating else 0.0
        t_new = communication_step(t, h, record, buf, stats, stages, ws, samples)
        record = False
        failed, seconds = _exchange(fmi, inputs, outputs, register, t, t_new, timed, clock, timespec)
        fmi_time += seconds
        if failed:
            break
        retry = onset_retry_step(adaptive and free, pen, buf[B_OUTPUT + O_PENETRATION], onset, h, h_min)
        if retry > 0.0:
            # the step crossed a contact onset too deep: back to t, retry to end just past it
            failed, seconds = _roll_back(buf, saved, fmi, register, t, timed, clock, timespec)
            fmi_time += seconds
            if failed:
                break
            retry_step = retry
            rollbacks += 1
            continue
        if extrapolating or linearising:
            if linearising:     # the force at the step's end the linearisation at t predicted
                fx_predicted, fy_predicted = _linearised_force(buf, 0), _linearised_force(buf, 1)
            else:
                fx_predicted, fy_predicted = fx_t + fx_slope * h, fy_t + fy_slope * h
            h_touching, miss = _contact_step_after(buf, fx_predicted, fy_predicted, fx_t, fy_t, h, h_min, h_contact,
                                                   h_touching, tolerance)
            register[G_MISS_SQ_SUM] += miss * miss
            register[G_MISS_MAX] = max(register[G_MISS_MAX], miss)
            register[G_MISS_COUNT] += 1.0
        if linearise:
            if buf[B_OUTPUT + O_CONTACT] > 0.5:
                failed, seconds = _linearise(buf, fmi, published, register, t_new, timed, clock, timespec)
                fmi_time += seconds
                if failed:
                    break
            else:
                buf[B_LINEARISED_AT] = -1.0
        retry_step = 0.0
        pen_before = pen
        t = t_new
        record = True
        steps += 1
        if free:
            free_steps += 1
        elif h < h_contact and t < t_stop:
            shrunk_steps += 1
    register[G_CONTACT_STEP] = h_touching
    if record and failed == 0:      # ``record``, not a literal True: numba would compile the step a second time
        communication_step(t, 0.0, record, buf, stats, stages, ws, samples)
    register[G_T] = t
    register[G_PREVIOUS_PENETRATION] = pen_before
    register[G_STEPS] = steps
    register[G_FREE_STEPS] = free_steps
    register[G_SHRUNK_STEPS] = shrunk_steps
    register[G_ROLLBACKS] = rollbacks
    register[G_FMI_TIME] = fmi_time
    return failed
