"""A bar pendulum hung through the clearance joint, in exudyn (issue 25): the case on which the
deepest-point contact stops exudyn's implicit solver.

The ground carries the pin (centre at the origin); the bar (the paper's rod: 0.19 kg,
8.8e-4 kg m^2, 0.22 m) carries the bushing at its upper end, (0, L/2) in its frame from its centre
of mass, and hangs in gravity.  It starts at rest, turned by ``angle_deg`` about the pin centre,
with the bushing touching the pin (zero penetration).  exudyn's generalized-alpha solver with its
default Newton settings and adaptive step (a step whose Newton iteration fails is halved) runs at
the nominal step ``step_s``; the joint's forces enter through an ``ObjectGenericODE2`` force user
function, wear once per accepted step (as in :mod:`validation.exudyn_model`).

Used by tests/test_fitted_contact.py and benchmarks/bench_contact_smoothness.py.
"""
from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGenericODE2, \
    ObjectRigidBody2D

from wearjoint.core import layout as L
from wearjoint.joint import ClearanceJoint
from wearjoint.parameters import JointParameters

BAR_MASS_KG = 0.19
BAR_INERTIA_KG_M2 = 8.8e-4
BAR_LENGTH_M = 0.22
GRAVITY_M_S2 = 9.81


def pendulum_joint(**changes) -> JointParameters:
    """The paper's joint with the pin at the ground's origin and the bushing at the bar's upper end."""
    return JointParameters(pin_offset_m=(0.0, 0.0), bushing_offset_m=(0.0, 0.5 * BAR_LENGTH_M), **changes)


def run_pendulum(joint: JointParameters, angle_deg: float, end_time_s: float, step_s: float = 1e-5) -> dict:
    """Simulate the pendulum (module docstring); returns whether exudyn completed, the time reached
    [s], accepted steps, steps shorter than ``step_s`` (halved after a failed Newton iteration),
    the shortest step [s], Newton iterations, the largest |omega| of the bar over the last half of
    the time reached [rad/s], the last accepted state's penetration [m] and the bar's speed there
    [m/s], the largest wear depth [m] and the wall time [s]."""
    a = math.radians(angle_deg)
    c, s = math.cos(a), math.sin(a)
    gap = joint.clearance_m
    half = 0.5 * BAR_LENGTH_M
    # bushing centre below the pin centre by the clearance along the bar's axis, COM half a bar below it
    x0 = s * gap + s * half
    y0 = -c * gap - c * half
    jnt = ClearanceJoint(joint)
    ground = np.zeros(3)
    pos, vel = np.zeros(3), np.zeros(3)
    force = np.zeros(3)
    record = {"t": 0.0, "accepted": 0, "reduced": 0, "min_step": math.inf, "omega": []}

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[x0, y0, a], initialCoordinates=[0.0, 0.0, 0.0],
                                       initialVelocities=[0.0, 0.0, 0.0]))
    body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=BAR_MASS_KG, inertia=BAR_INERTIA_KG_M2))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                     loadVector=[0.0, -GRAVITY_M_S2, 0.0]))
    reference = np.array([x0, y0, a])

    def contact_force(mbs_, t, item, q, q_t):
        pos[:] = reference + q
        vel[:] = q_t
        r = jnt.evaluate_array(ground, ground, pos, vel)
        force[:] = r[L.R_BUSHING_FX:L.R_BUSHING_TORQUE + 1]
        return force

    def post_step(mbs_, t):
        dt = t - record["t"]
        if dt <= 0.0:
            return True
        sd = mbs_.systemData
        pos[:] = reference + sd.GetODE2Coordinates()
        vel[:] = sd.GetODE2Coordinates_t()
        jnt.advance_array(ground, ground, pos, vel, dt)
        record["accepted"] += 1
        record["reduced"] += dt < step_s * (1.0 - 1e-6)
        record["min_step"] = min(record["min_step"], dt)
        record["omega"].append((t, vel[2]))
        record["t"] = t
        return True

    mbs.AddObject(ObjectGenericODE2(nodeNumbers=[node], massMatrix=np.zeros((3, 3)), forceUserFunction=contact_force))
    mbs.SetPostStepUserFunction(post_step)
    mbs.Assemble()
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.endTime = end_time_s
    ti.numberOfSteps = max(1, int(round(end_time_s / step_s)))
    ti.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.active = False
    solver = exu.MainSolverImplicitSecondOrder()
    wall0 = time.perf_counter()
    try:
        solver.SolveSystem(mbs, settings)
    except RuntimeError:                      # exudyn raises when the step would fall below its minimum
        pass
    wall = time.perf_counter() - wall0
    omega = np.array(record["omega"]).reshape(-1, 2)
    late = omega[omega[:, 0] >= 0.5 * record["t"], 1] if omega.size else np.zeros(1)
    return {"completed": record["t"] >= end_time_s * (1.0 - 1e-9), "time_reached_s": record["t"],
            "accepted_steps": record["accepted"], "reduced_steps": record["reduced"],
            "min_step_s": record["min_step"], "newton_iterations": solver.it.newtonStepsCount,
            "late_max_abs_omega_rad_s": float(np.abs(late).max()), "final_penetration_m": jnt.result[L.R_PENETRATION],
            "final_speed_m_s": math.hypot(vel[0], vel[1]), "max_wear_depth_m": jnt.max_wear_depth_m,
            "wall_time_s": wall}


__all__ = ["run_pendulum", "pendulum_joint"]
