"""`wearjoint sweep COMMAND [sweep options] [COMMAND's options]`: a grid of cases times an
ensemble of seeds, each case one run of COMMAND (simulate, cosim, wear-study), run as Dask
tasks (:mod:`wearjoint.sweep`, docs/how-to/sweep_on_dask.md).  Exit status 0 when every case is ok, 1 when
some failed, 2 for bad input, 130 after Ctrl-C (finished cases kept; continue with --resume)."""
from __future__ import annotations

import argparse
import os
import sys

from .._compile.prefetch import usable_cores
from ..parameters import ParameterError
from ..sweep.bias import Bias
from ..sweep.design import SEED_ANGLE_STEP_DEG, TARGETS, command_options, sweep_design
from ..sweep.limits import check_cluster, check_seeds, check_workers
from ..targets import target as sweep_target
from . import OneLineErrorParser
from .out_folder import prepare_out_folder

DEFAULT_SEEDS = 1   # runs per grid point when neither --seeds nor the design file says


def add_arguments(parser) -> None:
    parser.add_argument("target", choices=TARGETS, metavar="COMMAND",
                        help="the command each case runs: " + ", ".join(TARGETS))
    parser.add_argument("options", nargs=argparse.REMAINDER,
                        help="sweep options and COMMAND's options (wearjoint sweep COMMAND --help lists them)")


def add_ensemble_arguments(parser) -> None:
    """--seeds, --workers, --scheduler (each only if ``parser`` lacks it)."""
    g = parser.add_argument_group("ensemble (Dask)")
    _add(parser, g, "--seeds", type=int, default=None,
         help=f"runs per grid point; seed s starts the crank s*{SEED_ANGLE_STEP_DEG:g} deg further "
              f"(default {DEFAULT_SEEDS})")
    _add(parser, g, "--workers", type=int, default=None,
         help="worker processes of the local Dask cluster (default: one per core)")
    _add(parser, g, "--scheduler", default=None, metavar="ADDRESS",
         help="submit to the Dask cluster at ADDRESS (e.g. tcp://host:8786) instead of a local cluster")


def _add(parser, group, flag, **kwargs) -> None:
    if flag not in parser._option_string_actions:
        group.add_argument(flag, **kwargs)


def study_parser(study: str, target: str, description: str) -> argparse.ArgumentParser:
    """The head of the parser of ``wearjoint STUDY TARGET`` (sweep, sensitivity): TARGET's own options (the
    target's, :mod:`wearjoint.targets`) and the ensemble's; the study adds its group."""
    parser = OneLineErrorParser(prog=f"wearjoint {study} {target}", allow_abbrev=False, description=description)
    sweep_target(target).add_arguments(parser)
    add_ensemble_arguments(parser)
    return parser


def target_parser(target: str) -> argparse.ArgumentParser:
    """The parser of ``wearjoint sweep TARGET``: TARGET's own options plus the sweep's."""
    parser = study_parser("sweep", target, f"run wearjoint {target} over a grid of parameter values and seeds "
                                           "as Dask tasks")
    g = parser.add_argument_group("sweep")
    g.add_argument("--vary", action="append", default=[], metavar="NAME=V1,V2,...",
                   help="values of one option (written without its dashes, e.g. restitution=0.6,0.9); "
                        "repeat for a grid")
    g.add_argument("--design", default=None, metavar="FILE.toml",
                   help="a TOML design: seeds = N, [vary] name = [values] (a grid), [[case]] tables (points)")
    _add(parser, g, "--resume", action="store_true", help="run only the cases not yet done in --out")
    g.add_argument("--retry-failed", action="store_true", help="with --resume: run the failed cases again")
    parser.set_defaults(seeds=None)
    return parser


def run(args) -> int:
    target = target_parser(args.target).parse_args(args.options)
    args.out = target.out                        # the results folder, for its report (wearjoint.cli.main)
    # --out is the target's option: checked once parsed; the folders it makes go if the run is refused
    args.out_folders_made = prepare_out_folder("sweep", target.out, "--out")
    return run_from_args(args.target, target)


def run_from_args(command: str, args) -> int:
    """Run the sweep ``args`` describes (TARGET's options plus the sweep's); prints the outcome."""
    from ..sweep import run_sweep

    if getattr(args, "retry_failed", False) and not args.resume:
        raise ParameterError("--retry-failed is invalid without --resume: allowed with --resume (it runs the failed "
                             "cases of the sweep in --out again)")
    design = sweep_design(command, getattr(args, "vary", None), getattr(args, "design", None))
    seeds = args.seeds if args.seeds is not None else design["seeds"]
    seeds = check_seeds(DEFAULT_SEEDS if seeds is None else seeds)
    check_cluster(args.workers, args.scheduler)
    workers = check_workers(args.workers) if args.workers is not None else usable_cores()
    try:
        summary = run_sweep(command, command_options(command, args), args.out, vary=design["vary"],
                            points=design["points"], seeds=seeds, no_plots=getattr(args, "no_plots", False),
                            workers=workers, scheduler=args.scheduler, resume=args.resume,
                            retry_failed=getattr(args, "retry_failed", False), progress=not args.quiet,
                            where=design["where"])
    except KeyboardInterrupt:
        summary = {"interrupted": True}
    if summary.get("interrupted"):
        name = "sweep" if getattr(args, "vary", None) is not None else f"{command} --seeds"   # wear-study's ensemble
        print(f"wearjoint {name}: interrupted; finished cases are kept in {args.out} (continue with --resume)",
              file=sys.stderr)
        return 130
    print_outcome(summary, args.out)
    return 1 if summary["failed"] else 0


def print_outcome(summary: dict, out) -> None:
    """Counts, each grid point's values and key figures (mean +- std over seeds, and the wear
    factor's bias beside them), the notes on that bias, the failed cases."""
    import csv

    from ..sweep.report import BIAS_NOTE, regime_line

    def counted(n: int, what: str) -> str:
        return f"{n} {what}{'' if n == 1 else 's'}"

    print(f"  {counted(summary['cases'], 'case')} ({counted(summary['grid_points'], 'grid point')} x "
          f"{counted(summary['seeds'], 'seed')}): "
          f"{summary['ok']} ok, {summary['failed']} failed, {summary['skipped_as_done']} already done; "
          f"{summary['wall_time_s']:.1f} s")
    notes = {}
    with open(os.path.join(out, "ensemble.csv"), newline="") as f:
        reader = csv.DictReader(f)
        names = reader.fieldnames[1:reader.fieldnames.index("n_ok")]
        for row in reader:
            snapshots = sorted((int(k[3:].split("_")[0]), k[:-5]) for k in row
                               if k.startswith("rev") and k.endswith("_max_wear_depth_m_mean"))
            keys = ["max_wear_depth_m"] + [key for _, key in snapshots] + ["life_revolutions", "life_hours"]
            values = ", ".join(f"{name}={row[name]}" for name in names) or "base case"
            print(f"  point {row['point']} ({values}): {row['n_ok']} ok  "
                  + "  ".join(filter(None, (_mean_std(row, k) for k in keys))))
            if regime_line(row):
                print(f"    {regime_line(row)}")
            if row.get("life_reached_mean") and float(row["life_reached_mean"]) < 1.0:
                reached = round(float(row["life_reached_mean"]) * int(row["n_ok"]))
                print(f"    the life's depth (--life-depth-m) reached by {reached} of {row['n_ok']} seeds: the others "
                      "stop short of it (a longer study: more --revolutions)")
            notes.update(dict.fromkeys(filter(None, (row.get(BIAS_NOTE) or "").split(" | "))))
    for note in notes:
        print(f"  wear-factor bias of {note}")
    for failure in summary["failures"][:10]:
        print(f"  failed {failure['case_id']} (seed {failure['seed']}): {failure['error']}")
    print(f"results in {out}")


def _mean_std(row: dict, key: str) -> str:
    """``KEY mean ± std (bias B)``: the seeds' scatter and, where the run states it, the wear factor's bias."""
    mean, std, bias = row.get(f"{key}_mean"), row.get(f"{key}_std"), row.get(f"{key}_bias_rel")
    if not mean:
        return ""
    text = f"{key} {float(mean):.4g}" + (f" ± {float(std):.2g}" if std else "")
    if bias:
        text += f" (bias {Bias.from_csv(bias).text})"
    return text


__all__ = ["add_arguments", "run", "run_from_args", "add_ensemble_arguments", "target_parser", "DEFAULT_SEEDS"]
