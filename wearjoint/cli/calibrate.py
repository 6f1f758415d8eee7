"""`wearjoint calibrate`: fit k_w to measured (revolutions, max depth) points on a finished wear study's growth
curve (:mod:`wearjoint.studies.calibration`), one coefficient or the mild-to-severe law."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..parameters import ParameterError
from ..results import write_json_atomic
from ..studies.calibration import fit_archard, fit_mild_severe, plot_calibration
from ..studies.wear_study_plots import EXPERIMENT_MAX_DEPTH_M, EXPERIMENT_REVOLUTIONS

LAWS = ("archard", "mild-severe")
EXPERIMENT_POINTS = ",".join(f"{n}:{d:g}" for n, d in zip(EXPERIMENT_REVOLUTIONS, EXPERIMENT_MAX_DEPTH_M))  # Sec. 7


def add_arguments(parser) -> None:
    parser.add_argument("--study", required=True, help="a finished wear-study folder (summary.json, wear_growth.csv)")
    parser.add_argument("--points", default=EXPERIMENT_POINTS,
                        help="measured REVOLUTIONS:MAX_DEPTH_M pairs, comma separated (default: the paper's "
                             "experiment, %(default)s)")
    parser.add_argument("--law", choices=LAWS, default="archard", help="wear law to fit (default %(default)s)")
    parser.add_argument("--transition-depth-m", type=float, default=None,
                        help="mild-severe: the max depth at which the wear turns severe [m] (default: the first "
                             "point's depth)")
    parser.add_argument("--tolerance", type=float, default=0.1,
                        help="archard: residuals within this share count as a fit (default %(default)g)")
    parser.add_argument("--out", default=None,
                        help="where to write calibration.json and calibration.png (default: --study)")
    parser.add_argument("--no-plots", action="store_true", help="skip calibration.png")


def _points(text: str) -> list[tuple[float, float]]:
    points = []
    for item in text.split(","):
        revolutions, sep, depth = item.partition(":")
        try:
            points.append((float(revolutions), float(depth)))
        except ValueError:
            raise ParameterError(f"points={text!r} is invalid: allowed REVOLUTIONS:MAX_DEPTH_M pairs, e.g. "
                                 f"{EXPERIMENT_POINTS}") from None
        if not sep:
            raise ParameterError(f"points={text!r} is invalid: allowed REVOLUTIONS:MAX_DEPTH_M pairs")
    return sorted(points)


def run(args) -> int:
    study = Path(args.study)
    try:
        summary = json.loads((study / "summary.json").read_text())
        growth = np.loadtxt(study / "wear_growth.csv", delimiter=",", skiprows=1, ndmin=2)
        joint = summary["parameters"]["joint"]
        k0 = float(joint["wear_coefficient_m2_N"]) * float(joint["wear_factor"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ParameterError(f"study={args.study!r} is invalid: not a finished wear study ({exc!r})") from None
    points = _points(args.points)
    if args.law == "archard":
        result = fit_archard(growth, k0, points, tolerance=args.tolerance)
        fits = [result]
        interval = result["interval_m2_N"]
        print(f"  k_w {result['wear_coefficient_m2_N']:.4g} m^2/N"
              + (f", {result['confidence']:.0%} interval [{interval[0]:.3g}, {interval[1]:.3g}]" if interval else
                 " (one point: no interval)"))
        print("  residuals " + ", ".join(f"{r:+.1%}" for r in result["residuals_rel"])
              + ("" if result["fits"] else f": one k_w cannot fit these points within {args.tolerance:.0%}; "
                 "try --law mild-severe"))
    else:
        transition = args.transition_depth_m if args.transition_depth_m is not None else points[0][1]
        result = fit_mild_severe(growth, k0, points, transition)
        fits = [fit_archard(growth, k0, points, tolerance=args.tolerance), result]
        print(f"  k_mild {result['mild_wear_coefficient_m2_N']:.4g} m^2/N up to {transition:g} m "
              f"(revolution {result['transition_revolutions']:.4g}), k_severe "
              f"{result['severe_wear_coefficient_m2_N']:.4g} m^2/N; {result['parameters_fitted']} parameters, "
              f"{result['degrees_of_freedom']} degrees of freedom left")
    result.update({"study": str(study), "study_wear_coefficient_m2_N": k0,
                   "points": [{"revolutions": n, "max_wear_depth_m": d} for n, d in points]})
    out = Path(args.out) if args.out else study
    out.mkdir(parents=True, exist_ok=True)
    write_json_atomic(out / "calibration.json", result)
    if not args.no_plots:
        plot_calibration(growth, k0, points, fits, out / "calibration.png")
    print(f"results in {out}")
    return 0


__all__ = ["add_arguments", "run"]
