"""Command-line options shared by several commands: declared once in :mod:`wearjoint.run_options` (the sweeps'
targets take the same, :mod:`wearjoint.targets`); here what only the command line does with them: the model from
parsed options with its note, the printed summary and the exit status.

Model options: every field of :class:`JointParameters` and
:class:`SliderCrankParameters` becomes an option named after it (SI units in the
name, e.g. ``--pin-radius-m 0.01``); the joint's body-frame offsets follow the
mechanism's lengths unless given explicitly.  Also the results folder and
progress options, the FMU options and the printed summary.
"""
from __future__ import annotations

import sys

from .. import run_options
from ..checks import with_options
from ..interrupts import stopped_by_ctrl_c
from ..parameters import JointParameters, ParameterError, SliderCrankParameters, joint_size_note
from ..run_options import (
    add_fmu_arguments, add_initial_profile_argument, add_model_arguments, add_output_arguments, add_settling_argument,
    calibrated_wear_coefficient, gravity_value, model_from_options, read_initial_profile, restate_default,
)
from ..run_options import option_name as _option


def require_option(option: str, value, ok: bool, allowed: str) -> None:
    """ParameterError naming ``option`` as written (``--fmu``), its ``value`` and what is ``allowed`` unless ``ok``:
    for an option whose value the API knows under another name, or not at all."""
    if not ok:
        raise ParameterError(f"{option}={value!r} is invalid: allowed {allowed}")


def take_calibration(args, joint_values: dict) -> None:
    """``--calibration DIR``'s k_w into the joint's given values (:func:`calibrated_wear_coefficient`), refused
    beside ``--wear-coefficient-m2-N``."""
    run_options.take_calibration(vars(args), joint_values)


def given_options(args, cls) -> dict:
    """The fields of ``cls`` (a parameter set) given on the command line, by field name."""
    return run_options.given_options(vars(args), cls)


def model_notes(joint: JointParameters, mechanism: SliderCrankParameters, args) -> None:
    """Before a run (unless --quiet): the note that a given contact stiffness overrides the one the radii and materials
    give, and the note that a length of the joint is longer than the crank and rod both (summary.json's
    ``joint_size_note``: before the run, since such a run may diverge)."""
    if getattr(args, "quiet", False):
        return
    if joint.contact_stiffness_N_m1_5 is not None:
        print(f"note: --contact-stiffness-N-m1-5 {joint.contact_stiffness_N_m1_5:g} overrides the "
              f"{joint.stiffness_from_materials():.4g} N/m^1.5 the radii and materials give (Eqs. 16-17)",
              file=sys.stderr)
    size = joint_size_note(joint, mechanism)["joint_size_note"]
    if size:
        print(f"note: {size}", file=sys.stderr)


def model_from_args(args, every_law: bool = False) -> tuple[JointParameters, SliderCrankParameters]:
    """Build (and validate) the parameter sets from parsed options
    (:func:`wearjoint.run_options.model_from_options`), with their notes (:func:`model_notes`)."""
    joint, mechanism = model_from_options(vars(args), every_law)
    model_notes(joint, mechanism, args)
    return joint, mechanism


def check_settling(args) -> int:
    """The --settling-revolutions value, refused in one line unless an integer >= 0."""
    return run_options.check_settling(vars(args))


SUMMARY_KEYS = ("revolutions", "realtime_factor", "compile_time_s", "max_contact_force_N", "ideal_joint_force_max_N",
                "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                "slider_acc_error_max_m_s2", "slider_acc_error_rms_m_s2", "max_eccentricity_m", "max_wear_depth_m",
                "max_wear_angle_deg", "worn_volume_m3", "wear_coefficient_source")


def print_summary(summary: dict, args, extra_keys=()) -> None:
    """The summary's key figures (and ``extra_keys``), one per line, as summary.json will state them once the
    report adds what only the options know (:func:`wearjoint.targets.report_facts`: k_w from ``--calibration``),
    then the results folder ``args.out``."""
    from ..targets import report_facts

    summary = {**summary, **report_facts(vars(args))}
    for k in SUMMARY_KEYS + tuple(extra_keys):
        v = summary.get(k)
        print(f"  {k:28s} {v:.6g}" if isinstance(v, float) else f"  {k:28s} {v}")
    if summary.get("wear_coefficient_note"):
        print(f"note: {summary['wear_coefficient_note']}", file=sys.stderr)
    print(f"results in {args.out}")


def exit_status(record, command: str) -> int:
    """A run's exit status: 0; 130 if Ctrl-C stopped it; 1 (its failure said in one line on stderr) if it diverged."""
    if stopped_by_ctrl_c(record):
        return 130
    if record.failure:
        print(f"wearjoint {command}: error: {record.failure}", file=sys.stderr)
        return 1
    return 0


__all__ = ["add_fmu_arguments", "add_initial_profile_argument", "add_model_arguments", "add_output_arguments",
           "add_settling_argument", "calibrated_wear_coefficient", "check_settling", "exit_status", "given_options",
           "gravity_value", "model_from_args", "model_notes", "print_summary", "read_initial_profile", "require_option",
           "restate_default", "take_calibration", "with_options", "SUMMARY_KEYS", "_option"]
