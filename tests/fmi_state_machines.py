"""Hypothesis state machines that drive the native FMU in process through fmpy (run as a child process
by tests/fmu/test_fmi_fuzz.py, so that a crash of the FMU cannot take pytest down).

``python tests/fmi_state_machines.py FMU_DIR MACHINE EXAMPLES STEPS`` runs one machine and prints, as
its last line, a JSON object of counts.  MACHINE: ``calls-<fmi version>-<cs|me>`` (legal and illegal
call orders with odd values, every status checked against the FMI state tables, every output read
with an OK status finite) or ``corrupt-<fmi version>`` (serialised states with flipped bits,
truncations, splices and planted values: refused, or restored exactly).
"""
import json
import math
import sys
from collections import Counter

import numpy as np
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, invariant, precondition, rule, run_state_machine_as_test

from wearjoint.core.layout import ADMISSIBLE_PENETRATION_SHARE
from wearjoint.fmu import variables as fv
from wearjoint.parameters import JointParameters

OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
ODD = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 1e-300, -0.0, 5e-324])
VALUE = st.one_of(st.floats(-0.5, 0.5), ODD)
# finite steps up to 1 s (a step of 1e300 s in contact, refused with Discard: tests/fmu/test_fmi_fuzz.py::
# test_a_huge_step_is_refused)
STEP = st.one_of(st.floats(0.0, 1e-4), st.sampled_from([-1e-5, math.nan, math.inf, -math.inf, 0.0, 1.0]))
COUNTS = Counter()

# The modes of FMI 2.0 (Co-Simulation §4.2.4, Model Exchange §3.2.3) and FMI 3.0 (§3.2) the machines track.
INSTANTIATED, INITIALISATION, STEP_MODE, EVENT, CONTINUOUS, TERMINATED = range(6)
INITIALISED = {STEP_MODE, EVENT, CONTINUOUS, TERMINATED}
CLEARANCE_M = 1e-4
# the fuzz FMU's joint refuses a step whose inputs put the pin deeper into the wall (core.admissibility)
ADMISSIBLE_PENETRATION_M = ADMISSIBLE_PENETRATION_SHARE * JointParameters().pin_radius_m


def wall_overlap(inputs) -> float:
    """How far ``inputs`` put the pin into the unworn bushing wall [m] (the fuzz FMU's offsets are 0: |e| is the
    distance of the bodies' reference points)."""
    return math.hypot(inputs[0] - inputs[6], inputs[1] - inputs[7]) - CLEARANCE_M


def status_of(call, *args):
    """The FMI status of one call through fmpy (which raises for a status above Warning)."""
    try:
        call(*args)
    except FMICallException as exc:
        return exc.status
    return OK


def contact_inputs(depth: float, angle: float) -> list[float]:
    """The pin at rest at the origin, the bushing placed so that the pin overlaps it by ``depth`` [m]."""
    e = CLEARANCE_M + depth
    return [0.0, 0.0, 0.0, 0.1, 0.0, -15.0, -e * math.cos(angle), -e * math.sin(angle), 0.0, 0.0, 0.0, 3.0]


class Instance:
    """One fmpy instance of FMI ``version`` (2, 3) and ``kind`` ('cs', 'me') with uniform calls."""

    def __init__(self, fmu_dir: str, version: int, kind: str):
        from fmpy import fmi2, fmi3
        md = read_model_description(fmu_dir)
        self.version, self.kind = version, kind
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.n_points = sum(1 for v in md.modelVariables if v.name.startswith("wear_depth"))
        if version == 3:
            self.n_points = int(next(v.start for v in md.modelVariables if v.name == "n_points"))
        cls = {(2, "cs"): fmi2.FMU2Slave, (2, "me"): fmi2.FMU2Model,
               (3, "cs"): fmi3.FMU3Slave, (3, "me"): fmi3.FMU3Model}[version, kind]
        identifier = (md.coSimulation if kind == "cs" else md.modelExchange).modelIdentifier
        self.fmu = cls(guid=md.guid, unzipDirectory=fmu_dir, modelIdentifier=identifier, instanceName="fuzz")
        self.fmu.instantiate()
        self.inputs = [self.vr[v.name] for v in fv.INPUTS]
        self.outputs = [self.vr[v.name] for v in fv.SCALAR_OUTPUTS]

    def setup(self):
        return status_of(self.fmu.setupExperiment, None, 0.0) if self.version == 2 else OK

    def set_reals(self, vrs, values):
        f = self.fmu.setReal if self.version == 2 else self.fmu.setFloat64
        return status_of(f, vrs, values)

    def get_reals(self, vrs):
        """(status, values)."""
        try:
            if self.version == 2:
                return OK, self.fmu.getReal(vrs)
            return OK, self.fmu.getFloat64(vrs, nValues=len(vrs))
        except FMICallException as exc:
            return exc.status, None

    def profile(self):
        """(status, wear depths)."""
        if self.version == 2:
            return self.get_reals([self.vr[fv.wear_depth_name(z + 1)] for z in range(self.n_points)])
        try:
            return OK, self.fmu.getFloat64([self.vr["wear_depth"]], nValues=self.n_points)
        except FMICallException as exc:
            return exc.status, None

    def do_step(self, t, h):
        return status_of(self.fmu.doStep, t, h)

    def completed_integrator_step(self):
        if self.version == 2:
            return status_of(self.fmu.completedIntegratorStep)
        return status_of(self.fmu.completedIntegratorStep, True)

    def new_discrete_states(self):
        return status_of(self.fmu.newDiscreteStates if self.version == 2 else self.fmu.updateDiscreteStates)

    def serialise(self, state):
        return (self.fmu.serializeFMUstate if self.version == 2 else self.fmu.serializeFMUState)(state)

    def deserialise(self, data):
        """(status, state)."""
        try:
            return OK, (self.fmu.deSerializeFMUstate if self.version == 2 else self.fmu.deserializeFMUState)(data)
        except FMICallException as exc:
            return exc.status, None

    def get_state(self):
        try:
            return OK, (self.fmu.getFMUstate if self.version == 2 else self.fmu.getFMUState)()
        except FMICallException as exc:
            return exc.status, None

    def set_state(self, state):
        return status_of(self.fmu.setFMUstate if self.version == 2 else self.fmu.setFMUState, state)

    def free_state(self, state):
        return status_of(self.fmu.freeFMUstate if self.version == 2 else self.fmu.freeFMUState, state)


class CallOrder(RuleBasedStateMachine):
    """Legal and illegal call orders with odd values.  Expected: the status the FMI state tables give
    (a call out of its modes is an error), Discard for a step with non-finite inputs or step size, OK for one
    whose pin sits well inside the admissible penetration at moderate speeds (beyond it the step may be refused,
    Discard: docs/reference/model.md §3.14), Error for unknown value references and non-finite outputs, and finite
    outputs behind every OK."""

    FMU_DIR, VERSION, KIND = "", 2, "cs"
    states = Bundle("states")

    def __init__(self):
        super().__init__()
        self.i = Instance(self.FMU_DIR, self.VERSION, self.KIND)
        assert self.i.setup() == OK
        self.mode = INSTANTIATED
        self.time = self.completed = 0.0   # Model Exchange: the time and the end of the last completed step
        self.inputs = [0.0] * len(fv.INPUTS)
        self.held = []   # states taken: (state, mode class, outputs or None)

    def teardown(self):
        for state, *_ in self.held:
            if state is not None:
                self.i.free_state(state)
        self.i.fmu.freeInstance()

    def expect(self, name, status, allowed):
        COUNTS["calls"] += 1
        COUNTS[f"status {status}"] += 1
        assert status in allowed, f"{name} in mode {self.mode}: status {status}, expected one of {allowed}"

    def finite_inputs(self):
        return all(math.isfinite(x) for x in self.inputs)

    @rule()
    def enter_initialisation(self):
        status = status_of(self.i.fmu.enterInitializationMode)
        self.expect("enterInitializationMode", status, {OK} if self.mode == INSTANTIATED else {ERROR})
        if self.mode == INSTANTIATED:
            self.mode = INITIALISATION

    @rule()
    def exit_initialisation(self):
        status = status_of(self.i.fmu.exitInitializationMode)
        self.expect("exitInitializationMode", status, {OK} if self.mode == INITIALISATION else {ERROR})
        if self.mode == INITIALISATION:
            self.mode = STEP_MODE if self.KIND == "cs" else EVENT

    @rule(index=st.integers(0, len(fv.INPUTS) - 1), value=VALUE)
    def set_input(self, index, value):
        status = self.i.set_reals([self.i.inputs[index]], [value])
        settable = self.mode in {INSTANTIATED, INITIALISATION, STEP_MODE, EVENT, CONTINUOUS}
        self.expect("setReal", status, {OK} if settable else {ERROR})
        if status == OK:
            self.inputs[index] = value

    @rule(depth=st.floats(-2e-6, 6e-6), angle=st.floats(0.0, 2 * math.pi))
    def set_contact_inputs(self, depth, angle):
        values = contact_inputs(depth, angle)
        status = self.i.set_reals(self.i.inputs, values)
        if status == OK:
            self.inputs = values

    @rule(vr=st.sampled_from([10 ** 6, 2 ** 32 - 1, -1 % 2 ** 32]), value=VALUE)
    def set_unknown(self, vr, value):
        self.expect("setReal of an unknown value reference", self.i.set_reals([vr], [value]), {ERROR})

    @rule()
    def get_outputs(self):
        status, values = self.i.get_reals(self.i.outputs)
        readable = self.mode != INSTANTIATED
        self.expect("getReal", status, {OK, ERROR} if readable and self.finite_inputs() else {ERROR})
        if status == OK:
            COUNTS["outputs read OK"] += 1
            COUNTS["non-finite outputs behind OK"] += sum(not math.isfinite(v) for v in values)
            assert all(math.isfinite(v) for v in values), values

    @rule()
    def get_profile(self):
        status, values = self.i.profile()
        self.expect("getReal of the profile", status, {OK} if self.mode != INSTANTIATED else {ERROR})
        if status == OK:
            assert all(math.isfinite(v) and v >= 0.0 for v in values)

    @rule(h=STEP)
    def do_step(self, h):
        status = self.i.do_step(self.time, h) if self.KIND == "cs" else ERROR
        if self.KIND != "cs":
            return
        if self.mode != STEP_MODE:
            self.expect("doStep", status, {ERROR})
        elif not (self.finite_inputs() and math.isfinite(h) and h >= 0.0):
            self.expect("doStep", status, {DISCARD})
        else:   # well inside the admissible penetration at moderate speeds: accepted; else it may be refused
            admissible = (wall_overlap(self.inputs) <= 0.5 * ADMISSIBLE_PENETRATION_M
                          and max(map(abs, self.inputs)) <= 100.0)
            self.expect("doStep", status, {OK} if admissible else {OK, DISCARD})
            if status == OK:
                self.time += h

    @precondition(lambda self: self.KIND == "me")
    @rule(dt=STEP)
    def set_time(self, dt):
        t = self.time + dt
        status = status_of(self.i.fmu.setTime, t)
        if self.mode not in {EVENT, CONTINUOUS}:
            self.expect("setTime", status, {ERROR})
        else:
            self.expect("setTime", status, {OK} if math.isfinite(t) else {ERROR})
            if status == OK:
                self.time = t

    @precondition(lambda self: self.KIND == "me")
    @rule()
    def enter_continuous_time_mode(self):
        status = status_of(self.i.fmu.enterContinuousTimeMode)
        self.expect("enterContinuousTimeMode", status, {OK} if self.mode == EVENT else {ERROR})
        if status == OK:
            self.mode = CONTINUOUS

    @precondition(lambda self: self.KIND == "me")
    @rule()
    def enter_event_mode(self):
        status = status_of(self.i.fmu.enterEventMode)
        self.expect("enterEventMode", status, {OK} if self.mode in {EVENT, CONTINUOUS} else {ERROR})
        if status == OK:
            self.mode = EVENT

    @precondition(lambda self: self.KIND == "me")
    @rule()
    def new_discrete_states(self):
        status = self.i.new_discrete_states()
        allowed = ({OK, ERROR} if self.finite_inputs() else {ERROR}) if self.mode == EVENT else {ERROR}
        self.expect("newDiscreteStates", status, allowed)

    @precondition(lambda self: self.KIND == "me")
    @rule()
    def completed_integrator_step(self):
        status = self.i.completed_integrator_step()
        if self.mode != CONTINUOUS:
            self.expect("completedIntegratorStep", status, {ERROR})
        elif not (self.finite_inputs() and self.time >= self.completed):
            self.expect("completedIntegratorStep", status, {DISCARD, ERROR})
        else:   # as doStep; Model Exchange refuses inputs deeper in the wall than any contact with fmi2Error (§3.14)
            admissible = (wall_overlap(self.inputs) <= 0.5 * ADMISSIBLE_PENETRATION_M
                          and max(map(abs, self.inputs)) <= 100.0)
            self.expect("completedIntegratorStep", status, {OK} if admissible else {OK, ERROR})
            if status == OK:
                self.completed = self.time

    @rule(target=states)
    def get_state(self):
        status, state = self.i.get_state()
        self.expect("getFMUstate", status, {OK})
        outputs = None
        if self.mode != INSTANTIATED and self.finite_inputs():
            read, values = self.i.get_reals(self.i.outputs)
            outputs = values if read == OK else None
        self.held.append((state, self.mode in INITIALISED, outputs, list(self.inputs), self.time))
        return len(self.held) - 1

    @rule(slot=states)
    def set_state(self, slot):
        state, initialised, outputs, inputs, time = self.held[slot]
        status = self.i.set_state(state)
        if state is None:
            self.expect("setFMUstate of a freed state", status, {ERROR})
            return
        self.expect("setFMUstate", status, {OK})
        if initialised and self.mode not in {STEP_MODE, EVENT, CONTINUOUS}:
            self.mode = STEP_MODE if self.KIND == "cs" else EVENT
        elif not initialised and self.mode in INITIALISED:
            self.mode = INITIALISATION
        self.inputs, self.time = list(inputs), time
        self.completed = time
        if outputs is not None and self.mode != INSTANTIATED:
            read, values = self.i.get_reals(self.i.outputs)
            assert read == OK and values == outputs, f"a restored state gives other outputs: {values} {outputs}"
            COUNTS["states restored exactly"] += 1

    @rule(slot=states)
    def serialise_round_trip(self, slot):
        state = self.held[slot][0]
        if state is None:
            return
        data = self.i.serialise(state)
        status, copy = self.i.deserialise(data)
        self.expect("deSerializeFMUstate of serialised bytes", status, {OK})
        assert self.i.serialise(copy) == data
        self.i.free_state(copy)

    @rule(slot=states)
    def free_state(self, slot):
        state = self.held[slot][0]
        if state is not None:
            self.expect("freeFMUstate", self.i.free_state(state), {OK})
            self.held[slot] = (None, *self.held[slot][1:])

    @rule()
    def terminate(self):
        status = status_of(self.i.fmu.terminate)
        legal = {STEP_MODE} if self.KIND == "cs" else {EVENT, CONTINUOUS}
        self.expect("terminate", status, {OK} if self.mode in legal else {OK, ERROR})
        if status == OK:
            self.mode = TERMINATED

    @rule()
    def reset(self):
        self.expect("reset", status_of(self.i.fmu.reset), {OK})
        self.mode, self.time, self.completed, self.inputs = INSTANTIATED, 0.0, 0.0, [0.0] * len(fv.INPUTS)
        assert self.i.setup() == OK

    @invariant()
    def counted(self):
        COUNTS["steps"] += 1


class Corruption(RuleBasedStateMachine):
    """Serialised states of a wearing FMU, corrupted: flipped bits, truncated, extended, two states
    spliced, non-finite or huge values planted.  Each must be refused at deserialisation, or be a
    state that serialises back to exactly its bytes and gives finite outputs."""

    FMU_DIR, VERSION = "", 2
    serialised = Bundle("serialised")

    def __init__(self):
        super().__init__()
        self.i = Instance(self.FMU_DIR, self.VERSION, "cs")
        self.i.setup()
        # wear visible within a few steps (tens of um per 10 us step in contact): a larger factor wears
        # millimetres per step, and a step that would wear past the bushing radius is refused (Discard)
        self.i.set_reals([self.i.vr["wear_factor"]], [100.0])
        self.i.fmu.enterInitializationMode()
        self.i.fmu.exitInitializationMode()
        self.time = 0.0
        self.times = {}      # a serialised state's bytes -> its time (a step after setting it starts there)

    def teardown(self):
        self.i.fmu.freeInstance()

    @rule(depth=st.floats(0.0, 6e-6), angle=st.floats(0.0, 2 * math.pi), steps=st.integers(1, 5))
    def wear(self, depth, angle, steps):
        self.i.set_reals(self.i.inputs, contact_inputs(depth, angle))
        for _ in range(steps):      # Discard: the step would wear past the bushing radius (refused, unchanged)
            status = self.i.do_step(self.time, 1e-5)
            assert status in (OK, DISCARD), status
            if status == OK:
                self.time += 1e-5

    @rule(target=serialised)
    def serialise(self):
        status, state = self.i.get_state()
        data = self.i.serialise(state)
        self.i.free_state(state)
        self.times[bytes(data)] = self.time
        return data

    def attempt(self, kind, original, data, other=None):
        COUNTS[f"tried {kind}"] += 1
        status, state = self.i.deserialise(bytes(data))
        if status != OK:
            assert status == ERROR
            COUNTS[f"refused {kind}"] += 1
            return
        same = bytes(data) in (original, other)   # a splice at an end gives one of the two intact states
        COUNTS[f"accepted {kind}" + (" (unchanged bytes)" if same else "")] += 1
        assert self.i.serialise(state) == bytes(data), "an accepted state does not serialise to its bytes"
        assert self.i.set_state(state) == OK
        self.time = self.times.get(bytes(data), self.time)
        read, values = self.i.get_reals(self.i.outputs)
        COUNTS["non-finite outputs behind OK"] += read == OK and not all(math.isfinite(v) for v in values)
        assert read != OK or all(math.isfinite(v) for v in values)
        self.i.free_state(state)
        assert same, f"{kind}: a corrupted state was accepted"

    @rule(data=serialised, bits=st.lists(st.integers(0, 2 ** 40), min_size=1, max_size=8))
    def flip_bits(self, data, bits):
        mutated = bytearray(data)
        for b in bits:
            mutated[(b // 8) % len(data)] ^= 1 << (b % 8)
        self.attempt("flipped bits", data, mutated)

    @rule(data=serialised, position=st.integers(0, 2 ** 30), value=ODD)
    def plant_value(self, data, position, value):
        mutated = bytearray(data)
        at = position % max(len(data) - 8, 1)
        mutated[at:at + 8] = np.float64(value).tobytes()
        self.attempt("planted value", data, mutated)

    @rule(data=serialised, keep=st.integers(0, 2 ** 30), extra=st.binary(max_size=16))
    def truncate_or_extend(self, data, keep, extra):
        self.attempt("truncated or extended", data, data[:keep % len(data)] + extra)

    @rule(first=serialised, second=serialised, at=st.integers(0, 2 ** 30))
    def splice(self, first, second, at):
        cut = at % len(first)
        self.attempt("spliced", first, first[:cut] + second[cut:], second)


def run(fmu_dir: str, machine: str, examples: int, steps: int, derandomize: bool = False) -> None:
    name, version = machine.split("-")[:2]
    if name == "calls":
        cls = type("Calls", (CallOrder,), {"FMU_DIR": fmu_dir, "VERSION": int(version), "KIND": machine.split("-")[2]})
    else:
        cls = type("Corrupt", (Corruption,), {"FMU_DIR": fmu_dir, "VERSION": int(version)})
    run_state_machine_as_test(cls, settings=settings(max_examples=examples, stateful_step_count=steps, deadline=None,
                                                     database=None, derandomize=derandomize,
                                                     suppress_health_check=list(HealthCheck)))


if __name__ == "__main__":
    run(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5:] == ["derandomize"])
    print(json.dumps(dict(COUNTS)))
