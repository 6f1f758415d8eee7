"""`wearjoint` command line.

Each command lives in its own module, which provides ``cli_arguments(parser)``
and ``cli_run(args) -> int``; only the invoked command's module is imported.
Parameter errors print one line and exit with status 2, never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from .parameters import ParameterError

COMMANDS = {
    "simulate": ("wearjoint.simulate_cli", "monolithic slider-crank simulation (no FMI)"),
    "build-fmu": ("wearjoint.fmu.build_pythonfmu", "build the ClearanceWearJoint FMU (FMI 2.0 co-simulation)"),
    "cosim": ("wearjoint.cosim", "co-simulate the slider-crank with the joint FMU through fmpy"),
    "validate": ("wearjoint.validation.compare", "cross-check monolithic, FMU and exudyn runs"),
    "wear-study": ("wearjoint.validation.wear_study", "thousands of revolutions of wear (paper Figs. 7-8)"),
}


def build_parser(command: str | None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="wearjoint", description="wearjoint: a planar revolute clearance joint whose bushing wears - monolithic simulation, FMU co-simulation, validation and the paper's wear study.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if name == command:
            importlib.import_module(module).cli_arguments(p)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    if command not in COMMANDS:
        command = None
    parser = build_parser(command)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    module = importlib.import_module(COMMANDS[args.command][0])
    try:
        return int(module.cli_run(args) or 0)
    except ParameterError as exc:
        print(f"wearjoint {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
