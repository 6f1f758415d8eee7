"""Integrators of the slider-crank with the clearance joint, and the per-step recorder.

Fixed-step RK4 and adaptive Dormand-Prince 5(4) (error control on positions
and velocities, maximum step).  The joint's state (wear profile, contact-onset
memory) changes only at accepted points (``accept_joint``); stage
evaluations never change it.  Both locate contact onsets (see :func:`integrate`).
``record_step`` accumulates per-revolution statistics and time-series samples;
the co-simulation master uses it too.  They are the slider-crank's: they reach the mechanism through
:mod:`wearjoint.core.slider_crank` (``derivative``, its state layout, its recorder's columns); another mechanism
(the four-bar of ``wearjoint/examples/four_bar.py``) runs in exudyn with the same joint kernels.
"""
import math

import numpy as np

from .layout import (
    CRANK, K_N_SAMPLES, K_NEXT_SAMPLE, K_PREVIOUS_CONTACT, K_PREVIOUS_PENETRATION, K_SAMPLE_DT, M_ACTIVE,
    MODE_CLEARANCE, MODE_EXTERNAL, MODE_LINEARISED,
    MP_OMEGA, N_COORDINATES, R_CONTACT, R_ECCENTRICITY_X, R_ECCENTRICITY_Y, R_FRICTION_FORCE,
    R_NORMAL_FORCE, R_PENETRATION, R_PIN_FX, R_PIN_FY, R_TANGENTIAL_VELOCITY, S_ACC_MAX, S_ACC_MIN, S_CONTACT_TIME,
    S_ECC_MAX, S_FORCE_MAX, S_IMPACTS, S_TIME, SLIDER, T_CONTACT, T_CRANK_ANGLE, T_ECC_X, T_ECC_Y,
    T_FRICTION_FORCE, T_NORMAL_FORCE, T_PENETRATION, T_PIN_FX, T_PIN_FY, T_RELATIVE_OMEGA, T_SLIDER_A, T_SLIDER_V,
    T_SLIDER_X, T_TANGENTIAL_VELOCITY, T_TIME, Y_SLIDER_V, Y_SLIDER_X,
)
from .jit import kernel
from .joint_access import (
    JOINT_CHANGED, JOINT_EVALUATED, JOINT_UNCHANGED, JOINT_WORN, accept_joint, contact_at, joint_failed,
)
from .joint_location import body_rate, joint_bodies
from .slider_crank import angle_trig, derivative, derivative_evaluated, derivative_rotated, stage_trig

RK4 = 0
DOPRI5 = 1
SAMPLE_TIME_SLACK = 1e-3     # a point this share of the step that ended there before a sample time is on it
_PI_BETA = 0.04
_PI_EXPONENT = 0.2 - 0.75 * _PI_BETA

# Dormand-Prince 5(4) tableau: row s of _DOPRI_A gives stage s from stages 0..s-1; the last
# row is the 5th-order solution (b), so the 7th stage is f at the step's end (FSAL)
_DOPRI_C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0])
_DOPRI_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
])
# error estimate: 5th- minus 4th-order weights
_DOPRI_E = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0,
                     22.0 / 525.0, -1.0 / 40.0])
_RK4_C = np.array([0.5, 0.5, 1.0])
_UNUSED_TRIG = (0.0, 0.0, 0.0, 0.0)    # rk4_step's trig where the mode calls libm per stage
# the derivative where it runs once per Dormand-Prince step or once per run, not per stage: compiled once and called
# from those four sites.  Inlined at each, a cold run compiled the mechanism's derivative four more times per
# specialisation; DOPRI with wear over two revolutions runs as fast, within this machine's noise.  RK4's per-step
# derivative stays inlined: called, its 1 us step took 4-5 % longer (and called at every stage, 12 %)
_derivative_per_step = kernel(derivative.py_func)
_derivative_evaluated_per_step = kernel(derivative_evaluated.py_func)


@kernel
def contact_share(penetration_start, penetration_end):
    """Share of a step spent in contact, the signed penetration taken linear over the
    step: 1 or 0 when both ends agree, else the part on the positive side.  (An
    adaptive step that ends just past a contact onset counts almost no contact time.)"""
    if penetration_start >= 0.0 and penetration_end >= 0.0:
        return 1.0
    if penetration_start < 0.0 and penetration_end < 0.0:
        return 0.0
    inside = penetration_end if penetration_end >= 0.0 else penetration_start
    return inside / (abs(penetration_end) + abs(penetration_start))


@kernel(inline='always')
def onset_retry_step(free_at_start, pen_start, pen_end, onset_tol, step, h_min):
    """Contact-onset location: a step that started in free flight (``free_at_start``,
    signed penetration pen_start < 0) and ended deeper than ``onset_tol`` [m] inside
    the bushing is retried with the step interpolated linearly in the signed
    penetration to end onset_tol / 2 past the onset (at least h_min) [s]; returns 0.0
    when the step stands."""
    if free_at_start and pen_start < 0.0 and pen_end > onset_tol and step > h_min:
        return max(h_min, step * (0.5 * onset_tol - pen_start) / (pen_end - pen_start))
    return 0.0


@kernel
def record_step(t, dt, y, dy, result, mp, rev_stats, samples, track):
    """Account the accepted point (t, y) that ends a step of length dt.

    ``result`` is the joint evaluation there (layout.R_*).  Updates the row of
    the current crank revolution in ``rev_stats`` (impacts = contact onsets,
    contact time (:func:`contact_share`), slider acceleration extremes, max normal force, max
    eccentricity) and appends a sample when t reaches the next sample time.
    """
    contact = result[R_CONTACT] > 0.5
    rev = int(mp[MP_OMEGA] * t / (2.0 * math.pi) * (1.0 - 1e-14))
    acc = dy[N_COORDINATES + SLIDER]
    ecc = math.sqrt(result[R_ECCENTRICITY_X] ** 2 + result[R_ECCENTRICITY_Y] ** 2)
    if 0 <= rev < rev_stats.shape[0]:
        row = rev_stats[rev]
        if contact and track[K_PREVIOUS_CONTACT] < 0.5:
            row[S_IMPACTS] += 1.0
        row[S_CONTACT_TIME] += dt * contact_share(track[K_PREVIOUS_PENETRATION], result[R_PENETRATION])
        row[S_TIME] += dt
        row[S_ACC_MAX] = max(row[S_ACC_MAX], acc)
        row[S_ACC_MIN] = min(row[S_ACC_MIN], acc)
        row[S_FORCE_MAX] = max(row[S_FORCE_MAX], result[R_NORMAL_FORCE])
        row[S_ECC_MAX] = max(row[S_ECC_MAX], ecc)
    track[K_PREVIOUS_CONTACT] = 1.0 if contact else 0.0
    track[K_PREVIOUS_PENETRATION] = result[R_PENETRATION]
    # a point a sliver of its step before the sample time is on it: a fixed-step master's time, a sum of its steps,
    # ends 1e-18 s short of a multiple of the sample interval and had put that sample one step late
    slack = SAMPLE_TIME_SLACK * dt
    if t >= track[K_NEXT_SAMPLE] - slack:
        i = int(track[K_N_SAMPLES])
        if i < samples.shape[0]:
            s = samples[i]
            s[T_TIME] = t
            s[T_CRANK_ANGLE] = y[CRANK + 2]
            s[T_SLIDER_X] = y[Y_SLIDER_X]
            s[T_SLIDER_V] = y[Y_SLIDER_V]
            s[T_SLIDER_A] = acc
            s[T_PIN_FX] = result[R_PIN_FX]
            s[T_PIN_FY] = result[R_PIN_FY]
            s[T_NORMAL_FORCE] = result[R_NORMAL_FORCE]
            s[T_FRICTION_FORCE] = result[R_FRICTION_FORCE]
            s[T_ECC_X] = result[R_ECCENTRICITY_X]
            s[T_ECC_Y] = result[R_ECCENTRICITY_Y]
            s[T_PENETRATION] = result[R_PENETRATION]
            s[T_CONTACT] = 1.0 if contact else 0.0
            pin, bushing = joint_bodies(mp)
            s[T_RELATIVE_OMEGA] = body_rate(y, pin) - body_rate(y, bushing)
            s[T_TANGENTIAL_VELOCITY] = result[R_TANGENTIAL_VELOCITY]
            track[K_N_SAMPLES] = i + 1
        while track[K_NEXT_SAMPLE] <= t + slack:
            track[K_NEXT_SAMPLE] += track[K_SAMPLE_DT]


@kernel
def record_points(t_previous, times, ys, dys, results, mp, rev_stats, samples, track):
    """:func:`record_step` for each point of a recorded run (a third-party master's communication
    points): ``times`` (n,) [s], the point before them at ``t_previous`` [s]; ``ys`` and ``dys``
    (n, 18) the state and its derivative (only what :func:`record_step` reads need be filled),
    ``results`` (n, N_RESULT) the joint's outputs."""
    for i in range(times.shape[0]):
        record_step(times[i], times[i] - (times[i - 1] if i > 0 else t_previous), ys[i], dys[i], results[i], mp,
                    rev_stats, samples, track)


@kernel(inline='always')
def rk4_step(t, y, h, trig, mode, mp, joint, body_forces, ws, k1, stages):
    """One classical RK4 step of length h, y updated in place; k1 = f(t, y) and trig =
    ``angle_trig(y, mp)`` on entry, ``stages`` is (4, len(y)) scratch.  Four derivative
    evaluations, no bookkeeping.  The open joint's modes (MODE_EXTERNAL, MODE_LINEARISED: a co-simulation
    master's step) rotate the stages' trigonometry from trig; the others call libm as the FMU's joint does, so
    that a monolithic run and the FMU's Model Exchange run stay bit-identical."""
    n2 = y.shape[0]
    ys = stages[3]
    previous = k1
    open_joint = mode == MODE_EXTERNAL or mode == MODE_LINEARISED
    for s in range(3):
        c = _RK4_C[s]
        for i in range(n2):
            ys[i] = y[i] + c * h * previous[i]
        stage = stage_trig(trig, y, ys, mp) if open_joint else angle_trig(ys, mp)
        derivative_rotated(t + c * h, ys, stage, mode, mp, joint, body_forces, ws, stages[s])
        previous = stages[s]
    k2 = stages[0]
    k3 = stages[1]
    k4 = stages[2]
    for i in range(n2):
        y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@kernel(inline='always')   # two call sites, each with its mode a constant: numba prunes the other modes
def rk4_open_joint(t, h, n_steps, y, mode, mp, joint, body_forces, ws, dy, stages):
    """Integrate y over [t, t + h] in ``n_steps`` RK4 steps with the open joint's loads held at
    ``body_forces`` (MODE_EXTERNAL: a co-simulation step with the inputs held, Eqs. 39-44) or linearised
    (MODE_LINEARISED: F0 + J (u - u0) of the linearisation ``joint``, written to ``body_forces``);
    dy = f(t + h, y) on return.  ``stages``: (4, len(y)) scratch."""
    step = h / n_steps
    for i in range(n_steps):
        trig = angle_trig(y, mp)
        derivative_rotated(t + i * step, y, trig, mode, mp, joint, body_forces, ws, dy)
        rk4_step(t + i * step, y, step, trig, mode, mp, joint, body_forces, ws, dy, stages)
    derivative(t + h, y, mode, mp, joint, body_forces, ws, dy)


# the first values of the joint's result (layout.R_*) a wear update changes at an accepted point, its kinematics kept:
# the forces and torques on both bodies, the normal and friction force, the penetration
WORN_VALUES = R_PENETRATION + 1


@kernel(inline='always')   # one call site in the integrators' loop: inlined, a cold run compiles it once
def accept_point(t, y, h, k_end, mode, mp, joint, body_forces, ws, dy, reuse_k_end, before):
    """Joint bookkeeping at an accepted point, then dy = f(t, y) with the updated joint; returns True if the
    bookkeeping wore, or may have worn, the bushing (JOINT_EVALUATED, JOINT_WORN), the contact's first WORN_VALUES
    values before it in ``before`` (for :func:`record_accepted`).

    ``reuse_k_end``: ``k_end`` is f(t, y) and the joint's result array holds the contact
    evaluated there (DOPRI's last stage); both are reused unless the joint changed, and the
    contact is not evaluated again where the joint's bookkeeping left it evaluated (JOINT_EVALUATED).
    """
    pin, bushing = joint_bodies(mp)
    state = JOINT_UNCHANGED
    if mode == MODE_CLEARANCE:
        if not reuse_k_end:
            contact_at(joint, t, y, pin, bushing)
        for r in range(WORN_VALUES):
            before[r] = joint.result[r]
        state = accept_joint(joint, t, y, pin, bushing, h, True)
    if reuse_k_end and state == JOINT_UNCHANGED:
        for i in range(dy.shape[0]):
            dy[i] = k_end[i]
    elif mode == MODE_CLEARANCE and (state == JOINT_UNCHANGED or state == JOINT_EVALUATED):
        _derivative_evaluated_per_step(t, y, mp, joint, body_forces, ws, dy)
    else:
        _derivative_per_step(t, y, mode, mp, joint, body_forces, ws, dy)
    return state == JOINT_EVALUATED or state == JOINT_WORN


@kernel(inline='always')
def record_accepted(t, dt, y, dy, worn, implicit, before, mp, joint, body_forces, ws, record_dy, rev_stats, samples,
                    track):
    """:func:`record_step` of the accepted point (t, y) with f(t, y) = ``dy``; where its bookkeeping wore the
    bushing (``worn``: :func:`accept_point`), with the forces and the penetration the integrator's steps took
    there, the accelerations with those forces (``record_dy``, scratch).  A wear batch drops the force at once and
    the pin sinks into the new wear over the steps after it.  An explicit step (RK4, DOPRI) runs through that
    sawtooth: recorded at the middle of the jump, the mean of the contact before the wear (``before``) and after
    it.  An ``implicit`` step (BDF) ends with the force before the wear: recorded there.  Recorded after the drop,
    a run in lasting contact at fast wear sat at the sawtooth's bottom, off by up to a batch's drop (first order
    in the step; docs/reference/model.md §3.11).  Where nothing jumped (an FMU's step that joined its wear batch
    without applying it), the point as it is: no second derivative."""
    result = joint.result
    jumped = False
    if worn:
        for r in range(WORN_VALUES):
            jumped = jumped or before[r] != result[r]
    if not jumped:
        record_step(t, dt, y, dy, result, mp, rev_stats, samples, track)
        return
    share = 1.0 if implicit else 0.5
    for r in range(WORN_VALUES):
        after = result[r]
        result[r] = share * before[r] + (1.0 - share) * after
        before[r] = after
    _derivative_evaluated_per_step(t, y, mp, joint, body_forces, ws, record_dy)
    record_step(t, dt, y, record_dy, result, mp, rev_stats, samples, track)
    for r in range(WORN_VALUES):
        result[r] = before[r]


def integrate(method, t, t_end, y, control, mode, mp, joint, body_forces, ws, dy,
              rev_stats, samples, track):
    """Integrate y from t to t_end; ``dy`` is set to f(t, y) first and holds f at the end (t == t_end:
    only f(t, y)).
    ``joint`` is a :data:`core.joint_access.JointArrays` (the joint in process) or a
    :data:`~wearjoint.cosim.fmu_joint.FmuJoint` (an FMU's Model Exchange interface): the same steps.

    control = [h (RK4 step or DOPRI initial/next step), h_max, rtol, atol_position,
    atol_velocity, h_min, onset_penetration, h_max_free] (DOPRI: h_max bounds a step that starts in contact,
    h_max_free one that starts in free flight, where nothing wears).  Returns (t, accepted steps, rejected
    steps); control[0] holds the step to continue with.

    Contact onset (RK4 and DOPRI, MODE_CLEARANCE): a step that starts in free
    flight and ends deeper than ``onset_penetration`` inside the bushing is
    retried with a step interpolated (linearly in the signed penetration) to end
    just past the onset, so that the impact velocity stored for Eq. (15) does
    not depend on the step size.  DOPRI continues from the shortened step; RK4
    returns to its fixed step h after it.
    """
    n2 = y.shape[0]
    # a Python function: a compiled one allocating the scratch would make numba link and emit the whole
    # integrator again on a cold run (docs/how-to/choose_step_and_master.md, "First runs and speed")
    stages = np.empty((4, n2))                  # RK4 scratch
    k = np.empty((7, n2))                       # DOPRI stages; k[6] = f at the step's end
    k_stage = np.empty(n2)                      # f of the current stage (no views of k in the loop)
    y_new = np.empty(n2)
    before = np.empty(WORN_VALUES)             # the contact before an accepted point's wear
    record_dy = np.empty(n2)                    # f there with the forces recorded
    return _integrate_steps(method, t, t_end, y, control, mode, mp, joint, body_forces, ws, dy,
                            rev_stats, samples, track, stages, k, k_stage, y_new, before, record_dy)


@kernel
def _integrate_steps(method, t, t_end, y, control, mode, mp, joint, body_forces, ws, dy,
                     rev_stats, samples, track, stages, k, k_stage, y_new, before, record_dy):
    """The loop of :func:`integrate`, on preallocated scratch (a kernel cannot allocate)."""
    n2 = y.shape[0]
    n = N_COORDINATES
    result = joint.result
    h = control[0]
    h_max_contact = control[1]
    rtol = control[2]
    atol_q = control[3]
    atol_v = control[4]
    h_min = control[5]
    onset_tol = control[6]
    h_max_free = control[7]
    locate_onsets = mode == MODE_CLEARANCE
    pin, bushing = joint_bodies(mp)
    memory = joint.memory
    err_previous = 1e-4
    accepted = 0
    rejected = 0
    onset_step = np.inf                         # RK4: a shortened step that ends just past a contact onset
    _derivative_per_step(t, y, mode, mp, joint, body_forces, ws, dy)
    pen_start = result[R_PENETRATION]
    while t < t_end * (1.0 - 1e-15) - 1e-300 and not joint_failed(joint):
        if method == RK4:
            step = min(h, t_end - t, onset_step)
            for i in range(n2):
                y_new[i] = y[i]
            trig = angle_trig(y_new, mp) if mode == MODE_EXTERNAL else _UNUSED_TRIG   # only MODE_EXTERNAL rotates
            rk4_step(t, y_new, step, trig, mode, mp, joint, body_forces, ws, dy, stages)
            evaluated = False
            worn = False
            if locate_onsets:
                contact_at(joint, t + step, y_new, pin, bushing)
                retry = onset_retry_step(memory[M_ACTIVE] < 0.5, pen_start, result[R_PENETRATION], onset_tol, step,
                                         h_min)
                if retry > 0.0:
                    onset_step = retry
                    rejected += 1
                    continue
                for r in range(WORN_VALUES):
                    before[r] = result[r]
                state = accept_joint(joint, t + step, y_new, pin, bushing, step, True)
                evaluated = state == JOINT_UNCHANGED or state == JOINT_EVALUATED
                worn = state == JOINT_EVALUATED or state == JOINT_WORN
            onset_step = np.inf
            t += step
            accepted += 1
            for i in range(n2):
                y[i] = y_new[i]
            if evaluated:                       # the joint's result holds its contact at (t, y)
                derivative_evaluated(t, y, mp, joint, body_forces, ws, dy)
            else:
                derivative(t, y, mode, mp, joint, body_forces, ws, dy)
            record_accepted(t, step, y, dy, worn, False, before, mp, joint, body_forces, ws, record_dy, rev_stats,
                            samples, track)
            pen_start = result[R_PENETRATION]
            continue
        # Dormand-Prince 5(4)
        h_max = h_max_free if locate_onsets and memory[M_ACTIVE] < 0.5 else h_max_contact
        h = min(h, h_max)
        step = min(h, t_end - t)
        for i in range(n2):
            k[0, i] = dy[i]
        for stage in range(1, 7):
            for i in range(n2):
                acc = 0.0
                for j in range(stage):
                    acc += _DOPRI_A[stage, j] * k[j, i]
                y_new[i] = y[i] + step * acc
            derivative(t + _DOPRI_C[stage] * step, y_new, mode, mp, joint, body_forces, ws, k_stage)
            for i in range(n2):
                k[stage, i] = k_stage[i]
        retry = onset_retry_step(locate_onsets and memory[M_ACTIVE] < 0.5, pen_start, result[R_PENETRATION],
                                 onset_tol, step, h_min)
        if retry > 0.0:
            h = retry
            rejected += 1
            continue
        err = 0.0
        for i in range(n2):
            acc = 0.0
            for j in range(7):
                acc += _DOPRI_E[j] * k[j, i]
            e = step * acc
            scale = (atol_q if i < n else atol_v) + rtol * max(abs(y[i]), abs(y_new[i]))
            err += (e / scale) ** 2
        err = math.sqrt(err / n2)
        if err <= 1.0 or step <= h_min:
            t += step
            accepted += 1
            for i in range(n2):
                y[i] = y_new[i]
            worn = accept_point(t, y, step, k_stage, mode, mp, joint, body_forces, ws, dy, True, before)
            record_accepted(t, step, y, dy, worn, False, before, mp, joint, body_forces, ws, record_dy, rev_stats,
                            samples, track)
            pen_start = result[R_PENETRATION]
            # PI step-size control (Hairer, Norsett & Wanner, dopri5: beta = 0.04)
            factor = min(5.0, max(0.1, 0.9 * max(err, 1e-10) ** -_PI_EXPONENT * err_previous ** _PI_BETA))
            err_previous = max(err, 1e-4)
            if step == h:
                h = min(h_max, max(h_min, step * factor))
        else:
            rejected += 1
            h = max(h_min, step * max(0.2, 0.9 * err ** -_PI_EXPONENT))
    control[0] = h
    return t, accepted, rejected
