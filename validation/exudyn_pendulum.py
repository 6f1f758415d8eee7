"""A bar pendulum hung through the clearance joint, in exudyn: the case on which the
deepest-point contact stops exudyn's implicit solver.

The ground carries the pin (centre at the origin); the bar (the paper's rod: 0.19 kg,
8.8e-4 kg m^2, 0.22 m) carries the bushing at its upper end, (0, L/2) in its frame from its centre
of mass, and hangs in gravity.  It starts at rest, turned by ``angle_deg`` about the pin centre,
with the bushing touching the pin (zero penetration).  exudyn's generalized-alpha solver with its
default Newton settings and adaptive step (a step whose Newton iteration fails is halved) runs at
the nominal step ``step_s``; the joint goes in through :func:`wearjoint.exudyn.add_clearance_joint`
(ground = pin body, bar = bushing body).

Used by benchmarks/bench_contact_smoothness.py.
"""
from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D

from wearjoint.core import layout as L
from wearjoint.exudyn import add_clearance_joint, set_post_step, simulation_settings
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
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[x0, y0, a], initialCoordinates=[0.0, 0.0, 0.0],
                                       initialVelocities=[0.0, 0.0, 0.0]))
    body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=BAR_MASS_KG, inertia=BAR_INERTIA_KG_M2))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                     loadVector=[0.0, -GRAVITY_M_S2, 0.0]))
    handle = add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), body, joint)
    velocity = np.zeros(3)
    omega = []

    def post_step(mbs_, t):                   # after the joint accepted the step
        velocity[:] = mbs_.systemData.GetODE2Coordinates_t()
        omega.append((t, velocity[2]))
        return True

    set_post_step(mbs, post_step)
    mbs.Assemble()
    settings = simulation_settings(end_time_s, step_s)
    solver = exu.MainSolverImplicitSecondOrder()
    wall0 = time.perf_counter()
    try:
        solver.SolveSystem(mbs, settings)
    except RuntimeError:                      # exudyn raises when the step would fall below its minimum
        pass
    wall = time.perf_counter() - wall0
    steps = np.diff(np.r_[0.0, handle.history()["time_s"]])
    omega = np.array(omega).reshape(-1, 2)[1:]     # [0]: exudyn's call at the start
    late = omega[omega[:, 0] >= 0.5 * handle.t, 1] if omega.size else np.zeros(1)
    return {"completed": handle.t >= end_time_s * (1.0 - 1e-9), "time_reached_s": handle.t,
            "accepted_steps": handle.accepted_steps, "reduced_steps": int(np.sum(steps < step_s * (1.0 - 1e-6))),
            "min_step_s": float(steps.min()) if steps.size else math.inf,
            "newton_iterations": solver.it.newtonStepsCount, "late_max_abs_omega_rad_s": float(np.abs(late).max()),
            "final_penetration_m": handle.joint.result[L.R_PENETRATION],
            "final_speed_m_s": math.hypot(velocity[0], velocity[1]), "max_wear_depth_m": handle.joint.max_wear_depth_m,
            "wall_time_s": wall}


__all__ = ["run_pendulum", "pendulum_joint"]
