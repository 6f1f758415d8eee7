"""`wearjoint cosim`: the FMU co-simulation from the command line."""
from __future__ import annotations

import sys

from ..cosim import SCHEMES, CoSimulationError, CoSimulationOptions, run_cosimulation
from ..cosim.model_exchange import INTERFACES, run_model_exchange
from ..results import write_results
from ..simulate import SimulationOptions
from .options import add_fmu_arguments, add_model_arguments, add_output_arguments, model_from_args, print_summary

_DEFAULTS = CoSimulationOptions()
COMMUNICATION_KEYS = ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s")
INTEGRATOR_KEYS = ("integrator_accepted_steps", "integrator_rejected_steps")
_MONOLITHIC = SimulationOptions()


def add_arguments(parser) -> None:
    """Options of ``wearjoint cosim``: results folder, FMU, coupling, and every model parameter."""
    add_output_arguments(parser)
    add_fmu_arguments(parser)
    parser.add_argument("--fmu-interface", choices=INTERFACES, default="co-simulation",
                        help="co-simulation: this master exchanges with the FMU at communication steps (the "
                             "options below); model-exchange: the mechanism and the FMU's joint in one integrator, "
                             "the same adaptive Dormand-Prince as `simulate` (its tolerances: --rtol, --atol-*, "
                             "--max-step) (default %(default)s)")
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
    me = parser.add_argument_group("model exchange (--fmu-interface model-exchange)")
    me.add_argument("--rtol", type=float, default=_MONOLITHIC.rtol, help="relative tolerance (default %(default)g)")
    me.add_argument("--atol-position", type=float, default=_MONOLITHIC.atol_position_m,
                    help="absolute tolerance of positions [m] (default %(default)g)")
    me.add_argument("--atol-velocity", type=float, default=_MONOLITHIC.atol_velocity_m_s,
                    help="absolute tolerance of velocities [m/s] (default %(default)g)")
    add_model_arguments(parser)


def run(args) -> int:
    """Run, write the results folder, print the summary; 1 with a one-line message on an FMU error."""
    joint, mechanism = model_from_args(args)
    try:
        if args.fmu_interface == "model-exchange":
            max_step = args.max_step if args.max_step != _DEFAULTS.max_step_s else (
                1e-5 if joint.wear_coefficient_m2_N * joint.wear_factor > 0 else _MONOLITHIC.max_step_s)
            options = SimulationOptions(revolutions=args.revolutions, integrator="dopri", rtol=args.rtol,
                                        atol_position_m=args.atol_position, atol_velocity_m_s=args.atol_velocity,
                                        max_step_s=max_step, onset_penetration_m=args.onset_penetration,
                                        sample_dt_s=args.sample_dt)
            record = run_model_exchange(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet,
                                        fmu_backend=args.fmu_backend)
            keys = INTEGRATOR_KEYS
        else:
            options = CoSimulationOptions(revolutions=args.revolutions, scheme=args.scheme, step_s=args.step,
                                          max_step_s=args.max_step, min_step_s=args.min_step,
                                          onset_penetration_m=args.onset_penetration, sample_dt_s=args.sample_dt)
            record = run_cosimulation(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet,
                                      fmu_backend=args.fmu_backend)
            keys = COMMUNICATION_KEYS
    except CoSimulationError as exc:
        print(f"wearjoint cosim: error: {exc}", file=sys.stderr)
        return 1
    summary = write_results(record, args.out, plots=not args.no_plots)
    print_summary(summary, args.out, keys)
    return 0 if record.completed else 130


__all__ = ["add_arguments", "run"]
