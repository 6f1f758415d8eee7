"""The SliderCrank FMU's linearised load coupling (parameter load_coupling 1): over a Co-Simulation step it
integrates F0 + J (u - u0), the linearisation a ClearanceWearJoint FMU publishes (docs/reference/fmu.md §5).

The reference is independent of that code path: the same FMU with the loads held (load_coupling 0) over many
short steps, the test itself setting the linear loads F0 + J (u - u0) at each from the FMU's kinematic outputs;
as the short steps shrink it converges to the mechanism under the linear loads.
"""
from __future__ import annotations

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from slider_crank_fmu import initialised_slave, slider_crank_fmus, smooth_loads  # noqa: E402

from wearjoint.fmu import slider_crank as sc  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402

STIFFNESS_N_M = 2e5        # a spring between the pin and the bushing centre, across the clearance
DAMPING_N_S_M = 40.0
H_S = 2e-4                 # one communication step: a tenth of the spring's period with the rod's mass
LOADS = [v.name for v in sc.LOAD_INPUTS[:6]]
KINEMATICS = [v.name for v in fv.INPUTS]
VR = sc.VALUE_REFERENCES


@pytest.fixture(scope="module")
def fmu(shared_build, tmp_path_factory):
    return slider_crank_fmus(shared_build, tmp_path_factory)[2]


def spring(normal_force: float = 500.0) -> dict:
    """A linearisation: the pin pulled towards its position u0 by a spring and a damper along x and y (d pin force
    / d pin position -k, / d bushing position +k, likewise the velocities), the torques and the normal force
    constant (``normal_force``)."""
    derivatives = {name: 0.0 for name in fv.JACOBIAN_SLOTS}
    for axis in ("x", "y"):
        for body, sign in (("pin", -1.0), ("bushing", 1.0)):
            derivatives[fv.derivative_name(f"pin_force_{axis}", f"{body}_{axis}")] = sign * STIFFNESS_N_M
            derivatives[fv.derivative_name(f"pin_force_{axis}", f"{body}_v{axis}")] = sign * DAMPING_N_S_M
    return {**derivatives, "normal_force": normal_force}


def linear_loads(f0, derivatives, u, u0) -> np.ndarray:
    """F0 + J (u - u0) on the pin body and the bushing body (its force minus the pin's, Eq. 22)."""
    du = np.asarray(u) - u0
    row = {name: sum(derivatives[fv.derivative_name(name, k)] * du[m] for m, k in enumerate(KINEMATICS))
           for name in fv.LINEARISED_ROWS}
    pin = [f0[0] + row["pin_force_x"], f0[1] + row["pin_force_y"], f0[2] + row["pin_torque"]]
    return np.array([*pin, f0[3] - row["pin_force_x"], f0[4] - row["pin_force_y"], f0[5] + row["bushing_torque"]])


def run(fmu, coupling: int, substeps: int, linearisation: dict, f0, slider=0.0) -> np.ndarray:
    """The mechanism's state after one step H_S from its start: ``coupling`` 1, one step of the FMU taking the
    linearisation; 0, ``substeps`` steps with the linear loads set by the test at each (held)."""
    slave = initialised_slave(fmu, {sc.LOAD_COUPLING_NAME: float(coupling), sc.MAX_INTERNAL_STEP_NAME: H_S / 64})
    u0 = np.array(slave.getReal([VR[k] for k in KINEMATICS]))
    state_vrs = [VR[v.name] for v in sc.STATES]
    if coupling:
        inputs = {**dict(zip(LOADS, f0)), "slider_force": slider, **linearisation,
                  **{fv.evaluated_input_name(k): u0[m] for m, k in enumerate(KINEMATICS)}}
        slave.setReal([VR[k] for k in inputs], list(inputs.values()))
        slave.doStep(0.0, H_S)
    else:
        h = H_S / substeps
        for i in range(substeps):
            u = slave.getReal([VR[k] for k in KINEMATICS])
            loads = linear_loads(f0, linearisation, u, u0) if linearisation["normal_force"] > 0.0 else np.zeros(6)
            slave.setReal([VR[k] for k in (*LOADS, "slider_force")], [*loads, slider])
            slave.doStep(i * h, h)
    y = np.array(slave.getReal(state_vrs))
    slave.terminate()
    slave.freeInstance()
    return y


def test_a_linearised_step_is_the_mechanism_under_the_linear_loads(fmu):
    """One step with the loads linearised lands where many short held steps with the loads the linearisation
    gives at each converge to (first order in the short step: 1/2000 of the step leaves ~1e-3 of the one held
    step's error), and far from one held step."""
    f0 = smooth_loads(0.0)[:6]
    linearisation = spring()
    linearised = run(fmu, 1, 1, linearisation, f0)
    reference = run(fmu, 0, 2000, linearisation, f0)
    held = run(fmu, 0, 1, linearisation, f0)
    coarse = run(fmu, 0, 200, linearisation, f0)
    scale = np.abs(held - reference).max()
    assert scale > 0.0
    assert np.abs(linearised - reference).max() < 0.01 * scale
    # the reference converges: ten times the short step, about ten times its distance from the linearised step
    assert np.abs(coarse - linearised).max() > 3.0 * np.abs(reference - linearised).max()


def test_the_linearised_loads_vanish_where_the_normal_force_does_not_push(fmu):
    """With the published normal force 0 (no contact at the evaluated inputs) the step takes no joint loads,
    whatever the loads and derivatives carried: the state is that of one step with the loads 0; with them held it
    differs."""
    f0 = smooth_loads(0.0)[:6]
    released = run(fmu, 1, 1, spring(normal_force=0.0), f0)
    unloaded = run(fmu, 0, 1, {**spring(), "normal_force": 0.0}, np.zeros(6))
    np.testing.assert_allclose(released, unloaded, rtol=0.0, atol=1e-12)
    assert np.abs(run(fmu, 0, 1, {**spring(), "normal_force": 1.0}, f0) - unloaded).max() > 1e-9


def test_a_load_coupling_that_is_no_code_is_refused_naming_it(fmu):
    """load_coupling 0.5: exitInitializationMode fails with one message naming the parameter, its value and the
    codes allowed."""
    from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

    messages = []
    logger = fmi2CallbackLoggerTYPE(lambda env, name, status, category, text: messages.append(text.decode()))
    callbacks = fmi2CallbackFunctions(logger=logger, allocateMemory=defaultCallbacks.allocateMemory,
                                      freeMemory=defaultCallbacks.freeMemory)
    slave = FMU2Slave(guid=fmu["token"], unzipDirectory=str(fmu["dir"]), modelIdentifier=sc.MODEL_IDENTIFIER,
                      instanceName="refused")
    slave.instantiate(callbacks=callbacks, loggingOn=True)
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.setReal([VR[sc.LOAD_COUPLING_NAME]], [0.5])
    with pytest.raises(Exception):
        slave.exitInitializationMode()
    assert messages == ["fmi2ExitInitializationMode: parameter load_coupling=0.5 is invalid: allowed 0 (hold), "
                        "1 (linearised)"]
    slave.freeInstance()
