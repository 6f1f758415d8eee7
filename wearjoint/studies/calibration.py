"""Fit the wear coefficient to measured (revolutions, max depth) points (docs/wear_study.md, "The experiment").

The model's depth depends on k_w and the revolutions N through k_w N only (the dynamics follow the
profile, which the product k_w N sets), so one wear study at k_0 gives the master curve D_0 and the
depth at any k_w is d(N; k_w) = D_0(N k_w / k_0).  The fit needs no further simulation:

* **one k_w** (``archard``): least squares of ln d_i - ln D_0(s N_i) over s = k_w / k_0; the standard
  error of ln s from the residuals and the local growth exponents p_i = dln D_0 / dln x (n - 1 degrees
  of freedom, Student's t), the residuals per point, and whether they stay within ``tolerance``;
* **mild-to-severe** (``mild-severe``, Rodriguez et al. 2007): k_mild until the max depth reaches the
  transition depth d_t (given, not fitted), k_severe beyond, on the same master curve: two parameters,
  determined exactly by two points (no degrees of freedom left: no interval).
"""
from __future__ import annotations

import math

import numpy as np
from scipy import optimize, stats

from wearjoint.parameters import ParameterError


def master_curve(growth: np.ndarray):
    """(D_0, D_0^-1) from a study's wear_growth.csv rows (revolutions, max depth, ...): linear interpolation,
    0 at revolution 0."""
    r = np.r_[0.0, growth[:, 0]]
    d = np.maximum.accumulate(np.r_[0.0, growth[:, 1]])
    return (lambda x: np.interp(x, r, d, right=np.nan)), (lambda depth: np.interp(depth, d, r, right=np.nan))


def _check_points(points, reach: float, depth_reach: float) -> tuple[np.ndarray, np.ndarray]:
    n = np.array([p[0] for p in points], float)
    d = np.array([p[1] for p in points], float)
    if n.size == 0 or not (np.all(np.isfinite(n)) and np.all(n > 0) and np.all(np.isfinite(d)) and np.all(d > 0)):
        raise ParameterError(f"points={list(points)!r} are invalid: allowed REVOLUTIONS:DEPTH_M pairs, both > 0")
    if d.max() > depth_reach:
        raise ParameterError(f"points: the deepest, {d.max():g} m, is beyond the study's max depth {depth_reach:g} m "
                             f"(after {reach:g} revolutions): run the study further or with a larger k_w")
    return n, d


def fit_archard(growth: np.ndarray, k0: float, points, tolerance: float = 0.1, confidence: float = 0.95) -> dict:
    """One k_w for all ``points`` [(revolutions, max depth [m])], on the study ``growth`` run at k0 [m^2/N]."""
    curve, inverse = master_curve(growth)
    n, d = _check_points(points, growth[-1, 0], growth[-1, 1])

    def residuals(log_s):
        return np.log(curve(math.exp(log_s) * n)) - np.log(d)

    start = np.log(inverse(d) / n)                       # each point's own exact s
    lo, hi = start.min() - 1e-9, start.max() + 1e-9
    best = optimize.minimize_scalar(lambda x: float(np.sum(residuals(x) ** 2)), bounds=(lo, hi), method="bounded",
                                    options={"xatol": 1e-10})
    log_s = float(best.x)
    res = residuals(log_s)
    x = math.exp(log_s) * n
    exponents = np.array([_local_exponent(curve, xi, growth[-1, 0]) for xi in x])
    dof = n.size - 1
    if dof > 0 and np.any(exponents > 0):
        sigma = math.sqrt(float(np.sum(res ** 2)) / dof)
        se = sigma / math.sqrt(float(np.sum(exponents ** 2)))
        half = stats.t.ppf(0.5 + confidence / 2, dof) * se
        interval = [k0 * math.exp(log_s - half), k0 * math.exp(log_s + half)]
    else:
        se, interval = None, None
    return {"law": "archard", "wear_coefficient_m2_N": k0 * math.exp(log_s), "standard_error_log": se,
            "confidence": confidence, "interval_m2_N": interval, "degrees_of_freedom": dof,
            "residuals_rel": [float(math.expm1(r)) for r in res], "tolerance_rel": tolerance,
            "fits": bool(np.all(np.abs(np.expm1(res)) <= tolerance)),
            "each_point_alone_m2_N": [float(k0 * math.exp(s)) for s in start],
            "local_growth_exponents": exponents.tolist()}


def _local_exponent(curve, x: float, reach: float) -> float:
    """dln D_0 / dln x at x, by a central difference of 10 % (one-sided at the study's end)."""
    a, b = x / 1.1, min(x * 1.1, reach)
    return float(math.log(curve(b) / curve(a)) / math.log(b / a))


def predicted_depth(growth: np.ndarray, k0: float, revolutions: np.ndarray, fit: dict) -> np.ndarray:
    """The max depth [m] after ``revolutions`` under a fit of :func:`fit_archard` or :func:`fit_mild_severe`
    (nan beyond the study's reach)."""
    curve, inverse = master_curve(growth)
    n = np.asarray(revolutions, float)
    if fit["law"] == "archard":
        return curve(n * fit["wear_coefficient_m2_N"] / k0)
    k_mild, k_severe = fit["mild_wear_coefficient_m2_N"] / k0, fit["severe_wear_coefficient_m2_N"] / k0
    x_t = float(inverse(fit["transition_depth_m"]))
    n_t = x_t / k_mild
    return curve(np.where(n <= n_t, k_mild * n, x_t + k_severe * (n - n_t)))


def plot_calibration(growth: np.ndarray, k0: float, points, fits: list, path) -> None:
    """The fitted laws' max depth against revolutions with the measured points."""
    from wearjoint.plots import plt, save_figure

    n_max = max(p[0] for p in points) * 1.1
    n = np.linspace(0.0, n_max, 400)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for fit in fits:
        label = (f"one k_w = {fit['wear_coefficient_m2_N']:.3g} m²/N" if fit["law"] == "archard" else
                 f"mild {fit['mild_wear_coefficient_m2_N']:.3g} → severe {fit['severe_wear_coefficient_m2_N']:.3g} "
                 f"m²/N at {fit['transition_depth_m'] * 1e3:.3g} mm")
        ax.plot(n, predicted_depth(growth, k0, n, fit) * 1e3, "-", label=label)
    ax.plot([p[0] for p in points], [p[1] * 1e3 for p in points], "ko", label="measured")
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [mm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, path)


def fit_mild_severe(growth: np.ndarray, k0: float, points, transition_depth_m: float) -> dict:
    """k_mild up to ``transition_depth_m`` of max depth, k_severe beyond; exact for two points, least squares
    for more."""
    curve, inverse = master_curve(growth)
    n, d = _check_points(points, growth[-1, 0], growth[-1, 1])
    if not (math.isfinite(transition_depth_m) and 0.0 < transition_depth_m < growth[-1, 1]):
        raise ParameterError(f"transition_depth_m={transition_depth_m!r} is invalid: allowed in (0, "
                             f"{growth[-1, 1]:g}) m (the study's max depth)")
    if n.size < 2:
        raise ParameterError("points: the mild-to-severe law needs at least two points")
    x_t = float(inverse(transition_depth_m))

    def predicted(params):
        k_mild, k_severe = np.exp(params)
        n_t = x_t / k_mild
        x = np.where(n <= n_t, k_mild * n, x_t + k_severe * (n - n_t))
        return curve(x)

    guess = np.log(inverse(d) / n)
    try:
        fit = optimize.least_squares(lambda p: np.log(predicted(p)) - np.log(d), x0=[guess.min(), guess.max()])
    except ValueError:                               # a trial law ran past the study's curve: nan residuals
        raise ParameterError(f"points: the mild-to-severe fit needs the study's curve beyond its {growth[-1, 0]:g} "
                             "revolutions: run the study further or with a larger k_w") from None
    k_mild, k_severe = np.exp(fit.x)
    res = np.log(predicted(fit.x)) - np.log(d)
    return {"law": "mild-severe", "transition_depth_m": transition_depth_m,
            "mild_wear_coefficient_m2_N": float(k0 * k_mild), "severe_wear_coefficient_m2_N": float(k0 * k_severe),
            "transition_revolutions": float(x_t / k_mild), "parameters_fitted": 2,
            "degrees_of_freedom": int(n.size - 2), "residuals_rel": [float(math.expm1(r)) for r in res]}


__all__ = ["master_curve", "fit_archard", "fit_mild_severe", "predicted_depth", "plot_calibration"]
