"""The joint FMU's published linearisation (docs/reference/fmu.md §5, "The published linearisation"): the outputs
d_<load>_d_<input> are the derivatives of its loads with respect to its inputs, the outputs evaluated_<input> the inputs they belong to, in
FMI 2.0 and 3.0, at unworn, worn and gap states; against central differences of the loads (independent of the
kernels' derivatives) and against the FMI directional derivatives of the same loads."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("fmpy")
from test_directional_derivatives import (  # noqa: E402
    INPUT_NAMES, STATES, TOLERANCE, central_differences, normalised_error, started,
)

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
