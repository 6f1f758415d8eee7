"""`wearjoint cosim-study`: co-simulation error versus communication step and coupling scheme
(:mod:`wearjoint.studies.cosim_study`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..checks import RunStopped, path as path_argument
from ..cosim.master_layout import SCHEMES
from ..parameters import ParameterError
from ..studies.cosim_study import PAPER_STEPS_S, failed_runs, markdown_table, run_study, study_plan, write_study
from .options import add_fmu_arguments, add_model_arguments, model_from_args, require_option, with_options

# the options by the names the study's check gives their values (wearjoint.studies.cosim_study.study_plan)
STUDY_OPTIONS = {"revolutions": "--revolutions", "step_s": "--steps", "scheme": "--schemes", "fmu_path": "--fmu"}


def add_arguments(parser) -> None:
    parser.add_argument("--out", type=path_argument, required=True, help="output folder (created)")
    parser.add_argument("--revolutions", type=float, default=2.0, help="crank revolutions per run (default %(default)s)")
    parser.add_argument("--steps", type=float, nargs="+", default=None,
                        help="communication steps [s] (default: " + ", ".join(f"{s:g}" for s in PAPER_STEPS_S)
                             + " on the paper's mechanism, scaled by the step rule for others: docs/explanation/cosim_study.md)")
    parser.add_argument("--schemes", nargs="+", default=["zoh", "extrapolation", "adaptive"],
                        help="coupling schemes (default zoh extrapolation adaptive; any of " + ", ".join(SCHEMES) + ")")
    add_fmu_arguments(parser)
    parser.add_argument("--replot", type=path_argument, default=None, metavar="JSON",
                        help="only redo the table and figure from a previous cosim_study.json")
    add_model_arguments(parser, skip=("wear_factor",))
    parser.epilog = ("The model options set the mechanism and the joint (its wear factor is the study's 0.01); "
                     "the point-wise window is 15 ms of the paper's 0.4 s crank period, scaled with yours.")


def run(args) -> int:
    """Run the study (or reload it with --replot), write its files, print the table; exit status 1 (one line on
    stderr) if a co-simulation failed or diverged, its row saying so."""
    if args.replot is not None:
        study = _read_study(args.replot)
    else:
        joint, mechanism = model_from_args(args)
        require_option("--schemes", " ".join(args.schemes), len(set(args.schemes)) == len(args.schemes),
                       "distinct names from " + ", ".join(SCHEMES))
        try:
            study_plan(args.revolutions, args.steps, args.schemes, args.fmu, joint, mechanism)
        except ParameterError as exc:
            raise with_options(exc, STUDY_OPTIONS) from None
        try:
            study = run_study(args.revolutions, args.steps, args.schemes, fmu_path=args.fmu,
                              log=lambda m: print(m, file=sys.stderr, flush=True), fmu_backend=args.fmu_backend,
                              joint=joint, mechanism=mechanism)
        except RunStopped as exc:
            print(f"wearjoint cosim-study: error: {exc}", file=sys.stderr)
            return 1
    print(write_study(study, args.out))
    failed = failed_runs(study)
    if failed and args.replot is None:
        cosims = sum(r["engine"] == "cosim" for r in study["rows"])
        print(f"wearjoint cosim-study: error: {len(failed)} of {cosims} co-simulations failed (their rows say so, "
              f"with no numbers): {'; '.join(r['run'] + ': ' + r['failed'].split(';')[0] for r in failed)}",
              file=sys.stderr)
        return 1
    return 0


def _read_study(path: Path) -> dict:
    """The study in a cosim_study.json that cosim-study wrote, refused in one line naming --replot otherwise."""
    try:
        study = json.loads(path.read_text())
        markdown_table(study)           # every key the table and figure read
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ParameterError(f"--replot={str(path)!r} is invalid: allowed a cosim_study.json that cosim-study wrote "
                             f"({type(exc).__name__}: {exc})") from None
    return study


__all__ = ["add_arguments", "run"]
