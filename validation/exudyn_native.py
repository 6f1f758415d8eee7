"""exudyn's own contact as the unworn clearance joint: ``ObjectContactSphereSphere``
with ``isHollowSphere1``, a sphere in a hollow sphere, which in the plane is a pin in a bushing.

An independent contact law in exudyn's C++ code, none of the wearjoint kernels: the cross-check
of the contact law itself (the ``exudyn-native`` engine of ``wearjoint validate``).  It cannot
wear.  The mapping from :class:`JointParameters` (:func:`native_contact_parameters`,
docs/explanation/validation.md "exudyn's own contact"):

- marker 0 = the pin centre (pin body), marker 1 = the bushing centre (bushing body), the hollow
  one (the other way round the pin sits 40 um from the centre under 132 kN);
  ``spheresRadii`` = (R_i, R_j);
- ``contactStiffness`` = K [N/m^n], ``contactStiffnessExponent`` = n: F_e = K delta^n, delta = |e| - c;
- ``impactModel`` 1 (Hunt-Crossley): F_N = K delta^n (1 + 3/2 (1 - e_x) delta_dot / delta_dot^-),
  the Lankarani-Nikravesh form with delta_dot^- stored at the impact and floored at
  ``minimumImpactVelocity``; e_x = (1 + e_r^2)/2 makes 3/2 (1 - e_x) = 3/4 (1 - e_r^2), the same
  coefficient.  exudyn has no damping without a stored impact velocity (its models 0-2 all store
  one; model 0 is a linear dashpot), so for our default Hunt-Crossley damping
  ``minimumImpactVelocity`` = the restitution speed v_r: every impact slower than v_r (about 95 % of
  the paper case's) then gets exactly our law, faster ones less damping; for Lankarani-Nikravesh it is
  our floor of delta_dot^-; ``contactDamping`` 0;
- ``dynamicFriction`` = mu; ``frictionProportionalZone`` v_reg = v0 + v1: exudyn's friction
  mu F_N min(1, |v_T|/v_reg) then has Ambrosio's mean deficit (the integral of 1 - c_d over |v_T|,
  (v0 + v1)/2) and the smallest largest difference from his ramp (v0/(v0 + v1) of mu F_N).

What remains different (docs/explanation/validation.md, "which law makes the difference"): exudyn's exact
circle against our N_d bushing points (the one difference measured to matter), no clip of F_N at 0
(its damping may pull while the pin separates), friction regularised linearly from 0 (ours: none
below v0), both forces at the middle of the overlap (ours: on the pin surface), the contact state
held over each Newton solve (its discontinuous iteration).  At fixed steps (exudyn_model), delta_dot^-
is taken at the end of the first step in contact, as our helper takes it.

Only validation/ and wearjoint.exudyn import exudyn.
"""
from __future__ import annotations

import math

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    MarkerBodyRigid, NodeGenericData, NodeRigidBody2D, ObjectContactSphereSphere, ObjectRigidBody2D,
)

from wearjoint.core import layout as L
from wearjoint.core.damping import hunt_crossley_damping
from wearjoint.exudyn import _Body, _start_eccentricity
from wearjoint.parameters import JointParameters, ParameterError

HUNT_CROSSLEY = 1                  # exudyn's impactModel number
DATA_GAP, DATA_TANGENT_SPEED, DATA_IMPACT_VELOCITY, DATA_PLASTIC = range(4)   # its data node's coordinates
_OUT = exu.OutputVariableType


def native_restitution(p: JointParameters) -> float:
    """exudyn's Hunt-Crossley restitution e_x with 3/2 (1 - e_x) = chi of ``p``'s law in the onset form
    F = K delta^n (1 + chi delta_dot / delta_dot^-): the paper's 3/4 (1 - e_r^2) for Lankarani-Nikravesh, else
    the closed form's a(e_r), which Hunt-Crossley's alpha v_r and Lankarani-Nikravesh exact's chi are
    (docs/reference/model.md §3.5)."""
    if p.contact_damping == "lankarani-nikravesh":
        return 0.5 * (1.0 + p.restitution * p.restitution)
    return 1.0 - float(hunt_crossley_damping(p.restitution)) / 1.5


def native_law(p: JointParameters) -> dict:
    """The changes to ``p`` whose wearjoint kernels compute exudyn's law (up to exudyn's exact circle and the
    differences of docs/explanation/validation.md): the deepest point's K delta^n with the onset-memory damping of the same
    chi, floored at exudyn's ``minimumImpactVelocity`` (our restitution speed v_r where ``p`` has a memory-free
    law)."""
    memory = p.contact_damping in ("lankarani-nikravesh", "lankarani-nikravesh-exact")
    floor = p.impact_velocity_floor_m_s if memory else p.restitution_speed_m_s
    law = "lankarani-nikravesh" if p.contact_damping == "lankarani-nikravesh" else "lankarani-nikravesh-exact"
    return {"contact_model": "deepest", "contact_damping": law, "impact_velocity_floor_m_s": floor}


def native_contact_parameters(p: JointParameters) -> dict:
    """``ObjectContactSphereSphere`` arguments for the joint ``p`` (see the module docstring)."""
    return {"spheresRadii": [p.pin_radius_m, p.bushing_radius_m], "isHollowSphere1": True,
            "contactStiffness": p.stiffness_N_m1_5, "contactStiffnessExponent": p.contact_exponent,
            "contactDamping": 0.0, "impactModel": HUNT_CROSSLEY,
            "restitutionCoefficient": native_restitution(p),
            "minimumImpactVelocity": native_law(p)["impact_velocity_floor_m_s"],
            "dynamicFriction": p.friction_coefficient,
            "frictionProportionalZone": p.friction_v0_m_s + p.friction_v1_m_s}


def _check_unworn(p: JointParameters) -> None:
    if p.wear_coefficient_m2_N * p.wear_factor > 0.0:
        raise ParameterError("exudyn's own contact cannot wear: set wear_factor=0 (or wear_coefficient_m2_N=0) "
                             "or use the wearjoint contact (contact='discrete')")


class NativeContact:
    """exudyn's contact between ``pin_body`` and ``bushing_body`` (object numbers of
    ``ObjectRigidBody2D`` or ``ObjectGround``) at the ``JointParameters`` offsets; add before
    ``mbs.Assemble()``.  :meth:`read` gives its state in our result layout."""

    def __init__(self, mbs, pin_body, bushing_body, parameters: JointParameters):
        _check_unworn(parameters)
        self.params = parameters
        self.pin, self.bushing = _Body(mbs, "pin_body", pin_body), _Body(mbs, "bushing_body", bushing_body)
        # exudyn's contact state starts as the initial configuration's (gap c - |e| [m]; no stored impact)
        data = (parameters.clearance_m - _start_eccentricity(self.pin, self.bushing, parameters), 0.0, 0.0, 0.0)
        self.bodies = (pin_body, bushing_body)
        offsets = (parameters.pin_offset_m, parameters.bushing_offset_m)
        self.markers = tuple(mbs.AddMarker(MarkerBodyRigid(bodyNumber=body, localPosition=[*offset, 0.0]))
                             for body, offset in zip(self.bodies, offsets))
        self.data_node = mbs.AddNode(NodeGenericData(initialCoordinates=list(data), numberOfDataCoordinates=4))
        self.object_number = mbs.AddObject(ObjectContactSphereSphere(
            markerNumbers=list(self.markers), nodeNumber=self.data_node, **native_contact_parameters(parameters)))

    def _reference_point(self, mbs, k: int) -> np.ndarray:
        body = (self.pin, self.bushing)[k]
        if body.node is None:
            return body.reference[:2]
        return np.asarray(mbs.GetNodeOutput(body.node, _OUT.Position))[:2]

    def read(self, mbs, out: np.ndarray) -> np.ndarray:
        """exudyn's contact at the system's current state into ``out`` (layout.R_*): its force on the
        pin (and the opposite on the bushing) at its contact point (the middle of the overlap), torques
        about the bodies' reference points, F_N = -f.n, friction f.t (n = e/|e|, t = n turned +90 deg),
        delta = -gap, delta_dot and v_T of the pin relative to the bushing; the eccentricity in the
        bushing frame.  R_CONTACT_INDEX is -1 (no bushing points)."""
        pin_marker, bushing_marker = self.markers
        g = (np.asarray(mbs.GetMarkerOutput(pin_marker, _OUT.Position))
             - np.asarray(mbs.GetMarkerOutput(bushing_marker, _OUT.Position)))[:2]
        angle = float(mbs.GetMarkerOutput(bushing_marker, _OUT.Rotation)[2])
        c, s = math.cos(angle), math.sin(angle)
        gap = float(np.ravel(mbs.GetObjectOutput(self.object_number, _OUT.DisplacementLocal))[0])
        force = np.asarray(mbs.GetObjectOutput(self.object_number, _OUT.Force))[:2]      # on the pin
        point = np.asarray(mbs.GetObjectOutput(self.object_number, _OUT.Position))[:2]
        relative = -np.asarray(mbs.GetObjectOutput(self.object_number, _OUT.Velocity))[:2]  # pin - bushing
        e = math.hypot(g[0], g[1])
        n = g / e if e > 0.0 else np.array([1.0, 0.0])
        t = np.array([-n[1], n[0]])
        out[:] = 0.0
        out[L.R_ECCENTRICITY_X] = c * g[0] + s * g[1]
        out[L.R_ECCENTRICITY_Y] = -s * g[0] + c * g[1]
        out[L.R_CONTACT_ANGLE] = math.atan2(out[L.R_ECCENTRICITY_Y], out[L.R_ECCENTRICITY_X]) % (2.0 * math.pi)
        out[L.R_CONTACT_INDEX] = -1.0
        out[L.R_PENETRATION] = -gap
        if not np.any(force):
            return out
        for k, (first, sign) in enumerate(((L.R_PIN_FX, 1.0), (L.R_BUSHING_FX, -1.0))):
            f = sign * force
            arm = point - self._reference_point(mbs, k)
            out[first:first + 3] = f[0], f[1], arm[0] * f[1] - arm[1] * f[0]
        out[L.R_NORMAL_FORCE] = -force @ n
        out[L.R_FRICTION_FORCE] = force @ t
        out[L.R_CONTACT] = 1.0 if gap <= 0.0 else 0.0
        out[L.R_PENETRATION_RATE] = relative @ n
        out[L.R_TANGENTIAL_VELOCITY] = relative @ t
        return out


def native_contact_forces(parameters: JointParameters, pos_i, vel_i, pos_j, vel_j,
                          impact_velocity: float = 0.0) -> np.ndarray:
    """exudyn's contact (layout.R_*) for two free bodies at positions (x [m], y [m], angle [rad]) and
    velocities (vx, vy, omega) of their reference points, with its stored impact velocity
    delta_dot^- [m/s] (floored at ``minimumImpactVelocity`` by exudyn) and its contact and friction
    states taken at this configuration, as after its post-Newton update."""
    system = exu.SystemContainer()
    mbs = system.AddSystem()
    bodies = [mbs.AddObject(ObjectRigidBody2D(mass=1.0, inertia=1.0, nodeNumber=mbs.AddNode(
        NodeRigidBody2D(referenceCoordinates=list(pos), initialVelocities=list(vel)))))
        for pos, vel in ((pos_i, vel_i), (pos_j, vel_j))]
    contact = NativeContact(mbs, *bodies, parameters.replace(wear_factor=0.0))
    mbs.Assemble()
    index = mbs.systemData.GetNodeLTGData(contact.data_node)
    data = np.asarray(mbs.systemData.GetDataCoordinates())
    out = np.zeros(L.N_RESULT)
    data[index[DATA_GAP]] = -1.0                              # assume contact, to read the slip speed
    mbs.systemData.SetDataCoordinates(data)
    contact.read(mbs, out)
    data[index] = (-out[L.R_PENETRATION], abs(out[L.R_TANGENTIAL_VELOCITY]), impact_velocity, 0.0)
    mbs.systemData.SetDataCoordinates(data)
    contact.read(mbs, out)
    system.Reset()
    return out


__all__ = ["NativeContact", "native_law", "native_contact_parameters", "native_contact_forces", "native_restitution",
           "HUNT_CROSSLEY"]
