"""`wearjoint simulate`: the monolithic run from the command line."""
from __future__ import annotations


from ..results import write_results
from ..parameters import MAX_WEAR_STEP_S
from ..simulate import (
    DEFAULT_WEAR_STEP_SHARE, DOPRI_WEAR_CONTACT_STEP_S, GEAR_JACOBIANS, GEAR_SOLVERS, INTEGRATORS, NO_WEAR_MAX_STEP_S,
    SimulationOptions, run_simulation,
)
from .options import (
    add_initial_profile_argument, add_model_arguments, add_output_arguments, add_settling_argument, check_settling,
    exit_status, model_from_args, print_summary, read_initial_profile,
)

_DEFAULTS = SimulationOptions()


def add_integration_arguments(parser) -> None:
    g = parser.add_argument_group("integration")
    g.add_argument("--revolutions", type=float, default=_DEFAULTS.revolutions, help="crank revolutions to simulate")
    g.add_argument("--integrator", choices=INTEGRATORS, default=_DEFAULTS.integrator,
                   help="rk4 (fixed step), dopri (adaptive Dormand-Prince 5(4)), gear (BDF, the paper's method)")
    g.add_argument("--gear-solver", choices=GEAR_SOLVERS, default=_DEFAULTS.gear_solver,
                   help="BDF of --integrator gear: SUNDIALS CVODE (scikit-sundae) or scipy's")
    g.add_argument("--gear-jacobian", choices=GEAR_JACOBIANS, default=_DEFAULTS.gear_jacobian,
                   help="Jacobian of --integrator gear: exact (the contact's with the mechanism's) or the solver's "
                        "finite differences")
    g.add_argument("--step", type=float, default=_DEFAULTS.step_s, help="RK4 step [s]")
    g.add_argument("--rtol", type=float, default=_DEFAULTS.rtol, help="relative tolerance (dopri, gear)")
    g.add_argument("--atol-position", type=float, default=_DEFAULTS.atol_position_m, help="absolute tolerance on positions [m, rad]")
    g.add_argument("--atol-velocity", type=float, default=_DEFAULTS.atol_velocity_m_s, help="absolute tolerance on velocities [m/s, rad/s]")
    g.add_argument("--max-step", type=float, default=None,
                   help=f"largest step [s] (default {NO_WEAR_MAX_STEP_S:g}; with wear {MAX_WEAR_STEP_S:g}, dopri "
                        f"{DOPRI_WEAR_CONTACT_STEP_S:g}, less where a step's share of the penetration would pass "
                        f"{DEFAULT_WEAR_STEP_SHARE:g}; at most {MAX_WEAR_STEP_S:g} and a share of 4: docs/reference/model.md §7)")
    free_flight = f"(default {NO_WEAR_MAX_STEP_S:g}; --max-step when that is given)"
    g.add_argument("--free-flight-max-step", type=float, default=None,
                   help="dopri: largest step that starts with no contact [s], where nothing wears " + free_flight)
    g.add_argument("--sample-dt", type=float, default=_DEFAULTS.sample_dt_s, help="time-series spacing [s]")
    g.add_argument("--ideal", action="store_true", help="ideal crank-rod revolute (no clearance)")
    add_initial_profile_argument(g)


def options_from_args(args) -> SimulationOptions:
    return SimulationOptions(revolutions=args.revolutions, integrator=args.integrator, step_s=args.step,
                             rtol=args.rtol, atol_position_m=args.atol_position,
                             atol_velocity_m_s=args.atol_velocity, max_step_s=args.max_step,
                             free_flight_max_step_s=args.free_flight_max_step,
                             sample_dt_s=args.sample_dt, ideal=args.ideal, gear_solver=args.gear_solver,
                             gear_jacobian=args.gear_jacobian)


def add_arguments(parser) -> None:
    add_output_arguments(parser)
    add_settling_argument(parser)
    add_integration_arguments(parser)
    add_model_arguments(parser)


def run(args) -> int:
    joint, mechanism = model_from_args(args)
    options = options_from_args(args)
    settling = check_settling(args)
    profile = None if args.initial_profile is None else read_initial_profile(args.initial_profile, joint)
    record = run_simulation(joint, mechanism, options, progress=not args.quiet, initial_profile_m=profile)
    record.settling_revolutions = settling
    summary = write_results(record, args.out, plots=not args.no_plots)
    print_summary(summary, args.out, ("integrator_accepted_steps", "integrator_rejected_steps"))
    return exit_status(record, "simulate")


__all__ = ["add_arguments", "run", "add_integration_arguments", "options_from_args"]
