"""C entry points of the slider-crank's kernels for the native ``SliderCrank`` FMU.

The numba ``cfunc``s the AOT build compiles for the mechanism FMU (:mod:`wearjoint.fmu.aot`,
model ``slider-crank``): the very kernels the monolithic engine and the co-simulation master run
(:mod:`wearjoint.core.slider_crank`, Eqs. 38-44 with Baumgarte stabilisation, the crank-rod joint
open: ``MODE_EXTERNAL``, or ``MODE_LINEARISED``), on arrays the C model owns and passes as raw pointers.  Nothing
here allocates.  ``y`` = [q, q_dot] (18 values: crank, rod, slider, each x, y, angle), ``inputs`` (layout.
MECHANISM_INPUT_*) = the joint's (Fx, Fy, T) on its pin body then on its bushing body (global frame, torques about
the centres of mass), the master's load on the slider [N] (positive towards the crank's pivot), then the
linearisation a joint FMU publishes.  The workspace of :func:`wearjoint.kernel_calls.mechanism_arrays` comes
as seven arrays:
``jac`` and ``schur`` (9 x 9), ``phi``, ``phi_dot``, ``gamma``, ``minv`` (M^-1), ``force`` (9 each).
The FMU state is written, checked and read by the state format's entry points
(:mod:`wearjoint.fmu.state_entry_points`), as the joint FMU's.
"""
from numba import carray, types

from ..core.integrators import rk4_open_joint
from ..core.jit import kernel
from ..core.layout import (
    ALL_KINEMATIC_COLUMNS, MECHANISM_INPUT_DERIVATIVES, MECHANISM_INPUT_EVALUATED, MECHANISM_INPUT_NORMAL_FORCE,
    MECHANISM_INPUT_SLIDER_FORCE, MODE_EXTERNAL, MODE_LINEARISED, MP_SLIDER_FORCE_INPUT, N_COORDINATES,
    N_KINEMATIC_INPUTS, N_LINEARISATION, N_MECHANISM_FIELDS, N_MECHANISM_INPUTS, N_MECHANISM_PARAMETERS,
)
from ..core.linearisation import linearisation_from_published
from ..core.joint_location import joint_kinematics
from ..core.slider_crank import derivative, initial_state, inverse_mass_diagonal, no_joint
from ..core.slider_load import load_table_problem, mechanism_parameter_vector
from ..mechanism_parameters import FIELD_SCALES
from .aot import entry_point
from .state_entry_points import (  # noqa: F401  (the FMU state's entry points, aot.ENTRY_POINTS)
    check_header_native, check_values_native, read_state_native, state_size_native, write_state_native,
)

_F64 = types.CPointer(types.float64)
_N = N_COORDINATES
_WORKSPACE = (_F64,) * 7


@kernel(inline='always')
def workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force):
    return (carray(jac, (_N, _N)), carray(schur, (_N, _N)), carray(phi, _N), carray(phi_dot, _N), carray(gamma, _N),
            carray(minv, _N), carray(force, _N))


@entry_point(types.int32(_F64, _F64, _F64))
def parameters_native(fields, mp, minv):
    """The kernels' parameter vector (layout.MP_*) from the FMU's mechanism parameters (rpm, degrees;
    wearjoint.mechanism_parameters.MECHANISM_FIELDS) and M^-1 (Eq. 42); returns 0, or what is wrong with the
    slider-load table (core.slider_load.load_table_problem: nothing packed)."""
    f = carray(fields, N_MECHANISM_FIELDS)
    problem = load_table_problem(f)
    if problem != 0:
        return problem
    p = carray(mp, N_MECHANISM_PARAMETERS)
    mechanism_parameter_vector(f, FIELD_SCALES, p)
    inverse_mass_diagonal(p, carray(minv, _N))
    return 0


@entry_point(types.int32(types.float64, _F64, *_WORKSPACE, _F64))
def initial_state_native(t, mp, jac, schur, phi, phi_dot, gamma, minv, force, y):
    """The ideal mechanism's consistent state at time t [s] into y (crank at th0 - omega t); returns 0."""
    initial_state(t, carray(mp, N_MECHANISM_PARAMETERS), workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force),
                  carray(y, 2 * _N))
    return 0


@entry_point(types.int32(types.float64, _F64, _F64, _F64, *_WORKSPACE, _F64))
def derivative_native(t, y, mp, inputs, jac, schur, phi, phi_dot, gamma, minv, force, dy):
    """dy = dy/dt of y = [q, q_dot] under the ``inputs`` (Eq. 44); returns 0."""
    p = carray(mp, N_MECHANISM_PARAMETERS)
    u = carray(inputs, N_MECHANISM_INPUTS)
    p[MP_SLIDER_FORCE_INPUT] = u[MECHANISM_INPUT_SLIDER_FORCE]
    derivative(t, carray(y, 2 * _N), MODE_EXTERNAL, p, no_joint(p), u[:6],
               workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force), carray(dy, 2 * _N))
    return 0


@entry_point(types.int32(types.float64, types.float64, types.int64, types.int64, _F64, _F64, _F64, *_WORKSPACE, _F64,
                         _F64, _F64, _F64))
def step_native(t, h, n_steps, linearised, y, mp, inputs, jac, schur, phi, phi_dot, gamma, minv, force, dy, stages,
                linearisation, loads):
    """y advanced over [t, t + h] in n_steps RK4 steps, dy = f at the end; the joint's loads held at the inputs
    or, if ``linearised``, F0 + J (u - u0) of the linearisation the inputs carry (core.linearisation;
    ``linearisation``: layout.N_LINEARISATION scratch, ``loads``: 6); ``stages``: 4 x 18 scratch.  Returns 0."""
    p = carray(mp, N_MECHANISM_PARAMETERS)
    u = carray(inputs, N_MECHANISM_INPUTS)
    p[MP_SLIDER_FORCE_INPUT] = u[MECHANISM_INPUT_SLIDER_FORCE]
    ws = workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force)
    if linearised:
        lin = carray(linearisation, N_LINEARISATION)
        linearisation_from_published(u[:6], u[MECHANISM_INPUT_NORMAL_FORCE],
                                     u[MECHANISM_INPUT_DERIVATIVES:MECHANISM_INPUT_EVALUATED], ALL_KINEMATIC_COLUMNS,
                                     u[MECHANISM_INPUT_EVALUATED:], lin)
        rk4_open_joint(t, h, n_steps, carray(y, 2 * _N), MODE_LINEARISED, p, lin, carray(loads, 6), ws,
                       carray(dy, 2 * _N), carray(stages, (4, 2 * _N)))
    else:
        rk4_open_joint(t, h, n_steps, carray(y, 2 * _N), MODE_EXTERNAL, p, no_joint(p), u[:6], ws,
                       carray(dy, 2 * _N), carray(stages, (4, 2 * _N)))
    return 0


@entry_point(types.int32(_F64, _F64, _F64))
def joint_kinematics_native(y, mp, out):
    """out = the clearance joint's kinematic inputs (layout.N_KINEMATIC_INPUTS: the pin body's x, y, angle, vx,
    vy, omega, then the bushing body's; the ground's zero) from y (core.joint_location); returns 0."""
    joint_kinematics(carray(y, 2 * _N), carray(mp, N_MECHANISM_PARAMETERS), carray(out, N_KINEMATIC_INPUTS))
    return 0
