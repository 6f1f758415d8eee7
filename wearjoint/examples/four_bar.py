"""A four-bar linkage with two wearing clearance joints, built in exudyn with
:func:`wearjoint.exudyn.add_clearance_joint` (docs/explanation/four_bar.md).

    python -m wearjoint.examples.four_bar --out results/four_bar [--revolutions 3] [--wear-factor 100]

Links (docs/explanation/four_bar.md says where the values come from): ground A-D of length d along X,
crank A-B (a), coupler B-C (b), rocker D-C (c); a Grashof crank-rocker (a + b <= c + d).  The crank
turns counter-clockwise at a constant speed (a coordinate constraint on its angle), A and D are
ideal revolute joints to ground, B and C are clearance joints whose bushings sit in the coupler's
ends (pins on the crank and on the rocker).  Bodies are rigid, referenced at their centres of
mass, in gravity (-Y).  The ideal linkage's rocker angle is Freudenstein's closed form
(:func:`freudenstein_rocker_angle`).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    LoadMassProportional, MarkerBodyMass, MarkerBodyPosition, MarkerNodeCoordinate, NodePointGround,
    NodeRigidBody2D, ObjectConnectorCoordinate, ObjectGround, ObjectJointRevolute2D, ObjectRigidBody2D,
)

from wearjoint.checks import with_options
from wearjoint.exudyn import add_clearance_joint, check_step, set_post_step, simulation_settings, solve_dynamic
from wearjoint.parameters import JointParameters, ParameterError, require
from wearjoint.progress import Progress
from wearjoint.validation.exudyn_native import NativeContact

CONTACTS = ("wearjoint", "native")     # our joint; exudyn's own contact (unworn)


@dataclass(frozen=True)
class FourBar:
    """Link lengths [m], masses [kg], centroidal inertias [kg m^2] and the crank's speed and start."""
    crank_m: float = 0.050            # a: the paper's crank
    coupler_m: float = 0.220          # b: the paper's connecting rod
    rocker_m: float = 0.150           # c
    ground_m: float = 0.200           # d
    crank_mass_kg: float = 3.0        # the paper's crank (Table 1)
    crank_inertia_kg_m2: float = 7.36e-3
    coupler_mass_kg: float = 0.19     # the paper's rod (Table 1)
    coupler_inertia_kg_m2: float = 8.8e-4
    rocker_mass_kg: float = 0.13      # a slender aluminium bar like the rod, scaled to its length
    rocker_inertia_kg_m2: float = 0.13 * 0.150 ** 2 / 12.0
    crank_speed_rpm: float = 150.0    # the paper's
    initial_crank_angle_deg: float = 90.0
    gravity_m_s2: float = 9.81

    def __post_init__(self):
        lengths = sorted((self.crank_m, self.coupler_m, self.rocker_m, self.ground_m))
        require("crank_m", self.crank_m, self.crank_m == lengths[0] and lengths[0] + lengths[3] <= lengths[1] +
                 lengths[2], "the shortest link, with shortest + longest <= the other two (Grashof crank-rocker)")

    @property
    def omega_rad_s(self) -> float:
        return self.crank_speed_rpm * 2.0 * math.pi / 60.0


def freudenstein_rocker_angle(crank_angle, linkage: FourBar):
    """The rocker angle theta4 [rad] of the ideal linkage at crank angle theta2 (open branch):
    Freudenstein's equation K1 cos th4 - K2 cos th2 + K3 = cos(th2 - th4) solved by the half-angle
    substitution."""
    a, b, c, d = linkage.crank_m, linkage.coupler_m, linkage.rocker_m, linkage.ground_m
    th2 = np.asarray(crank_angle, dtype=float)
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2.0 * a * c)
    big_a = np.cos(th2) - k1 - k2 * np.cos(th2) + k3
    big_b = -2.0 * np.sin(th2)
    big_c = k1 - (k2 + 1.0) * np.cos(th2) + k3
    return 2.0 * np.arctan2(-big_b - np.sqrt(big_b * big_b - 4.0 * big_a * big_c), 2.0 * big_a)


def ideal_configuration(linkage: FourBar, crank_angle: float):
    """Angles (th2, th3, th4) [rad] and rates [rad/s] of the ideal linkage at ``crank_angle``,
    the crank turning at +omega: the loop a e^(i th2) + b e^(i th3) = d + c e^(i th4) and its
    time derivative."""
    a, b, c, d = linkage.crank_m, linkage.coupler_m, linkage.rocker_m, linkage.ground_m
    th2 = crank_angle
    th4 = float(freudenstein_rocker_angle(th2, linkage))
    th3 = math.atan2(c * math.sin(th4) - a * math.sin(th2), d + c * math.cos(th4) - a * math.cos(th2))
    w2 = linkage.omega_rad_s
    # b w3 e^(i th3) - c w4 e^(i th4) = -a w2 e^(i th2) (times i), real and imaginary parts
    m = np.array([[-b * math.sin(th3), c * math.sin(th4)], [b * math.cos(th3), -c * math.cos(th4)]])
    rhs = np.array([a * w2 * math.sin(th2), -a * w2 * math.cos(th2)])
    w3, w4 = np.linalg.solve(m, rhs)
    return (th2, th3, th4), (w2, float(w3), float(w4))


def clearance_joint(linkage_clearance_m: float, **changes) -> JointParameters:
    """The paper's joint (Table 2) with radial clearance ``linkage_clearance_m``: the bushing radius
    R_i + c; the contact stiffness follows from the materials (internal contact, Eq. 16 as corrected)."""
    base = JointParameters()
    return base.replace(bushing_radius_m=base.pin_radius_m + linkage_clearance_m, **changes)


class FourBarModel:
    """The linkage in exudyn with clearance joints at B and C (module docstring)."""

    def __init__(self, linkage: FourBar | None = None, clearance_m: float = 1e-4, wear_factor: float = 0.0,
                 contact: str = "wearjoint"):
        """``contact``: ``wearjoint`` (our joint, :func:`add_clearance_joint`) or ``native`` (exudyn's own
        hollow-sphere contact, unworn: :class:`~wearjoint.validation.exudyn_native.NativeContact`)."""
        require("contact", contact, contact in CONTACTS, "one of " + ", ".join(CONTACTS))
        self.contact = contact
        self.linkage = linkage = linkage or FourBar()
        require("clearance_m", clearance_m, 0.0 < clearance_m < 1e-3, "in (0, 1 mm)")
        a, b, c = linkage.crank_m, linkage.coupler_m, linkage.rocker_m
        (th2, th3, th4), (w2, w3, w4) = ideal_configuration(linkage, math.radians(linkage.initial_crank_angle_deg))
        self.system_container = exu.SystemContainer()
        mbs = self.mbs = self.system_container.AddSystem()
        ground = mbs.AddObject(ObjectGround())
        d = linkage.ground_m
        bx, by = a * math.cos(th2), a * math.sin(th2)                        # B, ideal
        frames = {"crank": ((0.5 * bx, 0.5 * by), th2, w2, (-0.5 * a * w2 * math.sin(th2), 0.5 * a * w2 * math.cos(th2))),
                  "coupler": ((bx + 0.5 * b * math.cos(th3), by + 0.5 * b * math.sin(th3)), th3, w3,
                              (-a * w2 * math.sin(th2) - 0.5 * b * w3 * math.sin(th3),
                               a * w2 * math.cos(th2) + 0.5 * b * w3 * math.cos(th3))),
                  "rocker": ((d + 0.5 * c * math.cos(th4), 0.5 * c * math.sin(th4)), th4, w4,
                             (-0.5 * c * w4 * math.sin(th4), 0.5 * c * w4 * math.cos(th4)))}
        inertia = {"crank": (linkage.crank_mass_kg, linkage.crank_inertia_kg_m2),
                   "coupler": (linkage.coupler_mass_kg, linkage.coupler_inertia_kg_m2),
                   "rocker": (linkage.rocker_mass_kg, linkage.rocker_inertia_kg_m2)}
        self.nodes, self.bodies = {}, {}
        for name, ((x, y), angle, rate, (vx, vy)) in frames.items():
            node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[x, y, angle], initialVelocities=[vx, vy, rate]))
            body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=inertia[name][0], inertia=inertia[name][1]))
            mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                             loadVector=[0.0, -linkage.gravity_m_s2, 0.0]))
            self.nodes[name], self.bodies[name] = node, body

        def revolute(body_a, local_a, body_b, local_b):
            mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=body_a, localPosition=[*local_a, 0.0])),
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=body_b, localPosition=[*local_b, 0.0]))]))

        revolute(ground, (0.0, 0.0), self.bodies["crank"], (-0.5 * a, 0.0))          # A
        revolute(ground, (d, 0.0), self.bodies["rocker"], (-0.5 * c, 0.0))           # D
        omega = linkage.omega_rad_s
        mbs.AddObject(ObjectConnectorCoordinate(                                      # th2 - th2(0) = omega t
            markerNumbers=[mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0)),
                           mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=self.nodes["crank"], coordinate=2))],
            offsetUserFunction=lambda mbs_, t, item, offset: omega * t))
        add = add_clearance_joint if contact == "wearjoint" else NativeContact
        self.joints = {
            "B": add(mbs, self.bodies["crank"], self.bodies["coupler"], clearance_joint(
                clearance_m, pin_offset_m=(0.5 * a, 0.0), bushing_offset_m=(-0.5 * b, 0.0), wear_factor=wear_factor)),
            "C": add(mbs, self.bodies["rocker"], self.bodies["coupler"], clearance_joint(
                clearance_m, pin_offset_m=(0.5 * c, 0.0), bushing_offset_m=(0.5 * b, 0.0), wear_factor=wear_factor)),
        }
        self.reference = {name: np.array(frame[0] + (frame[1],)) for name, frame in frames.items()}
        self.time, self.crank_angle, self.rocker_angle = [], [], []
        self._progress = None
        set_post_step(mbs, self._record)
        mbs.Assemble()

    def _record(self, mbs, t):
        q = mbs.systemData.GetODE2Coordinates()
        self.time.append(t)
        for name, out in (("crank", self.crank_angle), ("rocker", self.rocker_angle)):
            out.append(self.reference[name][2] + q[mbs.systemData.GetNodeLTGODE2(self.nodes[name])[2]])
        if self._progress is not None and len(self.time) % 2000 == 0:
            self._progress.update(t)
        return True

    def close(self) -> None:
        """Release the exudyn system: its user functions refer to this model, a reference cycle
        through exudyn's C++ side that Python's collector cannot break."""
        self.system_container.Reset()

    def simulate(self, end_time_s: float, step_s: float = 1e-5, progress: bool = False) -> dict:
        """exudyn's generalized-alpha (its explicit solvers take no revolute joints) at the fixed step
        ``step_s`` [s] to ``end_time_s`` [s]; returns the rocker angle and Freudenstein's at every
        accepted step, the wall time, exudyn's steps and Newton iterations, and ``completed``: False
        if exudyn's Newton stopped earlier (docs/explanation/four_bar.md), the run then ending there."""
        require("end_time_s", end_time_s, math.isfinite(end_time_s) and end_time_s > 0.0, "> 0 s")
        handles = self.joints.values() if self.contact == "wearjoint" else ()
        check_step(step_s, handles)
        linkage = self.linkage
        # the coordinates' size for Newton's round-off floor: the linkage's extent, and the crank's
        # angle (which grows without bound) times the pin's offset from the crank's centre
        crank_turned = math.radians(linkage.initial_crank_angle_deg) + linkage.omega_rad_s * end_time_s
        scale = max(linkage.ground_m + linkage.rocker_m, 0.5 * linkage.crank_m * crank_turned)
        settings = simulation_settings(end_time_s, step_s, handles, coordinate_scale_m=scale)
        if self.contact == "native":    # fixed steps: its recommended step sizes stop the solver (exudyn_model)
            settings.timeIntegration.discontinuous.useRecommendedStepSize = False
        self._progress = Progress(end_time_s, "four-bar", enabled=progress)
        wall = time.perf_counter()
        completed = True
        try:
            solve_dynamic(self.mbs, settings)
        except exu.SolverError:
            completed = False
        finally:
            wall = time.perf_counter() - wall
            self._progress.close()
        iterations = self.mbs.sys["dynamicSolver"].it
        t = np.array(self.time)
        crank, rocker = np.array(self.crank_angle), np.array(self.rocker_angle)
        return {"time_s": t[1:], "crank_angle_rad": crank[1:], "rocker_angle_rad": rocker[1:],
                "ideal_rocker_angle_rad": freudenstein_rocker_angle(crank[1:], linkage), "wall_time_s": wall,
                "completed": completed, "solver_steps": len(t) - 1,
                "newton_iterations_per_step": iterations.newtonStepsCount / max(1, len(t) - 1)}


def _figures(out: Path, run: dict, model: FourBarModel) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    t = run["time_s"]
    axes[0].plot(t, np.degrees(run["rocker_angle_rad"] - run["ideal_rocker_angle_rad"]) * 60.0, lw=0.6)
    axes[0].set(xlabel="time [s]", ylabel="rocker angle - Freudenstein [arcmin]",
                title="rocker angle against the ideal linkage")
    for name, handle in model.joints.items():
        h = handle.history()
        axes[1].plot(h["time_s"], h["normal_force_N"], lw=0.5, label=f"joint {name}")
        phi, depth = handle.joint.wear_profile
        axes[2].plot(phi, depth * 1e6, label=f"joint {name}")
    axes[1].set(xlabel="time [s]", ylabel="normal force [N]", title="contact forces")
    axes[2].set(xlabel="angle in the coupler's frame [deg]", ylabel="wear depth [um]", title="worn bushings")
    for ax in axes[1:]:
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "four_bar.png", dpi=120)
    plt.close(fig)


# the options by the names the model's checks give their values
OPTIONS = {"revolutions": "--revolutions", "clearance_m": "--clearance-m", "wear_factor": "--wear-factor",
           "step_s": "--step"}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="A four-bar with two wearing clearance joints in exudyn")
    parser.add_argument("--out", required=True, metavar="DIR")
    parser.add_argument("--revolutions", type=float, default=3.0,
                        help="crank revolutions (default %(default)s)")
    parser.add_argument("--clearance-m", type=float, default=1e-4)
    parser.add_argument("--wear-factor", type=float, default=100.0,
                        help="wear acceleration factor (default %(default)s)")
    parser.add_argument("--step", type=float, default=1e-5, help="solver step [s] (default %(default)s)")
    args = parser.parse_args(argv)
    try:
        require("revolutions", args.revolutions, math.isfinite(args.revolutions) and args.revolutions > 0, "> 0")
        model = FourBarModel(clearance_m=args.clearance_m, wear_factor=args.wear_factor)
        run = model.simulate(args.revolutions * 60.0 / model.linkage.crank_speed_rpm, args.step, progress=True)
    except ParameterError as exc:        # named as written: --step, not step_s
        print(f"four_bar: error: {with_options(exc, OPTIONS)}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    error = run["rocker_angle_rad"] - run["ideal_rocker_angle_rad"]
    summary = {"revolutions": args.revolutions, "completed": run["completed"],
               "simulated_time_s": float(run["time_s"][-1]),
               "wall_time_s": run["wall_time_s"], "solver": "exudyn GeneralizedAlpha", "step_s": args.step,
               "solver_steps": run["solver_steps"], "newton_iterations_per_step": run["newton_iterations_per_step"],
               "clearance_m": args.clearance_m, "wear_factor": args.wear_factor,
               "max_rocker_angle_error_rad": float(np.abs(error).max()), "linkage": asdict(model.linkage)}
    for name, handle in model.joints.items():
        h = handle.history()
        summary[f"joint_{name}"] = {"max_normal_force_N": float(h["normal_force_N"].max()),
                                    "max_wear_depth_m": handle.joint.max_wear_depth_m,
                                    "max_wear_angle_deg": handle.joint.max_wear_angle_deg,
                                    "worn_volume_m3": handle.joint.worn_volume_m3}
        handle.joint.save_profile(out / f"profile_{name}.csv")
    np.savez_compressed(out / "timeseries.npz", **{k: v for k, v in run.items() if isinstance(v, np.ndarray)})
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    _figures(out, run, model)
    model.close()
    print(json.dumps({k: v for k, v in summary.items() if k != "linkage"}, indent=1))
    if not run["completed"]:
        print(f"four_bar: exudyn's Newton stopped at t = {summary['simulated_time_s']:.6g} s, before "
              f"{args.revolutions} revolutions (docs/explanation/four_bar.md, Limits); the results up to there are in {out}",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
