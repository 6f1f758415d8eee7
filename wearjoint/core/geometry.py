"""Geometry of the bushing and the contact search (paper Secs. 2-3, Eqs. 2-8).

Pure numba functions on arrays.  The search works in the bushing frame: the pin centre
relative to the bushing centre is the eccentricity e, and bushing point z sits at
rho_z (cos phi_z, sin phi_z), rho_z = R_j + h_z (Eqs. 3, 35).  Points are grouped in
blocks of BLOCK_SIZE whose smallest wear depth bounds the distance of all their points
from the pin centre, so a search or a sum skips the blocks that cannot matter.
"""
import math

import numpy as np

from .jit import kernel
from .layout import BLOCK_SIZE

TWO_PI = 2.0 * math.pi
OUTWARD_SCAN_POINTS = 16  # points scanned each side of the direction of e before the block search
DIRECTION_WALK_STEPS = 8  # points walked from the last deepest point towards e's direction


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


@kernel
def max_depth(wear_depth):
    """The largest wear depth of the profile [m] (0 unworn)."""
    deepest = 0.0
    for z in range(wear_depth.shape[0]):
        deepest = max(deepest, wear_depth[z])
    return deepest


@kernel(inline='always')
def distance_sq(z, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """|d_z|^2 [m^2]: squared distance from the pin centre (eccentricity e) to bushing point z
    at radius R_j + h_z (Eqs. 3-5).  Hot loops pass an unsigned z: numba then skips its
    negative-index wrap (a select per load, which turns a vectorised loop into gathers)."""
    rho = bushing_radius + wear_depth[z]
    dx = rho * cos_phi[z] - ex
    dy = rho * sin_phi[z] - ey
    return dx * dx + dy * dy


@kernel(inline='always')
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
                 np.inf, np.int64(-1))[::-1]


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


@kernel(inline='always')
def direction_point(ex, ey, n):
    """The bushing point (of N_d = n) nearest the direction of e = (ex, ey) in the bushing frame: point k at
    phi_k = (k + 1) 2 pi / N_d (Eq. 3); point N_d - 1 (phi = 0) for e = 0."""
    return wrap_index(int(round(math.atan2(ey, ex) * n / TWO_PI)) - 1, n)


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
    return e, ux, uy, direction_point(ex, ey, n)


@kernel(inline='always')
def _dot(k, vx, vy, cos_phi, sin_phi):
    """v . u_k: the vector (vx, vy) on point k's direction."""
    return cos_phi[k] * vx + sin_phi[k] * vy


@kernel(inline='always')
def _direction_point_from(ex, ey, cos_phi, sin_phi, start):
    """:func:`_direction_point` by walking from point ``start`` (e.g. the last deepest point) to the
    point whose direction has the largest dot product with e, which is the point nearest e's direction
    (equally spaced points: a local maximum is the maximum), without the arctangent.  Ties: either
    of the two points that bracket e's direction, which is all the search needs.  Falls back to
    :func:`_direction_point` after DIRECTION_WALK_STEPS points or without a start."""
    n = cos_phi.shape[0]
    if not 0 <= start < n or (ex == 0.0 and ey == 0.0):
        return _direction_point(ex, ey, n)
    e = math.sqrt(ex * ex + ey * ey)            # |e| and u_e: off the walk's path (it compares e.u_k)
    k = start
    best = _dot(np.uint64(k), ex, ey, cos_phi, sin_phi)
    step = 1 if _dot(np.uint64(wrap_index(k + 1, n)), ex, ey, cos_phi, sin_phi) > best else -1
    for _ in range(DIRECTION_WALK_STEPS):
        nxt = wrap_index(k + step, n)
        c = _dot(np.uint64(nxt), ex, ey, cos_phi, sin_phi)
        if c <= best:
            return e, ex / e, ey / e, k
        k = nxt
        best = c
    return _direction_point(ex, ey, n)


@kernel(inline='always')
def point_nearest_angle(angle, n):
    """The bushing point (of n) nearest the bushing-frame angle ``angle`` in [0, 2 pi) [rad]; -1 for any
    other value (point k at (k + 1) 2 pi / n, Eq. 3)."""
    if not 0.0 <= angle < TWO_PI:
        return -1
    return wrap_index(int(angle * (n / TWO_PI) + 0.5) - 1, n)


@kernel(inline='always')
def angle_near_point(vx, vy, k, cos_phi, sin_phi):
    """Bushing-frame angle of the vector (vx, vy) in [0, 2 pi) [rad], atan2's to rounding: phi_k plus
    the angle from point k's direction, by the arctangent's series where that angle is small (|tan|
    <= 1/16: the series to x^13 leaves < 1e-19 rad), else atan2 (a library call costs more)."""
    c = cos_phi[k] * vx + sin_phi[k] * vy
    s = cos_phi[k] * vy - sin_phi[k] * vx
    if c > 0.0 and abs(s) <= 0.0625 * c:
        x = s / c
        x2 = x * x
        atan = x * (1.0 + x2 * (-1.0 / 3.0 + x2 * (1.0 / 5.0 + x2 * (-1.0 / 7.0 + x2 * (
            1.0 / 9.0 + x2 * (-1.0 / 11.0 + x2 * (1.0 / 13.0)))))))
        angle = (k + 1) * TWO_PI / cos_phi.shape[0] + atan       # phi_k of bushing_points, Eq. (3)
        if angle >= TWO_PI:
            return angle - TWO_PI
        return angle + TWO_PI if angle < 0.0 else angle
    angle = math.atan2(vy, vx)
    return angle + TWO_PI if angle < 0.0 else angle


@kernel
def _is_direction_block(b, b0, nb):
    """True for the block holding the direction of e and its two neighbours."""
    off = wrap_index(b - b0, nb)
    return off <= 1 or off == nb - 1


@kernel(inline='always')
def arc_cosine_bound(x):
    """acos(x) or a little more [rad], x < 1: near 1 (t = 1 - x <= 0.1) sqrt(2t) (1 + t/6), above
    acos(1 - t) = sqrt(2t) (1 + t/12 + 3t^2/160 + ...) by under 1 % of it (no libm call: the contact's
    small overlaps); else acos(x) by libm's asin."""
    t = 1.0 - x
    if t <= 0.1:
        return math.sqrt(2.0 * t) * (1.0 + t / 6.0)
    return 2.0 * math.asin(math.sqrt(0.5 * min(t, 2.0)))


@kernel(inline='always')
def reach_cosine(e, bushing_radius, limit_sq):
    """cos Delta* [-]: beyond the angle Delta* from e's direction every bushing point (rho >= R_j > |e|) has
    |d_z|^2 = rho^2 + |e|^2 - 2 rho |e| cos Delta > limit_sq [m^2]."""
    return (bushing_radius * bushing_radius + e * e - limit_sq) / (2.0 * bushing_radius * e)


@kernel(inline='always')
def reach_points(cos_reach, n):
    """(Delta* or a little more [rad], the half-width in points of a window about the point nearest e's
    direction that holds every point within Delta*: + 1 for the centre's rounding, + 2 for the cells reaching
    in) of cos_reach = :func:`reach_cosine` < 1."""
    reach = arc_cosine_bound(cos_reach)
    return reach, int(reach / (2.0 * math.pi / n)) + 3


@kernel(inline='always')
def candidate_blocks(e, bushing_radius, limit_sq, k0, n, nb):
    """(first block, count) of the blocks, cyclically from the first, that may hold a point with
    |d_z|^2 <= limit_sq [m^2]: those reaching within the angle Delta* of point k0 (a point nearest e's
    direction, to one spacing), where the angular bound with rho = R_j (every rho >= R_j), R_j^2 + |e|^2 -
    2 R_j |e| cos Delta, reaches limit_sq, widened by two spacings; every block where that is more than a
    third of the circle or |e| is not in (0, R_j)."""
    if not 0.0 < e < bushing_radius:
        return 0, nb
    c = reach_cosine(e, bushing_radius, limit_sq)
    if not c > 0.5:
        return 0, nb
    half = 2 if c >= 1.0 else reach_points(c, n)[1]
    if 2 * half + 1 >= n:
        return 0, nb
    first = wrap_index(k0 - half, n) // BLOCK_SIZE
    last = wrap_index(k0 + half, n) // BLOCK_SIZE
    return first, (last - first if last >= first else last + nb - first) + 1


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
       tie the best, among those :func:`candidate_blocks` leaves (with the
       best after the three blocks: a point outside cannot beat or tie it).
    Ties go to the lower index, as in the full scan.
    """
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    if nb <= 3:
        return find_deepest_point_full(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    e, ux, uy, k0 = _direction_point_from(ex, ey, cos_phi, sin_phi, hint)
    rho_min = bushing_radius                    # every wear depth is >= 0
    # np.int64: with a literal -1 numba would compile _scan_block for it too, while typing best_k
    best_d2, best_k = _scan(ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth, k0, k0 + 1, np.inf,
                            np.int64(-1))
    if 0 <= hint < n and hint != k0:
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
    first, count = candidate_blocks(e, bushing_radius, _tie_margin(best_d2), k0, n, nb)
    for j in range(count):
        b = wrap_index(first + j, nb)
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


@kernel
def refresh_blocks(wear_depth, block_min, first, last):
    """Recompute block minima of the blocks holding points first..last (wrapping)."""
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    span = last - first
    if span + BLOCK_SIZE >= n:                  # the ends may share a block after wrapping
        block_minimum_depth(wear_depth, block_min)
        return
    b = (first % n) // BLOCK_SIZE
    b_last = (last % n) // BLOCK_SIZE
    while True:
        block_min[b] = block_minimum(wear_depth, b)
        if b == b_last:
            return
        b = wrap_index(b + 1, nb)
