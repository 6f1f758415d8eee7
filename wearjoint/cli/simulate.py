"""`wearjoint simulate`: the monolithic run from the command line (its options and configuration are the sweeps'
target's, :mod:`wearjoint.targets`)."""
from __future__ import annotations

from ..interrupts import results_kept
from ..results import write_results
from ..run_options import add_simulate_arguments as add_arguments
from ..targets import simulate_config, simulate_record
from .options import exit_status, model_notes, print_summary


def compiled_kernels(args) -> str:
    """The compile notice's key of the kernels the run compiles (wearjoint._compile.notice.ESTIMATES): BDF's
    (the mechanism's Jacobian too) or the explicit integrators'."""
    return "simulate-gear" if args.integrator == "gear" else "simulate"


def run(args) -> int:
    config = simulate_config(vars(args))
    model_notes(config.joint, config.mechanism, args)
    with results_kept():           # Ctrl-C after the run waits for its results
        record = simulate_record(config, progress=not args.quiet)
        summary = write_results(record, args.out, plots=not args.no_plots,
                                figure_worker=getattr(args, "figure_worker", None))   # started by cli.main
        print_summary(summary, args, ("integrator_accepted_steps", "integrator_rejected_steps"))
    return exit_status(record, "simulate")


__all__ = ["add_arguments", "run"]
