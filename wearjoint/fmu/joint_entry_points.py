"""C entry points of the joint's hot path, for hosts that call it from native code.

The native FMU (wearjoint/fmu/build_native.py) compiles these numba ``cfunc``s ahead of
time (:mod:`wearjoint.fmu.aot`) and its C model (fmu_src/joint/joint_model.c) calls them:
they run the same kernels as :meth:`wearjoint.ClearanceJoint.evaluate_array` and
``advance_array`` (and the contact's exact derivatives, for FMI directional derivatives) on
the joint's arrays, passed as raw pointers (``kinematics`` = the 12 FMU inputs: pin x, y,
angle, vx, vy, omega, then the bushing's).  Nothing here allocates or touches Python
objects, so a call costs about as much as the kernel.
"""
import numpy as np
from numba import carray, types

from ..core.admissibility import admissible_force, admissible_penetration, is_admissible, wall_overlap
from ..core.contact import contact_jacobian, evaluate_contact, update_contact_memory
from ..core.geometry import block_minimum_depth, bushing_points
from ..core.layout import HELD_LINEARISED, N_JOINT_PARAMETERS, N_MEMORY, N_RESULT
from ..core.wear import (
    accept_contact, accept_linearised_contact, advance_joint, complete_joint_parameters, worn_volume,
)
from .aot import entry_point
from .state_entry_points import (  # noqa: F401  (the joint FMU's state entry points, aot.ENTRY_POINTS)
    check_header_native, check_values_native, read_state_native, state_size_native, write_state_native,
)

_F64 = types.CPointer(types.float64)
# evaluate: (kinematics, joint parameters, cos_phi, sin_phi, wear_depth, block_min, memory, result, mask,
#  n_points, n_blocks); advance/accept: the same with the float64 scratch ``work`` (2 N_d) after ``mask``, and dt
_ARRAYS = (_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, types.voidptr)
_SIZES = (types.int64, types.int64)
EVALUATE_SIGNATURE = types.int32(*_ARRAYS, *_SIZES)
ADVANCE_SIGNATURE = types.int32(*_ARRAYS, _F64, *_SIZES, types.float64, types.int64)
# jacobian: evaluate's arrays with ``jacobian`` (N_RESULT x 12 doubles, row-major) in place of ``mask``
JACOBIAN_SIGNATURE = types.int32(*_ARRAYS[:-1], _F64, *_SIZES)
# accept: advance's with ``jacobian`` before ``mask`` (read where held is HELD_LINEARISED)
ACCEPT_SIGNATURE = types.int32(*_ARRAYS[:-1], _F64, types.voidptr, _F64, *_SIZES, types.float64, types.int64)


@entry_point(EVALUATE_SIGNATURE)
def evaluate_native(kinematics, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, mask,
                    n_points, n_blocks):
    """Forces for the kinematics into ``result`` (layout.R_*), Eqs. 1-23; returns 0."""
    k = carray(kinematics, 12)
    evaluate_contact(k[0:3], k[3:6], k[6:9], k[9:12], carray(jp, N_JOINT_PARAMETERS), carray(cos_phi, n_points),
                     carray(sin_phi, n_points), carray(wear_depth, n_points), carray(block_min, n_blocks),
                     carray(memory, N_MEMORY), carray(result, N_RESULT))
    return 0


@entry_point(JACOBIAN_SIGNATURE)
def jacobian_native(kinematics, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, jacobian, n_points,
                    n_blocks):
    """:func:`evaluate_native` and d result[r] / d kinematics[m] into ``jacobian[12 r + m]``; returns 0."""
    k = carray(kinematics, 12)
    contact_jacobian(k[0:3], k[3:6], k[6:9], k[9:12], carray(jp, N_JOINT_PARAMETERS), carray(cos_phi, n_points),
                     carray(sin_phi, n_points), carray(wear_depth, n_points), carray(block_min, n_blocks),
                     carray(memory, N_MEMORY), carray(result, N_RESULT), carray(jacobian, (N_RESULT, 12)))
    return 0


@entry_point(ADVANCE_SIGNATURE)
def advance_native(kinematics, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, mask, work,
                   n_points, n_blocks, dt, held):
    """Accept a step of dt [s] ending at the kinematics (``held`` != 0: held over the step, a Co-Simulation
    step) (wear, contact memory); returns 1 if the joint's state changed, 0 if not, -1 if the step was
    refused (its wear absurd; nothing changed)."""
    k = carray(kinematics, 12)
    changed = advance_joint(k[0:3], k[3:6], k[6:9], k[9:12], dt, held != 0, carray(jp, N_JOINT_PARAMETERS),
                            carray(cos_phi, n_points), carray(sin_phi, n_points), carray(wear_depth, n_points),
                            carray(block_min, n_blocks), carray(memory, N_MEMORY),
                            carray(mask, n_points, dtype=np.bool_), carray(work, 2 * n_points),
                            carray(result, N_RESULT))
    return changed


@entry_point(ACCEPT_SIGNATURE)
def accept_native(kinematics, jp, cos_phi, sin_phi, wear_depth, block_min, memory, result, jacobian, mask, work,
                  n_points, n_blocks, dt, held):
    """:func:`advance_native` when ``result`` already holds the evaluation at these kinematics and
    this state (the forces were read since the inputs last changed): the wear and onset update
    only, without evaluating the contact again; ``held`` 2: held, and ``jacobian`` (N_RESULT x 12, row-major) holds
    the derivatives at these kinematics a linearising host read (:func:`accept_linearised_contact`; else unread);
    returns as :func:`advance_native`."""
    k = carray(kinematics, 12)
    arrays = (carray(jp, N_JOINT_PARAMETERS), carray(cos_phi, n_points), carray(sin_phi, n_points),
              carray(wear_depth, n_points), carray(block_min, n_blocks), carray(memory, N_MEMORY),
              carray(mask, n_points, dtype=np.bool_), carray(work, 2 * n_points))
    if held == HELD_LINEARISED:
        return accept_linearised_contact(carray(result, N_RESULT), carray(jacobian, (N_RESULT, 12)), k[0:3], k[3:6],
                                         k[6:9], k[9:12], dt, *arrays)
    return accept_contact(carray(result, N_RESULT), k[0:3], k[3:6], k[6:9], k[9:12], dt, held != 0, *arrays)


@entry_point(types.int32(_F64, _F64, _F64, types.int64))
def bushing_points_native(phi, cos_phi, sin_phi, n_points):
    """phi_z, cos phi_z, sin phi_z of the bushing points (Eq. 3); returns 0."""
    bushing_points(carray(phi, n_points), carray(cos_phi, n_points), carray(sin_phi, n_points))
    return 0


@entry_point(types.int32(_F64, _F64, types.int64, types.int64))
def block_minima_native(wear_depth, block_min, n_points, n_blocks):
    """Refresh the contact search's block minima after the wear profile was replaced; returns 0."""
    block_minimum_depth(carray(wear_depth, n_points), carray(block_min, n_blocks))
    return 0


@entry_point(types.float64(_F64, _F64, types.int64))
def worn_volume_native(jp, wear_depth, n_points):
    """Volume removed from the bushing [m^3]."""
    return worn_volume(carray(jp, N_JOINT_PARAMETERS), carray(wear_depth, n_points))


@entry_point(types.int32(_F64, _F64, _F64, types.int64, _F64))
def wall_overlap_native(result, jp, wear_depth, n_points, out):
    """out = [how far the pin of the evaluation ``result`` is in the bushing wall [m], the admissible penetration
    [m], the admissible normal force [N]] (core.admissibility); returns 0 where that contact is admissible, else 1."""
    p = carray(jp, N_JOINT_PARAMETERS)
    o = carray(out, 3)
    r = carray(result, N_RESULT)
    depth = carray(wear_depth, n_points)
    o[0] = wall_overlap(r, p, depth)
    o[1] = admissible_penetration(p)
    o[2] = admissible_force(p)
    return 0 if is_admissible(r, p, depth) else 1


@entry_point(types.int32(_F64))
def complete_parameters_native(jp):
    """Fill the derived slots of the joint parameter vector (E*, effective k_w); returns 0."""
    complete_joint_parameters(carray(jp, N_JOINT_PARAMETERS))
    return 0


@entry_point(types.int32(_F64, _F64, _F64))
def update_contact_memory_native(result, jp, memory):
    """Contact-onset bookkeeping for the evaluation in ``result`` (a Model Exchange event);
    returns 1 if the contact memory changed, else 0."""
    changed = update_contact_memory(carray(result, N_RESULT), carray(jp, N_JOINT_PARAMETERS),
                                    carray(memory, N_MEMORY))
    return 1 if changed else 0
