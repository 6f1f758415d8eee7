"""Contact kernels of the clearance joint (paper Secs. 2-4, Eqs. 1-23).

Pure numba functions on arrays.  Bodies: i carries the pin, j the bushing.
The search works in the bushing frame: the pin centre relative to the bushing
centre is the eccentricity e, and bushing point z sits at
rho_z (cos phi_z, sin phi_z), rho_z = R_j + h_z (Eqs. 3, 35).

Conventions (docs/model.md §3): delta = R_i - |d| (Eq. 6, positive inside
the pin); n points from the pin centre to the deepest bushing point (Eq. 8);
the normal force on the pin is -F_N n (it pushes the pin back towards the
bushing centre) and the friction on the pin opposes the pin's sliding velocity
relative to the bushing; torques are planar cross products l_x F_y - l_y F_x.
"""
import math

import numpy as np

from .jit import kernel
from .layout import (
    BLOCK_SIZE, M_ACTIVE, M_IMPACT_VELOCITY, P_BUSHING_OFFSET_X, P_BUSHING_OFFSET_Y,
    P_BUSHING_RADIUS, P_CONTACT_POINT, P_EXPONENT, P_FRICTION, P_PIN_OFFSET_X, P_PIN_OFFSET_Y, P_PIN_RADIUS,
    P_RESTITUTION, P_STIFFNESS, P_V0, P_V1, P_VELOCITY_FLOOR, R_BUSHING_FX, R_BUSHING_FY,
    R_BUSHING_TORQUE, R_CONTACT, R_CONTACT_ANGLE, R_CONTACT_INDEX, R_ECCENTRICITY_X,
    R_ECCENTRICITY_Y, R_FRICTION_FORCE, R_NORMAL_FORCE, R_PENETRATION, R_PENETRATION_RATE,
    R_PIN_FX, R_PIN_FY, R_PIN_TORQUE, R_TANGENTIAL_VELOCITY,
)

TWO_PI = 2.0 * math.pi
OUTWARD_SCAN_POINTS = 16  # points scanned each side of the direction of e before the block search


@kernel
def bushing_points(phi, cos_phi, sin_phi):
    """Body-frame angles phi_z = z 2 pi / N_d, z = 1..N_d (Eq. 3) [rad], index k = z - 1, and
    their cosines and sines, for N_d = len(phi)."""
    n = phi.shape[0]
    for k in range(n):
        phi[k] = (k + 1) * TWO_PI / n
        cos_phi[k] = math.cos(phi[k])
        sin_phi[k] = math.sin(phi[k])


def bushing_point_angles(n_points: int) -> np.ndarray:
    """phi_z of :func:`bushing_points` [rad] as a new array."""
    phi, cos_phi, sin_phi = np.empty(n_points), np.empty(n_points), np.empty(n_points)
    bushing_points(phi, cos_phi, sin_phi)
    return phi


@kernel(inline='always')
def wrap_index(k, n):
    """k mod n for k in [-n, 2n) without an integer division (a hot-path modulo costs
    tens of cycles)."""
    if k < 0:
        return k + n
    if k >= n:
        return k - n
    return k


@kernel
def block_minimum(wear_depth, b):
    """Smallest wear depth of block b (points b*BLOCK_SIZE .. b*BLOCK_SIZE + BLOCK_SIZE - 1): four
    interleaved minima, four points a round (a minimum does not depend on the order), so each
    comparison waits for the one four points back instead of the one before."""
    lo = np.uint64(b * BLOCK_SIZE)
    hi = np.uint64(min(b * BLOCK_SIZE + BLOCK_SIZE, wear_depth.shape[0]))
    m0 = m1 = m2 = m3 = wear_depth[lo]
    k = lo + np.uint64(1)
    while k + np.uint64(4) <= hi:
        m0 = min(m0, wear_depth[k])
        m1 = min(m1, wear_depth[k + np.uint64(1)])
        m2 = min(m2, wear_depth[k + np.uint64(2)])
        m3 = min(m3, wear_depth[k + np.uint64(3)])
        k += np.uint64(4)
    while k < hi:
        m0 = min(m0, wear_depth[k])
        k += np.uint64(1)
    return min(min(m0, m1), min(m2, m3))


@kernel
def block_minimum_depth(wear_depth, block_min):
    """Fill ``block_min[b]`` with the smallest wear depth of every block b."""
    for b in range(block_min.shape[0]):
        block_min[b] = block_minimum(wear_depth, b)


@kernel(inline='always')
def distance_sq(z, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """|d_z|^2 [m^2]: squared distance from the pin centre (eccentricity e) to bushing point z
    at radius R_j + h_z (Eqs. 3-5).  Hot loops pass an unsigned z: numba then skips its
    negative-index wrap (a select per load, which turns a vectorised loop into gathers)."""
    rho = bushing_radius + wear_depth[z]
    dx = rho * cos_phi[z] - ex
    dy = rho * sin_phi[z] - ey
    return dx * dx + dy * dy


@kernel
def _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, lo, hi, best_d2, best_k):
    """Smallest (|d_z|^2, z) over points lo..hi-1, ties to the lower index (Eqs. 4-5)."""
    for k in range(lo, hi):
        d2 = distance_sq(np.uint64(k), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
        if d2 <= best_d2:                       # rarely true: one well-predicted branch per point
            if d2 < best_d2 or k < best_k:
                best_d2 = d2
                best_k = k
    return best_d2, best_k


@kernel
def _count_candidates(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, lo, hi, best_d2):
    """How many of points lo..hi-1 have |d_z|^2 <= best_d2.  Branch-free, so the compiler
    vectorises it (a min/argmin loop it does not: ~9x faster per point than :func:`_scan`);
    the same :func:`distance_sq` as :func:`_scan`, so the comparison is exact."""
    count = 0
    for k in range(np.uint64(lo), np.uint64(hi)):
        count += distance_sq(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth) <= best_d2
    return count


@kernel
def _scan_block(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, lo, hi, best_d2, best_k):
    """:func:`_scan` of points lo..hi-1, skipped when none of them can replace or tie the best."""
    if _count_candidates(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, lo, hi, best_d2) == 0:
        return best_d2, best_k
    return _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, lo, hi, best_d2, best_k)


@kernel
def find_deepest_point_full(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """Full scan of all bushing points: (index, |d|^2) of the point nearest the pin centre."""
    return _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, 0, wear_depth.shape[0],
                 np.inf, -1)[::-1]


@kernel
def _angular_lower_bound_sq(e, c, rho_min):
    """Lower bound of |d|^2 = rho^2 + e^2 - 2 rho e cos(Delta') over rho >= rho_min and
    Delta' in [Delta, pi], with c = cos(Delta): reached at Delta' = Delta,
    rho = max(rho_min, e c)."""
    ec = e * c
    r = max(rho_min, ec) - ec
    return r * r + e * e * max(0.0, 1.0 - c * c)


@kernel
def _block_lower_bound_sq(e, ux, uy, bushing_radius, cos_phi, sin_phi, block_min, b, n):
    """Lower bound of |d_z|^2 over block b (its span must not contain the direction of e):
    cos Delta is the larger dot product of u_e with the block's end points."""
    lo = np.uint64(b * BLOCK_SIZE)              # unsigned indices: no negative-index wrap
    hi = np.uint64(min(b * BLOCK_SIZE + BLOCK_SIZE, n) - 1)
    c = max(cos_phi[lo] * ux + sin_phi[lo] * uy, cos_phi[hi] * ux + sin_phi[hi] * uy)
    return _angular_lower_bound_sq(e, c, bushing_radius + block_min[np.uint64(b)])


@kernel
def _direction_point(ex, ey, n):
    """|e|, the unit vector of e ((1, 0) for e = 0) and the point nearest its direction."""
    e = math.sqrt(ex * ex + ey * ey)
    if e > 0.0:
        ux = ex / e
        uy = ey / e
    else:
        ux = 1.0
        uy = 0.0
    return e, ux, uy, wrap_index(int(round(math.atan2(uy, ux) / (TWO_PI / n))) - 1, n)


@kernel
def _is_direction_block(b, b0, nb):
    """True for the block holding the direction of e and its two neighbours."""
    off = wrap_index(b - b0, nb)
    return off <= 1 or off == nb - 1


@kernel
def _tie_margin(best_d2):
    """Candidates whose bound is within rounding of the best are still scanned."""
    return best_d2 * (1.0 + 1e-12) + 1e-30


@kernel(inline='always')
def _outward_cos(k0, o, n, ux, uy, cos_phi, sin_phi):
    """cos of the smaller angle between the direction (ux, uy) and points k0 +- o."""
    kp = wrap_index(k0 + o, n)
    km = wrap_index(k0 - o, n)
    return max(cos_phi[kp] * ux + sin_phi[kp] * uy, cos_phi[km] * ux + sin_phi[km] * uy)


@kernel(inline='always')
def find_deepest_point(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, hint):
    """Exact search with pruning, identical to :func:`find_deepest_point_full`.

    ``hint``: a point to try first, e.g. the deepest point of the previous
    evaluation (-1 or out of range: none).  A good hint makes the best distance
    tight early, so fewer blocks need scanning; it never changes the result.

    1. Scan outward from the point nearest the direction of e; after offset o,
       every unscanned point is at least as far in angle as k0 +- (o + 1), so
       with radius >= R_j (wear depths are >= 0) it cannot be nearer than
       :func:`_angular_lower_bound_sq`: stop once that bound exceeds the best.
       On a circular or mildly worn bushing this decides after a few points.
    2. Otherwise (deep local wear), scan the three blocks around the direction
       of e and every other block whose own lower bound could still beat or
       tie the best.
    Ties go to the lower index, as in the full scan.
    """
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    if nb <= 3:
        return find_deepest_point_full(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    e, ux, uy, k0 = _direction_point(ex, ey, n)
    rho_min = bushing_radius                    # every wear depth is >= 0
    best_d2, best_k = _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, k0, k0 + 1, np.inf, -1)
    if 0 <= hint < n:
        best_d2, best_k = _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, hint, hint + 1, best_d2,
                                best_k)
    # the outward scan can only decide if the bound at its last offset beats the point at k0
    # (on a deep, conforming lobe it cannot: go straight to the blocks)
    if _angular_lower_bound_sq(e, _outward_cos(k0, OUTWARD_SCAN_POINTS, n, ux, uy, cos_phi, sin_phi),
                               rho_min) > _tie_margin(best_d2):
        for o in range(1, OUTWARD_SCAN_POINTS + 1):
            if _angular_lower_bound_sq(e, _outward_cos(k0, o, n, ux, uy, cos_phi, sin_phi),
                                       rho_min) > _tie_margin(best_d2):
                return best_k, best_d2
            kp = wrap_index(k0 + o, n)
            km = wrap_index(k0 - o, n)
            best_d2, best_k = _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, kp, kp + 1, best_d2,
                                    best_k)
            best_d2, best_k = _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, km, km + 1, best_d2,
                                    best_k)
    b0 = k0 // BLOCK_SIZE
    for db in (-1, 0, 1):
        lo = wrap_index(b0 + db, nb) * BLOCK_SIZE
        best_d2, best_k = _scan_block(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth,
                                      lo, min(lo + BLOCK_SIZE, n), best_d2, best_k)
    for b in range(nb):
        if _is_direction_block(b, b0, nb):
            continue
        if _block_lower_bound_sq(e, ux, uy, bushing_radius, cos_phi, sin_phi, block_min, b, n) <= _tie_margin(best_d2):
            lo = b * BLOCK_SIZE
            best_d2, best_k = _scan_block(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth,
                                          lo, min(lo + BLOCK_SIZE, n), best_d2, best_k)
    return best_k, best_d2


@kernel
def penetrating_points(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                       block_min, mask):
    """Mark in ``mask`` every bushing point with |d_z| <= R_i (Eq. 5); return their count.

    Blocks whose lower bound on |d|^2 exceeds R_i^2 hold no such point and are skipped.
    """
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    e, ux, uy, k0 = _direction_point(ex, ey, n)
    b0 = k0 // BLOCK_SIZE
    r2 = pin_radius * pin_radius
    count = 0
    mask[:] = False
    for b in range(nb):
        if nb > 3 and not _is_direction_block(b, b0, nb) and _block_lower_bound_sq(
                e, ux, uy, bushing_radius, cos_phi, sin_phi, block_min, b, n) > _tie_margin(r2):
            continue
        lo = b * BLOCK_SIZE
        for k in range(lo, min(lo + BLOCK_SIZE, n)):
            if distance_sq(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth) <= r2:
                mask[k] = True
                count += 1
    return count


@kernel(inline='always')
def _fit_terms(psi, scale, c0, c1, c2, c3, ex_a, ey_a, bushing_radius):
    """The fitted profile of :func:`fitted_contact` at psi [rad] past its segment's first point a, with
    e = (ex_a, ey_a) in point a's frame: (rho [m], cos psi, sin psi, e.u, e.w [m], g, dg/dpsi), u and w
    the radial and tangential unit vectors there and g = (rho u - e).d(rho u)/dpsi [m^2]."""
    t = psi * scale
    rho = bushing_radius + (c0 + t * (c1 + t * (c2 + t * c3)))
    drho = (c1 + t * (2.0 * c2 + 3.0 * t * c3)) * scale
    d2rho = (2.0 * c2 + 6.0 * t * c3) * scale * scale
    cs = math.cos(psi)
    sn = math.sin(psi)
    eu = ex_a * cs + ey_a * sn
    ew = ey_a * cs - ex_a * sn
    g = drho * (rho - eu) - rho * ew
    dg = d2rho * (rho - eu) + drho * drho - 2.0 * drho * ew + rho * eu
    return rho, cs, sn, eu, ew, g, dg


FIT_ITERATIONS = 64           # safeguarded Newton on the fitted profile: 2-4 steps, bisection at worst
FIT_TOLERANCE_RAD = 1e-14     # a Newton step this small ends it (the point it would move from is kept)


@kernel
def fitted_contact(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """Point of the fitted bushing profile nearest the pin centre (eccentricity e [m]), beside the
    deepest bushing point k (docs/model.md 3.10; replaces Eqs. 7-8 by their continuous form).

    Between points a and a + 1 the profile is rho = R_j + h(t), t = (phi - phi_a)/dphi, with h the
    cubic that blends the parabola through points a - 1, a, a + 1 and the one through a, a + 1, a + 2
    linearly in t (Catmull-Rom in polar form): through every point, with a continuous slope, exact
    for a circle and for a quadratic h.  The segment is the one on the side of k towards which |d|
    decreases; there Newton steps on g = (rho u - e).d(rho u)/dphi = 0, kept inside the segment
    (else bisection), find the nearest point.  Returns (a, psi [rad] past phi_a, rho [m], u_x, u_y,
    d_r, d_t): u the radial unit vector (bushing frame) and d = rho u - e split into its part along u
    and along u rotated by +90 deg [m]."""
    n = wear_depth.shape[0]
    scale = n / TWO_PI
    dphi = TWO_PI / n
    rho_k = bushing_radius + wear_depth[k]
    slope_k = 0.5 * (wear_depth[wrap_index(k + 1, n)] - wear_depth[wrap_index(k - 1, n)]) * scale
    a = k
    psi = 0.0
    if slope_k * (rho_k - (ex * cos_phi[k] + ey * sin_phi[k])) > rho_k * (ey * cos_phi[k] - ex * sin_phi[k]):
        a = wrap_index(k - 1, n)                # g > 0 at k: |d| decreases towards k - 1
        psi = dphi
    h0 = wear_depth[wrap_index(a - 1, n)]
    h1 = wear_depth[a]
    h2 = wear_depth[wrap_index(a + 1, n)]
    h3 = wear_depth[wrap_index(a + 2, n)]
    m1 = 0.5 * (h2 - h0)
    m2 = 0.5 * (h3 - h1)
    c2 = 3.0 * (h2 - h1) - 2.0 * m1 - m2
    c3 = 2.0 * (h1 - h2) + m1 + m2
    ex_a = ex * cos_phi[a] + ey * sin_phi[a]
    ey_a = ey * cos_phi[a] - ex * sin_phi[a]
    if ex_a > 0.0:                              # start near the direction of e (there on a circle)
        psi = min(dphi, max(0.0, ey_a / ex_a))
    lo = 0.0
    hi = dphi
    for _ in range(FIT_ITERATIONS):
        rho, cs, sn, eu, ew, g, dg = _fit_terms(psi, scale, h1, m1, c2, c3, ex_a, ey_a, bushing_radius)
        if g < 0.0:
            lo = psi
        else:
            hi = psi
        new = 0.5 * (lo + hi)
        if dg > 0.0 and lo <= psi - g / dg <= hi:
            new = psi - g / dg
        if abs(new - psi) <= FIT_TOLERANCE_RAD:     # the point at psi is as near as round-off tells
            break
        psi = new
    return a, psi, rho, cos_phi[a] * cs - sin_phi[a] * sn, sin_phi[a] * cs + cos_phi[a] * sn, rho - eu, -ew


@kernel
def lankarani_nikravesh(penetration, penetration_rate, impact_velocity, stiffness, exponent,
                        restitution):
    """Normal force F_N = K delta^n (1 + 3(1 - e_r^2)/4 delta_dot/delta_dot^-) >= 0, Eq. (15) [N]."""
    hysteresis = 1.0 + 0.75 * (1.0 - restitution * restitution) * penetration_rate / impact_velocity
    # delta^1.5 (Hertz, the default) as delta sqrt(delta): several times cheaper than pow
    power = penetration * math.sqrt(penetration) if exponent == 1.5 else penetration ** exponent
    return max(0.0, stiffness * power * hysteresis)


@kernel
def ambrosio_friction_factor(sliding_speed, v0, v1):
    """Dynamic correction coefficient c_d of Eq. (19) on |v_T|; 0 below v0, 1 above v1."""
    if sliding_speed <= v0:
        return 0.0
    if sliding_speed >= v1:
        return 1.0
    return (sliding_speed - v0) / (v1 - v0)


@kernel
def _cross(lx, ly, fx, fy):
    return lx * fy - ly * fx


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
    previous = out[R_CONTACT_INDEX]             # the last evaluation's deepest point: a search hint only
    hint = int(previous) if 0.0 <= previous < wear_depth.shape[0] else -1
    # pin centre, Eq. (1), and bushing centre in global coordinates
    ax = ci * jp[P_PIN_OFFSET_X] - si * jp[P_PIN_OFFSET_Y]
    ay = si * jp[P_PIN_OFFSET_X] + ci * jp[P_PIN_OFFSET_Y]
    pin_x = xi + ax
    pin_y = yi + ay
    bx = cj * jp[P_BUSHING_OFFSET_X] - sj * jp[P_BUSHING_OFFSET_Y]
    by = sj * jp[P_BUSHING_OFFSET_X] + cj * jp[P_BUSHING_OFFSET_Y]
    # eccentricity in the bushing frame
    gx = pin_x - (xj + bx)
    gy = pin_y - (yj + by)
    ex = cj * gx + sj * gy
    ey = -sj * gx + cj * gy
    out[R_ECCENTRICITY_X] = ex
    out[R_ECCENTRICITY_Y] = ey
    for r in range(R_ECCENTRICITY_X):
        out[r] = 0.0
    out[R_CONTACT_INDEX] = -1.0
    out[R_TANGENTIAL_VELOCITY] = 0.0
    out[R_PENETRATION_RATE] = 0.0

    pin_radius = jp[P_PIN_RADIUS]
    bushing_radius = jp[P_BUSHING_RADIUS]
    k, d2 = find_deepest_point(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, hint)
    n = wear_depth.shape[0]
    if int(jp[P_CONTACT_POINT]) == 0:          # nearest point of the fitted profile (docs/model.md 3.10)
        a, psi, rho, ux, uy, d_r, d_t = fitted_contact(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
        d = math.sqrt(d_r * d_r + d_t * d_t)
        dlx = d_r * ux - d_t * uy
        dly = d_r * uy + d_t * ux
        contact_angle = (0.0 if a == n - 1 else (a + 1) * TWO_PI / n) + psi
        if contact_angle >= TWO_PI:
            contact_angle -= TWO_PI
    else:                                       # the deepest bushing point (Eqs. 7-8)
        d = math.sqrt(d2)
        rho = bushing_radius + wear_depth[k]
        ux = cos_phi[k]
        uy = sin_phi[k]
        dlx = rho * ux - ex
        dly = rho * uy - ey
        contact_angle = 0.0 if k == n - 1 else (k + 1) * TWO_PI / n          # phi_z in [0, 2 pi)
    out[R_PENETRATION] = pin_radius - d                            # Eq. (6); negative: the gap
    if d > pin_radius:
        angle = math.atan2(ey, ex)
        out[R_CONTACT_ANGLE] = angle + TWO_PI if angle < 0.0 else angle
        return
    # normal n (Eq. 8) in the bushing frame, then globally
    if d > 0.0:
        nlx = dlx / d
        nly = dly / d
    else:
        nlx = ux
        nly = uy
    nx = cj * nlx - sj * nly
    ny = sj * nlx + cj * nly
    tx = -ny
    ty = nx
    penetration = pin_radius - d
    # contact points: pin surface (Eq. 9) and the bushing point (Eqs. 10, 36)
    qix = pin_x + pin_radius * nx
    qiy = pin_y + pin_radius * ny
    sx = jp[P_BUSHING_OFFSET_X] + rho * ux
    sy = jp[P_BUSHING_OFFSET_Y] + rho * uy
    ljx = cj * sx - sj * sy
    ljy = sj * sx + cj * sy
    lix = qix - xi
    liy = qiy - yi
    # material velocities of the two contact points (Eqs. 11-12, 37)
    vix = vxi - wi * liy
    viy = vyi + wi * lix
    vjx = vxj - wj * ljy
    vjy = vyj + wj * ljx
    rvx = vix - vjx
    rvy = viy - vjy
    penetration_rate = rvx * nx + rvy * ny                         # Eq. (13)
    v_t = rvx * tx + rvy * ty                                      # Eq. (14)
    if memory[M_ACTIVE] > 0.5:
        impact_velocity = memory[M_IMPACT_VELOCITY]
    else:
        impact_velocity = max(penetration_rate, jp[P_VELOCITY_FLOOR])
    f_n = lankarani_nikravesh(penetration, penetration_rate, impact_velocity,
                              jp[P_STIFFNESS], jp[P_EXPONENT], jp[P_RESTITUTION])
    c_d = ambrosio_friction_factor(abs(v_t), jp[P_V0], jp[P_V1])
    f_t = -jp[P_FRICTION] * c_d * f_n * (1.0 if v_t > 0.0 else -1.0)   # Eq. (18), along t on the pin
    fx = -f_n * nx + f_t * tx                                      # Eq. (20), on the pin
    fy = -f_n * ny + f_t * ty
    out[R_PIN_FX] = fx
    out[R_PIN_FY] = fy
    out[R_PIN_TORQUE] = _cross(lix, liy, fx, fy)                   # Eq. (21)
    out[R_BUSHING_FX] = -fx                                        # Eq. (22)
    out[R_BUSHING_FY] = -fy
    out[R_BUSHING_TORQUE] = _cross(ljx, ljy, -fx, -fy)             # Eq. (23)
    out[R_NORMAL_FORCE] = f_n
    out[R_FRICTION_FORCE] = f_t
    out[R_CONTACT] = 1.0
    out[R_CONTACT_INDEX] = k
    out[R_TANGENTIAL_VELOCITY] = v_t
    out[R_PENETRATION_RATE] = penetration_rate
    out[R_CONTACT_ANGLE] = contact_angle


@kernel
def update_contact_memory(result, jp, memory):
    """Onset bookkeeping after an accepted step (docs/model.md §3.5).

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
