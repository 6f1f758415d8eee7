"""`wearjoint build-fmu`: build ClearanceWearJoint.fmu with either backend (native: FMI 2.0 or 3.0, Co-Simulation
and Model Exchange; pythonfmu: FMI 2.0 Co-Simulation), the native one for linux64, win64 and aarch64-linux
(whichever toolchains are installed), or (``--model slider-crank``, native) the mechanism FMU SliderCrank.fmu."""
from __future__ import annotations

import sys
from pathlib import Path

from ..fmu import platforms
from ..fmu import slider_crank as sc
from ..fmu import variables as fv
from ..fmu.build import DEFAULT_FMI_VERSION, FMI_VERSIONS, build_fmu, default_fmu_path
from ..fmu.fmi import BACKENDS, DEFAULT_BACKEND
from ..cosim.step_rule import communication_step_rule
from ..fmu.build_native import DEFAULT_MODEL, MODELS
from ..mechanism_parameters import mechanism_from_options
from ..parameters import JointParameters, ParameterError, SliderCrankParameters, wear_coefficient_source
from ..run_options import restate_default
from .options import _option, add_model_arguments, given_options, model_from_args, take_calibration


DESCRIPTION = (f"build the ClearanceWearJoint FMU (FMI {' or '.join(f'{v}.0' for v in FMI_VERSIONS)}; native backend: "
               "Co-Simulation and Model Exchange in one FMU, pythonfmu: FMI 2.0 Co-Simulation) or, with --model "
               "slider-crank, the mechanism FMU SliderCrank.fmu")


def add_arguments(parser) -> None:
    """Options of ``wearjoint build-fmu`` (and its description, :data:`DESCRIPTION`)."""
    parser.description = DESCRIPTION
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="directory for the FMU (default: the user cache, keyed by the backend, sources, model, "
                             "start values, FMI version and platforms)")
    parser.add_argument("--model", choices=tuple(MODELS), default=DEFAULT_MODEL,
                        help="joint: ClearanceWearJoint.fmu; slider-crank: SliderCrank.fmu, the paper's slider-crank "
                             "with the crank-rod joint open (native backend; --n-points does not apply) "
                             "(default %(default)s)")
    parser.add_argument("--n-points", type=int, default=JointParameters.n_points, metavar="N",
                        help="number of bushing points N_d, fixed in the FMU (default %(default)s)")
    parser.add_argument("--backend", choices=BACKENDS, default=DEFAULT_BACKEND,
                        help="native: the kernels compiled ahead of time and a C FMI layer (needs only libc/libm); "
                             "pythonfmu: the Python slave (the host needs Python with numpy and numba) "
                             "(default %(default)s)")
    parser.add_argument("--fmi-version", type=int, choices=FMI_VERSIONS, default=DEFAULT_FMI_VERSION,
                        help="FMI version of the FMU: 2, or 3 (native backend only: the wear profile is one array "
                             "sized by the structural parameter n_points, --n-points is its start value) "
                             "(default %(default)s)")
    parser.add_argument("--platforms", default="auto", metavar="LIST",
                        help="native backend: comma-separated platforms to carry binaries for, of "
                             f"{', '.join(platforms.CROSS_PLATFORMS)} (FMI 3.0 names accepted), or auto: this machine's "
                             "plus every one whose cross toolchain is installed (.ci/install-cross-toolchains "
                             "installs them) (default %(default)s)")
    parser.add_argument("--force", action="store_true", help="rebuild even if an identical FMU exists")
    parser.add_argument("--profile-stride", type=int, default=1, metavar="S",
                        help="FMI 2.0 joint: a wear_depth[z] output every S-th bushing point (1: all N_d, 0: none; "
                             "fewer outputs keep a host's result files small; the whole profile stays in the FMU's "
                             "state, and FMI 3.0 has it as one array) (default %(default)s)")
    add_model_arguments(parser, skip=("n_points",))
    restate_default(parser, "pin_offset_m", "0 0, the joint alone; with a slider-crank option, the crank's tip")
    restate_default(parser, "bushing_offset_m", "0 0, the joint alone; with a slider-crank option, the rod's big end")
    parser.epilog = ("The model options become the FMU's parameter start values (native backend): the joint's with "
                     "--model joint (the slider-crank's lengths, if given, place its pin and bushing centres at the "
                     "crank tip and rod end), the slider-crank's with --model slider-crank.")


def model_parameters(args) -> tuple[JointParameters | None, SliderCrankParameters]:
    """The parameter sets the model options give: (the joint, or None with --model slider-crank; the
    slider-crank); ParameterError for an option of the other model."""
    mechanism_given = given_options(args, SliderCrankParameters)
    joint_given = {k: v for k, v in given_options(args, JointParameters).items() if k != "n_points"}
    if args.model == "slider-crank":
        if joint_given or args.no_wear or args.calibration is not None:
            option = (_option(next(iter(joint_given))) if joint_given else
                      "--no-wear" if args.no_wear else "--calibration")
            raise ParameterError(f"{option} is a joint parameter: it applies to --model joint, not SliderCrank.fmu")
        return None, mechanism_from_options(mechanism_given)
    if mechanism_given:           # the joint of this slider-crank: its centres at the crank tip and the rod end
        return model_from_args(args)
    take_calibration(args, joint_given)
    joint = JointParameters(**joint_given, **({"wear_factor": 0.0} if args.no_wear else {}))
    return joint, SliderCrankParameters()


def run(args) -> int:
    """Build the FMU and print its path; 0 on success, 2 with a message on stderr otherwise."""
    try:
        version = args.fmi_version
        requested = args.platforms
        joint, mechanism = model_parameters(args)
        starts = sc.parameter_starts(mechanism) if joint is None else fv.parameter_starts(joint)
        note = (f"The start value of wear_coefficient is the fit of the calibration {args.calibration} "
                f"({joint.wear_coefficient_m2_N:g} m2/N)." if args.calibration is not None else "")
        out = Path(args.out) if args.out is not None else \
            default_fmu_path(args.n_points, args.backend, fmi_version=version, platforms=requested,
                             model=args.model, starts=starts, profile_stride=args.profile_stride, note=note).parent
        path = build_fmu(out, n_points=args.n_points, force=args.force, backend=args.backend, fmi_version=version,
                         platforms=requested, model=args.model, starts=starts, profile_stride=args.profile_stride,
                         note=note)
        if starts:
            print("start values: " + ", ".join(f"{k}={v:g}" for k, v in starts.items()), file=sys.stderr)
        if joint is not None:
            print(communication_step_rule(joint, mechanism).text(), file=sys.stderr)
            note = wear_coefficient_source(joint, None)["wear_coefficient_note"]   # the FMU goes into any host
            if note:
                print(f"note: {note}; in a host, the FMU's parameter wear_coefficient sets it", file=sys.stderr)
        if args.backend == "native":
            built, skipped = platforms.select(requested)
            print(f"built: {', '.join(t.folder(version) for t in built)}", file=sys.stderr)
            for name, reason in skipped.items():
                print(f"skipped {name}: {reason}", file=sys.stderr)
    except (OSError, RuntimeError) as exc:     # a bad option's ParameterError: cli.main's one line, naming it
        print(f"wearjoint build-fmu: error: {exc}", file=sys.stderr)
        return 2
    print(path)
    return 0


__all__ = ["add_arguments", "run"]
