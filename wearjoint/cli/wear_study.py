"""`wearjoint wear-study`: the wear study (:mod:`wearjoint.validation.wear_study`), its
factor-convergence study and the calibration of k_w from the command line."""
from __future__ import annotations

import dataclasses
import math
import sys

from ..parameters import MAX_WEAR_STEP_S, ParameterError
from ..validation.wear_calibration import calibrate_wear_coefficient, run_convergence
from ..validation.wear_study import (
    DEFAULT_WEAR_FACTOR, ENGINES, PRINTED_WEAR_COEFFICIENT_M2_N, STUDY_INTEGRATORS,
    WearStudyConfig, run_wear_study,
)
from .options import add_fmu_arguments, add_model_arguments, add_output_arguments, model_from_args, restate_default
from .sweep import add_ensemble_arguments


def parse_int_list(name: str, text: str) -> tuple:
    """'1000,2000' -> (1000, 2000); a clear ParameterError for anything else."""
    values = []
    for item in str(text).split(","):
        item = item.strip()
        try:
            values.append(int(item))
        except ValueError:
            raise ParameterError(f"{name}: {item!r} is not an integer (expected e.g. 1000,2000)") from None
    return tuple(values)


def parse_float_list(name: str, text: str) -> tuple:
    values = []
    for item in str(text).split(","):
        try:
            values.append(float(item))
        except ValueError:
            raise ParameterError(f"{name}: {item.strip()!r} is not a number (expected e.g. 1,10,50)") from None
    return tuple(values)


# WearStudyConfig's defaults: the one source of the options' defaults
_STUDY = {f.name: f.default for f in dataclasses.fields(WearStudyConfig) if f.default is not dataclasses.MISSING}
_MAX_STEP_DEFAULT = ("(default %(default)g)" if _STUDY["max_step_s"] is not None else
                     f"(default: the wear-step limit of the run's wear, at most {MAX_WEAR_STEP_S:g}; docs/model.md §7)")


def add_arguments(parser) -> None:
    add_output_arguments(parser)
    parser.add_argument("--revolutions", default=str(_STUDY["revolutions"]),
                        help="crank revolutions to reach (integer) (default %(default)s)")
    parser.add_argument("--snapshots", default=None,
                        help="revolutions at which to keep the profile, comma separated (default: quarters)")
    parser.add_argument("--engine", choices=ENGINES, default=_STUDY["engine"],
                        help="simulation engine (default %(default)s)")
    add_fmu_arguments(parser, fmu_file=False, when="with --engine cosim")
    parser.add_argument("--cycle-jump", default=None, metavar="M,J",
                        help="after every M simulated revolutions scale their wear increment by J "
                             "(wear factor 1 unless --wear-factor is given)")
    parser.add_argument("--integrator", choices=STUDY_INTEGRATORS, default=_STUDY["integrator"],
                        help="rk4: fixed steps of --max-step; dopri: adaptive, at most --max-step "
                             "(default %(default)s)")
    parser.add_argument("--max-step", type=float, default=_STUDY["max_step_s"],
                        help="largest integration step [s] (RK4: the step) " + _MAX_STEP_DEFAULT)
    parser.add_argument("--checkpoint-every", type=float, default=_STUDY["checkpoint_every_revolutions"],
                        help="simulated revolutions between checkpoints (default %(default)g)")
    parser.add_argument("--impact-threshold-m-s2", type=float, default=_STUDY["impact_threshold_m_s2"],
                        help="impact event: |a - a_ideal| above this [m/s^2] (default %(default)g)")
    parser.add_argument("--resume", action="store_true", help="continue the study checkpointed in --out")
    task = parser.add_argument_group("other tasks")
    task.add_argument("--convergence", default=None, metavar="F1,F2,...",
                      help="convergence study of the acceleration factors (first = reference, normally 1)")
    task.add_argument("--calibrate-max-depth-m", type=float, default=None,
                      help="find the effective k_w whose study ends at this max depth (e.g. 0.58e-3)")
    add_model_arguments(parser)
    restate_default(parser, "wear_factor", f"{DEFAULT_WEAR_FACTOR:g}; 1 with --cycle-jump")
    add_ensemble_arguments(parser)   # --seeds N: N seeds as Dask tasks (wearjoint.sweep), Fig. 7 with bands


def config_from_args(args) -> WearStudyConfig:
    joint, mechanism = model_from_args(args)
    revolutions = parse_int_list("--revolutions", args.revolutions)
    if len(revolutions) != 1:
        raise ParameterError("--revolutions takes one integer")
    revolutions = revolutions[0]
    if args.snapshots is not None:
        snapshots = parse_int_list("--snapshots", args.snapshots)
    else:
        snapshots = tuple(sorted({max(1, revolutions * q // 4) for q in (1, 2, 3, 4)}))
    jump_m, jump_j = 0, 1.0
    if args.cycle_jump is not None:
        parts = args.cycle_jump.split(",")
        if len(parts) != 2:
            raise ParameterError(f"--cycle-jump {args.cycle_jump!r}: expected M,J (e.g. 2,10)")
        jump_m = parse_int_list("--cycle-jump M", parts[0])[0]
        jump_j = parse_float_list("--cycle-jump J", parts[1])[0]
        if jump_m < 1:
            raise ParameterError(f"--cycle-jump M={jump_m} is invalid: allowed an integer >= 1")
    if args.wear_factor is None and not args.no_wear:
        joint = joint.replace(wear_factor=1.0 if args.cycle_jump is not None else DEFAULT_WEAR_FACTOR)
    return WearStudyConfig(joint=joint, mechanism=mechanism, revolutions=revolutions, snapshots=snapshots,
                           jump_revolutions=jump_m, jump_factor=jump_j, engine=args.engine,
                           integrator=args.integrator, max_step_s=args.max_step,
                           checkpoint_every_revolutions=args.checkpoint_every,
                           impact_threshold_m_s2=args.impact_threshold_m_s2, fmu_backend=args.fmu_backend)


def run(args) -> int:
    from ..cosim import CoSimulationError
    from ..runner import RunDiverged

    if args.seeds is not None and args.seeds > 1:
        from .sweep import run_from_args
        return run_from_args("wear-study", args)
    config = config_from_args(args)
    try:
        if args.convergence is not None:
            factors = parse_float_list("--convergence", args.convergence)
            for f in factors:
                if not (math.isfinite(f) and f > 0):
                    raise ParameterError(f"--convergence: factor {f!r} is invalid: allowed > 0")
            result = run_convergence(config, factors, args.out, resume=args.resume, progress=not args.quiet)
            for row in result["rows"]:
                print(f"  {row['run']:14s} rev {row['revolution']:6d}  max depth {row['max_wear_depth_m'] * 1e6:9.2f} µm"
                      f"  rel diff {row['max_depth_rel_diff']:+.3f}  rms rel {row['rms_profile_diff_rel']:.3f}")
            print(f"largest factor within {result['tolerance_rel']:.0%}: {result['largest_factor_within_tolerance']}")
        elif args.calibrate_max_depth_m is not None:
            result = calibrate_wear_coefficient(config, args.calibrate_max_depth_m, args.out, resume=args.resume,
                                                progress=not args.quiet)
            print(f"  printed k_w {PRINTED_WEAR_COEFFICIENT_M2_N:.3g} m^2/N wears "
                  f"{result['printed_rate']['mean_depth_per_revolution_m'] * 1e6:.3g} µm per revolution")
            print(f"  effective k_w {result['effective_wear_coefficient_m2_N']:.4g} m^2/N "
                  f"(ratio to printed {result['ratio_to_printed']:.4g}) reaches "
                  f"{result['reached_max_depth_m'] * 1e3:.4g} mm after {config.revolutions} revolutions")
        else:
            summary = run_wear_study(config, args.out, resume=args.resume, progress=not args.quiet,
                                     plots=not args.no_plots)
            for s in summary["snapshots"]:
                print(f"  rev {s['revolution']:6d}  max depth {s['max_wear_depth_m'] * 1e3:.4f} mm at "
                      f"{s['max_wear_angle_deg']:.1f} deg  lobes {_angle(s['lobe_0_angle_deg'])}/"
                      f"{_angle(s['lobe_180_angle_deg'])} deg  impact events {s['impact_events']}")
            print(f"  wall time {summary['wall_time_s']:.1f} s")
    except KeyboardInterrupt:
        print(f"wearjoint wear-study: interrupted; finished work is checkpointed in {args.out} "
              "(continue with --resume)", file=sys.stderr)
        return 130
    except (CoSimulationError, RunDiverged) as exc:
        print(f"wearjoint wear-study: error: {exc}; finished work is checkpointed in {args.out}", file=sys.stderr)
        return 1
    print(f"results in {args.out}")
    return 0


def _angle(value) -> str:
    return "-" if value is None else f"{value:.1f}"


__all__ = ["add_arguments", "run", "config_from_args", "parse_int_list", "parse_float_list"]
