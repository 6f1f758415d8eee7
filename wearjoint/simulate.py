"""Monolithic (in-process, no FMI) simulation of the slider-crank with the clearance joint."""
from __future__ import annotations

import importlib
import math

import numpy as np

from .core import layout as L
from .core.integrators import DOPRI5, RK4, WORN_VALUES, accept_point, integrate, record_accepted
from .core.joint_access import JointArrays
from .core.slider_crank import derivative
from .core.slider_crank_jacobian import make_jacobian_workspace, state_jacobian
from .joint import ClearanceJoint
from .slider_crank import SliderCrank
from .parameters import (
    JointParameters, ParameterError, SliderCrankParameters, require, check_joint_fits_mechanism, paper_joint,
)
from .results import RunParameters, RunRecord, new_revolution_stats, new_track
from .checks import RunDiverged
from .runner import inadmissible_message, overload_advice, run_engine
from .simulation_options import (
    DEFAULT_WEAR_STEP_SHARE, GEAR_JACOBIANS, GEAR_SOLVERS, INTEGRATORS, SimulationOptions, check_run_arguments,
    wear_step_limit_s,
)


class Simulation:
    """One slider-crank (ideal or with the clearance joint) and its integration state."""

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 options: SimulationOptions | None = None, initial_profile_m=None):
        """``initial_profile_m``: the bushing's wear depth [m] at every point to start from (a worn bushing;
        default unworn), checked against the joint (n_points, finite, within the bushing radius)."""
        check_run_arguments(joint, mechanism, options, SimulationOptions)
        self.mechanism = SliderCrank(mechanism)
        joint = joint or paper_joint(self.mechanism.params)
        self.options = (options or SimulationOptions()).for_joint(joint, self.mechanism.params)
        check_joint_fits_mechanism(joint, self.mechanism.params)
        o = self.options
        clearance_joint = self.mechanism.params.clearance_joint
        require("gear_jacobian", o.gear_jacobian, o.integrator != "gear" or o.ideal or o.gear_jacobian != "exact"
                or clearance_joint == "crank-rod",
                f"'numerical' with clearance_joint={clearance_joint!r} (the exact Jacobian is the crank-rod joint's)")
        self.joint = ClearanceJoint(joint)
        if initial_profile_m is not None:
            self.joint.set_wear_profile(initial_profile_m)
        self.mode = L.MODE_IDEAL if self.options.ideal else L.MODE_CLEARANCE
        self.t = 0.0
        self.y = self.mechanism.initial_state()
        self.dy = np.empty_like(self.y)
        self.body_forces = np.zeros(6)
        self._accept_scratch = (np.empty(WORN_VALUES), np.empty_like(self.y))   # gear: record_accepted's
        first_step = self.options.step_s if self.options.integrator == "rk4" else min(1e-6, self.options.max_step_s)
        self.control = np.array([first_step, self.options.max_step_s, self.options.rtol,
                                 self.options.atol_position_m, self.options.atol_velocity_m_s,
                                 self.options.min_step_s, self.options.onset_penetration_m,
                                 self.options.free_flight_max_step_s])
        n_rev = int(math.ceil(self.options.revolutions)) + 1
        self.revolution_stats = new_revolution_stats(n_rev)
        self.track = new_track(self.options.sample_dt_s)
        self.accepted = 0
        self.rejected = 0
        # gear: the BDF solvers' counts (right-hand sides outside finite-difference Jacobians, Jacobians,
        # LU decompositions (scipy only)), summed over the solvers (one per advance_to)
        self.solver_counts = {}
        self._integrator_joint = None
        self._derivative()

    @property
    def _joint_arrays(self):
        """The joint the integrator calls: the in-process arrays, or the one :meth:`integrate_with` gave."""
        return self.joint.arrays if self._integrator_joint is None else self._integrator_joint

    def integrate_with(self, joint) -> None:
        """Integrate with ``joint`` in place of the in-process arrays from now on (RK4 or DOPRI): an
        :data:`~wearjoint.cosim.fmu_joint.FmuJoint`, the joint FMU's Model Exchange interface that
        :class:`~wearjoint.cosim.model_exchange.ModelExchangeSimulation` composes with this engine.  The
        derivative at the current state is evaluated through it."""
        self._integrator_joint = joint
        self._derivative()

    def _derivative(self):
        """dy = f(t, y).  RK4 and DOPRI: by their integrator over no time (it evaluates f where it starts), so a
        cold run compiles the right-hand side inside the integrator only, not on its own too."""
        mp, ws = self.mechanism.parameter_vector, self.mechanism.workspace
        if self.options.integrator == "gear":
            derivative(self.t, self.y, self.mode, mp, self._joint_arrays, self.body_forces, ws, self.dy)
        else:
            integrate(self.method_code, self.t, self.t, self.y, self.control, self.mode, mp, self._joint_arrays,
                      self.body_forces, ws, self.dy, self.revolution_stats, np.zeros((0, L.N_SAMPLE_COLUMNS)),
                      self.track)

    @property
    def method_code(self) -> int:
        """The integrators' code of RK4 or DOPRI (not gear)."""
        return RK4 if self.options.integrator == "rk4" else DOPRI5

    def checkpoint(self) -> dict:
        """Everything needed to continue bit-identically (arrays and bytes; picklable)."""
        return {"t": self.t, "y": self.y.copy(), "control": self.control.copy(),
                "joint_state": self.joint.state_to_bytes(), "revolution_stats": self.revolution_stats.copy(),
                "track": self.track.copy(), "accepted": self.accepted, "rejected": self.rejected,
                "solver_counts": dict(self.solver_counts)}

    def restore(self, checkpoint: dict) -> None:
        """Continue from :meth:`checkpoint` (same parameters and options)."""
        self.t = float(checkpoint["t"])
        self.y[:] = checkpoint["y"]
        control = np.asarray(checkpoint["control"])
        self.control[:control.size] = control          # a checkpoint written before the free-flight cap: 7 values
        self.joint.state_from_bytes(checkpoint["joint_state"])
        self.revolution_stats[:] = checkpoint["revolution_stats"]
        self.track[:] = checkpoint["track"]
        self.accepted = int(checkpoint["accepted"])
        self.rejected = int(checkpoint["rejected"])
        self.solver_counts.update(checkpoint.get("solver_counts", {}))
        self._derivative()

    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) of the bushing (bushing body's frame), copies."""
        return self.joint.phi_deg, self.joint.wear_depth.copy(), self.joint.worn_volume_m3

    def max_wear_depth_m(self) -> float:
        return self.joint.max_wear_depth_m

    def set_wear_profile(self, depth_m) -> None:
        """Replace the bushing's wear depths [m] (cycle jumping); the derivative at the current
        state is recomputed with the new profile."""
        self.joint.set_wear_profile(depth_m)
        self._derivative()

    def close(self) -> None:
        """Nothing to free (the co-simulation engine frees its FMU instance here)."""

    @property
    def joint_parameters(self) -> JointParameters:
        return self.joint.params

    def describe(self) -> tuple[RunParameters, dict]:
        """The run record's parameters and the integrator's counts (:class:`wearjoint.runner.Engine`)."""
        parameters = RunParameters("monolithic", self.joint.params, self.mechanism.params, "simulation", self.options)
        extra = {"integrator_accepted_steps": self.accepted, "integrator_rejected_steps": self.rejected,
                 **{"integrator_" + key: value for key, value in self.solver_counts.items()}}
        return parameters, extra

    def warm_up(self) -> None:
        """Compile the kernels :meth:`advance_to` calls (numba) without advancing.  RK4 and DOPRI:
        compiled when the engine was built (:meth:`_derivative` runs their integrator over no time);
        gear: its kernels, on copies of the state."""
        if self.options.integrator != "gear":
            return
        joint = JointArrays(*(a.copy() for a in self._joint_arrays))
        y, dy, forces = self.y.copy(), self.dy.copy(), self.body_forces.copy()
        stats, track = self.revolution_stats.copy(), self.track.copy()
        samples = np.zeros((0, L.N_SAMPLE_COLUMNS))
        mp, ws = self.mechanism.parameter_vector, self.mechanism.workspace
        if self.options.gear_solver == "cvode":
            importlib.import_module("sksundae.cvode")   # here: its import is not part of the run's time
        before, record_dy = self._accept_scratch
        worn = accept_point(self.t, y, 0.0, dy, self.mode, mp, joint, forces, ws, dy.copy(), False, before)
        record_accepted(self.t, 0.0, y, dy, worn, True, before, mp, joint, forces, ws, record_dy, stats, samples, track)
        for function in self._gear_functions(joint):
            if function is not None:
                function(self.t, y)

    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        """Integrate to t_end, writing samples into ``samples``; returns how many."""
        self.track[L.K_N_SAMPLES] = 0
        if self.options.integrator == "gear":
            self._gear_to(t_end, samples)
        else:
            self.t, acc, rej = integrate(self.method_code, self.t, t_end, self.y, self.control, self.mode,
                                         self.mechanism.parameter_vector, self._joint_arrays,
                                         self.body_forces, self.mechanism.workspace, self.dy,
                                         self.revolution_stats, samples, self.track)
            self.accepted += acc
            self.rejected += rej
        failure = self.joint.failure
        if failure[0] != 0.0:
            advice = (overload_advice(self.joint.params, self.mechanism)
                      or "take a shorter step or an adaptive integrator")
            raise RunDiverged(inadmissible_message(failure[1], failure[2], failure[3], self.joint.params,
                                                   "an accepted step", float(self.joint.wear_depth.max()), advice),
                              int(self.track[L.K_N_SAMPLES]))
        return int(self.track[L.K_N_SAMPLES])

    def _gear_to(self, t_end: float, samples: np.ndarray) -> None:
        """BDF of variable order 1-5 (the paper's Gear method): SUNDIALS CVODE (``gear_solver="cvode"``)
        or scipy's, one solver per call, started at order 1; the joint's bookkeeping (wear, contact
        onsets, statistics, samples) at each accepted step, as the other integrators."""
        mp = self.mechanism.parameter_vector
        joint = self._joint_arrays
        rhs, jacobian = self._gear_functions(joint)
        solve = _cvode_steps if self.options.gear_solver == "cvode" else _scipy_bdf_steps
        for t, y in solve(rhs, jacobian, self.t, self.y, t_end, self.options, self.solver_counts):
            h = t - self.t
            self.t = t
            self.y[:] = y
            before, record_dy = self._accept_scratch
            worn = accept_point(self.t, self.y, h, self.dy, self.mode, mp, joint, self.body_forces,
                                self.mechanism.workspace, self.dy, False, before)
            if self.joint.failure[0] != 0.0:
                break
            record_accepted(self.t, h, self.y, self.dy, worn, True, before, mp, joint, self.body_forces,
                            self.mechanism.workspace, record_dy, self.revolution_stats, samples, self.track)
            self.accepted += 1

    def _gear_functions(self, joint: JointArrays):
        """(f, J) for the BDF solvers: f(t, y) = y_dot and J(t, y) = d y_dot / dy (Eqs. 38-44 with the
        joint; J exact, :mod:`wearjoint.core.slider_crank_jacobian`, or None: the solver's finite
        differences, ``gear_jacobian="numerical"`` and the ideal mechanism), each a new array, evaluated
        on a contiguous copy of y (the solvers pass strided or read-only arrays: numba would compile
        each layout apart)."""
        mp, ws, mode = self.mechanism.parameter_vector, self.mechanism.workspace, self.mode
        y_copy = np.empty_like(self.y)

        def rhs(t, y):
            y_copy[:] = y
            out = np.empty_like(y_copy)
            derivative(t, y_copy, mode, mp, joint, self.body_forces, ws, out)
            return out

        if self.options.gear_jacobian != "exact" or mode != L.MODE_CLEARANCE:
            return rhs, None
        jacobian_ws = make_jacobian_workspace()

        def jacobian(t, y):
            y_copy[:] = y
            out = np.empty((y_copy.shape[0], y_copy.shape[0]))
            state_jacobian(t, y_copy, mp, joint, jacobian_ws, out)
            return out
        return rhs, jacobian


def _tolerances(o: SimulationOptions) -> np.ndarray:
    return np.r_[np.full(L.N_COORDINATES, o.atol_position_m), np.full(L.N_COORDINATES, o.atol_velocity_m_s)]


def _scipy_bdf_steps(rhs, jacobian, t, y, t_end, o: SimulationOptions, counts: dict):
    """Yield (t, y) after each accepted step of scipy's BDF from (t, y) to t_end; adds its counts."""
    from scipy.integrate import BDF

    solver = BDF(rhs, t, y.copy(), t_end, max_step=o.max_step_s, rtol=o.rtol, atol=_tolerances(o),
                 first_step=min(o.max_step_s, 1e-7), jac=jacobian)
    while solver.status == "running":
        solver.step()
        if solver.status == "failed":
            raise RuntimeError(f"BDF failed at t={solver.t:.6g} s: {solver.message}")
        yield solver.t, solver.y
    for key, value in (("rhs_evaluations", solver.nfev), ("jacobian_evaluations", solver.njev),
                       ("lu_decompositions", solver.nlu)):
        counts[key] = counts.get(key, 0) + value


def _cvode_steps(rhs, jacobian, t, y, t_end, o: SimulationOptions, counts: dict):
    """Yield (t, y) after each internal step of SUNDIALS CVODE (BDF, dense Newton) from (t, y) to
    t_end (stopping there exactly); adds its counts."""
    from sksundae.cvode import CVODE

    def cvode_rhs(t, y, y_dot):
        y_dot[:] = rhs(t, y)

    def cvode_jacobian(t, y, y_dot, out):
        out[:] = jacobian(t, y)

    solver = CVODE(cvode_rhs, method="BDF", rtol=o.rtol, atol=_tolerances(o), max_step=o.max_step_s,
                   first_step=min(o.max_step_s, 1e-7), jacfn=None if jacobian is None else cvode_jacobian)
    result = solver.init_step(t, y.copy())
    while t < t_end:
        result = solver.step(t_end, method="onestep", tstop=t_end)
        if not result.success:
            raise RuntimeError(f"CVODE failed after t={t:.6g} s: {result.message}")
        t = result.t
        yield t, result.y
    for key, value in (("rhs_evaluations", result.nfev), ("jacobian_evaluations", result.njev)):
        counts[key] = counts.get(key, 0) + value


def run_simulation(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                   options: SimulationOptions | None = None, progress: bool = True,
                   chunks_per_revolution: int = 8, initial_profile_m=None) -> RunRecord:
    """Simulate ``options.revolutions`` crank revolutions from the bushing's ``initial_profile_m`` (default
    unworn; :class:`Simulation`); returns the run's record.

    The run proceeds in chunks (:func:`wearjoint.runner.run_engine`: progress
    bar, compilation timed apart, Ctrl-C keeps the finished chunks with ``completed = False``).
    """
    check_run_arguments(joint, mechanism, options, SimulationOptions, chunks_per_revolution=chunks_per_revolution)
    o = options or SimulationOptions()
    return run_engine(lambda: Simulation(joint, mechanism, o, initial_profile_m), o.revolutions,
                      (mechanism or SliderCrankParameters()).period_s, o.sample_dt_s, "simulate", progress,
                      chunks_per_revolution)


__all__ = ["SimulationOptions", "Simulation", "run_simulation", "INTEGRATORS", "GEAR_SOLVERS",
           "GEAR_JACOBIANS", "DEFAULT_WEAR_STEP_SHARE", "wear_step_limit_s", "ParameterError"]
