"""`wearjoint cosim-study`: co-simulation error versus communication step and coupling scheme
(:mod:`wearjoint.studies.cosim_study`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..parameters import ParameterError, require
from ..studies.cosim_study import PAPER_STEPS_S, run_study, write_study
from .options import add_fmu_arguments, add_model_arguments, model_from_args


def add_arguments(parser) -> None:
    parser.add_argument("--out", type=Path, required=True, help="output folder (created)")
    parser.add_argument("--revolutions", type=float, default=2.0, help="crank revolutions per run")
    parser.add_argument("--steps", type=float, nargs="+", default=None,
                        help="communication steps [s] (default: " + ", ".join(f"{s:g}" for s in PAPER_STEPS_S)
                             + " on the paper's mechanism, scaled by the step rule for others: docs/explanation/cosim_study.md)")
    parser.add_argument("--schemes", nargs="+", default=["zoh", "extrapolation", "adaptive"],
                        help="coupling schemes")
    add_fmu_arguments(parser)
    parser.add_argument("--replot", type=Path, default=None, metavar="JSON",
                        help="only redo the table and figure from a previous cosim_study.json")
    add_model_arguments(parser, skip=("wear_factor",))
    parser.epilog = ("The model options set the mechanism and the joint (its wear factor is the study's 0.01); "
                     "the point-wise window is 15 ms of the paper's 0.4 s crank period, scaled with yours.")


def run(args) -> int:
    """Run the study (or reload it with --replot), write its files, print the table."""
    if args.replot is not None:
        study = json.loads(args.replot.read_text())
    else:
        if args.no_wear:          # a ParameterError is one line from the CLI's dispatch (exit status 2)
            raise ParameterError("--no-wear is not allowed here: the study compares the profiles worn at wear "
                                 "factor 0.01")
        joint, mechanism = model_from_args(args)
        for step in args.steps or ():
            require("--steps", step, step > 0.0, "communication steps > 0 [s]")
        study = run_study(args.revolutions, args.steps, args.schemes, fmu_path=args.fmu,
                          log=lambda m: print(m, file=sys.stderr, flush=True), fmu_backend=args.fmu_backend,
                          joint=joint, mechanism=mechanism)
    print(write_study(study, args.out))
    return 0


__all__ = ["add_arguments", "run"]
