"""The wearing clearance joint in any exudyn mechanism (docs/reference/exudyn.md §8).

    from wearjoint.exudyn import add_clearance_joint
    handle = add_clearance_joint(mbs, pin_body, bushing_body, JointParameters(...))
    mbs.Assemble(); exu.SolveDynamic(mbs, settings)
    handle.joint.wear_profile, handle.result(), handle.history()

``pin_body`` and ``bushing_body`` are object numbers of ``ObjectRigidBody2D`` bodies or of an
``ObjectGround`` (either side, not both).  The pin and bushing centres sit at the
``JointParameters`` offsets in each body's frame, relative to the body's reference point (its
node); for ground, relative to the ground's reference position (the global origin by default).
Each joint is one zero-mass ``ObjectGenericODE2`` on the bodies' nodes whose force user function
returns the contact forces and torques of :meth:`wearjoint.ClearanceJoint.evaluate_array` (the
same kernels as the monolithic engine and the FMU: Eqs. 1-23), so exudyn's implicit
(generalized-alpha) and explicit solvers see them on the right-hand side; its Jacobian user function
returns the same kernel's exact derivatives (:func:`wearjoint.core.contact.contact_jacobian`) in one compiled call.  Wear
and the contact-onset memory advance once per accepted step (Eqs. 24-35), in a post-step function
that serves every joint of the system (one compiled call per joint) and then calls the user's own
post-step function, if one was set before the first joint was added (one set later would replace it: the
solve then stops within :data:`UNACCEPTED_FORCE_TIMES` steps, naming :func:`set_post_step`).
:func:`simulation_settings` gives exudyn's settings with Newton's absolute tolerance above the contact's round-off
floor.  The post-step function also refuses a solver step
longer than :data:`MAX_WEAR_STEP_S` while a joint wears (SolveDynamic then raises, naming the step) and
warns once if a step's share k_f k_w F v dt of the contact's penetration passed its limit
(:attr:`JointParameters.wear_step_share`, docs/reference/model.md §7).

exudyn prints "detected large amount of memory allocations ... this may be due to user functions" for
every system with a clearance joint: its force and Jacobian user functions hand exudyn a new numpy
array per call, which exudyn counts.  It is harmless: that conversion is part of the measured cost
per step (`python benchmarks/bench_exudyn_joint.py`).  :func:`solve_dynamic` is ``exu.SolveDynamic`` without that warning.

The first solve of a process compiles the joint's numba kernels unless numba's cache holds them (the first use
after an install or a change of the sources: tens of seconds): once that has lasted two seconds, one line on stderr
says so, then a count of the compilations (:func:`wearjoint._compile.notice.first_use_starts`).

This module and ``validation/`` are the only ones that import exudyn.
"""
from __future__ import annotations

import math
import warnings
from typing import Callable

import exudyn as exu
import numpy as np
from exudyn.itemInterface import ObjectGenericODE2

from ._compile.notice import first_use_over, first_use_starts
from .core import layout as L
from .core.admissibility import wall_overlap
from .core.generalized_coordinates import accept_step, generalized_contact_forces, generalized_force_jacobian
from .core.pressure import foundation_modulus_factor
from .core.wear import STEP_INADMISSIBLE, STEP_OVERSHOT
from .checks import RunDiverged, is_real, refuse
from .joint import ClearanceJoint, ContactResult, overshoot_message
from .parameters import MAX_WEAR_STEP_S, JointParameters, ParameterError, require
from .runner import inadmissible_message

# the columns of ClearanceJointHandle.history(), one row per accepted step
HISTORY_COLUMNS = ("time_s", "normal_force_N", "friction_force_N", "penetration_m", "eccentricity_x_m",
                   "eccentricity_y_m", "pin_force_x_N", "pin_force_y_N", "pin_torque_N_m", "bushing_force_x_N",
                   "bushing_force_y_N", "bushing_torque_N_m", "max_wear_depth_m")
_HISTORY_SLOTS = np.array([L.R_NORMAL_FORCE, L.R_FRICTION_FORCE, L.R_PENETRATION, L.R_ECCENTRICITY_X,
                           L.R_ECCENTRICITY_Y, L.R_PIN_FX, L.R_PIN_FY, L.R_PIN_TORQUE, L.R_BUSHING_FX, L.R_BUSHING_FY,
                           L.R_BUSHING_TORQUE])
NEWTON_SAFETY = 10.0     # Newton's absolute tolerance over the residual's round-off floor (simulation_settings)
MAX_STEPS = 2.0 ** 53    # simulation_settings' most steps (whole floats)
# a joint whose force has been asked at this many times after its last accepted step checks that the system's
# post-step function is still the joints' (a step takes 1 time with generalized-alpha, up to 7 with an explicit solver)
UNACCEPTED_FORCE_TIMES = 64
_EPSILON = float(np.finfo(float).eps)


_OTHER_INDICES = (exu.NodeIndex, exu.MarkerIndex, exu.LoadIndex, exu.SensorIndex)


class _Body:
    """One side of the joint: a planar rigid body's node, or ground (fixed)."""

    def __init__(self, mbs, argument: str, number):
        if isinstance(number, _OTHER_INDICES):     # a node's or marker's number: it may be an object's number too
            raise ParameterError(f"{argument}={int(number)} is invalid: it is an exudyn {type(number).__name__}, "
                                 "not an object's (allowed: the number mbs.AddObject returned for an "
                                 "ObjectRigidBody2D or ObjectGround)")
        try:
            item = mbs.GetObject(number)
        except Exception:  # exudyn raises its own error types for unknown numbers
            raise ParameterError(f"{argument}={number!r} is invalid: not an object of this system "
                                 f"(allowed: the number of an ObjectRigidBody2D or ObjectGround)") from None
        kind = item["objectType"]
        if kind not in ("RigidBody2D", "Ground"):
            raise ParameterError(f"{argument}={number!r} is invalid: it is an exudyn {kind} object "
                                 "(allowed: ObjectRigidBody2D or ObjectGround)")
        self.argument, self.number = argument, int(number)    # exudyn's ObjectIndex never equals an int: compare these
        self.node = item["nodeNumber"] if kind == "RigidBody2D" else None
        self.reference, self.position, self.velocity = np.zeros(3), np.zeros(3), np.zeros(3)
        self.read_reference(mbs)

    def read_reference(self, mbs) -> None:
        """The body's reference coordinates (x, y, angle) as the system holds them now, in place (the kernels keep
        these arrays), and its initial ones (:attr:`initial`): a node's reference and initial coordinates, a
        ground's reference position and its rotation about z."""
        if self.node is not None:
            node = mbs.GetNode(self.node)
            self.reference[:] = node["referenceCoordinates"]
            self.initial = self.reference + np.array(node["initialCoordinates"], dtype=float)
            return
        item = mbs.GetObject(self.number)
        rotation = np.array(item["referenceRotation"], dtype=float)    # exudyn keeps it in step with referenceHT
        if not np.allclose((*rotation[2], *rotation[:2, 2]), (0.0, 0.0, 1.0, 0.0, 0.0), rtol=0.0, atol=1e-12):
            raise ParameterError(f"{self.argument}={self.number} is invalid: its ObjectGround's referenceRotation "
                                 "turns it out of the x-y plane (allowed: a rotation about z)")
        position = item["referencePosition"]
        self.reference[:] = (position[0], position[1], math.atan2(rotation[1, 0], rotation[0, 0]))
        self.position[:], self.initial = self.reference, self.reference.copy()       # ground does not move


_SAME_TIME = 1e-12     # times this close (relative, at least 1 s) are one: a continuation's start and the last end
_SAME_STEP = 1e-6      # steps this close (relative) are the solver's fixed step: no solve starts there


# the error a joint's user function raised in the solve under way: exudyn passes on its text inside its own error,
# solve_dynamic raises it as it is
_RAISED: list = []


def _kept(error: Exception) -> Exception:
    _RAISED[:] = [error]
    return error


def _solve_starts_at(mbs, t: float) -> bool:
    """True if t is the start time of the solve under way (exudyn's SolveDynamic stores its settings in mbs.sys, as
    storeSolver, its default, asks): its post-step call for the initial state, not the end of a step."""
    settings = mbs.sys.get("simulationSettings")
    return settings is not None and t == settings.timeIntegration.startTime


class ClearanceJointHandle:
    """One clearance joint in an exudyn system: :attr:`joint` (the :class:`ClearanceJoint`:
    profile, state, save/load), :meth:`result` and :meth:`history`; :attr:`object_number` is
    its ``ObjectGenericODE2``.  :attr:`t` is the time of the last accepted step [s] (or of the solve's start; NaN
    before the first solve), :attr:`accepted_steps` their count over all runs.  The first solve may start at any
    ``startTime``.

    Each later solve whose start time is not :attr:`t` (exudyn's ``SolveDynamic`` starts from the initial
    state, at ``startTime``: a second solve of the same system, from an earlier time or a later one) begins a new
    run: the joint keeps its worn profile (the same bushing; the pending wear batch applied), forgets its contact
    memory (a new trajectory) and accepts every step from the new start time; :meth:`history` gives the last run,
    ``history(run=k)`` an earlier one (:attr:`runs`).  A solve that starts at :attr:`t` (to rounding: 1e-12 s
    relative) continues the run (exudyn's continuation: the final state copied into the initial one,
    ``startTime`` the last end time).  A later start is known by the settings ``SolveDynamic`` stores in
    ``mbs.sys`` (its default ``storeSolver=True``)."""

    def __init__(self, mbs, pin: _Body, bushing: _Body, parameters: JointParameters):
        self.joint = ClearanceJoint(parameters)
        self.pin, self.bushing = pin, bushing
        self._nodes = [body for body in (pin, bushing) if body.node is not None]
        n = 3 * len(self._nodes)
        self._q, self._q_t, self._force = np.zeros(n), np.zeros(n), np.zeros(n)
        self._local_indices = self._indices([np.arange(3 * k, 3 * k + 3) for k in range(len(self._nodes))])
        self._system_indices = None   # the nodes' ODE2 coordinates in the system (after Assemble)
        self._references_read = False  # the bodies' reference coordinates read at this solve's start
        self._history = np.zeros((1024, len(HISTORY_COLUMNS)))
        self._rows = 0
        self._run_starts = [0]        # the first history row of each run
        self.t = math.nan             # no solve yet
        self._last_step = math.nan
        self.accepted_steps = 0
        self._wear_share_warned = False
        self._force_time = math.nan     # the last time the force function was asked at, and how many times
        self._force_times = 0           # since the last accepted step (_check_post_step)
        j = self.joint
        # the kernels' arguments, built once (every array lives as long as the joint and is updated in place)
        self._shared = (pin.reference, bushing.reference, pin.position, pin.velocity, bushing.position,
                        bushing.velocity, j.parameter_vector, j.cos_phi, j.sin_phi, j.wear_depth, j.block_min, j.memory)
        self._force_arguments = (self._q, self._q_t, *self._local_indices, *self._shared, j.result, self._force)
        self._accept_arguments = None   # after Assemble
        self._jacobian_arguments = (*self._force_arguments[:-1], np.zeros((L.N_RESULT, L.N_KINEMATIC_INPUTS)),
                                    np.zeros((n, n)))
        self.object_number = mbs.AddObject(ObjectGenericODE2(
            nodeNumbers=[body.node for body in self._nodes], massMatrix=np.zeros((n, n)),
            forceUserFunction=self.generalized_force, jacobianUserFunction=self.generalized_jacobian))

    def _indices(self, node_indices) -> tuple[np.ndarray, np.ndarray]:
        """(pin, bushing) coordinate indices from one index triple per node of :attr:`_nodes`; ground: empty."""
        triples = iter(node_indices)
        return tuple(np.asarray(() if body.node is None else next(triples), dtype=np.int64)
                     for body in (self.pin, self.bushing))

    def generalized_force(self, mbs, t, item, q, q_t):
        """GenericODE2 force user function: (Fx, Fy, T) on each node's body, applied; one compiled
        call (exudyn calls it per Newton iteration)."""
        first_use_starts("exudyn")        # the first calls compile the kernels (unless numba's cache has them)
        if t != self._force_time:
            if not self._references_read or t < self.t:     # the first solve, or one from before the last step
                self._read_references(mbs)
            self._force_time = t
            self._force_times += 1
            if self._force_times > UNACCEPTED_FORCE_TIMES:
                self._check_post_step(mbs)
        self._q[:], self._q_t[:] = q, q_t
        generalized_contact_forces(*self._force_arguments)
        return self._force

    def generalized_jacobian(self, mbs, t, item, q, q_t, factor_q, factor_q_t):
        """GenericODE2 Jacobian user function: -(factor_q dF/dq + factor_q_t dF/dq_t) of the force above,
        exact (the contact's derivatives), in one compiled call (instead of exudyn's 2n + 1 calls of the
        force)."""
        self._q[:], self._q_t[:] = q, q_t
        arguments = self._jacobian_arguments
        generalized_force_jacobian(*arguments, factor_q, factor_q_t)
        return arguments[-1]

    def _read_references(self, mbs) -> None:
        """The bodies' reference coordinates as the system holds them at the first solve's start and at a later
        solve's from an earlier time (set anew after :func:`add_clearance_joint` by ``mbs.SetNodeParameter``; a
        continuation keeps them), the start checked again (its second step had blamed the step)."""
        self.pin.read_reference(mbs)
        self.bushing.read_reference(mbs)
        _start_eccentricity(self.pin, self.bushing, self.joint.params, " this solve starts from")
        self._references_read = True

    def _check_post_step(self, mbs) -> None:
        """Refuse a system whose post-step function no longer serves the joints (``mbs.SetPostStepUserFunction``
        after :func:`add_clearance_joint`): their wear, contact memory and history would stand still, silently."""
        self._force_times = 0
        current = mbs.GetPostStepUserFunction()
        current = current.get("function") if isinstance(current, dict) else current
        if not isinstance(current, _PostStep):
            raise _kept(ParameterError(f"the system's post-step user function {current!r} is invalid with clearance "
                                       "joints: set by mbs.SetPostStepUserFunction after add_clearance_joint, it "
                                       "replaced the joints' own and they would neither wear nor record a step; allowed: "
                                       "wearjoint.exudyn.set_post_step(mbs, f), which calls f after the joints"))

    def _accept(self, mbs, t: float, q, q_t) -> None:
        """Wear and contact-onset bookkeeping over the accepted step ending at t, then one history row.
        (``mbs`` comes with each call: a handle holding it would make a reference cycle through exudyn's
        C++ side, which Python's collector cannot see, and keep the whole system alive.)"""
        dt = t - self.t
        if math.isnan(dt) or abs(dt) <= _SAME_TIME * max(1.0, abs(t)):   # exudyn's call for a solve's initial state
            self.t, self._force_times = t, 0    # (the first, or a continuation's: its start the last end, to rounding);
            return                # the force there (initial accelerations) is the first step's start, not inside it
        if dt < 0.0 or (not abs(dt - self._last_step) <= _SAME_STEP * dt and _solve_starts_at(mbs, t)):
            self._new_run(t)      # a solve from an earlier time, or a later one than the last step's end
            return
        j = self.joint
        wear_rate = j.parameter_vector[L.P_WEAR_COEFFICIENT]
        if wear_rate > 0.0 and dt > MAX_WEAR_STEP_S * (1.0 + 1e-9):
            raise _kept(ParameterError(f"the solver's step {dt:.6g} s (t = {t:.6g} s) is invalid with wear: allowed "
                                       f"at most {MAX_WEAR_STEP_S:g} s; set timeIntegration.numberOfSteps to at least "
                                       f"endTime / {MAX_WEAR_STEP_S:g}, e.g. settings = wearjoint.exudyn.simulation_"
                                       "settings(end_time_s, 1e-5), or wear_factor=0 (docs/reference/model.md §7)"))
        if self._system_indices is None:
            self._system_indices = self._indices([mbs.systemData.GetNodeLTGODE2(body.node) for body in self._nodes])
            self._accept_arguments = (*self._system_indices, *self._shared, j.mask, j.work, j.result, _HISTORY_SLOTS)
        if self._rows == self._history.shape[0]:
            self._history = np.concatenate([self._history, np.zeros_like(self._history)])
        # an implicit solver (generalized-alpha: equilibrium at the step's end) evaluates the force only at t: the
        # force it applied over the step is that one; an explicit one also inside the step (the trapezoid of its start
        # and end force).  With the trapezoid, generalized-alpha wore 22 % short of Archard at wear_factor 100, 1e-5 s
        at_end = self._force_times == 1 and self._force_time == t
        self._force_times = 0
        code = accept_step(*self._accept_arguments, q, q_t, t, dt, at_end, self._history, self._rows)
        first_use_over()
        if code == STEP_INADMISSIBLE:            # nothing changed (docs/reference/model.md §3.14)
            starting = self._rows - self._run_starts[-1] <= 1     # the run's first accepted point is exempt
            raise _kept(RunDiverged(inadmissible_message(
                t, wall_overlap(j.result, j.parameter_vector, j.wear_depth), j.result[L.R_NORMAL_FORCE], j.params,
                "the run's second step" if starting else "exudyn's step", float(j.wear_depth.max()),
                "the run started there: check the bodies' initial coordinates and the joint's offsets" if starting
                else "take a shorter step or an adaptive integrator")))
        self._rows += 1
        self.t, self._last_step = t, dt
        self.accepted_steps += 1
        if code == STEP_OVERSHOT and not self._wear_share_warned:   # (docs/reference/model.md §7)
            self._wear_share_warned = True
            warnings.warn(f"at t = {t:.6g} s {overshoot_message(dt, j.params)}", RuntimeWarning, stacklevel=2)

    def _new_run(self, t: float) -> None:
        """A solve starting at ``t`` [s], before the last accepted step: a new run (a new history segment, the
        joint :meth:`~ClearanceJoint.restart`-ed) if the last one accepted a step, from ``t`` on."""
        if self._rows > self._run_starts[-1]:
            self.joint.restart()
            self._run_starts.append(self._rows)
        self.t = t

    def result(self) -> ContactResult:
        """The contact at the end of the last accepted step (before that step's wear), its extent (half-width, mean
        pressure, contact arc) on the profile as worn now."""
        return self.joint._contact_result(self.joint.result.copy(), self.joint.wear_depth)

    @property
    def runs(self) -> int:
        """How many runs the history holds: the first, and one per solve that started before the last accepted
        step."""
        return len(self._run_starts)

    def history(self, run: int = -1) -> dict:
        """One row per accepted step of a run (default the last; 0 the first, as a list index):
        ``{column: array}`` with the columns of :data:`HISTORY_COLUMNS` (SI units in the names; forces on each
        body in the global frame, the eccentricity in the bushing frame, penetration negative for the gap)."""
        runs = self.runs
        require("run", run, isinstance(run, (int, np.integer)) and not isinstance(run, bool) and -runs <= run < runs,
                f"an integer in [{-runs}, {runs - 1}] (this handle has {runs} run(s))")
        ends = [*self._run_starts[1:], self._rows]
        rows = slice(self._run_starts[run], ends[run])
        return {name: self._history[rows, k].copy() for k, name in enumerate(HISTORY_COLUMNS)}


class _PostStep:
    """The system's post-step function: every joint accepts the step, then the user's function runs."""

    def __init__(self, user_function: Callable | None):
        self.handles: list[ClearanceJointHandle] = []
        self.user_function = user_function

    def __call__(self, mbs, t):
        data = mbs.systemData
        q, q_t = data.GetODE2Coordinates(), data.GetODE2Coordinates_t()
        for handle in self.handles:
            handle._accept(mbs, t, q, q_t)
        return True if self.user_function is None else self.user_function(mbs, t)


def _post_step(mbs, install: bool = True) -> _PostStep | None:
    """The system's :class:`_PostStep`, installed over the user's function if there is none yet (else None)."""
    current = mbs.GetPostStepUserFunction()          # 0, or {"function": f, "type": "Python"}
    current = current.get("function") if isinstance(current, dict) else None
    if isinstance(current, _PostStep) or not install:
        return current if isinstance(current, _PostStep) else None
    dispatcher = _PostStep(current if callable(current) else None)
    mbs.SetPostStepUserFunction(dispatcher)
    return dispatcher


def set_post_step(mbs, user_function: Callable | None) -> None:
    """Set the user's post-step function ``f(mbs, t) -> bool`` of a system with clearance joints:
    it runs after the joints have accepted each step (``mbs.SetPostStepUserFunction`` would replace
    the joints' own); None removes it."""
    if not (user_function is None or callable(user_function)):
        refuse("user_function", user_function, "a function f(mbs, t) -> bool, or None")
    _post_step(mbs).user_function = user_function


def add_clearance_joint(mbs, pin_body, bushing_body, parameters: JointParameters) -> ClearanceJointHandle:
    """Add a wearing clearance joint between ``pin_body`` and ``bushing_body`` (object numbers of
    ``ObjectRigidBody2D`` or ``ObjectGround``) of the exudyn system ``mbs``, before
    ``mbs.Assemble()``; any number per system.  The pin centre must lie within the radial clearance at the initial
    configuration, or past it by at most the admissible penetration (a preload; docs/reference/model.md §3.14).
    Raises ParameterError naming the argument."""
    if not isinstance(mbs, exu.MainSystem):
        shown = repr(mbs) if "\n" not in repr(mbs) and len(repr(mbs)) <= 80 else f"<a {type(mbs).__name__}>"
        raise ParameterError(f"mbs={shown} is invalid: allowed an exudyn MainSystem "
                             "(exudyn.SystemContainer().AddSystem())")
    if not isinstance(parameters, JointParameters):
        raise ParameterError(f"parameters={parameters!r} is invalid: allowed a wearjoint.JointParameters")
    pin, bushing = _Body(mbs, "pin_body", pin_body), _Body(mbs, "bushing_body", bushing_body)
    if pin.number == bushing.number:
        raise ParameterError(f"bushing_body={bushing_body!r} is invalid: it is pin_body too (allowed: another body)")
    if pin.node is not None and bushing.node is not None and int(pin.node) == int(bushing.node):
        raise ParameterError(f"bushing_body={bushing_body!r} is invalid: it moves with node {int(pin.node)}, "
                             "pin_body's (allowed: a body on another node)")
    if pin.node is None and bushing.node is None:
        raise ParameterError(f"bushing_body={bushing_body!r} is invalid: pin_body is ground too "
                             "(allowed: a rigid body on at least one side)")
    for body in (pin, bushing):
        require(body.argument, body.number, np.isfinite(body.initial).all(), "a body whose coordinates (x, y, angle) "
                f"are finite at the initial configuration (they are {tuple(body.initial.tolist())})")
    p = parameters
    for k, other in enumerate(getattr(_post_step(mbs, install=False), "handles", ())):   # one bushing: half the load each
        q = other.joint.params            # within the clearance: 1 nm apart had passed
        near, there = max(p.clearance_m, q.clearance_m), ((other.pin.number, q.pin_offset_m),
                                                          (other.bushing.number, q.bushing_offset_m))
        same = all(any(b == c and math.dist(o, u) <= near for c, u in there)
                   for b, o in ((pin.number, p.pin_offset_m), (bushing.number, p.bushing_offset_m)))
        require("bushing_body", bushing_body, not same, f"a place no other joint has: joint {k} of this system joins "
                f"these bodies within the clearance ({near:g} m) of these offsets (two would each carry half the load)")
    _start_eccentricity(pin, bushing, p)
    handle = ClearanceJointHandle(mbs, pin, bushing, parameters)
    _post_step(mbs).handles.append(handle)
    return handle


def _start_eccentricity(pin: _Body, bushing: _Body, p: JointParameters, when: str = "") -> float:
    """|pin centre - bushing centre| [m] at the bodies' initial coordinates; ParameterError unless within the clearance
    and the admissible penetration (§3.14; ``when`` qualifies "the initial configuration")."""
    pin_centre, bushing_centre = (complex(*body.initial[:2]) + np.exp(1j * body.initial[2]) * complex(*offset)
                                  for body, offset in ((pin, p.pin_offset_m), (bushing, p.bushing_offset_m)))
    if not (e := abs(pin_centre - bushing_centre)) <= p.clearance_m + p.admissible_penetration_m:
        where = "outside the bushing" if e > p.bushing_radius_m else "deeper in its wall than any contact reaches"
        raise _kept(ParameterError(   # kept: raised inside a solve, solve_dynamic raises it as it is
            f"parameters pin_offset_m={p.pin_offset_m} and bushing_offset_m={p.bushing_offset_m} are invalid for these "
            f"bodies: they put the pin centre {e:.6g} m from the bushing centre at the initial configuration{when}, "
            f"{where}: allowed at most the clearance and the admissible penetration, {p.clearance_m:.6g} + "
            f"{p.admissible_penetration_m:.6g} m (docs/reference/model.md §3.14)"))
    return e


def contact_stiffness_bound(parameters: JointParameters) -> float:
    """An upper bound [N/m] of the joint's force derivative in the eccentricity, friction included: (1 + mu) times,
    with the foundation, its stiffness in full conformity, pi k_f L R_j ~ 1.67 K sqrt(c) (the resultant's Jacobian
    k_f L R_j/R_i int d d^T dphi over the arcs in contact, |d| = R_i); with the deepest point, n K c^(n-1)."""
    p = parameters
    if p.contact_model == "foundation":
        kappa = foundation_modulus_factor(p.stiffness_N_m1_5, p.pin_radius_m, p.bushing_radius_m)
        stiffness = math.pi * kappa * p.pin_radius_m * p.bushing_radius_m
    else:
        stiffness = p.contact_exponent * p.stiffness_N_m1_5 * p.clearance_m ** (p.contact_exponent - 1.0)
    return (1.0 + p.friction_coefficient) * stiffness


def solve_dynamic(mbs, settings, **options):
    """``exu.SolveDynamic(mbs, settings, **options)`` without exudyn's memory-allocation warning, which a clearance
    joint's user functions always raise (a new array per call, counted by exudyn; harmless): exudyn's threshold
    (``exudyn.solver.solverCheckMemoryAllocationsThreshold``) is lifted for the call and restored after.  A first
    solve that fails before its first accepted step closes its compile watch here.  An error a joint raised inside
    the solve (a step too long for wear, a run that blew up) is raised as it is (ParameterError, RunDiverged), not
    as exudyn's error around its text."""
    import exudyn.solver as solver

    threshold = solver.solverCheckMemoryAllocationsThreshold
    solver.solverCheckMemoryAllocationsThreshold = math.inf
    _RAISED.clear()
    try:
        return exu.SolveDynamic(mbs, settings, **options)
    except Exception:
        if _RAISED:
            raise _RAISED.pop() from None
        raise
    finally:
        solver.solverCheckMemoryAllocationsThreshold = threshold
        first_use_over()


def simulation_settings(end_time_s: float, step_s: float, handles=(), coordinate_scale_m: float = 1.0
                        ) -> "exu.SimulationSettings":
    """exudyn settings for ``end_time_s`` [s] in whole fixed steps of at most ``step_s`` [s] (the fewest such),
    quiet: no solution file, no console output, sensors sampled at every step (exudyn's default, every
    0.01 s, reads an impact tens of us long as a fraction of its peak; add them with ``storeInternal=True``
    to read them back), with Newton's absolute tolerance above
    the contact's round-off floor (docs/reference/exudyn.md §8): exudyn's residual M a - f [N, N m] cannot fall
    below the jump of the contact force when a position crosses one rounding step, k eps X (k the
    contact's stiffness, at most :func:`contact_stiffness_bound` of the ``handles``' joints, or of
    the paper's joint without handles; X = ``coordinate_scale_m`` [m], the largest |coordinate| of a
    pin or bushing centre, or |angle| x offset of a turning body), and a body at rest starts each
    step already at that floor, so only the absolute tolerance can end Newton there: it is
    :data:`NEWTON_SAFETY` k eps X (3e-6 N for the paper's joint at X = 1 m), a joint load F then
    resolved to that over F.  The relative tolerance stays exudyn's; modified Newton updates the
    Jacobian after 2 iterations without convergence instead of 8 (fewer iterations per step)."""
    require("end_time_s", end_time_s, _positive(end_time_s), "a finite time > 0 s")
    handles = _checked_handles(handles)
    check_step(step_s, handles)
    require("step_s", step_s, end_time_s / step_s <= MAX_STEPS,
            f"at least end_time_s / 2**53 = {end_time_s / MAX_STEPS:g} s")
    require("coordinate_scale_m", coordinate_scale_m, _positive(coordinate_scale_m), "a finite length > 0 m")
    stiffness = max((contact_stiffness_bound(h.joint.params) for h in handles),
                    default=contact_stiffness_bound(JointParameters()))
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = end_time_s
    # at most step_s: rounding to the nearest count could give a step over it, which the wear-step check refuses
    settings.timeIntegration.numberOfSteps = max(1, math.ceil(end_time_s / step_s * (1.0 - 1e-12)))
    newton = settings.timeIntegration.newton
    newton.absoluteTolerance = NEWTON_SAFETY * _EPSILON * coordinate_scale_m * stiffness
    newton.maxModifiedNewtonIterations = 2      # exudyn's default: 8
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = end_time_s / settings.timeIntegration.numberOfSteps
    return settings


def check_step(step_s: float, handles) -> None:
    """Refuse, before a run, a fixed solver step ``step_s`` [s] the joints cannot work with: with wear, at
    most :data:`MAX_WEAR_STEP_S`.  (The joints' post-step function checks every accepted step anyway.)"""
    require("step_s", step_s, _positive(step_s), "a finite step > 0 s")
    wearing = [h for h in _checked_handles(handles) if h.joint.parameter_vector[L.P_WEAR_COEFFICIENT] > 0.0]
    if wearing and step_s > MAX_WEAR_STEP_S:
        raise ParameterError(f"parameter step_s={step_s!r} is invalid with wear: allowed at most {MAX_WEAR_STEP_S!r} s "
                             "(set wear_factor=0 for a longer step)")


def _positive(value) -> bool:
    """Whether ``value`` is a finite real number > 0."""
    return is_real(value) and math.isfinite(value) and value > 0.0


def _checked_handles(handles) -> tuple:
    """``handles`` as a tuple of :class:`ClearanceJointHandle`, else ParameterError."""
    try:
        checked = tuple(handles)
    except TypeError:
        checked = (None,)
    if isinstance(handles, str) or not all(isinstance(h, ClearanceJointHandle) for h in checked):
        refuse("handles", handles, "a sequence of the handles add_clearance_joint returned")
    return checked


__all__ = ["add_clearance_joint", "set_post_step", "check_step", "simulation_settings", "solve_dynamic",
           "contact_stiffness_bound", "ClearanceJointHandle", "HISTORY_COLUMNS", "MAX_WEAR_STEP_S", "NEWTON_SAFETY",
           "UNACCEPTED_FORCE_TIMES"]
