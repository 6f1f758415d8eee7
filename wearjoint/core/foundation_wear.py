"""The elastic-foundation placement of the Archard increment, relaxed exactly over the step
(docs/reference/model.md §3.7, §3.11): the bushing points' overlaps with the pin, their cell weights over the
runs of blocks that may touch it, the uniform pin advance that keeps Archard's volume, and the update.
Pure numba functions on the joint's arrays; :func:`foundation_wear` is the entry, called by
:func:`wearjoint.core.wear.apply_wear`.
"""
import math

import numpy as np

from .geometry import (
    _block_lower_bound_sq, _direction_point, _is_direction_block, _tie_margin, candidate_blocks, refresh_blocks,
    wrap_index,
)
from .jit import kernel
from .layout import BLOCK_SIZE
from .pressure import cell_overlap, cell_overlap_gradient, overlap

WEAR_REFUSED = -1.0                    # the step's wear is absurd; nothing changed
# a Newton step from a residual below this share of the volume is the last: the next residual, measured as
# 0.16-0.17 times the square of the relative residual before the step, is below 1e-14 (no check pass)
NEWTON_LAST_STEP = 1e-7
# the overlap a pin that clears the wall is moved to: far below any increment, so that the update is the pin's
# geometric advance (lambda >> 1: every point wears its shifted overlap), independent of this value
TOUCH_OVERLAP_M = 1e-12


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
    only if block b holds no point inside the pin, by its angle from e (:func:`geometry.candidate_blocks`) or its
    lower bound (:func:`geometry._block_lower_bound_sq`), else by the overlaps of its points, which are left in
    ``work`` (:func:`_fill_overlaps`).  Blocks of fewer than 4 points are always kept, so the runs
    of kept blocks are at least 4 points apart.  Returns a block that is not kept, or -1 if all are."""
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    e, ux, uy, k0 = _direction_point(ex, ey, n)
    b0 = k0 // BLOCK_SIZE
    margin = _tie_margin(pin_radius * pin_radius)
    first, count = candidate_blocks(e, bushing_radius, margin, k0, n, nb)
    skipped = -1
    for b in range(nb):
        lo = b * BLOCK_SIZE
        hi = min(lo + BLOCK_SIZE, n)
        forced = nb <= 3 or hi - lo < 4
        if (not forced and not _is_direction_block(b, b0, nb)
                and (wrap_index(b - first, nb) >= count
                     or _block_lower_bound_sq(e, ux, uy, bushing_radius, cos_phi, sin_phi, block_min, b, n) > margin)):
            kept[b] = False
        else:
            inside = _fill_overlaps(lo, hi, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, work)
            kept[b] = forced or inside > 0
        if not kept[b]:
            skipped = b
    return skipped


@kernel
def _summand(z, before, after, bushing_radius, wear_depth, work):
    """Point z's weight w_z = :func:`cell_overlap` of the overlaps in work[:N_d] of points
    ``before``, z, ``after``, stored in work[N_d + z]; returns w_z (R_j + h_z)."""
    n = wear_depth.shape[0]
    w = cell_overlap(work[before], work[z], work[after])
    work[n + z] = w
    return (bushing_radius + wear_depth[z]) * w


@kernel(inline='always')
def _segment_sums(lo, hi, bushing_radius, wear_depth, work, sums):
    """:func:`_cell_weights` over points lo..hi-1 (1 <= lo, hi <= N_d - 1: no wrapping), carrying its
    four partial sums: each new term goes to the chain the sums' rotation brings up,
    (s1, s2, s3, s0 + x), so four terms in a row add to s0..s3 in place (the unrolled loop: no
    moves, and each addition waits for the one four terms back)."""
    z = np.uint64(lo)
    end = np.uint64(hi)
    one = np.uint64(1)
    while z + np.uint64(4) <= end:
        x0 = _summand(z, z - one, z + one, bushing_radius, wear_depth, work)
        x1 = _summand(z + one, z, z + np.uint64(2), bushing_radius, wear_depth, work)
        x2 = _summand(z + np.uint64(2), z + one, z + np.uint64(3), bushing_radius, wear_depth, work)
        x3 = _summand(z + np.uint64(3), z + np.uint64(2), z + np.uint64(4), bushing_radius, wear_depth, work)
        sums = (sums[0] + x0, sums[1] + x1, sums[2] + x2, sums[3] + x3)
        z += np.uint64(4)
    while z < end:
        x = _summand(z, z - one, z + one, bushing_radius, wear_depth, work)
        sums = (sums[1], sums[2], sums[3], sums[0] + x)
        z += one
    return sums


@kernel
def _cell_weights(first, last, cyclic, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, work):
    """The :func:`cell_overlap` weights of points first..last (first >= -1, last < 2 N_d, at most
    N_d points, wrapping; ``cyclic``: the whole circle) into work[N_d:] from their overlaps in
    work[:N_d], and the run's overlap integral, sum of w_z (R_j + h_z) dphi.  A run that is not cyclic
    first gets the overlaps of the two points on either side computed (their blocks may have been
    skipped).  Four partial sums in a fixed order, which does not depend on the CPU (the native FMU gives the same
    numbers)."""
    n = wear_depth.shape[0]
    if not cyclic:
        for i in (first - 1, first, last, last + 1):
            z = wrap_index(i, n)
            work[z] = overlap(z, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth)
    sums = (0.0, 0.0, 0.0, 0.0)
    i = first
    while i <= last:
        z = wrap_index(i, n)
        if z == 0 or z == n - 1:                     # the points whose neighbours wrap
            x = _summand(z, wrap_index(z - 1, n), wrap_index(z + 1, n), bushing_radius, wear_depth, work)
            sums = (sums[1], sums[2], sums[3], sums[0] + x)
            i += 1
        else:
            end = min(last + 1, i + n - 1 - z)          # up to point n - 2
            sums = _segment_sums(z, z + end - i, bushing_radius, wear_depth, work, sums)
            i = end
    return ((sums[0] + sums[1]) + (sums[2] + sums[3])) * (2.0 * math.pi / n)


@kernel(inline='always')
def relaxation_factor(lam):
    """phi(lambda) = (1 - exp(-lambda)) / lambda [-]: the share of the explicit increment that wearing a
    point whose pressure relaxes as exp(-lambda s / Delta s) removes over the step (docs/reference/model.md §3.11)."""
    if lam < 1e-3:                            # the series: 1 - exp(-lambda) would cancel (libm has no expm1 here)
        return 1.0 - lam * (0.5 - lam * (1.0 / 6.0 - lam / 24.0))
    return (1.0 - math.exp(-lam)) / lam


# the passes of _foundation_pass; np.int64, not literal ints: numba would compile the passes' three levels once per
# mode (four times; 11 s of a cold simulate), where the mode's branches cost 0.8 % of a worn FMU step's instructions
PASS_WEIGHTS, PASS_SHIFT, PASS_APPLY, PASS_COEFFICIENTS = (np.int64(mode) for mode in range(4))
UNSET = -1.0                           # work[N_d + z]: point z's relaxed coefficient is not computed yet (c >= 0)


@kernel(inline='always')
def _coefficient(z, n, rho, scale, relative_dt, slide, rotation, work):
    """Point z's (of N_d = n) relaxed coefficient c_z = Delta s_z phi(scale Delta s_z) (:func:`_relaxed_run`),
    from work[N_d + z] or computed there if UNSET (one exponential per point and step, none for a point never in
    contact)."""
    c = work[n + z]
    if c < 0.0:
        ds = rho * relative_dt if rotation else slide
        c = ds * relaxation_factor(scale * ds)
        work[n + z] = c
    return c


@kernel
def _relaxed_run(mode, first, last, shift, scale, relative_dt, slide, rotation, bushing_radius, wear_depth,
                 work):
    """Over points first..last (first >= -1, last < 2 N_d, at most N_d points, wrapping) with their overlaps
    in work[:N_d], each point's pressure p_z = cell mean of (o + shift)+ times k_eff, relaxed over the step:
    lambda_z = scale Delta s_z (scale = k_w k_eff [1/m]), increment scale c_z cell_overlap(o + shift) with
    c_z = Delta s_z phi(lambda_z) (:func:`_coefficient`).  PASS_COEFFICIENTS (work[N_d:] holds the weights w_z,
    the cell overlaps at shift 0): returns (PASS_SHIFT's two sums at shift 0, the explicit update's volume sum
    rho_z Delta s_z w_z) and leaves in work[N_d:] c_z where the cell is in contact, UNSET elsewhere (they do not
    depend on the shift; the passes compute a missing one when a shift brings its cell into contact);
    PASS_SHIFT: returns (the volume sum rho_z c_z cell_overlap(o + shift), its derivative in shift, 0);
    PASS_APPLY: applies the increments, returns (the largest increment, 0, 0).  Streams the overlaps: each
    point's once."""
    n = wear_depth.shape[0]
    volume = slope = explicit = 0.0
    coefficients = mode == PASS_COEFFICIENTS
    z = wrap_index(first, n)
    before = work[wrap_index(first - 1, n)] if coefficients else work[wrap_index(first - 1, n)] + shift
    at = work[z] if coefficients else work[z] + shift
    for i in range(first, last + 1):
        following = wrap_index(i + 1, n)
        after = work[following] if coefficients else work[following] + shift
        touching = max(before, max(at, after)) > 0.0
        if coefficients:
            rho = bushing_radius + wear_depth[z]
            ds = rho * relative_dt if rotation else slide
            w = work[n + z]
            explicit += rho * ds * w
            work[n + z] = UNSET
            if touching:                              # PASS_SHIFT at shift 0, whose cell overlap is w
                c = _coefficient(z, n, rho, scale, relative_dt, slide, rotation, work)
                g_before, g_at, g_after = cell_overlap_gradient(before, at, after)
                volume += rho * c * w
                slope += rho * c * (g_before + g_at + g_after)
        elif touching:                                # else a cell out of contact: no overlap, gradient, wear
            rho = bushing_radius + wear_depth[z]
            c = _coefficient(z, n, rho, scale, relative_dt, slide, rotation, work)
            mean = cell_overlap(before, at, after)
            if mode == PASS_SHIFT:
                g_before, g_at, g_after = cell_overlap_gradient(before, at, after)
                volume += rho * c * mean
                slope += rho * c * (g_before + g_at + g_after)
            elif mean > 0.0:
                dh = scale * c * mean
                wear_depth[z] = rho + dh - bushing_radius
                volume = max(volume, dh)
        before, at, z = at, after, following
    return volume, slope, explicit


@kernel(inline='always')
def _block_start(b, nb, n):
    """First point of block b, counted on past n for b >= nb (blocks of a second turn)."""
    return n + (b - nb) * BLOCK_SIZE if b >= nb else b * BLOCK_SIZE


@kernel
def _run_pass(mode, first, last, cyclic, shift, scale, relative_dt, slide, rotation, ex, ey, pin_radius,
              bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work):
    """One run of :func:`_foundation_pass`: PASS_WEIGHTS, :func:`_cell_weights` -> (integral, 0, 0, -inf);
    otherwise :func:`_relaxed_run`'s three numbers and the largest overlap at the run's two ends (each end
    point and its outer neighbour; -inf for the whole circle), whose cells a shift above minus that would
    bring into contact."""
    if mode == PASS_WEIGHTS:
        total = _cell_weights(first, last, cyclic, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                              work)
        return total, 0.0, 0.0, -math.inf
    a, b, c = _relaxed_run(mode, first, last, shift, scale, relative_dt, slide, rotation, bushing_radius,
                           wear_depth, work)
    if mode == PASS_APPLY:
        refresh_blocks(wear_depth, block_min, first, last)
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
    second (PASS_APPLY; 0 for PASS_WEIGHTS) or its sum (PASS_SHIFT), and the largest end overlap."""
    n = wear_depth.shape[0]
    nb = block_min.shape[0]
    if skipped < 0:
        # np.int64 / np.bool_: with literal arguments numba would compile _run_pass, _relaxed_run and
        # _cell_weights a second time
        return _run_pass(mode, np.int64(0), n - 1, np.bool_(True), shift, scale, relative_dt, slide, rotation, ex,
                         ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work)
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
            x, y, z, e = _run_pass(mode, first, last, np.bool_(False), shift, scale, relative_dt, slide, rotation, ex,
                                   ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, work)
            first_sum += x
            second = second + y if mode == PASS_SHIFT or mode == PASS_COEFFICIENTS else max(second, y)
            third_sum += z
            edge = max(edge, e)
            start = -1
    return first_sum, second, third_sum, edge


@kernel
def _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi,
                 wear_depth, block_min, kept, skipped, work):
    """The uniform overlap shift a >= 0 [m] (the pin's advance into the groove it wears) at which the relaxed
    increments remove the explicit update's volume, sum rho Delta s phi cell(o + a) = sum rho Delta s w
    (Newton on a convex, increasing function of a, from a = 0 where it is below, to 1e-13 of the volume), and
    the largest end overlap of the runs it was solved on.  Leaves the relaxed coefficients in work[N_d:]
    (PASS_COEFFICIENTS: UNSET where no pass needed one)."""
    volume, slope, explicit, edge = _foundation_pass(PASS_COEFFICIENTS, 0.0, scale, relative_dt, slide, rotation,
                                                     ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi,
                                                     wear_depth, block_min, kept, skipped, work)
    shift = 0.0                               # the coefficients' pass gave the volume and slope at shift 0
    for _ in range(60):
        missing = explicit - volume
        if not slope > 0.0 or abs(missing) <= 1e-13 * explicit:
            break
        step = missing / slope
        shift = max(0.0, shift + step)
        if abs(step) <= 1e-15 * (shift + 1e-30) or abs(missing) <= NEWTON_LAST_STEP * explicit:
            break                             # quadratic convergence: the step just taken leaves ~0.2 missing^2
        volume, slope, _, edge = _foundation_pass(PASS_SHIFT, shift, scale, relative_dt, slide, rotation, ex, ey,
                                                  pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth,
                                                  block_min, kept, skipped, work)
    return shift, edge


@kernel(inline='always')
def archard_volume_fits(k_w, f_n, relative_dt, slide, rotation, bushing_radius, contact_length):
    """False if Archard's volume k_w F_N Delta s of a relative rotation ``relative_dt`` [rad] (points slide at radii
    <= 2 R_j) or a tangential ``slide`` [m] exceeds the whole bushing's, pi R_j^2 L, or is not finite."""
    slide_bound = 2.0 * bushing_radius * relative_dt if rotation else slide
    return k_w * f_n * slide_bound <= math.pi * bushing_radius * bushing_radius * contact_length


@kernel
def _touching_position(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth):
    """The pin centre moved from (ex, ey) outward along its own direction until the first bushing point
    overlaps by TOUCH_OVERLAP_M [m]: the least s >= 0 with |rho_z n_z - (e + s u)|^2 = R_i^2 - 2 R_i TOUCH_OVERLAP_M
    over the points z, u = e / |e|."""
    norm = math.sqrt(ex * ex + ey * ey)
    ux, uy = (ex / norm, ey / norm) if norm > 0.0 else (1.0, 0.0)
    reach_sq = pin_radius * pin_radius - 2.0 * pin_radius * TOUCH_OVERLAP_M
    move = math.inf
    for z in range(wear_depth.shape[0]):
        rho = bushing_radius + wear_depth[z]
        dx = rho * cos_phi[z] - ex
        dy = rho * sin_phi[z] - ey
        along = dx * ux + dy * uy
        discriminant = along * along - (dx * dx + dy * dy) + reach_sq
        if along > 0.0 and discriminant >= 0.0:
            move = min(move, along - math.sqrt(discriminant))
    move = max(move, 0.0)
    return ex + move * ux, ey + move * uy


@kernel
def foundation_wear(k_w, f_n, contact_length, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                    cos_phi, sin_phi, wear_depth, block_min, mask, work):
    """Elastic-foundation (Winkler) placement of the Archard increment, relaxed exactly over the step
    (docs/reference/model.md §3.7, §3.11).

    The pressure on the bushing is proportional to the local overlap of the worn surface with the pin,
    p(phi) = k_eff o+(phi), k_eff = F_N / (L int o+ rho dphi), so it integrates to the normal force over
    the arc in contact.  Wearing a point lowers its pressure at the rate k_eff k_w per unit of sliding, so
    over the step point z's pressure relaxes by exp(-lambda_z), lambda_z = k_eff k_w Delta s_z, while the
    load the pin carries pushes it uniformly deeper by the overlap a: h_z += k_w Delta s_z phi(lambda_z)
    k_eff cell(o + a)+, with a set so that the removed volume stays Archard's, k_w F_N Delta s (for small
    lambda the explicit update h_z += k_w p_z Delta s_z).  Any lambda is stable: a point never wears more
    than its shifted overlap.  Pressures are cell means (:func:`cell_overlap`) of the depths before the
    update.  A pin at (ex, ey) that clears the wall (a batch's load-weighted mean position,
    :func:`wearjoint.core.wear.batch_wear`) is first moved outward along its direction until it touches
    (:func:`_touching_position`).  Scratch: ``mask`` (bool, N_d), whose first nb entries flag the blocks of
    points that may overlap, and ``work`` (float64, 2 N_d), which holds the points' overlaps (work[:N_d]) and weights
    (work[N_d:]).  Returns the largest increment [m], or WEAR_REFUSED with nothing changed if the step's
    Archard volume exceeds the whole bushing's (pi R_j^2 L) or the pin's advance its radius, or either is
    not finite."""
    skipped = _mark_blocks(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask, work)
    total, _, _, _ = _foundation_pass(PASS_WEIGHTS, 0.0, 0.0, relative_dt, slide, rotation, ex, ey,
                                         pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask,
                                         skipped, work)
    if total <= 0.0:
        # the pin clears the worn wall (a batch's load-weighted mean position: the mean of contact points along
        # the concave wall lies inside it): move it outward along its direction until it touches
        ex, ey = _touching_position(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth)
        skipped = _mark_blocks(ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask,
                               work)
        total, _, _, _ = _foundation_pass(PASS_WEIGHTS, 0.0, 0.0, relative_dt, slide, rotation, ex, ey,
                                          pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min,
                                          mask, skipped, work)
        if not total > 0.0:
            return WEAR_REFUSED
    scale = k_w * f_n / (contact_length * total)
    if not archard_volume_fits(k_w, f_n, relative_dt, slide, rotation, bushing_radius, contact_length):
        return WEAR_REFUSED
    shift, edge = _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                               cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
    if edge + shift > 0.0:                    # the shifted contact reaches past a run: the whole circle
        skipped = np.int64(-1)                 # not a literal: the passes compiled once
        _fill_overlaps(np.int64(0), wear_depth.shape[0], ex, ey, pin_radius, bushing_radius, cos_phi, sin_phi,
                       wear_depth, work)
        _foundation_pass(PASS_WEIGHTS, 0.0, 0.0, relative_dt, slide, rotation, ex, ey, pin_radius,
                         bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
        shift, _ = _pin_advance(scale, relative_dt, slide, rotation, ex, ey, pin_radius, bushing_radius,
                                cos_phi, sin_phi, wear_depth, block_min, mask, skipped, work)
    if not shift <= bushing_radius:           # increments are at most the overlap + the shift
        return WEAR_REFUSED
    largest, _, _, _ = _foundation_pass(PASS_APPLY, shift, scale, relative_dt, slide, rotation, ex, ey,
                                        pin_radius, bushing_radius, cos_phi, sin_phi, wear_depth, block_min, mask,
                                        skipped, work)
    return largest
