"""The FMU states of the ClearanceWearJoint FMU of both backends through fmpy: a round trip is exact, a
state carries the parameters, a bad deserialised state fails with fmi2Error naming the failed check
(conftest.py's fixtures ``fmu`` and ``slave``)."""
import gc

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy_instance import INPUT_NAMES, P, SCALAR_NAMES, Slave, contact_inputs  # noqa: E402

from wearjoint.core import state_format  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.joint import read_state_bytes, state_bytes  # noqa: E402


def _run(slave, fmu, steps, t0, dt=1e-5, derivatives=False):
    """Steps with a slowly changing input; every output after every step (``derivatives``: the loads' derivatives
    too, as a linearising master reads them)."""
    names = SCALAR_NAMES + (list(fv.JACOBIAN_SLOTS) if derivatives else []) + fmu["wear"]
    rows = []
    for k in range(steps):
        depth, direction = 3e-6 + 1e-7 * k, 1.0 + 0.01 * k
        inputs = contact_inputs(depth=depth, direction=direction)
        e, de, dtheta = P.clearance_m + depth, 1e-7 / dt, 0.01 / dt      # the pin centre's velocity: e' u + e theta' t
        inputs[3] += de * np.cos(direction) - e * dtheta * np.sin(direction)
        inputs[4] += de * np.sin(direction) + e * dtheta * np.cos(direction)
        slave.set_inputs(inputs)
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


def test_a_linearising_hosts_state_restores_into_another_instance(slave, fmu):
    """A host that reads the loads' derivatives (a linearising master) has each step wear with the linearised
    force.  Its state restored into a fresh instance stepped once with the held force instead (the state did not
    say the host linearises): the first forces read were 3 % off."""
    _run(slave, fmu, 10, 0.0, derivatives=True)
    serialised = slave.fmu.serializeFMUstate(slave.fmu.getFMUstate())
    first = _run(slave, fmu, 15, 1e-4, derivatives=True)
    other = Slave(fmu, "restored").initialise()
    try:
        other.fmu.setFMUstate(other.fmu.deSerializeFMUstate(serialised))
        assert np.array_equal(_run(other, fmu, 15, 1e-4, derivatives=True), first)
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


@pytest.mark.parametrize("version", [2, 3])
def test_a_state_carries_the_flags_the_hosts_calls_left(fmus, version):
    """What the next step depends on besides the values: a Model Exchange step completed at these inputs (its
    contact-onset bookkeeping done: an event update there does nothing) and a host that read the loads' derivatives
    (its next step wears with the linearised force).  Restored into a fresh instance, a state serialises to the
    same bytes, the flags included; neither was in the state."""
    from fmpy_instance import JOINT, Joint

    def serialised(joint):
        f = joint.fmu
        return f.serializeFMUstate(f.getFMUstate()) if version == 2 else f.serializeFMUState(f.getFMUState())

    def head(data):
        return read_state_bytes(data, state_format.CONTENTS_FMU, fv.STATE_HEAD_SIZE, JOINT.n_points)[0]

    for kind in ("me", "cs"):
        a, b = Joint(fmus[version], version, kind).start(), Joint(fmus[version], version, kind).start()
        try:
            a.set(INPUT_NAMES, contact_inputs(params=JOINT))
            if kind == "me":
                a.fmu.completedIntegratorStep() if version == 2 else a.fmu.completedIntegratorStep(True)
            else:
                a.get(list(fv.JACOBIAN_SLOTS)[:1])
            data = serialised(a)
            assert list(head(data)[-2:]) == ([0.0, 1.0] if kind == "me" else [1.0, 0.0])
            b.restore(data)
            assert serialised(b) == data
        finally:
            a.free()
            b.free()
