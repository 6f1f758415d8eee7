"""`wearjoint cosim`: the FMU co-simulation from the command line."""
from __future__ import annotations

import sys

from ..cosim import SCHEMES, CoSimulationError, CoSimulationOptions, run_cosimulation
from ..results import write_results
from .options import add_fmu_arguments, add_model_arguments, add_output_arguments, model_from_args, print_summary

_DEFAULTS = CoSimulationOptions()
COMMUNICATION_KEYS = ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s")


def add_arguments(parser) -> None:
    """Options of ``wearjoint cosim``: results folder, FMU, coupling, and every model parameter."""
    add_output_arguments(parser)
    add_fmu_arguments(parser)
    g = parser.add_argument_group("co-simulation")
    g.add_argument("--revolutions", type=float, default=_DEFAULTS.revolutions, help="crank revolutions to simulate")
    g.add_argument("--scheme", choices=SCHEMES, default=_DEFAULTS.scheme,
                   help="zoh: fixed communication step, forces held; extrapolation: fixed step, forces "
                        "extrapolated in contact; adaptive: extrapolation, large steps in free flight, "
                        "rollback to contact onsets (default %(default)s)")
    g.add_argument("--step", type=float, default=_DEFAULTS.step_s,
                   help="communication step [s] (adaptive: in contact) (default %(default)g)")
    g.add_argument("--max-step", type=float, default=_DEFAULTS.max_step_s,
                   help="largest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--min-step", type=float, default=_DEFAULTS.min_step_s,
                   help="smallest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--onset-penetration", type=float, default=_DEFAULTS.onset_penetration_m,
                   help="how deep past a contact onset an adaptive step may end [m] (default %(default)g)")
    g.add_argument("--sample-dt", type=float, default=_DEFAULTS.sample_dt_s, help="time-series spacing [s]")
    add_model_arguments(parser)


def run(args) -> int:
    """Run, write the results folder, print the summary; 1 with a one-line message on an FMU error."""
    joint, mechanism = model_from_args(args)
    options = CoSimulationOptions(revolutions=args.revolutions, scheme=args.scheme, step_s=args.step,
                                  max_step_s=args.max_step, min_step_s=args.min_step,
                                  onset_penetration_m=args.onset_penetration, sample_dt_s=args.sample_dt)
    try:
        record = run_cosimulation(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet,
                                  fmu_backend=args.fmu_backend)
    except CoSimulationError as exc:
        print(f"wearjoint cosim: error: {exc}", file=sys.stderr)
        return 1
    summary = write_results(record, args.out, plots=not args.no_plots)
    print_summary(summary, args.out, COMMUNICATION_KEYS)
    return 0 if record.completed else 130


__all__ = ["add_arguments", "run"]
