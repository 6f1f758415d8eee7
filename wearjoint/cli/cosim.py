"""`wearjoint cosim`: the FMU co-simulation from the command line."""
from __future__ import annotations

import sys

from ..cosim import SCHEMES, CoSimulationError, CoSimulationOptions, run_cosimulation
from ..cosim.masters import DEFAULT_STEP_S, MASTERS, master_available, run_master
from ..cosim.model_exchange import INTERFACES, run_model_exchange
from ..parameters import finite, require
from ..results import write_results
from ..simulate import SimulationOptions
from .options import (
    add_fmu_arguments, add_initial_profile_argument, add_model_arguments, add_output_arguments, add_settling_argument,
    check_settling, exit_status, model_from_args, print_summary, read_initial_profile,
)

_DEFAULTS = CoSimulationOptions()
COMMUNICATION_KEYS = ("communication_steps", "rollbacks", "fmi_time_s", "master_time_s")
INTEGRATOR_KEYS = ("integrator_accepted_steps", "integrator_rejected_steps")
_MONOLITHIC = SimulationOptions()


def add_arguments(parser) -> None:
    """Options of ``wearjoint cosim``: results folder, FMU, coupling, and every model parameter."""
    add_output_arguments(parser)
    add_settling_argument(parser)
    add_fmu_arguments(parser)
    parser.add_argument("--fmu-interface", choices=INTERFACES, default="co-simulation",
                        help="co-simulation: this master exchanges with the FMU at communication steps (the "
                             "options below); model-exchange: the mechanism and the FMU's joint in one integrator, "
                             "the same adaptive Dormand-Prince as `simulate` (its tolerances: --rtol, --atol-*, "
                             "--max-step) (default %(default)s)")
    g = parser.add_argument_group("co-simulation")
    g.add_argument("--master", default="wearjoint", metavar="MASTER",
                   help=f"who runs the co-simulation, one of {', '.join(MASTERS)}: wearjoint is this package's master "
                        "(the options below); the others run SliderCrankWithClearance.ssp (export-ssp) at the fixed "
                        "step --step: OSP libcosim, ecos, fmpy's SSP simulator, OpenModelica's OMSimulator (its Python "
                        "package importable: pip install omsimulator, or a build's lib/<platform> on PYTHONPATH), or "
                        "the system as one fmpy container FMU in fmpy (or in fmusim with --fmusim) (default "
                        "%(default)s)")
    g.add_argument("--fmusim", metavar="PATH", default=None,
                   help="with --master container: run the container FMU in this fmusim binary instead of fmpy")
    g.add_argument("--revolutions", type=float, default=_DEFAULTS.revolutions, help="crank revolutions to simulate")
    g.add_argument("--scheme", choices=SCHEMES, default=_DEFAULTS.scheme,
                   help="zoh: fixed communication step, forces held; extrapolation: fixed step, forces "
                        "extrapolated in contact; adaptive: extrapolation, large steps in free flight, "
                        "rollback to contact onsets (default %(default)s)")
    g.add_argument("--step", type=float, default=None,
                   help=f"communication step [s] (adaptive: in contact) (default {_DEFAULTS.step_s:g}; with a "
                        f"third-party master {DEFAULT_STEP_S:g}, a fixed step)")
    g.add_argument("--max-step", type=float, default=_DEFAULTS.max_step_s,
                   help="largest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--min-step", type=float, default=_DEFAULTS.min_step_s,
                   help="smallest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--onset-penetration", type=float, default=_DEFAULTS.onset_penetration_m,
                   help="how deep past a contact onset an adaptive step may end [m] (default %(default)g)")
    g.add_argument("--sample-dt", type=float, default=_DEFAULTS.sample_dt_s, help="time-series spacing [s]")
    add_initial_profile_argument(g)
    me = parser.add_argument_group("model exchange (--fmu-interface model-exchange)")
    me.add_argument("--rtol", type=float, default=_MONOLITHIC.rtol, help="relative tolerance (default %(default)g)")
    me.add_argument("--atol-position", type=float, default=_MONOLITHIC.atol_position_m,
                    help="absolute tolerance of positions [m] (default %(default)g)")
    me.add_argument("--atol-velocity", type=float, default=_MONOLITHIC.atol_velocity_m_s,
                    help="absolute tolerance of velocities [m/s] (default %(default)g)")
    add_model_arguments(parser)


def _third_party(args, joint, mechanism):
    """The run record of the third-party ``args.master`` (checked: installed, step > 0)."""
    missing = master_available(args.master)
    if missing is not None:
        installed = [m for m in MASTERS if m == "wearjoint" or master_available(m) is None]
        require("--master", args.master, False,
                 f"one of the masters installed here, {', '.join(installed)} ({missing})")
    step = DEFAULT_STEP_S if args.step is None else args.step
    require("--step", step, finite("--step", step) > 0.0, "a communication step > 0 [s]")
    return run_master(args.master, joint, mechanism, args.revolutions, step, args.sample_dt, fmusim=args.fmusim)


def run(args) -> int:
    """Run, write the results folder, print the summary; 1 with a one-line message on an FMU error,
    2 on a bad option (one line naming it)."""
    require("--master", args.master, args.master in MASTERS, "one of " + ", ".join(MASTERS))
    require("--fmusim", args.fmusim, args.fmusim is None or args.master == "container", "only with --master container")
    require("--initial-profile", None if args.initial_profile is None else str(args.initial_profile),
             args.initial_profile is None or args.master == "wearjoint",
             "only with --master wearjoint (it sets the FMU's state; the SSP's masters start unworn)")
    joint, mechanism = model_from_args(args)
    settling = check_settling(args)
    profile = None if args.initial_profile is None else read_initial_profile(args.initial_profile, joint)
    try:
        if args.master != "wearjoint":
            record = _third_party(args, joint, mechanism)
            keys = ("master", "communication_steps")
        elif args.fmu_interface == "model-exchange":
            # --max-step left at the master's default: SimulationOptions' own (DOPRI with wear 1e-5 s, else 1e-4 s)
            max_step = None if args.max_step == _DEFAULTS.max_step_s else args.max_step
            options = SimulationOptions(revolutions=args.revolutions, integrator="dopri", rtol=args.rtol,
                                        atol_position_m=args.atol_position, atol_velocity_m_s=args.atol_velocity,
                                        max_step_s=max_step, onset_penetration_m=args.onset_penetration,
                                        sample_dt_s=args.sample_dt)
            record = run_model_exchange(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet,
                                        fmu_backend=args.fmu_backend, initial_profile_m=profile)
            keys = INTEGRATOR_KEYS
        else:
            options = CoSimulationOptions(revolutions=args.revolutions, scheme=args.scheme,
                                          step_s=_DEFAULTS.step_s if args.step is None else args.step,
                                          max_step_s=args.max_step, min_step_s=args.min_step,
                                          onset_penetration_m=args.onset_penetration, sample_dt_s=args.sample_dt)
            record = run_cosimulation(joint, mechanism, options, fmu_path=args.fmu, progress=not args.quiet,
                                      fmu_backend=args.fmu_backend, initial_profile_m=profile)
            keys = COMMUNICATION_KEYS
    except (CoSimulationError, RuntimeError) as exc:
        print(f"wearjoint cosim: error: {exc}", file=sys.stderr)
        return 1
    record.settling_revolutions = settling
    summary = write_results(record, args.out, plots=not args.no_plots)
    print_summary(summary, args.out, keys)
    return exit_status(record, "cosim")


__all__ = ["add_arguments", "run"]
