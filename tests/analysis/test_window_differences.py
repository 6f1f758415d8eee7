"""analysis.window_differences: the point-wise comparison over the first impacts (validate, cosim-study)."""
import numpy as np
import pytest

from wearjoint import analysis
from wearjoint.core import layout as L


def _samples(times, values):
    s = np.zeros((len(times), L.N_SAMPLE_COLUMNS))
    s[:, L.T_TIME] = times
    s[:, L.T_ECC_X] = values
    return s


def test_a_run_that_samples_later_is_not_extrapolated_back():
    """A co-simulation records its first sample at its first communication point (1e-4 s in free flight): the
    reference's earlier samples are left out instead of compared with that sample's value held back."""
    t_ref = np.arange(1, 101) * 1e-5                       # 10 us .. 1 ms
    reference = _samples(t_ref, t_ref ** 2)                # a pin leaving the centre
    t = np.arange(1, 11) * 1e-4                            # 0.1 ms .. 1 ms
    record = _samples(t, t ** 2 + 1e-9)                    # the same motion, 1 nm off
    d = analysis.window_differences(record, reference, 1e-3, (L.T_ECC_X,))
    assert d.shape == (91, 1)                              # reference samples from 0.1 ms on
    assert np.abs(d).max() <= 1e-9 + 0.25 * 1e-8 + 1e-15    # 1 nm and the interpolation of t^2 over 0.1 ms (h^2/4)


def test_a_run_that_ends_before_the_window_is_refused():
    reference = _samples(np.arange(1, 11) * 1e-4, np.zeros(10))
    with pytest.raises(ValueError, match="before the window end"):
        analysis.window_differences(_samples(np.arange(1, 6) * 1e-4, np.zeros(5)), reference, 1e-3, (L.T_ECC_X,))
