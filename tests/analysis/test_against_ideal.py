"""against_ideal: the designer's answers against the ideal joint are taken over the revolutions and the time the run's
other answers are (analysis.steady_revolutions, analysis.time_rms)."""
import math

import numpy as np
import pytest

from wearjoint import against_ideal, analysis
from wearjoint.core import layout as L
from wearjoint.parameters import SliderCrankParameters
from wearjoint.results import new_revolution_stats

MECHANISM = SliderCrankParameters()
PERIOD = MECHANISM.period_s


def _samples(times):
    s = np.zeros((len(times), L.N_SAMPLE_COLUMNS))
    s[:, L.T_TIME] = times
    return s


def test_the_time_rms_of_a_sine_does_not_move_with_the_sampling():
    """A run samples at its steps in free flight and at the sample spacing in contact: dense where the error is
    large, the plain mean over the samples weighted the impacts (a press: 16.5 to 20.3 m/s² at three step limits,
    17.5 over time).  Over time, a sine's RMS is its amplitude over sqrt 2 on any grid."""
    rng = np.random.default_rng(3)
    for t in (np.linspace(0.0, 1.0, 2001), np.sort(np.concatenate([np.linspace(0.0, 1.0, 201),
                                                                  rng.uniform(0.2, 0.3, 3000)]))):
        signal = 5.0 * np.sin(2.0 * np.pi * 3.0 * t)
        assert analysis.time_rms(signal, analysis.sample_durations(t)) == pytest.approx(5.0 / math.sqrt(2.0),
                                                                                        rel=2e-3)
    spike = np.concatenate([np.arange(0.0, 0.5, 1e-4), np.arange(0.5, 0.501, 1e-6), np.arange(0.501, 1.0, 1e-4)])
    error = np.where((spike >= 0.5) & (spike < 0.501), 10.0, 0.0)      # 10 for 1 ms of 1 s, sampled 100x denser
    assert analysis.time_rms(error, analysis.sample_durations(spike)) == pytest.approx(10.0 * math.sqrt(1e-3),
                                                                                       rel=0.05)   # edges: 5e-5 s
    assert math.sqrt(np.mean(error ** 2)) > 5.0 * 10.0 * math.sqrt(1e-3)   # what the mean over samples said


def test_the_joint_force_over_the_ideal_takes_the_revolutions_of_the_max_contact_force():
    """1.6 revolutions: the run's extremes leave out revolution 0 (the start-up); the ideal joint's largest force
    came from revolution 0 (where a press's stroke lay, 7871 N) while the clearance joint's came from revolution 1
    (4170 N), and the ratio said 0.53 where revolution 1 against itself is 1.09."""
    stats = new_revolution_stats(2)
    stats[0, L.S_TIME], stats[1, L.S_TIME] = PERIOD, 0.6 * PERIOD
    stats[0, L.S_FORCE_MAX], stats[1, L.S_FORCE_MAX] = 9000.0, 4170.0
    times = np.linspace(0.0, 1.6 * PERIOD, 321)[1:]
    ideal = np.where(times < PERIOD, 7871.0, 3809.0)
    statistics = analysis.run_statistics(stats, 1)
    summary = against_ideal.summary_statistics(_samples(times), stats, MECHANISM, 1,
                                               statistics["max_contact_force_N"], (np.ones_like(times), ideal))
    assert statistics["max_contact_force_N"] == 4170.0
    assert summary["ideal_joint_force_max_N"] == 3809.0
    assert summary["joint_force_over_ideal"] == pytest.approx(4170.0 / 3809.0)


def test_a_sliver_after_the_last_revolution_is_no_revolution_on_either_side():
    """1.02 revolutions: the 2 % of revolution 1 is no revolution after the start-up (the largest contact force and
    the last revolution's impacts were its own); both sides keep revolution 0 and say so."""
    stats = new_revolution_stats(2)
    stats[0, [L.S_TIME, L.S_FORCE_MAX, L.S_IMPACTS]] = PERIOD, 9000.0, 40.0
    stats[1, [L.S_TIME, L.S_FORCE_MAX, L.S_IMPACTS]] = 0.02 * PERIOD, 300.0, 1.0
    times = np.linspace(0.0, 1.02 * PERIOD, 205)[1:]
    ideal = np.where(times < PERIOD, 7871.0, 100.0)
    statistics = analysis.run_statistics(stats, 1)
    summary = against_ideal.summary_statistics(_samples(times), stats, MECHANISM, 1,
                                               statistics["max_contact_force_N"], (np.ones_like(times), ideal))
    assert statistics["statistics_from_revolution"] == 0 and "included" in statistics["start_up"]
    assert statistics["max_contact_force_N"] == 9000.0 and statistics["impacts_per_revolution"] == 40
    assert summary["joint_force_over_ideal"] == pytest.approx(9000.0 / 7871.0)


def test_a_run_inside_its_start_up_takes_it_on_both_sides():
    """0.8 revolutions, the start-up not over: both keep revolution 0 (statistics_from_revolution 0)."""
    stats = new_revolution_stats(1)
    stats[0, L.S_TIME], stats[0, L.S_FORCE_MAX] = 0.8 * PERIOD, 2000.0
    times = np.linspace(0.0, 0.8 * PERIOD, 101)[1:]
    statistics = analysis.run_statistics(stats, 1)
    summary = against_ideal.summary_statistics(_samples(times), stats, MECHANISM, 1,
                                               statistics["max_contact_force_N"],
                                               (np.zeros_like(times), np.full_like(times, 1000.0)))
    assert statistics["statistics_from_revolution"] == 0
    assert summary["joint_force_over_ideal"] == pytest.approx(2.0)


def test_a_revolution_with_one_sample_has_no_statistics_against_the_ideal():
    """A wear study's last revolution's time series starts with the previous revolution's last point (t = 2T - 2e-13):
    revolutions.csv gave that revolution an error max = RMS of 0.0047 m/s² from that one sample, where its real error
    is hundreds of m/s²; it is NaN, as for every revolution without samples."""
    stats = new_revolution_stats(3)
    stats[:, L.S_TIME] = PERIOD
    times = np.concatenate([[2.0 * PERIOD - 2.3e-13], np.linspace(2.0 * PERIOD, 3.0 * PERIOD, 201)[1:]])
    table = against_ideal.revolution_columns(_samples(times), stats, MECHANISM)
    assert np.isnan(table[:2]).all() and np.isfinite(table[2]).all()
