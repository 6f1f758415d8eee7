"""The ClearanceWearJoint FMU (docs/model.md section 5) of both backends driven through fmpy.

Each FMU is built once per session (fixtures ``native_fmu``, ``built_fmu`` for pythonfmu);
the behaviour tests run on both backends (fixture ``fmu``); every test gets fresh instances.
"""
import collections
import gc
import itertools
import json
import math
import os
import subprocess
import sys
import textwrap
from ctypes import byref
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import (FMU2Slave, defaultCallbacks, fmi2CallbackFunctions,  # noqa: E402
                       fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.core import state_format  # noqa: E402
from wearjoint.joint import read_state_bytes, state_bytes  # noqa: E402
from wearjoint.cli.build_fmu import add_arguments, run  # noqa: E402
from wearjoint.fmu.build_pythonfmu import build_fmu, build_key, default_fmu_path  # noqa: E402

FMI_DISCARD, FMI_ERROR, FMI_FATAL = 2, 3, 4
INPUT_NAMES = [v.name for v in fv.INPUTS]
FORCE_NAMES = ["pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque"]
SCALAR_NAMES = [v.name for v in fv.SCALAR_OUTPUTS]
P = JointParameters()
REPO_ROOT = Path(__file__).resolve().parents[1]


def rotate(angle, x, y):
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


def contact_inputs(depth=5e-6, direction=1.0, pin_omega=10.0, bushing_x=0.2):
    """Inputs with the pin centre at clearance + ``depth`` from the bushing centre along
    the global angle ``direction``; both bodies rotated, the pin spinning about its resting centre."""
    bushing_angle, pin_angle = 0.3, 0.7
    bx, by = rotate(bushing_angle, *P.bushing_offset_m)
    centre = (bushing_x + bx, 0.05 + by)
    e = P.clearance_m + depth
    pin_centre = (centre[0] + e * math.cos(direction), centre[1] + e * math.sin(direction))
    px, py = rotate(pin_angle, *P.pin_offset_m)
    return [pin_centre[0] - px, pin_centre[1] - py, pin_angle, pin_omega * py, -pin_omega * px, pin_omega,
            bushing_x, 0.05, bushing_angle, 0.0, 0.0, 0.0]


# fmpy's native logger proxy (it formats the printf-style message) keeps ONE logger per
# process, so all instances share this one and messages are routed by instance name.
LOGS = collections.defaultdict(list)
_LOGGER = fmi2CallbackLoggerTYPE(
    lambda env, instance, status, category, message: LOGS[instance.decode()].append((status, message.decode())))
CALLBACKS = fmi2CallbackFunctions(logger=_LOGGER, allocateMemory=defaultCallbacks.allocateMemory,
                                  freeMemory=defaultCallbacks.freeMemory)
addLoggerProxy(byref(CALLBACKS))
_INSTANCE_NUMBERS = itertools.count()


class Slave:
    """One fmpy FMU2Slave instance (unique instance name) with its log messages as (status, text)."""

    def __init__(self, fmu, name, parameters=None, integers=None, logging_on=True):
        self.vr = fmu["vr"]
        name = f"{name}_{next(_INSTANCE_NUMBERS)}"
        self.log = LOGS[name]
        md = fmu["md"]
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmu["dir"],
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=CALLBACKS, loggingOn=logging_on)
        self.start(parameters, integers)

    def start(self, parameters=None, integers=None):
        """setupExperiment, enterInitializationMode and the given parameter values."""
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        if parameters:
            self.fmu.setReal([self.vr[k] for k in parameters], list(parameters.values()))
        if integers:
            self.fmu.setInteger([self.vr[k] for k in integers], list(integers.values()))
        return self

    def initialise(self):
        self.fmu.exitInitializationMode()
        return self

    def set_inputs(self, values):
        self.fmu.setReal([self.vr[n] for n in INPUT_NAMES], list(values))

    def get(self, names):
        return np.array(self.fmu.getReal([self.vr[n] for n in names]))

    def errors(self):
        return [text for status, text in self.log if status >= FMI_ERROR]

    def assert_failed_with_error(self, failure, *words):
        """The call failed with fmi2Error, logged (status error, no fatal) with all ``words``."""
        assert failure.value.status == FMI_ERROR
        assert any(all(w in text for w in words) for status, text in self.log if status == FMI_ERROR), self.log
        assert not any(status == FMI_FATAL for status, _ in self.log), self.log

    def free(self):
        self.fmu.freeInstance()


@pytest.fixture(scope="module")
def fmu(any_fmu, tmp_path_factory):
    backend, path = any_fmu
    md = read_model_description(str(path))
    directory = extract(str(path), unzipdir=str(tmp_path_factory.mktemp("fmu_extracted")))
    wear = [fv.wear_depth_name(z) for z in range(1, P.n_points + 1)]
    return {"md": md, "dir": directory, "vr": fv.value_references(md), "wear": wear, "backend": backend,
            "path": path}


@pytest.fixture
def slave(fmu):
    s = Slave(fmu, "joint").initialise()
    yield s
    s.free()


# ------------------------------------------------------------- modelDescription
def test_validate_fmu_reports_no_problem(fmu):
    assert validate_fmu(str(fmu["path"])) == []


def test_model_description_matches_the_variable_table(fmu):
    md = fmu["md"]
    table = fv.fmu_variables(P.n_points)
    assert [v.name for v in md.modelVariables] == [v.name for v in table]
    for v, row in zip(md.modelVariables, table):
        assert v.description, v.name
        assert v.causality == row.causality
        if v.type == "Real":
            assert v.unit == row.unit, v.name
    n_points = next(v for v in md.modelVariables if v.name == "n_points")
    assert (n_points.variability, int(n_points.start)) == ("constant", P.n_points)
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert md.coSimulation.providesDirectionalDerivative == (fmu["backend"] == "native")   # pythonfmu: none


def test_parameter_defaults_are_the_papers(fmu):
    starts = {}
    for v in fmu["md"].modelVariables:
        if v.causality == "parameter":
            starts[v.name] = int(v.start) if v.type == "Integer" else float(v.start)
    assert fv.joint_parameters_from_fmi(starts, P.n_points) == JointParameters()


def test_every_joint_parameter_is_an_fmu_parameter():
    from dataclasses import fields

    covered = {p.field for p in fv.PARAMETERS} | {"n_points"}
    assert covered == {f.name for f in fields(JointParameters)}
    assert fv.joint_parameters_from_fmi(fv.fmi_parameter_values(P.replace(rho_mode="paper")), P.n_points) \
        == P.replace(rho_mode="paper")


def test_model_structure_declares_direct_feed_through(fmu):
    md = fmu["md"]
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    for unknown in md.outputs:
        depends_on = {v.name for v in unknown.dependencies}
        if unknown.variable.name in fv.FEED_THROUGH_OUTPUTS:   # the geometry: positions; the forces: all inputs
            assert depends_on == set(fv.OUTPUT_DEPENDENCIES[unknown.variable.name]) <= inputs, unknown.variable.name
        else:
            assert depends_on == set(), unknown.variable.name


# ------------------------------------------------------------- forces
def test_forces_are_the_joints_and_point_back_to_the_bushing_centre(slave):
    direction = 1.0
    x = contact_inputs(direction=direction)
    slave.set_inputs(x)
    out = dict(zip(SCALAR_NAMES, slave.get(SCALAR_NAMES)))

    expected = ClearanceJoint(JointParameters()).evaluate(x[:6], x[6:])
    got = [out[n] for n in FORCE_NAMES]
    np.testing.assert_allclose(got, [*expected.pin_force, *expected.bushing_force], rtol=1e-12, atol=0)
    assert out["contact"] == 1.0
    assert out["penetration"] == pytest.approx(5e-6, rel=1e-3)
    assert out["normal_force"] == pytest.approx(expected.normal_force_N, rel=1e-12)
    # the foundation's K delta^1.5 (3 % under it at 5 um: docs/model.md §3.10)
    assert out["normal_force"] == pytest.approx(P.contact_stiffness_N_m1_5 * 5e-6 ** 1.5, rel=4e-2)

    pin_force = np.array([out["pin_force_x"], out["pin_force_y"]])
    outward = np.array([math.cos(direction), math.sin(direction)])
    cos_to_centre = -pin_force @ outward / np.linalg.norm(pin_force)
    assert cos_to_centre >= math.cos(math.atan(P.friction_coefficient)) - 1e-9
    assert out["pin_force_x"] == -out["bushing_force_x"] and out["pin_force_y"] == -out["bushing_force_y"]
    # contact angle and eccentricity in the bushing frame (bushing body angle 0.3 rad)
    assert out["contact_angle"] == pytest.approx(direction - 0.3, abs=2 * math.pi / P.n_points)
    np.testing.assert_allclose([out["eccentricity_x"], out["eccentricity_y"]],
                               (P.clearance_m + 5e-6) * np.array([math.cos(0.7), math.sin(0.7)]), rtol=1e-6)


def test_outputs_follow_inputs_without_a_step(slave):
    slave.set_inputs(contact_inputs(depth=2e-6))
    shallow = slave.get(["normal_force"])[0]
    slave.set_inputs(contact_inputs(depth=4e-6))
    deep = slave.get(["normal_force"])[0]
    assert deep / shallow == pytest.approx(2.0 ** 1.5, rel=2e-2)
    slave.set_inputs(contact_inputs(depth=-5e-5))
    assert list(slave.get(["contact", "normal_force", "pin_force_x"])) == [0.0, 0.0, 0.0]


def test_get_real_of_any_list_matches_one_value_at_a_time(slave, fmu):
    slave.set_inputs(contact_inputs(depth=4e-6))
    for k in range(20):
        slave.fmu.doStep(k * 1e-5, 1e-5)
    worn = int(np.argmax(slave.get(fmu["wear"]))) + 1
    names = [fv.wear_depth_name(worn), "pin_force_x", "pin_x", "max_wear_depth", "restitution", "pin_force_x",
             "worn_volume", "normal_force", fv.wear_depth_name(1), "bushing_omega"]
    together = slave.get(names)
    one_by_one = [slave.get([name])[0] for name in names]
    assert together.tolist() == one_by_one
    assert together[0] > 0.0 and together[3] == together[0] and together[4] == P.restitution
    assert slave.fmu.getReal([]) == []


def test_set_real_in_any_order_or_subset_equals_the_full_write(slave):
    x = contact_inputs(depth=3e-6)
    slave.set_inputs(x)
    expected = slave.get(SCALAR_NAMES)
    slave.set_inputs(contact_inputs(depth=-5e-5))
    order = list(reversed(INPUT_NAMES))
    slave.fmu.setReal([slave.vr[n] for n in order], [x[INPUT_NAMES.index(n)] for n in order])
    assert slave.get(SCALAR_NAMES).tolist() == expected.tolist()
    slave.set_inputs(contact_inputs(depth=-5e-5))
    for name, value in zip(INPUT_NAMES, x):
        slave.fmu.setReal([slave.vr[name]], [value])
    assert slave.get(SCALAR_NAMES).tolist() == expected.tolist()


def test_non_finite_input_is_forgotten_once_set_finite(slave):
    x = contact_inputs()
    x[3] = math.inf
    slave.set_inputs(x)
    with pytest.raises(FMICallException) as failure:
        slave.get(["pin_force_x"])
    slave.assert_failed_with_error(failure, "pin_force_x", "pin_vx=inf")
    slave.fmu.setReal([slave.vr["pin_vx"]], [0.0])   # a subset write clears it
    assert slave.get(["contact"])[0] == 1.0
    huge = contact_inputs(depth=-5e-5)
    huge[0] += 1e308   # finite values whose sum overflows: both bodies far out, no contact
    huge[6] += 1e308
    slave.set_inputs(huge)
    assert slave.get(["contact", "normal_force"]).tolist() == [0.0, 0.0]
    gc.collect()


def test_calls_on_the_wrong_variables_fail_with_fmi2_error_naming_them(slave):
    """Outputs and Integers are not settable as Reals, Reals not as Integers, and the FMU has no
    Booleans or Strings: each call fails with fmi2Error and the instance goes on."""
    vr = slave.vr
    for call, words in ((lambda: slave.fmu.setReal([vr["pin_force_x"]], [1.0]), ("pin_force_x", "cannot be set")),
                        (lambda: slave.fmu.setReal([vr["rho_mode"]], [1.0]), ("rho_mode", "cannot be set")),
                        (lambda: slave.fmu.setInteger([vr["restitution"]], [1]), ("restitution", "cannot be set")),
                        (lambda: slave.fmu.getReal([vr["rho_mode"]]), ("rho_mode", "Real")),
                        (lambda: slave.fmu.getInteger([vr["pin_x"]]), ("pin_x", "Integer")),
                        (lambda: slave.fmu.getBoolean([0]), ("Boolean",))):
        with pytest.raises(FMICallException) as failure:
            call()
        slave.assert_failed_with_error(failure, *words)
    assert slave.fmu.getInteger([vr["rho_mode"], vr["n_points"]]) == [0, P.n_points]
    slave.set_inputs(contact_inputs())
    assert slave.get(["contact"])[0] == 1.0
    gc.collect()


# ------------------------------------------------------------- wear
def test_do_step_wears_where_the_pin_presses(slave, fmu):
    x = contact_inputs(direction=2.0, pin_omega=10.0)
    slave.set_inputs(x)
    dt, steps, archard = 1e-5, 40, 0.0
    for k in range(steps):
        normal_force = slave.get(["normal_force"])[0]
        archard += P.wear_coefficient_m2_N * normal_force * P.bushing_radius_m * 10.0 * dt
        slave.fmu.doStep(k * dt, dt)
    h = slave.get(fmu["wear"])
    contact_angle, max_wear, volume = slave.get(["contact_angle", "max_wear_depth", "worn_volume"])

    phi = np.arange(1, P.n_points + 1) * 2 * math.pi / P.n_points
    assert h.min() >= 0.0 and h.max() > 0.0
    offset = np.abs(np.remainder(phi - contact_angle + math.pi, 2 * math.pi) - math.pi)
    assert h[np.argmin(offset)] > 0.0
    worn = h > 0.0
    centre = math.atan2(np.sin(phi[worn]).mean(), np.cos(phi[worn]).mean())
    assert abs(math.remainder(centre - contact_angle, 2 * math.pi)) < 2 * 2 * math.pi / P.n_points
    assert np.all(h[offset > 0.5] == 0.0)
    assert max_wear == h.max()
    # polar area between the worn and the unworn circle, times the contact length
    area = 0.5 * np.sum((P.bushing_radius_m + h) ** 2 - P.bushing_radius_m ** 2) * 2 * math.pi / P.n_points
    assert volume == pytest.approx(P.contact_length_m * area, rel=1e-12)
    # Archard: removed volume = k_w * F_N * sliding distance (rotation: R_j |omega_rel| dt)
    assert volume == pytest.approx(archard, rel=2e-2)


def test_two_instances_keep_independent_state(fmu):
    a = Slave(fmu, "a").initialise()
    b = Slave(fmu, "b").initialise()
    try:
        a.set_inputs(contact_inputs(depth=5e-6))
        b.set_inputs(contact_inputs(depth=-2e-5))
        for k in range(20):
            a.fmu.doStep(k * 1e-5, 1e-5)
            b.fmu.doStep(k * 1e-5, 1e-5)
        assert a.get(["max_wear_depth"])[0] > 0.0
        assert b.get(["max_wear_depth", "worn_volume", "normal_force"]).tolist() == [0.0, 0.0, 0.0]
        assert a.get(["contact"])[0] == 1.0
    finally:
        a.free()
        b.free()


# ------------------------------------------------------------- FMU state
def _run(slave, fmu, steps, t0, dt=1e-5):
    """Steps with a slowly changing input; every output after every step."""
    names = SCALAR_NAMES + fmu["wear"]
    rows = []
    for k in range(steps):
        slave.set_inputs(contact_inputs(depth=3e-6 + 1e-7 * k, direction=1.0 + 0.01 * k))
        slave.fmu.doStep(t0 + k * dt, dt)
        rows.append(slave.get(names))
    return np.array(rows)


def test_fmu_state_round_trip_is_exact(slave, fmu):
    _run(slave, fmu, 10, 0.0)
    state = slave.fmu.getFMUstate()
    first = _run(slave, fmu, 15, 1e-4)
    slave.fmu.setFMUstate(state)
    again = _run(slave, fmu, 15, 1e-4)
    assert first[:, SCALAR_NAMES.index("max_wear_depth")].max() > 0.0
    assert np.array_equal(first, again)

    serialised = slave.fmu.serializeFMUstate(state)
    slave.fmu.freeFMUstate(state)
    other = Slave(fmu, "restored").initialise()
    try:
        restored = other.fmu.deSerializeFMUstate(serialised)
        other.fmu.setFMUstate(restored)
        assert np.array_equal(_run(other, fmu, 15, 1e-4), first)
    finally:
        other.free()


def test_fmu_state_carries_the_parameters(fmu):
    a = Slave(fmu, "state_a", parameters={"restitution": 0.5, "friction_coefficient": 0.2}).initialise()
    b = Slave(fmu, "state_b").initialise()
    try:
        _run(a, fmu, 5, 0.0)
        state = a.fmu.getFMUstate()
        serialised = a.fmu.serializeFMUstate(state)
        expected = _run(a, fmu, 5, 5e-5)
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(serialised))
        assert np.array_equal(_run(b, fmu, 5, 5e-5), expected)
        a.fmu.setFMUstate(state)   # back to the state taken, same parameters: nothing rebuilt
        assert np.array_equal(_run(a, fmu, 5, 5e-5), expected)
    finally:
        a.free()
        b.free()


def test_a_bad_deserialised_state_fails_with_fmi2_error(slave, fmu):
    """Refused at deSerializeFMUstate (native) or at setFMUstate (pythonfmu), with fmi2Error naming the
    failed check: the checksum of a changed byte, the size of a truncated state, the range of a value
    in a state sealed with a valid checksum."""
    _run(slave, fmu, 3, 0.0)
    good = slave.fmu.serializeFMUstate(slave.fmu.getFMUstate())
    flipped = bytearray(good)
    flipped[-12] ^= 0x10
    head, memory, wear = read_state_bytes(good, state_format.CONTENTS_FMU, fv.STATE_HEAD_SIZE, P.n_points)
    # the FMU (native: the kernels compiled into it) and the in-process writer give the same bytes
    assert state_bytes(state_format.CONTENTS_FMU, head, memory, wear) == good and wear.max() > 0.0
    wear[-1] = -1e-6
    cases = [(bytes(flipped), ("FMUstate", "CRC-32C", "corrupted")),
             (good[:-8], ("FMUstate", f"has {len(good) - 8} bytes, its header declares {len(good)}")),
             (state_bytes(state_format.CONTENTS_FMU, head, memory, wear),
              ("FMUstate", f"wear_depth[{P.n_points}]=-1e-06 m is negative: allowed a depth in [0, 0.0101] m"))]
    for data, words in cases:
        with pytest.raises(FMICallException) as failure:
            slave.fmu.setFMUstate(slave.fmu.deSerializeFMUstate(data))
        slave.assert_failed_with_error(failure, *words)
    slave.fmu.setFMUstate(slave.fmu.deSerializeFMUstate(good))
    assert slave.get(["max_wear_depth"])[0] > 0.0
    gc.collect()


# ------------------------------------------------------------- errors
# The FMU's status shim turns the slave's errors into fmi2Error (pythonfmu alone: fmi2Fatal).
@pytest.mark.parametrize("name, value, allowed", [
    ("bushing_radius", 0.0099, "pin_radius"), ("restitution", 1.5, "(0, 1]"), ("friction_v1", 1e-4, "friction_v0"),
    ("rho_mode", 2, "paper"), ("contact_exponent", 2.0, "1.5 with contact_model"),   # the default foundation
])
def test_bad_parameter_fails_initialisation_with_fmi2_error_naming_it(fmu, name, value, allowed):
    kind = "integers" if isinstance(value, int) else "parameters"
    s = Slave(fmu, f"bad_{name}", **{kind: {name: value}})
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, name, repr(value), allowed)
    s.fmu.terminate()
    s.free()
    gc.collect()  # the host survives pythonfmu's reference release after the failure
    fresh = Slave(fmu, "after_failure").initialise()
    fresh.set_inputs(contact_inputs())
    assert fresh.get(["contact"])[0] == 1.0
    fresh.free()


def test_instance_is_reset_after_a_failed_initialisation(fmu):
    s = Slave(fmu, "reset", parameters={"restitution": 1.5})
    with pytest.raises(FMICallException):
        s.initialise()
    s.fmu.reset()
    gc.collect()
    s.start(parameters={"restitution": 0.8}).initialise()
    x = contact_inputs()
    s.set_inputs(x)
    expected = ClearanceJoint(P.replace(restitution=0.8)).evaluate(x[:6], x[6:])
    np.testing.assert_allclose(s.get(FORCE_NAMES[:3]), expected.pin_force, rtol=1e-12, atol=0)
    s.free()


def test_errors_are_logged_with_logging_off(fmu):
    s = Slave(fmu, "quiet", parameters={"restitution": 1.5}, logging_on=False)
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, "restitution")
    s.free()
    gc.collect()


def test_n_points_and_fixed_parameters_cannot_change(fmu, slave):
    s = Slave(fmu, "n_points")
    s.fmu.setInteger([s.vr["n_points"]], [P.n_points])  # the built value is accepted
    with pytest.raises(FMICallException) as failure:
        s.fmu.setInteger([s.vr["n_points"]], [100])
    s.assert_failed_with_error(failure, "n_points", "100")
    s.free()
    with pytest.raises(FMICallException) as failure:
        slave.fmu.setReal([slave.vr["restitution"]], [0.5])
    slave.assert_failed_with_error(failure, "restitution", "fixed")
    gc.collect()


def test_non_finite_input_fails_get_real_and_discards_do_step(slave, fmu):
    x = contact_inputs()
    x[0] = math.nan
    slave.set_inputs(x)
    with pytest.raises(FMICallException) as failure:
        slave.get(["normal_force", "worn_volume"])
    slave.assert_failed_with_error(failure, "normal_force", "pin_x=nan")
    assert slave.get(["worn_volume", "max_wear_depth"]).tolist() == [0.0, 0.0]  # not input-dependent
    with pytest.raises(FMICallException) as failure:
        slave.fmu.doStep(0.0, 1e-5)
    assert failure.value.status == FMI_DISCARD
    assert sum("dostep" in text.lower() and "pin_x" in text for text in slave.errors()) == 1
    slave.set_inputs(contact_inputs())
    slave.fmu.doStep(0.0, 1e-5)
    assert slave.get(["contact"])[0] == 1.0
    gc.collect()


# ------------------------------------------------------------- run-time imports
HOST_SCRIPT = textwrap.dedent("""
    import json, sys
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    fmu = sys.argv[1]
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    before = set(sys.modules)
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu), modelIdentifier="ClearanceWearJoint",
                  instanceName="imports")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.setReal([vr["pin_x"]], [-0.135])
    s.doStep(0.0, 1e-5)
    force = s.getReal([vr["pin_force_x"], vr["worn_volume"]])
    s.terminate()
    s.freeInstance()
    loaded = sorted(set(sys.modules) - before)
    wearjoint_file = sys.modules["wearjoint"].__file__
    try:
        import scipy  # the host may still import it itself
        host_scipy = True
    except ImportError:
        host_scipy = False
    print(json.dumps({"loaded": loaded, "wearjoint": wearjoint_file, "host_scipy": host_scipy}))
""")


def test_fmu_runtime_imports_only_numpy_numba_and_wearjoint(built_fmu, tmp_path):
    done = subprocess.run([sys.executable, "-c", HOST_SCRIPT, str(built_fmu)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    heavy = [m for m in report["loaded"] if m.split(".")[0] in ("scipy", "matplotlib", "exudyn", "fmpy_gui")]
    assert heavy == []
    assert "numba" in report["loaded"] and "wearjoint.joint" in report["loaded"]
    assert "resources" in report["wearjoint"]  # the FMU's own copy of the package
    try:
        import scipy  # noqa: F401
    except ImportError:
        return
    assert report["host_scipy"], "the FMU left scipy blocked in sys.modules"


def test_library_modules_stay_light(tmp_path):
    code = ("import sys, wearjoint.fmu.variables, wearjoint.fmu.build_pythonfmu; "
            "print(sorted(m for m in ('pythonfmu', 'fmpy', 'exudyn', 'matplotlib') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                          cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(REPO_ROOT)})
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


CLOSURE_SCRIPT = textwrap.dedent("""
    import json, sys
    resources = sys.argv[1]
    sys.path.insert(0, resources)
    import ClearanceWearJoint  # noqa: F401
    print(json.dumps({name: module.__file__ for name, module in sys.modules.items()
                      if name == "wearjoint" or name.startswith("wearjoint.")}))
""")


def test_fmu_ships_exactly_the_slaves_import_closure(fmu, tmp_path):
    if fmu["backend"] != "pythonfmu":
        pytest.skip("the native FMU ships no Python")
    resources = Path(fmu["dir"]) / "resources"
    done = subprocess.run([sys.executable, "-c", CLOSURE_SCRIPT, str(resources)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    loaded = {Path(f).resolve() for f in json.loads(done.stdout.strip().splitlines()[-1]).values()}
    package = (resources / "wearjoint").resolve()
    assert all(package in f.parents for f in loaded), loaded   # nothing from the source tree
    assert loaded == {f.resolve() for f in package.rglob("*.py")}


def test_build_key_follows_the_shipped_files_only(tmp_path, monkeypatch):
    from wearjoint.fmu import build_pythonfmu as fmu_build

    tree = tmp_path / "tree"
    for source in (*fmu_build.shipped_sources(), fmu_build.PACKAGE_DIR / "runner.py"):
        copy = tree / source.relative_to(fmu_build.PACKAGE_DIR.parent)
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_bytes(source.read_bytes())
    monkeypatch.setattr(fmu_build, "PACKAGE_DIR", tree / "wearjoint")
    monkeypatch.setattr(fmu_build, "SLAVE_SOURCE", tree / fmu_build.SLAVE_SOURCE.relative_to(REPO_ROOT))
    monkeypatch.setattr(fmu_build, "SHIM_SOURCE", tree / fmu_build.SHIM_SOURCE.relative_to(REPO_ROOT))
    key = fmu_build.build_key(P.n_points)
    assert key == build_key(P.n_points)

    def edited(relative):
        path = tree / relative
        original = path.read_bytes()
        path.write_bytes(original + b"\n# edited\n")
        try:
            return fmu_build.build_key(P.n_points)
        finally:
            path.write_bytes(original)

    assert edited("wearjoint/runner.py") == key
    for shipped in ("wearjoint/joint.py", "wearjoint/core/contact.py", "fmu_src/status_shim.c",
                    "fmu_src/ClearanceWearJoint.py"):
        assert edited(shipped) != key, shipped


# ------------------------------------------------------------- build command
def test_build_is_skipped_when_identical_and_n_points_is_built_in(tmp_path):
    small = build_fmu(tmp_path, n_points=64)
    stamp = small.stat().st_mtime_ns
    assert build_fmu(tmp_path, n_points=64) == small
    assert small.stat().st_mtime_ns == stamp
    build_fmu(tmp_path, n_points=64, force=True)
    assert small.stat().st_mtime_ns != stamp

    md = read_model_description(str(small))
    assert sum(v.name.startswith("wear_depth[") for v in md.modelVariables) == 64
    assert next(int(v.start) for v in md.modelVariables if v.name == "n_points") == 64
    assert validate_fmu(str(small)) == []
    assert default_fmu_path(64) != default_fmu_path(P.n_points)


@pytest.mark.parametrize("backend", ["native", "pythonfmu"])
def test_build_fails_clearly_without_a_c_compiler(tmp_path, monkeypatch, capsys, backend):
    import argparse

    from wearjoint.fmu.build import build_fmu as build_with

    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    with pytest.raises(RuntimeError, match="C compiler"):
        build_with(tmp_path, n_points=64, force=True, backend=backend)
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    assert run(parser.parse_args(["--out", str(tmp_path / "out"), "--n-points", "64", "--backend", backend])) == 2
    assert "no-such-cc" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("backend", ["native", "pythonfmu"])
def test_cli_reports_a_bad_n_points(capsys, tmp_path, backend):
    import argparse

    parser = argparse.ArgumentParser()
    add_arguments(parser)
    assert run(parser.parse_args(["--out", str(tmp_path), "--n-points", "3", "--backend", backend])) == 2
    assert "n_points" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())
