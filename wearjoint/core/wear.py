"""Wear kernels of the clearance joint (paper Sec. 5, Eqs. 24-35).

Archard's law removes the volume k_w F_N ds (Eq. 24); the depth update of
Eq. (28) is h_z += k_w p Delta s_z.  Where the increment goes (docs/reference/model.md §3.7):

* ``foundation`` (default): the pressure follows the local overlap of the worn
  surface with the pin (an elastic, Winkler foundation), integrated over each
  point's arc cell, normalised to the step's mean normal force and relaxed
  exactly over the step (:mod:`.foundation_wear`, docs/reference/model.md §3.11).
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


from .admissibility import is_admissible
from .contact import evaluate_contact, update_contact_memory
from .damping import damping_coefficient
from .foundation_wear import WEAR_REFUSED, archard_volume_fits, foundation_wear
from .geometry import block_minimum_depth, distance_sq, penetrating_points, refresh_blocks, wrap_index
from .jit import kernel
from .pressure import foundation_modulus_factor
from .layout import (
    PLACEMENT_FOUNDATION, PLACEMENT_PATCH, RHO_CONFORMAL, SLIDING_ROTATION, M_BATCH_ANGLE, M_BATCH_MOMENT_X,
    M_BATCH_MOMENT_Y, M_BATCH_INDEX, M_BATCH_LOAD, M_BATCH_SLIDE,
    M_BATCH_TIME, M_START_FORCE, MAX_WEAR_STEP_S, N_RESULT, NO_START_FORCE, P_ARCHARD_COEFFICIENT, P_BUSHING_POISSON_RATIO,
    P_BUSHING_RADIUS, P_BUSHING_YOUNGS_MODULUS, P_CONTACT_LENGTH, P_DAMPING_COEFFICIENT, P_EFFECTIVE_MODULUS,
    P_FOUNDATION_MODULUS, P_PIN_POISSON_RATIO, P_PIN_RADIUS, P_PIN_YOUNGS_MODULUS, P_RHO_MODE, P_SLIDING, P_STIFFNESS,
    P_WEAR_COEFFICIENT, P_WEAR_FACTOR, P_WEAR_INTERVAL, P_WEAR_PLACEMENT, R_CONTACT, R_CONTACT_INDEX, R_ECCENTRICITY_X,
    R_ECCENTRICITY_Y, R_NORMAL_FORCE, R_PENETRATION, R_TANGENTIAL_VELOCITY, WEAR_BATCH_SHARE, WEAR_STEP_SHARE,
    WEAR_STEP_SHARE_EXPLICIT,
)


# accept_contact / advance_joint; STEP_OVERSHOT: changed, by a wearing step over the wear-step limit;
# STEP_INADMISSIBLE: refused, nothing changed: the state is deeper in the wall than any contact (core.admissibility)
STEP_INADMISSIBLE, STEP_REFUSED, STEP_UNCHANGED, STEP_CHANGED, STEP_OVERSHOT = -2, -1, 0, 1, 2


@kernel
def effective_modulus(pin_youngs_modulus, pin_poisson_ratio, bushing_youngs_modulus, bushing_poisson_ratio):
    """Composite modulus E* of Eq. (32) [Pa]: 1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j (standard Hertz
    form; the paper pairs the indices the other way, docs/reference/model.md §3)."""
    return 1.0 / ((1.0 - pin_poisson_ratio * pin_poisson_ratio) / pin_youngs_modulus
                  + (1.0 - bushing_poisson_ratio * bushing_poisson_ratio) / bushing_youngs_modulus)


@kernel
def materials_contact_stiffness(pin_radius, bushing_radius, effective_modulus_Pa):
    """Contact stiffness K [N/m^1.5] of a pin inside a bushing, Eqs. (16)-(17) with the internal-contact
    radius R_i R_j / (R_j - R_i): K = 4/(3 pi (h_i + h_j)) sqrt(R), h_k = (1 - nu_k^2)/(pi E_k), i.e.
    4 E* sqrt(R) / 3 (docs/reference/model.md §3.1)."""
    return 4.0 / 3.0 * effective_modulus_Pa * math.sqrt(pin_radius * bushing_radius / (bushing_radius - pin_radius))


@kernel
def complete_joint_parameters(jp):
    """Fill the derived slots of the joint parameter vector from the given ones: E* (Eq. 32), the
    contact stiffness where it is given as 0 (from the radii and materials, Eqs. 16-17), the wear
    coefficient the updates use (k_w times the wear acceleration factor), the elastic foundation's
    k_f L / R_i (:func:`core.pressure.foundation_modulus_factor`: three square roots the contact would
    otherwise take at every evaluation) and the damping law's coefficient (:func:`core.damping.damping_coefficient`:
    solved once from the restitution)."""
    jp[P_EFFECTIVE_MODULUS] = effective_modulus(jp[P_PIN_YOUNGS_MODULUS], jp[P_PIN_POISSON_RATIO],
                                                jp[P_BUSHING_YOUNGS_MODULUS], jp[P_BUSHING_POISSON_RATIO])
    if jp[P_STIFFNESS] == 0.0:
        jp[P_STIFFNESS] = materials_contact_stiffness(jp[P_PIN_RADIUS], jp[P_BUSHING_RADIUS], jp[P_EFFECTIVE_MODULUS])
    jp[P_WEAR_COEFFICIENT] = jp[P_ARCHARD_COEFFICIENT] * jp[P_WEAR_FACTOR]
    jp[P_FOUNDATION_MODULUS] = foundation_modulus_factor(jp[P_STIFFNESS], jp[P_PIN_RADIUS], jp[P_BUSHING_RADIUS])
    jp[P_DAMPING_COEFFICIENT] = damping_coefficient(jp)


@kernel
def equivalent_radius(pin_radius, worn_bushing_radius, rho_mode):
    """rho* of Eq. (31) [m]: RHO_CONFORMAL R_i R~/(R~ - R_i) (default), RHO_PAPER R_i R~/(R_i + R~)."""
    if rho_mode == RHO_CONFORMAL:
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


@kernel(inline='always')
def wears(result, f_n, jp, dt):
    """True if an accepted step of dt [s] ending at the contact ``result`` with the mean normal force f_n
    [N] wears the bushing (the increments of :func:`apply_wear` may still round to 0): in contact,
    f_n > 0, k_w > 0, dt > 0."""
    return not (result[R_CONTACT] < 0.5 or jp[P_WEAR_COEFFICIENT] <= 0.0 or dt <= 0.0 or f_n <= 0.0)


@kernel(inline='always')
def step_mean_normal_force(result, memory, held, force_rate, dt):
    """The normal force [N] the wear of an accepted step of dt [s] ending at the contact ``result`` takes: where
    the host applied that force over the step, ``held`` (a co-simulation step, the kinematics held; an implicit
    solver's, its equilibrium at the step's end: wearjoint.exudyn), the contact's own, or with ``force_rate``
    [N/s] (a co-simulation host that applies the loads linearised at the step's start) the mean of that force
    changing at that rate (:func:`_linear_mean`); before the first accepted point the contact's own; else the
    trapezoid of the step's start (memory[M_START_FORCE], the last accepted point on its worn profile) and its
    end, the mean force the host's integrator applied over a step that began just after a wear update
    (docs/reference/model.md §3.11)."""
    if held:
        return _linear_mean(result[R_NORMAL_FORCE], force_rate * dt)
    start = memory[M_START_FORCE]
    if start < 0.0:
        return result[R_NORMAL_FORCE]
    return 0.5 * (start + result[R_NORMAL_FORCE])


@kernel(inline='always')
def _linear_mean(f0, change):
    """The mean over a step of the normal force max(0, f0 + change s), s from 0 to 1 [N]: f0 + change / 2, or where it
    reaches 0 within the step (the linearised contact ends there) f0^2 / (2 |change|); f0 itself for no change or no
    force."""
    if f0 <= 0.0 or change == 0.0:
        return f0
    if change >= -f0:
        return f0 + 0.5 * change
    return f0 * f0 / (-2.0 * change)


@kernel
def normal_force_rate(jacobian, vel_i, vel_j):
    """dF_n/dt [N/s] of the normal force linearised in the kinematic inputs (``jacobian``: N_RESULT x 12, d
    result[r] / d input[m], inputs x, y, theta, vx, vy, omega of body i, then j) along the inputs' velocities,
    the bodies' accelerations left out (the inputs do not hold them)."""
    rate = 0.0
    for m in range(3):
        rate += jacobian[R_NORMAL_FORCE, m] * vel_i[m] + jacobian[R_NORMAL_FORCE, 6 + m] * vel_j[m]
    return rate


@kernel(inline='always')
def _relaxation(k, angle, slide, jp, wear_depth):
    """lambda = k_f k_w Delta s at the deepest point k of a step or batch relative rotation ``angle`` [rad] and
    tangential ``slide`` [m] (docs/reference/model.md §7)."""
    k_f = jp[P_FOUNDATION_MODULUS] * jp[P_PIN_RADIUS] / jp[P_CONTACT_LENGTH]     # the slot holds k_f L / R_i
    rotation = int(jp[P_SLIDING]) == SLIDING_ROTATION
    return k_f * jp[P_WEAR_COEFFICIENT] * ((jp[P_BUSHING_RADIUS] + wear_depth[k]) * angle if rotation else slide)


@kernel
def _foundation_increment(k, ex, ey, f_n, angle, slide, jp, cos_phi, sin_phi, wear_depth, block_min, mask, work):
    """The foundation's relaxed update (:func:`foundation_wear`) of a pin at eccentricity (ex, ey) with deepest
    point k, mean normal force f_n [N], relative rotation ``angle`` [rad] and tangential ``slide`` [m]; returns
    (the largest increment or WEAR_REFUSED, lambda over WEAR_STEP_SHARE)."""
    share = _relaxation(k, angle, slide, jp, wear_depth) / WEAR_STEP_SHARE       # on the profile before the update
    largest = foundation_wear(jp[P_WEAR_COEFFICIENT], f_n, jp[P_CONTACT_LENGTH], angle, slide,
                              int(jp[P_SLIDING]) == SLIDING_ROTATION,
                              ex, ey, jp[P_PIN_RADIUS], jp[P_BUSHING_RADIUS], cos_phi, sin_phi, wear_depth,
                              block_min, mask, work)
    return largest, share


@kernel
def apply_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min, mask, work):
    """Archard update of the wear profile over an accepted step of length dt, Eqs. (28)-(33).

    ``result`` is the contact evaluation at the accepted state, ``f_n`` the step's mean normal force
    [N] (:func:`step_mean_normal_force`).  Sliding
    distance: ``rotation`` (R_j + h_z)|d alpha| with alpha the relative angle
    of the two bodies, Eq. (33), taken as |omega_i - omega_j| dt; or
    ``tangential`` |v_T| dt at the contact.  Returns (the largest depth increment [m], the step's share
    of the wear-step limit: the largest lambda over WEAR_STEP_SHARE for the relaxed ``foundation``
    update (lambda = k_f k_w Delta s at the contact, docs/reference/model.md §7), the largest increment over
    WEAR_STEP_SHARE_EXPLICIT times the penetration for the explicit
    ``patch`` and ``penetration``), or (WEAR_REFUSED, 0) with nothing changed where a step would wear a
    point by more than the bushing radius or by a non-finite depth (a step no physical host takes:
    h = 1e300 s, say).
    """
    if not wears(result, f_n, jp, dt):
        return 0.0, 0.0
    k = int(result[R_CONTACT_INDEX])
    relative_rate = abs(vel_i[2] - vel_j[2])
    tangential_slide = abs(result[R_TANGENTIAL_VELOCITY]) * dt
    placement = int(jp[P_WEAR_PLACEMENT])
    if placement == PLACEMENT_FOUNDATION:
        return _foundation_increment(k, result[R_ECCENTRICITY_X], result[R_ECCENTRICITY_Y], f_n, relative_rate * dt,
                                     tangential_slide, jp, cos_phi, sin_phi, wear_depth, block_min, mask, work)
    k_w = jp[P_WEAR_COEFFICIENT]
    n = wear_depth.shape[0]
    dphi = 2.0 * math.pi / n
    pin_radius = jp[P_PIN_RADIUS]
    bushing_radius = jp[P_BUSHING_RADIUS]
    worn_radius = bushing_radius + wear_depth[k]
    rho = equivalent_radius(pin_radius, worn_radius, int(jp[P_RHO_MODE]))
    half_width = hertz_half_width(f_n, rho, jp[P_CONTACT_LENGTH], jp[P_EFFECTIVE_MODULUS])
    pressure = f_n / (2.0 * half_width * jp[P_CONTACT_LENGTH])          # Eqs. (25), (29)
    rotation = int(jp[P_SLIDING]) == SLIDING_ROTATION
    largest = 0.0
    # a bound on the increments below (patch weights <= 4/pi, depths <= R_j): refuse an absurd step
    slide_bound = 2.0 * worn_radius * relative_rate * dt if rotation else tangential_slide
    if not k_w * pressure * (4.0 / math.pi) * slide_bound <= bushing_radius:
        return WEAR_REFUSED, 0.0
    if placement == PLACEMENT_PATCH:
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
        refresh_blocks(wear_depth, block_min, k - m, k + m)
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
def _flush_batch(jp, cos_phi, sin_phi, wear_depth, block_min, mask, work, memory):
    """Apply the wear batch in ``memory`` (M_BATCH_*) at its load-weighted mean eccentricity with its
    load-weighted mean normal force and summed sliding, then empty it; returns :func:`_foundation_increment`'s
    (largest, share), or (WEAR_REFUSED, 0) with nothing changed, the batch kept."""
    angle, slide, load = memory[M_BATCH_ANGLE], memory[M_BATCH_SLIDE], memory[M_BATCH_LOAD]
    measure = angle if int(jp[P_SLIDING]) == SLIDING_ROTATION else slide
    largest, share = 0.0, 0.0
    if load > 0.0 and measure > 0.0:
        largest, share = _foundation_increment(int(memory[M_BATCH_INDEX]), memory[M_BATCH_MOMENT_X] / load,
                                               memory[M_BATCH_MOMENT_Y] / load, load / measure, angle, slide, jp,
                                               cos_phi, sin_phi, wear_depth, block_min, mask, work)
        if largest < 0.0:
            return largest, share
    for m in range(M_BATCH_TIME, M_BATCH_INDEX + 1):
        memory[m] = 0.0
    return largest, share


@kernel
def batch_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min, mask, work, memory):
    """The foundation's wear of an accepted step, gathered into batches of contact time jp[P_WEAR_INTERVAL]
    (docs/reference/model.md §3.11): the step's time, sliding and load (F_N times the sliding) join the batch in
    ``memory``, which is applied (:func:`_flush_batch`) when it reaches the interval or the largest lambda
    WEAR_BATCH_SHARE, before it would pass either, and when the contact ends.  The removed volume is Archard's,
    k_w sum F_N Delta s, as step by step; the relaxed update takes the batch at the pin's load-weighted mean
    position.  Returns (the largest increment, share) as :func:`apply_wear`, or (WEAR_REFUSED, 0)
    with nothing changed if the step alone would wear absurdly."""
    wearing = wears(result, f_n, jp, dt)
    angle = abs(vel_i[2] - vel_j[2]) * dt
    slide = abs(result[R_TANGENTIAL_VELOCITY]) * dt
    if wearing and not archard_volume_fits(jp[P_WEAR_COEFFICIENT], f_n, angle, slide,
                                           int(jp[P_SLIDING]) == SLIDING_ROTATION,
                                           jp[P_BUSHING_RADIUS], jp[P_CONTACT_LENGTH]):
        return WEAR_REFUSED, 0.0
    interval = jp[P_WEAR_INTERVAL]
    k = int(result[R_CONTACT_INDEX])
    largest, share = 0.0, 0.0
    if memory[M_BATCH_TIME] > 0.0 and (
            not wearing or memory[M_BATCH_TIME] + dt > interval * (1.0 + 1e-9)
            or _relaxation(int(memory[M_BATCH_INDEX]), memory[M_BATCH_ANGLE] + angle, memory[M_BATCH_SLIDE] + slide,
                           jp, wear_depth) > WEAR_BATCH_SHARE):
        largest, share = _flush_batch(jp, cos_phi, sin_phi, wear_depth, block_min, mask, work, memory)
        if largest < 0.0:
            return largest, share
    if not wearing:
        return largest, share
    memory[M_BATCH_TIME] += dt
    memory[M_BATCH_ANGLE] += angle
    memory[M_BATCH_SLIDE] += slide
    load = f_n * (angle if int(jp[P_SLIDING]) == SLIDING_ROTATION else slide)
    memory[M_BATCH_LOAD] += load
    memory[M_BATCH_MOMENT_X] += load * result[R_ECCENTRICITY_X]
    memory[M_BATCH_MOMENT_Y] += load * result[R_ECCENTRICITY_Y]
    memory[M_BATCH_INDEX] = k
    if (memory[M_BATCH_TIME] >= interval * (1.0 - 1e-9)
            or _relaxation(k, memory[M_BATCH_ANGLE], memory[M_BATCH_SLIDE], jp, wear_depth) >= WEAR_BATCH_SHARE):
        applied, applied_share = _flush_batch(jp, cos_phi, sin_phi, wear_depth, block_min, mask, work, memory)
        if applied < 0.0:
            return applied, applied_share
        largest, share = max(largest, applied), max(share, applied_share)
    return largest, share


@kernel(inline='always')
def _accept(result, pos_i, vel_i, pos_j, vel_j, dt, held, force_rate, jp, cos_phi, sin_phi, wear_depth, block_min,
            memory, mask, work, after):
    """:func:`accept_contact` with the contact after the wear evaluated into ``after`` (N_RESULT values; may be
    ``result`` itself); returns (its STEP_* code, True if ``after`` was evaluated)."""
    # the first accepted point is exempt: a master's first step may come before its inputs were connected
    # (fmpy's SSP simulator steps the joint once on their start values; the FMU warns of that pin outside the bushing);
    # inadmissible, it wears nothing and starts no contact: the next step starts from no force
    if not is_admissible(result, jp, wear_depth):
        if memory[M_START_FORCE] != NO_START_FORCE:
            return STEP_INADMISSIBLE, False
        memory[M_START_FORCE] = 0.0
        return STEP_UNCHANGED, False
    f_n = step_mean_normal_force(result, memory, held, force_rate, dt)
    if int(jp[P_WEAR_PLACEMENT]) == PLACEMENT_FOUNDATION and jp[P_WEAR_INTERVAL] > 0.0:
        largest, share = batch_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min,
                                    mask, work, memory)
    else:
        largest, share = apply_wear(result, f_n, vel_i, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min,
                                    mask, work)
    if largest < 0.0:
        return STEP_REFUSED, False
    changed = update_contact_memory(result, jp, memory)
    evaluated = largest > 0.0 and not held
    if evaluated:
        for r in range(N_RESULT):                # the search starts from the contact before the wear
            after[r] = result[r]
        evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, after)
        memory[M_START_FORCE] = after[R_NORMAL_FORCE]
    else:
        memory[M_START_FORCE] = result[R_NORMAL_FORCE]
    if largest > 0.0 and (dt > MAX_WEAR_STEP_S * (1.0 + 1e-9) or share > 1.0):
        return STEP_OVERSHOT, evaluated
    return (STEP_CHANGED if largest > 0.0 or changed else STEP_UNCHANGED), evaluated


@kernel
def accept_contact(result, pos_i, vel_i, pos_j, vel_j, dt, held, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                   mask, work):
    """Archard update over dt with the step's mean normal force (:func:`step_mean_normal_force`) and the
    contact-onset bookkeeping for ``result``, the contact evaluated at the accepted state (pos, vel) on the
    profile the step began with (left as it is).  The foundation's wear goes in batches (:func:`batch_wear`)
    where jp[P_WEAR_INTERVAL] > 0.  memory[M_START_FORCE] becomes the normal force there on the new profile,
    evaluated in ``work`` after the wear (not ``held``: a held step's wear takes its own end force).  Returns
    STEP_CHANGED if the joint's forces changed, STEP_OVERSHOT if they did by a step over the wear-step limit
    (longer than MAX_WEAR_STEP_S, or past its share of the wear, :func:`apply_wear`; docs/reference/model.md §7),
    STEP_UNCHANGED, STEP_REFUSED (nothing changed: the wear would be absurd, :func:`apply_wear`) or
    STEP_INADMISSIBLE (nothing changed: the pin is deeper in the wall than any contact, core.admissibility)."""
    return _accept(result, pos_i, vel_i, pos_j, vel_j, dt, held, 0.0, jp, cos_phi, sin_phi, wear_depth, block_min,
                   memory, mask, work, work[:N_RESULT])[0]


@kernel
def accept_linearised_contact(result, jacobian, pos_i, vel_i, pos_j, vel_j, dt, jp, cos_phi, sin_phi, wear_depth,
                              block_min, memory, mask, work):
    """:func:`accept_contact` of a held step whose host applies the loads linearised at its start, F0 + J (u - u0)
    (a linearising co-simulation master; ``jacobian``: J at these kinematics, N_RESULT x 12): the wear takes the
    mean normal force of that linearisation along the inputs' velocities (:func:`normal_force_rate`), not the
    force at the step's start (with it, the linearised coupling wore the paper's groove 3.6 % short at wear
    factor 100: docs/explanation/numerics.md)."""
    return _accept(result, pos_i, vel_i, pos_j, vel_j, dt, True, normal_force_rate(jacobian, vel_i, vel_j), jp,
                   cos_phi, sin_phi, wear_depth, block_min, memory, mask, work, work[:N_RESULT])[0]


@kernel
def accept_contact_refreshing(result, pos_i, vel_i, pos_j, vel_j, dt, jp, cos_phi, sin_phi, wear_depth, block_min,
                              memory, mask, work):
    """:func:`accept_contact` of a step whose kinematics end it (not held) that leaves in ``result`` the contact
    on the new profile where the step wore (the evaluation the next step starts from, made once); returns (the
    STEP_* code, True if ``result`` is that evaluation)."""
    return _accept(result, pos_i, vel_i, pos_j, vel_j, dt, False, 0.0, jp, cos_phi, sin_phi, wear_depth, block_min,
                   memory, mask, work, result)


@kernel
def advance_joint(pos_i, vel_i, pos_j, vel_j, dt, held, jp, cos_phi, sin_phi, wear_depth, block_min, memory, mask,
                  work, result):
    """Accept the state (pos, vel) as the end of a step of length dt (``held``: the step's end force applied over
    it, :func:`step_mean_normal_force`): evaluate the contact there (into ``result``), then :func:`accept_contact`; returns its
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
