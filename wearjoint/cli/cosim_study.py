"""`wearjoint cosim-study`: co-simulation error versus communication step and coupling scheme
(:mod:`wearjoint.validation.cosim_study`)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..validation.cosim_study import run_study, write_study
from .options import add_fmu_arguments


def add_arguments(parser) -> None:
    parser.add_argument("--out", type=Path, required=True, help="output folder (created)")
    parser.add_argument("--revolutions", type=float, default=2.0, help="crank revolutions per run")
    parser.add_argument("--steps", type=float, nargs="+", default=[1e-6, 2e-6, 5e-6, 1e-5],
                        help="communication steps [s]")
    parser.add_argument("--schemes", nargs="+", default=["zoh", "extrapolation", "adaptive"],
                        help="coupling schemes")
    add_fmu_arguments(parser)
    parser.add_argument("--replot", type=Path, default=None, metavar="JSON",
                        help="only redo the table and figure from a previous cosim_study.json")


def run(args) -> int:
    """Run the study (or reload it with --replot), write its files, print the table."""
    if args.replot is not None:
        study = json.loads(args.replot.read_text())
    else:
        study = run_study(args.revolutions, args.steps, args.schemes, fmu_path=args.fmu,
                          log=lambda m: print(m, file=sys.stderr, flush=True), fmu_backend=args.fmu_backend)
    print(write_study(study, args.out))
    return 0


__all__ = ["add_arguments", "run"]
