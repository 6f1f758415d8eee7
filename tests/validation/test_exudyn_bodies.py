"""The bodies a clearance joint joins in exudyn (docs/reference/exudyn.md, "Bodies"): a ground turned about z carries
its bushing in its own frame; one turned out of the plane is refused."""
from __future__ import annotations

import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D,
)

from wearjoint import JointParameters  # noqa: E402
from wearjoint.exudyn import add_clearance_joint, simulation_settings  # noqa: E402
from wearjoint.parameters import ParameterError  # noqa: E402

BAR_LENGTH, BAR_MASS, GRAVITY = 0.2, 0.5, 9.81     # [m], [kg], [m/s^2]


def test_a_rotated_ground_carries_the_bushing_in_its_own_frame():
    """A bushing on a ground turned 90 degrees about z (referenceRotation, or referenceHT: exudyn keeps the two in
    step), its centre given in that frame, (0.1, 0) m: globally at (0, 0.1).  A 0.5 kg bar hangs from it, started at
    its static sag: the joint carries the bar's weight and the pin sits c + delta below the bushing centre, globally
    -y, in the turned bushing frame at 180 degrees, where the wear and eccentricity are reported.  A rotation out of
    the plane is refused."""
    from exudyn.rigidBodyUtilities import RotationMatrixX, RotationMatrixZ

    mbs = exu.SystemContainer().AddSystem()
    p = JointParameters(bushing_offset_m=(0.1, 0.0), pin_offset_m=(0.0, 0.5 * BAR_LENGTH), wear_factor=0.0,
                        contact_damping="lankarani-nikravesh")
    weight = BAR_MASS * GRAVITY
    sag = p.clearance_m + (weight / p.stiffness_N_m1_5) ** (1.0 / p.contact_exponent)
    ground = mbs.AddObject(ObjectGround(referenceRotation=RotationMatrixZ(0.5 * math.pi)))
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.0, 0.1 - sag - 0.5 * BAR_LENGTH, 0.0]))
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=BAR_MASS, inertia=BAR_MASS * BAR_LENGTH ** 2 / 12))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)),
                                     loadVector=[0.0, -GRAVITY, 0.0]))
    tilted = mbs.AddObject(ObjectGround(referenceRotation=RotationMatrixX(0.1)))
    with pytest.raises(ParameterError, match=r"^bushing_body=.* is invalid: its ObjectGround's referenceRotation turns "
                                             r"it out of the x-y plane \(allowed: a rotation about z\)$"):
        add_clearance_joint(mbs, bar, tilted, p)
    handle = add_clearance_joint(mbs, bar, ground, p)
    mbs.Assemble()
    exu.SolveDynamic(mbs, simulation_settings(0.05, 1e-5))
    h = handle.history()
    late = h["time_s"] > 0.04
    assert np.mean(h["normal_force_N"][late]) == pytest.approx(weight, rel=1e-3)
    assert np.mean(h["eccentricity_x_m"][late]) == pytest.approx(-sag, rel=1e-3)
    assert abs(np.mean(h["eccentricity_y_m"][late])) < 1e-3 * sag
    result = handle.result()          # the contact's extent too, as ClearanceJoint.evaluate gives it
    assert result.in_contact and result.half_width_m > 0.0 and result.mean_pressure_Pa > 0.0
    assert result.contact_arc_rad[0] < math.pi < result.contact_arc_rad[1]
