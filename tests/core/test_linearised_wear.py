"""The wear of a held step whose host applies the loads linearised at its start (core.wear.accept_linearised_contact,
what the joint FMU's Co-Simulation step does once its derivatives were read there): Archard's volume with the mean
of that linear normal force over the step, F0 + (dF/dt) dt / 2, or F0^2 / (2 |dF/dt| dt) where it reaches 0 within
the step (the linearised contact ends there)."""
import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.joint import ClearanceJoint
from wearjoint.parameters import JointParameters

AT_REST = np.zeros(3)
STEP_S = 1e-5
RADIAL_SPEED_M_S = 0.01     # the pin moving along the contact's normal: the position column the rate reads


def pressed_turning_pin():
    """A joint whose step's wear goes at once, and a pin pressed 2 um into it, turning and moving outwards."""
    joint = ClearanceJoint(JointParameters(wear_factor=0.5, wear_interval_s=0.0))
    return (joint, np.array([joint.params.clearance_m + 2e-6, 0.0, 0.0]),
            np.array([RADIAL_SPEED_M_S, 0.0, 100.0]))


def linearised_step_volume(change_share: float) -> float:
    """The volume [m^3] one linearised step of a pressed, turning pin wears, its normal force changing by
    ``change_share`` of its start over the step (dF/dx times the radial speed, through the Jacobian's row)."""
    joint, pos_i, vel_i = pressed_turning_pin()
    jacobian = np.zeros((L.N_RESULT, 12))
    joint.linearise_array(pos_i, vel_i, AT_REST, AT_REST, jacobian)
    start_force = joint.result[L.R_NORMAL_FORCE]
    assert start_force > 0.0
    jacobian[L.R_NORMAL_FORCE, :] = 0.0
    jacobian[L.R_NORMAL_FORCE, 0] = change_share * start_force / (RADIAL_SPEED_M_S * STEP_S)
    before = joint.worn_volume_m3
    assert joint.accept_linearised_array(pos_i, vel_i, AT_REST, AT_REST, STEP_S, jacobian) >= 0
    return joint.worn_volume_m3 - before


@pytest.mark.parametrize("change_share, mean_share", [
    (0.5, 1.25), (-0.5, 0.75), (-1.0, 0.5),        # F0 + dF/2
    (-2.0, 0.25), (-4.0, 0.125),                   # reaching 0 at 1/2, 1/4 of the step: F0^2 / (2 |dF|)
])
def test_a_linearised_step_wears_with_the_mean_of_its_linear_normal_force(change_share, mean_share):
    held = linearised_step_volume(0.0)           # no change: the force at the step's start, as a held step's
    joint, pos_i, vel_i = pressed_turning_pin()
    assert joint.advance_array(pos_i, vel_i, AT_REST, AT_REST, STEP_S, True) >= 0
    assert held == joint.worn_volume_m3 > 0.0
    assert linearised_step_volume(change_share) / held == pytest.approx(mean_share, rel=1e-5)
