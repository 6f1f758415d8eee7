"""A run against the ideal joint: the designer's first answers (docs/model.md §6).

The slider's acceleration error |a - a_ideal| (a_ideal: the closed-form ideal slider-crank at the sample times; the
crank is driven, so the ideal kinematics do not depend on the loads) and the ideal crank-rod revolute's reaction
with the same gravity and slider load (:meth:`wearjoint.mechanism.SliderCrank.ideal_joint_force`), per revolution
and over the run's counted revolutions (after the start-up, as :func:`wearjoint.analysis.run_statistics` counts).
"""
from __future__ import annotations

import math

import numpy as np

from .analysis import counted_revolutions, last_revolution, revolution_of
from .core import layout as L

# revolutions.csv's columns of this module, after wearjoint.analysis.REVOLUTION_COLUMNS
REVOLUTION_COLUMNS = ("slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "ideal_joint_force_max_N")


def _acc_error(samples: np.ndarray, mechanism) -> np.ndarray:
    """|a - a_ideal| [m/s^2] of the slider at every sample."""
    from .mechanism import SliderCrank

    t = samples[:, L.T_TIME]
    return np.abs(samples[:, L.T_SLIDER_A] - SliderCrank(mechanism).closed_form(t)["slider_a_m_s2"])


def slider_acc_error_max(record) -> float:
    """Largest |a - a_ideal| [m/s^2] of a run record's slider: summary.json's ``slider_acc_error_max_m_s2``
    (:func:`summary_statistics`), NaN without samples in its counted revolutions."""
    value = summary_statistics(record.samples, record.revolution_stats, record.parameters.mechanism,
                               record.settling_revolutions, None)["slider_acc_error_max_m_s2"]
    return math.nan if value is None else value


def revolution_columns(samples: np.ndarray, stats: np.ndarray, mechanism) -> np.ndarray:
    """Per revolution 0 .. last (rows), :data:`REVOLUTION_COLUMNS`: the largest and the RMS |a - a_ideal| of the
    samples in it and the ideal joint's largest reaction at those times [N]; NaN where a revolution has no sample."""
    from .mechanism import SliderCrank

    n = last_revolution(stats) + 1
    out = np.full((n, len(REVOLUTION_COLUMNS)), np.nan)
    if samples.shape[0] == 0:
        return out
    t = samples[:, L.T_TIME]
    revolution = revolution_of(t, mechanism.period_s)
    error = _acc_error(samples, mechanism)
    ideal = SliderCrank(mechanism).ideal_joint_force(t)
    for k in range(n):
        rows = revolution == k
        if rows.any():
            out[k] = (error[rows].max(), math.sqrt(float(np.mean(error[rows] ** 2))), ideal[rows].max())
    return out


def summary_statistics(samples: np.ndarray, stats: np.ndarray, mechanism, settling_revolutions: int,
                       max_contact_force_N) -> dict:
    """summary.json's answers over the samples of the counted revolutions after the start-up (all counted ones
    where none is left): ``slider_acc_error_max_m_s2``, ``slider_acc_error_rms_m_s2``, ``ideal_joint_force_max_N``
    and ``joint_force_over_ideal`` (``max_contact_force_N`` over it); None without samples."""
    from .mechanism import SliderCrank

    counted = counted_revolutions(stats)
    after = counted[counted >= settling_revolutions]
    t = samples[:, L.T_TIME]
    inside = np.isin(revolution_of(t, mechanism.period_s), after if after.size else counted)
    if not inside.any():
        return dict.fromkeys(("slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "ideal_joint_force_max_N",
                              "joint_force_over_ideal"))
    error = _acc_error(samples[inside], mechanism)
    ideal = float(SliderCrank(mechanism).ideal_joint_force(t[inside]).max())
    return {"slider_acc_error_max_m_s2": float(error.max()),
            "slider_acc_error_rms_m_s2": math.sqrt(float(np.mean(error ** 2))),
            "ideal_joint_force_max_N": ideal,
            "joint_force_over_ideal": (max_contact_force_N / ideal if max_contact_force_N is not None and ideal > 0.0
                                       else None)}
