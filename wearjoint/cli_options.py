"""Command-line options shared by every simulating command.

Every field of :class:`JointParameters` and :class:`SliderCrankParameters`
becomes an option named after it (SI units in the name, e.g.
``--pin-radius-m 0.01``).  The joint's body-frame offsets follow the
mechanism's lengths unless given explicitly.
"""
from __future__ import annotations

import argparse
import dataclasses

from .parameters import (
    RHO_MODES, SLIDING_DISTANCES, WEAR_PLACEMENTS, JointParameters, SliderCrankParameters,
)

_CHOICES = {"rho_mode": RHO_MODES, "wear_placement": WEAR_PLACEMENTS, "sliding_distance": SLIDING_DISTANCES}
_HELP = {
    "rho_mode": "equivalent radius of the Hertz patch (MODEL.md 3.2)",
    "wear_placement": "where the Archard increment goes (MODEL.md 3.7)",
    "sliding_distance": "sliding distance of Eq. 33 (MODEL.md 3.8)",
    "wear_factor": "wear acceleration factor on k_w",
    "n_points": "bushing discrete points N_d",
}


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


def _add_dataclass_options(group, cls, skip=()) -> None:
    for f in dataclasses.fields(cls):
        if f.name in skip:
            continue
        default = f.default
        help_text = _HELP.get(f.name, "") + f" (default {default})"
        if f.name in _CHOICES:
            group.add_argument(_option(f.name), dest=f.name, choices=_CHOICES[f.name], default=None, help=help_text)
        elif isinstance(default, tuple):
            group.add_argument(_option(f.name), dest=f.name, type=float, nargs=2, default=None,
                               metavar=("X", "Y"), help=help_text)
        else:
            group.add_argument(_option(f.name), dest=f.name, type=type(default), default=None, help=help_text)


def add_model_arguments(parser: argparse.ArgumentParser) -> None:
    """Options for every mechanism and joint parameter, plus --no-wear and --stiffness-from-materials."""
    _add_dataclass_options(parser.add_argument_group("slider-crank (paper Table 1)"), SliderCrankParameters)
    joint = parser.add_argument_group("clearance joint (paper Table 2, MODEL.md section 3)")
    _add_dataclass_options(joint, JointParameters)
    joint.add_argument("--no-wear", action="store_true", help="switch wear off (wear_factor = 0)")
    joint.add_argument("--stiffness-from-materials", action="store_true",
                       help="compute K from radii and materials (Eq. 16, internal-contact form)")


def _given(args, cls) -> dict:
    return {f.name: (tuple(getattr(args, f.name)) if isinstance(getattr(args, f.name), list) else getattr(args, f.name))
            for f in dataclasses.fields(cls) if getattr(args, f.name, None) is not None}


def model_from_args(args) -> tuple[JointParameters, SliderCrankParameters]:
    """Build (and validate) the parameter sets from parsed options."""
    mechanism = SliderCrankParameters(**_given(args, SliderCrankParameters))
    joint_values = {**mechanism.joint_offsets(), **_given(args, JointParameters)}
    if args.no_wear:
        joint_values["wear_factor"] = 0.0
    joint = JointParameters(**joint_values)
    if args.stiffness_from_materials:
        joint = joint.replace(contact_stiffness_N_m1_5=joint.stiffness_from_materials("internal"))
    return joint, mechanism
