"""The native FMU as FMI 3.0 (``wearjoint build-fmu --fmi-version 3``, docs/reference/fmu.md §5):
Co-Simulation and Model Exchange, the wear profile as one Float64 array sized by the structural
parameter ``n_points`` (set in Configuration Mode), the options as FMI 3 enumerations, and the
same numbers as the FMI 2.0 build.
"""
import ctypes
import subprocess
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description, simulate_fmu  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Float64, fmi3ValueReference  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402
from fmi_host import needed_libraries  # noqa: E402
from fmpy_instance import enter_initialisation  # noqa: E402
from kinematic_trace import slider_crank_trace  # noqa: E402

from wearjoint import ClearanceJoint, paper_joint  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.build import build_fmu  # noqa: E402
from wearjoint.fmu.model_description import enumeration_type_name, fmi3_value_references  # noqa: E402
from wearjoint.core.state_format import CONTENTS_FMU  # noqa: E402
from wearjoint.joint import JointState, read_state_bytes  # noqa: E402
from wearjoint.parameters import ParameterError  # noqa: E402

SCALAR_NAMES = [v.name for v in fv.SCALAR_OUTPUTS]
FORCE_NAMES = [name for name in SCALAR_NAMES if name in fv.RESULT_SLOTS]
INPUT_NAMES = [v.name for v in fv.INPUTS]
VR3 = fmi3_value_references()
N_POINTS = paper_joint().n_points
TRACE_STEP = 1e-4     # [s]
TRACE_ROWS = 4000     # one crank revolution (0.4 s)
WEAR_FACTOR = 10.0    # tens of um of wear in one revolution
TRACE_JOINT = paper_joint(wear_factor=WEAR_FACTOR)


# ------------------------------------------------------------- FMUs and a kinematic trace
@pytest.fixture(scope="module")
def fmi3_fmu(shared_build):
    return shared_build(backend="native", fmi_version=3)


def _unzipped(path, tmp_path_factory, name):
    return {"path": path, "dir": Path(extract(str(path), unzipdir=str(tmp_path_factory.mktemp(name)))),
            "md": read_model_description(str(path))}


@pytest.fixture(scope="module")
def fmi3(fmi3_fmu, tmp_path_factory):
    return _unzipped(fmi3_fmu, tmp_path_factory, "fmi3_unzipped")


@pytest.fixture(scope="module")
def fmi2(native_fmu, tmp_path_factory):
    return _unzipped(native_fmu, tmp_path_factory, "fmi2_unzipped")


@pytest.fixture(scope="module")
def trace():
    """One revolution of the slider-crank with wear, every TRACE_STEP."""
    return slider_crank_trace(TRACE_JOINT, TRACE_ROWS, TRACE_STEP)


class Log:
    """An FMI 3.0 logger keeping (status, category, message)."""

    def __init__(self):
        self.messages = []

    def __call__(self, environment, status, category, message):
        self.messages.append((status, category.decode(), message.decode()))

    def text(self):
        return "\n".join(m for _, _, m in self.messages)


def _slave3(fmi3, n_points=None, params=TRACE_JOINT, log=None, name="fmi3"):
    """An FMI 3.0 Co-Simulation instance with ``params``, initialised (n_points set in Configuration Mode)."""
    fmu = FMU3Slave(guid=fmi3["md"].guid, unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName=name)
    fmu.instantiate(logMessage=log)
    if n_points is not None:
        fmu.enterConfigurationMode()
        fmu.setUInt64([VR3["n_points"]], [n_points])
        fmu.exitConfigurationMode()
    fmu.enterInitializationMode(startTime=0.0)
    reals, enumerations = fv.fmi_parameter_values_by_type(params)
    fmu.setFloat64([VR3[k] for k in reals], list(reals.values()))
    fmu.setInt64([VR3[k] for k in enumerations], list(enumerations.values()))
    fmu.exitInitializationMode()
    return fmu


def _slave2(fmi2, params=TRACE_JOINT, name="fmi2"):
    vr = fv.value_references(fmi2["md"])
    fmu = FMU2Slave(guid=fmi2["md"].guid, unzipDirectory=str(fmi2["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName=name)
    fmu.instantiate()
    enter_initialisation(fmu, vr, params)
    fmu.exitInitializationMode()
    return fmu, vr


def _relative(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = np.maximum(np.maximum(np.abs(a), np.abs(b)), 1e-300)
    return float(np.max(np.abs(a - b) / scale)) if a.size else 0.0


def _run_side_by_side(fmu3, fmu2, vr2, rows, n_points, profile_every=500):
    """Drive both FMUs through ``rows``; the largest relative difference of the scalar outputs and
    of the profiles, the number of comparisons, and the last profiles."""
    inputs2 = [vr2[name] for name in INPUT_NAMES]
    scalars2 = [vr2[name] for name in SCALAR_NAMES]
    wear2 = [vr2[fv.wear_depth_name(z)] for z in range(1, n_points + 1)]
    inputs3 = [VR3[name] for name in INPUT_NAMES]
    scalars3 = [VR3[name] for name in SCALAR_NAMES]
    worst_scalar = worst_profile = 0.0
    compared = 0
    for i, row in enumerate(rows):
        fmu3.setFloat64(inputs3, list(row[2:]))
        fmu2.setReal(inputs2, list(row[2:]))
        worst_scalar = max(worst_scalar, _relative(fmu3.getFloat64(scalars3), fmu2.getReal(scalars2)))
        compared += 1
        if i % profile_every == 0:
            worst_profile = max(worst_profile, _relative(fmu3.getFloat64([VR3["wear_depth"]], nValues=n_points),
                                                         fmu2.getReal(wear2)))
        fmu3.doStep(row[0], row[1])
        fmu2.doStep(row[0], row[1])
    profile3 = np.array(fmu3.getFloat64([VR3["wear_depth"]], nValues=n_points))
    profile2 = np.array(fmu2.getReal(wear2))
    return worst_scalar, max(worst_profile, _relative(profile3, profile2)), compared, profile3, profile2


# ------------------------------------------------------------- the FMU and its model description
def test_fmi3_fmu_validates_and_is_a_self_contained_fmi3_binary(fmi3):
    assert validate_fmu(str(fmi3["path"])) == []
    md = fmi3["md"]
    assert md.fmiVersion == "3.0" and md.coSimulation is not None and md.modelExchange is not None
    assert md.numberOfEventIndicators == 1
    binary = fmi3["dir"] / "binaries" / "x86_64-linux" / f"{fv.MODEL_NAME}.so"
    assert binary.is_file() and not (fmi3["dir"] / "binaries" / "linux64").exists()
    assert needed_libraries(binary) <= {"libc.so.6", "libm.so.6"}
    defined = subprocess.run(["nm", "-D", "--defined-only", str(binary)], capture_output=True, text=True,
                             check=True).stdout.split()[2::3]
    assert defined and all(name.startswith("fmi3") for name in defined), defined
    assert {"fmi3InstantiateCoSimulation", "fmi3InstantiateModelExchange", "fmi3DoStep", "fmi3EnterConfigurationMode",
            "fmi3CompletedIntegratorStep", "fmi3SerializeFMUState"} <= set(defined)
    sources = fmi3["dir"] / "sources"
    for name in ("fmi3Functions.c", "joint_state.c", "model_variables.h", "build.sh", "kernels/wearjoint_advance.ll",
                 "kernels/linux64/wearjoint_advance.o"):
        assert (sources / name).is_file(), name
    assert not (sources / "fmi2Functions.c").exists()


def test_variables_enumerations_array_and_structure(fmi3):
    root = ET.fromstring(zipfile.ZipFile(fmi3["path"]).read("modelDescription.xml"))
    assert root.get("fmiVersion") == "3.0" and root.get("instantiationToken") and root.get("guid") is None
    variables = {v.get("name"): v for v in root.find("ModelVariables")}
    # every scalar keeps its FMI 2.0 value reference
    assert {name: int(v.get("valueReference")) for name, v in variables.items()} == VR3
    assert [n for n, vr in VR3.items() if vr < VR3["wear_depth"]] == [v.name for v in fv.fmu_variables(0)]
    # the options are FMI 3 enumerations with the parameter module's items
    types = {t.get("name"): t for t in root.find("TypeDefinitions")}
    for p in fv.PARAMETERS:
        v = variables[p.variable.name]
        if p.choices is None:
            assert v.tag == "Float64" and v.get("unit") == p.variable.unit
            continue
        assert v.tag == "Enumeration" and v.get("declaredType") == enumeration_type_name(p.variable.name)
        items = types[v.get("declaredType")]
        assert items.tag == "EnumerationType"
        assert [(i.get("name"), int(i.get("value"))) for i in items] == list(L.CHOICES[p.field])   # the kernels' codes
        assert int(v.get("start")) == p.variable.start
    n_points = variables["n_points"]
    assert (n_points.tag, n_points.get("causality"), n_points.get("variability"), n_points.get("start")) == \
        ("UInt64", "structuralParameter", "fixed", str(N_POINTS))
    wear = variables["wear_depth"]
    assert (wear.tag, wear.get("causality"), wear.get("unit")) == ("Float64", "output", "m")
    assert [d.get("valueReference") for d in wear.findall("Dimension")] == [str(VR3["n_points"])]
    assert not any(name.startswith("wear_depth[") for name in variables)
    assert variables["time"].get("causality") == "independent"
    structure = root.find("ModelStructure")
    outputs = {int(u.get("valueReference")): u.get("dependencies") for u in structure.findall("Output")}
    assert outputs == {VR3[n]: " ".join(str(VR3[i]) for i in fv.OUTPUT_DEPENDENCIES.get(n, ()))
                       for n in [*SCALAR_NAMES, *(v.name for v in fv.LINEARISATION_OUTPUTS), "wear_depth"]}
    assert [u.get("valueReference") for u in structure.findall("EventIndicator")] == [str(VR3["penetration"])]
    md = fmi3["md"]
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert root.find("CoSimulation").get("providesIntermediateUpdate") == "false"
    assert root.find("ModelExchange").get("needsCompletedIntegratorStep") == "true"


def test_pythonfmu_and_unknown_fmi_versions_are_refused(tmp_path):
    with pytest.raises(ParameterError, match="fmi_version"):
        build_fmu(tmp_path, backend="pythonfmu", fmi_version=3)
    with pytest.raises(ParameterError, match="fmi_version"):
        build_fmu(tmp_path, backend="native", fmi_version=4)
    assert not any(tmp_path.iterdir())


# ------------------------------------------------------------- the same numbers as FMI 2.0
def test_fmi3_cosimulation_equals_fmi2_over_a_trace_with_wear(fmi3, fmi2, trace, record_property):
    log = Log()
    fmu3 = _slave3(fmi3, log=log)
    fmu2, vr2 = _slave2(fmi2)
    try:
        worst_scalar, worst_profile, compared, profile3, profile2 = _run_side_by_side(fmu3, fmu2, vr2, trace, N_POINTS)
        record_property("fmi3_vs_fmi2_worst_relative", max(worst_scalar, worst_profile))
        assert compared == TRACE_ROWS
        assert profile3.max() > 1e-5            # the trace wore the bushing
        assert worst_scalar == 0.0 and worst_profile == 0.0   # bit for bit (<= 1e-12 required)
        assert np.array_equal(profile3, profile2)
        # the FMU state is the FMI 2.0 one, byte for byte
        state3, state2 = fmu3.getFMUState(), fmu2.getFMUState()
        assert fmu3.serializeFMUState(state3) == fmu2.serializeFMUState(state2)
        fmu3.freeFMUState(state3)
        fmu2.freeFMUState(state2)
        assert not log.messages
    finally:
        for fmu in (fmu3, fmu2):
            fmu.terminate()
            fmu.freeInstance()


@pytest.mark.parametrize("n_points", [628, pytest.param(2514, marks=pytest.mark.slow)])
def test_n_points_set_in_configuration_mode_sizes_the_profile(fmi3, trace, n_points, tmp_path_factory):
    fmu3 = _slave3(fmi3, n_points=n_points)
    fmi2_n = _unzipped(build_fmu(tmp_path_factory.mktemp(f"fmi2_n{n_points}"), n_points=n_points, backend="native"),
                       tmp_path_factory, f"fmi2_n{n_points}_unzipped")
    fmu2, vr2 = _slave2(fmi2_n)
    try:
        assert fmu3.getUInt64([VR3["n_points"]]) == [n_points]
        rows = trace[:800]
        worst_scalar, worst_profile, _, profile3, profile2 = _run_side_by_side(fmu3, fmu2, vr2, rows, n_points, 200)
        assert profile3.shape == (n_points,) and profile3.max() > 0
        assert worst_scalar == 0.0 and worst_profile == 0.0
        # the array holds exactly n_points values: asking for one more is an error
        with pytest.raises(FMICallException):
            fmu3.getFloat64([VR3["wear_depth"]], nValues=n_points + 1)
        # the state holds n_points depths (the FMI 2.0 format): 24-byte header, float64 values, CRC-32C
        state = fmu3.getFMUState()
        data = fmu3.serializeFMUState(state)
        assert len(data) == 24 + 8 * (fv.STATE_HEAD_SIZE + L.N_MEMORY + n_points) + 4
        assert np.array_equal(read_state_bytes(data, CONTENTS_FMU, fv.STATE_HEAD_SIZE, n_points)[2], profile3)
        fmu3.freeFMUState(state)
    finally:
        for fmu in (fmu3, fmu2):
            fmu.terminate()
            fmu.freeInstance()


def test_fmu_state_serialize_deserialize_round_trip_is_exact(fmi3, trace):
    fmu = _slave3(fmi3, n_points=628)
    inputs = [VR3[n] for n in INPUT_NAMES]
    outputs = [VR3[n] for n in SCALAR_NAMES]
    try:
        for row in trace[:1500]:
            fmu.setFloat64(inputs, list(row[2:]))
            fmu.doStep(row[0], row[1])
        state = fmu.getFMUState()
        data = fmu.serializeFMUState(state)
        fmu.freeFMUState(state)

        def continue_run():
            values = []
            for row in trace[1500:1900]:
                fmu.setFloat64(inputs, list(row[2:]))
                values.append(fmu.getFloat64(outputs))
                fmu.doStep(row[0], row[1])
            return np.array(values), np.array(fmu.getFloat64([VR3["wear_depth"]], nValues=628))

        first, profile = continue_run()
        restored = fmu.deserializeFMUState(data)
        fmu.setFMUState(restored)
        fmu.freeFMUState(restored)
        state = fmu.getFMUState()
        assert fmu.serializeFMUState(state) == data
        fmu.freeFMUState(state)
        again, profile_again = continue_run()
        assert np.array_equal(first, again) and np.array_equal(profile, profile_again)
        assert profile.max() > 0
    finally:
        fmu.terminate()
        fmu.freeInstance()


# ------------------------------------------------------------- bad input: fmi3Error with a message
def test_invalid_n_points_gives_fmi3error_naming_it(fmi3):
    log = Log()
    fmu = FMU3Slave(guid=fmi3["md"].guid, unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName="bad_n")
    fmu.instantiate(logMessage=log)
    try:
        fmu.enterConfigurationMode()
        for bad in (3, 0, 7, 10**7):
            with pytest.raises(FMICallException) as error:
                fmu.setUInt64([VR3["n_points"]], [bad])
            assert error.value.status == 3
            assert f"n_points={bad} is invalid" in log.messages[-1][2]
            assert "[8, 1000000]" in log.messages[-1][2] and log.messages[-1][0] == 3
        assert fmu.getUInt64([VR3["n_points"]]) == [N_POINTS]   # unchanged
        fmu.exitConfigurationMode()
        # outside Configuration Mode n_points cannot change
        with pytest.raises(FMICallException):
            fmu.setUInt64([VR3["n_points"]], [628])
        assert "Configuration Mode" in log.messages[-1][2] and "n_points" in log.messages[-1][2]
        fmu.setUInt64([VR3["n_points"]], [N_POINTS])   # its own value: allowed, nothing changes
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        assert fmu.getUInt64([VR3["n_points"]]) == [N_POINTS]
        assert len(fmu.getFloat64([VR3["wear_depth"]], nValues=N_POINTS)) == N_POINTS
    finally:
        fmu.terminate()
        fmu.freeInstance()


@pytest.mark.parametrize("name, value, allowed", [
    ("pin_radius", -0.01, "allowed > 0"),
    ("bushing_radius", 0.009, "allowed > 0 (at most 100 m) and > pin_radius"),
    ("restitution", 1.5, "allowed in [0.001, 1]"),
    ("rho_mode", 7, "allowed one of 0 (conformal), 1 (paper)"),
])
def test_bad_parameter_fails_initialisation_naming_the_variable(fmi3, name, value, allowed):
    log = Log()
    fmu = FMU3Slave(guid=fmi3["md"].guid, unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName="bad_parameter")
    fmu.instantiate(logMessage=log)
    try:
        fmu.enterInitializationMode()
        if isinstance(value, int):
            fmu.setInt64([VR3[name]], [value])
        else:
            fmu.setFloat64([VR3[name]], [value])
        with pytest.raises(FMICallException) as error:
            fmu.exitInitializationMode()
        assert error.value.status == 3
        status, category, message = log.messages[-1]
        assert (status, category) == (3, "logStatusError")
        assert message.startswith(f"fmi3ExitInitializationMode: parameter {name}={value} is invalid: {allowed}")
    finally:
        fmu.freeInstance()


def test_call_order_null_pointers_and_unknown_references_give_fmi3error(fmi3, capfd):
    log = Log()
    md = fmi3["md"]
    with pytest.raises(Exception, match="Failed to instantiate"):
        FMU3Slave(guid="{not-this-fmu}", unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME,
                  instanceName="token").instantiate(logMessage=log)
    assert "instantiationToken" in log.text()
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME, instanceName="order")
    fmu.instantiate(logMessage=log)
    lib, component = fmu.dll, fmu.component
    try:
        with pytest.raises(FMICallException):     # outputs before initialisation
            fmu.getFloat64([VR3["pin_force_x"]])
        with pytest.raises(FMICallException):     # doStep before initialisation
            fmu.doStep(0.0, 1e-3)
        assert "not allowed in state Instantiated" in log.text()
        fmu.enterInitializationMode()
        with pytest.raises(FMICallException):     # enterConfigurationMode after Instantiated
            fmu.enterConfigurationMode()
        fmu.exitInitializationMode()
        for call in (lambda: fmu.getFloat64([999]), lambda: fmu.setFloat64([VR3["pin_force_x"]], [1.0]),
                     lambda: fmu.setFloat64([VR3["pin_radius"]], [0.02]),     # a parameter after initialisation
                     lambda: fmu.getInt64([VR3["pin_radius"]]), lambda: fmu.getBoolean([0]),
                     lambda: fmu.getFloat64([VR3["pin_x"], VR3["wear_depth"]], nValues=2),
                     lambda: fmu.enterEventMode(), lambda: fmu.updateDiscreteStates()):
            with pytest.raises(FMICallException):
                call()
        # NULL arrays and pointers, straight through ctypes
        get = lib.fmi3GetFloat64
        get.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p, ctypes.c_size_t]
        assert get(component, None, 1, None, 1) == 3
        assert get(None, None, 0, None, 0) == 3
        step = lib.fmi3DoStep
        step.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_bool, ctypes.c_void_p,
                         ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
        assert step(component, 0.0, 1e-3, True, None, None, None, None) == 3
        state = lib.fmi3GetFMUState
        state.argtypes = [ctypes.c_void_p, ctypes.c_void_p]
        assert state(component, None) == 3
        assert "NULL" in log.text()
        # non-finite inputs: fmi3Error for the forces, fmi3Discard for the step; finite inputs recover
        fmu.setFloat64([VR3["pin_x"]], [float("nan")])
        with pytest.raises(FMICallException):
            fmu.getFloat64([VR3["normal_force"]])
        with pytest.raises(FMICallException) as discarded:
            fmu.doStep(0.0, 1e-3)
        assert discarded.value.status == 2
        flags, last = [ctypes.c_bool(True) for _ in range(3)], ctypes.c_double(-1.0)
        assert step(component, 0.0, 1e-3, True, *map(ctypes.byref, flags), ctypes.byref(last)) == 2
        assert [f.value for f in flags] == [False, True, False] and last.value == 0.0   # the step cannot be retaken
        fmu.setFloat64([VR3["pin_x"]], [0.0])
        fmu.doStep(0.0, 1e-3)
        vr = (fmi3ValueReference * 1)(VR3["time"])
        value = (fmi3Float64 * 1)()
        fmu.fmi3GetFloat64(component, vr, 1, value, 1)
        assert value[0] == 1e-3
        assert all(status == 3 or status == 2 for status, _, _ in log.messages)
    finally:
        fmu.terminate()
        fmu.freeInstance()
    assert capfd.readouterr().out == ""


# ------------------------------------------------------------- Model Exchange through fmpy's own solver
def _me_input(trace, rows):
    signals = np.zeros(rows, dtype=[("time", np.float64), *((name, np.float64) for name in INPUT_NAMES)])
    signals["time"] = trace[:rows, 0]
    for k, name in enumerate(INPUT_NAMES):
        signals[name] = trace[:rows, 2 + k]
    return signals


ME_ROWS = 600   # 60 ms of the trace: several contact onsets


def test_model_exchange_in_fmpy_equals_the_joint_at_the_output_points(fmi3, fmi2, trace):
    """fmpy.simulate_fmu(ModelExchange) with the trace's 12 inputs (linearly interpolated by fmpy),
    its own solver (CVode; no continuous states, so it steps between the output points and
    watches the event indicator).  The check: at every output point, the forces fmpy recorded
    equal the in-process ClearanceJoint's evaluation at the inputs the FMU held there, with the
    joint given the FMU's own wear profile and contact memory at that point (read from its FMU
    state, captured in step_finished right before fmpy samples).  Wear was applied at
    completedIntegratorStep, contact onsets stored at events; the FMI 2.0 build through the same
    solver gives the same records."""
    signals = _me_input(trace, ME_ROWS)
    stop = float(trace[ME_ROWS - 1, 0])
    reals, _ = fv.fmi_parameter_values_by_type(TRACE_JOINT)
    fmu = FMU3Model(guid=fmi3["md"].guid, unzipDirectory=str(fmi3["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName="me")
    fmu.instantiate()
    states = {}

    def capture(time, recorder):
        state = fmu.getFMUState()
        states[time] = fmu.serializeFMUState(state)
        fmu.freeFMUState(state)
        return True

    outputs = [*FORCE_NAMES, "max_wear_depth", "wear_depth", *INPUT_NAMES]
    try:
        result = simulate_fmu(str(fmi3["path"]), fmi_type="ModelExchange", fmu_instance=fmu, input=signals,
                              start_values=reals, stop_time=stop, output_interval=TRACE_STEP, output=outputs,
                              step_finished=capture)
    finally:
        fmu.freeInstance()
    assert len(result) >= ME_ROWS - 1
    joint = ClearanceJoint(TRACE_JOINT)
    checked = onsets = 0
    previous_contact = 0.0
    last_at = {time: i for i, time in enumerate(result["time"])}   # after an event: the row after its update
    for i, row in enumerate(result):
        data = states.get(row["time"])
        if data is None or last_at[row["time"]] != i:
            continue
        head, memory, wear = read_state_bytes(data, CONTENTS_FMU, fv.STATE_HEAD_SIZE, TRACE_JOINT.n_points)
        inputs = head[2:2 + len(fv.INPUTS)]
        assert np.array_equal(inputs, [row[name] for name in INPUT_NAMES])
        assert np.array_equal(wear, row["wear_depth"])
        joint.set_state(JointState(wear, memory))
        expected = joint.evaluate_array(inputs[0:3], inputs[3:6], inputs[6:9], inputs[9:12])
        assert [row[name] for name in FORCE_NAMES] == [expected[fv.RESULT_SLOTS[name]] for name in FORCE_NAMES]
        onsets += previous_contact < 0.5 <= row["contact"]
        previous_contact = row["contact"]
        checked += 1
    assert checked >= ME_ROWS - 1 and onsets >= 3
    assert result["max_wear_depth"][-1] > 0 and result["wear_depth"].shape[1] == N_POINTS

    # the FMI 2.0 build runs in Model Exchange through the same solver and records the same numbers
    result2 = simulate_fmu(str(fmi2["path"]), fmi_type="ModelExchange", input=signals, start_values=reals,
                           stop_time=stop, output_interval=TRACE_STEP, output=[*FORCE_NAMES, "max_wear_depth"])
    assert len(result2) == len(result)
    for name in ("time", *FORCE_NAMES, "max_wear_depth"):
        assert np.array_equal(result2[name], result[name]), name


def test_cli_builds_fmi3_with_the_flag_and_fmi2_by_default(fmi3_fmu, tmp_path, capsys):
    from wearjoint.cli import main

    assert main(["build-fmu", "--fmi-version", "3", "--out", str(tmp_path / "three")]) == 0
    built = Path(capsys.readouterr().out.strip())
    assert read_model_description(str(built)).fmiVersion == "3.0"
    assert zipfile.ZipFile(built).read("modelDescription.xml").count(b"instantiationToken") == 1
    assert main(["build-fmu", "--backend", "pythonfmu", "--fmi-version", "3", "--out", str(tmp_path / "py")]) == 2
    assert "fmi_version" in capsys.readouterr().err
    from wearjoint.fmu.build import DEFAULT_FMI_VERSION, default_fmu_path

    assert DEFAULT_FMI_VERSION == 2
    assert default_fmu_path(fmi_version=3) != default_fmu_path()
