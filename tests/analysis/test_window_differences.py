"""analysis.window_differences: the point-wise comparison over the first impacts (validate, cosim-study), at the
run's own points against a reference recorded at every step."""
import numpy as np
import pytest

from wearjoint import analysis
from wearjoint.core import layout as L


def _samples(times, values):
    s = np.zeros((len(times), L.N_SAMPLE_COLUMNS))
    s[:, L.T_TIME] = times
    s[:, L.T_ECC_X] = values
    return s


def test_a_sparse_run_is_judged_at_its_own_points():
    """A co-simulation's free-flight steps are up to 0.1 ms long: a run that computes a kinked motion exactly at
    those points is 1 nm off (its offset) at each of them, where interpolating it at the reference's dense samples
    would report the chord across the kink (0.5 um here) as its error."""
    t_ref = np.arange(1, 1001) * 1e-6                      # 1 us .. 1 ms, every step
    motion = lambda t: 1e-2 * np.abs(t - 0.45e-3)          # a pin that reverses at 0.45 ms (an impact)
    reference = _samples(t_ref, motion(t_ref))
    t = np.arange(1, 11) * 1e-4                            # 0.1 ms .. 1 ms
    record = _samples(t, motion(t) + 1e-9)
    d = analysis.window_differences(record, reference, 1e-3, (L.T_ECC_X,))
    assert d.shape == (10, 1)
    assert np.abs(d - 1e-9).max() < 1e-14
    inside = t_ref >= t[0]
    chord = np.interp(t_ref[inside], t, record[:, L.T_ECC_X]) - reference[inside, L.T_ECC_X]
    assert np.abs(chord).max() > 4e-7                      # what interpolating the run reported


def test_a_run_that_samples_before_the_reference_is_not_compared_with_its_first_value_held_back():
    """Samples earlier than the reference's first are left out, not compared with the reference's first value."""
    reference = _samples(np.arange(10, 101) * 1e-5, np.arange(10, 101) * 1e-9)
    record = _samples(np.arange(1, 101) * 1e-5, np.arange(1, 101) * 1e-9)
    d = analysis.window_differences(record, reference, 1e-3, (L.T_ECC_X,))
    assert d.shape == (91, 1) and np.abs(d).max() < 1e-20


def test_a_run_that_ends_before_the_window_is_refused_and_a_short_reference_shortens_the_window():
    """The window ends at the reference's last sample in it (a study shorter than the window compares what both
    ran); a run that stops before that point (diverged) is refused, naming both times."""
    long, brief = _samples(np.arange(1, 11) * 1e-4, np.zeros(10)), _samples(np.arange(1, 6) * 1e-4, np.zeros(5))
    with pytest.raises(ValueError, match="run ends at 0.0005 s, before the window end 0.001 s"):
        analysis.window_differences(brief, long, 1e-3, (L.T_ECC_X,))
    assert analysis.window_differences(long, brief, 1e-3, (L.T_ECC_X,)).shape == (5, 1)
