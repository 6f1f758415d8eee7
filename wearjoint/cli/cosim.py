"""`wearjoint cosim`: the FMU co-simulation from the command line (its options and configuration are the sweeps'
target's, :mod:`wearjoint.targets`)."""
from __future__ import annotations

import sys

from ..cosim import CoSimulationError
from ..cosim.step_rule import unchecked_step_note
from ..interrupts import results_kept
from ..results import write_results
from ..run_options import add_cosim_arguments as add_arguments
from ..targets import cosim_config, cosim_record
from .options import exit_status, model_notes, print_summary

COMMUNICATION_KEYS = ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s")
INTEGRATOR_KEYS = ("integrator_accepted_steps", "integrator_rejected_steps")


def compiles(args) -> bool:
    """Whether the run may compile numba kernels: not with this package's co-simulation master once its library is
    built (cosim.native_master: its loop and the run's kernels come compiled)."""
    if args.master != "wearjoint" or args.fmu_interface != "co-simulation":
        return True             # Model Exchange runs the monolithic integrators; a third-party run's record, numba's
    from ..cosim.native_master import native_master

    return native_master(build=False) is None


def compiled_kernels(args) -> str:
    """The compile notice's key of the kernels the run compiles (wearjoint._compile.notice.ESTIMATES): through the
    FMU's Model Exchange interface the monolithic engine's, in a third-party master those that make its trace the
    run's record, else the co-simulation master's."""
    if args.master != "wearjoint":
        return "cosim-trace"
    return "cosim-me" if args.fmu_interface == "model-exchange" else "cosim"


def run(args) -> int:
    """Run, write the results folder, print the summary; 1 with a one-line message on an FMU error,
    2 on a bad option (one line naming it)."""
    config = cosim_config(vars(args))
    model_notes(config.joint, config.mechanism, args)
    if config.master != "wearjoint" and not args.quiet:
        note = unchecked_step_note(config.step_s, config.load_coupling, config.joint, config.mechanism)
        if note:
            print(f"note: {note}", file=sys.stderr)
    with results_kept():           # Ctrl-C after the run waits for its results
        try:
            record = cosim_record(config, progress=not args.quiet)
        except (CoSimulationError, RuntimeError) as exc:
            print(f"wearjoint cosim: error: {exc}", file=sys.stderr)
            return 1
        summary = write_results(record, args.out, plots=not args.no_plots,
                                figure_worker=getattr(args, "figure_worker", None))   # started by cli.main
        keys = (("master", "communication_steps") if config.master != "wearjoint" else
                INTEGRATOR_KEYS if config.interface == "model-exchange" else COMMUNICATION_KEYS)
        print_summary(summary, args, keys)
    return exit_status(record, "cosim")


__all__ = ["add_arguments", "compiled_kernels", "compiles", "run"]
