"""`wearjoint wear-study`: the wear study (:mod:`wearjoint.studies.wear_study`), its
factor-convergence study and the calibration of k_w from the command line."""
from __future__ import annotations

import math
import sys
from pathlib import Path

from ..checks import require
from ..joint import StateError
from ..parameters import JointParameters, ParameterError, SliderCrankParameters
from ..run_options import add_wear_study_arguments
from ..studies.cycle_jump import replay_volume_warning
from ..studies.wear_calibration import calibrate_wear_coefficient, check_target_depth
from ..studies.wear_convergence import JUMP, run_convergence
from ..studies.wear_study import PRINTED_WEAR_COEFFICIENT_M2_N, WearStudyConfig, run_wear_study
from ..studies.wear_study_recovery import (CHECKPOINT_NAME, DERIVED, OPTIONS, SNAPSHOTS_NAME, checkpoint_revolution,
                                          read_checkpoint)
from ..sweep.limits import check_seeds
from .options import with_options
from .study_options import config_from_args, parse_float_list
from .sweep import add_ensemble_arguments


def add_arguments(parser) -> None:
    """The study's options (:func:`wearjoint.run_options.add_wear_study_arguments`, the sweeps' target's) and its
    ensemble's (--seeds N: N seeds as Dask tasks, Fig. 7 with bands)."""
    add_wear_study_arguments(parser)
    add_ensemble_arguments(parser)


def run(args) -> int:
    from ..cosim import CoSimulationError
    from ..checks import RunStopped
    from ..studies.wear_study import StudyDiverged

    ensemble = args.seeds is not None and check_seeds(args.seeds) > 1
    for flag, value in (("--workers", args.workers), ("--scheduler", args.scheduler)):
        if value is not None and not ensemble:       # one study runs here, on one core
            raise ParameterError(f"{flag}={value!r} is invalid: allowed only with --seeds N, N > 1 (the "
                                 "ensemble's studies spread over Dask workers; one study runs in this process)")
    _check_out(args, ensemble)
    _refuse_unread(args)
    if ensemble:
        from .sweep import run_from_args
        return run_from_args("wear-study", args)
    try:
        config = config_from_args(args)
        if args.calibrate_max_depth_m is not None:
            check_target_depth(args.calibrate_max_depth_m, config.joint.bushing_radius_m)
        if args.resume and args.convergence is None and args.calibrate_max_depth_m is None:
            config = _resumed_config(config, args)
    except ParameterError as exc:       # a study setting named as the command line writes it
        raise with_options(exc, {**OPTIONS, "target_max_depth_m": "--calibrate-max-depth-m"}) from None
    try:
        if args.convergence is not None:
            factors = [JUMP if item.strip() == JUMP else parse_float_list("--convergence", item)[0]
                       for item in args.convergence.split(",")]
            for f in factors:
                if f != JUMP and not (math.isfinite(f) and f > 0):
                    raise ParameterError(f"--convergence: factor {f!r} is invalid: allowed > 0 or {JUMP}")
            result = run_convergence(config, factors, args.out, resume=args.resume, progress=not args.quiet)
            for row in result["rows"]:
                print(f"  {row['run']:14s} rev {row['revolution']:6d}  max depth {row['max_wear_depth_m'] * 1e6:9.2f} µm"
                      f"  rel diff {_number(row['max_depth_rel_diff'], '+.3f')}"
                      f"  rms rel {_number(row['rms_profile_diff_rel'], '.3f')}"
                      + ("  (diverged)" if row["status"] == "diverged" else ""))
            print(f"largest factor within {result['tolerance_rel']:.0%}: {result['largest_factor_within_tolerance']}")
            if "reference_error_estimate_rel" in result:
                print(f"the reference ({JUMP}) estimates its own error at "
                      f"{result['reference_error_estimate_rel']:.2%} of its final max depth (summed over its jumps)")
            if result["diverged"]:
                label, message = next(iter(result["diverged"].items()))
                others = [k for k in result["diverged"] if k != label]
                print(f"wearjoint wear-study: error: {label}: {message}; "
                      + (f"{', '.join(others)} diverged too; " if others else "")
                      + f"the table of the runs that finished is {args.out / 'convergence.csv'}", file=sys.stderr)
                return 1
        elif args.calibrate_max_depth_m is not None:
            try:
                result = calibrate_wear_coefficient(config, args.calibrate_max_depth_m, args.out, resume=args.resume,
                                                    progress=not args.quiet,
                                                    command_line=getattr(args, "command_line", None))
            except ParameterError as exc:        # a target no k_w the joint admits reaches
                raise with_options(exc, {"target_max_depth_m": "--calibrate-max-depth-m"}) from None
            print(f"  printed k_w {PRINTED_WEAR_COEFFICIENT_M2_N:.3g} m^2/N wears "
                  f"{result['printed_rate']['mean_depth_per_revolution_m'] * 1e6:.3g} µm per revolution")
            print(f"  effective k_w {result['effective_wear_coefficient_m2_N']:.4g} m^2/N "
                  f"(ratio to printed {result['ratio_to_printed']:.4g}) reaches "
                  f"{result['reached_max_depth_m'] * 1e3:.4g} mm after {config.revolutions} revolutions")
        else:
            summary = run_wear_study(config, args.out, resume=args.resume, progress=not args.quiet,
                                     plots=not args.no_plots, command_line=getattr(args, "command_line", None))
            for s in summary["snapshots"]:
                print(f"  rev {s['revolution']:6d}  max depth {s['max_wear_depth_m'] * 1e3:.4g} mm at "
                      f"{_angle(s['max_wear_angle_deg'])} deg  lobes {_angle(s['lobe_0_angle_deg'])}/"
                      f"{_angle(s['lobe_180_angle_deg'])} deg  impact events {s['impact_events']}")
            span = summary.get("life")
            if span:
                print(f"  to {span['depth_m'] * 1e3:.4g} mm: " + (
                    f"{span['revolutions']:.4g} revolutions, {span['hours']:.4g} h at "
                    f"{config.mechanism.crank_speed_rpm:g} rpm ({span['note']})" if span["revolutions"] is not None
                    else span["note"]))
            print(f"  wall time {summary['wall_time_s']:.1f} s")
            warning = replay_volume_warning(summary.get("cycle_jumping") or {})
            if warning:
                print(f"wearjoint wear-study: warning: {warning}", file=sys.stderr)
    except StudyDiverged as exc:       # its outputs for what finished are written; the message says what next
        print(f"wearjoint wear-study: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"wearjoint wear-study: interrupted; finished work is checkpointed in {args.out}"
              f"{_reached(Path(args.out))} (continue with --resume)", file=sys.stderr)
        return 130
    except (CoSimulationError, RunStopped) as exc:
        print(f"wearjoint wear-study: error: {exc}; finished work is checkpointed in {args.out}", file=sys.stderr)
        return 1
    print(f"results in {args.out}")
    return 0


# the options (dests) that set a study's, its joint's or its mechanism's field, where not the field's name alone
_SET_BY = {"max_step_s": ("max_step",), "jump_block_revolutions": ("cycle_jump_block",),
           "checkpoint_every_revolutions": ("checkpoint_every",),
           "jump_tolerance": ("cycle_jump_tolerance", "no_cycle_jump", "wear_factor", "no_wear"),
           "wear_factor": ("wear_factor", "no_wear"), "wear_coefficient_m2_N": ("wear_coefficient_m2_N", "calibration")}


def _resumed_config(config: WearStudyConfig, args) -> WearStudyConfig:
    """The study ``--resume`` continues: the settings of the checkpoint in ``--out``, each one the command line
    wrote (``args.written``) from ``config`` instead; run_wear_study then refuses a written physical setting that
    differs, naming it.  ``config`` itself where the checkpoint's settings do not make a study (its own message)."""
    written = getattr(args, "written", None)
    if written is None:
        return config

    def merged(checkpointed: dict, given: dict) -> dict:
        return {k: given[k] if set(_SET_BY.get(k, (k,))) & written else v for k, v in checkpointed.items()}

    try:
        old = read_checkpoint(Path(args.out) / CHECKPOINT_NAME)["config"]
        study = merged({k: v for k, v in old.items() if k not in DERIVED}, config.to_dict())
        if study["revolutions"] != old["revolutions"] and "snapshots" not in written:
            study["snapshots"] = config.snapshots            # they follow --revolutions: its quarters
        return WearStudyConfig(**{**study, "snapshots": tuple(study["snapshots"]),
                                  "joint": JointParameters(**merged(old["joint"], config.joint.to_dict())),
                                  "mechanism": SliderCrankParameters.from_dict(merged(old["mechanism"],
                                                                                      config.mechanism.to_dict()))})
    except (ParameterError, KeyError, TypeError, ValueError):
        return config


def _refuse_unread(args) -> None:
    """The options the command's task leaves unread, refused in one line (each had been taken without a word):
    another task beside --convergence, a life or a wear factor beside a task that runs studies of its own, a
    cycle-jump block without cycle jumping."""
    task = ("--convergence" if args.convergence is not None else
            "--calibrate-max-depth-m" if args.calibrate_max_depth_m is not None else None)
    converging = args.convergence is not None
    require("--calibrate-max-depth-m", args.calibrate_max_depth_m, not (converging and args.calibrate_max_depth_m
            is not None), "without --convergence (one task a command)")
    require("--life-depth-m", args.life_depth_m, task is None or args.life_depth_m is None,
            f"without {task} (its studies state none: calibrate --life-depth-m on a study)")
    require("--wear-factor", args.wear_factor, not (converging and args.wear_factor is not None),
            "without --convergence (the factors are --convergence's)")
    require("--cycle-jump-block", args.cycle_jump_block, task is not None or args.cycle_jump_block
            == WearStudyConfig.jump_block_revolutions or not (args.no_cycle_jump or args.wear_factor is not None),
            "only with cycle jumping (not with --no-cycle-jump or --wear-factor)")


def _check_out(args, ensemble: bool) -> None:
    """--out refused in one line where it holds the other kind of study (a single study, an ensemble of --seeds), and
    --resume where --out holds nothing to continue (it never starts afresh)."""
    from ..sweep.runner import SPEC_NAME

    out = Path(args.out)
    single = (out / CHECKPOINT_NAME).is_file() or (out / SNAPSHOTS_NAME).is_file()
    if ensemble and single:
        raise ParameterError(f"--out={str(out)!r} is invalid with --seeds {args.seeds}: it holds a single wear study "
                             f"({CHECKPOINT_NAME}); allowed a folder of the ensemble's own")
    if not ensemble and (out / SPEC_NAME).is_file():
        raise ParameterError(f"--out={str(out)!r} is invalid without --seeds: it holds an ensemble ({SPEC_NAME}); "
                             "continue it with the options that started it, --seeds N included, and --resume, or "
                             "choose another --out")
    if not args.resume or ensemble:     # an ensemble's: the sweep's --resume check (sweep.runner.resumed)
        return
    if args.convergence is not None or args.calibrate_max_depth_m is not None:    # a study per subfolder
        held, what = any(out.glob(f"*/{CHECKPOINT_NAME}")), f"*/{CHECKPOINT_NAME}"
    else:
        held, what = (out / CHECKPOINT_NAME).is_file(), CHECKPOINT_NAME
    if not held:
        raise ParameterError(f"--resume is invalid with --out {str(out)!r}: it holds no study to continue (no {what}); "
                             "allowed on a folder a wear-study checkpointed (run without --resume to start one)")


def _reached(out: Path) -> str:
    """`` up to revolution N`` of a single study's checkpoint in ``out`` ('' where there is none to read: an ensemble,
    a study stopped before its first checkpoint)."""
    try:
        return f" up to revolution {checkpoint_revolution(read_checkpoint(out / CHECKPOINT_NAME)):.6g}"
    except (ParameterError, StateError, KeyError, TypeError):
        return ""


def _angle(value) -> str:
    return "-" if value is None else f"{value:.1f}"


def _number(value, spec: str) -> str:
    return "-" if value is None else format(value, spec)


__all__ = ["add_arguments", "run"]
