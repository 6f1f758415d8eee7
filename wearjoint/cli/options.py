"""Command-line options shared by several commands, defined once.

Model options: every field of :class:`JointParameters` and
:class:`SliderCrankParameters` becomes an option named after it (SI units in the
name, e.g. ``--pin-radius-m 0.01``); the joint's body-frame offsets follow the
mechanism's lengths unless given explicitly.  Also the results folder and
progress options, the FMU options and the printed summary.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np

from ..core import layout as L
from ..core.geometry import bushing_point_angles
from ..fmu.fmi import BACKENDS, DEFAULT_BACKEND
from ..joint_fields import JOINT_FIELDS
from ..mechanism_parameters import MECHANISM_FIELDS, mechanism_from_options
from ..parameters import OPTION_CHOICES, JointParameters, ParameterError, SliderCrankParameters
_HELP = {
    **{f.field: f.text for f in JOINT_FIELDS if f.component is None},
    "pin_offset_m": "pin centre in the pin body's frame, x y [m]",
    "bushing_offset_m": "bushing centre in the bushing body's frame, x y [m]",
    "n_points": "bushing discrete points N_d",
    **{f.field: f.text for f in MECHANISM_FIELDS if f.component is None and f.field not in ("slider_force_table",
                                                                                            "clearance_joint")},
    "clearance_joint": "the joint with the clearance (the other two are ideal): crank-rod, the crank's tip in the "
                       "rod's big end (the paper's); rod-slider, the slider's pin in the rod's small end; "
                       "crank-ground, the crank's journal in a bushing at the pivot (docs/model.md §1)",
    "gravity_m_s2": "gravity [m/s^2]: G for (0, -G), across the slide (the paper's), or GX,GY in the mechanism's "
                    "frame (x along the slider's axis, from the crank's pivot towards the slider)",
    "slider_force_table": "CSV file crank_angle_deg,force_N: the slider's load over a revolution, linearly "
                          "interpolated, positive towards the crank's pivot; the angles rise from 0 to 360 and the "
                          "360 row repeats the 0 row's load (docs/model.md §3.12)",
}


def gravity_value(text: str):
    """``--gravity-m-s2``: one value G, or GX,GY."""
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed G or GX,GY (numbers)") from None
    if len(values) == 1:
        return values[0]
    if len(values) == 2:
        return tuple(values)
    raise argparse.ArgumentTypeError(f"{text!r}: allowed G or GX,GY (one or two numbers)")


# model options whose default is not a value: what the parameter set does without them
_UNSET = {"effective_mass_kg": "(default: the mass the clearance joint decelerates along the rod: rod and slider at "
                               "the crank-rod joint, 0.89 for the paper's; the slider at the rod-slider joint; all "
                               "three bodies at the crank-ground joint)",
          "contact_stiffness_N_m1_5": "(default: from the radii and materials, 4 E* sqrt(R_i R_j/(R_j - R_i))/3, "
                                      "Eqs. 16-17; 7.951e10 for the paper's joint)"}


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


def _default_text(value) -> str:
    """A default as the command line writes it: ``0.025 0`` for a pair."""
    return " ".join(f"{v:g}" for v in value) if isinstance(value, tuple) else str(value)


# the joint's centres in a slider-crank command: the clearance joint's, from the mechanism's lengths
_OFFSETS = {name: f"(default {_default_text(value)}, {where}; follows --clearance-joint and {source})"
            for (name, value), where, source in
            zip(SliderCrankParameters().joint_offsets().items(), ("the crank's tip", "the rod's big end"),
                ("--crank-length-m", "--rod-length-m"))}


def _add_dataclass_options(group, cls, skip=()) -> None:
    for f in dataclasses.fields(cls):
        if f.name in skip:
            continue
        default = f.default
        remark = _OFFSETS.get(f.name) or _UNSET.get(f.name) or f"(default {_default_text(default)})"
        help_text = " ".join(filter(None, (_HELP.get(f.name), remark)))
        if f.name == "clearance_joint":
            group.add_argument(_option(f.name), dest=f.name, choices=L.CLEARANCE_JOINTS, default=None,
                               help=help_text)
        elif f.name in OPTION_CHOICES:
            group.add_argument(_option(f.name), dest=f.name, choices=OPTION_CHOICES[f.name], default=None, help=help_text)
        elif f.name == "gravity_m_s2":
            group.add_argument(_option(f.name), dest=f.name, type=gravity_value, default=None, metavar="G|GX,GY",
                               help=_HELP[f.name] + " (default 0,-9.81)")
        elif f.name == "slider_force_table":
            group.add_argument(_option(f.name), dest=f.name, type=Path, default=None, metavar="FILE",
                               help=_HELP[f.name])
        elif isinstance(default, tuple):
            group.add_argument(_option(f.name), dest=f.name, type=float, nargs=2, default=None,
                               metavar=("X", "Y"), help=help_text)
        else:
            group.add_argument(_option(f.name), dest=f.name, type=float if default is None else type(default),
                               default=None, help=help_text)


def add_model_arguments(parser: argparse.ArgumentParser, skip=()) -> None:
    """Options for every mechanism and joint parameter but those of ``skip`` (the command's own), plus --no-wear."""
    _add_dataclass_options(parser.add_argument_group("slider-crank (paper Table 1)"), SliderCrankParameters)
    joint = parser.add_argument_group("clearance joint (paper Table 2, docs/model.md §3)")
    _add_dataclass_options(joint, JointParameters, skip)
    joint.add_argument("--no-wear", action="store_true", help="switch wear off (wear_factor = 0)")
    if "wear_coefficient_m2_N" not in skip:
        joint.add_argument("--calibration", type=Path, default=None, metavar="DIR",
                           help="take k_w from a `wearjoint calibrate` folder (its calibration.json's one-k_w fit) "
                                "instead of --wear-coefficient-m2-N; summary.json names it as the source")


def take_calibration(args, joint_values: dict) -> None:
    """``--calibration DIR``'s k_w into the joint's given values (:func:`calibrated_wear_coefficient`), refused
    beside ``--wear-coefficient-m2-N``."""
    if getattr(args, "calibration", None) is None:
        return
    if "wear_coefficient_m2_N" in joint_values:
        raise ParameterError("parameters calibration and wear_coefficient_m2_N are both given: allowed one")
    joint_values["wear_coefficient_m2_N"] = calibrated_wear_coefficient(args.calibration)


def calibrated_wear_coefficient(folder) -> float:
    """The one-k_w fit [m^2/N] of a `wearjoint calibrate` folder's calibration.json."""
    path = Path(folder) / "calibration.json"
    try:
        fit = json.loads(path.read_text())
        value = float(fit["wear_coefficient_m2_N"]) if fit.get("law") == "archard" else math.nan
    except (OSError, ValueError, KeyError, TypeError):
        value = None
    if value is None or not (math.isfinite(value) and value > 0.0):
        raise ParameterError(f"parameter calibration={str(folder)!r} is invalid: allowed a `wearjoint calibrate` "
                             f"folder whose calibration.json holds a one-k_w (archard) fit; {path} "
                             + ("does not" if value is None else "is a mild-severe fit"))
    return value


def restate_default(parser: argparse.ArgumentParser, dest: str, default_text: str) -> None:
    """Give model option ``dest``'s help the default this command uses instead of the parameter set's
    (e.g. wear-study's wear factor): ``default_text`` replaces the ``(default ...)`` remark."""
    action = next(a for a in parser._actions if a.dest == dest)
    action.help = " ".join(filter(None, (_HELP.get(dest), f"(default {default_text})")))


def given_options(args, cls) -> dict:
    """The fields of ``cls`` (a parameter set) given on the command line, by field name."""
    return {f.name: (tuple(getattr(args, f.name)) if isinstance(getattr(args, f.name), list) else getattr(args, f.name))
            for f in dataclasses.fields(cls) if getattr(args, f.name, None) is not None}


def model_from_args(args) -> tuple[JointParameters, SliderCrankParameters]:
    """Build (and validate) the parameter sets from parsed options."""
    mechanism = mechanism_from_options(given_options(args, SliderCrankParameters))
    joint_values = {**mechanism.joint_defaults(), **given_options(args, JointParameters)}
    take_calibration(args, joint_values)
    if args.no_wear:
        joint_values["wear_factor"] = 0.0
    joint = JointParameters(**joint_values)
    if joint.contact_stiffness_N_m1_5 is not None and not getattr(args, "quiet", False):
        print(f"note: --contact-stiffness-N-m1-5 {joint.contact_stiffness_N_m1_5:g} overrides the "
              f"{joint.stiffness_from_materials():.4g} N/m^1.5 the radii and materials give (Eqs. 16-17)",
              file=sys.stderr)
    return joint, mechanism


def add_output_arguments(parser: argparse.ArgumentParser, plots: bool = True) -> None:
    """--out DIR (required), --no-plots (if ``plots``) and --quiet."""
    parser.add_argument("--out", type=Path, required=True, help="results folder (created)")
    if plots:
        parser.add_argument("--no-plots", action="store_true", help="skip the PNG figures")
    parser.add_argument("--quiet", action="store_true", help="no progress output")


def add_settling_argument(parser: argparse.ArgumentParser) -> None:
    """--settling-revolutions N: the start-up revolutions left out of the summary's extremes."""
    parser.add_argument("--settling-revolutions", type=int, default=1, metavar="N",
                        help="start-up revolutions left out of the run's max contact force and eccentricity, reported "
                             "apart under start_up (the pin starts centred at full speed) (default %(default)s)")


def check_settling(args) -> int:
    """The --settling-revolutions value, refused in one line unless an integer >= 0."""
    if args.settling_revolutions < 0:
        raise ParameterError(f"parameter --settling-revolutions={args.settling_revolutions} is invalid: allowed an "
                             "integer >= 0")
    return args.settling_revolutions


def add_initial_profile_argument(group) -> None:
    """--initial-profile FILE: a worn bushing to start from."""
    group.add_argument("--initial-profile", type=Path, default=None, metavar="FILE",
                       help="start from this worn bushing: a profile.csv (phi_deg,wear_depth_m, one row per bushing "
                            "point, as every run writes); with --no-wear the profile stays as given")


def read_initial_profile(path: Path, joint) -> np.ndarray:
    """The wear depths [m] of a profile.csv for ``joint``; ParameterError naming the file and what does not fit."""
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as exc:
        raise ParameterError(f"parameter --initial-profile={str(path)!r} is invalid: allowed a readable "
                             f"profile.csv with columns phi_deg,wear_depth_m ({exc})") from None
    expected = np.degrees(bushing_point_angles(joint.n_points))
    if data.shape != (joint.n_points, 2) or not np.allclose(data[:, 0], expected, atol=1e-6):
        raise ParameterError(f"parameter --initial-profile={str(path)!r} is invalid: allowed a profile of this joint's "
                             f"{joint.n_points} bushing points (--n-points) at its angles, "
                             f"got {data.shape[0]} rows")
    return data[:, 1]


def add_fmu_arguments(parser, fmu_file: bool = True, when: str = "") -> None:
    """--fmu-backend (and --fmu FILE if ``fmu_file``): which joint FMU a co-simulation loads;
    ``when`` qualifies the help (e.g. "with --engine cosim")."""
    qualifier = f" ({when})" if when else ""
    if fmu_file:
        parser.add_argument("--fmu", type=Path, default=None,
                            help="ClearanceWearJoint.fmu to use (default: the cached build of --fmu-backend, "
                                 f"built if missing){qualifier}")
    parser.add_argument("--fmu-backend", choices=BACKENDS, default=DEFAULT_BACKEND,
                        help="FMU backend: native (compiled kernels, C FMI layer) or pythonfmu (Python slave)"
                             f"{qualifier} (default %(default)s)")


SUMMARY_KEYS = ("revolutions", "realtime_factor", "compile_time_s", "max_contact_force_N", "ideal_joint_force_max_N",
                "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                "slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "max_eccentricity_m", "max_wear_depth_m",
                "max_wear_angle_deg", "worn_volume_m3", "wear_coefficient_source")


def print_summary(summary: dict, out: Path, extra_keys=()) -> None:
    """The summary's key figures (and ``extra_keys``), one per line, then the results folder."""
    for k in SUMMARY_KEYS + tuple(extra_keys):
        v = summary.get(k)
        print(f"  {k:28s} {v:.6g}" if isinstance(v, float) else f"  {k:28s} {v}")
    if summary.get("wear_coefficient_note"):
        print(f"note: {summary['wear_coefficient_note']}", file=sys.stderr)
    print(f"results in {out}")


def exit_status(record, command: str) -> int:
    """A run's exit status: 0; 1 (its failure said in one line on stderr) if it diverged; 130 if Ctrl-C stopped it."""
    if record.failure:
        print(f"wearjoint {command}: error: {record.failure}", file=sys.stderr)
        return 1
    return 0 if record.completed else 130
