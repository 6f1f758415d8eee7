"""The co-simulation master's loop and the kernels a run calls once as C entry points, compiled ahead of time.

:func:`master_loop_native` is :func:`wearjoint.cosim.master_loop.master_loop` on raw pointers (and
:func:`start_point_native` its :func:`~wearjoint.cosim.master_loop.start_point`; the others the mechanism's
parameter vector and start (the SliderCrank FMU's), its ideal joint's reaction, the bushing's points (the joint
FMU's) and the materials' stiffness: :mod:`wearjoint.kernel_calls` calls them): the AOT build
(:mod:`wearjoint.fmu.aot`, model ``master``) compiles it from the same numba kernels into a shared library
(:mod:`wearjoint.cosim.native_master`), which the master then calls through ctypes instead of numba's dispatcher,
so that a co-simulation needs no numba compilation of its loop.  The arguments are those of ``master_loop``, each
array as its address (and its length where it varies), the FMU's functions and libc's clock as addresses; the
workspace of :func:`wearjoint.kernel_calls.mechanism_arrays` as its seven arrays.
"""
from numba import carray, types

from ..core import layout as L
from ..core.slider_crank import ideal_joint_forces
from ..core.wear import effective_modulus, materials_contact_stiffness
from ..fmu.aot import entry_point
from ..fmu.instance import N_INPUTS
from ..fmu.joint_entry_points import bushing_points_native  # noqa: F401  (the joint FMU's: aot.ENTRY_POINTS)
from ..fmu.slider_crank_entry_points import (  # noqa: F401  (the mechanism's vectors and start: aot.ENTRY_POINTS)
    initial_state_native, parameters_native, workspace_arrays,
)
from .master_layout import B_ROLLBACK_END, N_OUTPUTS, N_REGISTER, N_SETTINGS
from .master_loop import master_loop, start_point

_F64 = types.CPointer(types.float64)
_U32 = types.CPointer(types.uint32)
_ADDRESS = types.intp
SIGNATURE = types.intp(
    types.float64, _F64, _F64, _F64, types.intp, _F64, types.intp, _F64,   # t_end, register, settings, buf, stats, stages
    _F64, _F64, types.intp,                                                 # saved, samples
    *(_F64,) * 7,                                                           # the workspace
    _ADDRESS, _U32, _U32, types.CPointer(types.uintp), *(_ADDRESS,) * 6,    # fmi (master_loop)
    _U32, types.intp, _F64,                                                 # published
    _ADDRESS, types.CPointer(types.int64))                                  # clock, timespec


@entry_point(SIGNATURE)
def master_loop_native(t_end, register, settings, buf, n_buf, stats, n_revolutions, stages, saved, samples, n_samples,
                       jac, schur, phi, phi_dot, gamma, minv, force,
                       component, input_vrs, output_vrs, state_slot, do_step, set_real, get_real, get_state, set_state,
                       free_state, derivative_vrs, n_derivatives, derivatives, clock, timespec):
    """:func:`~wearjoint.cosim.master_loop.master_loop` (same result) on the arrays at these addresses."""
    fmi = (component, carray(input_vrs, N_INPUTS), carray(output_vrs, N_OUTPUTS), carray(state_slot, 1),
           do_step, set_real, get_real, get_state, set_state, free_state)
    return master_loop(t_end, carray(register, N_REGISTER), carray(settings, N_SETTINGS), carray(buf, n_buf),
                       carray(stats, (n_revolutions, L.N_STATS)), carray(stages, (4, 2 * L.N_COORDINATES)),
                       carray(saved, B_ROLLBACK_END), carray(samples, (n_samples, L.N_SAMPLE_COLUMNS)),
                       workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force), fmi,
                       (carray(derivative_vrs, n_derivatives), carray(derivatives, n_derivatives)), clock,
                       carray(timespec, 2))


@entry_point(types.int32(_F64, types.intp))
def start_point_native(buf, n_buf):
    """:func:`~wearjoint.cosim.master_loop.start_point` on the master's buffer; returns 0."""
    start_point(carray(buf, n_buf))
    return 0


@entry_point(types.int32(_F64, types.intp, _F64, *(_F64,) * 7, _F64, _F64, _F64, _F64, _F64))
def ideal_joint_forces_native(times, n_times, mp, jac, schur, phi, phi_dot, gamma, minv, force, result, y, qdd,
                              body_forces, out):
    """:func:`~wearjoint.core.slider_crank.ideal_joint_forces` at n_times times; returns 0."""
    ideal_joint_forces(carray(times, n_times), carray(mp, L.N_MECHANISM_PARAMETERS),
                       workspace_arrays(jac, schur, phi, phi_dot, gamma, minv, force), carray(result, L.N_RESULT),
                       carray(y, 2 * L.N_COORDINATES), carray(qdd, L.N_COORDINATES), carray(body_forces, 6),
                       carray(out, n_times))
    return 0


@entry_point(types.float64(types.float64, types.float64, types.float64, types.float64))
def effective_modulus_native(pin_youngs_modulus, pin_poisson_ratio, bushing_youngs_modulus, bushing_poisson_ratio):
    """:func:`~wearjoint.core.wear.effective_modulus` [Pa] (Eq. 32)."""
    return effective_modulus(pin_youngs_modulus, pin_poisson_ratio, bushing_youngs_modulus, bushing_poisson_ratio)


@entry_point(types.float64(types.float64, types.float64, types.float64))
def materials_contact_stiffness_native(pin_radius, bushing_radius, modulus):
    """:func:`~wearjoint.core.wear.materials_contact_stiffness` [N/m^1.5] (Eqs. 16-17)."""
    return materials_contact_stiffness(pin_radius, bushing_radius, modulus)
