"""FMU states of the native joint FMU: in memory getFMUstate/setFMUstate copy the joint's values (no
checksum: the co-simulation master's rollbacks), a state may be overwritten in place; serialised states
keep the state format and every check, and a refused one leaves the state it was to overwrite as it was."""
from ctypes import byref

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402

from fmpy_instance import enter_initialisation  # noqa: E402
from kinematic_trace import slider_crank_trace  # noqa: E402
from wearjoint import paper_joint  # noqa: E402
from wearjoint.core import state_format  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.joint import read_state_bytes, state_bytes  # noqa: E402

JOINT = paper_joint(wear_factor=2000.0)
STEP_S = 1e-5
ROWS = slider_crank_trace(JOINT, 2400, STEP_S)   # in contact and wearing from about row 1000


@pytest.fixture
def instance(native_fmu, tmp_path):
    md = read_model_description(str(native_fmu))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(native_fmu), unzipdir=str(tmp_path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="memory_state")
    fmu.instantiate()
    vr = fv.value_references(md)
    enter_initialisation(fmu, vr, JOINT)
    fmu.exitInitializationMode()
    yield fmu, vr
    fmu.terminate()
    fmu.freeInstance()


def _run(fmu, vr, rows):
    """Inputs, outputs and doStep per row; every scalar output after each, then the wear profile."""
    inputs = [vr[v.name] for v in fv.INPUTS]
    outputs = [vr[v.name] for v in fv.SCALAR_OUTPUTS]
    seen = []
    for t, h, *kinematics in rows:
        fmu.setReal(inputs, kinematics)
        seen.extend(fmu.getReal(outputs))
        fmu.doStep(t, h)
    wear = fmu.getReal([vr[fv.wear_depth_name(z)] for z in range(1, JOINT.n_points + 1)])
    return np.array(seen + list(wear))


def test_in_memory_state_round_trip_is_exact_when_overwritten_in_place(instance):
    fmu, vr = instance
    _run(fmu, vr, ROWS[:1000])
    state = fmu.getFMUstate()
    pointer = state.value
    _run(fmu, vr, ROWS[1000:1200])
    fmu.fmi2GetFMUstate(fmu.component, byref(state))      # the master's rollback snapshot: reused
    assert state.value == pointer
    first = _run(fmu, vr, ROWS[1200:2400])
    fmu.setFMUstate(state)
    assert np.array_equal(_run(fmu, vr, ROWS[1200:2400]), first)
    assert first[-JOINT.n_points:].max() > 0.0                # the bushing wore after the snapshot
    fmu.freeFMUstate(state)


def test_corrupted_serialised_state_is_refused_and_changes_no_state(instance):
    fmu, vr = instance
    _run(fmu, vr, ROWS[:1200])
    state = fmu.getFMUstate()
    data = fmu.serializeFMUstate(state)
    head, memory, wear = read_state_bytes(data, state_format.CONTENTS_FMU, fv.STATE_HEAD_SIZE, JOINT.n_points)
    assert state_bytes(state_format.CONTENTS_FMU, head, memory, wear) == data and wear.max() > 0.0
    expected = _run(fmu, vr, ROWS[1200:1600])
    corrupted = bytearray(data)
    corrupted[len(data) // 2] ^= 0x04                        # one bit of a wear depth
    with pytest.raises(FMICallException):
        fmu.deSerializeFMUstate(bytes(corrupted), state)     # to overwrite the state: refused
    fmu.setFMUstate(state)                                   # the state as it was
    assert np.array_equal(_run(fmu, vr, ROWS[1200:1600]), expected)
    restored = fmu.deSerializeFMUstate(data)
    fmu.setFMUstate(restored)
    assert np.array_equal(_run(fmu, vr, ROWS[1200:1600]), expected)
    assert fmu.serializeFMUstate(restored) == data
    fmu.freeFMUstate(state)
    fmu.freeFMUstate(restored)
