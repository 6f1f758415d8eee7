"""The slider-crank's parameter vector from its fields, the slider-load table's check and the load on the
slider (layout.MP_*; the fields' table is wearjoint.mechanism_parameters.MECHANISM_FIELDS)."""
import math

from .jit import kernel
from .layout import (
    LOAD_TABLE_END, LOAD_TABLE_PERIODIC, LOAD_TABLE_RISE, LOAD_TABLE_ROW_BASE, LOAD_TABLE_ROWS, LOAD_TABLE_START,
    MAX_LOAD_ROWS, MP_LOAD_ANGLES, MP_LOAD_FORCES, MP_LOAD_ROWS, MP_OMEGA, MP_SLIDER_FORCE, MP_SLIDER_FORCE_INPUT,
    MP_THETA0, N_MECHANISM_FIELDS,
)


@kernel
def mechanism_parameter_vector(fields, scales, mp):
    """The kernels' parameter vector mp (layout.MP_*) from the mechanism's fields in the user's units (rpm,
    degrees; wearjoint.mechanism_parameters.field_vector, the SliderCrank FMU's parameters in their order):
    slot k = fields[k] scales[0, k] / scales[1, k] (wearjoint.mechanism_parameters.FIELD_SCALES); the master's
    slider load 0."""
    for k in range(N_MECHANISM_FIELDS):
        mp[k] = fields[k] * scales[0, k] / scales[1, k]
    mp[MP_SLIDER_FORCE_INPUT] = 0.0
    return N_MECHANISM_FIELDS


@kernel
def load_table_problem(fields):
    """0 if the slider-load table in ``fields`` (the mechanism's fields in the user's units: degrees) is valid:
    no rows, or 2 to MAX_LOAD_ROWS rows whose angles rise strictly from 0 to 360 and whose 360 row repeats the 0
    row's load; else kind * LOAD_TABLE_ROW_BASE + the (1-based) row it concerns (layout.LOAD_TABLE_*;
    wearjoint.mechanism_parameters.LOAD_TABLE_PROBLEMS words each kind, the FMU logs the same words)."""
    rows_value = fields[MP_LOAD_ROWS]
    rows = int(rows_value)
    if rows == 0 and rows_value == 0.0:
        return 0
    if rows != rows_value or rows < 2 or rows > MAX_LOAD_ROWS:
        return LOAD_TABLE_ROWS * LOAD_TABLE_ROW_BASE
    if fields[MP_LOAD_ANGLES] != 0.0:
        return LOAD_TABLE_START * LOAD_TABLE_ROW_BASE + 1
    for k in range(1, rows):
        if not fields[MP_LOAD_ANGLES + k] > fields[MP_LOAD_ANGLES + k - 1]:
            return LOAD_TABLE_RISE * LOAD_TABLE_ROW_BASE + k + 1
    if fields[MP_LOAD_ANGLES + rows - 1] != 360.0:
        return LOAD_TABLE_END * LOAD_TABLE_ROW_BASE + rows
    if fields[MP_LOAD_FORCES + rows - 1] != fields[MP_LOAD_FORCES]:
        return LOAD_TABLE_PERIODIC * LOAD_TABLE_ROW_BASE + rows
    return 0


@kernel(inline='always')
def slider_load(t, mp):
    """The load on the slider [N] at time t [s], positive towards the crank's pivot: the constant, the master's
    input and the table at theta1 = theta0 - omega t (mod 2 pi), linearly interpolated between its rows."""
    load = mp[MP_SLIDER_FORCE] + mp[MP_SLIDER_FORCE_INPUT]
    if mp[MP_LOAD_ROWS] >= 2.0:
        rows = int(mp[MP_LOAD_ROWS])
        angle = (mp[MP_THETA0] - mp[MP_OMEGA] * t) % (2.0 * math.pi)
        lo = 0
        hi = rows - 1
        while hi - lo > 1:                   # the segment [a_lo, a_hi] holding the angle (a_0 = 0, a_last = 2 pi)
            mid = (lo + hi) // 2
            if mp[MP_LOAD_ANGLES + mid] <= angle:
                lo = mid
            else:
                hi = mid
        a0 = mp[MP_LOAD_ANGLES + lo]
        a1 = mp[MP_LOAD_ANGLES + hi]
        f0 = mp[MP_LOAD_FORCES + lo]
        load += f0 + (mp[MP_LOAD_FORCES + hi] - f0) * (angle - a0) / (a1 - a0)
    return load
