"""A third-party master's trace (:class:`MasterTrace`: the traced outputs, :data:`TRACED`, at every communication
point) and the :class:`wearjoint.results.RunRecord` it makes (:func:`record_from_trace`), the per-revolution statistics
accounted by the engines' own recorder (:func:`wearjoint.core.integrators.record_points`), cut at its first
non-physical point (:func:`trace_divergence`).  The adapters that make traces: :mod:`wearjoint.cosim.masters`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis import past_admissible, pin_left_bushing
from ..core import layout as L
from ..fmu import ssp
from ..kernel_calls import bushing_point_angles
from ..results import RunParameters, RunRecord, new_revolution_stats, new_track
from ..slider_crank import pack_mechanism_parameters

# what every adapter records at each communication point: (component, variable)
MECHANISM_TRACED = ("crank_angle", "slider_x", "slider_v", "slider_a", "pin_omega", "bushing_omega")
JOINT_TRACED = ("pin_force_x", "pin_force_y", "normal_force", "friction_force", "penetration", "contact",
                "eccentricity_x", "eccentricity_y", "tangential_velocity", "max_wear_depth", "worn_volume")
TRACED = tuple((ssp.MECHANISM, n) for n in MECHANISM_TRACED) + tuple((ssp.JOINT, n) for n in JOINT_TRACED)
_COLUMN = {key: k for k, key in enumerate(TRACED)}
# where record_step finds each traced quantity: the state y, its derivative dy, the joint's result (and
# the joint's bodies' angular velocities, by the clearance joint's place: record_from_trace)
_Y = {"crank_angle": L.CRANK + 2, "slider_x": L.Y_SLIDER_X, "slider_v": L.Y_SLIDER_V}
_DY = {"slider_a": L.N_COORDINATES + L.SLIDER}
_RESULT = {"pin_force_x": L.R_PIN_FX, "pin_force_y": L.R_PIN_FY, "normal_force": L.R_NORMAL_FORCE,
           "friction_force": L.R_FRICTION_FORCE, "penetration": L.R_PENETRATION, "contact": L.R_CONTACT,
           "eccentricity_x": L.R_ECCENTRICITY_X, "eccentricity_y": L.R_ECCENTRICITY_Y,
           "tangential_velocity": L.R_TANGENTIAL_VELOCITY}

@dataclass
class MasterTrace:
    """A third-party master's run: ``values[i, k]`` is ``TRACED[k]`` at ``time_s[i]`` [s] (the
    communication points from 0); ``wear_depth_m`` the final profile, None where unreadable;
    ``wall_time_s`` the stepping loop, ``load_time_s`` loading and initialising the FMUs; ``failure`` why the
    master stopped before the stop time."""

    master: str
    step_s: float
    time_s: np.ndarray
    values: np.ndarray
    wear_depth_m: np.ndarray | None
    wall_time_s: float
    load_time_s: float
    failure: str = ""        # why the master stopped early ('' if it reached the stop time)
    log: tuple = ()          # the warnings and errors of the master's own log (OMSimulator's), as its lines


_JOINT_COLUMNS = [k for (component, _), k in _COLUMN.items() if component == ssp.JOINT]


def align_joint(trace: MasterTrace) -> MasterTrace:
    """A master that reads the joint's outputs right after its doStep, before it moves the step's
    connections, sees them one step behind the mechanism's (forces at the kinematics the step began
    with; fmpy's simulator moreover starts every connector at 0, so its first joint row is of zero
    kinematics): each joint row moved to the point it belongs to, the last point dropped."""
    trace.values[:-1, _JOINT_COLUMNS] = trace.values[1:, _JOINT_COLUMNS]
    trace.values, trace.time_s = trace.values[:-1], trace.time_s[:-1]
    return trace


def record_from_trace(trace: MasterTrace, joint, mechanism, sample_dt_s: float, parameters: RunParameters,
                      chunk: int = 100_000) -> RunRecord:
    """The run record of a trace up to its first non-physical point (:func:`trace_divergence`): per-revolution
    statistics and samples from the engines' recorder (every communication point is an accepted point; ``chunk``
    points at a time), the worn profile where the master gave one at that point (else NaN: no profile.csv nor its
    figure; the max wear depth from the joint's scalar output)."""
    from ..core.integrators import record_points   # numba's kernel: the package's own master imports no numba
    from ..core.joint_location import JOINT_BODIES

    bad, failure = trace_divergence(trace, joint)
    # what came before written: a master that went on past it (ecos) keeps nothing after, nor its final profile,
    # which the steps after it may have worn
    went_on = bad is not None and trace.time_s.size - bad > 1
    if bad is not None:
        trace.values, trace.time_s = trace.values[:max(bad, 1)], trace.time_s[:max(bad, 1)]
    if went_on:
        trace.wear_depth_m = None
    mp = pack_mechanism_parameters(mechanism)
    period = mechanism.period_s
    n = trace.time_s.size
    revolutions = trace.time_s[-1] / period
    stats = new_revolution_stats(int(np.ceil(revolutions * (1.0 - 1e-12))))
    samples = np.zeros((int(trace.time_s[-1] / sample_dt_s) + 2, L.N_SAMPLE_COLUMNS))
    track = new_track(sample_dt_s)
    ys, dys, results = np.zeros((chunk, 2 * L.N_COORDINATES)), np.zeros((chunk, 2 * L.N_COORDINATES)), \
        np.zeros((chunk, L.N_RESULT))
    # the pin body's and the bushing body's angular velocities (the mechanism's outputs to the joint) where
    # record_step reads them: a relative_omega_rad_s of 0 had made every third-party run's regime "impacting"
    bodies = JOINT_BODIES[L.CLEARANCE_JOINTS.index(mechanism.clearance_joint)]
    rates = {name: L.N_COORDINATES + int(body) + 2 for name, body in zip(("pin_omega", "bushing_omega"), bodies)
             if body != L.GROUND}
    where = [(k, array, table[name]) for (_, name), k in _COLUMN.items()
             for array, table in ((ys, {**_Y, **rates}), (dys, _DY), (results, _RESULT)) if name in table]
    for first in range(0, n, chunk):
        rows = slice(first, min(n, first + chunk))
        m = rows.stop - rows.start
        for k, array, index in where:
            array[:m, index] = trace.values[rows, k]
        # the step ending at a chunk's first point began at the previous chunk's last (the first: none)
        record_points(trace.time_s[max(0, first - 1)], trace.time_s[rows], ys[:m], dys[:m], results[:m], mp, stats,
                      samples, track)
    max_depth = trace.values[:, _COLUMN[(ssp.JOINT, "max_wear_depth")]]
    ends = np.searchsorted(trace.time_s, (np.arange(stats.shape[0]) + 1) * period * (1.0 + 1e-12), side="right") - 1
    profile = trace.wear_depth_m if trace.wear_depth_m is not None else np.full(joint.n_points, np.nan)
    # the steps from 0 to the trace's end (a master's trace may or may not hold the row at 0)
    extra = {"master": trace.master, "communication_steps": round(trace.time_s[-1] / trace.step_s),
             "step_s": trace.step_s, **({"master_log_warnings": list(trace.log)} if trace.log else {})}
    if trace.wear_depth_m is None:
        extra.update(max_wear_depth_m=float(max_depth[-1]), max_wear_angle_deg=None,
                     wear_profile=(f"read after {trace.master} went on past the failure: left out"
                                   if went_on else f"not readable through {trace.master}")
                     + ": no profile.csv nor its figure; max_wear_depth_m and worn_volume_m3 are the joint's outputs")
    failure = failure or (
        f"the run diverged: {trace.failure}; the communication step {trace.step_s:g} s is too long for this contact "
        "(take a shorter one, or wearjoint's adaptive master; docs/explanation/cosim_study.md)" if trace.failure else "")
    return RunRecord(samples=samples[:int(track[L.K_N_SAMPLES])], revolution_stats=stats, wear_growth_m=max_depth[ends],
                     phi_deg=np.degrees(bushing_point_angles(joint.n_points)), wear_depth_m=profile,
                     worn_volume_m3=float(trace.values[-1, _COLUMN[(ssp.JOINT, "worn_volume")]]),
                     simulated_time_s=float(trace.time_s[-1]), wall_time_s=trace.wall_time_s,
                     compile_time_s=trace.load_time_s, revolutions=float(revolutions), period_s=period,
                     clearance_m=joint.clearance_m, contact_stiffness_N_m1_5=joint.stiffness_N_m1_5,
                     parameters=parameters, extra=extra, completed=not failure, failure=failure)


def trace_divergence(trace: MasterTrace, joint) -> tuple[int | None, str]:
    """(None, '') if every communication point of ``trace`` is physical, else the first that is not and why: the pin
    further into the bushing wall than ``joint`` admits (:func:`wearjoint.analysis.pin_left_bushing` with the
    wear depth the joint reported there) or a value not finite."""
    e = np.hypot(trace.values[:, _COLUMN[(ssp.JOINT, "eccentricity_x")]],
                 trace.values[:, _COLUMN[(ssp.JOINT, "eccentricity_y")]])
    depth = trace.values[:, _COLUMN[(ssp.JOINT, "max_wear_depth")]]
    force = trace.values[:, _COLUMN[(ssp.JOINT, "normal_force")]]
    bad = np.flatnonzero(past_admissible(e, depth, force, joint.clearance_m, joint.admissible_penetration_m,
                                         joint.admissible_force_N) | ~np.isfinite(trace.values).all(axis=1))
    if not bad.size:
        return None, ""
    k = int(bad[0])
    reason = pin_left_bushing(float(e[k]) if np.isfinite(trace.values[k]).all() else math.nan, joint.clearance_m,
                              float(depth[k]), joint.admissible_penetration_m, float(force[k]), joint.admissible_force_N)
    return k, (f"the run diverged at t = {trace.time_s[k]:.6g} s: {reason}; nothing after this is physical ("
               f"{trace.master}'s communication step {trace.step_s:g} s is too long for this contact: take a shorter "
               "one, or wearjoint's adaptive master; docs/explanation/cosim_study.md)")
