"""Cycle jumping's wear (docs/reference/model.md §3.11): the loading of a sampled revolution, replayed over the
revolutions a jump stands for through the relaxed wear update, sample by sample.

A sample of the loading is the contact of one accepted point (layout.T_* columns of the time series):
the pin's eccentricity in the bushing frame, its penetration, the normal force, the relative angular
velocity and the tangential velocity, and the time it stands for.  Replaying it on the profile the jump
has worn so far places the pin along the recorded direction where its penetration of that profile is the
recorded one (placing it where it carries the recorded force instead wore 11 % less deep after 1000
revolutions than the reference, docs/explanation/wear_study.md), then wears the profile by
:func:`wearjoint.core.wear.apply_wear` over ``scale`` times the sample's time.  The relaxed update is
stable for any scale: a point never wears more than its overlap with the advancing pin, and Archard's
volume k_w F_N Delta s is kept exactly."""
import math

from .contact import evaluate_contact
from .foundation_wear import WEAR_REFUSED
from .geometry import max_depth
from .jit import kernel
from .layout import (
    P_BUSHING_OFFSET_X, P_BUSHING_OFFSET_Y, P_BUSHING_RADIUS, P_PIN_OFFSET_X, P_PIN_OFFSET_Y, P_PIN_RADIUS,
    R_PENETRATION, R_TANGENTIAL_VELOCITY,
)
from .wear import apply_wear

# columns of a loading row
LOAD_ECC_X, LOAD_ECC_Y, LOAD_PENETRATION, LOAD_NORMAL_FORCE, LOAD_RELATIVE_OMEGA, LOAD_TANGENTIAL_VELOCITY, \
    LOAD_DURATION = range(7)
N_LOAD_COLUMNS = 7
PLACEMENT_ITERATIONS = 30
PLACEMENT_TOLERANCE = 1e-3     # of the recorded penetration
PLACEMENT_BISECTIONS = 60       # the fallback's halvings of a bracket of at most the clearance plus the depth
MIN_PLACEMENT_SLOPE = 0.01     # a measured slope below this keeps the previous one (a step across a contact change)


@kernel
def _place_pin(distance, ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
               result):
    """Evaluate the contact with the pin centre at ``distance`` [m] along (ux, uy) from the bushing centre
    (bushing frame = global here: the bushing body at rest at angle 0, the pin body at angle 0)."""
    pos_j[0] = -jp[P_BUSHING_OFFSET_X]
    pos_j[1] = -jp[P_BUSHING_OFFSET_Y]
    pos_j[2] = 0.0
    pos_i[0] = distance * ux - jp[P_PIN_OFFSET_X]
    pos_i[1] = distance * uy - jp[P_PIN_OFFSET_Y]
    pos_i[2] = 0.0
    evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result)


@kernel
def _place_at_penetration(distance, target, ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi, wear_depth,
                          block_min, memory, result):
    """The pin along (ux, uy), from ``distance`` [m], where its penetration of the profile is ``target`` [m];
    ``result`` the contact there.  Secant steps on the penetration's measured slope in the distance (1 where
    the worn surface is normal to the direction; on the flank of a groove deeper than the clearance it falls
    to a third and less), the first step with slope 1.  Where they do not reach it (the pin short of the bottom
    of a groove deepened since the row was recorded, touching only a shoulder whose gap a move changes by a
    hundredth of it: they fell short and the row wore nothing), bisection between the distances seen below and
    above the target."""
    slope = 1.0
    previous_distance, previous_penetration = distance, 0.0
    below, above = 0.0, math.inf            # distances whose penetration is below / above the target
    for iteration in range(PLACEMENT_ITERATIONS):
        _place_pin(distance, ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                   result)
        penetration = result[R_PENETRATION]
        miss = target - penetration
        if abs(miss) <= PLACEMENT_TOLERANCE * target:
            return
        if miss > 0.0:
            below = max(below, distance)
        else:
            above = min(above, distance)
        if iteration > 0 and distance != previous_distance:
            measured = (penetration - previous_penetration) / (distance - previous_distance)
            if measured > MIN_PLACEMENT_SLOPE:
                slope = min(measured, 1.0)
        previous_distance, previous_penetration = distance, penetration
        distance += miss / slope
    if above == math.inf:                   # past it: the pin's reach beyond the deepest point by the target
        above = jp[P_BUSHING_RADIUS] - jp[P_PIN_RADIUS] + max_depth(wear_depth) + 2.0 * target
    for _ in range(PLACEMENT_BISECTIONS):
        distance = 0.5 * (below + above)
        _place_pin(distance, ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                   result)
        miss = target - result[R_PENETRATION]
        if abs(miss) <= PLACEMENT_TOLERANCE * target:
            return
        if miss > 0.0:
            below = distance
        else:
            above = distance


@kernel
def _row_direction(row, jp, vel_i, vel_j):
    """(ux, uy, |e|) of a loading row, the rotation-only kinematics set; |e| = 0 for a row that does not wear."""
    e = math.hypot(row[LOAD_ECC_X], row[LOAD_ECC_Y])
    if not (row[LOAD_PENETRATION] > 0.0 and row[LOAD_NORMAL_FORCE] > 0.0 and e > 0.0 and row[LOAD_DURATION] > 0.0):
        return 0.0, 0.0, 0.0
    omega = row[LOAD_RELATIVE_OMEGA]
    vel_i[0] = omega * jp[P_PIN_OFFSET_Y]           # the pin body turns about the pin centre (at angle 0): the
    vel_i[1] = -omega * jp[P_PIN_OFFSET_X]          # centre at rest, no penetration rate, the force elastic
    vel_i[2] = omega
    vel_j[0] = vel_j[1] = vel_j[2] = 0.0
    return row[LOAD_ECC_X] / e, row[LOAD_ECC_Y] / e, e


@kernel
def replay_wear(loading, scale, passes, jp, cos_phi, sin_phi, wear_depth, block_min, memory, mask, work, result,
                pos_i, vel_i, pos_j, vel_j):
    """Wear ``wear_depth`` by the loading rows (columns LOAD_*) replayed in order ``passes`` times, each row
    over ``scale`` / ``passes`` times its duration [s], its pin at its recorded penetration of the profile
    worn so far, its wear with its recorded normal force.  Scratch: ``memory`` (N_MEMORY), ``mask``/``work``
    (as :func:`apply_wear`), ``result`` (N_RESULT), the four kinematics (3 each).  Returns the largest
    increment of one row [m], or WEAR_REFUSED (the profile then holds the rows before the refused one)."""
    largest = 0.0
    for _ in range(passes):
        for r in range(loading.shape[0]):
            row = loading[r]
            ux, uy, e = _row_direction(row, jp, vel_i, vel_j)
            if e == 0.0:
                continue
            _place_at_penetration(e, row[LOAD_PENETRATION], ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi,
                                  wear_depth, block_min, memory, result)
            result[R_TANGENTIAL_VELOCITY] = row[LOAD_TANGENTIAL_VELOCITY]
            dh, _ = apply_wear(result, row[LOAD_NORMAL_FORCE], vel_i, vel_j, row[LOAD_DURATION] * scale / passes, jp,
                               cos_phi, sin_phi, wear_depth, block_min, mask, work)
            if dh < 0.0:
                return WEAR_REFUSED
            largest = max(largest, dh)
    return largest
