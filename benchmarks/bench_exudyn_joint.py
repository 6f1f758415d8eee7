"""The cost of ``wearjoint.exudyn.add_clearance_joint`` in exudyn, measured in one run.

    python benchmarks/bench_exudyn_joint.py [--end-time 0.2] [--repeats 3]

Bars hung from ground and swinging from 3 degrees, generalized-alpha at 10 us with wear: one bar
through one clearance joint, two bars through two, and one bar on an ideal revolute joint (the
same system without the joint's Python callbacks).  Prints steps per second and microseconds per
step, the joint's cost per step (against the ideal joint), how often exudyn calls the joint's force
and Jacobian user functions per step (counted in one more run: the counting is not timed), and the
kernel's own cost per evaluation (``evaluate_contact`` from a numba loop) for comparison: what is left
is exudyn calling Python.  Medians of ``--repeats`` runs, with the load average.
"""
from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from repeats import Load, add_repeats_argument  # noqa: E402

import exudyn as exu  # noqa: E402
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, MarkerBodyPosition, NodeRigidBody2D, ObjectGround, ObjectJointRevolute2D,
    ObjectRigidBody2D,
)

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.exudyn import add_clearance_joint, simulation_settings  # noqa: E402

LENGTH, MASS = 0.22, 0.19          # the paper's rod [m], [kg]
STEP = 1e-5


def swinging_bars(n_bars: int, ideal: bool):
    """``n_bars`` bars hung side by side from 3 degrees; returns (system container, mbs, handles)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    handles = []
    angle = math.radians(3.0)
    for k in range(n_bars):
        pivot = np.array([0.5 * k, 0.0])
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[pivot[0] + 0.5 * LENGTH * math.sin(angle),
                                                                 -0.5 * LENGTH * math.cos(angle), angle]))
        bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=MASS, inertia=MASS * LENGTH ** 2 / 12.0))
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)),
                                         loadVector=[0.0, -9.81, 0.0]))
        ground = mbs.AddObject(ObjectGround(referencePosition=[pivot[0], pivot[1], 0.0]))
        if ideal:
            mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0])),
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=bar, localPosition=[0.0, 0.5 * LENGTH, 0.0]))]))
            continue
        handles.append(add_clearance_joint(mbs, ground, bar, JointParameters(bushing_offset_m=(0.0, 0.5 * LENGTH),
                                                                             wear_factor=100.0)))
    return sc, mbs, handles


def run(n_bars: int, ideal: bool, end_time: float) -> tuple[float, int]:
    """(wall time [s], steps) of one simulation."""
    sc, mbs, handles = swinging_bars(n_bars, ideal)
    mbs.Assemble()
    settings = simulation_settings(end_time, STEP)
    wall = time.perf_counter()
    exu.SolveDynamic(mbs, settings)
    return time.perf_counter() - wall, settings.timeIntegration.numberOfSteps


def calls_per_step(n_bars: int, end_time: float) -> tuple[float, float]:
    """(force, Jacobian) user-function calls per step exudyn makes, all joints together."""
    sc, mbs, handles = swinging_bars(n_bars, False)
    calls = {"forceUserFunction": 0, "jacobianUserFunction": 0}

    def counting(name, function):
        def counted(*args):
            calls[name] += 1
            return function(*args)
        return counted
    for handle in handles:      # exudyn keeps the functions it was given: give it counting ones
        mbs.ModifyObject(handle.object_number, {
            "forceUserFunction": counting("forceUserFunction", handle.generalized_force),
            "jacobianUserFunction": counting("jacobianUserFunction", handle.generalized_jacobian)})
    mbs.Assemble()
    settings = simulation_settings(end_time, STEP)
    exu.SolveDynamic(mbs, settings)
    steps = settings.timeIntegration.numberOfSteps
    return calls["forceUserFunction"] / steps, calls["jacobianUserFunction"] / steps


def kernel_seconds_per_evaluation(n: int = 200_000) -> float:
    from numba import njit

    from wearjoint.core.contact import evaluate_contact

    joint = ClearanceJoint(JointParameters())

    @njit
    def loop(n, pos_i, vel_i, pos_j, vel_j, jp, c, s, h, b, m, out):
        total = 0.0
        for k in range(n):
            pos_j[0] = -1.05e-4 + 1e-12 * (k % 7)
            evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, c, s, h, b, m, out)
            total += out[0]
        return total
    args = (np.zeros(3), np.array([0.0, 0.0, -1.0]), np.array([-1.05e-4, 0.0, 0.0]), np.array([0.0, 0.2, 0.0]),
            joint.parameter_vector, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min, joint.memory,
            joint.result)
    loop(10, *args)
    wall = time.perf_counter()
    loop(n, *args)
    return (time.perf_counter() - wall) / n


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--end-time", type=float, default=0.2, help="simulated time per run [s] (default %(default)s)")
    add_repeats_argument(parser)
    args = parser.parse_args(argv)
    load = Load()
    run(1, False, 0.01)                                   # compile the kernels and warm up exudyn
    figures = {}
    for label, n_bars, ideal in (("ideal revolute", 1, True), ("1 clearance joint", 1, False),
                                 ("2 clearance joints", 2, False)):
        runs = [run(n_bars, ideal, args.end_time) for _ in range(args.repeats)]
        wall, steps = statistics.median([r[0] for r in runs]), runs[0][1]
        figures[label] = (wall, steps, n_bars)
        print(f"{label:<20} {steps / wall:>9.0f} steps/s   {1e6 * wall / steps:7.1f} us/step")
    ideal = figures["ideal revolute"][0] / figures["ideal revolute"][1]
    kernel = kernel_seconds_per_evaluation()
    for label in ("1 clearance joint", "2 clearance joints"):
        wall, steps, n_bars = figures[label]
        forces, jacobians = calls_per_step(n_bars, args.end_time)
        print(f"{label}: {1e6 * (wall / steps - ideal):.1f} us per step over the ideal joint; exudyn calls the force "
              f"user functions {forces:.2f} and the Jacobian ones {jacobians:.2f} times per step; the kernel itself "
              f"takes {1e6 * kernel:.2f} us per evaluation")
    print(f"medians of {args.repeats} runs of {args.end_time} s; {load.stop()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
