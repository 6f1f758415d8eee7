"""The foundation's wear in batches of contact time (core.wear.batch_wear, docs/reference/model.md §3.11).

A pin pressed into the bushing at a fixed eccentricity while it turns: every accepted step's wear
joins a batch, applied once per ``wear_interval_s`` of contact time, before the batch's lambda would
pass WEAR_BATCH_SHARE, and when the contact ends.  Archard's volume k_w sum F_N Delta s is kept
whatever the batches; a step as long as the interval is the unbatched step; a batch survives a
state round trip.
"""
from __future__ import annotations

import functools

import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.joint import ClearanceJoint, JointState, StateError
from wearjoint.parameters import (MAX_WEAR_STEP_S, WEAR_BATCH_SHARE, JointParameters, ParameterError,
                                  SliderCrankParameters, paper_joint)
from wearjoint.simulate import SimulationOptions, run_simulation

SPIN_RAD_S = 100.0          # pin's rotation relative to the bushing
PENETRATION_M = 2e-6
AT_REST = np.zeros(3)


def pressed_joint(interval_s: float, wear_factor: float = 0.5) -> ClearanceJoint:
    return ClearanceJoint(JointParameters(wear_factor=wear_factor, wear_interval_s=interval_s))


def press(joint: ClearanceJoint, dt: float, steps: int, eccentricity_m: float | None = None) -> float:
    """``steps`` held steps of ``dt`` with the pin at ``eccentricity_m`` along x (default: clearance plus
    PENETRATION_M), turning at SPIN_RAD_S; returns Archard's k_w sum F_N (R_j |d alpha|) of the forces the steps
    saw (the bushing's radius for the sliding radius: the depths here are 1e-4 of it)."""
    e = joint.params.clearance_m + PENETRATION_M if eccentricity_m is None else eccentricity_m
    pos_i, vel_i = np.array([e, 0.0, 0.0]), np.array([0.0, 0.0, SPIN_RAD_S])
    k_w = joint.parameter_vector[L.P_WEAR_COEFFICIENT]
    archard = 0.0
    for _ in range(steps):
        assert joint.advance_array(pos_i, vel_i, AT_REST, AT_REST, dt, True) >= 0
        archard += k_w * joint.result[L.R_NORMAL_FORCE] * joint.params.bushing_radius_m * SPIN_RAD_S * dt
    return archard


def batch_time(joint: ClearanceJoint) -> float:
    return float(joint.memory[L.M_BATCH_TIME])


@pytest.mark.parametrize("interval_s", [0.0, 1e-5, MAX_WEAR_STEP_S])
def test_batches_keep_archards_volume(interval_s):
    joint = pressed_joint(interval_s)
    archard = press(joint, 2e-6, 45)              # 90 us: whole batches of 10 and 30 us
    assert batch_time(joint) == 0.0
    assert joint.worn_volume_m3 == pytest.approx(archard, rel=1e-4)


def test_a_batch_waits_for_its_interval_then_wears_at_once():
    joint = pressed_joint(MAX_WEAR_STEP_S)
    press(joint, 2e-6, 14)
    assert joint.max_wear_depth_m == 0.0
    assert batch_time(joint) == pytest.approx(28e-6)
    press(joint, 2e-6, 1)                          # the 15th step fills 30 us
    assert joint.max_wear_depth_m > 0.0
    assert batch_time(joint) == 0.0


def test_a_batch_is_applied_when_the_contact_ends():
    joint = pressed_joint(MAX_WEAR_STEP_S)
    archard = press(joint, 2e-6, 5)
    assert joint.max_wear_depth_m == 0.0 and batch_time(joint) > 0.0
    press(joint, 2e-6, 1, eccentricity_m=0.5 * joint.params.clearance_m)     # free flight
    assert joint.result[L.R_CONTACT] < 0.5
    assert batch_time(joint) == 0.0
    assert joint.worn_volume_m3 == pytest.approx(archard, rel=1e-4)


def test_a_step_of_the_whole_interval_is_the_unbatched_step():
    """(To rounding: the batch's position is its load moment over its load.)"""
    batched, unbatched = pressed_joint(MAX_WEAR_STEP_S), pressed_joint(0.0)
    for joint in (batched, unbatched):
        press(joint, MAX_WEAR_STEP_S, 3)
    np.testing.assert_allclose(batched.wear_depth, unbatched.wear_depth, rtol=1e-12, atol=0.0)
    assert batch_time(batched) == 0.0


def test_a_batch_stops_before_its_relaxation_passes_the_share():
    """At a wear factor where one 2 us step has lambda 0.04 a batch holds two steps, not fifteen."""
    joint = pressed_joint(MAX_WEAR_STEP_S, wear_factor=5.6)
    pv = joint.parameter_vector
    k_f = pv[L.P_FOUNDATION_MODULUS] * pv[L.P_PIN_RADIUS] / pv[L.P_CONTACT_LENGTH]
    step_lambda = k_f * pv[L.P_WEAR_COEFFICIENT] * joint.params.bushing_radius_m * SPIN_RAD_S * 2e-6
    assert 0.5 * WEAR_BATCH_SHARE < 2 * step_lambda < WEAR_BATCH_SHARE < 3 * step_lambda
    press(joint, 2e-6, 2)
    assert joint.max_wear_depth_m == 0.0       # two steps wait
    press(joint, 2e-6, 1)                       # the third would pass the share: the two are applied first
    assert joint.max_wear_depth_m > 0.0
    assert batch_time(joint) == pytest.approx(2e-6)


def test_a_batch_survives_a_state_round_trip():
    whole, resumed = pressed_joint(MAX_WEAR_STEP_S), pressed_joint(MAX_WEAR_STEP_S)
    press(whole, 2e-6, 7)
    resumed.state_from_bytes(whole.state_to_bytes())
    assert batch_time(resumed) == batch_time(whole) > 0.0
    for joint in (whole, resumed):
        press(joint, 2e-6, 20)
    np.testing.assert_array_equal(resumed.wear_depth, whole.wear_depth)
    np.testing.assert_array_equal(resumed.memory, whole.memory)


@pytest.mark.parametrize("value", [-1e-6, 2 * MAX_WEAR_STEP_S, float("nan")])
def test_wear_interval_out_of_range_is_refused(value):
    with pytest.raises(ParameterError, match=r"wear_interval_s=\S+ is invalid: allowed (a finite real number )?in \[0, 3e-05\]"):
        JointParameters(wear_interval_s=value)


def test_a_corrupt_batch_in_a_state_is_refused():
    joint = pressed_joint(MAX_WEAR_STEP_S)
    press(joint, 2e-6, 3)
    memory = joint.memory.copy()
    memory[L.M_BATCH_INDEX] = joint.params.n_points          # past the last bushing point
    with pytest.raises(StateError, match=r"wear batch value 1257(\.0)? \(slot 9\) is invalid"):
        joint.set_state(JointState(joint.wear_depth.copy(), memory))


def test_a_batch_whose_mean_position_clears_the_wall_wears_an_arc_around_it():
    """Two steps pressed 2 um deep at +-0.3 rad: their load-weighted mean position, on the bisector, lies
    e (1 - cos 0.3) = 4.5 um inside the wall's reach, clear of it.  The batch keeps Archard's volume and
    wears an arc symmetric about the bisector, deepest there (the pin moved out until it touches): not the
    whole volume in one cell at the last step's deepest point."""
    joint = pressed_joint(MAX_WEAR_STEP_S)
    e = joint.params.clearance_m + PENETRATION_M
    angle = 0.3
    assert e * (1.0 - np.cos(angle)) > 2.0 * PENETRATION_M
    k_w = joint.parameter_vector[L.P_WEAR_COEFFICIENT]
    archard = 0.0
    for side in (1.0, -1.0):
        pos_i = np.array([e * np.cos(angle), side * e * np.sin(angle), 0.0])
        joint.advance_array(pos_i, np.array([0.0, 0.0, SPIN_RAD_S]), AT_REST, AT_REST, 1e-5, True)
        assert joint.result[L.R_CONTACT] > 0.5
        archard += k_w * joint.result[L.R_NORMAL_FORCE] * joint.params.bushing_radius_m * SPIN_RAD_S * 1e-5
    assert joint.max_wear_depth_m == 0.0 and batch_time(joint) > 0.0
    press(joint, 1e-5, 1, eccentricity_m=0.5 * joint.params.clearance_m)      # the contact ends: the batch wears
    depth = joint.wear_depth
    assert joint.worn_volume_m3 == pytest.approx(archard, rel=1e-4)
    bisector = int(np.argmin(np.abs(np.angle(np.exp(1j * joint.phi_rad)))))    # the point at angle 0
    assert np.argmax(depth) == bisector
    offsets = np.arange(1, depth.size // 2)
    np.testing.assert_allclose(depth[(bisector + offsets) % depth.size], depth[(bisector - offsets) % depth.size],
                               rtol=1e-6, atol=1e-6 * depth.max())
    assert np.count_nonzero(depth > 0.1 * depth.max()) >= 5


@functools.lru_cache(maxsize=None)
def _lasting_contact_record(revolutions=0.25, **options):
    """``revolutions`` (0.25: 0.1 s) of a rod–slider joint under 200 N at 100x the paper's k_w (the pin pressed into
    its wearing groove all along: a wear batch every step or two), every accepted point sampled: (the recorded slider
    acceleration's trapezoid integral over the steps in contact, the slider velocity's change over them [m/s], their
    time [s], the recorded normal force's mean over that time [N])."""
    mechanism = SliderCrankParameters(clearance_joint="rod-slider", slider_force_N=200.0)
    step = options.get("step_s", 1e-6)
    record = run_simulation(paper_joint(mechanism, wear_factor=100.0), mechanism,   # the period: 0.4 s
                            SimulationOptions(revolutions=revolutions, sample_dt_s=min(step, 1e-6), **options),
                            progress=False)
    s = record.samples
    t, v, a = s[:, L.T_TIME], s[:, L.T_SLIDER_V], s[:, L.T_SLIDER_A]
    both = (s[1:, L.T_CONTACT] > 0.5) & (s[:-1, L.T_CONTACT] > 0.5)
    dt = np.diff(t)[both]
    force = 0.5 * (s[1:, L.T_NORMAL_FORCE] + s[:-1, L.T_NORMAL_FORCE])
    return ((0.5 * (a[1:] + a[:-1]))[both] * dt).sum(), np.diff(v)[both].sum(), dt.sum(), \
        (force[both] * dt).sum() / dt.sum()


@pytest.mark.parametrize("options", [{"integrator": "rk4", "step_s": 1e-5}, {"integrator": "rk4", "step_s": 5e-6},
                                     {"integrator": "dopri", "max_step_s": 1e-5},
                                     {"integrator": "gear", "gear_jacobian": "numerical", "revolutions": 0.025}])
def test_the_recorded_acceleration_is_the_velocitys_slope_through_wear_batches(options):
    """A batch drops the force at once and the pin sinks into the new wear over the steps after it: the points are
    recorded at the middle of that jump (core.integrators.record_accepted).  Recorded after it (one revolution of
    this machine, RK4 at 10 and 5 us), the mean slider acceleration in contact sat 9.9 and 4.95 m/s² below its
    velocity's slope, the mean normal force at 195.4 and 198.8 N where 2.5 us gave 200.6 (now 202.3 N at each step).
    BDF ends its step with the force before the wear: recorded there (after it: 23.4 m/s² below).  The old
    recorder fails every case here."""
    integral, velocity_change, contact_time, normal_force = _lasting_contact_record(**options)
    revolutions = options.get("revolutions", 0.25)
    assert contact_time > 0.8 * revolutions * 0.4                  # lasting contact: the case the bias needs
    assert abs(integral - velocity_change) / contact_time < 0.1      # [m/s²]
    reference = _lasting_contact_record(revolutions, integrator="rk4", step_s=2.5e-6)[3]
    tolerance = 5e-3 if options["integrator"] == "gear" else 1e-3   # BDF's own error at its tolerances: 0.2 %
    assert abs(normal_force / reference - 1.0) < tolerance
