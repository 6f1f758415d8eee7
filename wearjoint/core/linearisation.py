"""The joint's loads linearised in its kinematics over a step (MODE_LINEARISED): a co-simulation master integrates
F0 + J (u - u0) through its step, F0 and J the joint FMU's loads and their directional derivatives at the step's
start, u the joint's kinematic inputs (layout.N_KINEMATIC_INPUTS) at each stage.  Where the linear normal force
reaches 0 within the step, the contact has ended: no loads."""
from numba import types
from numba.extending import overload

from .jit import kernel
from .joint_location import joint_kinematics
from .layout import (
    LIN_INPUTS, LIN_JACOBIAN, LIN_LOADS, LIN_SCRATCH, N_KINEMATIC_INPUTS, N_LINEARISED_LOADS,
    PUBLISHED_LINEARISED_LOADS, TRANSLATION_PAIRS,
)


@kernel
def linearisation_from_published(loads, normal_force, derivatives, columns, evaluated_inputs, linearisation):
    """``linearisation`` (layout.LIN_*) from what a joint FMU publishes: its six ``loads`` (the pin body's force x,
    y, torque, the bushing body's) and ``normal_force`` at the inputs ``evaluated_inputs`` (u0), ``derivatives`` the
    rows PUBLISHED_LINEARISED_LOADS of J, row-major, each the columns ``columns`` (kinematic inputs, in order): all 12
    (layout.ALL_KINEMATIC_COLUMNS) or layout.RELATIVE_COLUMNS, the others minus their TRANSLATION_PAIRS partner's; the
    bushing body's force rows are minus the pin body's (Eq. 22)."""
    for m in range(N_KINEMATIC_INPUTS):
        linearisation[LIN_INPUTS + m] = evaluated_inputs[m]
    for r in range(6):
        linearisation[LIN_LOADS + r] = loads[r]
    linearisation[LIN_LOADS + 6] = normal_force
    n_columns = len(columns)
    for k in range(len(PUBLISHED_LINEARISED_LOADS)):
        row = LIN_JACOBIAN + N_KINEMATIC_INPUTS * PUBLISHED_LINEARISED_LOADS[k]
        for c in range(n_columns):
            linearisation[row + columns[c]] = derivatives[n_columns * k + c]
        if n_columns < N_KINEMATIC_INPUTS:
            for pair in TRANSLATION_PAIRS:
                linearisation[row + pair[0]] = -linearisation[row + pair[1]]
    for r in range(2):
        row = LIN_JACOBIAN + N_KINEMATIC_INPUTS * r
        for m in range(N_KINEMATIC_INPUTS):
            linearisation[row + 3 * N_KINEMATIC_INPUTS + m] = -linearisation[row + m]


def linearised_loads(joint, y, mp, body_forces):
    """body_forces[0:6] = F0 + J (u(y) - u0) of the linearisation ``joint`` (an array, layout.LIN_*), 0 where the
    linearised normal force (its seventh row) is not positive; nothing for a joint of another engine (the
    mechanism's right-hand side takes one argument for every mode's joint)."""


@overload(linearised_loads)
def _overload_linearised_loads(joint, y, mp, body_forces):
    if isinstance(joint, types.Array):
        def linearised(joint, y, mp, body_forces):
            _loads(joint, y, mp, body_forces)
        return linearised

    def other(joint, y, mp, body_forces):
        return None
    return other


@kernel(inline='always')
def _loads(linearisation, y, mp, body_forces):
    du = linearisation[LIN_SCRATCH:LIN_SCRATCH + N_KINEMATIC_INPUTS]
    joint_kinematics(y, mp, du)
    for m in range(N_KINEMATIC_INPUTS):
        du[m] -= linearisation[LIN_INPUTS + m]
    normal = _row(linearisation, N_LINEARISED_LOADS - 1, du)
    for r in range(6):
        body_forces[r] = _row(linearisation, r, du) if normal > 0.0 else 0.0


@kernel(inline='always')
def _row(linearisation, r, du):
    """F0[r] + J[r] . du."""
    value = linearisation[LIN_LOADS + r]
    at = LIN_JACOBIAN + N_KINEMATIC_INPUTS * r
    for m in range(N_KINEMATIC_INPUTS):
        value += linearisation[at + m] * du[m]
    return value
