"""The ClearanceWearJoint FMU in OSP libcosim (a second, non-fmpy FMI master).

libcosim runs the FMU in this Python process, so pythonfmu finds the running
interpreter (no libpython preload needed here).  Inputs go through libcosim's
override manipulator, which applies them before each doStep; outputs are read
with the last-value observer after the step.
"""
import numpy as np
import pytest

pytest.importorskip("libcosimpy")
from fmpy import read_model_description  # noqa: E402
from libcosimpy.CosimExecution import CosimExecution  # noqa: E402
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level  # noqa: E402
from libcosimpy.CosimManipulator import CosimManipulator  # noqa: E402
from libcosimpy.CosimObserver import CosimObserver  # noqa: E402
from libcosimpy.CosimSlave import CosimLocalSlave  # noqa: E402

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.core.layout import N_RESULT  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402

STEP_S = 1e-5
OUTPUTS = ["pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque",
           "normal_force", "friction_force", "contact", "max_wear_depth", "worn_volume"]


def approach(params, steps=12):
    """Pin moving into the bushing wall along +x (bodies unrotated), spinning at 10 rad/s:
    eccentricity from clearance - 20 um to clearance + 6 um, velocities consistent with it."""
    (pin_dx, pin_dy), (bushing_dx, bushing_dy) = params.pin_offset_m, params.bushing_offset_m
    ecc = np.linspace(params.clearance_m - 20e-6, params.clearance_m + 6e-6, steps)
    speed = (ecc[1] - ecc[0]) / STEP_S
    omega = 10.0
    return [[bushing_dx - pin_dx + e, bushing_dy - pin_dy, 0.0, speed + omega * pin_dy, -omega * pin_dx, omega,
             0.0, 0.0, 0.0, 0.0, 0.0, 0.0] for e in ecc]


def test_libcosim_forces_match_the_joint(any_fmu):
    _, built_fmu = any_fmu
    log_output_level(CosimLogLevel.ERROR)
    params = JointParameters(restitution=0.8, rho_mode="paper")
    vr = fv.value_references(read_model_description(str(built_fmu)))
    inputs = [vr[v.name] for v in fv.INPUTS]
    outputs = [vr[n] for n in OUTPUTS]

    execution = CosimExecution.from_step_size(round(STEP_S * 1e9))
    slave = CosimLocalSlave(fmu_path=str(built_fmu), instance_name="joint")
    index = execution.add_local_slave(slave)
    assert index >= 0
    override = CosimManipulator.create_override()
    execution.add_manipulator(override)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    values = fv.fmi_parameter_values(params)
    for name in ("restitution", "rho_mode"):
        if isinstance(values[name], int):
            assert execution.integer_initial_value(index, vr[name], values[name])
        else:
            assert execution.real_initial_value(index, vr[name], values[name])

    joint = ClearanceJoint(params)
    jacobian = np.zeros((N_RESULT, 12))
    got, expected = [], []
    for x in approach(params):
        assert override.slave_real_values(index, inputs, x)
        assert execution.step(1)
        got.append(observer.last_real_values(index, outputs))
        # doStep: left endpoint = these inputs, held; the last-value observer read every variable after the step
        # before, the loads' derivatives too (a linearising master one step late, docs/reference/model.md §3.11): the
        # wear takes the linear force's mean at these inputs
        kinematics = (np.array(x[0:3]), np.array(x[3:6]), np.array(x[6:9]), np.array(x[9:12]))
        joint.linearise_array(*kinematics, jacobian)
        joint.accept_linearised_array(*kinematics, STEP_S, jacobian)
        r = joint.evaluate(x[:6], x[6:])               # outputs read after the step
        expected.append([*r.pin_force, *r.bushing_force, r.normal_force_N, r.friction_force_N,
                         float(r.in_contact), joint.max_wear_depth_m, joint.worn_volume_m3])
    got, expected = np.array(got), np.array(expected)

    contact = got[:, OUTPUTS.index("contact")]
    assert contact[0] == 0.0 and contact[-1] == 1.0      # the trajectory does run into the wall
    assert got[-1, OUTPUTS.index("worn_volume")] > 0.0
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-300)
