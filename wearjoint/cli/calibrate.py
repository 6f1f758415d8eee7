"""`wearjoint calibrate`: fit k_w to measured (revolutions, max depth) points on a finished wear study's growth
curve (:mod:`wearjoint.studies.calibration`), one coefficient or the mild-to-severe law."""
from __future__ import annotations

import json
import math
import shlex
import sys
import warnings
from pathlib import Path

import numpy as np

from ..parameters import ParameterError
from ..results import write_json_atomic
from ..studies.calibration import (
    DEFAULT_TOLERANCE, MAX_POINT_REVOLUTIONS, MIN_DEPTH_M, check_tolerance, falling_depths, fit_archard,
    fit_mild_severe, life, master_curve_check, plot_calibration, predictions, uncertainty_range,
)
from ..studies.wear_study_plots import EXPERIMENT_MAX_DEPTH_M, EXPERIMENT_REVOLUTIONS
from .options import require_option, with_options

LAWS = ("archard", "mild-severe")
# the options whose values a fit checks against the study, by the names the fits give them
FIT_OPTIONS = {"points": "--points", "transition_depth_m": "--transition-depth-m"}
EXPERIMENT_POINTS = ",".join(f"{n}:{d:g}" for n, d in zip(EXPERIMENT_REVOLUTIONS, EXPERIMENT_MAX_DEPTH_M))  # Sec. 7


def add_arguments(parser) -> None:
    parser.add_argument("--study", required=True, help="a finished wear-study folder (summary.json, wear_growth.csv)")
    parser.add_argument("--points", default=None,
                        help="measured REVOLUTIONS:MAX_DEPTH_M pairs, or REVOLUTIONS:MAX_DEPTH_M:UNCERTAINTY_M, comma "
                             f"separated; left out, a study of the paper's mechanism and joint fits its experiment, "
                             f"{EXPERIMENT_POINTS}, and any other study refuses to run")
    parser.add_argument("--depth-uncertainty-m", type=float, default=None,
                        help="archard: the standard uncertainty of every measured depth [m] (a point's own third "
                             "value takes precedence): the fit becomes a likelihood, with a test of the model and a "
                             "95 %% interval (without it: k_w alone)")
    parser.add_argument("--predict-revolutions", default=None,
                        help="archard: revolutions N1,N2,... to predict the max depth at, with its 95 %% band")
    parser.add_argument("--life-depth-m", type=float, default=None,
                        help="archard: a max depth [m] to predict the revolutions to, with their 95 %% band")
    parser.add_argument("--law", choices=LAWS, default="archard", help="wear law to fit (default %(default)s)")
    parser.add_argument("--transition-depth-m", type=float, default=None,
                        help="mild-severe (required there): the max depth at which the wear turns severe [m], a "
                             "stated input (with two points the two rates are then determined exactly: no interval)")
    parser.add_argument("--tolerance", type=float, default=None,
                        help=f"archard without depth uncertainties: residuals within this share count as a fit "
                             f"(default {DEFAULT_TOLERANCE:g}); with them the chi^2 test judges the fit")
    parser.add_argument("--out", default=None,
                        help="where to write calibration.json and calibration.png (default: --study)")
    parser.add_argument("--no-plots", action="store_true", help="skip calibration.png")


def _points(text: str, uncertainty: float | None = None) -> list[tuple[float, float, float | None]]:
    """(revolutions, max depth [m], its uncertainty [m] or None) of ``--points`` (``--depth-uncertainty-m`` where
    a point gives none)."""
    points = []
    for item in text.split(","):
        values = item.split(":")
        try:
            numbers = [float(v) for v in values]
        except ValueError:
            numbers = []
        require_option("--points", text, len(numbers) in (2, 3) and all(map(math.isfinite, numbers)),
                       f"REVOLUTIONS:MAX_DEPTH_M[:UNCERTAINTY_M] items of finite numbers, e.g. {EXPERIMENT_POINTS}")
        points.append((numbers[0], numbers[1], numbers[2] if len(numbers) == 3 else uncertainty))
    return sorted(points)


def _revolutions(text: str | None) -> list[float]:
    if text is None:
        return []
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    require_option("--predict-revolutions", text, values and all(v > 0 and math.isfinite(v) for v in values),
                   "N1,N2,... revolutions > 0")
    require_option("--predict-revolutions", text, all(v <= MAX_POINT_REVOLUTIONS for v in values),
                   f"N1,N2,... revolutions up to {MAX_POINT_REVOLUTIONS:g} (beyond any machine's life)")
    return values


def _read_study(folder: str) -> tuple[dict, np.ndarray, float]:
    """(summary, wear_growth.csv's rows, the study's k_w [m^2/N]) of a finished wear study, or --study refused in one
    line."""
    from ..sweep.runner import SPEC_NAME

    study = Path(folder)
    if (study / SPEC_NAME).is_file():       # a --seeds ensemble (a sweep): each of its studies is a case folder
        cases = sorted(p.parent for p in study.glob("cases/*/summary.json"))
        raise ParameterError(f"--study={folder!r} is invalid: it holds an ensemble of wear studies (--seeds; "
                             f"{SPEC_NAME}); allowed one wear study's folder, e.g. one of its cases"
                             + (f": {cases[0]}" if cases else " (cases/CASE_ID: none finished yet)"))
    try:
        summary = json.loads((study / "summary.json").read_text())
        with warnings.catch_warnings():     # a file without rows: said below, not warned
            warnings.simplefilter("ignore", UserWarning)
            growth = np.loadtxt(study / "wear_growth.csv", delimiter=",", skiprows=1, ndmin=2)
        joint = summary["parameters"]["joint"]
        k0 = float(joint["wear_coefficient_m2_N"])      # wear_growth.csv counts crank revolutions at any factor
        if not (growth.shape[0] and growth.shape[1] >= 2 and np.isfinite(growth[:, :2]).all() and growth[0, 0] > 0
                and np.all(np.diff(growth[:, 0]) > 0) and growth[-1, 1] > 0):
            raise ValueError("wear_growth.csv holds no rows of rising revolutions > 0 and finite max depths reaching "
                             "> 0")
        if not (math.isfinite(k0) and k0 > 0):
            raise ValueError(f"summary.json's k_w is {k0!r}, not > 0")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ParameterError(f"--study={folder!r} is invalid: not a finished wear study ({type(exc).__name__}: "
                             f"{exc}); allowed a wear-study folder (summary.json, wear_growth.csv)") from None
    return summary, growth, k0


def _bushing_radius(summary: dict) -> float | None:
    """The study's bushing radius [m] (its summary's joint), None where it states none (a study written by hand)."""
    radius = (summary["parameters"]["joint"] or {}).get("bushing_radius_m")
    return float(radius) if isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0 else None


def _verdict(result: dict, tolerance: float) -> str:
    """The residuals line's end: the model's test with depth uncertainties, else --tolerance."""
    if result.get("tolerance_rel") is None:       # with uncertainties: the test's verdict (one point: none)
        return ("" if result["fits"] is None else ": within their uncertainties (the chi^2 test), a fit"
                if result["fits"] else ": beyond their uncertainties (the chi^2 test), not a fit")
    return (f": each within --tolerance {tolerance:g} of its depth, a fit" if result["fits"]
            else f": beyond --tolerance {tolerance:g} of its depth, not a fit")


def _longer_study(command_line: str | None, revolutions: str) -> str:
    """The study's command (its summary's ``command_line``) to ``revolutions`` into a new folder: its --revolutions
    and --out replaced; without it, what to change in the command that made the study."""
    words = shlex.split(command_line or "")
    if words[:2] != ["wearjoint", "wear-study"] or "--resume" in words:   # an older version's resumed study: its
        # summary kept the resuming line alone, without the study's options
        return f"the command that made the study with --revolutions {revolutions} and --out NEW_FOLDER"
    kept, rest = [], iter(words)
    for word in rest:
        if word.split("=", 1)[0] in ("--revolutions", "--out"):
            if "=" not in word:
                next(rest, None)                 # its value
            continue
        kept.append(word)
    return shlex.join([*kept, "--revolutions", revolutions, "--out", "NEW_FOLDER"])


def _band(band, scale=1.0, unit="", why: str = "") -> str:
    """`` (95 % band LOW ... HIGH UNIT)``, or `` (no band: WHY)``."""
    return (f" (95 % band {band[0] * scale:.3g} ... {band[1] * scale:.3g}{unit})" if band
            else f" (no band: {why})" if why else " (no band)")


def _no_band(result: dict, needed: float | None = None) -> str:
    """Why a prediction or a life of an Archard fit ``result`` has no band (``needed``: the study revolutions its
    band's end needs, where that is why)."""
    if result.get("consistent") is False:
        return "one k_w does not fit these points (the chi^2 test): the figure holds only if it did"
    if result.get("interval_95_m2_N") is None:
        return "no interval without the depths' uncertainty (--depth-uncertainty-m)"
    return (f"an end of the interval lies beyond the study's curve; a study to {needed:.0f} revolutions reaches it"
            if needed else "an end of the interval lies beyond the study's curve")


def run(args) -> int:
    summary, growth, k0 = _read_study(args.study)
    study = Path(args.study)
    for option, value, allowed in (("--depth-uncertainty-m", args.depth_uncertainty_m, "> 0 [m]"),
                                   ("--life-depth-m", args.life_depth_m, "a max depth > 0 [m]"),
                                   ("--tolerance", args.tolerance, "a share > 0 of each measured depth")):
        require_option(option, value, value is None or (math.isfinite(value) and value > 0), allowed)
    radius = _bushing_radius(summary)
    least, most, text = uncertainty_range(radius)
    require_option("--depth-uncertainty-m", args.depth_uncertainty_m,
                   args.depth_uncertainty_m is None or least <= args.depth_uncertainty_m <= most, text)
    require_option("--life-depth-m", args.life_depth_m,
                   args.life_depth_m is None or MIN_DEPTH_M <= args.life_depth_m < (radius or math.inf),
                   f"a max depth of at least {MIN_DEPTH_M:g} m (a few atomic layers: the least wear Archard's law "
                   "describes)" + (f" below the bushing radius {radius:g} m (worn through there)" if radius else ""))
    for option, value in (("--predict-revolutions", args.predict_revolutions), ("--life-depth-m", args.life_depth_m)):
        require_option(option, value, value is None or args.law == "archard", "only with --law archard")
    require_option("--transition-depth-m", args.transition_depth_m,
                   args.transition_depth_m is None or args.law == "mild-severe", "only with --law mild-severe")
    if args.points is None:         # the paper's experiment, on a study of the paper's case only (its summary has it)
        if "experiment" not in summary:
            raise ParameterError(f"--points is required with --study {args.study!r}: not a study of the paper's "
                                 f"mechanism and joint, whose experiment ({EXPERIMENT_POINTS}) is the default; allowed "
                                 "this machine's measured REVOLUTIONS:MAX_DEPTH_M[:UNCERTAINTY_M] points")
        args.points = EXPERIMENT_POINTS
    points = _points(args.points, args.depth_uncertainty_m)
    require_option("--tolerance", args.tolerance, args.tolerance is None or any(u is None for _, _, u in points),
                   "only without depth uncertainties (with them the chi^2 test judges the fit)")
    args.tolerance = DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance
    try:
        check_tolerance(args.tolerance)
    except ParameterError as exc:
        raise with_options(exc, {"tolerance": "--tolerance"}) from None
    args.bushing_radius_m = radius
    asked = _revolutions(args.predict_revolutions)
    try:
        result, fits = _fit(args, summary, growth, k0, points, asked)
    except ParameterError as exc:     # a value beyond what the study reaches
        raise with_options(exc, FIT_OPTIONS, {"points": args.points,
                                              "transition_depth_m": args.transition_depth_m}) from None
    falling = falling_depths(points)
    if falling:
        result["warning"] = falling
        print(f"wearjoint calibrate: warning: {falling}", file=sys.stderr)
    result.update({"study": str(study), "study_wear_coefficient_m2_N": k0,
                   "points": [{"revolutions": n, "max_wear_depth_m": d, "uncertainty_m": u} for n, d, u in points]})
    out = Path(args.out) if args.out else study
    out.mkdir(parents=True, exist_ok=True)
    if (out / "calibration.json").is_file():      # what --calibration reads: say that it changes
        print(f"replacing the fit in {out / 'calibration.json'} (another --out keeps it)")
    write_json_atomic(out / "calibration.json", result)
    if args.no_plots:
        (out / "calibration.png").unlink(missing_ok=True)     # an earlier fit's
    else:
        reach = [p["revolutions"] for p in result.get("predictions", []) if p["depth_m"] is not None]
        if (result.get("life") or {}).get("revolutions"):
            reach.append(result["life"]["revolutions"])
        plot_calibration(growth, k0, points, fits, out / "calibration.png",
                         max([p[0] for p in points] + reach) * 1.1)
    print(f"results in {out}")
    return 0


def _fit(args, summary: dict, growth: np.ndarray, k0: float, points: list, asked: list) -> tuple[dict, list]:
    """The fit of ``--law`` (with its predictions), printed: (calibration.json's content, the fits to plot)."""
    if args.law == "archard":
        curve_error = float((summary.get("cycle_jumping") or {}).get("error_estimate_summed_rel_to_final_depth", 0.0))
        result = fit_archard(growth, k0, points, tolerance=args.tolerance, curve_error_rel=curve_error,
                             bushing_radius_m=args.bushing_radius_m)
        factor = float(summary["parameters"]["joint"]["wear_factor"])
        if factor != 1.0:       # no error estimate of its own: the factor's bias is left out of the interval
            result["curve_error_note"] = (
                f"the study ran at --wear-factor {factor:g}, whose curve's error is not estimated nor in the "
                "interval (the paper's case: -10 % of the depth at 100, docs/explanation/wear_study.md); calibrate "
                "on a study at wear factor 1 (cycle jumping), or measure the bias: wear-study --convergence jump,F")
            print(f"  note: {result['curve_error_note']}")
        fits = [result]
        interval = result["interval_95_m2_N"]
        ends = ["below the study's curve" if interval and interval[0] is None else None,
                "beyond the study's curve (a new study with more --revolutions reaches it)"
                if interval and interval[1] is None else None]
        shown = (f", {result['confidence']:.0%} interval [" + ", ".join(
            end or f"{k:.3g}" for end, k in zip(ends, interval)) + "]" if interval else "")
        print(f"  k_w {result['wear_coefficient_m2_N']:.4g} m^2/N{shown}"
              + (f"; chi^2 {result['chi2']:.3g}, p {result['p_value']:.2g}" if result.get("p_value") is not None
                 else ""))
        if result["note"]:
            print(f"  {result['note']}")
        print("  residuals " + ", ".join(f"{r:+.1%} at {p[0]:g} rev" for r, p in zip(result["residuals_rel"], points))
              + _verdict(result, args.tolerance))
        result["master_curve"] = master_curve_check(k0, result)
        if result["master_curve"]["note"]:
            print(f"  {result['master_curve']['note']}")
        result["predictions"] = predictions(growth, k0, result, asked)
        for p in result["predictions"]:
            if p["depth_m"] is None:
                needed = f"{p['study_revolutions_needed']:.0f}"
                print(f"  after {p['revolutions']:.6g} revolutions: beyond the study's curve ({growth[-1, 0]:.4g} "
                      f"revolutions at its k_w); run the study to {needed} revolutions (the fitted k_w's 95 % "
                      f"interval included): {_longer_study(summary.get('command_line'), needed)}")
            else:
                print(f"  after {p['revolutions']:.6g} revolutions: max depth {p['depth_m'] * 1e3:.4g} mm"
                      + _band(p["band_95_m"], 1e3, " mm", _no_band(result, p.get("study_revolutions_needed"))))
        if args.life_depth_m is not None:
            rpm = (summary["parameters"].get("mechanism") or {}).get("crank_speed_rpm")
            result["life"] = span = life(growth, k0, result, args.life_depth_m, rpm)
            print(f"  to {args.life_depth_m * 1e3:.4g} mm: " + (
                f"{span['revolutions']:.4g} revolutions" + _band(span["band_95_revolutions"], why=_no_band(result))
                + (f", {span['hours']:.4g} h at {rpm:g} rpm"
                   + (_band(span["band_95_hours"], unit=" h") if span["band_95_hours"] else "") if rpm else "")
                if span["revolutions"] is not None else span["note"]))
    else:
        transition = args.transition_depth_m
        if transition is None:
            raise ParameterError("--transition-depth-m is required with --law mild-severe: the fit's "
                                 "transition_depth_m is missing (the max depth [m] where the wear turns severe, a "
                                 "stated input)")
        result = fit_mild_severe(growth, k0, points, transition, bushing_radius_m=args.bushing_radius_m)
        fits = [fit_archard(growth, k0, points, tolerance=args.tolerance, bushing_radius_m=args.bushing_radius_m),
                result]
        print(f"  k_mild {result['mild_wear_coefficient_m2_N']:.4g} m^2/N up to {transition:g} m "
              f"(revolution {result['transition_revolutions']:.4g}), k_severe "
              f"{result['severe_wear_coefficient_m2_N']:.4g} m^2/N; {result['parameters_fitted']} parameters, "
              f"{result['degrees_of_freedom']} degree{'' if result['degrees_of_freedom'] == 1 else 's'} of freedom left")
    return result, fits


__all__ = ["add_arguments", "run"]
