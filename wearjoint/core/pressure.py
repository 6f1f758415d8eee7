"""The elastic-foundation pressure on the bushing: one field for the contact force and the wear
(docs/reference/model.md §3.7, §3.10).

Bushing point z (angle phi_z, radius rho_z = R_j + h_z, Eq. 35) overlaps the pin by
o_z = (R_i^2 - |d_z|^2) / (2 R_i), d_z = rho_z u_z - e (Eq. 4): R_i - |d_z| to within a factor
1 - o/(2 R_i), positive inside the pin, and affine in e but for the common -|e|^2/(2 R_i), with
do_z/de = d_z / R_i.  The overlap is taken linear in phi between neighbouring points; a point's
weight w_z is the mean of its positive part over the point's arc cell (:func:`cell_overlap`), so
sum_z w_z rho_z dphi is the integral of o+ rho dphi for that interpolant, whatever N_d.

A linear (Winkler) foundation of modulus k_f [N/m^3] puts the pressure p = k_f o+ on the bushing,
along each point's d_z, through the pin centre.  Its resultant on the pin, in the bushing frame,

    F = -kappa sum_z w_z rho_z d_z,    kappa = k_f L dphi / R_i,

has the magnitude k_f L int o+ rho dphi (|d_z| ~ R_i): on the unworn bushing, where
R_i - |d| = delta - (R_j |e| / (R_j - |e|)) (phi - phi_e)^2 / 2 near the contact, to leading order
k_f L R_j (4 sqrt 2 / 3) delta^1.5 sqrt(R_i / (R_j |e|)), the paper's Hertz exponent.  k_f is set so
that this is K delta^1.5 as delta -> 0 (|e| -> c; :func:`foundation_modulus_factor`).  Any number of arcs in
contact, on any worn profile, sums the same way; F is continuous and has continuous first
derivatives in e (the positive part of a linear function has a continuous mean).
"""
import math

import numpy as np

from .geometry import direction_point, reach_cosine, reach_points, wrap_index
from .jit import kernel


@kernel(inline='always')
def overlap(z, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth):
    """Local overlap of bushing point z with the pin [m], (R_i^2 - |d_z|^2) / (2 R_i)."""
    rho = bushing_radius + wear_depth[z]
    dx = rho * cos_phi[z] - ex
    dy = rho * sin_phi[z] - ey
    return (pin_radius * pin_radius - (dx * dx + dy * dy)) / (2.0 * pin_radius)


@kernel(inline='always')
def _positive_mean(u, v):
    """Mean over an interval of max(0, f) for f linear from u to v."""
    if u >= 0.0 and v >= 0.0:
        return 0.5 * (u + v)
    if u <= 0.0 and v <= 0.0:
        return 0.0
    p = max(u, v)
    return 0.5 * p * p / (p - min(u, v))


@kernel(inline='always')
def _positive_mean_gradient(u, v):
    """(d/du, d/dv) of :func:`_positive_mean`: continuous where u or v crosses 0."""
    if u >= 0.0 and v >= 0.0:
        return 0.5, 0.5
    if u <= 0.0 and v <= 0.0:
        return 0.0, 0.0
    if u > 0.0:                                  # u > 0 > v: u^2 / (2 (u - v))
        s = 0.5 / ((u - v) * (u - v))
        return u * (u - 2.0 * v) * s, u * u * s
    s = 0.5 / ((v - u) * (v - u))                # v > 0 > u
    return v * v * s, v * (v - 2.0 * u) * s


@kernel(inline='always')
def cell_overlap(before, at, after):
    """Mean positive overlap over a point's arc cell [phi_z - dphi/2, phi_z + dphi/2], the overlap
    linear in phi between the point (``at``) and its neighbours (``before``, ``after``).  On the arc
    in contact (all three >= 0) it is (before + 6 at + after) / 8, outside it (all <= 0) 0."""
    if min(before, min(at, after)) >= 0.0:
        return 0.125 * (before + 6.0 * at + after)
    if max(before, max(at, after)) <= 0.0:
        return 0.0
    return 0.5 * (_positive_mean(0.5 * (before + at), at) + _positive_mean(at, 0.5 * (at + after)))


@kernel(inline='always')
def cell_overlap_gradient(before, at, after):
    """(d/d before, d/d at, d/d after) of :func:`cell_overlap`."""
    if min(before, min(at, after)) >= 0.0:
        return 0.125, 0.75, 0.125
    if max(before, max(at, after)) <= 0.0:
        return 0.0, 0.0, 0.0
    gu1, gv1 = _positive_mean_gradient(0.5 * (before + at), at)
    gu2, gv2 = _positive_mean_gradient(at, 0.5 * (at + after))
    return 0.25 * gu1, 0.25 * gu1 + 0.5 * gv1 + 0.5 * gu2 + 0.25 * gv2, 0.25 * gv2


@kernel
def foundation_modulus_factor(stiffness, pin_radius, bushing_radius):
    """kappa of the resultant (module docstring) per radian of cell, k_f L / R_i [N/m^2], with
    k_f = 3 K sqrt(c) / (4 sqrt(2) L sqrt(R_i R_j)) [N/m^3], c = R_j - R_i: the foundation whose force on
    the unworn bushing tends to K delta^1.5 as delta -> 0 (docs/reference/model.md §3.10)."""
    clearance = bushing_radius - pin_radius
    return 3.0 * stiffness * math.sqrt(clearance) / (4.0 * math.sqrt(2.0) * pin_radius
                                                     * math.sqrt(pin_radius * bushing_radius))


@kernel(inline='always')
def _point(z, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """(rho_z, d_z x, d_z y, |d_z|^2) of bushing point z, 0 <= z < N_d, |d_z|^2 as
    :func:`geometry.distance_sq`; R_i^2 - |d_z|^2 is 2 R_i o_z (the overlap without its constant divisor).
    Indexed unsigned: numba then adds no negative-index wrap."""
    u = np.uint64(z)
    rho = bushing_radius + wear_depth[u]
    dx = rho * cos_phi[u] - ex
    dy = rho * sin_phi[u] - ey
    return rho, dx, dy, dx * dx + dy * dy


@kernel
def _resultant_run(first, last, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, with_jacobian,
                   sums):
    """Add to ``sums`` the terms of points first..last (indices wrap; first >= -1, last < 2 N_d):
    (s0, sx, sy) = 2 R_i sum w_z rho_z (1, d_z), and with_jacobian M = sum rho_z d_z (x) g_z with
    g_z = R_i dw_z/de (4 entries, row-major); returns (sums, the smallest |d_z|^2 of the points, its z), ties
    to the lower z as :func:`geometry.find_deepest_point`.  Streams the overlaps: each point's once.  The
    overlaps are taken times 2 R_i (no division per point): w is homogeneous of degree 1 in them, its
    gradient of degree 0.  M is summed as 8 M, exactly (a power of 2): on the arc in contact, 8 g_z is
    d_(z-1) + 6 d_z + d_(z+1), without a multiplication by the weights."""
    n = wear_depth.shape[0]
    r2 = pin_radius * pin_radius
    s0, sx, sy, m11, m12, m21, m22 = sums
    sums = (s0, sx, sy, 8.0 * m11, 8.0 * m12, 8.0 * m21, 8.0 * m22)
    best_d2, best_z = math.inf, -1
    _, pdx, pdy, pd2 = _point(wrap_index(first - 1, n), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    z = wrap_index(first, n)
    rho, dx, dy, d2 = _point(z, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    po, o = r2 - pd2, r2 - d2
    for i in range(first, last + 1):
        following = wrap_index(i + 1, n)
        nrho, ndx, ndy, nd2 = _point(following, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
        no = r2 - nd2
        if d2 <= best_d2:                       # down a groove's flank, then rarely: a predictable branch
            if d2 < best_d2 or z < best_z:
                best_d2, best_z = d2, z
        if min(po, min(o, no)) >= 0.0:          # on the arc in contact: cell_overlap's first case, in a branch
            w = 0.125 * (po + 6.0 * o + no)     # of its own (the compiled loop is the shorter)
            if w > 0.0:
                sums = _add_cell(sums, rho, w, dx, dy, pdx + 6.0 * dx + ndx, pdy + 6.0 * dy + ndy, with_jacobian)
        else:
            w = cell_overlap(po, o, no)
            if w > 0.0:
                gb, ga, gc = cell_overlap_gradient(po, o, no)
                sums = _add_cell(sums, rho, w, dx, dy, 8.0 * (gb * pdx + ga * dx + gc * ndx),
                                 8.0 * (gb * pdy + ga * dy + gc * ndy), with_jacobian)
        pdx, pdy, po = dx, dy, o
        rho, dx, dy, d2, o, z = nrho, ndx, ndy, nd2, no, following
    s0, sx, sy, m11, m12, m21, m22 = sums
    return (s0, sx, sy, 0.125 * m11, 0.125 * m12, 0.125 * m21, 0.125 * m22), best_d2, best_z


@kernel(inline='always')
def _add_cell(sums, rho, w, dx, dy, gx, gy, with_jacobian):
    """``sums`` of :func:`_resultant_run` (with 8 M) plus point z's terms, from rho_z, w_z > 0, d_z and
    8 g_z."""
    s0, sx, sy, m11, m12, m21, m22 = sums
    rw = rho * w
    s0 += rw
    sx += rw * dx
    sy += rw * dy
    if with_jacobian:
        m11 += rho * dx * gx
        m12 += rho * dx * gy
        m21 += rho * dy * gx
        m22 += rho * dy * gy
    return s0, sx, sy, m11, m12, m21, m22


@kernel(inline='always')
def _unit(j, cos_phi, sin_phi):
    """(cos, sin) of j dphi for any integer j, from the points' table (phi_k = (k + 1) dphi)."""
    k = (j - 1) % cos_phi.shape[0]
    return cos_phi[k], sin_phi[k]


@kernel(inline='always')
def _half_unit(m, cos_phi, sin_phi, cos_half, sin_half):
    """(cos, sin) of m dphi / 2 for any integer m (cos_half, sin_half: of dphi / 2)."""
    c, s = _unit(m // 2, cos_phi, sin_phi)
    if m % 2 == 0:
        return c, s
    return c * cos_half - s * sin_half, s * cos_half + c * sin_half


@kernel
def _unworn_interior_sums(a, b, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, with_jacobian):
    """The sums of :func:`_resultant_run` over points a..b (any integers, b - a + 1 <= N_d) of an unworn
    stretch whose cells are all in contact, in closed form.  There rho = R_j, 2 R_i o_z = C + 2 R_j e.u_z
    with C = R_i^2 - R_j^2 - |e|^2, and u_(z-1) + u_(z+1) = 2 cos(dphi) u_z, so the cell weight is
    w_z = C + 2 R_j g e.u_z with g = (3 + cos dphi) / 4 and the gradient average (d_(z-1) + 6 d_z + d_(z+1)) / 8
    is R_j g u_z - e: every sum is one of n, S1 = sum u_z and S2 = sum u_z u_z^T, whose closed forms on the
    uniform grid are the Dirichlet kernels sin(n dphi/2)/sin(dphi/2) and sin(n dphi)/sin(dphi)."""
    count = b - a + 1
    cos_d, sin_d = cos_phi[0], sin_phi[0]                 # phi_0 = dphi
    cos_half = math.sqrt(0.5 * (1.0 + cos_d))
    sin_half = 0.5 * sin_d / cos_half
    d1 = _half_unit(count, cos_phi, sin_phi, cos_half, sin_half)[1] / sin_half
    d2 = _unit(count, cos_phi, sin_phi)[1] / sin_d
    ct, st = _half_unit(a + b + 2, cos_phi, sin_phi, cos_half, sin_half)   # the stretch's mid angle
    c2, s2 = ct * ct - st * st, 2.0 * ct * st
    s1x, s1y = d1 * ct, d1 * st
    s2xx, s2xy, s2yy = 0.5 * (count + d2 * c2), 0.5 * d2 * s2, 0.5 * (count - d2 * c2)
    rj = bushing_radius
    g = 0.25 * (3.0 + cos_d)
    c = pin_radius * pin_radius - rj * rj - (ex * ex + ey * ey)
    beta = 2.0 * rj * g
    e_s1 = ex * s1x + ey * s1y
    s0 = rj * (c * count + beta * e_s1)
    sx = rj * (c * (rj * s1x - count * ex) + beta * (rj * (s2xx * ex + s2xy * ey) - ex * e_s1))
    sy = rj * (c * (rj * s1y - count * ey) + beta * (rj * (s2xy * ex + s2yy * ey) - ey * e_s1))
    if not with_jacobian:
        return s0, sx, sy, 0.0, 0.0, 0.0, 0.0
    q = rj * rj * g
    m11 = rj * (q * s2xx - rj * (1.0 + g) * s1x * ex + count * ex * ex)
    m12 = rj * (q * s2xy - rj * (s1x * ey + g * ex * s1y) + count * ex * ey)
    m21 = rj * (q * s2xy - rj * (s1y * ex + g * ey * s1x) + count * ey * ex)
    m22 = rj * (q * s2yy - rj * (1.0 + g) * s1y * ey + count * ey * ey)
    return s0, sx, sy, m11, m12, m21, m22


@kernel(inline='always')
def _any_worn(first, last, wear_depth):
    """True if a point of first..last is worn (indices wrap; -n <= first, last < 2n, last - first < n): at
    most two contiguous stretches, each without a branch per point."""
    n = wear_depth.shape[0]
    if first < 0:
        return (_worn_bits(first + n, n, wear_depth) | _worn_bits(0, last + 1, wear_depth)) != 0
    if last >= n:
        return (_worn_bits(first, n, wear_depth) | _worn_bits(0, last - n + 1, wear_depth)) != 0
    return _worn_bits(first, last + 1, wear_depth) != 0


@kernel(inline='always')
def _worn_bits(start, stop, wear_depth):
    """Nonzero if a point of start..stop - 1 is worn: the OR of their bit patterns (a reduction the
    compiler vectorises; -0.0 counts as worn, which only sends the window to the point-by-point sum)."""
    bits = wear_depth.view(np.int64)
    acc = np.int64(0)
    for z in range(np.uint64(start), np.uint64(stop)):     # unsigned: no negative-index wrap per point
        acc |= bits[z]
    return acc


@kernel
def _unworn_window_sums(first, last, direction, reach, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi,
                        wear_depth, with_jacobian):
    """(done, sums) of :func:`_resultant_run` over first..last when every point the window touches is unworn:
    the stretch in contact (2 R_i o >= 0: within ``reach`` of e's direction, about the point index
    ``direction`` nearest it; the edges found again point by point) in closed form, its two edge cells
    point by point.  Not done
    (use the run) if a point is worn or the stretch has no interior."""
    n = wear_depth.shape[0]
    zeros = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    if _any_worn(first - 1, last + 1, wear_depth):
        return False, zeros
    steps = reach * n / (2.0 * math.pi)       # reach in points
    r2 = pin_radius * pin_radius
    lo = max(first + 1, int(math.ceil(direction - steps)))
    hi = min(last - 1, int(math.floor(direction + steps)))
    while lo <= hi and _point(wrap_index(lo, n), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)[3] > r2:
        lo += 1
    while lo - 1 > first and _point(wrap_index(lo - 1, n), ex, ey, bushing_radius, cos_phi, sin_phi,
                                    wear_depth)[3] <= r2:
        lo -= 1
    while hi >= lo and _point(wrap_index(hi, n), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)[3] > r2:
        hi -= 1
    while hi + 1 < last and _point(wrap_index(hi + 1, n), ex, ey, bushing_radius, cos_phi, sin_phi,
                                   wear_depth)[3] <= r2:
        hi += 1
    if hi - lo < 2:
        return False, zeros
    sums = _unworn_interior_sums(lo + 1, hi - 1, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, with_jacobian)
    sums = _resultant_run(lo - 1, lo, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                          with_jacobian, sums)[0]
    return True, _resultant_run(hi, hi + 1, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                                with_jacobian, sums)[0]


@kernel(inline='always')
def _window(centre, half, n):
    """(first, last, centre as a real index) of the window of points centre - half .. centre + half, shifted
    by n where it would start before -1 (the runs wrap indices from -1 up)."""
    first = centre - half
    if first < -1:
        return first + n, first + n + 2 * half, float(centre + n)
    return first, first + 2 * half, float(centre)


@kernel
def foundation_resultant(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, with_jacobian, deepest):
    """Elastic-foundation force on the pin per unit kappa, in the bushing frame, and its Jacobian
    (module docstring): returns (f_x, f_y, df_x/de_x, df_x/de_y, df_y/de_x, df_y/de_y, s0, k, |d_k|^2) with
    F = kappa f, f = -sum_z w_z rho_z d_z [m^3] and s0 = sum_z w_z rho_z [m^2] (the overlap
    integral divided by dphi).  The Jacobian is 0 unless ``with_jacobian``.

    Only the points within the angle Delta_max of e's direction can overlap the pin, whatever the
    wear: |d|^2 = rho^2 + |e|^2 - 2 rho |e| cos(Delta) grows with rho >= R_j (rho > |e|), so o > 0
    needs cos(Delta) > (R_j^2 + |e|^2 - R_i^2) / (2 R_j |e|).  The sum runs over that window and
    one point past each end (their cells reach into the contact): in closed form where every point
    of it is unworn (:func:`_unworn_window_sums`), else point by point, and then (k, |d_k|^2) is the
    point of the window nearest the pin centre, ties to the lower index (else (-1, inf)): if it is inside
    the pin it is the deepest point of the whole bushing (every point outside the window is outside the
    pin).  ``deepest``: the deepest bushing point if known (else -1); where it is unworn and so is the window
    about it, it is the point nearest e's direction, which is then not computed (an arctangent per
    evaluation)."""
    n = wear_depth.shape[0]
    sums = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    nearest_d2, nearest = math.inf, -1
    e = math.sqrt(ex * ex + ey * ey)
    if not 0.0 < e < math.inf:                   # centred, or not finite (finite inputs whose difference overflows)
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nearest, nearest_d2
    cos_max = reach_cosine(e, bushing_radius, pin_radius * pin_radius)
    if not cos_max < 1.0:                        # no point can reach the pin (NaN: a window of no width, not a wild one)
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nearest, nearest_d2
    reach, half = reach_points(cos_max, n)
    if 2 * half + 1 >= n:           # every point; np.int64: a literal 0 is one more compilation
        sums, nearest_d2, nearest = _resultant_run(np.int64(0), n - 1, ex, ey, pin_radius, bushing_radius, cos_phi,
                                                   sin_phi, wear_depth, with_jacobian, sums)
    else:
        hinted = 0 <= deepest < n and wear_depth[deepest] == 0.0
        first, last, direction = _window(deepest if hinted else direction_point(ex, ey, n), half, n)
        done, sums = _unworn_window_sums(first, last, direction, reach, ex, ey, pin_radius, bushing_radius, cos_phi,
                                         sin_phi, wear_depth, with_jacobian)
        if not done:
            if hinted:                               # the window must be about e's direction
                first, last, direction = _window(direction_point(ex, ey, n), half, n)
            sums, nearest_d2, nearest = _resultant_run(first, last, ex, ey, pin_radius, bushing_radius, cos_phi,
                                                       sin_phi, wear_depth, with_jacobian,
                                                       (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    s0, sx, sy, m11, m12, m21, m22 = sums
    scale = 0.5 / pin_radius                     # the runs' overlaps are 2 R_i o
    s0, sx, sy = s0 * scale, sx * scale, sy * scale
    if not with_jacobian:
        return -sx, -sy, 0.0, 0.0, 0.0, 0.0, s0, nearest, nearest_d2
    # df/de = -(M / R_i - s0 I): d(w rho d)/de = rho d (x) dw/de - w rho I
    return (-sx, -sy, s0 - m11 / pin_radius, -m12 / pin_radius, -m21 / pin_radius, s0 - m22 / pin_radius, s0,
            nearest, nearest_d2)
