"""The paper's slider-crank built natively in exudyn 1.13: an independent
check of the monolithic engine (:mod:`wearjoint.simulate`).

Crank, rod and slider are ``NodeRigidBody2D`` + ``ObjectRigidBody2D`` with the
nodes at the centres of mass (so the inertias are about the COM, docs/reference/model.md §7);
gravity is a mass-proportional load; the crank pivot, the rod-slider and the crank-rod joints
are ``ObjectJointRevolute2D`` but the clearance joint (``clearance_joint``); the slider runs on an ``ObjectJointPrismatic2D``
along X with its rotation constrained; the crank is driven by an
``ObjectConnectorCoordinate`` whose offset acts on the displacement from the
reference angle, offset(t) = -omega t (theta1 = theta0 - omega t).

``ideal=True`` closes the clearance joint with a revolute joint too.  Otherwise
the clearance joint goes in through the public helper
:func:`wearjoint.exudyn.add_clearance_joint` (its pin body and bushing body, core.joint_location):
a zero-mass ``ObjectGenericODE2`` on their nodes applies the clearance
force pair (Eqs. 20-23) on exudyn's right-hand side, and wear and the contact-onset
bookkeeping advance once per accepted step, before this model's recorder runs.

``contact="native"`` replaces the helper by exudyn's own contact
(``ObjectContactSphereSphere``, a pin in a hollow sphere: :mod:`.exudyn_native`), an
independent contact law in exudyn's C++ code, unworn; the joint's result is read from it
after every accepted step.

Only validation/ (this model, the pendulum, the four-bar) and wearjoint.exudyn import exudyn.
"""
from __future__ import annotations

import math
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    LoadForceVector, LoadMassProportional, MarkerBodyMass, MarkerBodyPosition, MarkerBodyRigid, MarkerNodeCoordinate,
    NodePointGround, NodeRigidBody2D, ObjectConnectorCoordinate, ObjectGround, ObjectJointPrismatic2D,
    ObjectJointRevolute2D, ObjectRigidBody2D,
)

from wearjoint.core import layout as L
from wearjoint.core.integrators import record_step
from wearjoint.core.slider_load import slider_load
from wearjoint.exudyn import add_clearance_joint, set_post_step, solve_dynamic
from wearjoint.joint import ClearanceJoint
from wearjoint.slider_crank import SliderCrank
from wearjoint.parameters import (
    JointParameters, ParameterError, SliderCrankParameters, finite, require, check_joint_fits_mechanism,
)
from wearjoint.progress import Progress
from wearjoint.results import RunParameters, RunRecord, new_revolution_stats, new_track
from wearjoint.validation.exudyn_native import NativeContact, native_contact_forces, native_contact_parameters

CONTACT_FORMULATIONS = ("discrete", "native")
DISCRETE = 0
NATIVE = 1
SAMPLE_BLOCK_ROWS = 4096     # samples are collected in blocks of this many rows
SPECTRAL_RADIUS = 0.9        # generalized-alpha rho_inf (exudyn's default; 1 = no numerical damping)


def _contact_formulation(contact: str) -> int:
    require("contact", contact, contact in CONTACT_FORMULATIONS, "one of " + ", ".join(CONTACT_FORMULATIONS))
    return CONTACT_FORMULATIONS.index(contact)


def _kinematics(name: str, values) -> tuple[np.ndarray, np.ndarray]:
    k = np.asarray(values, dtype=float)
    if k.shape != (6,) or not np.all(np.isfinite(k)):
        raise ParameterError(f"{name} must be 6 finite numbers (x, y, angle, vx, vy, omega), got {values!r}")
    return k[:3].copy(), k[3:].copy()


def contact_forces(joint: ClearanceJoint, pin_kinematics, bushing_kinematics,
                   contact: str = "discrete") -> np.ndarray:
    """The joint's result array (layout.R_*) for the given kinematics, computed by the
    wearjoint kernels (``ClearanceJoint.evaluate_array``) or by exudyn's own contact
    (:func:`.exudyn_native.native_contact_forces`, given the joint's stored delta_dot^- while a
    contact is active); kinematics = (x [m], y [m], angle [rad], vx, vy, omega) of each
    body's reference point, global frame.  The joint's state is read, not changed."""
    formulation = _contact_formulation(contact)
    pos_i, vel_i = _kinematics("pin_kinematics", pin_kinematics)
    pos_j, vel_j = _kinematics("bushing_kinematics", bushing_kinematics)
    if formulation == DISCRETE:
        return joint.evaluate_array(pos_i, vel_i, pos_j, vel_j).copy()
    memory = joint.memory
    impact_velocity = memory[L.M_IMPACT_VELOCITY] if memory[L.M_ACTIVE] > 0.5 else 0.0
    return native_contact_forces(joint.params, pos_i, vel_i, pos_j, vel_j, impact_velocity)


class ExudynSliderCrank:
    """The slider-crank as an exudyn system (see module docstring), with its
    per-step recording into our standard statistics and samples.

    ``initial_state`` = [q (9), q_dot (9)] (q = crank, rod, slider: x, y, angle at
    the centres of mass); default: :meth:`SliderCrank.initial_state` (pin centred,
    ideal velocities).  It must satisfy the mechanism's constraints.
    """

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 contact: str = "discrete", ideal: bool = False, initial_state=None):
        self.mechanism = SliderCrank(mechanism)
        mp = self.mechanism.params
        joint = joint or JointParameters(**mp.joint_defaults())
        check_joint_fits_mechanism(joint, mp)
        self.formulation = _contact_formulation(contact)
        if self.formulation == NATIVE and not ideal and joint.wear_coefficient_m2_N * joint.wear_factor > 0.0:
            raise ParameterError("contact='native' (exudyn's own contact) cannot wear: set "
                                 "wear_factor=0 (or wear_coefficient_m2_N=0) or use contact='discrete'")
        self.joint_parameters = joint
        self.ideal = bool(ideal)
        y0 = self.mechanism.initial_state() if initial_state is None else np.array(initial_state, dtype=float)
        if y0.shape != (2 * L.N_COORDINATES,) or not np.all(np.isfinite(y0)):
            raise ParameterError(f"initial_state must be {2 * L.N_COORDINATES} finite numbers [q, q_dot]")
        n = L.N_COORDINATES
        theta0 = self.mechanism.parameter_vector[L.MP_THETA0]
        if abs(y0[L.CRANK + 2] - theta0) > 1e-12 or abs(y0[n + L.CRANK + 2] + mp.omega_rad_s) > 1e-9:
            raise ParameterError(f"initial_state: the crank angle and rate must follow the driver, "
                                 f"{theta0!r} rad and {-mp.omega_rad_s!r} rad/s; got {y0[L.CRANK + 2]!r}, "
                                 f"{y0[n + L.CRANK + 2]!r}")
        self.reference = y0[:n].copy()                     # node reference coordinates = initial q
        self.y = y0.copy()
        self.dy = np.zeros_like(y0)
        self.t = 0.0
        self.accepted_steps = 0
        self.wear_growth = []
        self._progress = None
        self.system_container = exu.SystemContainer()
        self.mbs = self.system_container.AddSystem()
        self._build(y0)

    # ------------------------------------------------------------------ model
    def _build(self, y0: np.ndarray) -> None:
        mbs = self.mbs
        p = self.mechanism.params
        n = L.N_COORDINATES
        bodies = ((p.crank_mass_kg, p.crank_inertia_kg_m2), (p.rod_mass_kg, p.rod_inertia_kg_m2),
                  (p.slider_mass_kg, p.slider_inertia_kg_m2))
        self.nodes = []
        self.bodies = []
        for k, (mass, inertia) in enumerate(bodies):
            node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=list(y0[3 * k:3 * k + 3]),
                                               initialCoordinates=[0.0, 0.0, 0.0],
                                               initialVelocities=list(y0[n + 3 * k:n + 3 * k + 3])))
            body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=mass, inertia=inertia))
            mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                             loadVector=[*p.gravity_m_s2, 0.0]))
            self.nodes.append(node)
            self.bodies.append(body)
        crank, rod, slider = self.bodies
        if p.loaded:                                                     # the slider's load, the kernels' own
            mp_vector = self.mechanism.parameter_vector
            mbs.AddLoad(LoadForceVector(
                markerNumber=mbs.AddMarker(MarkerBodyPosition(bodyNumber=slider, localPosition=[0.0, 0.0, 0.0])),
                loadVector=[0.0, 0.0, 0.0],
                loadVectorUserFunction=lambda mbs_, t, load: [-slider_load(t, mp_vector), 0.0, 0.0]))
        ground = mbs.AddObject(ObjectGround())
        l1 = p.crank_length_m
        l2 = p.rod_length_m

        def revolute(body_a, local_a, body_b, local_b):
            mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=body_a, localPosition=[*local_a, 0.0])),
                mbs.AddMarker(MarkerBodyPosition(bodyNumber=body_b, localPosition=[*local_b, 0.0]))]))

        # the three revolutes (pin body, its point; bushing body, its point), the clearance joint's left open
        revolutes = {"crank-rod": (crank, (0.5 * l1, 0.0), rod, (-0.5 * l2, 0.0)),
                     "rod-slider": (slider, (0.0, 0.0), rod, (0.5 * l2, 0.0)),
                     "crank-ground": (crank, (-0.5 * l1, 0.0), ground, (0.0, 0.0))}
        pin_body, _, bushing_body, _ = revolutes[p.clearance_joint]
        for name, pair in revolutes.items():
            if name != p.clearance_joint or self.ideal:
                revolute(*pair)
        mbs.AddObject(ObjectJointPrismatic2D(                            # slider on X, rotation fixed
            markerNumbers=[mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0])),
                           mbs.AddMarker(MarkerBodyRigid(bodyNumber=slider, localPosition=[0.0, 0.0, 0.0]))],
            axisMarker0=[1.0, 0.0, 0.0], normalMarker1=[0.0, 1.0, 0.0], constrainRotation=True))
        omega = p.omega_rad_s
        ground_node = mbs.AddNode(NodePointGround())
        mbs.AddObject(ObjectConnectorCoordinate(                         # driver: th1 - th0 = -omega t
            markerNumbers=[mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0)),
                           mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=self.nodes[0], coordinate=2))],
            offsetUserFunction=lambda mbs_, t, item, offset: -omega * t))
        self.native = None
        if self.ideal or self.formulation == NATIVE:
            self.joint = ClearanceJoint(self.joint_parameters)        # unworn; its result: zero, or read from exudyn
            if not self.ideal:
                self.native = NativeContact(mbs, pin_body, bushing_body, self.joint_parameters)
        else:
            self.joint = add_clearance_joint(mbs, pin_body, bushing_body, self.joint_parameters).joint
        set_post_step(mbs, self.post_step)
        mbs.Assemble()
        for k, node in enumerate(self.nodes):
            if list(mbs.systemData.GetNodeLTGODE2(node)) != [3 * k, 3 * k + 1, 3 * k + 2]:
                raise RuntimeError("exudyn ordered the ODE2 coordinates unexpectedly; q must be crank, rod, slider")

    def close(self) -> None:
        """Release the exudyn system: its user functions refer to this model, a reference cycle
        through exudyn's C++ side that Python's collector cannot break."""
        self.system_container.Reset()

    # ------------------------------------------------------------------ stepping
    def post_step(self, mbs, t):
        """Once per accepted step, after the clearance joint's own bookkeeping (wear, contact
        onsets) at the step's end: our recorder."""
        dt = t - self.t
        if dt <= 0.0:               # exudyn also calls it once for the initial state
            return True
        sd = mbs.systemData
        n = L.N_COORDINATES
        y = self.y
        dy = self.dy
        q_t = sd.GetODE2Coordinates_t()
        y[:n] = self.reference + sd.GetODE2Coordinates()
        y[n:] = q_t
        dy[:n] = q_t
        dy[n:] = sd.GetODE2Coordinates_tt()
        joint = self.joint
        if self.native is not None:
            self.native.read(mbs, joint.result)
        record_step(t, dt, y, dy, joint.result, self.mechanism.parameter_vector, self.revolution_stats,
                    self._sample_block, self.track)
        if self.track[L.K_N_SAMPLES] >= self._sample_block.shape[0]:
            self._flush_samples()
        if t >= (len(self.wear_growth) + 1) * self.mechanism.params.period_s * (1.0 - 1e-12):
            self.wear_growth.append(joint.max_wear_depth_m)
        self.t = t
        self.accepted_steps += 1
        if self.accepted_steps % 1000 == 0 and self._progress is not None:
            self._progress.update(t)
        return True

    def _flush_samples(self) -> None:
        n = int(self.track[L.K_N_SAMPLES])
        self._sample_blocks.append(self._sample_block[:n].copy())
        self.track[L.K_N_SAMPLES] = 0

    def simulate(self, end_time_s: float, step_s: float = 1e-5, sample_dt_s: float = 1e-5,
                 spectral_radius: float = SPECTRAL_RADIUS, progress: bool = False) -> None:
        """Integrate from t = 0 to ``end_time_s`` [s] with exudyn's implicit
        generalized-alpha solver at the fixed step ``step_s`` [s] (rounded so that
        whole steps end at ``end_time_s``); fills :attr:`samples`,
        :attr:`revolution_stats`, :attr:`wear_growth`.  Call once per instance."""
        require("end_time_s", end_time_s, finite("end_time_s", end_time_s) > 0.0, "> 0")
        require("step_s", step_s, 0.0 < finite("step_s", step_s) <= end_time_s, f"in (0, end_time_s = {end_time_s!r}]")
        require("sample_dt_s", sample_dt_s, finite("sample_dt_s", sample_dt_s) > 0.0, "> 0")
        require("spectral_radius", spectral_radius, 0.0 <= finite("spectral_radius", spectral_radius) <= 1.0,
                 "in [0, 1]")
        if self.accepted_steps or self.t > 0.0:
            raise RuntimeError("ExudynSliderCrank.simulate runs once; build a new model for another run")
        period = self.mechanism.params.period_s
        self.revolution_stats = new_revolution_stats(int(math.ceil(end_time_s / period)) + 1)
        self.track = new_track(sample_dt_s)
        self._sample_block = np.zeros((SAMPLE_BLOCK_ROWS, L.N_SAMPLE_COLUMNS))
        self._sample_blocks = []
        settings = exu.SimulationSettings()
        ti = settings.timeIntegration
        ti.endTime = end_time_s
        ti.numberOfSteps = max(1, int(math.ceil(end_time_s / step_s - 1e-9)))
        ti.verboseMode = 0
        ti.generalizedAlpha.spectralRadius = spectral_radius
        if self.native is not None:
            # exudyn's contact recommends a step that ends at a contact onset, |gap / gap rate|: below its
            # minimum step (1e-8 s) the solver stops (at the first impact at 1 us steps); with a smaller
            # minimum, generalized-alpha's accelerations spike to 3e5 m/s^2 over such sliver steps and Newton
            # can stall at a relative residual of 2-3e-8 (stopped at 0.35 s with 1e-12 s).  So fixed steps: its
            # discontinuous iteration switches the contact state within a step (docs/explanation/validation.md).
            ti.discontinuous.useRecommendedStepSize = False
        settings.solution.file.write = False
        settings.solution.sensors.active = False
        settings.show.computationTime = False
        settings.show.statistics = False
        settings.show.globalTimers = False
        self.step_s = end_time_s / ti.numberOfSteps
        self._progress = Progress(end_time_s, "exudyn", enabled=progress)
        wall0 = time.perf_counter()
        try:
            solve_dynamic(self.mbs, settings, solverType=exu.DynamicSolverType.GeneralizedAlpha)
        finally:
            self.wall_time_s = time.perf_counter() - wall0
            self._progress.close()
            self._progress = None
            self._flush_samples()
            self.samples = np.concatenate(self._sample_blocks)
            self.revolution_stats = self.revolution_stats[:max(1, int(math.ceil(self.t / period - 1e-9)))]
        if self.t < end_time_s * (1.0 - 1e-9):
            raise RuntimeError(f"exudyn stopped at t = {self.t:.6g} s before end_time_s = {end_time_s:.6g} s")


def run_exudyn(joint: JointParameters | None, mechanism: SliderCrankParameters | None, revolutions: float,
               step_s: float = 1e-5, contact: str = "discrete", ideal: bool = False, sample_dt_s: float = 1e-5,
               progress: bool = True) -> RunRecord:
    """Simulate ``revolutions`` crank revolutions of the slider-crank in exudyn
    (generalized-alpha, fixed step ``step_s`` [s]; None = the paper's parameters);
    returns the same :class:`RunRecord` as :func:`wearjoint.simulate.run_simulation`,
    with ``parameters.engine == "exudyn"``."""
    require("revolutions", revolutions, finite("revolutions", revolutions) > 0.0, "> 0")
    require("ideal", ideal, isinstance(ideal, bool), "True or False")
    model = ExudynSliderCrank(joint, mechanism, contact=contact, ideal=ideal)
    period = model.mechanism.params.period_s
    try:
        model.simulate(revolutions * period, step_s, sample_dt_s, progress=progress)
    finally:
        model.close()
    j = model.joint
    return RunRecord(
        samples=model.samples, revolution_stats=model.revolution_stats,
        wear_growth_m=np.asarray(model.wear_growth), phi_deg=j.phi_deg, wear_depth_m=j.wear_depth.copy(),
        worn_volume_m3=j.worn_volume_m3, simulated_time_s=model.t, wall_time_s=model.wall_time_s,
        revolutions=model.t / period, period_s=period, clearance_m=j.params.clearance_m,
        contact_stiffness_N_m1_5=j.params.stiffness_N_m1_5,
        parameters=RunParameters("exudyn", j.params, model.mechanism.params, "simulation",
                                 {"revolutions": revolutions, "integrator": "exudyn GeneralizedAlpha",
                                  "step_s": model.step_s, "spectral_radius": SPECTRAL_RADIUS, "contact": contact,
                                  "ideal": ideal, "sample_dt_s": sample_dt_s}),
        extra={"integrator_accepted_steps": model.accepted_steps, "exudyn_version": exu.config.Version()})


# docs/explanation/validation.md, "exudyn's own contact": which law makes it differ.  label -> (contact, joint change).
# Our friction with v0 = 0, v1 = v_reg is exudyn's proportional zone (and maps to the same exudyn contact).
_ZONE = {"friction_v0_m_s": 0.0, "friction_v1_m_s": native_contact_parameters(JointParameters())["frictionProportionalZone"]}
LAW_STUDY = {
    "ours (foundation)": ("discrete", {}),
    "ours, deepest": ("discrete", {"contact_model": "deepest"}),
    "ours, deepest, N_d = 5028": ("discrete", {"contact_model": "deepest", "n_points": 5028}),
    "ours, deepest, exudyn's friction zone": ("discrete", {"contact_model": "deepest", **_ZONE}),
    "native": ("native", {}),
    "ours, deepest, mu = 0": ("discrete", {"contact_model": "deepest", "friction_coefficient": 0.0}),
    "native, mu = 0": ("native", {"friction_coefficient": 0.0}),
    "ours, deepest, e_r = 1": ("discrete", {"contact_model": "deepest", "restitution": 1.0}),
    "native, e_r = 1": ("native", {"restitution": 1.0}),
    "ours, deepest, floor 0.1 m/s": ("discrete", {"contact_model": "deepest", "impact_velocity_floor_m_s": 0.1}),
    "native, floor 0.1 m/s": ("native", {"impact_velocity_floor_m_s": 0.1}),
}


def law_study(configurations: dict = LAW_STUDY, ensemble: int = 8, revolutions: float = 5.0, step_s: float = 1e-5,
              progress: bool = False) -> dict:
    """Both exudyn contacts in the same exudyn model (generalized-alpha, fixed ``step_s`` [s]): for each
    label -> (contact, joint change) an ensemble of ``ensemble`` perturbed starts of ``revolutions``
    revolutions, no wear; returns label -> {"mean", "std"} of the validation's statistics."""
    from wearjoint.analysis import ensemble_statistics
    from wearjoint.sweep.design import perturbed_start

    base = SliderCrankParameters()
    joint = JointParameters(**base.joint_defaults(), wear_factor=0.0)
    out = {}
    for label, (contact, change) in configurations.items():
        records = [run_exudyn(joint.replace(**change), perturbed_start(base, k), revolutions, step_s, contact,
                              progress=progress) for k in range(ensemble)]
        mean, std = ensemble_statistics(records)
        out[label] = {"mean": mean, "std": std, "n": ensemble}
    return out


__all__ = ["run_exudyn", "CONTACT_FORMULATIONS", "ExudynSliderCrank", "contact_forces", "law_study", "LAW_STUDY"]


if __name__ == "__main__":      # python -m wearjoint.validation.exudyn_model OUT.json [ENSEMBLE] [REVOLUTIONS]
    import json
    import sys

    result = law_study(ensemble=int(sys.argv[2]) if len(sys.argv) > 2 else 8,
                       revolutions=float(sys.argv[3]) if len(sys.argv) > 3 else 5.0)
    with open(sys.argv[1], "w") as f:
        json.dump(result, f, indent=1)
