"""Every statistic a report shows, defined once: per-revolution statistics, profile
metrics (deepest point, wear lobes, profile differences), impact-vibration events (per
revolution, with the chattering revolutions) and the wear growth exponent.

Per-revolution statistics come from the rows the engines accumulate
(``layout.S_*``, one row per crank revolution, filled by
``core.integrators.record_step``); profile metrics from a worn profile
(``phi_deg`` in the bushing frame, ``wear_depth_m``).  ``summary.json`` (docs/reference/results.md §6), the
validation, the co-simulation study, the wear study and the benchmarks all read
these functions.
"""
from __future__ import annotations

import math

import numpy as np

from .core import layout as L

REVOLUTION_COLUMNS = ("revolution", "impacts", "contact_fraction", "slider_acc_max_m_s2",
                      "slider_acc_min_m_s2", "max_contact_force_N", "max_eccentricity_m",
                      "max_wear_depth_m", "impact_events", "chattering")
# impact-vibration events (paper Sec. 7: two per crank revolution, at the slider's dead centres), :func:`impact_events`
IMPACT_EVENT_THRESHOLD_M_S2 = 100.0     # a sample is in an event where |a - a_ideal| exceeds this [m/s^2]
IMPACT_EVENT_MERGE_DEG = 15.0           # clusters at most this much crank rotation apart are one event [deg]
CHATTER_IMPACTS_PER_REVOLUTION = 120    # a revolution with more contact onsets (impacts) than this chatters
IMPACT_EVENT_SAMPLES_PER_REVOLUTION = 360   # samples coarser than this many per revolution are noted as such
# samples in contact further apart than this [s] are noted too: an impact's burst lasts about a millisecond, its
# contacts tens of microseconds.  The paper's 4 revolutions: 1.67 events per revolution at --sample-dt 1e-5 and 1e-4 s
# (each sample is the first step's end after a multiple: the median spacing in contact a little over it), 2.67 at
# 2e-4, 4.0 at 3e-4
IMPACT_EVENT_MAX_SAMPLE_S = 1.5e-4


# ---------------------------------------------------------------- per-revolution statistics
def pin_left_bushing(max_eccentricity_m: float, clearance_m: float, max_wear_depth_m: float,
                     admissible_penetration_m: float, max_force_N: float = 0.0,
                     admissible_force_N: float = math.inf) -> str:
    """Why a run's numbers are not physical, '' when they may be: the pin centre went further from the bushing
    centre than c + h_max + the admissible penetration (:attr:`JointParameters.admissible_penetration_m`: a pin
    in its groove sits at c + h + its penetration, docs/reference/model.md §3.14), its normal force passed the admissible
    one (:attr:`JointParameters.admissible_force_N`), or a value is not finite."""
    if not (math.isfinite(max_eccentricity_m) and math.isfinite(max_wear_depth_m) and math.isfinite(max_force_N)):
        return "the state is not finite"
    if max_force_N > admissible_force_N:
        return (f"the normal force reached {max_force_N:.3g} N > the admissible {admissible_force_N:.3g} N (the Hertz "
                f"law's at the admissible penetration {admissible_penetration_m:.3g} m)")
    limit = clearance_m + max_wear_depth_m + admissible_penetration_m
    if max_eccentricity_m > limit:
        return (f"the pin went {max_eccentricity_m - clearance_m - max_wear_depth_m:.3g} m into the bushing wall: "
                f"eccentricity {max_eccentricity_m:.3g} m > clearance + max wear depth + admissible penetration "
                f"({admissible_penetration_m:.3g} m) = {limit:.3g} m")
    return ""


def past_admissible(eccentricity_m, wear_depth_m, normal_force_N, clearance_m: float, admissible_penetration_m: float,
                    admissible_force_N: float) -> np.ndarray:
    """Per point, True where :func:`pin_left_bushing` would object: the eccentricity past c + h + the admissible
    penetration, the normal force past the admissible one, or either not finite (``wear_depth_m`` a value or one
    per point)."""
    e = np.asarray(eccentricity_m, float)
    return (~(e <= clearance_m + np.asarray(wear_depth_m, float) + admissible_penetration_m)
            | ~(np.asarray(normal_force_N, float) <= admissible_force_N))


def sample_eccentricity_max(samples: np.ndarray) -> float:
    """Largest |eccentricity| [m] of time-series samples (NaN if one is not finite, 0 without samples)."""
    if samples.shape[0] == 0:
        return 0.0
    e = np.hypot(samples[:, L.T_ECC_X], samples[:, L.T_ECC_Y])
    return float(e.max()) if np.all(np.isfinite(samples)) else math.nan


def covered(stats: np.ndarray) -> np.ndarray:
    """Rows (revolutions) the run reached (some time accounted)."""
    return stats[:, L.S_TIME] > 0.0


def counted_revolutions(stats: np.ndarray) -> np.ndarray:
    """Indices of the revolutions that cover more than half the longest one (a sliver row after the last
    revolution is dropped): the rows the run's comparable statistics are taken over."""
    return np.flatnonzero(stats[:, L.S_TIME] > 0.5 * stats[:, L.S_TIME].max())


def last_revolution(stats: np.ndarray) -> int:
    """Index of the last revolution that was simulated (complete or partial)."""
    rows = np.nonzero(covered(stats))[0]
    return int(rows[-1]) if rows.size else 0


def contact_fraction(rows: np.ndarray):
    """Share of time in contact of statistics rows (NaN for a row without time)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return rows[..., L.S_CONTACT_TIME] / rows[..., L.S_TIME]


def _padded(values, n: int) -> np.ndarray:
    out = np.full(n, np.nan)
    if values is not None:
        values = np.asarray(values, dtype=float)
        m = min(n, values.size)
        out[:m] = values[:m]
    return out


def chattering(stats: np.ndarray) -> np.ndarray:
    """Per statistics row: more contact onsets than CHATTER_IMPACTS_PER_REVOLUTION (bool)."""
    return stats[..., L.S_IMPACTS] > CHATTER_IMPACTS_PER_REVOLUTION


def revolution_table(stats: np.ndarray, wear_growth_m: np.ndarray, impact_events_per_revolution=None,
                     revolution_numbers=None) -> np.ndarray:
    """One row per revolution up to the last one simulated, columns REVOLUTION_COLUMNS (``revolution``: 0, 1, ...,
    or ``revolution_numbers``, the revolution each simulated one stands for in a wear study; ``max_wear_depth_m``: at
    the revolution's end, NaN where not reached; ``impact_events``: the ``events`` of
    :func:`revolution_impact_events`, NaN where not given; ``chattering``: 0/1)."""
    n = last_revolution(stats) + 1
    rows = stats[:n]
    numbers = np.arange(n) if revolution_numbers is None else _padded(revolution_numbers, n)
    return np.column_stack([numbers, rows[:, L.S_IMPACTS], contact_fraction(rows), rows[:, L.S_ACC_MAX],
                            rows[:, L.S_ACC_MIN], rows[:, L.S_FORCE_MAX], rows[:, L.S_ECC_MAX],
                            _padded(wear_growth_m, n), _padded(impact_events_per_revolution, n),
                            chattering(rows).astype(float)])


def _finite(x):
    return float(x) if math.isfinite(x) else None


def steady_revolutions(stats: np.ndarray, settling_revolutions: int = 1, left_out=()) -> tuple[int, np.ndarray]:
    """(the first revolution, a mask of the rows) the run's extremes are taken over: its counted revolutions
    (:func:`counted_revolutions`: a sliver after the last is not a revolution) after the first
    ``settling_revolutions`` (the start-up transient), or all its counted ones if it ends before they are over;
    without the rows ``left_out`` (a wear study's simulated revolutions before its last, the final state: a
    cycle jump deepens the groove at once under a pin that has not moved, and the impact rings for a revolution
    or two) unless nothing else is left."""
    rows = np.zeros(stats.shape[0], dtype=bool)
    rows[counted_revolutions(stats)] = True
    first = max(0, int(settling_revolutions))
    first = first if rows[first:].any() else 0
    steady = rows & (np.arange(stats.shape[0]) >= first)
    kept = steady.copy()
    kept[np.asarray(left_out, dtype=np.int64)] = False
    return first, kept if kept.any() else steady


def steady_samples(samples: np.ndarray, stats: np.ndarray, period_s: float, settling_revolutions: int = 1,
                   left_out=()) -> np.ndarray:
    """The samples (a mask) of the revolutions the run's extremes are taken over (:func:`steady_revolutions`)."""
    steady = np.flatnonzero(steady_revolutions(stats, settling_revolutions, left_out)[1])
    return np.isin(revolution_of(samples[:, L.T_TIME], period_s), steady)


def run_statistics(stats: np.ndarray, settling_revolutions: int = 1, left_out=()) -> dict:
    """The statistics of ``summary.json`` (docs/reference/results.md §6): of the last counted revolution (a sliver
    after it, a run of 1.02 revolutions, is none) the contact fraction, the impacts and the slider acceleration
    extremes (None if not finite); the max contact force and the max eccentricity over the counted revolutions
    after the first ``settling_revolutions`` (the start-up transient: the pin starts centred at full speed), which
    are reported apart under ``start_up``, and without the rows ``left_out`` (:func:`steady_revolutions`).  A run
    that has not passed them (it ends in revolution ``settling_revolutions`` or before) keeps its transient in the
    statistics (``statistics_from_revolution`` 0) and says so."""
    counted = counted_revolutions(stats)
    last_index = int(counted[-1]) if counted.size else 0
    last = stats[last_index]
    first, steady = steady_revolutions(stats, settling_revolutions, left_out)
    transient = covered(stats) & (np.arange(stats.shape[0]) < first)
    out = {
        "max_contact_force_N": float(stats[steady, L.S_FORCE_MAX].max()) if steady.any() else 0.0,
        "contact_fraction": float(contact_fraction(last)) if last[L.S_TIME] > 0 else 0.0,
        "impacts_per_revolution": int(last[L.S_IMPACTS]),
        "slider_acc_max_m_s2": _finite(last[L.S_ACC_MAX]),
        "slider_acc_min_m_s2": _finite(last[L.S_ACC_MIN]),
        "max_eccentricity_m": float(stats[steady, L.S_ECC_MAX].max()) if steady.any() else 0.0,
        "statistics_from_revolution": first,
    }
    if transient.any():
        out["start_up"] = {"revolutions": first, "max_contact_force_N": float(stats[transient, L.S_FORCE_MAX].max()),
                           "max_eccentricity_m": float(stats[transient, L.S_ECC_MAX].max()),
                           "slider_acc_max_m_s2": _finite(stats[transient, L.S_ACC_MAX].max()),
                           "slider_acc_min_m_s2": _finite(stats[transient, L.S_ACC_MIN].min())}
    elif settling_revolutions > 0:
        ends_in = int(np.flatnonzero(covered(stats))[-1]) if covered(stats).any() else 0
        out["start_up"] = (f"included: the run ends in revolution {ends_in}, before more than half of revolution "
                           f"{settling_revolutions} (the first after the {settling_revolutions} start-up "
                           "revolution(s)) is run")
    return out


WHIRL_SHARE = 0.05           # a run whose pin whirls for more of its time than this is in the whirl regime


def whirl_fraction(samples: np.ndarray) -> float:
    """Share of the sampled time [-] in which the pin whirls backward: contact spells (consecutive samples in
    contact) in which the contact point (the eccentricity's angle in the bushing frame) travels at least one
    full turn against the pin's spin relative to the bushing, as a pin rolling round the bushing does (at
    -omega_rel R_i / c); impacts and sliding contacts move it back and forth with the load.  The
    friction-driven backward whirl of docs/tutorials/own_mechanism.md.  The samples must resolve a whirl turn (a
    sample spacing well below 2 pi c / (omega_rel R_i)): a coarser one aliases the angle's unwrapping."""
    if samples.shape[0] < 2:
        return 0.0
    angle = np.unwrap(np.arctan2(samples[:, L.T_ECC_Y], samples[:, L.T_ECC_X]))
    dt = np.diff(samples[:, L.T_TIME])
    backward = -np.diff(angle) * np.sign(0.5 * (samples[1:, L.T_RELATIVE_OMEGA] + samples[:-1, L.T_RELATIVE_OMEGA]))
    contact = (samples[1:, L.T_CONTACT] > 0.5) & (samples[:-1, L.T_CONTACT] > 0.5)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], contact.astype(np.int8), [0]))))
    whirling = sum(dt[a:b].sum() for a, b in zip(edges[::2], edges[1::2]) if backward[a:b].sum() >= 2.0 * math.pi)
    total = dt.sum()
    return float(whirling / total) if total > 0.0 else 0.0


def regime(samples: np.ndarray) -> dict:
    """The run's regime: ``backward whirl`` where the pin whirls for more than WHIRL_SHARE of the time
    (:func:`whirl_fraction`), ``permanent contact`` where no sample leaves the contact (a load that never reverses),
    else ``impacting``; with the whirl fraction."""
    share = whirl_fraction(samples)
    if share > WHIRL_SHARE:
        return {"regime": "backward whirl", "whirl_fraction": share}
    permanent = samples.shape[0] > 0 and bool(np.all(samples[:, L.T_CONTACT] > 0.5))
    return {"regime": "permanent contact" if permanent else "impacting", "whirl_fraction": share}


def mean_revolution_statistics(stats: np.ndarray, period_s: float, samples: np.ndarray | None = None) -> dict:
    """Robust statistics of a run for comparing runs: impacts per revolution and contact
    fraction over all the time of the revolutions that cover more than half the longest one
    (a sliver row after the last revolution is dropped), the per-revolution extremes
    averaged over those revolutions and, from ``samples``, the mean eccentricity while in
    contact."""
    rows = stats[counted_revolutions(stats)]
    time_s = rows[:, L.S_TIME].sum()
    out = {
        "impacts_per_revolution": float(rows[:, L.S_IMPACTS].sum() / (time_s / period_s)),
        "contact_fraction": float(rows[:, L.S_CONTACT_TIME].sum() / time_s),
        "slider_acc_max_m_s2": float(rows[:, L.S_ACC_MAX].mean()),
        "slider_acc_min_m_s2": float(rows[:, L.S_ACC_MIN].mean()),
        "max_contact_force_N": float(rows[:, L.S_FORCE_MAX].mean()),
        "max_eccentricity_m": float(rows[:, L.S_ECC_MAX].mean()),
    }
    if samples is not None:
        contact = samples[:, L.T_CONTACT] > 0.5
        eccentricity = np.hypot(samples[contact, L.T_ECC_X], samples[contact, L.T_ECC_Y])
        out["mean_eccentricity_in_contact_m"] = float(eccentricity.mean()) if eccentricity.size else float("nan")
    return out


def sample_statistics(samples: np.ndarray) -> dict:
    """Statistics of a window of time-series samples (e.g. the revolution ending at a wear
    snapshot, which need not be one row of the statistics): slider acceleration extremes
    and the share of samples in contact (None without samples)."""
    acc = samples[:, L.T_SLIDER_A]
    return {"slider_acc_max_m_s2": float(acc.max()) if acc.size else None,
            "slider_acc_min_m_s2": float(acc.min()) if acc.size else None,
            "contact_fraction_samples": float(samples[:, L.T_CONTACT].mean()) if acc.size else None}


def window_differences(samples: np.ndarray, reference: np.ndarray, window_s: float, columns) -> np.ndarray:
    """``samples`` at their own times in [the reference's first sample, window_s] minus ``reference`` interpolated
    linearly there, one column per sample column in ``columns``.  A run is judged at the points it computed: a
    co-simulation's free-flight steps of up to 0.1 ms, interpolated instead, looked 9 N off on the press of
    docs/tutorials/own_mechanism.md where it is 0.34 N.  The reference should be recorded at every step (its own
    interpolation then stays far below the differences compared).  The window ends at the reference's last sample
    in it; a run that ends before that is refused."""
    times = samples[:, L.T_TIME]
    ref_times = reference[:, L.T_TIME]
    end = ref_times[ref_times <= window_s][-1]
    if times[-1] < end * (1.0 - 1e-9):
        raise ValueError(f"run ends at {times[-1]:.6g} s, before the window end {end:.6g} s")
    rows = np.flatnonzero((times <= end) & (times >= ref_times[0] * (1.0 - 1e-9)))
    return np.column_stack([samples[rows, c] - np.interp(times[rows], ref_times, reference[:, c]) for c in columns])


# ---------------------------------------------------------------- impact events
def slider_acc_deviation(time_s, slider_a_m_s2, mechanism) -> np.ndarray:
    """|a - a_ideal| [m/s^2] of the slider at times ``time_s`` [s], a_ideal the closed-form ideal slider-crank of the
    ``SliderCrankParameters`` ``mechanism`` (its crank is driven: the ideal kinematics do not depend on the loads)."""
    from .slider_crank import SliderCrank

    return np.abs(np.asarray(slider_a_m_s2) - SliderCrank(mechanism).closed_form(time_s)["slider_a_m_s2"])


def _impact_clusters(t: np.ndarray, slider_a_m_s2, mechanism, threshold_m_s2: float, merge_deg: float):
    """(clusters of sample indices, |a - a_ideal| [m/s^2]) of :func:`impact_events`."""
    deviation = slider_acc_deviation(t, slider_a_m_s2, mechanism)
    above = np.flatnonzero(deviation > threshold_m_s2)
    if above.size == 0:
        return [], deviation
    splits = np.flatnonzero(np.diff(t[above]) > merge_deg / 360.0 * mechanism.period_s) + 1
    return np.split(above, splits), deviation


def impact_events(time_s, slider_a_m_s2, mechanism, threshold_m_s2: float = IMPACT_EVENT_THRESHOLD_M_S2,
                  merge_deg: float = IMPACT_EVENT_MERGE_DEG) -> list[dict]:
    """Impact(-vibration) events seen in the slider acceleration: clusters of samples with
    |a - a_ideal| > threshold (a_ideal: the closed-form ideal slider-crank of the
    ``SliderCrankParameters`` ``mechanism``); clusters at most merge_deg of crank rotation apart
    merge.  (Not the contact onsets counted as ``impacts`` per revolution.)

    Returns one dict per event: start/end time [s], crank rotation since t = 0 at the peak [deg, 0..360),
    peak |a - a_ideal| [m/s^2].
    """
    t = np.asarray(time_s)
    clusters, deviation = _impact_clusters(t, slider_a_m_s2, mechanism, threshold_m_s2, merge_deg)
    events = []
    for cluster in clusters:
        peak = cluster[np.argmax(deviation[cluster])]
        events.append({"start_s": float(t[cluster[0]]), "end_s": float(t[cluster[-1]]),
                       "peak_crank_rotation_deg": float((t[peak] / mechanism.period_s * 360.0) % 360.0),
                       "peak_deviation_m_s2": float(deviation[peak])})
    return events


def crank_angle_deg(theta1_rad) -> np.ndarray:
    """The crank angle theta1 (layout.T_CRANK_ANGLE, theta0 - omega t, unwrapped) [rad] as [deg] in [0, 360)."""
    deg = np.degrees(np.asarray(theta1_rad, dtype=float)) % 360.0
    return np.where(deg >= 360.0, 0.0, deg)       # -1e-17 % 360 rounds to 360


def revolution_of(t, period_s: float):
    """Revolution index of time(s) t [s], as the per-revolution statistics assign an accepted point."""
    return (np.asarray(t, dtype=float) / period_s * (1.0 - 1e-14)).astype(np.int64)


def sample_durations(t) -> np.ndarray:
    """The time [s] each sample at the times t [s] stands for: half the spacing to each neighbour (the ends: to their
    one).  A run samples at its steps where they are longer than the sample spacing (free flight) and at that spacing
    elsewhere: a mean over the samples weighted by these is a mean over time, not over the steps."""
    t = np.asarray(t, dtype=float)
    if t.size < 2:
        return np.ones(t.size)
    gaps = np.diff(t)
    out = np.empty(t.size)
    out[0], out[-1] = 0.5 * gaps[0], 0.5 * gaps[-1]
    out[1:-1] = 0.5 * (gaps[:-1] + gaps[1:])
    return out


def time_rms(values, durations) -> float:
    """The root mean square of ``values`` over time, each standing for its ``durations`` [s]
    (:func:`sample_durations`)."""
    values, durations = np.asarray(values, dtype=float), np.asarray(durations, dtype=float)
    total = float(durations.sum())
    if total <= 0.0:
        return math.sqrt(float(np.mean(values ** 2)))
    return math.sqrt(float((durations * values ** 2).sum()) / total)


def _sampled_revolutions(t: np.ndarray, n: int, period_s: float) -> tuple[np.ndarray, float]:
    """Which of revolutions 0..n-1 the sample times t [s] cover end to end (first and last sample, and every
    gap, within max(1 deg of crank rotation, 1.5 median spacings)), and the largest spacing in those [s]."""
    sampled = np.zeros(n, dtype=bool)
    if t.size < 2:
        return sampled, math.nan
    tol = max(period_s / IMPACT_EVENT_SAMPLES_PER_REVOLUTION, 1.5 * float(np.median(np.diff(t))))
    widest = 0.0
    for k in range(n):
        a, b = np.searchsorted(t, [k * period_s - tol, (k + 1) * period_s + tol])
        window = t[a:b]
        if window.size < 2 or window[0] > k * period_s + tol or window[-1] < (k + 1) * period_s - tol:
            continue
        gap = float(np.diff(window).max())
        if gap <= tol:
            sampled[k] = True
            widest = max(widest, gap)
    return sampled, (widest if sampled.any() else math.nan)


def revolution_impact_events(samples: np.ndarray, stats: np.ndarray, mechanism,
                             threshold_m_s2: float = IMPACT_EVENT_THRESHOLD_M_S2,
                             merge_deg: float = IMPACT_EVENT_MERGE_DEG) -> dict:
    """Impact-vibration events per revolution (revolutions 0 .. :func:`last_revolution` of ``stats``):
    :func:`impact_events` of the samples (layout.T_*), each counted in the revolution in which its peak
    sample falls.  Returns ``events`` (count per revolution, NaN where the samples do not cover the
    revolution end to end), ``angles_deg`` (per revolution, the crank angle theta1 at each event's peak
    [deg, 0..360), :func:`crank_angle_deg`), ``chattering`` (bool, :func:`chattering`), ``sampled`` (bool)
    ``sample_interval_s`` (the largest sample spacing in the sampled revolutions [s], NaN if none),
    ``contact_sample_spacing_s`` (the median spacing after a sample in contact, where the bursts are: free flight's
    long steps left out; NaN without contact), and the ``threshold_m_s2`` and ``merge_deg`` it used."""
    n = last_revolution(stats) + 1
    period = mechanism.period_s
    t = np.asarray(samples[:, L.T_TIME], dtype=float)
    sampled, interval = _sampled_revolutions(t, n, period)
    clusters, deviation = _impact_clusters(t, samples[:, L.T_SLIDER_A], mechanism, threshold_m_s2, merge_deg)
    angles = [[] for _ in range(n)]
    for cluster in clusters:
        peak = cluster[np.argmax(deviation[cluster])]
        # a peak on a revolution's boundary (to rounding) is the next revolution's, whose start (theta1 = 0) it is: a
        # run that ended as a burst began had counted it in its last revolution, beside that revolution's own start
        k = int(t[peak] / period * (1.0 + 1e-12))
        if 0 <= k < n:
            angles[k].append(float(crank_angle_deg(samples[peak, L.T_CRANK_ANGLE])))
    events = np.array([len(a) for a in angles], dtype=float)
    events[~sampled] = np.nan
    gaps = np.diff(t)[samples[:-1, L.T_CONTACT] > 0.5]
    return {"events": events, "angles_deg": angles, "chattering": chattering(stats[:n]), "sampled": sampled,
            "sample_interval_s": interval, "contact_sample_spacing_s": float(np.median(gaps)) if gaps.size else math.nan,
            "threshold_m_s2": threshold_m_s2, "merge_deg": merge_deg}


def impact_event_statistics(per: dict, mechanism, settling_revolutions: int = 1) -> dict:
    """summary.json's impact-vibration statistics (docs/reference/results.md §6) from ``per``, the run's
    :func:`revolution_impact_events`, over the counted revolutions: those the samples cover end to end after the
    start-up revolutions that
    :func:`run_statistics` leaves out (all sampled revolutions if none of those is left, e.g. a one-revolution
    run).  ``impact_events_per_revolution`` (mean), ``impact_event_crank_angles_deg`` (every counted event's
    peak crank angle [deg]), ``chattering_revolution_share``, ``impact_event_revolutions`` (the counted
    revolutions) and ``impact_event_definition``; None without a counted revolution."""
    n = per["events"].size
    first = max(0, int(settling_revolutions))
    counted = np.flatnonzero(per["sampled"] & (np.arange(n) >= first))
    notes = []
    if counted.size == 0 and per["sampled"].any():
        counted = np.flatnonzero(per["sampled"])
        notes.append("the start-up revolution(s) included: no later revolution is sampled end to end")
    interval_deg = per["sample_interval_s"] / mechanism.period_s * 360.0
    if interval_deg > 360.0 / IMPACT_EVENT_SAMPLES_PER_REVOLUTION:
        notes.append(f"samples up to {interval_deg:.3g} deg apart, coarser than 1/"
                     f"{IMPACT_EVENT_SAMPLES_PER_REVOLUTION} revolution: events may merge or be missed and their "
                     "angles are as coarse")
    elif per.get("contact_sample_spacing_s", math.nan) > IMPACT_EVENT_MAX_SAMPLE_S:
        notes.append(f"samples in contact {per['contact_sample_spacing_s']:.3g} s apart (median), coarser than "
                     f"{IMPACT_EVENT_MAX_SAMPLE_S:g} s: an impact's burst falls between them, so events split, "
                     "merge or are missed (the count moves with --sample-dt) and the largest |a - a_ideal| is low")
    if counted.size == 0:
        notes.append("no revolution is sampled end to end: no statistic")
    threshold_m_s2, merge_deg = per["threshold_m_s2"], per["merge_deg"]
    definition = (f"impact-vibration event: a cluster of time-series samples with |a_slider - a_ideal| > "
                  f"{threshold_m_s2:g} m/s^2 (a_ideal: the ideal slider-crank at the same time), clusters at most "
                  f"{merge_deg:g} deg of crank rotation apart merged; counted in the revolution of its peak sample, "
                  "its angle the crank angle theta1 there (deg, 0..360); a chattering revolution has more than "
                  f"{CHATTER_IMPACTS_PER_REVOLUTION} contact onsets (impacts); means over the revolutions after the "
                  "start-up that the samples cover end to end" + "".join(f"; {note}" for note in notes))
    return {"impact_events_per_revolution": float(per["events"][counted].mean()) if counted.size else None,
            "impact_event_crank_angles_deg": [a for k in counted for a in per["angles_deg"][k]],
            "chattering_revolution_share": float(per["chattering"][counted].mean()) if counted.size else None,
            "impact_event_revolutions": [int(k) for k in counted],
            "impact_event_definition": definition}


def revolution_statistics(record) -> dict:
    """:func:`mean_revolution_statistics` of a run record (with the mean eccentricity in contact)."""
    return mean_revolution_statistics(record.revolution_stats, record.period_s, record.samples)


def ensemble_mean_std(rows: list) -> tuple[dict, dict]:
    """(mean, sample standard deviation; 0 for one row) over rows of {name: value} of each name; None for a
    name that some row lacks (None), nan where a value is nan."""
    mean, std = {}, {}
    for name in rows[0]:
        values = [row[name] for row in rows]
        if None in values:
            mean[name] = std[name] = None
            continue
        v = np.array(values, dtype=float)
        with np.errstate(invalid="ignore"):    # a run without contact has no mean eccentricity in contact (nan)
            mean[name], std[name] = float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0
    return mean, std


def ensemble_statistics(records) -> tuple[dict, dict]:
    """(mean, sample standard deviation) over an ensemble's run records of each
    :func:`revolution_statistics` quantity."""
    return ensemble_mean_std([revolution_statistics(r) for r in records])


def revolution_row(stats: np.ndarray, revolution: int) -> dict:
    """Row ``revolution`` of :func:`revolution_table` (revolutions.csv's row with that ``revolution``) as
    {column: value} (NaN as None), or {} when the run has not reached it; e.g. a wear-study snapshot's
    slider acceleration extremes, so that a snapshot and revolutions.csv state the same numbers."""
    if not 0 <= revolution < stats.shape[0] or not covered(stats)[revolution]:
        return {}
    row = revolution_table(stats[:revolution + 1], np.zeros(0))[revolution]
    return {name: (_finite(value) if name != "revolution" else int(value)) for name, value in
            zip(REVOLUTION_COLUMNS, row) if name not in ("max_wear_depth_m", "impact_events")}
