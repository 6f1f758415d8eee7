"""Slider-crank multibody kernels (paper Sec. 6.1, Eqs. 38-44).

Coordinates q = [x1 y1 th1 x2 y2 th2 x3 y3 th3] (crank, rod, slider, each at
its centre of mass).  Constraints (Eq. 39): crank pivot at the origin (crank-ground
revolute), the driver th1 = th0 - omega t, rod-slider revolute, slider on the X axis
without rotation, crank-rod revolute; the clearance joint's revolute (layout.CLEARANCE_*:
core.joint_location) is open, the ideal mechanism keeps all.  The equations of motion
(Eq. 44) are solved through the Schur complement (C M^-1 C^T) lambda = C M^-1 Q - c with
the diagonal mass matrix (Eq. 42) and Baumgarte stabilisation c = gamma - 2 alpha Phi_dot -
beta^2 Phi; with the crank-rod joint open, in closed form
(:func:`open_joint_accelerations_rotated`).
"""
import math

import numpy as np

from .jit import kernel
from .joint_access import NoJoint, contact_forces
from .joint_location import body_angle, bodies_trig, clearance_location, joint_bodies
from .layout import (
    CLEARANCE_CRANK_ROD, CRANK, GROUND, MODE_CLEARANCE, MODE_IDEAL, MODE_LINEARISED, MP_ALPHA, MP_BETA,
    MP_CRANK_INERTIA, MP_CRANK_LENGTH, MP_CRANK_MASS, MP_GRAVITY_X, MP_GRAVITY_Y, MP_OMEGA, MP_ROD_INERTIA,
    MP_ROD_LENGTH, MP_ROD_MASS, MP_SLIDER_INERTIA, MP_SLIDER_MASS, MP_THETA0, N_COORDINATES, N_RESULT,
    R_BUSHING_FX, R_BUSHING_FY, R_BUSHING_TORQUE, R_CONTACT, R_CONTACT_INDEX, R_NORMAL_FORCE, R_PIN_FX, R_PIN_FY,
    R_PIN_TORQUE, ROD, SLIDER,
)
from .linearisation import linearised_loads
from .slider_load import slider_load
from .trig import rotated_trig


@kernel(inline='always')
def no_joint(mp):
    """The joint argument of :func:`derivative` in MODE_EXTERNAL, which reads none of it: a
    :data:`~.joint_access.NoJoint` on ``mp``, so nothing is allocated and no contact kernel is compiled."""
    return NoJoint(mp)


NO_BODY = -1
N_CONSTRAINTS = 9
# Constraint rows and the bodies (offsets into q) each one touches: crank pivot, the crank-ground revolute
# (0, 1), driver (2), rod-slider revolute (3, 4), y3 = 0 (5), th3 = 0 (6), crank-rod revolute (7, 8).
ROW_BODIES = np.array([[CRANK, NO_BODY], [CRANK, NO_BODY], [CRANK, NO_BODY],
                       [ROD, SLIDER], [ROD, SLIDER], [SLIDER, NO_BODY], [SLIDER, NO_BODY],
                       [CRANK, ROD], [CRANK, ROD]])
# the first of the clearance joint's two revolute rows, by location (layout.CLEARANCE_*)
JOINT_ROWS = np.array([7, 3, 0])
# the rows the mechanism keeps: all (ideal), or all but the clearance joint's, by location
IDEAL_ROWS = np.arange(N_CONSTRAINTS)
OPEN_ROWS = np.array([[0, 1, 2, 3, 4, 5, 6], [0, 1, 2, 5, 6, 7, 8], [2, 3, 4, 5, 6, 7, 8]])


@kernel
def ldl_solve(a, b, lo, hi):
    """Solve a[lo:hi, lo:hi] x = b[lo:hi] for a symmetric positive definite block
    (lower triangle used) by L D L^T with one division per pivot; the block is
    overwritten by the factors, x by b."""
    for j in range(lo, hi):
        d = a[j, j]
        for k in range(lo, j):
            d -= a[j, k] * a[j, k] * a[k, k]
        a[j, j] = d
        inv = 1.0 / d
        for i in range(j + 1, hi):
            s = a[i, j]
            for k in range(lo, j):
                s -= a[i, k] * a[j, k] * a[k, k]
            a[i, j] = s * inv
    for i in range(lo, hi):
        s = b[i]
        for k in range(lo, i):
            s -= a[i, k] * b[k]
        b[i] = s
    for i in range(hi - 1, lo - 1, -1):
        s = b[i] / a[i, i]
        for k in range(i + 1, hi):
            s -= a[k, i] * b[k]
        b[i] = s


@kernel
def _revolute(row, q, qd, body_a, sax, say, body_b, sbx, sby, jac, phi, phi_dot, gamma):
    """Rows row, row+1 of a revolute pair: Phi = r_a + A_a s_a - r_b - A_b s_b (Eq. 39)."""
    for sign, body, sx, sy in ((1.0, body_a, sax, say), (-1.0, body_b, sbx, sby)):
        if body == GROUND:                         # a fixed point (sx, sy) of the ground
            phi[row] += sign * sx
            phi[row + 1] += sign * sy
            continue
        th = q[body + 2]
        w = qd[body + 2]
        c = math.cos(th)
        s = math.sin(th)
        asx = c * sx - s * sy
        asy = s * sx + c * sy
        jac[row, body] = sign
        jac[row + 1, body + 1] = sign
        jac[row, body + 2] = -sign * asy          # d(A s)/d th = (-(A s)_y, (A s)_x)
        jac[row + 1, body + 2] = sign * asx
        phi[row] += sign * (q[body] + asx)
        phi[row + 1] += sign * (q[body + 1] + asy)
        phi_dot[row] += sign * (qd[body] - w * asy)
        phi_dot[row + 1] += sign * (qd[body + 1] + w * asx)
        gamma[row] += sign * asx * w * w           # Eq. (41)
        gamma[row + 1] += sign * asy * w * w


@kernel
def constraints(t, q, qd, mp, jac, phi, phi_dot, gamma):
    """Jacobian (Eq. 40), Phi (Eq. 39), Phi_dot and gamma (Eq. 41) of all N_CONSTRAINTS rows (ROW_BODIES)."""
    for r in range(N_CONSTRAINTS):
        phi[r] = 0.0
        phi_dot[r] = 0.0
        gamma[r] = 0.0
        for c in range(N_COORDINATES):
            jac[r, c] = 0.0
    l1 = mp[MP_CRANK_LENGTH]
    l2 = mp[MP_ROD_LENGTH]
    # the int arguments as np.int64: a literal one would make numba compile _revolute once per value
    _revolute(np.int64(0), q, qd, np.int64(CRANK), -0.5 * l1, 0.0, np.int64(GROUND), 0.0, 0.0, jac, phi, phi_dot,
              gamma)
    jac[2, CRANK + 2] = 1.0                       # driver th1 - (th0 - omega t) = 0
    phi[2] = q[CRANK + 2] - (mp[MP_THETA0] - mp[MP_OMEGA] * t)
    phi_dot[2] = qd[CRANK + 2] + mp[MP_OMEGA]
    _revolute(np.int64(3), q, qd, np.int64(ROD), 0.5 * l2, 0.0, np.int64(SLIDER), 0.0, 0.0, jac, phi, phi_dot,
              gamma)
    jac[5, SLIDER + 1] = 1.0                      # y3 = 0
    phi[5] = q[SLIDER + 1]
    phi_dot[5] = qd[SLIDER + 1]
    jac[6, SLIDER + 2] = 1.0                      # th3 = 0
    phi[6] = q[SLIDER + 2]
    phi_dot[6] = qd[SLIDER + 2]
    _revolute(np.int64(7), q, qd, np.int64(CRANK), 0.5 * l1, 0.0, np.int64(ROD), -0.5 * l2, 0.0, jac, phi,
              phi_dot, gamma)


@kernel
def mass_diagonal(mp, out):
    """Diagonal of M, Eq. (42)."""
    out[0] = out[1] = mp[MP_CRANK_MASS]
    out[2] = mp[MP_CRANK_INERTIA]
    out[3] = out[4] = mp[MP_ROD_MASS]
    out[5] = mp[MP_ROD_INERTIA]
    out[6] = out[7] = mp[MP_SLIDER_MASS]
    out[8] = mp[MP_SLIDER_INERTIA]


@kernel
def inverse_mass_diagonal(mp, out):
    """M^-1 of Eq. (42), its diagonal."""
    mass_diagonal(mp, out)
    for k in range(N_COORDINATES):
        out[k] = 1.0 / out[k]


@kernel
def accelerations(t, q, qd, mp, ideal, body_forces, ws, qdd):
    """q_dd of Eq. (44) for the clearance joint's loads ``body_forces`` = (Fx, Fy, T) on its pin body then
    (Fx, Fy, T) on its bushing body (Eq. 43 with gravity (g_x, g_y) and the slider's load, :func:`slider_load`);
    ``ideal``: the joint's revolute kept (its loads are then the constraint's, ``body_forces`` zero).  The
    Lagrange multipliers of the kept rows (IDEAL_ROWS or OPEN_ROWS, in their order) are left in ws[3]."""
    jac, schur, phi, phi_dot, gamma, minv, force = ws
    constraints(t, q, qd, mp, jac, phi, phi_dot, gamma)
    location = clearance_location(mp)
    rows = IDEAL_ROWS if ideal else OPEN_ROWS[location]
    m = rows.shape[0]
    gx = mp[MP_GRAVITY_X]
    gy = mp[MP_GRAVITY_Y]
    for k in range(N_COORDINATES):
        force[k] = 0.0
    for body, mass in ((CRANK, mp[MP_CRANK_MASS]), (ROD, mp[MP_ROD_MASS]), (SLIDER, mp[MP_SLIDER_MASS])):
        force[body] = mass * gx
        force[body + 1] = mass * gy
    force[SLIDER] -= slider_load(t, mp)
    pin, bushing = joint_bodies(mp)
    for k in range(3):
        force[pin + k] += body_forces[k]
        if bushing != GROUND:
            force[bushing + k] += body_forces[3 + k]
    alpha = mp[MP_ALPHA]
    beta = mp[MP_BETA]
    for r in range(N_CONSTRAINTS):                # c of every row into gamma
        gamma[r] = gamma[r] - 2.0 * alpha * phi_dot[r] - beta * beta * phi[r]
    # Schur system (C M^-1 C^T) lambda = C M^-1 Q - c over the kept rows, assembled over the bodies
    # that each pair of rows shares (ROW_BODIES); the rhs, then lambda, in phi_dot
    for i in range(m):
        r = rows[i]
        s = 0.0
        for slot in range(2):
            b = ROW_BODIES[r, slot]
            if b != NO_BODY:
                for c in range(b, b + 3):
                    s += jac[r, c] * minv[c] * force[c]
        phi_dot[i] = s - gamma[r]
        for i2 in range(i + 1):
            r2 = rows[i2]
            s = 0.0
            for slot in range(2):
                b = ROW_BODIES[r, slot]
                if b != NO_BODY and (ROW_BODIES[r2, 0] == b or ROW_BODIES[r2, 1] == b):
                    for c in range(b, b + 3):
                        s += jac[r, c] * minv[c] * jac[r2, c]
            schur[i, i2] = s
    ldl_solve(schur, phi_dot, np.int64(0), m)
    for c in range(N_COORDINATES):
        qdd[c] = force[c]
    for i in range(m):
        r = rows[i]
        for slot in range(2):
            b = ROW_BODIES[r, slot]
            if b != NO_BODY:
                for c in range(b, b + 3):
                    qdd[c] -= jac[r, c] * phi_dot[i]
    for c in range(N_COORDINATES):
        qdd[c] *= minv[c]


@kernel(inline='always')
def open_joint_accelerations_rotated(t, y, mp, body_forces, cos1, sin1, cos2, sin2, dy):
    """dy[n:] = q_dd of Eq. (44) with the crank-rod joint open, in closed form; y = [q, q_dot],
    cos1, sin1 and cos2, sin2 are cos/sin of the crank and rod angles.  Reads and writes
    the state vectors by index (no array views: their reference counting is the
    dominant cost of a hot loop).

    The same equations as :func:`accelerations` (Eqs. 39-44, Baumgarte
    c = gamma - 2 alpha Phi_dot - beta^2 Phi), solved through their structure:
    the crank's three rows (pivot, driver) are square in its coordinates, so
    C_1 q_dd_1 = c_1 fixes its accelerations whatever the loads; the slider's
    rows y3 = 0 and th3 = 0 fix y3_dd and th3_dd; what remains is the rod-slider
    revolute (rows 3-4) on (x2, y2, th2, x3), a 2x2 Schur complement.
    """
    n = N_COORDINATES
    alpha2 = 2.0 * mp[MP_ALPHA]
    beta_sq = mp[MP_BETA] * mp[MP_BETA]
    # crank: pivot r1 + A1 (-l1/2, 0) = 0 (rows 0-1) and driver th1 = th0 - omega t (row 2)
    th1 = y[CRANK + 2]
    w1 = y[n + CRANK + 2]
    h1 = -0.5 * mp[MP_CRANK_LENGTH]
    ax = h1 * cos1                              # A1 s1
    ay = h1 * sin1
    c0 = ax * w1 * w1 - alpha2 * (y[n + CRANK] - w1 * ay) - beta_sq * (y[CRANK] + ax)
    c1 = ay * w1 * w1 - alpha2 * (y[n + CRANK + 1] + w1 * ax) - beta_sq * (y[CRANK + 1] + ay)
    c2 = -alpha2 * (w1 + mp[MP_OMEGA]) - beta_sq * (th1 - (mp[MP_THETA0] - mp[MP_OMEGA] * t))
    dy[n + CRANK + 2] = c2
    dy[n + CRANK] = c0 + ay * c2                # x1_dd - ay th1_dd = c0
    dy[n + CRANK + 1] = c1 - ax * c2            # y1_dd + ax th1_dd = c1
    # slider: y3 = 0 (row 5), th3 = 0 (row 6)
    dy[n + SLIDER + 1] = -alpha2 * y[n + SLIDER + 1] - beta_sq * y[SLIDER + 1]
    dy[n + SLIDER + 2] = -alpha2 * y[n + SLIDER + 2] - beta_sq * y[SLIDER + 2]
    # rod-slider revolute r2 + A2 (l2/2, 0) - r3 = 0 (rows 3-4): J on (x2, y2, th2, x3)
    # row 3 = [1, 0, -by, -1], row 4 = [0, 1, bx, 0] (y3 enters row 4 with y3_dd known)
    w2 = y[n + ROD + 2]
    h2 = 0.5 * mp[MP_ROD_LENGTH]
    bx = h2 * cos2
    by = h2 * sin2
    c3 = bx * w2 * w2 - alpha2 * (y[n + ROD] - w2 * by - y[n + SLIDER]) - beta_sq * (y[ROD] + bx - y[SLIDER])
    c4 = (by * w2 * w2 - alpha2 * (y[n + ROD + 1] + w2 * bx - y[n + SLIDER + 1])
          - beta_sq * (y[ROD + 1] + by - y[SLIDER + 1]) + dy[n + SLIDER + 1])
    inv_m2 = 1.0 / mp[MP_ROD_MASS]
    inv_i2 = 1.0 / mp[MP_ROD_INERTIA]
    inv_m3 = 1.0 / mp[MP_SLIDER_MASS]
    fx2 = body_forces[3] + mp[MP_ROD_MASS] * mp[MP_GRAVITY_X]
    fy2 = body_forces[4] + mp[MP_ROD_MASS] * mp[MP_GRAVITY_Y]
    tz2 = body_forces[5]
    fx3 = mp[MP_SLIDER_MASS] * mp[MP_GRAVITY_X] - slider_load(t, mp)   # gravity and the load along the slide
    # (J M^-1 J^T) lambda = J M^-1 Q - c
    s11 = inv_m2 + by * by * inv_i2 + inv_m3
    s12 = -by * bx * inv_i2
    s22 = inv_m2 + bx * bx * inv_i2
    r1 = fx2 * inv_m2 - by * tz2 * inv_i2 - fx3 * inv_m3 - c3
    r2 = fy2 * inv_m2 + bx * tz2 * inv_i2 - c4
    det = s11 * s22 - s12 * s12
    lam3 = (s22 * r1 - s12 * r2) / det
    lam4 = (s11 * r2 - s12 * r1) / det
    dy[n + ROD] = (fx2 - lam3) * inv_m2
    dy[n + ROD + 1] = (fy2 - lam4) * inv_m2
    dy[n + ROD + 2] = (tz2 + by * lam3 - bx * lam4) * inv_i2
    dy[n + SLIDER] = (fx3 + lam3) * inv_m3


@kernel(inline='always')
def angle_trig(y, mp):
    """(cos, sin) of the clearance joint's pin body's angle, then of its bushing body's, in state y (the crank's
    and the rod's for the crank-rod joint, which :func:`open_joint_accelerations_rotated` shares)."""
    pin, bushing = joint_bodies(mp)
    return bodies_trig(y, pin, bushing)


@kernel(inline='always')
def stage_trig(trig, y, y_stage, mp):
    """:func:`angle_trig` of y_stage from trig = angle_trig(y, mp), y_stage a Runge-Kutta stage of a step from y."""
    pin, bushing = joint_bodies(mp)
    cos1, sin1 = rotated_trig(trig[0], trig[1], body_angle(y, pin), body_angle(y_stage, pin))
    cos2, sin2 = rotated_trig(trig[2], trig[3], body_angle(y, bushing), body_angle(y_stage, bushing))
    return cos1, sin1, cos2, sin2


@kernel(inline='always')
def derivative(t, y, mode, mp, joint, body_forces, ws, dy):
    """dy/dt of y = [q, q_dot].  MODE_CLEARANCE evaluates the joint (``joint``: a
    :data:`~.joint_access.JointArrays`, or a :data:`~wearjoint.cosim.fmu_joint.FmuJoint`; writes its result
    array); MODE_EXTERNAL uses ``body_forces`` as given, MODE_LINEARISED writes them from ``joint``, a linearisation
    (:func:`~.linearisation.linearised_loads`); MODE_IDEAL has none and writes the ideal
    revolute's reaction to the joint's result array (:func:`ideal_joint_reaction`)."""
    derivative_rotated(t, y, angle_trig(y, mp), mode, mp, joint, body_forces, ws, dy)


@kernel(inline='always')
def derivative_rotated(t, y, trig, mode, mp, joint, body_forces, ws, dy):
    """:func:`derivative` with trig = :func:`angle_trig` (y, mp) given (one set of trigonometric
    values for the pin's and the bushing's bodies, the joint and the mechanism)."""
    if mode == MODE_CLEARANCE:
        cos1, sin1, cos2, sin2 = trig
        pin, bushing = joint_bodies(mp)
        contact_forces(joint, t, y, pin, bushing, cos1, sin1, cos2, sin2)
    elif mode == MODE_LINEARISED:                # ``joint``: the linearisation (layout.LIN_*)
        linearised_loads(joint, y, mp, body_forces)
    _derivative_joint_evaluated(t, y, trig, mode, mp, joint, body_forces, ws, dy)


@kernel(inline='always')
def derivative_evaluated(t, y, mp, joint, body_forces, ws, dy):
    """:func:`derivative` of MODE_CLEARANCE where ``joint.result`` already holds the joint's contact at (t, y)
    (an accepted point whose joint did not change, or was evaluated on its new state): not evaluated again."""
    _derivative_joint_evaluated(t, y, angle_trig(y, mp), MODE_CLEARANCE, mp, joint, body_forces, ws, dy)


@kernel(inline='always')
def _derivative_joint_evaluated(t, y, trig, mode, mp, joint, body_forces, ws, dy):
    """:func:`derivative_rotated` after its joint's evaluation (MODE_CLEARANCE: the forces from ``joint.result``)."""
    n = N_COORDINATES
    cos1, sin1, cos2, sin2 = trig
    if mode == MODE_CLEARANCE:
        result = joint.result
        body_forces[0] = result[R_PIN_FX]
        body_forces[1] = result[R_PIN_FY]
        body_forces[2] = result[R_PIN_TORQUE]
        body_forces[3] = result[R_BUSHING_FX]
        body_forces[4] = result[R_BUSHING_FY]
        body_forces[5] = result[R_BUSHING_TORQUE]
    elif mode == MODE_IDEAL:
        for k in range(6):
            body_forces[k] = 0.0
    for k in range(n):
        dy[k] = y[n + k]
    if mode == MODE_IDEAL:
        accelerations(t, y[:n], y[n:], mp, True, body_forces, ws, dy[n:])
        ideal_joint_reaction(ws, mp, joint.result)
    elif clearance_location(mp) == CLEARANCE_CRANK_ROD:
        open_joint_accelerations_rotated(t, y, mp, body_forces, cos1, sin1, cos2, sin2, dy)
    else:
        accelerations(t, y[:n], y[n:], mp, False, body_forces, ws, dy[n:])


@kernel(inline='always')
def ideal_joint_reaction(ws, mp, result):
    """The ideal clearance joint's reaction as the joint's result (layout.R_*) after :func:`accelerations` of the
    ideal mechanism: -C^T lambda of its two revolute rows (JOINT_ROWS) on the pin body and on the bushing body,
    about their centres of mass (the ground's: the reaction at the pivot, no torque); the normal force is its
    magnitude, the joint always closed (contact 1, no penetration, no eccentricity, no friction)."""
    jac = ws[0]
    lam = ws[3]                          # lambda after the Schur solve (IDEAL_ROWS: row r at r)
    location = clearance_location(mp)
    row = JOINT_ROWS[location]
    pin, bushing = joint_bodies(mp)
    for k in range(N_RESULT):
        result[k] = 0.0
    for k in range(3):
        result[R_PIN_FX + k] = -(jac[row, pin + k] * lam[row] + jac[row + 1, pin + k] * lam[row + 1])
        if bushing != GROUND:
            result[R_BUSHING_FX + k] = -(jac[row, bushing + k] * lam[row] + jac[row + 1, bushing + k] * lam[row + 1])
    if bushing == GROUND:
        result[R_BUSHING_FX] = -result[R_PIN_FX]
        result[R_BUSHING_FY] = -result[R_PIN_FY]
    result[R_NORMAL_FORCE] = math.sqrt(result[R_PIN_FX] ** 2 + result[R_PIN_FY] ** 2)
    result[R_CONTACT] = 1.0
    result[R_CONTACT_INDEX] = -1.0


@kernel
def initial_state(t, mp, ws, y):
    """Consistent conditions at time t [s]: pin centred in the bushing, positions on the
    ideal mechanism at th1 = th0 - omega t (Eq. 39), velocities solving the ideal velocity
    constraints.  Uses ws's scratch (ws[6] as the zero velocity)."""
    l1 = mp[MP_CRANK_LENGTH]
    l2 = mp[MP_ROD_LENGTH]
    th1 = mp[MP_THETA0] - mp[MP_OMEGA] * t
    px = l1 * math.cos(th1)
    py = l1 * math.sin(th1)
    xs = px + math.sqrt(l2 * l2 - py * py)
    th2 = math.atan2(-py, xs - px)
    n = N_COORDINATES
    for k in range(2 * n):
        y[k] = 0.0
    y[CRANK] = 0.5 * px
    y[CRANK + 1] = 0.5 * py
    y[CRANK + 2] = th1
    y[ROD] = px + 0.5 * l2 * math.cos(th2)
    y[ROD + 1] = py + 0.5 * l2 * math.sin(th2)
    y[ROD + 2] = th2
    y[SLIDER] = xs
    jac, schur, phi, phi_dot, gamma, _, zero = ws
    for c in range(n):
        zero[c] = 0.0
    constraints(t, y[:n], zero, mp, jac, phi, phi_dot, gamma)
    # C q_dot = -Phi_t (Phi_t: omega in the driver row, i.e. phi_dot at q_dot = 0);
    # C is square and regular, so q_dot = C^T z with (C C^T) z = -Phi_t
    m = N_CONSTRAINTS
    for r in range(m):
        gamma[r] = -phi_dot[r]
        for r2 in range(r + 1):
            s = 0.0
            for c in range(n):
                s += jac[r, c] * jac[r2, c]
            schur[r, r2] = s
    ldl_solve(schur, gamma, np.int64(0), np.int64(m))   # not literals: one compiled ldl_solve
    for c in range(n):
        s = 0.0
        for r in range(m):
            s += jac[r, c] * gamma[r]
        y[n + c] = s


@kernel
def ideal_joint_forces(times, mp, ws, result, y, qdd, body_forces, out):
    """out[k] = |the ideal clearance joint's reaction| [N] at times[k] [s]: the ideal mechanism's consistent
    state there (:func:`initial_state`), its accelerations under gravity and the slider's load (Eq. 44) and the
    reaction (:func:`ideal_joint_reaction`).  Scratch: ``result`` (layout.N_RESULT), ``y`` (2 N_COORDINATES),
    ``qdd`` (N_COORDINATES), ``body_forces`` (6, zeros)."""
    n = N_COORDINATES
    for k in range(times.shape[0]):
        initial_state(times[k], mp, ws, y)
        accelerations(times[k], y[:n], y[n:], mp, True, body_forces, ws, qdd)
        ideal_joint_reaction(ws, mp, result)
        out[k] = result[R_NORMAL_FORCE]
