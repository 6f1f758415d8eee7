"""Admissible states (core.admissibility, docs/reference/model.md §3.14): the pin's overlap with the worn bushing wall along
its eccentricity, the bound (2 % of the pin radius), and an accepted step at an inadmissible state refused with
nothing changed (core.wear.STEP_INADMISSIBLE), but the joint's first."""
import math

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters
from wearjoint.core import layout as L
from wearjoint.core.admissibility import is_admissible, wall_overlap
from wearjoint.core.wear import STEP_INADMISSIBLE

JOINT = JointParameters(pin_radius_m=0.01, bushing_radius_m=0.0101, wear_factor=1000.0)


def _at(joint, eccentricity_m, angle):
    """A result array with the pin centre at ``eccentricity_m`` from the bushing centre along ``angle`` [rad]."""
    result = np.zeros(L.N_RESULT)
    result[L.R_ECCENTRICITY_X] = eccentricity_m * math.cos(angle)
    result[L.R_ECCENTRICITY_Y] = eccentricity_m * math.sin(angle)
    return result


def test_the_overlap_is_the_eccentricity_past_clearance_and_the_local_wear_depth():
    joint = ClearanceJoint(JOINT)
    k = 300                                                       # a point worn 50 um deep
    joint.wear_depth[k] = 5e-5
    angle = (k + 1) * 2.0 * math.pi / JOINT.n_points
    jp = joint.parameter_vector
    assert wall_overlap(_at(JOINT, 3e-4, angle), jp, joint.wear_depth) == pytest.approx(3e-4 - 1e-4 - 5e-5)
    assert wall_overlap(_at(JOINT, 3e-4, angle + math.pi), jp, joint.wear_depth) == pytest.approx(2e-4)
    bound = JOINT.admissible_penetration_m
    assert bound == pytest.approx(2e-4)
    # in the worn groove the pin may sit deeper than elsewhere; past the bound, and not finite, it may not
    assert is_admissible(_at(JOINT, 1e-4 + 5e-5 + 0.99 * bound, angle), jp, joint.wear_depth)
    assert not is_admissible(_at(JOINT, 1e-4 + 5e-5 + 1.01 * bound, angle), jp, joint.wear_depth)
    assert not is_admissible(_at(JOINT, 1e-4 + 1.01 * bound, angle + math.pi), jp, joint.wear_depth)
    assert not is_admissible(_at(JOINT, 14.0, 0.3), jp, joint.wear_depth)             # a pin 14 m away
    assert not is_admissible(_at(JOINT, math.nan, 0.3), jp, joint.wear_depth)


def _kinematics(eccentricity_m):
    """Pin and bushing bodies at rest, the pin centre ``eccentricity_m`` from the bushing centre along x."""
    return (np.array([eccentricity_m, 0.0, 0.0]), np.array([0.0, 0.0, 3.0]), np.zeros(3), np.zeros(3))


def test_an_inadmissible_step_changes_nothing_but_the_first_is_exempt():
    """The first accepted point is taken (a master may step the joint once before it connected the inputs), but
    an inadmissible one wears nothing and starts no contact (its sliding and force are not the mechanism's); at a
    later one deeper than the bound the step is refused and the profile, the contact memory and the volume stay."""
    joint = ClearanceJoint(JOINT)                                 # wear factor 1000: the sliding below would wear
    deep = JOINT.clearance_m + 2.0 * JOINT.admissible_penetration_m
    assert joint.advance_array(*_kinematics(deep), 1e-5) != STEP_INADMISSIBLE       # the first point
    assert joint.worn_volume_m3 == 0.0 and not joint.wear_depth.any()
    assert joint.memory[L.M_ACTIVE] == 0.0 and joint.memory[L.M_START_FORCE] == 0.0
    assert not joint.memory[L.M_BATCH_TIME:L.M_BATCH_INDEX + 1].any()             # no wear gathered either
    before = joint.wear_depth.copy(), joint.memory.copy(), joint.worn_volume_m3
    assert joint.advance_array(*_kinematics(deep), 1e-5) == STEP_INADMISSIBLE
    assert np.array_equal(joint.wear_depth, before[0]) and np.array_equal(joint.memory, before[1])
    assert joint.worn_volume_m3 == before[2]
    assert joint.advance_array(*_kinematics(JOINT.clearance_m + 1e-6), 1e-5) >= 0   # an admissible one goes on
    worn = ClearanceJoint(JOINT)
    worn.advance_array(*_kinematics(JOINT.clearance_m), 1e-5)
    worn.advance_array(*_kinematics(JOINT.clearance_m + 1e-6), 1e-5)                 # wears at wear factor 1000
    depth = worn.wear_depth.copy()
    assert depth.max() > 0.0
    assert worn.advance_array(*_kinematics(deep + depth.max()), 1e-5) == STEP_INADMISSIBLE
    assert np.array_equal(worn.wear_depth, depth)


def test_a_force_past_what_the_materials_carry_is_inadmissible_at_any_eccentricity():
    """The admissible force is the Hertz law's at the admissible penetration, K delta_adm^1.5: 225 kN for the
    paper's joint (K 7.951e10 N/m^1.5, delta_adm 0.2 mm); a blown-up coupling's damping force past it is refused
    even with the pin still near the wall."""
    paper = JointParameters()
    assert paper.admissible_force_N == pytest.approx(7.951e10 * 2e-4 ** 1.5, rel=1e-3)
    joint = ClearanceJoint(paper)
    result = _at(paper, paper.clearance_m + 1e-5, 0.4)
    result[L.R_NORMAL_FORCE] = 0.99 * paper.admissible_force_N
    assert is_admissible(result, joint.parameter_vector, joint.wear_depth)
    result[L.R_NORMAL_FORCE] = 1.01 * paper.admissible_force_N
    assert not is_admissible(result, joint.parameter_vector, joint.wear_depth)
    result[L.R_NORMAL_FORCE] = math.nan
    assert not is_admissible(result, joint.parameter_vector, joint.wear_depth)


def test_a_pin_in_a_groove_worn_past_the_bushing_radius_is_inadmissible():
    """A bushing worn deeper than its radius R_j (the deepest wear a state holds: no profile past it can be set or
    restored) has worn through: the pin sitting in that groove, touching its bottom, is refused; at R_j it is not."""
    joint = ClearanceJoint(JOINT)
    k = 300
    angle = (k + 1) * 2.0 * math.pi / JOINT.n_points
    jp = joint.parameter_vector
    for depth, admitted in ((JOINT.bushing_radius_m, True), (1.0001 * JOINT.bushing_radius_m, False)):
        joint.wear_depth[k] = depth
        touching = _at(JOINT, JOINT.clearance_m + depth, angle)                  # overlap 0 at the groove's bottom
        assert wall_overlap(touching, jp, joint.wear_depth) == pytest.approx(0.0, abs=1e-15)
        assert is_admissible(touching, jp, joint.wear_depth) == admitted, depth


def test_a_step_from_a_bushing_worn_through_is_refused_naming_it():
    """The joint's API refuses the step after the one that wore the bushing past its radius, with nothing changed."""
    from wearjoint.parameters import ParameterError

    joint = ClearanceJoint(JOINT)
    joint.advance_array(*_kinematics(JOINT.clearance_m), 1e-5)                       # the first point: exempt
    joint.wear_depth[-1] = 1.001 * JOINT.bushing_radius_m                             # at 0 rad (point N_d)
    depth = joint.wear_depth.copy()
    pin = [JOINT.clearance_m + depth[-1], 0.0, 0.0, 0.0, 0.0, 3.0]                 # touching the groove's bottom
    with pytest.raises(ParameterError, match=r"^the bushing wore through before this step: max depth 0.0101101 m, "
                                             r"its radius 0.0101 m: no step goes on"):
        joint.advance(pin, [0.0] * 6, 1e-5)
    assert np.array_equal(joint.wear_depth, depth)
