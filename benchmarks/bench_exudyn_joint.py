"""The cost of ``wearjoint.exudyn.add_clearance_joint`` in exudyn, measured in one run.

    python benchmarks/bench_exudyn_joint.py [--end-time 0.2] [--repeats 3] [--json FILE]

Bars hung from ground and swinging from 3 degrees, generalized-alpha at 10 us with wear, at
``simulation_settings()``: one bar through one clearance joint, two bars through two, and one bar
on an ideal revolute joint (the same system without the joint's Python callbacks).  Each clearance
case runs with the helper's exact Jacobian and, for comparison, with the forward differences the
helper used before (:class:`ForwardDifferences`, kept here only), and each of them at exudyn's
absolute Newton tolerance (1e-10 N) instead of the helper's: the helper's first version was forward
differences at exudyn's tolerance.  Prints microseconds per step, Newton iterations and Jacobian
updates per step (exudyn's counters), the joint's cost per step over the ideal joint, and the
kernels' own cost per evaluation (from a numba loop): what is left is exudyn calling Python.  Medians of ``--repeats`` runs, with the load average.
``--json FILE`` also writes the printed figures as JSON (benchmarks/performance_doc.py reads it).
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parent))
from repeats import Load, add_repeats_argument  # noqa: E402

import exudyn as exu  # noqa: E402
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, MarkerBodyPosition, NodeRigidBody2D, ObjectGround, ObjectJointRevolute2D,
    ObjectRigidBody2D,
)

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.core.generalized_coordinates import generalized_contact_forces  # noqa: E402
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


@njit
def forward_difference_jacobian(q, q_t, pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j, vel_j,
                                jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, force, base, jacobian,
                                factor_q, factor_q_t):
    """-(factor_q dF/dq + factor_q_t dF/dq_t) of the helper's force by forward differences with
    exudyn's step, 1e-7 max(|x|, 0.01): the helper's Jacobian before the exact one (benchmark only)."""
    n = q.shape[0]
    generalized_contact_forces(q, q_t, pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j, vel_j,
                               jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, base)
    jacobian[:, :] = 0.0
    for k in range(2 * n):
        x = q if k < n else q_t
        factor = factor_q if k < n else factor_q_t
        col = k % n
        x0 = x[col]
        epsilon = 1e-7 * max(abs(x0), 0.01)
        x[col] = x0 + epsilon
        generalized_contact_forces(q, q_t, pin_index, bushing_index, reference_i, reference_j, pos_i, vel_i, pos_j,
                                   vel_j, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, force)
        x[col] = x0
        for row in range(n):
            jacobian[row, col] -= factor * (force[row] - base[row]) / epsilon


class ForwardDifferences:
    """A joint's Jacobian user function by :func:`forward_difference_jacobian` (reads the handle's
    private kernel arguments: a benchmark, not an interface)."""

    def __init__(self, handle):
        n = handle._q.size
        self.handle = handle
        self.arguments = (*handle._force_arguments, np.zeros(n), np.zeros((n, n)))

    def __call__(self, mbs, t, item, q, q_t, factor_q, factor_q_t):
        self.handle._q[:], self.handle._q_t[:] = q, q_t
        forward_difference_jacobian(*self.arguments, factor_q, factor_q_t)
        return self.arguments[-1]


def run(n_bars: int, ideal: bool, end_time: float, differences: bool = False,
        exudyn_tolerance: bool = False) -> tuple[float, int, float, float]:
    """(wall time [s], steps, Newton iterations per step, Jacobian updates per step) of one simulation;
    ``differences``: the joints' Jacobian by forward differences; ``exudyn_tolerance``: Newton's
    absolute tolerance exudyn's 1e-10 N instead of the helper's."""
    sc, mbs, handles = swinging_bars(n_bars, ideal)
    if differences:         # exudyn keeps the functions it was given: give it the old ones
        for handle in handles:
            mbs.ModifyObject(handle.object_number, {"jacobianUserFunction": ForwardDifferences(handle)})
    mbs.Assemble()
    settings = simulation_settings(end_time, STEP, handles)
    if exudyn_tolerance:
        settings.timeIntegration.newton.absoluteTolerance = 1e-10
    wall = time.perf_counter()
    exu.SolveDynamic(mbs, settings)
    wall = time.perf_counter() - wall
    steps, counters = settings.timeIntegration.numberOfSteps, mbs.sys["dynamicSolver"].it
    return wall, steps, counters.newtonStepsCount / steps, counters.newtonJacobiCount / steps


def kernel_seconds_per_evaluation(n: int = 200_000) -> tuple[float, float]:
    """(evaluate_contact, contact_jacobian) seconds per evaluation from a numba loop, the pin 5 um deep."""
    from wearjoint.core.contact import contact_jacobian, evaluate_contact

    joint = ClearanceJoint(JointParameters())

    @njit
    def loop(n, with_jacobian, pos_i, vel_i, pos_j, vel_j, jp, c, s, h, b, m, out, jacobian):
        total = 0.0
        for k in range(n):
            pos_j[0] = -1.05e-4 + 1e-12 * (k % 7)
            if with_jacobian:
                contact_jacobian(pos_i, vel_i, pos_j, vel_j, jp, c, s, h, b, m, out, jacobian)
            else:
                evaluate_contact(pos_i, vel_i, pos_j, vel_j, jp, c, s, h, b, m, out)
            total += out[0]
        return total
    args = (np.zeros(3), np.array([0.0, 0.0, -1.0]), np.array([-1.05e-4, 0.0, 0.0]), np.array([0.0, 0.2, 0.0]),
            joint.parameter_vector, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min, joint.memory,
            joint.result, np.zeros((L.N_RESULT, L.N_KINEMATIC_INPUTS)))
    seconds = []
    for with_jacobian in (False, True):
        loop(10, with_jacobian, *args)
        wall = time.perf_counter()
        loop(n, with_jacobian, *args)
        seconds.append((time.perf_counter() - wall) / n)
    return seconds[0], seconds[1]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--end-time", type=float, default=0.2, help="simulated time per run [s] (default %(default)s)")
    add_repeats_argument(parser)
    parser.add_argument("--json", type=Path, default=None, help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    load = Load()
    rows = []
    run(1, False, 0.01)                                   # compile the kernels and warm up exudyn
    run(1, False, 0.01, differences=True)
    cases = [("ideal revolute", 1, True, False, False)]
    for joints in (1, 2):
        cases += [(f"{joints} joint{'s' if joints > 1 else ''}, {name}", joints, False, differences, tolerance)
                  for name, differences, tolerance in (("exact Jacobian", False, False),
                                                       ("forward differences", True, False),
                                                       ("exact, exudyn's tolerance", False, True),
                                                       ("differences, exudyn's tol. (before)", True, True))]
    ideal = None
    print(f"{'':<45} {'us/step':>8} {'over ideal':>10} {'Newton it/step':>15} {'Jacobians/step':>15}")
    for label, n_bars, is_ideal, differences, tolerance in cases:
        runs = [run(n_bars, is_ideal, args.end_time, differences, tolerance) for _ in range(args.repeats)]
        per_step = statistics.median(r[0] / r[1] for r in runs)
        ideal = per_step if is_ideal else ideal
        print(f"{label:<45} {1e6 * per_step:8.1f} {1e6 * (per_step - ideal):10.1f} {runs[0][2]:15.3f} "
              f"{runs[0][3]:15.4f}")
        rows.append({"case": label, "us per step": 1e6 * per_step,
                     "us per step runs": [1e6 * r[0] / r[1] for r in runs],
                     "us over ideal": 1e6 * (per_step - ideal), "Newton iterations per step": runs[0][2],
                     "Jacobians per step": runs[0][3]})
    force, jacobian = kernel_seconds_per_evaluation()
    print(f"kernels per evaluation: evaluate_contact {1e6 * force:.2f} us, contact_jacobian {1e6 * jacobian:.2f} us")
    print(f"medians of {args.repeats} runs of {args.end_time} s; {load.stop()}")
    if args.json:
        args.json.write_text(json.dumps({"end_time_s": args.end_time, "repeats": args.repeats,
                                         "load": [load.before, load.after], "cases": rows,
                                         "evaluate_contact_us": 1e6 * force, "contact_jacobian_us": 1e6 * jacobian},
                                        indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
