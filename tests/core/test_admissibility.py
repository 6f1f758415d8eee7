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
    """The first accepted point is taken (a master may step the joint once before it connected the inputs); at a
    later one deeper than the bound the step is refused and the profile, the contact memory and the volume stay."""
    joint = ClearanceJoint(JOINT.replace(wear_factor=0.0))     # the first point's wear would deepen the groove there
    deep = JOINT.clearance_m + 2.0 * JOINT.admissible_penetration_m
    assert joint.advance_array(*_kinematics(deep), 1e-5) != STEP_INADMISSIBLE       # the first point
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
