"""`wearjoint export-ssp`: write SliderCrankWithClearance.ssp, the paper's slider-crank as two FMUs
(SliderCrank and ClearanceWearJoint, native FMI 2.0) with their connections and parameter sets,
for any SSP master (OSP libcosim, ecos, fmpy's SSP simulator, OMSimulator); with
``--container-fmu`` also the same system as one fmpy container FMU, for any FMU importer."""
from __future__ import annotations

import math
import sys

from ..checks import require
from ..cosim.step_rule import communication_step_rule, paper_step_scale, unchecked_step_note
from ..fmu import platforms
from ..fmu.ssp import (
    CONTAINER_STEP_S, DEFAULT_STEP_S, LOAD_COUPLINGS, MIN_STEP_S, MIN_STEP_WHY, ON_TIME_STEP_S, check_stop_time,
    package_step_s,
)
from ..parameters import SliderCrankParameters, wear_coefficient_source
from ..simulation_options import check_wear_step, wear_step_limit_s
from .options import add_model_arguments, model_from_args


def add_arguments(parser) -> None:
    """Options of ``wearjoint export-ssp``."""
    parser.add_argument("--out", metavar="DIR", required=True, help="directory for SliderCrankWithClearance.ssp")
    parser.add_argument("--stop-time", type=float, default=None, metavar="S",
                        help="stop time of the default experiment [s] (default: one crank revolution, "
                             f"{SliderCrankParameters().period_s:g} s for the paper's)")
    parser.add_argument("--container-fmu", action="store_true",
                        help="also write SliderCrankWithClearance.fmu: the same system as one fmpy container FMU "
                             "(FMI 2.0 Co-Simulation; fmpy's container library: linux64, win64, darwin64)")
    parser.add_argument("--container-step", type=float, default=None, metavar="S",
                        help="the container's fixed internal step [s], the communication step of its two FMUs "
                             f"(default {CONTAINER_STEP_S:g})")
    parser.add_argument("--platforms", default="auto", metavar="LIST",
                        help="platforms the FMUs carry binaries for, of "
                             f"{', '.join(platforms.CROSS_PLATFORMS)}, or auto (default %(default)s)")
    parser.add_argument("--load-coupling", choices=LOAD_COUPLINGS, default="linearised",
                        help="how the mechanism takes the joint's loads over a communication step: linearised, "
                             "F0 + J (u - u0) from the joint's published derivatives (wired in the package); hold, "
                             "held at their values (default %(default)s)")
    parser.add_argument("--step", type=float, default=None, metavar="S",
                        help="communication step the package asks its masters for [s] (OMSimulator's and OSP's "
                             "annotations; default for the paper's mechanism "
                             + ", ".join(f"{DEFAULT_STEP_S[c]:g} s {c} ({ON_TIME_STEP_S[c]:g} s for OMSimulator)"
                                         for c in LOAD_COUPLINGS)
                             + ", scaled by the step rule for others: docs/explanation/cosim_study.md)")
    add_model_arguments(parser)
    parser.epilog = ("The model options become the parameter sets and the FMUs' start values; the joint's centres "
                     "follow the crank tip and the rod end.")


def run(args) -> int:
    """Write the package and print its path; 0 on success, 2 with a message on stderr otherwise."""
    from ..fmu.ssp import CONTAINER_FILE_NAME, container_fmu, export_ssp

    try:
        if args.container_step is not None:     # before anything is written
            require("container_step_s", args.container_step, args.container_step > 0.0 and
                    math.isfinite(args.container_step), "> 0 (the container's fixed step [s])")
        joint, mechanism = model_from_args(args)
        if args.stop_time is not None:
            check_stop_time(args.stop_time)
        container_step = _container_step(args, joint, mechanism)
        rule = communication_step_rule(joint, mechanism)
        scale = paper_step_scale(joint, mechanism)
        limit = wear_step_limit_s(joint, mechanism)
        step = on_time = args.step
        if args.step is None:        # the package's own steps (export_ssp's), for OSP's masters and OMSimulator
            step = package_step_s(args.load_coupling, scale, limit, mechanism.period_s)
            on_time = package_step_s(args.load_coupling, scale, limit, mechanism.period_s, on_time=True)
        path = export_ssp(args.out, mechanism, joint, stop_time=args.stop_time, platforms=args.platforms,
                          step_s=args.step, load_coupling=args.load_coupling, step_scale=scale)
        print(path)
        asks = (f"the package asks its masters for a communication step of {step:.3g} s, OMSimulator, which reads "
                f"the loads on time, for {on_time:.3g} s")
        if args.load_coupling == "linearised":
            print(f"{asks}; its mechanism integrates the joint's published linearisation, past the held loads' "
                  f"limit (with --load-coupling hold: {rule.text()})", file=sys.stderr)
        else:
            print(f"{rule.text()}; {asks}", file=sys.stderr)
        for note in (unchecked_step_note(step, args.load_coupling, joint, mechanism),
                     wear_coefficient_source(joint, mechanism)["wear_coefficient_note"]):
            if note:
                print(f"note: {note}", file=sys.stderr)
        if args.container_fmu or args.container_step is not None:
            print(container_fmu(path, path.with_name(CONTAINER_FILE_NAME), container_step))
    except (OSError, RuntimeError) as exc:     # a bad option's ParameterError: cli.main's one line, naming it
        print(f"wearjoint export-ssp: error: {exc}", file=sys.stderr)
        return 2
    return 0


def _container_step(args, joint, mechanism) -> float:
    """The container's fixed step [s]: ``--container-step`` from MIN_STEP_S to the package's stop time and the
    wear-step limit (the container steps the joint FMU at it: each step wears), refused in one line naming it
    otherwise; its default CONTAINER_STEP_S, or the wear-step limit where that is shorter."""
    limit = wear_step_limit_s(joint, mechanism)
    if args.container_step is None:
        return min(CONTAINER_STEP_S, limit)
    stop = mechanism.period_s if args.stop_time is None else args.stop_time
    require("container_step_s", args.container_step, args.container_step >= MIN_STEP_S,
            f">= {MIN_STEP_S:g} s ({MIN_STEP_WHY})")
    require("container_step_s", args.container_step, args.container_step <= stop,
            f"<= the package's stop time {stop:g} s (--stop-time)")
    check_wear_step("container_step_s", args.container_step, joint, mechanism)
    return args.container_step


__all__ = ["add_arguments", "run"]
