"""Fit the wear coefficient to measured (revolutions, max depth) points (docs/explanation/wear_study.md, "The experiment").

The model's depth depends on k_w and the revolutions N through k_w N only (the dynamics follow the
profile, which the product k_w N sets), so one wear study at k_0 gives the master curve D_0 and the
depth at any k_w is d(N; k_w) = D_0(N k_w / k_0).  The fit needs no further simulation:

* **one k_w** (``archard``): with the depths' measurement uncertainties, the likelihood of Gaussian depth
  errors over s = k_w / k_0 (:func:`fit_archard`): the model's chi-square test and a profile-likelihood
  interval; predictions and the revolutions to a depth limit with their bands (:func:`predictions`,
  :func:`life`); without uncertainties, least squares of the log depths and no interval;
* **mild-to-severe** (``mild-severe``, Rodriguez et al. 2007): k_mild until the max depth reaches the
  transition depth d_t (given, not fitted), k_severe beyond, on the same master curve: two parameters,
  determined exactly by two points (no degrees of freedom left: no interval).
"""
from __future__ import annotations

import math

import numpy as np
from scipy import optimize, stats

from wearjoint.checks import ParameterError, positive, require
from wearjoint.joint_fields import largest_value

# the ranges of a measured point: revolutions up to a trillion (190 years at 10,000 rpm, beyond any machine's life;
# 1e300 fitted a k_w of 1e-309 and called it a fit), a max depth from a nanometre (a few atomic layers: the least wear
# Archard's continuum law describes; 1e-300 fitted 5e-305), a depth uncertainty from a picometre (finer than any depth
# measurement; 1e-300 squared to 0 and made chi^2 NaN) to the bushing radius (no depth is larger; 1e300 overflowed)
MAX_POINT_REVOLUTIONS = 1e12
MIN_DEPTH_M = 1e-9
MIN_DEPTH_UNCERTAINTY_M = 1e-12
# the largest bushing radius a joint admits [m]: the bound where the study's own radius is not known
MAX_BUSHING_RADIUS_M = largest_value("bushing_radius_m")
# what reaches beyond a study's curve: a study's --resume continues it to its own --revolutions only
FURTHER = ("a new wear study with more --revolutions (or a larger --wear-coefficient-m2-N) into another --out "
           "reaches further (--resume continues a study to its own --revolutions only)")


def master_curve(growth: np.ndarray):
    """(D_0, D_0^-1) from a study's wear_growth.csv rows (revolutions, max depth, ...): linear interpolation,
    0 at revolution 0."""
    r = np.r_[0.0, growth[:, 0]]
    d = np.maximum.accumulate(np.r_[0.0, growth[:, 1]])
    return (lambda x: np.interp(x, r, d, right=np.nan)), (lambda depth: np.interp(depth, d, r, right=np.nan))


def uncertainty_range(bushing_radius_m: float | None = None) -> tuple[float, float, str]:
    """(least, largest, the range as a message states it) of a depth uncertainty [m] on a bushing of
    ``bushing_radius_m`` (None: the largest a joint admits)."""
    top, why = ((MAX_BUSHING_RADIUS_M, "the largest bushing radius a joint admits") if bushing_radius_m is None
                else (bushing_radius_m, "the bushing radius: no depth is larger"))
    return MIN_DEPTH_UNCERTAINTY_M, top, (f"from {MIN_DEPTH_UNCERTAINTY_M:g} m (finer than any depth measurement) to "
                                          f"{top:g} m ({why})")


def _check_points(points, reach: float, depth_reach: float,
                  bushing_radius_m: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(revolutions, depths [m], uncertainties [m]: NaN where not given) of ``points``, checked (their uncertainties
    against :func:`uncertainty_range`)."""
    n = np.array([p[0] for p in points], float)
    d = np.array([p[1] for p in points], float)
    u = np.array([p[2] if len(p) > 2 and p[2] is not None else math.nan for p in points], float)
    if n.size == 0 or not (np.all(np.isfinite(n)) and np.all(n > 0) and np.all(np.isfinite(d)) and np.all(d > 0)):
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed REVOLUTIONS:DEPTH_M pairs, "
                             "both finite and > 0")
    if not (np.all(n <= MAX_POINT_REVOLUTIONS) and np.all(d >= MIN_DEPTH_M)):
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed revolutions up to "
                             f"{MAX_POINT_REVOLUTIONS:g} (beyond any machine's life) and max depths from {MIN_DEPTH_M:g} "
                             "m (a few atomic layers: the least wear Archard's law describes)")
    given = ~np.isnan(u)
    if given.any() and not (given.all() and np.all(np.isfinite(u)) and np.all(u > 0)):
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed a finite depth uncertainty > 0 "
                             "for every point or for none (--depth-uncertainty-m U, or REVOLUTIONS:DEPTH_M:U)")
    least, most, text = uncertainty_range(bushing_radius_m)
    if given.any() and not (np.all(u >= least) and np.all(u <= most)):
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed depth uncertainties {text}")
    if d.max() > depth_reach:
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed max depths up to the "
                             f"study's, {depth_reach:g} m after {reach:g} revolutions; the deepest, {d.max():g} m, is "
                             f"beyond the study's max depth: {FURTHER}")
    return n, d, u


def falling_depths(points) -> str:
    """'' where the measured max depths never fall as the revolutions grow (beyond twice their combined
    uncertainty, where given), else what falls: a max depth cannot (different parts, or a mix-up)."""
    rows = sorted((p[0], p[1], p[2] if len(p) > 2 and p[2] else 0.0) for p in points)
    for (n1, d1, u1), (n2, d2, u2) in zip(rows, rows[1:]):
        if d2 < d1 - 2.0 * math.hypot(u1, u2):
            return (f"the measured max depth falls from {d1:g} m at {n1:g} revolutions to {d2:g} m at {n2:g}: a max "
                    "depth never falls as a bushing wears (other parts? a mix-up of the points?)")
    return ""


def check_tolerance(tolerance) -> float:
    """``tolerance`` where it is a share in (0, 1) of a depth, else the ParameterError naming it: from 1 on, every
    model depth below the measured one (a residual above -100 %) would count as a fit."""
    positive("tolerance", tolerance)
    require("tolerance", tolerance, tolerance < 1.0, "a share of each measured depth below 1 (from 1 on, every depth "
                                                    "below it fits)")
    return float(tolerance)


CONFIDENCE = 0.95   # of the model's test (rejected below 1 - CONFIDENCE) and of interval_95_m2_N
DEFAULT_TOLERANCE = 0.1   # without depth uncertainties: the share of each depth within which the residuals fit
ONE_POINT = ("one measured point: k_w matches it exactly, its interval from the point's uncertainty alone; no test "
             "of the model (that needs two points or more)")


def fit_archard(growth: np.ndarray, k0: float, points, tolerance: float = DEFAULT_TOLERANCE,
                curve_error_rel: float = 0.0, bushing_radius_m: float | None = None) -> dict:
    """One k_w for all ``points`` [(revolutions, max depth [m][, its standard uncertainty [m]])], on the study
    ``growth`` run at k0 [m^2/N].

    With uncertainties U_i: the likelihood of Gaussian depth errors, chi^2(s) = r^T C^-1 r with r_i = D_0(s N_i) -
    d_i and the covariance C_ij = U_i^2 delta_ij + c^2 D_0(s N_i) D_0(s N_j), c = ``curve_error_rel`` (the study's
    estimate of its curve's error: one error of the whole curve, common to every point, so that many points do
    not average it away; C^-1 by Sherman-Morrison); the model's test chi^2_min against n - 1 degrees of freedom
    (``consistent``: p >= 1 - CONFIDENCE); the interval where chi^2 - chi^2_min <= chi^2_1(CONFIDENCE) (profile
    likelihood: coverage for Gaussian errors, shrinking with U to the curve's own error), none where the model
    is rejected.  Without uncertainties the least squares of the log depths gives k_w alone: neither a test nor
    an interval (the residuals' misfit is no measurement error).  ``fits``: the test's verdict with uncertainties,
    else every residual within ``tolerance`` (< 1) of its depth.  ``bushing_radius_m``: the study's, the largest
    uncertainty (None: the largest radius a joint admits)."""
    curve, inverse = master_curve(growth)
    n, d, u = _check_points(points, growth[-1, 0], growth[-1, 1], bushing_radius_m)
    check_tolerance(tolerance)
    start = np.log(inverse(d) / n)                       # each point's own exact s
    out = {"law": "archard", "confidence": CONFIDENCE, "degrees_of_freedom": int(n.size - 1),
           "tolerance_rel": tolerance, "each_point_alone_m2_N": [float(k0 * math.exp(x)) for x in start]}
    top = math.log(growth[-1, 0] / n.max()) - 1e-9       # the largest s the study's curve reaches at every point

    def log_residuals(log_s):
        return np.log(curve(math.exp(log_s) * n)) - np.log(d)

    if not np.isfinite(u).all():
        best = optimize.minimize_scalar(lambda x: float(np.sum(log_residuals(x) ** 2)),
                                        bounds=(start.min() - 1e-9, start.max() + 1e-9), method="bounded",
                                        options={"xatol": 1e-10})
        log_s = float(best.x)
        out.update(wear_coefficient_m2_N=k0 * math.exp(log_s), interval_95_m2_N=None, chi2=None, p_value=None,
                   consistent=None, note="no depth uncertainty given (--depth-uncertainty-m): k_w without an "
                                         "interval or a test of the model")
    else:
        c2 = curve_error_rel * curve_error_rel

        def chi2(log_s):
            model = curve(math.exp(log_s) * n)
            r, w = model - d, 1.0 / (u * u)
            return float(np.sum(r * r * w) - c2 * np.sum(r * model * w) ** 2 / (1.0 + c2 * np.sum(model * model * w)))

        lo, hi = start.min() - 3.0, min(start.max() + 3.0, top)
        best = optimize.minimize_scalar(chi2, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
        log_s, chi2_min = float(best.x), float(best.fun)
        dof = n.size - 1
        p_value = float(stats.chi2.sf(chi2_min, dof)) if dof > 0 else None
        consistent = None if p_value is None else p_value >= 1.0 - CONFIDENCE     # one point: nothing to test
        limit = chi2_min + float(stats.chi2.ppf(CONFIDENCE, 1))
        bounds = []
        for edge in (lo, hi):
            if chi2(edge) > limit:
                bounds.append(float(k0 * math.exp(optimize.brentq(lambda x: chi2(x) - limit, *sorted((edge, log_s)),
                                                                  xtol=1e-12))))
            else:                                        # not reached within the study's curve
                bounds.append(None)
        out.update(wear_coefficient_m2_N=k0 * math.exp(log_s), chi2=chi2_min, p_value=p_value,
                   consistent=consistent, depth_uncertainty_m=u.tolist(), curve_error_rel=curve_error_rel,
                   interval_95_m2_N=bounds if consistent is not False else None, tolerance_rel=None,
                   note=ONE_POINT if consistent is None else "" if consistent else (
                       f"one k_w does not fit these points within their uncertainties (chi^2 = {chi2_min:.3g} on "
                       f"{dof} degree{'s' if dof > 1 else ''} of freedom, p = {p_value:.2g}): no interval; each "
                       "point alone gives its own k_w (each_point_alone_m2_N); a law whose rate changes with depth "
                       "(--law mild-severe) or larger uncertainties would be needed"))
    res = log_residuals(log_s)
    with_uncertainty = out["tolerance_rel"] is None      # the test judges (one point: nothing), not a share
    out.update(residuals_rel=[float(math.expm1(r)) for r in res],
               fits=out["consistent"] if with_uncertainty else bool(np.all(np.abs(np.expm1(res)) <= tolerance)),
               local_growth_exponents=[_local_exponent(curve, x, growth[-1, 0])
                                       for x in out["wear_coefficient_m2_N"] / k0 * n])
    return out


# how far the study's curve has been checked to rescale (depth a function of k_w N alone): within 0.8 % from 1/300 to
# 300 times the study's k_w (docs/explanation/wear_study.md, "The experiment"); it fails where the wear acts within single impacts
MASTER_CURVE_CHECKED = (1.0 / 300.0, 300.0)


def master_curve_check(k0: float, fit: dict) -> dict:
    """Whether the fitted k_w rescales the study's curve within the range where that was checked
    (:data:`MASTER_CURVE_CHECKED`); outside it, the note says to run the study at the fitted k_w."""
    ratio = fit["wear_coefficient_m2_N"] / k0
    within = MASTER_CURVE_CHECKED[0] <= ratio <= MASTER_CURVE_CHECKED[1]
    return {"rescaled_by": ratio, "checked_range": list(MASTER_CURVE_CHECKED), "within": within,
            "note": "" if within else (f"the fit rescales the study's curve by {ratio:.3g}, outside the checked "
                                       f"{MASTER_CURVE_CHECKED[0]:.3g} ... {MASTER_CURVE_CHECKED[1]:g}: run the study "
                                       "at the fitted k_w and calibrate on it")}


def predictions(growth: np.ndarray, k0: float, fit: dict, revolutions) -> list[dict]:
    """The max depth [m] after each of ``revolutions`` under an Archard ``fit`` with its band (the depths at the
    interval's ends; the master curve rises with s), or, beyond the study's curve, the study revolutions needed."""
    curve, _ = master_curve(growth)
    interval = fit.get("interval_95_m2_N") or [None, None]
    out = []
    for n in revolutions:
        x = n * fit["wear_coefficient_m2_N"] / k0
        entry = {"revolutions": float(n), "depth_m": None, "band_95_m": None}
        if x <= growth[-1, 0]:
            entry["depth_m"] = float(curve(x))
            if None not in interval and all(n * k / k0 <= growth[-1, 0] for k in interval):
                entry["band_95_m"] = [float(curve(n * k / k0)) for k in interval]
        needed = n * max(k for k in (fit["wear_coefficient_m2_N"], *interval) if k is not None) / k0
        if needed > growth[-1, 0]:
            entry["study_revolutions_needed"] = float(math.ceil(needed))
        out.append(entry)
    return out


def life(growth: np.ndarray, k0: float, fit: dict, depth_m: float, crank_speed_rpm: float | None = None) -> dict:
    """The revolutions to a max depth of ``depth_m`` [m] under an Archard ``fit`` (the study's own k_w: ``{"law":
    "archard", "wear_coefficient_m2_N": k0}``), with the band from its interval (None beyond the study's curve) and,
    at ``crank_speed_rpm``, the same in hours of running."""
    positive("depth_m", depth_m)
    _, inverse = master_curve(growth)
    x = float(inverse(depth_m))
    if not math.isfinite(x):
        return {"depth_m": depth_m, "revolutions": None, "band_95_revolutions": None, "hours": None,
                "band_95_hours": None, "note": f"beyond the study's max depth {growth[-1, 1]:g} m: {FURTHER}"}
    interval = fit.get("interval_95_m2_N")
    band = ([x * k0 / interval[1], x * k0 / interval[0]] if interval and None not in interval else None)
    revolutions = x * k0 / fit["wear_coefficient_m2_N"]
    hours = (lambda n: n / (60.0 * crank_speed_rpm)) if crank_speed_rpm else (lambda n: None)
    return {"depth_m": depth_m, "revolutions": revolutions, "band_95_revolutions": band, "hours": hours(revolutions),
            "band_95_hours": [hours(n) for n in band] if band and crank_speed_rpm else None}


def study_life(growth: np.ndarray, wear_coefficient_m2_N: float, depth_m: float | None,
               crank_speed_rpm: float) -> dict:
    """A wear study's summary entries for its life to ``depth_m`` (None: none) at its own k_w: ``life``
    (:func:`life`; no band, the k_w being assumed: along the master curve the life scales as 1/k_w) and its
    revolutions and hours as single numbers, which an ensemble (``--seeds``) states with their spread."""
    if depth_m is None:
        return {}
    k = wear_coefficient_m2_N
    span = life(growth, k, {"law": "archard", "wear_coefficient_m2_N": k}, depth_m, crank_speed_rpm)
    span["note"] = span.get("note") or (f"at the study's k_w {k:.4g} m^2/N; c times that k_w divides the life by c "
                                        "(the master curve); measured depths give k_w with an interval: wearjoint "
                                        "calibrate")
    return {"life": span, "life_revolutions": span["revolutions"], "life_hours": span["hours"]}


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


def plot_calibration(growth: np.ndarray, k0: float, points, fits: list, path, n_max: float | None = None) -> None:
    """The fitted laws' max depth against revolutions with the measured points (their uncertainties as error
    bars) out to ``n_max`` (default: past the last point); an Archard fit's interval as a band."""
    from wearjoint.plots import plt, save_figure

    n_max = n_max or max(p[0] for p in points) * 1.1
    n = np.linspace(0.0, n_max, 400)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for fit in fits:
        label = (f"one k_w = {fit['wear_coefficient_m2_N']:.3g} m²/N" if fit["law"] == "archard" else
                 f"mild {fit['mild_wear_coefficient_m2_N']:.3g} → severe {fit['severe_wear_coefficient_m2_N']:.3g} "
                 f"m²/N at {fit['transition_depth_m'] * 1e3:.3g} mm")
        ax.plot(n, predicted_depth(growth, k0, n, fit) * 1e3, "-", label=label)
        interval = fit.get("interval_95_m2_N")
        if fit["law"] == "archard" and interval and None not in interval:
            low, high = (predicted_depth(growth, k0, n, {**fit, "wear_coefficient_m2_N": k}) * 1e3 for k in interval)
            ax.fill_between(n, low, high, alpha=0.25, label=f"{fit['confidence']:.0%} band")
    errors = [p[2] * 1e3 if len(p) > 2 and p[2] else 0.0 for p in points]
    ax.errorbar([p[0] for p in points], [p[1] * 1e3 for p in points], yerr=errors, fmt="ko", capsize=3,
                label="measured")
    ax.set_xlabel("crank revolutions")
    ax.set_ylabel("max wear depth [mm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, path)


def fit_mild_severe(growth: np.ndarray, k0: float, points, transition_depth_m: float,
                    bushing_radius_m: float | None = None) -> dict:
    """k_mild up to ``transition_depth_m`` of max depth, k_severe beyond; exact for two points, least squares
    for more (``bushing_radius_m``: as :func:`fit_archard`'s)."""
    curve, inverse = master_curve(growth)
    n, d, _ = _check_points(points, growth[-1, 0], growth[-1, 1], bushing_radius_m)
    if not (math.isfinite(transition_depth_m) and 0.0 < transition_depth_m < growth[-1, 1]):
        raise ParameterError(f"parameter transition_depth_m={transition_depth_m!r} is invalid: allowed in (0, "
                             f"{growth[-1, 1]:g}) m (the study's max depth)")
    if n.size < 2:
        raise ParameterError(f"parameter points={list(points)!r} are invalid: allowed at least two points for the "
                             "mild-to-severe law")
    if d.max() <= transition_depth_m:               # the severe coefficient would be the start guess, unfitted
        raise ParameterError(f"parameter points={list(points)!r} are invalid: the mild-to-severe law needs a point "
                             f"deeper than the transition depth, {transition_depth_m:g} m (the deepest is {d.max():g} m): "
                             "without one the severe coefficient is not measured; fit one k_w (--law archard)")
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
        raise ParameterError(f"parameter points={list(points)!r} are invalid: the mild-to-severe fit needs the "
                             f"study's curve beyond its {growth[-1, 0]:g} revolutions: {FURTHER}") from None
    k_mild, k_severe = np.exp(fit.x)
    res = np.log(predicted(fit.x)) - np.log(d)
    return {"law": "mild-severe", "transition_depth_m": transition_depth_m,
            "mild_wear_coefficient_m2_N": float(k0 * k_mild), "severe_wear_coefficient_m2_N": float(k0 * k_severe),
            "transition_revolutions": float(x_t / k_mild), "parameters_fitted": 2,
            "degrees_of_freedom": int(n.size - 2), "residuals_rel": [float(math.expm1(r)) for r in res]}


__all__ = ["FURTHER", "master_curve", "fit_archard", "fit_mild_severe", "predicted_depth", "plot_calibration",
           "predictions", "life", "study_life", "falling_depths", "master_curve_check", "MASTER_CURVE_CHECKED",
           "check_tolerance", "uncertainty_range", "MAX_POINT_REVOLUTIONS", "MIN_DEPTH_M", "MIN_DEPTH_UNCERTAINTY_M",
           "MAX_BUSHING_RADIUS_M"]
