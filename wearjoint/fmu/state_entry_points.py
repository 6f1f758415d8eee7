"""C entry points of the state format (:mod:`wearjoint.core.state_format`) for every native FMU.

The joint FMU and the SliderCrank FMU write, check and read their FMU states with these numba
``cfunc``s, compiled ahead of time into each binary (:mod:`wearjoint.fmu.aot`): the same kernels
as the in-process joint, so one layout, one checksum and one set of checks for every state.
"""
from numba import carray, types

from ..core import state_format
from ..core.layout import N_MEMORY
from .aot import entry_point

_F64 = types.CPointer(types.float64)
_U8 = types.CPointer(types.uint8)


@entry_point(types.int64(types.int64, types.int64))
def state_size_native(n_head, n_points):
    """Bytes of a state with ``n_head`` head values and ``n_points`` wear depths."""
    return state_format.state_size(n_head, n_points)


@entry_point(types.int32(_U8, types.int64, types.int64, _F64, types.int64, _F64, _F64, types.int64))
def write_state_native(data, size, contents, head, n_head, memory, wear_depth, n_points):
    """Write a state of ``contents`` into ``data`` (``size`` bytes, checksum included); returns 0."""
    state_format.write_state(carray(data, size), contents, carray(head, n_head), carray(memory, N_MEMORY),
                             carray(wear_depth, n_points))
    return 0


@entry_point(types.int32(_U8, types.int64, types.int64, types.int64, types.int64, _F64))
def check_header_native(data, size, contents, n_head, n_points, values):
    """0 if ``data`` is an intact state of this kind and size, else the problem (values: what it compared)."""
    return state_format.check_header(carray(data, size), contents, n_head, n_points, carray(values, 4))


@entry_point(types.int32(_U8, types.int64, _F64, types.int64, _F64, _F64, types.int64))
def read_state_native(data, size, head, n_head, memory, wear_depth, n_points):
    """Copy a checked state's values out; returns 0."""
    state_format.read_state(carray(data, size), carray(head, n_head), carray(memory, N_MEMORY),
                            carray(wear_depth, n_points))
    return 0


@entry_point(types.int32(_F64, types.int64, _F64, _F64, types.int64, types.float64, types.float64, _F64))
def check_values_native(head, n_head, memory, wear_depth, n_points, bushing_radius, velocity_floor, values):
    """0 if a state's values are in range (an FMU head's time and flag, the contact memory, the wear
    depths up to ``bushing_radius``), else the problem (values: what it compared)."""
    return state_format.check_values(carray(head, n_head), carray(memory, N_MEMORY), carray(wear_depth, n_points),
                                     bushing_radius, velocity_floor, carray(values, 4))
