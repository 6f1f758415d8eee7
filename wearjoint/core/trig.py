"""Cosine and sine of a Runge-Kutta stage's angle from those of the step's start (:func:`rotated_trig`).

The mechanism's equations of motion need cos and sin of the crank's and the rod's angles at every
stage; libm's cos and sin cost ~10 ns a pair in a loop (more inside the stages: the call spills the
caller's registers), the rotation by the stage's small angle ~4 ns (benchmarks/bench_cosim.py times
the co-simulation master's mechanism step).
"""
import math

from .jit import kernel

# Taylor coefficients of sin(d) / d and (cos(d) - 1) / d^2 in d^2, to d^11 and d^12: below 1e-22
# truncation at |d| <= _ROTATION_MAX_ANGLE, where rotated_trig needs no libm call
_SIN_TAYLOR = (-1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0)
_COS_TAYLOR = (-0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0, 1.0 / 479001600.0)
_ROTATION_MAX_ANGLE = 0.125


@kernel(inline='always')
def rotated_trig(c, s, angle, new_angle):
    """cos and sin of ``new_angle`` [rad] from c = cos(angle), s = sin(angle): the angle-addition
    formulas with the difference's sine and cosine by their Taylor series where it is at most
    1/8 rad (a Runge-Kutta stage's rotation: no libm call, within a few ulp of libm), else libm's."""
    d = new_angle - angle
    if abs(d) > _ROTATION_MAX_ANGLE:
        return math.cos(new_angle), math.sin(new_angle)
    d2 = d * d
    sin_d = d + d * d2 * (_SIN_TAYLOR[0] + d2 * (_SIN_TAYLOR[1] + d2 * (_SIN_TAYLOR[2] + d2 * (
        _SIN_TAYLOR[3] + d2 * _SIN_TAYLOR[4]))))
    cos_d_minus_1 = d2 * (_COS_TAYLOR[0] + d2 * (_COS_TAYLOR[1] + d2 * (_COS_TAYLOR[2] + d2 * (
        _COS_TAYLOR[3] + d2 * (_COS_TAYLOR[4] + d2 * _COS_TAYLOR[5])))))
    return c + (c * cos_d_minus_1 - s * sin_d), s + (s * cos_d_minus_1 + c * sin_d)
