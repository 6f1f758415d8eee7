"""Cycle jumping's wear (docs/model.md §3.12): the loading of a sampled revolution, replayed over the
revolutions a jump stands for through the relaxed wear update, sample by sample.

A sample of the loading is the contact of one accepted point (layout.T_* columns of the time series):
the pin's eccentricity in the bushing frame, its penetration, the normal force, the relative angular
velocity and the tangential velocity, and the time it stands for.  Replaying it on the profile the jump
has worn so far places the pin along the recorded direction where its penetration of that profile is the
recorded one (so it still carries the recorded force), then wears the profile by
:func:`wearjoint.core.wear.apply_wear` over ``scale`` times the sample's time.  The relaxed update is
stable for any scale: a point never wears more than its overlap with the advancing pin, and Archard's
volume k_w F_N Delta s is kept exactly."""
import math

from .contact import evaluate_contact
from .foundation_wear import WEAR_REFUSED
from .jit import kernel
from .layout import (
    P_BUSHING_OFFSET_X, P_BUSHING_OFFSET_Y, P_PIN_OFFSET_X, P_PIN_OFFSET_Y, R_PENETRATION, R_TANGENTIAL_VELOCITY,
)
from .wear import apply_wear

# columns of a loading row
LOAD_ECC_X, LOAD_ECC_Y, LOAD_PENETRATION, LOAD_NORMAL_FORCE, LOAD_RELATIVE_OMEGA, LOAD_TANGENTIAL_VELOCITY, \
    LOAD_DURATION = range(7)
N_LOAD_COLUMNS = 7
PLACEMENT_ITERATIONS = 8
PLACEMENT_TOLERANCE = 1e-3     # of the recorded penetration


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
def replay_wear(loading, scale, jp, cos_phi, sin_phi, wear_depth, block_min, memory, mask, work, result, pos_i,
                vel_i, pos_j, vel_j):
    """Wear ``wear_depth`` by the loading rows (columns LOAD_*) replayed in order, each over ``scale`` times
    its duration [s].  Scratch: ``memory`` (N_MEMORY), ``mask``/``work`` (as :func:`apply_wear`), ``result``
    (N_RESULT), the four kinematics (3 each).  Returns the largest increment of one row [m], or
    WEAR_REFUSED (the profile then holds the rows before the refused one)."""
    largest = 0.0
    for r in range(loading.shape[0]):
        row = loading[r]
        target = row[LOAD_PENETRATION]
        f_n = row[LOAD_NORMAL_FORCE]
        e = math.hypot(row[LOAD_ECC_X], row[LOAD_ECC_Y])
        if not (target > 0.0 and f_n > 0.0 and e > 0.0 and row[LOAD_DURATION] > 0.0):
            continue
        ux, uy = row[LOAD_ECC_X] / e, row[LOAD_ECC_Y] / e
        vel_i[0] = vel_i[1] = vel_j[0] = vel_j[1] = vel_j[2] = 0.0
        vel_i[2] = row[LOAD_RELATIVE_OMEGA]
        distance = e
        for _ in range(PLACEMENT_ITERATIONS):       # penetration ~ distance - the local clearance: slope 1
            _place_pin(distance, ux, uy, vel_i, vel_j, pos_i, pos_j, jp, cos_phi, sin_phi, wear_depth, block_min,
                       memory, result)
            miss = target - result[R_PENETRATION]
            if abs(miss) <= PLACEMENT_TOLERANCE * target:
                break
            distance += miss
        result[R_TANGENTIAL_VELOCITY] = row[LOAD_TANGENTIAL_VELOCITY]
        dh, _ = apply_wear(result, f_n, vel_i, vel_j, row[LOAD_DURATION] * scale, jp, cos_phi, sin_phi, wear_depth,
                           block_min, mask, work)
        if dh < 0.0:
            return WEAR_REFUSED
        largest = max(largest, dh)
    return largest
