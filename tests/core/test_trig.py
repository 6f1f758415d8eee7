"""The stages' trigonometry (core/trig.py): cos and sin of a rotated angle against libm's."""
import math

import numpy as np
import pytest
from numba import njit

from wearjoint.core.trig import rotated_trig


@njit
def _rotated(angles, new_angles, out):
    for i in range(angles.shape[0]):
        out[0, i], out[1, i] = rotated_trig(math.cos(angles[i]), math.sin(angles[i]), angles[i], new_angles[i])


@pytest.mark.parametrize("largest_turn", [1e-9, 1e-3, 0.05, 0.125, 0.5, 3.0])
def test_rotated_cos_sin_equal_libm_to_a_few_ulp(largest_turn):
    """Angles of up to 4000 crank revolutions, turned by up to ``largest_turn`` rad either way (beyond
    1/8 rad, libm's own): each value within 4 ulp of 1 of libm's cos/sin of the new angle."""
    rng = np.random.default_rng(7)
    angles = rng.uniform(-2.6e4, 2.6e4, 200_000)
    new_angles = angles + rng.uniform(-largest_turn, largest_turn, angles.size)
    out = np.empty((2, angles.size))
    _rotated(angles, new_angles, out)
    ulp_of_one = np.spacing(1.0)
    assert np.abs(out[0] - np.cos(new_angles)).max() <= 4 * ulp_of_one
    assert np.abs(out[1] - np.sin(new_angles)).max() <= 4 * ulp_of_one


def test_no_turn_returns_the_values_given():
    out = np.empty((2, 1))
    _rotated(np.array([0.7]), np.array([0.7]), out)
    assert out[0, 0] == math.cos(0.7) and out[1, 0] == math.sin(0.7)


def test_the_masters_chained_rotations_stay_within_64_ulp_of_libm():
    """The co-simulation master rotates each step's cos/sin from the last step's, 31 times between libm
    calls: over 20 000 steps of up to 3 mrad, every value stays within 64 ulp of 1 of libm's."""
    from wearjoint.core import layout as L
    from wearjoint.cosim.master_layout import B_TRIG
    from wearjoint.cosim.master_loop import _step_trig

    rng = np.random.default_rng(3)
    buf = np.zeros(B_TRIG + 7)
    y = np.zeros(2 * L.N_COORDINATES)
    y[L.CRANK + 2], y[L.ROD + 2] = 2.0e4, -1.3
    mp = np.zeros(L.N_MECHANISM_PARAMETERS)                 # the crank-rod joint: the crank's and the rod's angles
    worst = 0.0
    for _ in range(20_000):
        y[L.CRANK + 2] += rng.uniform(0.0, 3e-3)
        y[L.ROD + 2] += rng.uniform(-3e-3, 3e-3)
        cos1, sin1, cos2, sin2 = _step_trig(buf, y, mp)
        worst = max(worst, abs(cos1 - math.cos(y[L.CRANK + 2])), abs(sin1 - math.sin(y[L.CRANK + 2])),
                    abs(cos2 - math.cos(y[L.ROD + 2])), abs(sin2 - math.sin(y[L.ROD + 2])))
    assert 0.0 < worst <= 64 * np.spacing(1.0)
