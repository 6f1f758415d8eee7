"""Impact-vibration events per revolution and chattering revolutions (wearjoint.analysis, docs/reference/results.md §6).

The synthetic trace: the ideal slider acceleration plus damped bursts A exp(-s/tau) sin(w s) (s: time since the
burst's start), whose |.| peaks at s* = atan(w tau) / w, placed so that each peak falls at a chosen crank angle
theta1 = theta0 - omega t; the expected angles are those chosen, not values the code under test computed.
"""
import csv
import json
import math

import numpy as np
import pytest

from wearjoint import analysis
from wearjoint.core import layout as L
from wearjoint.slider_crank import SliderCrank
from wearjoint.parameters import SliderCrankParameters

MECH = SliderCrankParameters(initial_crank_angle_deg=30.0)     # theta1 = 30 deg - rotation
PERIOD = MECH.period_s
DT = 1e-5                                                      # sample spacing [s] (0.009 deg)
W = 2.0 * math.pi * 2000.0                                     # burst: 2 kHz, decay time 2 ms (about 4 deg above 100)
TAU = 2e-3
S_PEAK = math.atan(W * TAU) / W
BASE_ANGLES = (5.0, 185.0)                                     # theta1 at the two bursts of every revolution [deg]
N_REV = 4                                                      # revolutions 0..3 whole, revolution 4 half sampled


def deg_per_sample(dt=DT):
    return dt / PERIOD * 360.0


def peak_time(revolution: int, theta1_deg: float) -> float:
    """The time in ``revolution`` at which theta1 = 30 deg - 360 t / T equals theta1_deg (mod 360)."""
    rotation = (30.0 - theta1_deg) % 360.0
    return (revolution + rotation / 360.0) * PERIOD


def trace(bursts, revolutions=N_REV + 0.5, dt=DT):
    """Samples (layout.T_*) of the ideal slider-crank plus ``bursts``: (peak time [s], amplitude [m/s^2])."""
    t = np.arange(1, int(round(revolutions * PERIOD / dt)) + 1) * dt
    samples = np.zeros((t.size, L.N_SAMPLE_COLUMNS))
    samples[:, L.T_TIME] = t
    samples[:, L.T_CRANK_ANGLE] = math.radians(30.0) - MECH.omega_rad_s * t     # unwrapped, as the kernels store it
    a = SliderCrank(MECH).closed_form(t)["slider_a_m_s2"].copy()
    for t_peak, amplitude in bursts:
        s = t - (t_peak - S_PEAK)
        on = s >= 0.0
        a[on] += amplitude * np.exp(-s[on] / TAU) * np.sin(W * s[on])
    samples[:, L.T_SLIDER_A] = a
    return samples


def stats_rows(impacts, last_share=0.5):
    """Per-revolution statistics with the given contact onsets; the last row covers ``last_share`` of a period."""
    stats = np.zeros((len(impacts), L.N_STATS))
    stats[:, L.S_IMPACTS] = impacts
    stats[:, L.S_TIME] = PERIOD
    stats[-1, L.S_TIME] = last_share * PERIOD
    return stats


# revolution 2's extras: a smaller burst 10 deg of rotation after the 185 deg one (merges into it), two bursts 30 deg
# apart (theta1 90 and 60: two events), and a weak burst 7 deg before the revolution starts merging with a strong one
# 2 deg after it (one event, whose peak is in revolution 2)
EXTRA = [(peak_time(2, 175.0), 500.0), (peak_time(2, 90.0), 1000.0), (peak_time(2, 60.0), 800.0),
         (peak_time(1, 37.0), 300.0), (peak_time(2, 28.0), 1000.0)]
EXPECTED = {0: [5.0, 185.0], 1: [5.0, 185.0], 2: [28.0, 5.0, 185.0, 90.0, 60.0], 3: [5.0, 185.0]}
BURSTS = [(peak_time(k, angle), 1000.0) for k in range(N_REV + 1) for angle in BASE_ANGLES
          if peak_time(k, angle) < (N_REV + 0.5) * PERIOD - 0.05] + EXTRA
IMPACTS = [50, 121, 120, 200, 10]                              # chattering: more than 120 contact onsets


@pytest.fixture(scope="module")
def synthetic():
    return trace(BURSTS), stats_rows(IMPACTS)


def test_the_events_are_the_bursts_at_their_crank_angles(synthetic):
    samples, stats = synthetic
    per = analysis.revolution_impact_events(samples, stats, MECH)
    assert per["sampled"].tolist() == [True, True, True, True, False]
    assert per["events"][:4].tolist() == [2, 2, 5, 2] and math.isnan(per["events"][4])
    for k, angles in EXPECTED.items():
        assert sorted(per["angles_deg"][k]) == pytest.approx(sorted(angles), abs=1.01 * deg_per_sample())
    assert per["chattering"].tolist() == [False, True, False, True, False]


def test_bursts_merge_within_the_merge_angle_and_separate_beyond():
    """Two single-sample spikes in revolution 0, 14 deg or 16 deg of crank rotation apart: one or two events."""
    for gap_deg, expected in ((14.0, 1), (16.0, 2), (40.0, 2)):
        samples = trace([], revolutions=1.0)
        i, j = round(0.3 * PERIOD / DT), round((0.3 + gap_deg / 360.0) * PERIOD / DT)
        samples[i, L.T_SLIDER_A] += 900.0
        samples[j, L.T_SLIDER_A] -= 400.0
        per = analysis.revolution_impact_events(samples, stats_rows([0], 1.0), MECH, merge_deg=15.0)
        assert per["events"].tolist() == [expected]
        assert per["angles_deg"][0][0] == pytest.approx((30.0 - 0.3 * 360.0) % 360.0, abs=1.01 * deg_per_sample())


def test_a_peak_on_a_revolution_boundary_is_the_next_revolutions_and_one_at_the_runs_end_is_none():
    """Spikes at the samples t = T and t = 2 T, the end of a two-revolution run: the first starts revolution 1 (theta1
    = 30 deg, the start angle), the second would start revolution 2, which the run does not hold.  It had been
    counted in revolution 1 beside that revolution's own start: 3.5 events per revolution where 3 happened."""
    samples = trace([], revolutions=2.0)
    ends = [int(np.argmin(np.abs(samples[:, L.T_TIME] - k * PERIOD))) for k in (1, 2)]
    assert ends[1] == samples.shape[0] - 1 and samples[ends[0], L.T_TIME] == pytest.approx(PERIOD, abs=1e-15)
    for i in ends:
        samples[i, L.T_SLIDER_A] += 900.0
    per = analysis.revolution_impact_events(samples, stats_rows([0, 0], 1.0), MECH)
    assert per["events"].tolist() == [0, 1]
    assert per["angles_deg"][1] == [pytest.approx(30.0, abs=1e-6)]


def test_no_event_below_the_threshold_or_without_bursts():
    samples = trace([(peak_time(0, 100.0), 90.0)], revolutions=1.0)      # peak 90 m/s^2 < 100
    per = analysis.revolution_impact_events(samples, stats_rows([130], 1.0), MECH)
    assert per["events"].tolist() == [0] and per["angles_deg"] == [[]] and per["chattering"].tolist() == [True]


def test_summary_statistics_of_the_counted_revolutions(synthetic):
    samples, stats = synthetic
    out = analysis.impact_event_statistics(analysis.revolution_impact_events(samples, stats, MECH), MECH,
                                           settling_revolutions=1)
    assert out["impact_event_revolutions"] == [1, 2, 3]                  # start-up 0 and the half revolution 4 out
    assert out["impact_events_per_revolution"] == pytest.approx(9.0 / 3.0)
    assert sorted(out["impact_event_crank_angles_deg"]) == pytest.approx(
        sorted(EXPECTED[1] + EXPECTED[2] + EXPECTED[3]), abs=1.01 * deg_per_sample())
    assert out["chattering_revolution_share"] == pytest.approx(2.0 / 3.0)
    text = out["impact_event_definition"]
    assert "100 m/s^2" in text and "15 deg" in text and "more than 120 contact onsets" in text
    assert "coarser" not in text


def test_one_revolution_is_used_and_coarse_samples_are_noted():
    dt = PERIOD / 200.0                                                  # 1.8 deg: coarser than 1/360 revolution
    samples = trace([(peak_time(0, 5.0), 1000.0), (peak_time(0, 185.0), 1000.0)], revolutions=1.0, dt=dt)
    out = analysis.impact_event_statistics(analysis.revolution_impact_events(samples, stats_rows([121], 1.0), MECH),
                                           MECH, settling_revolutions=1)
    assert out["impact_event_revolutions"] == [0]
    assert out["impact_events_per_revolution"] == 2.0 and out["chattering_revolution_share"] == 1.0
    assert sorted(out["impact_event_crank_angles_deg"]) == pytest.approx([5.0, 185.0], abs=1.01 * deg_per_sample(dt))
    assert "coarser than 1/360 revolution" in out["impact_event_definition"]


@pytest.mark.parametrize("dt,noted", [(1e-5, False), (1e-4, False), (2e-4, True)])
def test_samples_in_contact_coarser_than_a_burst_resolves_are_noted(dt, noted):
    """At --sample-dt 3e-4 s (1/1333 revolution, inside the 1/360 note) the paper's events per revolution moved from
    1.67 to 4.0; 1e-4 s gave 1e-5's count.  The spacing judged is the samples' in contact (free flight's long steps
    left out): every sample here is in contact."""
    samples = trace([(peak_time(0, 5.0), 1000.0)], revolutions=1.0, dt=dt)
    samples[:, L.T_CONTACT] = 1.0
    per = analysis.revolution_impact_events(samples, stats_rows([10], 1.0), MECH)
    assert per["contact_sample_spacing_s"] == pytest.approx(dt)
    said = analysis.impact_event_statistics(per, MECH)["impact_event_definition"]
    assert ("coarser than 0.00015 s" in said) == noted and "1/360" not in said
    samples[:, L.T_CONTACT] = 0.0                      # no contact: nothing to judge, nothing said
    per = analysis.revolution_impact_events(samples, stats_rows([10], 1.0), MECH)
    assert math.isnan(per["contact_sample_spacing_s"])
    assert "coarser" not in analysis.impact_event_statistics(per, MECH)["impact_event_definition"]


def test_the_angle_wraps_into_0_360():
    assert analysis.crank_angle_deg([-1e-17, -math.pi / 2, 2 * math.pi + 0.1, -4 * math.pi]).tolist() == \
        pytest.approx([0.0, 270.0, math.degrees(0.1), 0.0])
    assert np.all(analysis.crank_angle_deg(-np.linspace(0, 40, 10001)) < 360.0)


def test_a_short_run_writes_consistent_impact_event_results(tmp_path):
    from wearjoint.results import write_results
    from wearjoint.simulate import SimulationOptions, run_simulation

    record = run_simulation(options=SimulationOptions(revolutions=2), progress=False)
    write_results(record, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    with open(tmp_path / "revolutions.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert {"impact_events", "chattering"} <= set(rows[0])
    counted = summary["impact_event_revolutions"]
    assert counted == [1]                                                # after the start-up revolution
    angles = summary["impact_event_crank_angles_deg"]
    per_rev = summary["impact_events_per_revolution"]
    assert len(angles) == round(per_rev * len(counted)) == sum(int(float(rows[k]["impact_events"])) for k in counted)
    assert all(0.0 <= a < 360.0 for a in angles)
    for row in rows:
        assert float(row["chattering"]) == float(float(row["impacts"]) > 120)
    assert summary["chattering_revolution_share"] == pytest.approx(
        np.mean([float(rows[k]["chattering"]) for k in counted]))
    assert "100 m/s^2" in summary["impact_event_definition"]
    # each angle is the crank angle of a sample of a counted revolution whose |a - a_ideal| passes the threshold
    s = record.samples
    deviation = np.abs(s[:, L.T_SLIDER_A] - SliderCrank(record.parameters.mechanism).closed_form(s[:, L.T_TIME])[
        "slider_a_m_s2"])
    in_counted = np.isin(np.floor(s[:, L.T_TIME] / record.period_s), counted)
    sample_deg = np.degrees(s[:, L.T_CRANK_ANGLE]) % 360.0
    for a in angles:
        near = in_counted & (deviation > 100.0) & (np.abs(sample_deg - a) < 1e-9)
        assert near.any()
