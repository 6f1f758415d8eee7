"""The joint FMU's published linearisation (docs/reference/fmu.md §5, "The published linearisation"): the outputs
d_<load>_d_<input> are the derivatives of its loads with respect to its inputs, the outputs evaluated_<input> the inputs they belong to, in
FMI 2.0 and 3.0, at unworn, worn and gap states; against central differences of the loads (independent of the
kernels' derivatives) and against the FMI directional derivatives of the same loads."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("fmpy")
from test_directional_derivatives import (  # noqa: E402
    INPUT_NAMES, STATES, TOLERANCE, ContactState, central_differences, normalised_error, started,
)

from wearjoint import paper_joint  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402

ROWS = list(fv.LINEARISED_ROWS)
DERIVATIVES = [fv.derivative_name(row, name) for row in ROWS for name in INPUT_NAMES]
EVALUATED = [fv.evaluated_input_name(name) for name in INPUT_NAMES]


@pytest.mark.parametrize("state", STATES, ids=[s.name for s in STATES])
@pytest.mark.parametrize("version", (2, 3))
def test_published_derivatives_are_the_loads_derivatives(fmus, version, state):
    joint = started(fmus, version, "cs", state)
    try:
        x = state.inputs()
        joint.set(INPUT_NAMES, x)
        published = joint.get(DERIVATIVES).reshape(len(ROWS), 12)
        differences = central_differences(joint, x, ROWS)
        assert normalised_error(published, differences) <= TOLERANCE
        directional = np.array([joint.derivative(ROWS, INPUT_NAMES, seed) for seed in np.eye(12)]).T
        np.testing.assert_array_equal(published, directional)
        assert np.array_equal(joint.get(EVALUATED), x)
        assert np.any(published != 0.0) == (state.overlap > 0.0)
        # the loads read after the derivatives are those read alone (one evaluation gives both)
        loads = joint.get(ROWS)
        joint.set(INPUT_NAMES, x)
        np.testing.assert_array_equal(joint.get(ROWS), loads)
        assert not joint.errors()
    finally:
        joint.free()


@pytest.mark.parametrize("version", (2, 3))
def test_a_step_whose_master_read_the_derivatives_wears_with_the_linear_forces_mean(fmus, version):
    """docs/reference/model.md §3.11: the same Co-Simulation step from the same contact (approaching at 0.05 m/s,
    its force rising ~25 % over 10 us; every step's wear at once), once after its published derivatives were read
    (a linearising master) and once not: the worn volumes stand as that linear normal force's mean over the step,
    F + h/2 dF_N/dq . dq/dt (the derivatives read, the inputs' velocities), to the force F the held step takes."""
    state = ContactState("unworn-approaching", 1.0, 3e-6, 0.05, 0.2, params=paper_joint(wear_interval_s=0.0))
    step, x = 1e-5, np.array(state.inputs())
    normal = [fv.derivative_name("normal_force", name) for name in INPUT_NAMES]
    volumes, rates = [], []
    for read in (False, True):
        joint = started(fmus, version, "cs", state)
        try:
            joint.set(INPUT_NAMES, x)
            force, before = joint.get(["normal_force", "worn_volume"])
            if read:
                d = joint.get(normal)            # d/d(x, y, angle, vx, vy, omega), pin then bushing
                rates.append(d[[0, 1, 2, 6, 7, 8]] @ x[[3, 4, 5, 9, 10, 11]])
            joint.do_step(0.0, step)
            volumes.append(joint.get(["worn_volume"])[0] - before)
            assert not joint.errors()
        finally:
            joint.free()
    assert rates[0] * step > 0.1 * force
    assert volumes[1] / volumes[0] == pytest.approx(1.0 + 0.5 * step * rates[0] / force, rel=1e-5)


@pytest.fixture(scope="module")
def pythonfmu_fmus(built_fmu, tmp_path_factory):
    """The pythonfmu backend's FMI 2.0 FMU as tests/conftest.py's ``fmus`` gives the native ones."""
    from fmpy import extract, read_model_description

    md = read_model_description(str(built_fmu))
    return {2: {"path": built_fmu, "md": md, "vr": fv.value_references(md),
                "dir": extract(str(built_fmu), unzipdir=str(tmp_path_factory.mktemp("linearised_py_x")))}}


@pytest.mark.parametrize("backend, version", [("native", 2), ("native", 3), ("pythonfmu", 2)])
def test_a_step_whose_master_read_the_derivatives_one_step_late_wears_as_one_on_time(request, backend, version):
    """A master that reads the loads and their derivatives before it sets the step's inputs (libcosim and fmpy's
    SSP master: its mechanism integrates the linearisation of the point before) gets the same wear as one that reads
    them at those inputs, bit for bit: the FMU evaluates the loads and derivatives there itself; a master that read
    no derivatives, the held force's (docs/reference/model.md §3.11)."""
    fmus = request.getfixturevalue("fmus" if backend == "native" else "pythonfmu_fmus")
    state = ContactState("unworn-approaching", 1.0, 3e-6, 0.05, 0.2, params=paper_joint(wear_interval_s=0.0))
    step, x = 1e-5, np.array(state.inputs())
    before = x.copy()
    before[:2] -= 5e-7 * x[3:5] / np.hypot(x[3], x[4])          # the point before: 0.5 um back along the approach
    normal = [fv.derivative_name("normal_force", name) for name in INPUT_NAMES]
    volumes = {}
    for order in ("on time", "one step late", "held one step late"):
        joint = started(fmus, version, "cs", state)
        try:
            joint.set(INPUT_NAMES, x if order == "on time" else before)
            joint.get(["normal_force"])
            if order != "held one step late":
                joint.get(normal)
            if order != "on time":
                joint.set(INPUT_NAMES, x)
            start = joint.get(["worn_volume"])[0]
            joint.do_step(0.0, step)
            volumes[order] = joint.get(["worn_volume"])[0] - start
            assert not joint.errors()
        finally:
            joint.free()
    assert volumes["one step late"] == volumes["on time"]
    assert volumes["on time"] > 1.1 * volumes["held one step late"] > 0.0


def test_a_derivatives_own_derivative_is_refused_by_name(fmus):
    """fmi2GetDirectionalDerivative of a published derivative is an error naming it (second derivatives are not
    provided); an evaluated input's derivative is its seed for its input."""
    joint = started(fmus, 2, "cs", STATES[0])
    try:
        joint.set(INPUT_NAMES, STATES[0].inputs())
        np.testing.assert_array_equal(joint.derivative(["evaluated_pin_y"], ["pin_x", "pin_y"], [2.0, 5.0]), [5.0])
        with pytest.raises(Exception):
            joint.derivative(["d_pin_force_x_d_pin_x"], ["pin_x"], [1.0])
        assert "d_pin_force_x_d_pin_x" in joint.errors() and "not provided" in joint.errors()
    finally:
        joint.free()


def test_the_model_structure_declares_what_each_published_value_depends_on(fmus):
    """A derivative depends on every input, an evaluated input on its input alone, in both versions."""
    for version in (2, 3):
        declared = {unknown.variable.name: {v.name for v in unknown.dependencies}
                    for unknown in fmus[version]["md"].outputs}
        assert all(declared[name] == set(INPUT_NAMES) for name in DERIVATIVES)
        assert all(declared[fv.evaluated_input_name(name)] == {name} for name in INPUT_NAMES)
