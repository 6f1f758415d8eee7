"""Wear kernels of the clearance joint (paper Sec. 5, Eqs. 24-35).

Archard's law removes the volume k_w F_N ds (Eq. 24); the depth update of
Eq. (28) is h_z += k_w p Delta s_z.  Where the increment goes (docs/model.md §3.7):

* ``foundation`` (default): the pressure follows the local overlap of the worn
  surface with the pin (an elastic, Winkler foundation), integrated over each
  point's arc cell, normalised to the normal force (:func:`foundation_wear`).
* ``patch``: the paper's Hertz patch, p = F_N / (2 b L) (Eqs. 29-32); bushing
  point z stands for the arc cell [phi_z - dphi/2, phi_z + dphi/2] and receives
  the increment times the share of its cell inside the patch [-b, b] around
  the contact point, centred between bushing points at the vertex of the
  parabola through |d|^2 of the deepest point and its two neighbours
  (:func:`subgrid_contact_offset`).
* ``penetration``: every point with |d_z| <= R_i receives the full Hertz
  increment (the literal reading of Eq. 28).
"""
import math

import numpy as np

from .contact import evaluate_contact, update_contact_memory
from .geometry import (
    _block_lower_bound_sq, _direction_point, _is_direction_block, _tie_margin, block_minimum, block_minimum_depth,
    distance_sq, penetrating_points, wrap_index,
)
from .jit import kernel
from .pressure import cell_overlap, cell_overlap_gradient, foundation_modulus_factor, overlap
from .layout import (
    BLOCK_SIZE, M_START_FORCE, MAX_WEAR_STEP_S, N_RESULT, P_ARCHARD_COEFFICIENT, P_BUSHING_POISSON_RATIO,
    P_BUSHING_RADIUS, P_BUSHING_YOUNGS_MODULUS, P_CONTACT_LENGTH, P_EFFECTIVE_MODULUS, P_FOUNDATION_MODULUS,
    P_PIN_POISSON_RATIO, P_PIN_RADIUS, P_PIN_YOUNGS_MODULUS, P_RHO_MODE, P_SLIDING, P_STIFFNESS, P_WEAR_COEFFICIENT,
    P_WEAR_FACTOR, P_WEAR_PLACEMENT, R_CONTACT, R_CONTACT_INDEX, R_ECCENTRICITY_X, R_ECCENTRICITY_Y, R_NORMAL_FORCE,
    R_PENETRATION, R_TANGENTIAL_VELOCITY, WEAR_STEP_SHARE, WEAR_STEP_SHARE_EXPLICIT,
)


WEAR_REFUSED = -1.0                    # apply_wear: the step's wear is absurd; nothing changed
# accept_contact / advance_joint; STEP_OVERSHOT: changed, by a wearing step over the wear-step limit
STEP_REFUSED, STEP_UNCHANGED, STEP_CHANGED, STEP_OVERSHOT = -1, 0, 1, 2


@kernel
def effective_modulus(pin_youngs_modulus, pin_poisson_ratio, bushing_youngs_modulus, bushing_poisson_ratio):
    """Composite modulus E* of Eq. (32) [Pa]: 1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j (standard Hertz
    form; the paper pairs the indices the other way, docs/model.md 3)."""
    return 1.0 / ((1.0 - pin_poisson_ratio * pin_poisson_ratio) / pin_youngs_modulus
                  + (1.0 - bushing_poisson_ratio * bushing_poisson_ratio) / bushing_youngs_modulus)


@kernel
def complete_joint_parameters(jp):
    """Fill the derived slots of the joint parameter vector from the given ones: E* (Eq. 32),
    the wear coefficient the updates use (k_w times the wear acceleration factor) and the elastic
    foundation's k_f L / R_i (:func:`core.pressure.foundation_modulus_factor`: three square roots the
    contact would otherwise take at every evaluation)."""
    jp[P_EFFECTIVE_MODULUS] = effective_modulus(jp[P_PIN_YOUNGS_MODULUS], jp[P_PIN_POISSON_RATIO],
                                                jp[P_BUSHING_YOUNGS_MODULUS], jp[P_BUSHING_POISSON_RATIO])
    jp[P_WEAR_COEFFICIENT] = jp[P_ARCHARD_COEFFICIENT] * jp[P_WEAR_FACTOR]
    jp[P_FOUNDATION_MODULUS] = foundation_modulus_factor(jp[P_STIFFNESS], jp[P_PIN_RADIUS], jp[P_BUSHING_RADIUS])


@kernel
def equivalent_radius(pin_radius, worn_bushing_radius, rho_mode):
    """rho* of Eq. (31) [m]: 0 = conformal R_i R~/(R~ - R_i) (default), 1 = paper R_i R~/(R_i + R~)."""
    if rho_mode == 0:
        return pin_radius * worn_bushing_radius / (worn_bushing_radius - pin_radius)
    return pin_radius * worn_bushing_radius / (pin_radius + worn_bushing_radius)


@kernel
def hertz_half_width(normal_force, equivalent_radius_m, contact_length, effective_modulus):
    """Half contact width b = (4 F_N rho* / (pi L E*))^0.5, Eq. (30) [m]."""
    return math.sqrt(4.0 * normal_force * equivalent_radius_m / (math.pi * contact_length * effective_modulus))


@kernel
def _elliptic_integral(u):
    """Integral of sqrt(1 - x^2) from 0 to u, u in [-1, 1]."""
    return 0.5 * (u * math.sqrt(max(0.0, 1.0 - u * u)) + math.asin(u))


@kernel
def patch_weight(offset_angle, half_angle, dphi):
    """Hertz pressure on the arc cell [offset - dphi/2, offset + dphi/2] relative to the mean
    pressure, averaged over the cell: p(x)/p_mean = (4/pi) sqrt(1 - (x/b)^2) on [-b, b]
    (semi-elliptical line-contact pressure), zero outside.  Summed over the cells the
    weights integrate to the patch width, so the removed volume is k_w F_N Delta s."""
    lo = max(offset_angle - 0.5 * dphi, -half_angle)
    hi = min(offset_angle + 0.5 * dphi, half_angle)
    if hi <= lo:
        return 0.0
    return 4.0 / math.pi * half_angle * (_elliptic_integral(hi / half_angle)
                                         - _elliptic_integral(lo / half_angle)) / dphi


@kernel
def subgrid_contact_offset(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth):
    """Where, between bushing points, |d|^2 is smallest near the deepest point k, in
    units of the point spacing (in [-0.5, 0.5]): vertex of the parabola through
    points k - 1, k, k + 1."""
    n = wear_depth.shape[0]
    before = distance_sq(wrap_index(k - 1, n), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    at = distance_sq(k, ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    after = distance_sq(wrap_index(k + 1, n), ex, ey, bushing_radius, cos_phi, sin_phi, wear_depth)
    curvature = before - 2.0 * at + after
    if curvature <= 0.0:
        return 0.0
    return min(0.5, max(-0.5, 0.5 * (before - after) / curvature))


@kernel
def _refresh_blocks(wear_depth, block_min, first, last):
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


@kernel
def _fill_overlaps(lo, hi, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, work):
    """work[z] = :func:`overlap` of point z for z = lo..hi-1 (0 <= lo <= hi <= N_d, no wrapping).
    Returns how many of them are inside or on the pin (overlap >= 0, i.e. |d_z|^2 <= R_i^2: the
    count of :func:`geometry._count_candidates`).  Branch-free on unsigned indices: vectorised."""
    count = 0
    for z in range(np.uint64(lo), np.uint64(hi)):
        o = overlap(z, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth)
        work[z] = o
        count += o >= 0.0
    return count


@kernel
def _mark_blocks(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, kept, work):
    """kept[b] for every block b (``kept``: the first nb entries of the joint's point mask): False
    only if block b holds no point inside the pin, by the block's lower bound
    (:func:`geometry._block_lower_bound_sq`), else by the overlaps of its points, which are left in
    ``work`` (:func:`_fill_overlaps`).  Blocks of fewer than 4 points are always kept, so the runs
    of kept blocks are at least 4 points apart.  Returns a block that is not kept, or -1 if all are."""
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    e, ux, uy, k0 = _direction_point(ex, ey, n)
    b0 = k0 // BLOCK_SIZE
    margin = _tie_margin(pin_radius * pin_radius)
    skipped = -1
    for b in range(nb):
        lo = b * BLOCK_SIZE
        hi = min(lo + BLOCK_SIZE, n)
        forced = nb <= 3 or hi - lo < 4
        if (not forced and not _is_direction_block(b, b0, nb)
                and _block_lower_bound_sq(e, ux, uy, bushing_radius, cos_phi, sin_phi, block_min, b, n) > margin):
            kept[b] = False
        else:
            inside = _fill_overlaps(lo, hi, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, work)
            kept[b] = forced or inside > 0
        if not kept[b]:
            skipped = b
    return skipped


@kernel
def _summand(z, before, after, rotation, bushing_radius, wear_depth, work):
    """Point z's weight w_z = :func:`cell_overlap` of the overlaps in work[:N_d] of points
    ``before``, z, ``after``, stored in work[N_d + z]; returns (w_z (R_j + h_z), the peak
    candidate: that (``rotation``) or w_z)."""
    n = wear_depth.shape[0]
    w = cell_overlap(work[before], work[z], work[after])
    work[n + z] = w
    rho_w = (bushing_radius + wear_depth[z]) * w
    return rho_w, (rho_w if rotation else w)


@kernel(inline='always')
def _segment_sums(lo, hi, rotation, bushing_radius, wear_depth, work, sums, peaks):
    """:func:`_cell_weights` over points lo..hi-1 (1 <= lo, hi <= N_d - 1: no wrapping), carrying its
    four partial sums and maxima: each new term goes to the chain the sums' rotation brings up,
    (s1, s2, s3, s0 + x), so four terms in a row add to s0..s3 in place (the unrolled loop: no
    moves, and each addition waits for the one four terms back)."""
    z = np.uint64(lo)
    end = np.uint64(hi)
    one = np.uint64(1)
    while z + np.uint64(4) <= end:
        x0, q0 = _summand(z, z - one, z + one, rotation, bushing_radius, wear_depth, work)
        x1, q1 = _summand(z + one, z, z + np.uint64(2), rotation, bushing_radius, wear_depth, work)
        x2, q2 = _summand(z + np.uint64(2), z + one, z + np.uint64(3), rotation, bushing_radius, wear_depth, work)
        x3, q3 = _summand(z + np.uint64(3), z + np.uint64(2), z + np.uint64(4), rotation, bushing_radius,
                          wear_depth, work)
        sums = (sums[0] + x0, sums[1] + x1, sums[2] + x2, sums[3] + x3)
        peaks = (max(peaks[0], q0), max(peaks[1], q1), max(peaks[2], q2), max(peaks[3], q3))
        z += np.uint64(4)
    while z < end:
        x, q = _summand(z, z - one, z + one, rotation, bushing_radius, wear_depth, work)
        sums = (sums[1], sums[2], sums[3], sums[0] + x)
        peaks = (peaks[1], peaks[2], peaks[3], max(peaks[0], q))
        z += one
    return sums, peaks


@kernel
def _cell_weights(first, last, cyclic, rotation, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                  work):
    """The :func:`cell_overlap` weights of points first..last (first >= -1, last < 2 N_d, at most
    N_d points, wrapping; ``cyclic``: the whole circle) into work[N_d:] from their overlaps in
    work[:N_d], and (the run's overlap integral, sum of w_z (R_j + h_z) dphi; the largest
    w_z (R_j + h_z) (``rotation``) or w_z).  A run that is not cyclic first gets the overlaps of
    the two points on either side computed (their blocks may have been skipped).  Four partial
    sums in a fixed order, which does not depend on the CPU (the native FMU gives the same
    numbers)."""
    n = wear_depth.shape[0]
    if not cyclic:
        for i in (first - 1, first, last, last + 1):
            z = wrap_index(i, n)
            work[z] = overlap(z, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth)
    sums = (0.0, 0.0, 0.0, 0.0)
    peaks = (0.0, 0.0, 0.0, 0.0)
    i = first
    while i <= last:
        z = wrap_index(i, n)
        if z == 0 or z == n - 1:                     # the points whose neighbours wrap
            x, q = _summand(z, wrap_index(z - 1, n), wrap_index(z + 1, n), rotation, bushing_radius, wear_depth,
                            work)
            sums = (sums[1], sums[2], sums[3], sums[0] + x)
            peaks = (peaks[1], peaks[2], peaks[3], max(peaks[0], q))
            i += 1
        else:
            end = min(last + 1, i + n - 1 - z)          # up to point n - 2
            sums, peaks = _segment_sums(z, z + end - i, rotation, bushing_radius, wear_depth, work, sums, peaks)
            i = end
    total = ((sums[0] + sums[1]) + (sums[2] + sums[3])) * (2.0 * math.pi / n)
    return total, max(max(peaks[0], peaks[1]), max(peaks[2], peaks[3]))


@kernel(inline='always')
def relaxation_factor(lam):
    """phi(lambda) = (1 - exp(-lambda)) / lambda [-]: the share of the explicit increment that wearing a
    point whose pressure relaxes as exp(-lambda s / Delta s) removes over the step (docs/model.md §3.11)."""
    if lam < 1e-3:                            # the series: 1 - exp(-lambda) would cancel (libm has no expm1 here)
        return 1.0 - lam * (0.5 - lam * (1.0 / 6.0 - lam / 24.0))
    return (1.0 - math.exp(-lam)) / lam


PASS_WEIGHTS, PASS_SHIFT, PASS_APPLY = 0, 1, 2


@kernel
def _relaxed_run(mode, first, last, shift, scale, relative_dt, slide, rotation, bushing_radius, wear_depth,
                 work):
    """Over points first..last (first >= -1, last < 2 N_d, at most N_d points, wrapping) with their overlaps
    in work[:N_d] and weights in work[N_d:], each point's pressure p_z = cell mean of (o + shift)+ times
    k_eff, relaxed over the step: lambda_z = scale Delta s_z (scale = k_w k_eff [1/m]), increment
    scale Delta s_z phi(lambda_z) cell_overlap(o + shift).  PASS_SHIFT: returns (the volume sum
    sum rho_z Delta s_z phi_z cell_overlap(o + shift), its derivative in shift, the explicit update's
    sum rho_z Delta s_z w_z); PASS_APPLY: applies the increments, returns (the largest increment, 0, 0)."""
    n = wear_depth.shape[0]
    volume = slope = explicit = 0.0
    for i in range(first, last + 1):
        z = wrap_index(i, n)
        before = work[wrap_index(i - 1, n)] + shift
        at = work[z] + shift
        after = work[wrap_index(i + 1, n)] + shift
        rho = bushing_radius + wear_depth[z]
        ds = rho * relative_dt if rotation else slide
        lam = scale * ds
        phi = relaxation_factor(lam)
        mean = cell_overlap(before, at, after)
        if mode == PASS_SHIFT:
            g_before, g_at, g_after = cell_overlap_gradient(before, at, after)
            volume += rho * ds * phi * mean
            slope += rho * ds * phi * (g_before + g_at + g_after)
            explicit += rho * ds * work[n + z]
        elif mean > 0.0:
            dh = scale * ds * phi * mean
            wear_depth[z] = rho + dh - bushing_radius
            volume = max(volume, dh)
    return volume, slope, explicit


@kernel(inline='always')
def _block_start(b, nb, n):
    """First point of block b, counted on past n for b >= nb (blocks of a second turn)."""
    return n + (b - nb) * BLOCK_SIZE if b >= nb else b * BLOCK_SIZE


@kernel
def _run_pass(mode, first, last, cyclic, shift, scale, relative_dt, slide, rotation, ex, ey, pin_radius,
              bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work):
    """One run of :func:`_foundation_pass`: PASS_WEIGHTS, :func:`_cell_weights` -> (integral, peak, 0, -inf);
    otherwise :func:`_relaxed_run`'s three numbers and the largest overlap at the run's two ends (each end
    point and its outer neighbour; -inf for the whole circle), whose cells a shift above minus that would
    bring into contact."""
    if mode == PASS_WEIGHTS:
        total, peak = _cell_weights(first, last, cyclic, rotation, ex, ey, pin_radius, bushing_radius, cos_phi,
                                    sin_phi, wear_depth, work)
        return total, peak, 0.0, -math.inf
    a, b, c = _relaxed_run(mode, first, last, shift, scale, relative_dt, slide, rotation, bushing_radius,
                           wear_depth, work)
    if mode == PASS_APPLY:
        _refresh_blocks(wear_depth, block_min, first, last)
    if cyclic:
        return a, b, c, -math.inf
    n = wear_depth.shape[0]
    edge = max(max(work[wrap_index(first - 1, n)], work[wrap_index(first, n)]),
               max(work[wrap_index(last, n)], work[wrap_index(last + 1, n)]))
    return a, b, c, edge


@kernel
def _foundation_pass(mode, shift, scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                     cos_phi, sin_phi, wear_depth, block_min, kept, skipped, work):
    """:func:`_run_pass` over every run of kept blocks (:func:`_mark_blocks`; the whole circle if
    ``skipped`` < 0), each run widened by one point on both sides (a cell just outside can still overlap
    over part of its arc); returns the sums of the runs' first and third numbers, the largest of their
    second (PASS_WEIGHTS, PASS_APPLY) or its sum (PASS_SHIFT), and the largest end overlap."""
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    if skipped < 0:
        return _run_pass(mode, 0, n - 1, True, shift, scale, relative_dt, slide, rotation, ex, ey, pin_radius,
                         bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work)
    first_sum = second = third_sum = 0.0
    edge = -math.inf
    start = -1
    for j in range(1, nb + 1):
        b = skipped + j
        bb = b - nb if b >= nb else b
        keep = j < nb and kept[bb]
        if keep and start < 0:
            start = b
        elif not keep and start >= 0:
            first = _block_start(start, nb, n) - 1                      # one point before the run ...
            last = _block_start(b, nb, n)                               # ... and one after
            if first >= n:
                first -= n
                last -= n
            x, y, z, e = _run_pass(mode, first, last, False, shift, scale, relative_dt, slide, rotation, ex,
                                   ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work)
            first_sum += x
            second = second + y if mode == PASS_SHIFT else max(second, y)
            third_sum += z
            edge = max(edge, e)
            start = -1
    return first_sum, second, third_sum, edge


@kernel
def _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi,
                 wear_depth, block_min, kept, skipped, work):
    """The uniform overlap shift a >= 0 [m] (the pin's advance into the groove it wears) at which the relaxed
    increments remove the explicit update's volume, sum rho Delta s phi cell(o + a) = sum rho Delta s w
    (Newton on a convex, increasing function of a, from a = 0 where it is below), and the largest end
    overlap of the runs it was solved on."""
    shift = 0.0
    edge = -math.inf
    for _ in range(60):
        volume, slope, explicit, edge = _foundation_pass(PASS_SHIFT, shift, scale, relative_dt, slide,
                                                         rotation, ex, ey, pin_radius, bushing_radius, cos_phi,
                                                         sin_phi, wear_depth, block_min, kept, skipped, work)
        missing = explicit - volume
        if not slope > 0.0 or abs(missing) <= 1e-13 * explicit:
            break
        step = missing / slope
        shift = max(0.0, shift + step)
        if abs(step) <= 1e-15 * (shift + 1e-30):
            break
    return shift, edge


@kernel
def foundation_wear(k_w, f_n, contact_length, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                    cos_phi, sin_phi, wear_depth, block_min, mask, work, k):
    """Elastic-foundation (Winkler) placement of the Archard increment, relaxed exactly over the step
    (docs/model.md §3.7, §3.11).

    The pressure on the bushing is proportional to the local overlap of the worn surface with the pin,
    p(phi) = k_eff o+(phi), k_eff = F_N / (L int o+ rho dphi), so it integrates to the normal force over
    the arc in contact.  Wearing a point lowers its pressure at the rate k_eff k_w per unit of sliding, so
    over the step point z's pressure relaxes by exp(-lambda_z), lambda_z = k_eff k_w Delta s_z, while the
    load the pin carries pushes it uniformly deeper by the overlap a: h_z += k_w Delta s_z phi(lambda_z)
    k_eff cell(o + a)+, with a set so that the removed volume stays Archard's, k_w F_N Delta s (for small
    lambda the explicit update h_z += k_w p_z Delta s_z).  Any lambda is stable: a point never wears more
    than its shifted overlap.  Pressures are cell means (:func:`cell_overlap`) of the depths before the
    update.  Scratch: ``mask`` (bool, N_d), whose first nb entries flag the blocks of points that may
    overlap, and ``work`` (float64, 2 N_d), which holds the points' overlaps (work[:N_d]) and weights
    (work[N_d:]).  Returns the largest increment [m], or WEAR_REFUSED with nothing changed if an increment
    would exceed the bushing radius or is not finite."""
    skipped = _mark_blocks(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask, work)
    total, peak, _, _ = _foundation_pass(PASS_WEIGHTS, 0.0, 0.0, relative_dt, slide, rotation, ex, ey,
                                         pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask,
                                         skipped, work)
    if total <= 0.0:                          # cannot happen with F_N > 0 (the deepest point overlaps)
        n = wear_depth.shape[0]
        rho = bushing_radius + wear_depth[k]
        dh = k_w * f_n / (contact_length * rho * 2.0 * math.pi / n) * (rho * relative_dt if rotation else slide)
        if not dh <= bushing_radius:
            return WEAR_REFUSED
        wear_depth[k] += dh
        _refresh_blocks(wear_depth, block_min, k, k)
        return dh
    scale = k_w * f_n / (contact_length * total)
    if not scale * peak * (relative_dt if rotation else slide) <= bushing_radius:   # absurd or not finite
        return WEAR_REFUSED
    shift, edge = _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                               cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
    if edge + shift > 0.0:                    # the shifted contact reaches past a run: the whole circle
        skipped = -1
        _fill_overlaps(0, wear_depth.shape[0], ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                       work)
        _foundation_pass(PASS_WEIGHTS, 0.0, 0.0, relative_dt, slide, rotation, ex, ey, pin_radius,
                         bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
        shift, _ = _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                                cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
    largest, _, _, _ = _foundation_pass(PASS_APPLY, shift, scale, relative_dt, slide, rotation, ex, ey,
                                        pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask,
                                        skipped, work)
    return largest


@kernel(inline='always')
def wears(result, f_n, jp, dt):
    """True if an accepted step of dt [s] ending at the contact ``result`` with the mean normal force f_n
    [N] wears the bushing (the increments of :func:`apply_wear` may still round to 0): in contact,
    f_n > 0, k_w > 0, dt > 0."""
    return not (result[R_CONTACT] < 0.5 or jp[P_WEAR_COEFFICIENT] <= 0.0 or dt <= 0.0 or f_n <= 0.0)


@kernel(inline='always')
def step_mean_normal_force(result, memory, held):
    """The normal force [N] the wear of an accepted step ending at the contact ``result`` takes: the
    contact's own if the kinematics were ``held`` over the step (a co-simulation step) or before the first
    accepted point, else the trapezoid of the step's start (memory[M_START_FORCE], the last accepted point
    on its worn profile) and its end, the mean force the host's integrator applied over a step that began
    just after a wear update (docs/model.md §3.11)."""
    start = memory[M_START_FORCE]
    if held or start < 0.0:
        return result[R_NORMAL_FORCE]
    return 0.5 * (start + result[R_NORMAL_FORCE])


@kernel
def apply_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min, mask, work):
    """Archard update of the wear profile over an accepted step of length dt, Eqs. (28)-(33).

    ``result`` is the contact evaluation at the accepted state, ``f_n`` the step's mean normal force
    [N] (:func:`step_mean_normal_force`).  Sliding
    distance: ``rotation`` (R_j + h_z)|d alpha| with alpha the relative angle
    of the two bodies, Eq. (33), taken as |omega_i - omega_j| dt; or
    ``tangential`` |v_T| dt at the contact.  Returns (the largest depth increment [m], the step's share
    of the wear-step limit: the largest lambda over WEAR_STEP_SHARE for the relaxed ``foundation``
    update (lambda = k_f k_w Delta s at the contact, docs/model.md §7), the largest increment over
    WEAR_STEP_SHARE_EXPLICIT times the penetration for the explicit
    ``patch`` and ``penetration``), or (WEAR_REFUSED, 0) with nothing changed where a step would wear a
    point by more than the bushing radius or by a non-finite depth (a step no physical host takes:
    h = 1e300 s, say).
    """
    if not wears(result, f_n, jp, dt):
        return 0.0, 0.0
    k_w = jp[P_WEAR_COEFFICIENT]
    n = wear_depth.shape[0]
    dphi = 2.0 * math.pi / n
    k = int(result[R_CONTACT_INDEX])
    pin_radius = jp[P_PIN_RADIUS]
    bushing_radius = jp[P_BUSHING_RADIUS]
    worn_radius = bushing_radius + wear_depth[k]
    rho = equivalent_radius(pin_radius, worn_radius, int(jp[P_RHO_MODE]))
    half_width = hertz_half_width(f_n, rho, jp[P_CONTACT_LENGTH], jp[P_EFFECTIVE_MODULUS])
    pressure = f_n / (2.0 * half_width * jp[P_CONTACT_LENGTH])          # Eqs. (25), (29)
    rotation = int(jp[P_SLIDING]) == 0
    relative_rate = abs(vel_i[2] - vel_j[2])
    tangential_slide = abs(result[R_TANGENTIAL_VELOCITY]) * dt
    largest = 0.0
    placement = int(jp[P_WEAR_PLACEMENT])
    if placement == 2:
        largest = foundation_wear(k_w, f_n, jp[P_CONTACT_LENGTH], relative_rate * dt, tangential_slide, rotation,
                                  result[R_ECCENTRICITY_X], result[R_ECCENTRICITY_Y], pin_radius, bushing_radius,
                                  cos_phi, sin_phi, wear_depth, block_min, mask, work, k)
        k_f = jp[P_FOUNDATION_MODULUS] * pin_radius / jp[P_CONTACT_LENGTH]     # the slot holds k_f L / R_i
        share = k_f * k_w * (worn_radius * relative_rate * dt if rotation else tangential_slide)   # lambda, §7
        return largest, share / WEAR_STEP_SHARE
    # a bound on the increments below (patch weights <= 4/pi, depths <= R_j): refuse an absurd step
    slide_bound = 2.0 * worn_radius * relative_rate * dt if rotation else tangential_slide
    if not k_w * pressure * (4.0 / math.pi) * slide_bound <= bushing_radius:
        return WEAR_REFUSED, 0.0
    if placement == 0:
        half_angle = min(half_width / worn_radius, math.pi)
        centre = subgrid_contact_offset(k, result[R_ECCENTRICITY_X], result[R_ECCENTRICITY_Y], bushing_radius,
                                        cos_phi, sin_phi, wear_depth)
        m = min(int(math.ceil(half_angle / dphi + 1.0)), (n - 1) // 2)
        for off in range(-m, m + 1):
            w = patch_weight((off - centre) * dphi, half_angle, dphi)
            if w <= 0.0:
                continue
            z = wrap_index(k + off, n)
            slide = (bushing_radius + wear_depth[z]) * relative_rate * dt if rotation else tangential_slide
            dh = k_w * pressure * slide * w
            wear_depth[z] += dh
            largest = max(largest, dh)
        _refresh_blocks(wear_depth, block_min, k - m, k + m)
    else:
        penetrating_points(result[R_ECCENTRICITY_X], result[R_ECCENTRICITY_Y], pin_radius,
                           bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask)
        for z in range(n):
            if mask[z]:
                slide = (bushing_radius + wear_depth[z]) * relative_rate * dt if rotation else tangential_slide
                dh = k_w * pressure * slide
                wear_depth[z] += dh
                largest = max(largest, dh)
        block_minimum_depth(wear_depth, block_min)
    return largest, largest / (WEAR_STEP_SHARE_EXPLICIT * result[R_PENETRATION])


@kernel
def accept_contact(result, pos_i, vel_i, pos_j, vel_j, dt, held, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                   mask, work):
    """Archard update over dt with the step's mean normal force (:func:`step_mean_normal_force`) and the
    contact-onset bookkeeping for ``result``, the contact evaluated at the accepted state (pos, vel) on the
    profile the step began with (left as it is).  memory[M_START_FORCE] becomes the normal force there on
    the new profile, evaluated in ``work`` after the wear.  Returns STEP_CHANGED if the joint's forces changed,
    STEP_OVERSHOT if they did by a step over the wear-step limit (longer than MAX_WEAR_STEP_S, or past its
    share of the wear, :func:`apply_wear`; docs/model.md §7), STEP_UNCHANGED, or STEP_REFUSED (nothing
    changed: the wear would be absurd, :func:`apply_wear`)."""
    f_n = step_mean_normal_force(result, memory, held)
    largest, share = apply_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min, mask,
                                work)
    if largest < 0.0:
        return STEP_REFUSED
    changed = update_contact_memory(result, jp, memory)
    if largest > 0.0:
        after = work[:N_RESULT]
        for r in range(N_RESULT):                # the search starts from the contact before the wear
            after[r] = result[r]
        evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, after)
        memory[M_START_FORCE] = after[R_NORMAL_FORCE]
    else:
        memory[M_START_FORCE] = result[R_NORMAL_FORCE]
    if largest > 0.0 and (dt > MAX_WEAR_STEP_S * (1.0 + 1e-9) or share > 1.0):
        return STEP_OVERSHOT
    return STEP_CHANGED if largest > 0.0 or changed else STEP_UNCHANGED


@kernel
def advance_joint(pos_i, vel_i, pos_j, vel_j, dt, held, jp, cos_phi, sin_phi, wear_depth, block_min, memory, mask,
                  work, result):
    """Accept the state (pos, vel) as the end of a step of length dt (``held``: the kinematics held over
    the step): evaluate the contact there (into ``result``), then :func:`accept_contact`; returns its
    STEP_* code (STEP_CHANGED: forces at the same kinematics would differ)."""
    evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min,
                     memory, result)
    return accept_contact(result, pos_i, vel_i, pos_j, vel_j, dt, held, jp, cos_phi, sin_phi, wear_depth, block_min,
                          memory, mask, work)


@kernel
def worn_area(bushing_radius, wear_depth):
    """Area between the worn and the original bushing circle [m^2]: sum (rho^2 - R_j^2) dphi / 2."""
    n = wear_depth.shape[0]
    dphi = 2.0 * math.pi / n
    total = 0.0
    for z in range(n):
        total += wear_depth[z] * (2.0 * bushing_radius + wear_depth[z])
    return 0.5 * total * dphi


@kernel
def worn_volume(jp, wear_depth):
    """Volume removed from the bushing: contact length L times :func:`worn_area` [m^3]."""
    return jp[P_CONTACT_LENGTH] * worn_area(jp[P_BUSHING_RADIUS], wear_depth)
