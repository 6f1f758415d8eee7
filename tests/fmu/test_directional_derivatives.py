"""FMI directional derivatives of the native joint FMU (docs/reference/fmu.md §5): fmi2- and
fmi3GetDirectionalDerivative against central differences of the outputs (set the inputs +-h, read
them), FMI 2.0 and 3.0, Co-Simulation and Model Exchange, at unworn and worn contact states (the
wear profile and contact memory set through an FMU state); the ModelStructure's dependencies
against the same differences; errors.  The cross-built binaries: tests/fmu/test_platforms.py.
"""
from __future__ import annotations

import math
import zipfile
from dataclasses import dataclass
from xml.etree import ElementTree as ET

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import (  # noqa: E402
    FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE,
)
from fmpy.validation import validate_fmu  # noqa: E402
from fmpy_instance import Joint  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.core.layout import N_MEMORY  # noqa: E402
from wearjoint.core.state_format import CONTENTS_FMU  # noqa: E402
from wearjoint.fmu import slider_crank as sc  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.build import build_fmu  # noqa: E402
from wearjoint.joint import state_bytes  # noqa: E402

JOINT = paper_joint()
INPUT_NAMES = [v.name for v in fv.INPUTS]
OUTPUT_NAMES = [v.name for v in fv.SCALAR_OUTPUTS]
# per input (x, y [m], angle [rad], vx, vy [m/s], omega [rad/s]; pin, then bushing): the central
# differences' step, and a typical change (the clearance; it at a 0.1 m lever; friction's v1; it at 0.1 m)
STEP = np.tile([1e-9, 1e-9, 1e-8, 1e-6, 1e-6, 1e-5], 2)
SCALE = np.tile([1e-4, 1e-4, 1e-3, 1e-2, 1e-2, 1e-1], 2)
TOLERANCE = 1e-5     # of the output's change over a typical change of the inputs
KINDS = [(2, "cs"), (2, "me"), (3, "cs"), (3, "me")]


# ------------------------------------------------------------- contact states
GROOVE = (20e-6, 4.0, 0.3)   # a worn groove: depth [m], bushing-frame angle and Gaussian width [rad]


def groove_depth(phi):
    """The groove's wear depth at the bushing-frame angles ``phi``."""
    depth, centre, width = GROOVE
    return depth * np.exp(-(np.angle(np.exp(1j * (np.asarray(phi) - centre))) / width) ** 2)


@dataclass(frozen=True)
class ContactState:
    """The pin ``overlap`` [m] into the (worn) bushing along the bushing-frame angle ``direction``, the
    contact point moving at ``v_normal`` (> 0 approaching) and ``v_tangential`` [m/s] relative to the
    bushing; both bodies spinning; ``memory`` = (contact active, stored onset velocity [m/s], start force [N])."""

    name: str
    direction: float
    overlap: float
    v_normal: float
    v_tangential: float
    worn: bool = False
    memory: tuple = (0.0, 0.0, -1.0)
    params: object = JOINT

    def wear(self) -> np.ndarray:
        n = self.params.n_points
        return groove_depth(np.arange(1, n + 1) * 2.0 * math.pi / n) if self.worn else np.zeros(n)

    def inputs(self) -> list[float]:
        p = self.params
        bushing_angle, pin_angle, pin_omega, bushing_omega = 0.3, 0.7, 12.0, -3.0
        bushing_ref = np.array([0.2, 0.05])
        centre = bushing_ref + _rotate(bushing_angle, p.bushing_offset_m)
        worn = float(groove_depth(self.direction)) if self.worn else 0.0
        u = np.array([math.cos(bushing_angle + self.direction), math.sin(bushing_angle + self.direction)])
        pin_centre = centre + (p.clearance_m + worn + self.overlap) * u
        pin_ref = pin_centre - _rotate(pin_angle, p.pin_offset_m)
        contact = pin_centre + p.pin_radius_m * u
        relative = self.v_normal * u + self.v_tangential * np.array([-u[1], u[0]])
        pin_v = relative - _cross(pin_omega, contact - pin_ref)          # the pin's material point at contact
        bushing_v = -_cross(bushing_omega, contact - bushing_ref)        # the bushing's: at rest there
        return [*pin_ref, pin_angle, *pin_v, pin_omega, *bushing_ref, bushing_angle, *bushing_v, bushing_omega]

    def fmu_state(self) -> bytes:
        """The FMU state (contents "FMU instance") of an initialised instance with these parameters, inputs,
        contact memory (the wear batch empty) and wear profile, of a host that has read no derivatives."""
        head = [0.0, 1.0, *self.inputs(), *fv.fmi_parameter_values(self.params).values(), 0.0, 0.0]
        memory = [*self.memory, *[0.0] * (N_MEMORY - len(self.memory))]
        return state_bytes(CONTENTS_FMU, head, memory, self.wear())


def _rotate(angle, vector) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])


def _cross(omega, lever) -> np.ndarray:
    return np.array([-omega * lever[1], omega * lever[0]])


ONSET = (1.0, 0.05, 0.0)   # a contact that began at 0.05 m/s: the damping depends on the velocities
STATES = (
    ContactState("unworn-approaching", 1.0, 3e-6, 0.05, 0.2),
    ContactState("unworn-friction-ramp", 2.5, 5e-6, -0.01, 0.004, memory=(1.0, 0.08, 0.0)),
    ContactState("worn-groove", 4.05, 3e-6, 0.02, -0.006, worn=True, memory=ONSET),
    ContactState("worn-deepest-exponent-2", 3.9, 4e-6, 0.03, 0.3, worn=True, memory=ONSET,
                 params=paper_joint(contact_model="deepest", contact_exponent=2.0,
                                    contact_stiffness_N_m1_5=7.95e10)),
    ContactState("worn-gap", 1.0, -20e-6, 0.05, 0.1, worn=True),
)


def normalised_error(derivatives: np.ndarray, differences: np.ndarray) -> float:
    """The largest |derivative - difference| (outputs x inputs) times the input's SCALE, over the output's
    scale (its largest change over SCALE of one input); outputs whose differences are all 0 must have
    derivatives exactly 0 (the wear, the contact flag, everything in a gap but the geometry)."""
    scale = np.max(np.abs(differences) * SCALE, axis=1)
    constant = scale == 0.0
    assert np.all(derivatives[constant] == 0.0), np.argwhere(derivatives[constant] != 0.0)
    error = np.abs(derivatives - differences)[~constant] * SCALE / scale[~constant, None]
    return float(error.max(initial=0.0))


def started(fmus, version, kind, state: ContactState) -> Joint:
    joint = Joint(fmus[version], version, kind).start(state.params)
    joint.restore(state.fmu_state())
    return joint


def central_differences(joint: Joint, x, outputs, direction=None, n_values=None) -> np.ndarray:
    """(outputs(x + h) - outputs(x - h)) / 2h along each input (outputs x 12), or along ``direction`` (h = 1)."""
    columns = []
    for step in ([direction] if direction is not None else np.diag(STEP)):
        h = 1.0 if direction is not None else np.max(step)
        joint.set(INPUT_NAMES, np.add(x, step))
        plus = joint.get(outputs, n_values)
        joint.set(INPUT_NAMES, np.subtract(x, step))
        columns.append((plus - joint.get(outputs, n_values)) / (2.0 * h))
    joint.set(INPUT_NAMES, x)
    return np.array(columns).T


# ------------------------------------------------------------- the derivatives are the differences
@pytest.mark.parametrize("state", STATES, ids=[s.name for s in STATES])
@pytest.mark.parametrize("version, kind", KINDS, ids=[f"fmi{v}-{k}" for v, k in KINDS])
def test_directional_derivatives_equal_central_differences(fmus, version, kind, state, record_property):
    joint = started(fmus, version, kind, state)
    try:
        x = state.inputs()
        joint.set(INPUT_NAMES, x)
        # every scalar output and the wear profile (FMI 2.0: a few of its scalars; FMI 3.0: the array)
        wear = [fv.wear_depth_name(z) for z in (1, 400, 1257)] if version == 2 else ["wear_depth"]
        outputs, n_values = OUTPUT_NAMES + wear, None if version == 2 else len(OUTPUT_NAMES) + JOINT.n_points
        derivatives = np.array([joint.derivative(outputs, INPUT_NAMES, seed, n_values) for seed in np.eye(12)]).T
        differences = central_differences(joint, x, outputs, n_values=n_values)
        assert derivatives.shape == differences.shape == (n_values or len(outputs), 12)
        error = normalised_error(derivatives, differences)
        record_property("normalised_error", error)
        assert error <= TOLERANCE, error
        contact = joint.get(["contact"])[0]
        assert contact == (state.overlap > 0.0) and np.any(derivatives[:8] != 0.0) == (state.overlap > 0.0)
        # a combination of some inputs, in another order, against the differences along that direction
        knowns = INPUT_NAMES[::-2]
        seed = np.linspace(-1.0, 2.0, len(knowns)) * SCALE[::-2] * 1e-5
        direction = np.zeros(12)
        direction[[INPUT_NAMES.index(k) for k in knowns]] = seed
        combined = joint.derivative(OUTPUT_NAMES, knowns, seed)
        along = central_differences(joint, x, OUTPUT_NAMES, direction)[:, 0]
        scale = np.maximum(np.abs(along), np.abs(differences[:len(OUTPUT_NAMES)]) @ SCALE * 1e-5)
        assert np.all(np.abs(combined - along) <= TOLERANCE * np.where(scale > 0.0, scale, 1.0)), combined - along
        assert not joint.errors()
    finally:
        joint.free()


def test_model_structure_dependencies_are_the_inputs_each_output_changes_with(fmus):
    """An output's ModelStructure dependencies are exactly the inputs whose central differences are not 0 at
    some contact state (the contact flag: the penetration's, whose sign it is); the wear depends on none."""
    changes = np.zeros((len(OUTPUT_NAMES), 12), bool)
    for state in STATES:
        joint = started(fmus, 2, "cs", state)
        changes |= central_differences(joint, state.inputs(), OUTPUT_NAMES) != 0.0
        joint.free()
    changes[OUTPUT_NAMES.index("contact")] = changes[OUTPUT_NAMES.index("penetration")]
    expected = {name: {INPUT_NAMES[m] for m in np.flatnonzero(row)} for name, row in zip(OUTPUT_NAMES, changes)}
    assert expected["pin_force_x"] == set(INPUT_NAMES) and expected["max_wear_depth"] == set()
    for version in (2, 3):
        declared = {unknown.variable.name: {v.name for v in unknown.dependencies}
                    for unknown in fmus[version]["md"].outputs}
        assert declared.pop("wear_depth" if version == 3 else fv.wear_depth_name(1)) == set()
        assert {name: declared[name] for name in OUTPUT_NAMES} == expected


# ------------------------------------------------------------- what the FMUs declare
def _provides(xml: bytes, version: int) -> list:
    """providesDirectionalDerivative(s) of <CoSimulation> and <ModelExchange> (fmpy 0.3.32 reads FMI 3.0's as the
    FMI 2.0 name, always false)."""
    root = ET.fromstring(xml)
    return [root.find(tag).get("providesDirectionalDerivative" + ("s" if version == 3 else ""))
            for tag in ("CoSimulation", "ModelExchange")]


def test_the_native_joint_fmu_declares_directional_derivatives_and_validates(fmus):
    """... and the SliderCrank FMU none."""
    for version in (2, 3):
        assert _provides(zipfile.ZipFile(fmus[version]["path"]).read("modelDescription.xml"), version) == ["true"] * 2
        assert validate_fmu(str(fmus[version]["path"])) == []
        assert _provides(sc.model_description(version, "{00000000-0000-0000-0000-000000000000}", "test"),
                         version) == ["false"] * 2


# ------------------------------------------------------------- errors
@pytest.mark.parametrize("version", [2, 3])
def test_bad_references_states_and_inputs_give_an_error_naming_them(fmus, version):
    joint = Joint(fmus[version], version, "cs")
    try:
        with pytest.raises(FMICallException) as early:
            joint.derivative(["pin_force_x"], ["pin_x"], [1.0])
        assert early.value.status == 3 and "not allowed in state" in joint.errors()
        joint.start()
        vr = joint.vr
        for unknowns, knowns, named in ((["pin_x"], ["pin_x"], "unknown pin_x"),
                                        (["pin_radius"], ["pin_x"], "unknown pin_radius"),
                                        (["pin_force_x"], ["penetration"], "known penetration"),
                                        (["pin_force_x"], ["restitution"], "known restitution")):
            with pytest.raises(FMICallException) as failure:
                joint.derivative(unknowns, knowns, [1.0])
            assert failure.value.status == 3 and named in joint.errors(), joint.errors()
        args = ([vr["pin_force_x"], 99999], [vr["pin_x"]], [1.0])
        with pytest.raises(FMICallException):
            joint.fmu.getDirectionalDerivative(*args) if version == 2 else \
                joint.fmu.getDirectionalDerivative(*args, nSensitivity=2)
        assert "valueReference 99999" in joint.errors()
        if version == 3:   # nSensitivity counts the array's values
            with pytest.raises(FMICallException):
                joint.derivative(["pin_force_x", "wear_depth"], ["pin_x"], [1.0], n_values=2)
            assert "nSensitivity=2, but the 2 value references stand for 1258 values" in joint.errors()
        joint.set(["pin_y"], [math.nan])
        with pytest.raises(FMICallException):
            joint.derivative(["normal_force"], ["pin_x"], [1.0])
        assert "non-finite inputs (pin_y=nan)" in joint.errors()
        joint.set(["pin_y"], [0.0])
        assert joint.derivative(["normal_force", "max_wear_depth"], ["pin_x"], [1.0]).tolist() == [0.0, 0.0]
        assert all(status == 3 for status, _ in joint.log)
    finally:
        joint.free()


def test_the_slider_crank_fmu_says_it_provides_none(tmp_path):
    path = build_fmu(tmp_path, backend="native", platforms="linux64", model="slider-crank")
    md = read_model_description(str(path))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path), unzipdir=str(tmp_path / "x")),
                    modelIdentifier=sc.MODEL_IDENTIFIER, instanceName="slider_crank")
    messages = []
    logger = fmi2CallbackLoggerTYPE(lambda env, name, status, category, text: messages.append(text.decode()))
    fmu.instantiate(callbacks=fmi2CallbackFunctions(logger=logger, allocateMemory=defaultCallbacks.allocateMemory,
                                                    freeMemory=defaultCallbacks.freeMemory))
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        with pytest.raises(FMICallException) as failure:
            fmu.getDirectionalDerivative([sc.VALUE_REFERENCES["slider_x"]], [0], [1.0])
        assert failure.value.status == 3
        assert messages[-1] == "fmi2GetDirectionalDerivative: providesDirectionalDerivative is false for this FMU"
    finally:
        fmu.freeInstance()
