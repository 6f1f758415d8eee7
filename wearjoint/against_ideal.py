"""A run against the ideal joint: the designer's first answers (docs/reference/results.md §6).

The slider's acceleration error |a - a_ideal| (:func:`wearjoint.analysis.slider_acc_deviation`; its RMS over time,
:func:`wearjoint.analysis.time_rms`) and the ideal joint's reaction with the same gravity and slider load
(:meth:`wearjoint.slider_crank.SliderCrank.ideal_joint_force`), per revolution and over the revolutions the run's
extremes are taken over (:func:`wearjoint.analysis.steady_revolutions`, as ``max_contact_force_N``).  Both are taken
at every sample once (:func:`sample_comparison`) and shared by revolutions.csv and summary.json.
"""
from __future__ import annotations

import math

import numpy as np

from .analysis import last_revolution, revolution_of, sample_durations, slider_acc_deviation, steady_samples, time_rms
from .core import layout as L

# revolutions.csv's columns of this module, after wearjoint.analysis.REVOLUTION_COLUMNS
REVOLUTION_COLUMNS = ("slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "ideal_joint_force_max_N")
SUMMARY_KEYS = ("slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "ideal_joint_force_max_N",
                "joint_force_over_ideal")


def sample_comparison(samples: np.ndarray, mechanism) -> tuple[np.ndarray, np.ndarray]:
    """(|a - a_ideal| [m/s^2], the ideal joint's reaction [N]) at every sample (layout.T_*)."""
    from .slider_crank import SliderCrank

    t = samples[:, L.T_TIME]
    return slider_acc_deviation(t, samples[:, L.T_SLIDER_A], mechanism), SliderCrank(mechanism).ideal_joint_force(t)



def slider_acc_error_max(record) -> float:
    """Largest |a - a_ideal| [m/s^2] of a run record's slider over the samples summary.json's
    ``slider_acc_error_max_m_s2`` is taken over, NaN without any."""
    inside = steady_samples(record.samples, record.revolution_stats, record.period_s, record.settling_revolutions,
                            record.left_out_rows)
    if not inside.any():
        return math.nan
    samples = record.samples[inside]
    return float(slider_acc_deviation(samples[:, L.T_TIME], samples[:, L.T_SLIDER_A],
                                      record.parameters.mechanism).max())


def revolution_columns(samples: np.ndarray, stats: np.ndarray, mechanism, comparison=None) -> np.ndarray:
    """Per revolution 0 .. last (rows), :data:`REVOLUTION_COLUMNS`: the largest and the RMS |a - a_ideal| of the
    samples in it and the ideal joint's largest reaction at those times [N]; NaN where a revolution has fewer than two
    samples (a wear study's last revolution starts with the previous one's last point: one sample is no statistic of
    it) (``comparison``: :func:`sample_comparison` of ``samples`` where the caller has it)."""
    n = last_revolution(stats) + 1
    out = np.full((n, len(REVOLUTION_COLUMNS)), np.nan)
    if samples.shape[0] == 0:
        return out
    error, ideal = comparison if comparison is not None else sample_comparison(samples, mechanism)
    revolution = revolution_of(samples[:, L.T_TIME], mechanism.period_s)
    durations = sample_durations(samples[:, L.T_TIME])
    for k in range(n):
        rows = revolution == k
        if np.count_nonzero(rows) > 1:
            out[k] = (error[rows].max(), time_rms(error[rows], durations[rows]), ideal[rows].max())
    return out


def summary_statistics(samples: np.ndarray, stats: np.ndarray, mechanism, settling_revolutions: int,
                       max_contact_force_N, comparison=None, left_out=()) -> dict:
    """summary.json's answers over the samples of the revolutions ``max_contact_force_N`` is taken over
    (:func:`wearjoint.analysis.steady_samples`: after the start-up, without the rows ``left_out``):
    :data:`SUMMARY_KEYS`, ``joint_force_over_ideal`` being ``max_contact_force_N`` over the ideal's largest; None
    without samples (``comparison``: as :func:`revolution_columns`)."""
    inside = steady_samples(samples, stats, mechanism.period_s, settling_revolutions, left_out)
    if not inside.any():
        return dict.fromkeys(SUMMARY_KEYS)
    error, ideal = comparison if comparison is not None else sample_comparison(samples, mechanism)
    durations = sample_durations(samples[:, L.T_TIME])[inside]
    error, largest = error[inside], float(ideal[inside].max())
    return {"slider_acc_error_max_m_s2": float(error.max()),
            "slider_acc_error_rms_m_s2": time_rms(error, durations),
            "ideal_joint_force_max_N": largest,
            "joint_force_over_ideal": (max_contact_force_N / largest if max_contact_force_N is not None
                                       and largest > 0.0 else None)}
