"""The options of the runs, declared once: the command line's (:mod:`wearjoint.cli`) and the sweeps' targets'
(:mod:`wearjoint.targets`), and the model their values give.

Model options: every field of :class:`JointParameters` and :class:`SliderCrankParameters` becomes an option
named after it (SI units in the name, e.g. ``--pin-radius-m 0.01``); the joint's body-frame offsets follow the
mechanism's lengths unless given explicitly.  Also the results folder and progress options, the settling
revolutions, the initial profile and the FMU options, and the own options of ``simulate``, ``cosim`` and
``wear-study`` (:func:`add_simulate_arguments`, :func:`add_cosim_arguments`, :func:`add_wear_study_arguments`;
their defaults are the library's dataclasses').  :func:`model_from_options` turns option values (dest -> value,
as a parser gives them: ``vars(args)``, a sweep case's options) into the parameter sets.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import re
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .core import layout as L
from .fmu.fmi import BACKENDS, DEFAULT_BACKEND
from .joint_fields import JOINT_FIELDS, unread_by
from .kernel_calls import bushing_point_angles
from .mechanism_parameters import MECHANISM_FIELDS, mechanism_from_options, same_setting
from .parameters import OPTION_CHOICES, JointParameters, ParameterError, SliderCrankParameters, require
from .checks import path as path_argument

_HELP = {
    **{f.field: f.text for f in JOINT_FIELDS if f.component is None},
    "pin_offset_m": "pin centre in the pin body's frame, x y [m]",
    "bushing_offset_m": "bushing centre in the bushing body's frame, x y [m]",
    "n_points": "bushing discrete points N_d",
    **{f.field: f.text for f in MECHANISM_FIELDS if f.component is None and f.field not in ("slider_force_table",
                                                                                            "clearance_joint")},
    "clearance_joint": "the joint with the clearance (the other two are ideal): crank-rod, the crank's tip in the "
                       "rod's big end (the paper's); rod-slider, the slider's pin in the rod's small end; "
                       "crank-ground, the crank's journal in a bushing at the pivot (docs/reference/model.md §1)",
    "gravity_m_s2": "gravity [m/s^2]: G for (0, -G), across the slide (the paper's), or GX,GY in the mechanism's "
                    "frame (x along the slider's axis, from the crank's pivot towards the slider)",
    "slider_force_table": "CSV file crank_angle_deg,force_N: the slider's load over a revolution, linearly "
                          "interpolated, positive towards the crank's pivot; 2 to "
                          f"{L.MAX_LOAD_ROWS} rows whose angles rise from 0 to 360, the 360 row repeating the 0 "
                          "row's load (docs/reference/model.md §3.12)",
}


SAMPLE_DT_HELP = ("time-series spacing [s] (default %(default)g): a row at the first step's end at or after each "
                  "multiple of it (to a thousandth of that step); a longer step ({}) leaves fewer rows there")


def gravity_value(text: str):
    """``--gravity-m-s2``: one value G, or GX,GY (two bare integers refused: ``9,81``, a decimal comma or a pair?)."""
    parts = text.split(",")
    if re.fullmatch(r"\s*[+-]?\d+,\d+\s*", text) and float(text.replace(",", ".")) != 0.0:
        raise argparse.ArgumentTypeError(f"{text!r} is ambiguous (a decimal comma or a pair?): write "
                                         f"{text.replace(',', '.')} for G, or {parts[0]}.0,{parts[1]} for the pair")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed G or GX,GY (numbers)") from None
    if len(values) in (1, 2):
        return values[0] if len(values) == 1 else tuple(values)
    raise argparse.ArgumentTypeError(f"{text!r}: allowed G or GX,GY (one or two numbers)")


# model options whose default is not a value: what the parameter set does without them
_UNSET = {"effective_mass_kg": "(default: the mass the clearance joint decelerates along the rod: rod and slider at "
                               "the crank-rod joint, 0.89 for the paper's; the slider at the rod-slider joint; all "
                               "three bodies at the crank-ground joint)",
          "contact_stiffness_N_m1_5": "(default: from the radii and materials, 4 E* sqrt(R_i R_j/(R_j - R_i))/3, "
                                      "Eqs. 16-17; 7.951e10 for the paper's joint)"}


def option_name(name: str) -> str:
    """A field's option: ``--pin-radius-m`` for ``pin_radius_m``."""
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
        choices = L.CLEARANCE_JOINTS if f.name == "clearance_joint" else OPTION_CHOICES.get(f.name)
        if choices is not None:
            group.add_argument(option_name(f.name), dest=f.name, choices=choices, default=None, help=help_text)
        elif f.name == "gravity_m_s2":
            group.add_argument(option_name(f.name), dest=f.name, type=gravity_value, default=None, metavar="G|GX,GY",
                               help=_HELP[f.name] + " (default 0,-9.81)")
        elif f.name == "slider_force_table":
            group.add_argument(option_name(f.name), dest=f.name, type=path_argument, default=None, metavar="FILE",
                               help=_HELP[f.name])
        elif isinstance(default, tuple):
            group.add_argument(option_name(f.name), dest=f.name, type=float, nargs=2, default=None,
                               metavar=("X", "Y"), help=help_text)
        else:
            group.add_argument(option_name(f.name), dest=f.name, type=float if default is None else type(default),
                               default=None, help=help_text)


def add_model_arguments(parser: argparse.ArgumentParser, skip=()) -> None:
    """Options for every mechanism and joint parameter but those of ``skip`` (the command's own), and --no-wear."""
    _add_dataclass_options(parser.add_argument_group("slider-crank (paper Table 1)"), SliderCrankParameters)
    joint = parser.add_argument_group("clearance joint (paper Table 2, docs/reference/model.md §3)")
    _add_dataclass_options(joint, JointParameters, skip)
    if "wear_factor" not in skip:             # not where the command sets it (cosim-study)
        joint.add_argument("--no-wear", action="store_true", help="switch wear off (wear_factor = 0)")
    if "wear_coefficient_m2_N" not in skip:
        joint.add_argument("--calibration", type=path_argument, default=None, metavar="DIR",
                           help="take k_w from a `wearjoint calibrate` folder (its calibration.json's one-k_w fit) "
                                "instead of --wear-coefficient-m2-N; summary.json names it as the source")


def take_calibration(options: Mapping, joint_values: dict) -> None:
    """``--calibration DIR``'s k_w (``options["calibration"]``) into the joint's given values
    (:func:`calibrated_wear_coefficient`), refused beside ``--wear-coefficient-m2-N``."""
    if options.get("calibration") is None:
        return
    if "wear_coefficient_m2_N" in joint_values:
        raise ParameterError(f"--calibration={str(options['calibration'])!r} is invalid: allowed only "
                             "without --wear-coefficient-m2-N (one k_w)")
    joint_values["wear_coefficient_m2_N"] = calibrated_wear_coefficient(options["calibration"])


# what a calibration carries to another run only where it is the same: the machine's mechanism (its start angle, a
# seed, and the constraint stabilisation aside) and the joint's geometry, materials, friction and wear model
_CALIBRATION_JOINT_FIELDS = ("pin_radius_m", "bushing_radius_m", "contact_length_m", "pin_youngs_modulus_Pa",
                             "pin_poisson_ratio", "bushing_youngs_modulus_Pa", "bushing_poisson_ratio",
                             "friction_coefficient", "sliding_distance", "wear_placement", "contact_model")
_CALIBRATION_MECHANISM_SKIPPED = ("initial_crank_angle_deg", "baumgarte_alpha", "baumgarte_beta")


def calibration_facts(folder, joint: JointParameters, mechanism: SliderCrankParameters) -> dict:
    """What a run's summary states of its ``--calibration DIR`` k_w: its source, its 95 % interval (null where the
    fit has none) and a note (null where there is nothing to say): the fit was rejected by its test, it was made on a
    wear study of another machine (:func:`calibration_note`), its study's curve error is not in the interval."""
    try:
        fit = json.loads((Path(folder) / "calibration.json").read_text())
        fit = fit if isinstance(fit, dict) else {}
    except (OSError, ValueError):
        fit = {}
    notes = []
    if fit.get("consistent") is False:
        notes.append(f"the fit in {folder} was rejected by its test (chi^2 {fit.get('chi2', math.nan):.3g}, p "
                     f"{fit.get('p_value', math.nan):.2g}): one k_w does not fit its points within their "
                     "uncertainties, and it has no interval")
    notes += [note for note in (calibration_note(folder, joint, mechanism), fit.get("curve_error_note")) if note]
    return {"wear_coefficient_source": f"calibration {folder}",
            "wear_coefficient_interval_95_m2_N": fit.get("interval_95_m2_N"),
            "wear_coefficient_note": "; ".join(notes) or None}


def calibration_note(folder, joint: JointParameters, mechanism: SliderCrankParameters) -> str | None:
    """A line where ``--calibration DIR``'s fit was made on a wear study of another machine than the run's
    (``joint`` in ``mechanism``), naming what differs; None where it is the same one (or the study is gone)."""
    try:
        study = json.loads((Path(folder) / "calibration.json").read_text())["study"]
        fitted = json.loads((Path(study) / "summary.json").read_text())["parameters"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    ours = {"joint": joint.to_dict(), "mechanism": mechanism.to_dict()}
    differ = [name for group, names in (("joint", _CALIBRATION_JOINT_FIELDS),
                                        ("mechanism", [n for n in ours["mechanism"]
                                                       if n not in _CALIBRATION_MECHANISM_SKIPPED]))
              for name in names
              if not same_setting(name, json.loads(json.dumps(ours[group].get(name))), fitted.get(group, {}).get(name))]
    if not differ:
        return None
    return (f"k_w was fitted on the wear study {study}, of another machine (its {', '.join(differ)} "
            f"{'differ' if len(differ) > 1 else 'differs'}): its load, speed and materials set what k_w absorbs; "
            "calibrate on a study of this one")


def calibrated_wear_coefficient(folder) -> float:
    """The one-k_w fit [m^2/N] of a `wearjoint calibrate` folder's calibration.json."""
    path = Path(folder) / "calibration.json"
    fit, value = {}, None
    try:
        fit = json.loads(path.read_text())
        fit = fit if isinstance(fit, dict) else {}
        value = float(fit["wear_coefficient_m2_N"]) if fit.get("law") == "archard" else math.nan
    except (OSError, ValueError, KeyError, TypeError):
        pass
    if value is None or not (math.isfinite(value) and value > 0.0):
        if "target_max_depth_m" in fit:    # wear-study --calibrate-max-depth-m's
            problem = (f"holds a wear study's calibration to a depth, not a fit (give its k_w as "
                       f"--wear-coefficient-m2-N {fit.get('effective_wear_coefficient_m2_N')})")
        else:
            problem = "does not" if fit.get("law") != "mild-severe" else "is a mild-severe fit"
        raise ParameterError(f"parameter calibration={str(folder)!r} is invalid: allowed a `wearjoint calibrate` "
                             f"folder whose calibration.json holds a one-k_w (archard) fit; {path} {problem}")
    return value


def restate_default(parser: argparse.ArgumentParser, dest: str, default_text: str) -> None:
    """Give model option ``dest``'s help the default this command uses instead of the parameter set's
    (e.g. wear-study's wear factor): ``default_text`` replaces the ``(default ...)`` remark."""
    action = next(a for a in parser._actions if a.dest == dest)
    action.help = " ".join(filter(None, (_HELP.get(dest), f"(default {default_text})")))


def given_options(options: Mapping, cls) -> dict:
    """The fields of ``cls`` (a parameter set) given in ``options`` (not None), by field name."""
    return {f.name: (tuple(options[f.name]) if isinstance(options[f.name], list) else options[f.name])
            for f in dataclasses.fields(cls) if options.get(f.name) is not None}


def model_from_options(options: Mapping, every_law: bool = False) -> tuple[JointParameters, SliderCrankParameters]:
    """Build (and validate) the parameter sets from option values (dest -> value; an option left out or None
    is not given); a damping law's own parameter given with another law is refused unless ``every_law`` (a command
    that evaluates every law: contact-law)."""
    mechanism = mechanism_from_options(given_options(options, SliderCrankParameters))
    given = given_options(options, JointParameters)
    joint_values = {**mechanism.joint_defaults(), **given}
    law = joint_values.get("contact_damping", JointParameters.contact_damping)
    for row in () if every_law else unread_by(law, given):     # another law's parameter: it would change nothing
        require(option_name(row.field), given[row.field], False,
                f"only with --contact-damping {' or '.join(row.read_by)} (--contact-damping {law} does not read it)")
    take_calibration(options, joint_values)
    if options.get("no_wear"):
        given = options.get("wear_factor")
        require("--wear-factor", given, given is None or given == 0.0, "only without --no-wear (its wear factor is 0)")
        joint_values["wear_factor"] = 0.0
    return JointParameters(**joint_values), mechanism


def add_output_arguments(parser: argparse.ArgumentParser, plots: bool = True) -> None:
    """--out DIR (required), --no-plots (if ``plots``) and --quiet."""
    parser.add_argument("--out", type=path_argument, required=True, help="results folder (created)")
    if plots:
        parser.add_argument("--no-plots", action="store_true", help="skip the PNG figures")
    parser.add_argument("--quiet", action="store_true", help="no progress output")


def add_settling_argument(parser: argparse.ArgumentParser) -> None:
    """--settling-revolutions N: the start-up revolutions left out of the summary's extremes."""
    parser.add_argument("--settling-revolutions", type=int, default=1, metavar="N",
                        help="start-up revolutions left out of the run's max contact force and eccentricity, reported "
                             "apart under start_up (the pin starts centred at full speed) (default %(default)s)")


def check_settling(options: Mapping) -> int:
    """The --settling-revolutions value, refused in one line unless an integer >= 0."""
    settling = options["settling_revolutions"]
    if settling < 0:
        raise ParameterError(f"--settling-revolutions={settling} is invalid: allowed an integer >= 0")
    return settling


def add_initial_profile_argument(group) -> None:
    """--initial-profile FILE: a worn bushing to start from."""
    group.add_argument("--initial-profile", type=path_argument, default=None, metavar="FILE",
                       help="start from this worn bushing: a profile.csv (phi_deg,wear_depth_m, one row per bushing "
                            "point, as every run writes); with --no-wear the profile stays as given")


PROFILE_HEADER = "phi_deg,wear_depth_m"      # profile.csv's header (docs/reference/results.md)


def read_initial_profile(path: Path, joint) -> np.ndarray:
    """The wear depths [m] of a profile.csv for ``joint``: its header, a row per bushing point at that point's angle,
    depths in [0, bushing radius]; ParameterError naming --initial-profile, the file and what does not fit."""
    invalid = f"--initial-profile={str(path)!r} is invalid: allowed"
    try:
        with open(path) as f:
            header = f.readline().strip()
        with warnings.catch_warnings():            # an empty file: the shape check below says so, once
            warnings.simplefilter("ignore", UserWarning)
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{invalid} a readable profile.csv with columns {PROFILE_HEADER} ({exc})") from None
    if header != PROFILE_HEADER:
        raise ParameterError(f"{invalid} a profile.csv whose header is {PROFILE_HEADER}, got {header!r}")
    if data.shape != (joint.n_points, 2):
        raise ParameterError(f"{invalid} a profile of this joint's {joint.n_points} bushing points (--n-points), got "
                             f"{data.shape[0]} rows of {data.shape[1]} columns")
    expected = np.degrees(bushing_point_angles(joint.n_points))
    off = np.flatnonzero(~np.isclose(data[:, 0], expected, rtol=0.0, atol=1e-6))
    if off.size:
        raise ParameterError(f"{invalid} phi_deg at this joint's bushing points' angles, ascending from "
                             f"{expected[0]:g} deg in steps of {expected[1] - expected[0]:.6g} deg: row {off[0] + 1} "
                             f"has {data[off[0], 0]:g} deg, not {expected[off[0]]:g}")
    depth = data[:, 1]
    bad = np.flatnonzero(~(np.isfinite(depth) & (depth >= 0.0) & (depth <= joint.bushing_radius_m)))
    if bad.size:
        raise ParameterError(f"{invalid} wear_depth_m in [0, {joint.bushing_radius_m:g}] m (the bushing radius): row "
                             f"{bad[0] + 1} has {depth[bad[0]]:g}")
    return depth


def add_fmu_arguments(parser, fmu_file: bool = True, when: str = "") -> None:
    """--fmu-backend (and --fmu FILE if ``fmu_file``): which joint FMU a co-simulation loads;
    ``when`` qualifies the help (e.g. "with --engine cosim")."""
    qualifier = f" ({when})" if when else ""
    if fmu_file:
        parser.add_argument("--fmu", type=path_argument, default=None,
                            help="ClearanceWearJoint.fmu to use (default: the cached build of --fmu-backend, "
                                 f"built if missing){qualifier}")
    parser.add_argument("--fmu-backend", choices=BACKENDS, default=DEFAULT_BACKEND,
                        help="FMU backend: native (compiled kernels, C FMI layer) or pythonfmu (Python slave)"
                             f"{qualifier} (default %(default)s)")


# ------------------------------------------------------------------ the own options of simulate, cosim, wear-study
def add_tolerance_arguments(group, integrators: str) -> None:
    """--rtol, --atol-position, --atol-velocity of the adaptive ``integrators`` (SimulationOptions' defaults)."""
    from .simulation_options import SimulationOptions

    defaults = SimulationOptions()
    group.add_argument("--rtol", type=float, default=defaults.rtol,
                       help=f"relative tolerance ({integrators}) (default %(default)g)")
    group.add_argument("--atol-position", type=float, default=defaults.atol_position_m,
                       help="absolute tolerance on positions [m, rad] (default %(default)g)")
    group.add_argument("--atol-velocity", type=float, default=defaults.atol_velocity_m_s,
                       help="absolute tolerance on velocities [m/s, rad/s] (default %(default)g)")


def add_integration_arguments(parser) -> None:
    """simulate's integration options (SimulationOptions' defaults)."""
    from .parameters import MAX_WEAR_STEP_S
    from .simulation_options import (
        DEFAULT_WEAR_STEP_SHARE, DOPRI_WEAR_CONTACT_STEP_S, GEAR_JACOBIANS, GEAR_SOLVERS, INTEGRATORS,
        NO_WEAR_MAX_STEP_S, SimulationOptions,
    )

    defaults = SimulationOptions()
    g = parser.add_argument_group("integration")
    g.add_argument("--revolutions", type=float, default=defaults.revolutions, help="crank revolutions to simulate")
    g.add_argument("--integrator", choices=INTEGRATORS, default=defaults.integrator,
                   help="rk4 (fixed step), dopri (adaptive Dormand-Prince 5(4)), gear (BDF, the paper's method) "
                        "(default %(default)s)")
    g.add_argument("--gear-solver", choices=GEAR_SOLVERS, default=defaults.gear_solver,
                   help="BDF of --integrator gear: SUNDIALS CVODE (scikit-sundae) or scipy's (default %(default)s)")
    g.add_argument("--gear-jacobian", choices=GEAR_JACOBIANS, default=defaults.gear_jacobian,
                   help="Jacobian of --integrator gear: exact (the contact's with the mechanism's; the crank-rod "
                        "joint's) or the solver's finite differences (default: exact where there is one)")
    g.add_argument("--step", type=float, default=defaults.step_s, help="RK4 step [s] (default %(default)g)")
    add_tolerance_arguments(g, "dopri, gear")
    g.add_argument("--max-step", type=float, default=None,
                   help=f"largest step [s] (default {NO_WEAR_MAX_STEP_S:g}; with wear {MAX_WEAR_STEP_S:g}, dopri "
                        f"{DOPRI_WEAR_CONTACT_STEP_S:g}, less where a step's share of the penetration would pass "
                        f"{DEFAULT_WEAR_STEP_SHARE:g}; at most {MAX_WEAR_STEP_S:g} and a share of 4: docs/reference/model.md §7)")
    free_flight = f"(default {NO_WEAR_MAX_STEP_S:g}; --max-step when that is given)"
    g.add_argument("--free-flight-max-step", type=float, default=None,
                   help="dopri: largest step that starts with no contact [s], where nothing wears " + free_flight)
    g.add_argument("--sample-dt", type=float, default=defaults.sample_dt_s, help=SAMPLE_DT_HELP.format(
        "a dopri step in free flight, up to --free-flight-max-step"))
    g.add_argument("--ideal", action="store_true", help="the clearance joint (--clearance-joint) ideal: no clearance")
    add_initial_profile_argument(g)


def add_simulate_arguments(parser) -> None:
    """Options of ``wearjoint simulate``: results folder, settling, integration, and every model parameter."""
    add_output_arguments(parser)
    add_settling_argument(parser)
    add_integration_arguments(parser)
    add_model_arguments(parser)


def add_cosim_arguments(parser) -> None:
    """Options of ``wearjoint cosim``: results folder, FMU, coupling, and every model parameter."""
    from .cosim import SCHEMES, CoSimulationOptions
    from .cosim.cosimulation import DEFAULT_CONTACT_STEP_S
    from .cosim.masters import DEFAULT_STEP_S, MASTERS
    from .fmu.fmi import INTERFACES
    from .fmu.ssp import LOAD_COUPLINGS
    defaults = CoSimulationOptions()
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
    g.add_argument("--load-coupling", choices=LOAD_COUPLINGS, default="linearised",
                   help="with a third-party master: how the package's mechanism takes the joint's loads over a step, "
                        "linearised (F0 + J (u - u0) from the joint's published derivatives) or hold (default "
                        "%(default)s)")
    g.add_argument("--revolutions", type=float, default=defaults.revolutions, help="crank revolutions to simulate")
    g.add_argument("--scheme", choices=SCHEMES, default=defaults.scheme,
                   help="zoh: fixed communication step, forces held; extrapolation: fixed step, forces "
                        "extrapolated in contact; adaptive: extrapolation, large steps in free flight, "
                        "rollback to contact onsets; linearised: adaptive, the loads in contact linearised in the "
                        "kinematics with the derivatives the FMU publishes (default %(default)s)")
    g.add_argument("--step", type=float, default=None,
                   help=f"communication step [s] (adaptive: in contact; linearised: the largest in contact) (default "
                        f"{defaults.step_s:g}, with the linearised scheme; "
                        f"{DEFAULT_CONTACT_STEP_S['adaptive']:g} with the others; "
                        f"with a third-party master a fixed step, {DEFAULT_STEP_S['linearised']:g} linearised, "
                        f"{DEFAULT_STEP_S['hold']:g} hold)")
    g.add_argument("--max-step", type=float, default=defaults.max_step_s,
                   help="largest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--min-step", type=float, default=defaults.min_step_s,
                   help="smallest adaptive communication step [s] (default %(default)g)")
    g.add_argument("--onset-penetration", type=float, default=defaults.onset_penetration_m,
                   help="how deep past a contact onset an adaptive step may end [m] (default %(default)g)")
    g.add_argument("--coupling-tolerance", type=float, default=None,
                   help="adaptive, linearised: the relative miss of the predicted contact force each contact step "
                        "aims at, between --step/8 and --step, a linearised contact starting at --step/4 (0: the fixed "
                        "rule, the step halved where the miss passes 0.3); force jumps miss at any step, so the "
                        "reported miss can stay above it; every run "
                        "reports it in summary.json, coupling_force_miss_rms and _max (default "
                        f"{defaults.coupling_tolerance:g}, with the linearised scheme; 0 with the others)")
    g.add_argument("--sample-dt", type=float, default=defaults.sample_dt_s, help=SAMPLE_DT_HELP.format(
        "an adaptive step in free flight, up to --max-step"))
    add_initial_profile_argument(g)
    add_tolerance_arguments(parser.add_argument_group("model exchange (--fmu-interface model-exchange)"), "dopri")
    add_model_arguments(parser)


def add_wear_study_arguments(parser) -> None:
    """Options of ``wearjoint wear-study`` (WearStudyConfig's defaults) but its ensemble's (``--seeds``,
    ``--workers``, ``--scheduler``: :func:`wearjoint.cli.sweep.add_ensemble_arguments`)."""
    from .cosim.cosimulation import DEFAULT_CONTACT_STEP_S
    from .studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
    from .studies.wear_study import DEFAULT_WEAR_FACTOR, ENGINES, STUDY_INTEGRATORS, STUDY_STEP_S, WearStudyConfig

    study = {f.name: f.default for f in dataclasses.fields(WearStudyConfig) if f.default is not dataclasses.MISSING}
    max_step_default = ("(default %(default)g)" if study["max_step_s"] is not None else
                        f"(default: {STUDY_STEP_S:g}, less where the run's wear needs it, through the FMU "
                        f"(--engine cosim, the adaptive scheme) {DEFAULT_CONTACT_STEP_S['adaptive']:g}; "
                        "docs/reference/model.md §7)")
    add_output_arguments(parser)
    parser.add_argument("--revolutions", default=str(study["revolutions"]),
                        help="crank revolutions to reach (integer) (default %(default)s)")
    parser.add_argument("--snapshots", default=None,
                        help="revolutions at which to keep the profile, comma separated (default: quarters)")
    parser.add_argument("--engine", choices=ENGINES, default=study["engine"],
                        help="simulation engine (default %(default)s)")
    add_fmu_arguments(parser, fmu_file=False, when="with --engine cosim")
    jump = parser.add_mutually_exclusive_group()
    jump.add_argument("--cycle-jump-tolerance", type=float, default=None, metavar="TOL",
                      help="cycle jumping (the default without --wear-factor): a jump's error estimate relative to "
                           f"the max depth (default {DEFAULT_JUMP_TOLERANCE:g})")
    jump.add_argument("--no-cycle-jump", action="store_true",
                      help="simulate every revolution (with --wear-factor F: every F-th)")
    parser.add_argument("--cycle-jump-block", type=int, default=study["jump_block_revolutions"], metavar="M",
                        help="simulated revolutions of a cycle-jump block (default %(default)s)")
    parser.add_argument("--integrator", choices=STUDY_INTEGRATORS, default=study["integrator"],
                        help="rk4: fixed steps of --max-step; dopri: adaptive, at most --max-step "
                             "(default %(default)s)")
    parser.add_argument("--max-step", type=float, default=study["max_step_s"],
                        help="largest integration step [s] (RK4: the step) " + max_step_default)
    parser.add_argument("--rtol", type=float, default=study["rtol"],
                        help="dopri: relative tolerance (default %(default)g)")
    parser.add_argument("--checkpoint-every", type=float, default=study["checkpoint_every_revolutions"],
                        help="simulated revolutions between checkpoints (default %(default)g)")
    parser.add_argument("--impact-threshold-m-s2", type=float, default=study["impact_threshold_m_s2"],
                        help="impact event: |a - a_ideal| above this [m/s^2] (default %(default)g)")
    parser.add_argument("--life-depth-m", type=float, default=None, metavar="DEPTH",
                        help="state the life to this max wear depth [m] at the study's k_w, in revolutions and hours")
    parser.add_argument("--resume", action="store_true",
                        help="continue the study checkpointed in --out (the options left out are its checkpoint's; "
                             "an ensemble of seeds: give the options that started it)")
    task = parser.add_argument_group("other tasks")
    task.add_argument("--convergence", default=None, metavar="F1,F2,...",
                      help="convergence study of the acceleration factors (first = reference: 1 for brute force, "
                           "or jump for the cycle-jumping route, e.g. jump,100 for the bias of F = 100 on this "
                           "mechanism and horizon)")
    task.add_argument("--calibrate-max-depth-m", type=float, default=None,
                      help="find the effective k_w whose study ends at this max depth (e.g. 0.58e-3)")
    add_model_arguments(parser)
    restate_default(parser, "wear_factor", f"{DEFAULT_WEAR_FACTOR:g}; another value turns cycle jumping off")


__all__ = ["gravity_value", "option_name", "add_model_arguments", "take_calibration", "calibrated_wear_coefficient",
           "calibration_facts", "calibration_note", "restate_default", "given_options", "model_from_options",
           "add_output_arguments", "add_settling_argument", "check_settling", "add_initial_profile_argument",
           "read_initial_profile", "add_fmu_arguments", "add_tolerance_arguments", "add_integration_arguments",
           "add_simulate_arguments", "add_cosim_arguments", "add_wear_study_arguments"]
