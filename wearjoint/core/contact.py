"""Contact force kernels of the clearance joint (paper Secs. 2-4, Eqs. 1-23) and their exact
derivatives.

Pure numba functions on arrays.  Bodies: i carries the pin, j the bushing.  The contact model
(``jp[P_CONTACT_MODEL]``, docs/reference/model.md §3.10):

* 0, ``foundation`` (default): the elastic-foundation pressure of :mod:`.pressure` on every
  bushing point the pin overlaps, any number of arcs; its resultant is the elastic normal force,
  its direction the normal n, and both bodies' forces act at the pin-surface point
  Q = pin centre + R_i n (the pressure passes through the pin centre).
* 1, ``deepest``: the paper's, K delta^n at the deepest bushing point k (Eqs. 5-8), applied at
  the pin-surface point Q_i (Eq. 9) and the bushing point Q_j (Eq. 10).

On either, a damping law turns the elastic force F_e into the normal force (``jp[P_CONTACT_DAMPING]``,
:mod:`.damping`, docs/reference/model.md §3.5): 0, Hunt-Crossley, F_e max(0, 1 + alpha delta_dot) with alpha
from the restitution e_r at the impact speed v_r; 1 and 3, Lankarani-Nikravesh (Eq. 15, and with the exact
chi), F_e (1 + chi delta_dot / delta_dot^-) with the approach velocity stored at the contact's onset; 2, Tsuji,
max(0, F_e + c sqrt(F_e / delta) delta_dot): a restitution that does not depend on the speed.  Ambrosio's
friction (Eqs. 18-19) acts along t = n rotated +90 deg.  Conventions
(docs/reference/model.md §3): delta = R_i - |d| (Eq. 6) at the deepest point; n points from the pin centre into
the bushing; the normal force on the pin is -F_N n; friction on the pin opposes its sliding relative
to the bushing; torques are planar cross products l_x F_y - l_y F_x.

Derivatives are forward mode through the same code: :func:`_forces` carries, beside every
value, its derivative along one direction of the 12 kinematic inputs (x, y, theta, vx, vy,
omega of body i, then of body j); :func:`contact_jacobian` runs it for the 12 unit directions.
"""
import math

import numpy as np

from .geometry import angle_near_point, find_deepest_point, point_nearest_angle
from .jit import kernel
from .layout import (
    CONTACT_FOUNDATION, DAMPING_HUNT_CROSSLEY, DAMPING_TSUJI, M_ACTIVE, M_IMPACT_VELOCITY, N_KINEMATIC_INPUTS,
    N_JOINT_PARAMETERS, N_MEMORY, N_RESULT, P_BUSHING_OFFSET_X, P_BUSHING_OFFSET_Y, P_BUSHING_RADIUS,
    P_CONTACT_DAMPING, P_CONTACT_MODEL, P_DAMPING_COEFFICIENT, P_EXPONENT, P_FOUNDATION_MODULUS, P_FRICTION,
    P_PIN_OFFSET_X, P_PIN_OFFSET_Y, P_PIN_RADIUS, P_STIFFNESS, P_V0, P_V1, P_VELOCITY_FLOOR,
    R_BUSHING_FX, R_BUSHING_FY, R_BUSHING_TORQUE, R_CONTACT, R_CONTACT_ANGLE, R_CONTACT_INDEX, R_ECCENTRICITY_X,
    R_ECCENTRICITY_Y, R_FRICTION_FORCE, R_NORMAL_FORCE, R_PENETRATION, R_PENETRATION_RATE, R_PIN_FX, R_PIN_FY,
    R_PIN_TORQUE, R_TANGENTIAL_VELOCITY,
)
from .pressure import foundation_resultant

TWO_PI = 2.0 * math.pi
NO_DIRECTION = (0.0,) * N_KINEMATIC_INPUTS


@kernel
def ambrosio_friction_factor(sliding_speed, v0, v1):
    """Dynamic correction coefficient c_d of Eq. (19) on |v_T|; 0 below v0, 1 above v1."""
    if sliding_speed <= v0:
        return 0.0
    if sliding_speed >= v1:
        return 1.0
    return (sliding_speed - v0) / (v1 - v0)


@kernel(inline='always')
def _ambrosio_slope(sliding_speed, v0, v1):
    """d c_d / d|v_T| of :func:`ambrosio_friction_factor` [s/m] (0 outside the ramp)."""
    return 1.0 / (v1 - v0) if v0 < sliding_speed < v1 else 0.0


@kernel
def _deepest_elastic_force(ex, ey, k, d2, jp, cos_phi, sin_phi, wear_depth):
    """The paper's elastic force on the pin at the deepest point k, bushing frame: -K delta^n m with
    m = d_k / |d_k|, and its Jacobian in e (returns f_x, f_y, J11, J12, J21, J22)."""
    rho = jp[P_BUSHING_RADIUS] + wear_depth[k]
    dx = rho * cos_phi[k] - ex
    dy = rho * sin_phi[k] - ey
    d = math.sqrt(d2)
    if d <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    mx = dx / d
    my = dy / d
    delta = jp[P_PIN_RADIUS] - d
    exponent = jp[P_EXPONENT]
    if exponent == 1.5:               # delta sqrt(delta): several times cheaper than pow
        root = math.sqrt(delta)
        power = delta * root
        slope = 1.5 * root
    else:
        power = delta ** exponent
        slope = exponent * delta ** (exponent - 1.0)
    stiffness = jp[P_STIFFNESS]
    a = -stiffness * slope              # -K n delta^(n-1) m m^T + K delta^n (I - m m^T) / |d|
    b = stiffness * power / d
    return (-stiffness * power * mx, -stiffness * power * my,
            a * mx * mx + b * (1.0 - mx * mx), (a - b) * mx * my, (a - b) * mx * my, a * my * my + b * (1.0 - my * my))


@kernel(inline='always')
def _cross(lx, ly, fx, fy):
    return lx * fy - ly * fx


@kernel(inline='always')
def _kinematics(xi, yi, ci, si, xj, yj, cj, sj, dq, jp):
    """Pin centre (Eq. 1) and eccentricity e = A_j^T (r_i^P - r_j^P) with their derivatives along dq:
    returns ((ax, ay, gx, gy, ex, ey), (their derivatives)) with a = A_i s_i^P the pin centre from
    body i's reference point and g = r_i^P - r_j^P (global)."""
    ax = ci * jp[P_PIN_OFFSET_X] - si * jp[P_PIN_OFFSET_Y]
    ay = si * jp[P_PIN_OFFSET_X] + ci * jp[P_PIN_OFFSET_Y]
    bx = cj * jp[P_BUSHING_OFFSET_X] - sj * jp[P_BUSHING_OFFSET_Y]
    by = sj * jp[P_BUSHING_OFFSET_X] + cj * jp[P_BUSHING_OFFSET_Y]
    gx = xi + ax - (xj + bx)
    gy = yi + ay - (yj + by)
    ex = cj * gx + sj * gy
    ey = -sj * gx + cj * gy
    dax = -ay * dq[2]
    day = ax * dq[2]
    dgx = dq[0] + dax - dq[6] + by * dq[8]
    dgy = dq[1] + day - dq[7] - bx * dq[8]
    dex = cj * dgx + sj * dgy + ey * dq[8]
    dey = -sj * dgx + cj * dgy - ex * dq[8]
    return (ax, ay, gx, gy, ex, ey), (dax, day, dgx, dgy, dex, dey)


@kernel(inline='always')
def _forces(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, dq, jp, memory, elastic, common_point,
            bushing_point, fallback, depth):
    """Forces of the contact from the elastic force on the pin ``elastic`` = (f_x, f_y, J11, J12, J21, J22)
    (bushing frame, J its Jacobian in e), with their derivatives along dq (forward mode).
    ``common_point``: both bodies' forces act at Q = pin centre + R_i n (the foundation), else body
    j's at ``bushing_point`` (bushing frame, from the bushing centre: the deepest point, Eq. 10).
    ``fallback``: the normal (bushing frame) where the elastic force is exactly 0.  ``depth``: the penetration
    delta (Eq. 6) and the unit vector d_k / |d_k| (bushing frame) whose product with de is its derivative.
    Returns (values, derivatives), each (F_x, F_y, T_i, T_j, F_N, F_T, v_T, delta_dot, n_x, n_y) with
    F = (F_x, F_y) on the pin (global), T the torques about the reference points, n global."""
    (ax, ay, gx, gy, ex, ey), (dax, day, dgx, dgy, dex, dey) = _kinematics(xi, yi, ci, si, xj, yj, cj, sj, dq, jp)
    flx, fly, j11, j12, j21, j22 = elastic
    dflx = j11 * dex + j12 * dey
    dfly = j21 * dex + j22 * dey
    f_e = math.sqrt(flx * flx + fly * fly)
    if f_e > 0.0:                                   # n = -f / |f| (bushing frame), Eq. (8)
        nlx = -flx / f_e
        nly = -fly / f_e
        df_e = (flx * dflx + fly * dfly) / f_e
        dnlx = -(dflx + nlx * df_e) / f_e
        dnly = -(dfly + nly * df_e) / f_e
    else:
        nlx, nly = fallback
        df_e = dnlx = dnly = 0.0
    nx = cj * nlx - sj * nly                        # global normal, and t = n rotated +90 deg
    ny = sj * nlx + cj * nly
    dnx = cj * dnlx - sj * dnly - ny * dq[8]
    dny = sj * dnlx + cj * dnly + nx * dq[8]
    tx, ty, dtx, dty = -ny, nx, -dny, dnx
    pin_radius = jp[P_PIN_RADIUS]
    lix = ax + pin_radius * nx                      # Q_i - r_i, Eq. (9)
    liy = ay + pin_radius * ny
    dlix = dax + pin_radius * dnx
    dliy = day + pin_radius * dny
    if common_point:                                # Q - r_j = g + A_j s_j^P + R_i n
        bx = cj * jp[P_BUSHING_OFFSET_X] - sj * jp[P_BUSHING_OFFSET_Y]
        by = sj * jp[P_BUSHING_OFFSET_X] + cj * jp[P_BUSHING_OFFSET_Y]
        ljx = gx + bx + pin_radius * nx
        ljy = gy + by + pin_radius * ny
        dljx = dgx - by * dq[8] + pin_radius * dnx
        dljy = dgy + bx * dq[8] + pin_radius * dny
    else:                                           # Q_j - r_j = A_j (s_j^P + rho_k u_k), Eq. (10)
        sx = jp[P_BUSHING_OFFSET_X] + bushing_point[0]
        sy = jp[P_BUSHING_OFFSET_Y] + bushing_point[1]
        ljx = cj * sx - sj * sy
        ljy = sj * sx + cj * sy
        dljx = -ljy * dq[8]
        dljy = ljx * dq[8]
    # material velocities of the two contact points and their difference (Eqs. 11-12)
    rvx = (vxi - wi * liy) - (vxj - wj * ljy)
    rvy = (vyi + wi * lix) - (vyj + wj * ljx)
    drvx = (dq[3] - dq[5] * liy - wi * dliy) - (dq[9] - dq[11] * ljy - wj * dljy)
    drvy = (dq[4] + dq[5] * lix + wi * dlix) - (dq[10] + dq[11] * ljx + wj * dljx)
    rate = rvx * nx + rvy * ny                      # Eq. (13)
    drate = drvx * nx + drvy * ny + rvx * dnx + rvy * dny
    v_t = rvx * tx + rvy * ty                       # Eq. (14)
    dv_t = drvx * tx + drvy * ty + rvx * dtx + rvy * dty
    # the damping law (core.damping, docs/reference/model.md §3.5): Hunt-Crossley with a constant alpha, Lankarani-Nikravesh
    # with the onset velocity stored, Eq. (15), or Tsuji's F_e + c sqrt(F_e / delta) delta_dot
    law = jp[P_CONTACT_DAMPING]
    coefficient = jp[P_DAMPING_COEFFICIENT]
    if law == DAMPING_TSUJI:                        # c sqrt(F_e / delta): c sqrt(K delta^(n-1)) for K delta^n
        delta, ux, uy = depth
        if f_e > 0.0 and delta > 0.0:
            scale = coefficient * math.sqrt(f_e / delta)
            ddelta = ux * dex + uy * dey
            f_n = f_e + scale * rate
            df_n = df_e + scale * (0.5 * rate * (df_e / f_e - ddelta / delta) + drate)
        else:
            f_n = df_n = 0.0
    else:
        if law == DAMPING_HUNT_CROSSLEY:
            h = 1.0 + coefficient * rate
            dh = coefficient * drate
        else:
            if memory[M_ACTIVE] > 0.5:
                impact_velocity = memory[M_IMPACT_VELOCITY]
                dh = coefficient * drate / impact_velocity
            elif rate > jp[P_VELOCITY_FLOOR]:       # the approach velocity stands in: h = 1 + chi
                impact_velocity = rate
                dh = 0.0
            else:
                impact_velocity = jp[P_VELOCITY_FLOOR]
                dh = coefficient * drate / impact_velocity
            h = 1.0 + coefficient * rate / impact_velocity
        f_n = f_e * h
        df_n = df_e * h + f_e * dh
    if f_n <= 0.0:                                  # no adhesion
        f_n = df_n = 0.0
    # Ambrosio friction, Eqs. (18-19): d(c_d(|v|) sign v)/dv = c_d'(|v|)
    mu = jp[P_FRICTION]
    sign = 1.0 if v_t > 0.0 else -1.0
    c_d = ambrosio_friction_factor(abs(v_t), jp[P_V0], jp[P_V1])
    f_t = -mu * c_d * f_n * sign
    df_t = -mu * (_ambrosio_slope(abs(v_t), jp[P_V0], jp[P_V1]) * dv_t * f_n + c_d * sign * df_n)
    fx = -f_n * nx + f_t * tx                       # Eq. (20), on the pin
    fy = -f_n * ny + f_t * ty
    dfx = -df_n * nx - f_n * dnx + df_t * tx + f_t * dtx
    dfy = -df_n * ny - f_n * dny + df_t * ty + f_t * dty
    t_i = _cross(lix, liy, fx, fy)                  # Eq. (21)
    t_j = -_cross(ljx, ljy, fx, fy)                 # Eqs. (22-23): -F at Q_j
    dt_i = _cross(dlix, dliy, fx, fy) + _cross(lix, liy, dfx, dfy)
    dt_j = -_cross(dljx, dljy, fx, fy) - _cross(ljx, ljy, dfx, dfy)
    return ((fx, fy, t_i, t_j, f_n, f_t, v_t, rate, nlx, nly),
            (dfx, dfy, dt_i, dt_j, df_n, df_t, dv_t, drate, dnlx, dnly))


@kernel
def evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min,
                     memory, out):
    """Contact forces of the clearance joint for given body kinematics (Eqs. 1-23, 34-37).

    pos = (x, y, theta) of a body's reference point [m, m, rad], vel = its
    velocities; i = pin body, j = bushing body.  ``memory`` holds the contact
    onset bookkeeping of accepted steps: while no contact is active, the
    current approach velocity stands in for delta_dot^- (a contact starting
    inside a step).  Writes forces, torques and diagnostics into ``out``
    (layout.R_*); never changes the joint's state.  The deepest point that ``out`` holds
    from the previous evaluation seeds the search (work only: the result is exact).
    """
    evaluate_contact_scalars(pos_i[0], pos_i[1], math.cos(pos_i[2]), math.sin(pos_i[2]), vel_i[0], vel_i[1],
                             vel_i[2], pos_j[0], pos_j[1], math.cos(pos_j[2]), math.sin(pos_j[2]), vel_j[0],
                             vel_j[1], vel_j[2], jp, cos_phi, sin_phi, wear_depth, block_min, memory, out)


@kernel
def evaluate_contact_scalars(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, jp, cos_phi, sin_phi,
                             wear_depth, block_min, memory, out):
    """:func:`evaluate_contact` on scalar kinematics: position (x, y), cos/sin theta and
    velocities (vx, vy, omega) of the pin body i and the bushing body j.  For hosts
    that hold the bodies in a state vector (the mechanism's right-hand side, which
    also shares cos/sin with the equations of motion): no array views, whose
    reference counting costs more than the contact itself in a hot loop."""
    _contact(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, jp, cos_phi, sin_phi, wear_depth, block_min,
             memory, out, False)


@kernel
def contact_jacobian(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, out,
                     jacobian):
    """:func:`evaluate_contact` into ``out``, and the exact derivatives of its outputs with respect to
    the 12 kinematic inputs into ``jacobian`` (N_RESULT x 12: d out[r] / d input[m], inputs x, y,
    theta, vx, vy, omega of body i, then of body j).  Rows of the discrete outputs (contact flag,
    deepest point) are 0.  Where the force is not differentiable (the deepest point changes, friction's
    ramp ends, the contact begins) it is one of the one-sided derivatives.  The 12 directions are one loop
    that stores into ``jacobian`` flattened (rows it need not check for overlaps), with the parameters and
    the memory as values (:func:`_as_values`): the compiler computes what does not depend on the direction
    once and runs the directions side by side, in SIMD lanes."""
    xi, yi, ci, si = pos_i[0], pos_i[1], math.cos(pos_i[2]), math.sin(pos_i[2])
    xj, yj, cj, sj = pos_j[0], pos_j[1], math.cos(pos_j[2]), math.sin(pos_j[2])
    vxi, vyi, wi, vxj, vyj, wj = vel_i[0], vel_i[1], vel_i[2], vel_j[0], vel_j[1], vel_j[2]
    in_contact, elastic, common_point, bushing_point, fallback, dkx, dky, d = _contact(
        xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, jp, cos_phi, sin_phi, wear_depth, block_min,
        memory, out, True)
    ex = out[R_ECCENTRICITY_X]
    ey = out[R_ECCENTRICITY_Y]
    e2 = ex * ex + ey * ey
    depth = (out[R_PENETRATION], fallback[0], fallback[1])
    jp, memory = _as_values(jp, memory)
    entries = jacobian.flat                                         # d out[r] / d input[m] at 12 r + m
    for k in range(N_RESULT * N_KINEMATIC_INPUTS):
        entries[k] = 0.0
    if not in_contact:                                              # the contact angle is the direction of e
        for m in range(N_KINEMATIC_INPUTS):
            dex, dey = _put_geometry_rows(entries, m, _unit_direction(m), xi, yi, ci, si, xj, yj, cj, sj, jp, dkx,
                                          dky, d)
            _put(entries, R_CONTACT_ANGLE, m, (ex * dey - ey * dex) / e2 if e2 > 0.0 else 0.0)
        return
    for m in range(N_KINEMATIC_INPUTS):
        dq = _unit_direction(m)
        _put_geometry_rows(entries, m, dq, xi, yi, ci, si, xj, yj, cj, sj, jp, dkx, dky, d)
        values, derivative = _forces(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, dq, jp, memory,
                                     elastic, common_point, bushing_point, fallback, depth)
        nlx, nly = values[8], values[9]
        dfx, dfy, dt_i, dt_j, df_n, df_t, dv_t, drate, dnlx, dnly = derivative
        _put(entries, R_PIN_FX, m, dfx)
        _put(entries, R_PIN_FY, m, dfy)
        _put(entries, R_PIN_TORQUE, m, dt_i)
        _put(entries, R_BUSHING_FX, m, -dfx)
        _put(entries, R_BUSHING_FY, m, -dfy)
        _put(entries, R_BUSHING_TORQUE, m, dt_j)
        _put(entries, R_NORMAL_FORCE, m, df_n)
        _put(entries, R_FRICTION_FORCE, m, df_t)
        _put(entries, R_TANGENTIAL_VELOCITY, m, dv_t)
        _put(entries, R_PENETRATION_RATE, m, drate)
        _put(entries, R_CONTACT_ANGLE, m, nlx * dnly - nly * dnlx)


@kernel(inline='always')
def _put_geometry_rows(entries, m, dq, xi, yi, ci, si, xj, yj, cj, sj, jp, dkx, dky, d):
    """Column m (direction dq) of the eccentricity and penetration rows of :func:`contact_jacobian`; returns de.
    delta = R_i - |d_k|, d_k = rho_k u_k - e = (dkx, dky), d = |d_k|: d delta = d_k.de / |d_k|."""
    _, (_, _, _, _, dex, dey) = _kinematics(xi, yi, ci, si, xj, yj, cj, sj, dq, jp)
    _put(entries, R_ECCENTRICITY_X, m, dex)
    _put(entries, R_ECCENTRICITY_Y, m, dey)
    _put(entries, R_PENETRATION, m, (dkx * dex + dky * dey) / d if d > 0.0 else 0.0)
    return dex, dey


@kernel(inline='always')
def _put(entries, r, m, value):
    """d out[r] / d input[m] = value into :func:`contact_jacobian`'s ``jacobian`` flattened."""
    entries[N_KINEMATIC_INPUTS * r + m] = value


@kernel(inline='always')
def _as_values(jp, memory):
    """``jp`` and ``memory`` as tuples, indexed as the arrays: values, which a compiled loop that stores into
    another array need not load again after every store (the arrays might share memory), so that what it
    computes from them it computes once."""
    return ((jp[0], jp[1], jp[2], jp[3], jp[4], jp[5], jp[6], jp[7], jp[8], jp[9], jp[10], jp[11], jp[12], jp[13],
             jp[14], jp[15], jp[16], jp[17], jp[18], jp[19], jp[20], jp[21], jp[22], jp[23], jp[24], jp[25], jp[26],
             jp[27], jp[28], jp[29], jp[30], jp[31]),
            (memory[0], memory[1], memory[2], memory[3], memory[4], memory[5], memory[6], memory[7], memory[8],
             memory[9]))


if (N_JOINT_PARAMETERS, N_MEMORY) != (32, 10):
    raise RuntimeError("_as_values spells out 32 joint parameters and 10 memory entries: update it with the layout")


@kernel
def _contact(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, jp, cos_phi, sin_phi, wear_depth, block_min,
             memory, out, with_jacobian):
    """The contact of :func:`evaluate_contact_scalars` into ``out``; returns what
    :func:`contact_jacobian` needs to differentiate it: (in contact, the elastic force and its
    Jacobian in e (with_jacobian, else 0), common point, bushing point, fallback normal (see
    :func:`_forces`), d_k x, d_k y, |d_k|)."""
    previous = out[R_CONTACT_INDEX]             # search hints only: the last evaluation's deepest point,
    if 0.0 <= previous < wear_depth.shape[0]:   # else the point nearest its contact angle
        hint = int(previous)
    else:
        hint = point_nearest_angle(out[R_CONTACT_ANGLE], wear_depth.shape[0])
    (_, _, _, _, ex, ey), _ = _kinematics(xi, yi, ci, si, xj, yj, cj, sj, NO_DIRECTION, jp)
    for r in range(out.shape[0]):
        out[r] = 0.0
    out[R_ECCENTRICITY_X] = ex
    out[R_ECCENTRICITY_Y] = ey
    out[R_CONTACT_INDEX] = -1.0
    pin_radius = jp[P_PIN_RADIUS]
    bushing_radius = jp[P_BUSHING_RADIUS]
    n = wear_depth.shape[0]
    foundation = int(jp[P_CONTACT_MODEL]) == CONTACT_FOUNDATION
    resultant = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1, math.inf)
    k, d2 = -1, math.inf
    if foundation and 0.0 <= previous < n and wear_depth[hint] > 0.0:
        # last in contact at a worn point: the resultant's window first, whose nearest point, if inside the
        # pin, is the deepest point (the search's answer, found without it)
        resultant = foundation_resultant(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                                         with_jacobian, np.int64(-1))   # not a literal: one compile
        if resultant[7] >= 0 and not math.sqrt(resultant[8]) > pin_radius:
            k, d2 = resultant[7], resultant[8]
    windowed = k >= 0
    if not windowed:
        k, d2 = find_deepest_point(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, hint)
    rho = bushing_radius + wear_depth[k]
    dkx = rho * cos_phi[k] - ex                 # d_k = rho_k u_k - e: pin centre to the deepest point
    dky = rho * sin_phi[k] - ey
    d = math.sqrt(d2)
    out[R_PENETRATION] = pin_radius - d                            # Eq. (6); negative: the gap
    bushing_point = (rho * cos_phi[k], rho * sin_phi[k])
    fallback = (dkx / d, dky / d) if d > 0.0 else (cos_phi[k], sin_phi[k])
    if d > pin_radius:
        out[R_CONTACT_ANGLE] = angle_near_point(ex, ey, k, cos_phi, sin_phi)
        return False, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0), True, bushing_point, fallback, dkx, dky, d
    if foundation:
        if not windowed:
            resultant = foundation_resultant(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                                             with_jacobian, k)
        fx, fy, j11, j12, j21, j22 = resultant[:6]
        scale = jp[P_FOUNDATION_MODULUS] * (TWO_PI / n)
        elastic = (scale * fx, scale * fy, scale * j11, scale * j12, scale * j21, scale * j22)
        common_point = True
    else:
        elastic = _deepest_elastic_force(ex, ey, k, d2, jp, cos_phi, sin_phi, wear_depth)
        common_point = False
    values, _ = _forces(xi, yi, ci, si, vxi, vyi, wi, xj, yj, cj, sj, vxj, vyj, wj, NO_DIRECTION, jp, memory,
                        elastic, common_point, bushing_point, fallback, (pin_radius - d, fallback[0], fallback[1]))
    fx, fy, t_i, t_j, f_n, f_t, v_t, rate, nlx, nly = values
    out[R_PIN_FX] = fx
    out[R_PIN_FY] = fy
    out[R_PIN_TORQUE] = t_i
    out[R_BUSHING_FX] = -fx                                        # Eq. (22)
    out[R_BUSHING_FY] = -fy
    out[R_BUSHING_TORQUE] = t_j
    out[R_NORMAL_FORCE] = f_n
    out[R_FRICTION_FORCE] = f_t
    out[R_CONTACT] = 1.0
    out[R_CONTACT_INDEX] = k
    out[R_TANGENTIAL_VELOCITY] = v_t
    out[R_PENETRATION_RATE] = rate
    out[R_CONTACT_ANGLE] = angle_near_point(nlx, nly, k, cos_phi, sin_phi)
    return True, elastic, common_point, bushing_point, fallback, dkx, dky, d


@kernel(inline='always')
def _unit_direction(m):
    """The m-th unit vector of the 12 kinematic inputs, as a tuple."""
    return (1.0 if m == 0 else 0.0, 1.0 if m == 1 else 0.0, 1.0 if m == 2 else 0.0, 1.0 if m == 3 else 0.0,
            1.0 if m == 4 else 0.0, 1.0 if m == 5 else 0.0, 1.0 if m == 6 else 0.0, 1.0 if m == 7 else 0.0,
            1.0 if m == 8 else 0.0, 1.0 if m == 9 else 0.0, 1.0 if m == 10 else 0.0, 1.0 if m == 11 else 0.0)


@kernel
def update_contact_memory(result, jp, memory):
    """Onset bookkeeping after an accepted step (docs/reference/model.md §3.5).

    A contact that is new at the accepted state stores its approach velocity,
    floored at ``impact_velocity_floor``, as delta_dot^- of Eq. (15); leaving
    contact clears it.  Returns True if the memory changed.
    """
    if result[R_CONTACT] > 0.5:
        if memory[M_ACTIVE] < 0.5:
            memory[M_ACTIVE] = 1.0
            memory[M_IMPACT_VELOCITY] = max(result[R_PENETRATION_RATE], jp[P_VELOCITY_FLOOR])
            return True
        return False
    if memory[M_ACTIVE] > 0.5:
        memory[M_ACTIVE] = 0.0
        memory[M_IMPACT_VELOCITY] = 0.0
        return True
    return False
