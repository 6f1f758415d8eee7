"""Monolithic (in-process, no FMI) simulation of the slider-crank with the clearance joint."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .core import layout as L
from .core.integrators import DOPRI5, RK4, accept_point, integrate, record_step
from .core.mechanism import JointArrays, derivative
from .joint import ClearanceJoint
from .mechanism import SliderCrank
from .parameters import (
    JointParameters, ParameterError, SliderCrankParameters, _finite, _require,
    check_joint_fits_mechanism,
)
from .results import RunRecord, new_revolution_stats, new_track
from .runner import record_run, run_in_chunks

INTEGRATORS = ("rk4", "dopri", "gear")


MAX_WEAR_STEP_S = 1e-5      # largest adaptive step with wear [s] (docs/model.md §7)
NO_WEAR_MAX_STEP_S = 1e-4   # largest adaptive step without wear [s]


@dataclass(frozen=True)
class SimulationOptions:
    """How to integrate.  ``rk4``: fixed ``step_s``.  ``dopri``: adaptive
    Dormand-Prince 5(4) with ``rtol``/``atol_*`` and ``max_step_s``.  ``gear``:
    scipy's BDF (the paper's Gear method; slow, for comparison) with the same
    tolerances and ``max_step_s`` (None: 1e-4 s, or :data:`MAX_WEAR_STEP_S` when the joint wears;
    an adaptive run with wear refuses a larger one).  ``onset_penetration_m``: how deep past a
    contact onset an adaptive step may end (event location, see
    ``core.integrators.integrate``).  ``sample_dt_s``: spacing of the time series."""

    revolutions: float = 2.0
    integrator: str = "dopri"
    step_s: float = 1e-6
    rtol: float = 1e-6
    atol_position_m: float = 1e-9
    atol_velocity_m_s: float = 1e-5
    max_step_s: float | None = None
    min_step_s: float = 1e-10
    onset_penetration_m: float = 1e-8
    sample_dt_s: float = 1e-5
    ideal: bool = False

    def __post_init__(self):
        _require("revolutions", self.revolutions, _finite("revolutions", self.revolutions) > 0.0, "> 0")
        _require("integrator", self.integrator, self.integrator in INTEGRATORS, "one of " + ", ".join(INTEGRATORS))
        positive = ("step_s", "rtol", "atol_position_m", "atol_velocity_m_s", "min_step_s", "sample_dt_s",
                    "onset_penetration_m") + (() if self.max_step_s is None else ("max_step_s",))
        for name in positive:
            _require(name, getattr(self, name), _finite(name, getattr(self, name)) > 0.0, "> 0")
        largest = MAX_WEAR_STEP_S if self.max_step_s is None else self.max_step_s   # None: at least this
        _require("min_step_s", self.min_step_s, self.min_step_s <= largest, f"<= max_step_s = {largest!r}")

    def for_joint(self, joint: JointParameters) -> "SimulationOptions":
        """These options for a run of ``joint``: the default ``max_step_s`` resolved (docs/model.md §7:
        with wear a step must stay well below the penetration depth), an explicit adaptive
        ``max_step_s`` above :data:`MAX_WEAR_STEP_S` refused when the joint wears."""
        wears = joint.wear_coefficient_m2_N * joint.wear_factor > 0.0 and not self.ideal
        if self.max_step_s is None:
            return dataclasses.replace(self, max_step_s=MAX_WEAR_STEP_S if wears else NO_WEAR_MAX_STEP_S)
        if wears and self.integrator != "rk4" and self.max_step_s > MAX_WEAR_STEP_S:
            raise ParameterError(f"max_step_s={self.max_step_s!r} is invalid with wear (wear_coefficient_m2_N * "
                                 f"wear_factor > 0): allowed at most {MAX_WEAR_STEP_S!r} s, a wear step must stay "
                                 "well below the penetration depth (docs/model.md §7)")
        return self

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


class Simulation:
    """One slider-crank (ideal or with the clearance joint) and its integration state."""

    def __init__(self, joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                 options: SimulationOptions | None = None):
        self.mechanism = SliderCrank(mechanism)
        joint = joint or JointParameters(**self.mechanism.params.joint_offsets())
        self.options = (options or SimulationOptions()).for_joint(joint)
        check_joint_fits_mechanism(joint, self.mechanism.params)
        self.joint = ClearanceJoint(joint)
        self.mode = L.MODE_IDEAL if self.options.ideal else L.MODE_CLEARANCE
        self.t = 0.0
        self.y = self.mechanism.initial_state()
        self.dy = np.empty_like(self.y)
        self.body_forces = np.zeros(6)
        first_step = self.options.step_s if self.options.integrator == "rk4" else min(1e-6, self.options.max_step_s)
        self.control = np.array([first_step, self.options.max_step_s, self.options.rtol,
                                 self.options.atol_position_m, self.options.atol_velocity_m_s,
                                 self.options.min_step_s, self.options.onset_penetration_m])
        n_rev = int(math.ceil(self.options.revolutions)) + 1
        self.revolution_stats = new_revolution_stats(n_rev)
        self.track = new_track(self.options.sample_dt_s)
        self.accepted = 0
        self.rejected = 0
        self._derivative()

    @property
    def _joint_arrays(self) -> JointArrays:
        return joint_arrays(self.joint)

    def _derivative(self):
        derivative(self.t, self.y, self.mode, self.mechanism.parameter_vector, self._joint_arrays,
                   self.body_forces, self.mechanism.workspace, self.dy)

    def checkpoint(self) -> dict:
        """Everything needed to continue bit-identically (arrays and bytes; picklable)."""
        return {"t": self.t, "y": self.y.copy(), "control": self.control.copy(),
                "joint_state": self.joint.state_to_bytes(), "revolution_stats": self.revolution_stats.copy(),
                "track": self.track.copy(), "accepted": self.accepted, "rejected": self.rejected}

    def restore(self, checkpoint: dict) -> None:
        """Continue from :meth:`checkpoint` (same parameters and options)."""
        self.t = float(checkpoint["t"])
        self.y[:] = checkpoint["y"]
        self.control[:] = checkpoint["control"]
        self.joint.state_from_bytes(checkpoint["joint_state"])
        self.revolution_stats[:] = checkpoint["revolution_stats"]
        self.track[:] = checkpoint["track"]
        self.accepted = int(checkpoint["accepted"])
        self.rejected = int(checkpoint["rejected"])
        self._derivative()

    def wear_profile(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(phi_deg, wear_depth_m, worn_volume_m3) of the bushing (rod frame), copies."""
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

    def warm_up(self) -> None:
        """Compile the kernels :meth:`advance_to` calls (numba) without advancing: the
        integrator runs over zero time, on copies of the state."""
        joint = JointArrays(*(a.copy() for a in self._joint_arrays))
        y, dy, forces = self.y.copy(), self.dy.copy(), self.body_forces.copy()
        stats, track = self.revolution_stats.copy(), self.track.copy()
        samples = np.zeros((0, L.N_SAMPLE_COLUMNS))
        mp, ws = self.mechanism.parameter_vector, self.mechanism.workspace
        if self.options.integrator == "gear":
            accept_point(self.t, y, 0.0, dy, self.mode, mp, joint, forces, ws, dy.copy(), False)
            record_step(self.t, 0.0, y, dy, joint.result, mp, stats, samples, track)
        else:
            integrate(RK4, self.t, self.t, y, self.control.copy(), self.mode, mp, joint, forces, ws, dy,
                      stats, samples, track)

    def advance_to(self, t_end: float, samples: np.ndarray) -> int:
        """Integrate to t_end, writing samples into ``samples``; returns how many."""
        self.track[L.K_N_SAMPLES] = 0
        if self.options.integrator == "gear":
            self._gear_to(t_end, samples)
        else:
            method = RK4 if self.options.integrator == "rk4" else DOPRI5
            self.t, acc, rej = integrate(method, self.t, t_end, self.y, self.control, self.mode,
                                         self.mechanism.parameter_vector, self._joint_arrays,
                                         self.body_forces, self.mechanism.workspace, self.dy,
                                         self.revolution_stats, samples, self.track)
            self.accepted += acc
            self.rejected += rej
        return int(self.track[L.K_N_SAMPLES])

    def _gear_to(self, t_end: float, samples: np.ndarray) -> None:
        """scipy BDF (variable order 1-5, the Gear family); joint bookkeeping per accepted step."""
        from scipy.integrate import BDF

        mp = self.mechanism.parameter_vector
        joint = self._joint_arrays
        dy = np.empty_like(self.y)

        def rhs(t, y):
            derivative(t, y, self.mode, mp, joint, self.body_forces, self.mechanism.workspace, dy)
            return dy.copy()

        o = self.options
        atol = np.r_[np.full(L.N_COORDINATES, o.atol_position_m), np.full(L.N_COORDINATES, o.atol_velocity_m_s)]
        solver = BDF(rhs, self.t, self.y.copy(), t_end, max_step=o.max_step_s, rtol=o.rtol, atol=atol,
                     first_step=min(o.max_step_s, 1e-7))
        while solver.status == "running":
            t_prev = solver.t
            solver.step()
            if solver.status == "failed":
                raise RuntimeError(f"BDF failed at t={solver.t:.6g} s: {solver.message}")
            self.y[:] = solver.y
            self.t = solver.t
            accept_point(self.t, self.y, self.t - t_prev, self.dy, self.mode, mp, joint, self.body_forces,
                    self.mechanism.workspace, self.dy, False)
            record_step(self.t, self.t - t_prev, self.y, self.dy, self.joint.result, mp,
                        self.revolution_stats, samples, self.track)
            self.accepted += 1


def run_simulation(joint: JointParameters | None = None, mechanism: SliderCrankParameters | None = None,
                   options: SimulationOptions | None = None, progress: bool = True,
                   chunks_per_revolution: int = 8) -> RunRecord:
    """Simulate ``options.revolutions`` crank revolutions; returns the run's record.

    The run proceeds in chunks (:func:`wearjoint.runner.run_in_chunks`: progress
    bar, compilation timed apart, Ctrl-C keeps the finished chunks with ``completed = False``).
    """
    o = options or SimulationOptions()
    period = (mechanism or SliderCrankParameters()).period_s
    run = run_in_chunks(lambda: Simulation(joint, mechanism, o), o.revolutions, period, o.sample_dt_s, "simulate",
                        progress, chunks_per_revolution)
    sim = run.engine
    return record_run(run, sim.revolution_stats, o.revolutions, period, sim.joint.params,
                      parameters={"joint": sim.joint.params.to_dict(), "mechanism": sim.mechanism.params.to_dict(),
                                  "simulation": sim.options.to_dict(), "engine": "monolithic"},
                      extra={"integrator_accepted_steps": sim.accepted, "integrator_rejected_steps": sim.rejected})


def joint_arrays(joint: ClearanceJoint) -> JointArrays:
    """The arrays of a :class:`ClearanceJoint` as the kernels take them (no copies)."""
    return JointArrays(joint.parameter_vector, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                       joint.memory, joint._mask, joint.work, joint.result)


__all__ = ["SimulationOptions", "Simulation", "run_simulation", "joint_arrays", "INTEGRATORS", "ParameterError"]
