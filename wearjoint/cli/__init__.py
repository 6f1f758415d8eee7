"""`wearjoint` command line: one module per command in this package.

Each command module provides ``add_arguments(parser)`` and ``run(args) -> int``
(its one-line help is in :data:`COMMANDS`); only the invoked command's module is imported.  Options
shared by several commands (the model, the results folder, the FMU) are defined
once in :mod:`wearjoint.cli.options`.  Parameter errors print one line and exit
with status 2, never a traceback.  A command whose kernels compile first says so
(:mod:`wearjoint._compile.notice`).
"""
from __future__ import annotations

import argparse
import atexit
import contextlib
import importlib
import json
import os
import re
import shlex
import sys
import threading
from pathlib import Path

from ..checks import ParameterError   # light: the figure worker starts before numba loads
from .out_folder import FILE_COMMANDS, RESULT_COMMANDS, prepare_out_folder, remove_empty_folders, results_commands

# command -> (module, one-line help); kept here so that `wearjoint --help` imports no command
COMMANDS = {
    "simulate": ("wearjoint.cli.simulate", "monolithic slider-crank simulation (no FMI)"),
    "build-fmu": ("wearjoint.cli.build_fmu", "build the ClearanceWearJoint FMU (FMI 2.0 or 3.0, Co-Simulation and "
                                             "Model Exchange) or the SliderCrank FMU"),
    "export-ssp": ("wearjoint.cli.export_ssp", "write SliderCrankWithClearance.ssp: slider-crank and joint FMUs wired"),
    "cosim": ("wearjoint.cli.cosim", "co-simulate the slider-crank with the joint FMU through fmpy"),
    "validate": ("wearjoint.cli.validate", "cross-check monolithic, FMU and exudyn runs"),
    "wear-study": ("wearjoint.cli.wear_study", "thousands of revolutions of wear (paper Figs. 7-8)"),
    "calibrate": ("wearjoint.cli.calibrate", "fit k_w (or a mild-to-severe law) to measured max depths on a study"),
    "cosim-study": ("wearjoint.cli.cosim_study", "co-simulation error versus communication step and scheme"),
    "sweep": ("wearjoint.cli.sweep", "a grid of parameter values x seeds of simulate, cosim or wear-study on Dask"),
    "sensitivity": ("wearjoint.cli.sensitivity", "which parameters drive the outputs: Morris or Sobol' on Dask (SALib)"),
    "contact-law": ("wearjoint.cli.contact_law", "restitution of a single impact against its speed under each contact "
                                                 "damping law"),
    "report": ("wearjoint.cli.report", "(re)write a results folder's report.html: summary, parameters, figures"),
}
# commands whose figures a second process draws, started before anything else (wearjoint.figure_worker)
FIGURE_COMMANDS = ("simulate", "cosim")
DESCRIPTION = ("wearjoint: a planar revolute clearance joint whose bushing wears - monolithic simulation, "
               "FMU co-simulation, validation and the paper's wear study.")


# an option's value that is a negative number or a list of numbers starting with one (by commas, or colons: calibrate's
# points): argparse (3.10-3.12) takes -1e-6, -inf, -9.81,0 and -1:1e-5 for options and says "expected one argument",
# which names no value; read as values, the option's own check names it and its range
_NUMBER = r"(?:(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|inf|infinity|nan)"
_NEGATIVE_NUMBER = re.compile(rf"^-{_NUMBER}(?:[,:][-+]?{_NUMBER})*$", re.IGNORECASE)


_INVALID_VALUE = re.compile(r"^argument ([^:]+): invalid (\w+) value: (.*)$")
_KINDS = {"int": "an integer (digits only: not 1.5 or 1e3)", "float": "a number",
          "path": "a path, not an empty one (that would be the current folder)"}


class OneLineErrorParser(argparse.ArgumentParser):
    """argparse's parser whose error is one line (the option, what is wrong; where to look), not the usage block;
    a negative number in any notation (or a list of numbers starting with one) is a value."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message):
        """``message`` in one line; argparse's "argument --n: invalid int value: 'x'" as the other errors state it,
        ``--n='x' is invalid: allowed an integer``, with the range of a parameter the tables rule
        (``--pin-radius-m='abc' is invalid: allowed a number > 0 (from 1e-06 to 100 m)``) or, for the command's other
        options, the range their own check states (``--step='x' is invalid: allowed a finite real number > 0``)."""
        typed = _INVALID_VALUE.match(message)
        if typed:
            option, kind, value = typed.groups()
            action = next((a for a in self._actions if option in a.option_strings), None)
            known = action is not None and kind in ("int", "float")
            table = _table_rule(action.dest) if known else ""
            checked = _option_rule(self.prog.split()[-1], action.dest, value) if known and not table else None
            allowed = (f"{_KINDS.get(kind, f'a {kind} value')}{table}" if checked is None
                       else f"{checked} (digits only: not 1.5 or 1e3)" if kind == "int" else checked)
            message = f"{option}={value} is invalid: allowed {allowed}"
        self.exit(2, f"{self.prog}: error: {message} (`{self.prog} --help` lists the options)\n")


def _table_rule(dest: str) -> str:
    """`` > 0 (from 1e-06 to 100 m)``: the rule of the joint's or the mechanism's parameter ``dest`` as its table
    states it (joint_fields, mechanism_parameters), '' for any other option."""
    from ..checks import ANY
    from ..joint_fields import FIELD_NAMES, JOINT_FIELDS, allowed_text
    from ..mechanism_parameters import FINITE, MECHANISM_FIELDS, RULE_TEXT, TABLE_ANGLE, TABLE_ROWS

    joint = next((f for f in JOINT_FIELDS if f.field == dest and f.component is None and f.choices is None
                  and f.allowed != ANY), None)
    mechanism = next((f for f in MECHANISM_FIELDS if f.field == dest and f.component is None and f.choices is None
                      and f.rule not in (FINITE, TABLE_ROWS, TABLE_ANGLE)), None)
    rule = allowed_text(joint, FIELD_NAMES) if joint else RULE_TEXT[mechanism.rule] if mechanism else ""
    return f" {rule}" if rule else ""


# command -> the class (module, name) whose fields its run options set, beside the joint's and the mechanism's
_OPTION_CLASSES = {"simulate": ("wearjoint.simulation_options", "SimulationOptions"),
                   "cosim": ("wearjoint.cosim.cosimulation", "CoSimulationOptions"),
                   "wear-study": ("wearjoint.studies.wear_study", "WearStudyConfig")}


def _option_rule(command: str, dest: str, shown_value: str) -> str | None:
    """What the run option ``dest`` of ``command`` allows, as its class's own check states it for the value argparse
    could not read (``shown_value``, a repr): ``a finite real number > 0``; None where that class has no such field."""
    import ast
    import dataclasses

    from ..mechanism_parameters import SliderCrankParameters
    from ..parameters import JointParameters

    if command not in _OPTION_CLASSES:
        return None
    module, name = _OPTION_CLASSES[command]
    cls = getattr(importlib.import_module(module), name)
    fields = {f.name for f in dataclasses.fields(cls)}
    field = next((n for n in (dest, *(f"{dest}_{s}" for s in _UNIT_SUFFIXES)) if n in fields), None)
    if field is None:
        return None
    models = {"joint": JointParameters(), "mechanism": SliderCrankParameters()}    # WearStudyConfig requires them
    try:
        cls(**{n: m for n, m in models.items() if n in fields}, **{field: ast.literal_eval(shown_value)})
    except ParameterError as exc:
        head, found, allowed = str(exc).partition(" is invalid: allowed ")
        return allowed if found and head.startswith(f"parameter {field}=") else None
    except (TypeError, ValueError, ArithmeticError):    # a check that does not name it: the kind alone
        return None
    return None


def build_parser(command: str | None) -> argparse.ArgumentParser:
    """The parser; only ``command``'s options are added (its module imported)."""
    parser = OneLineErrorParser(prog="wearjoint", description=DESCRIPTION)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if name == command:
            importlib.import_module(module).add_arguments(p)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    if command not in COMMANDS:
        command = None
    figures = _figure_worker(command, argv)
    try:
        parser = build_parser(command)
        args, extras = parser.parse_known_args(argv)
        if extras:                  # named by the command's parser: "wearjoint cosim: error: ..."
            commands = next(a for a in parser._actions if a.dest == "command").choices
            (commands[args.command] if args.command else parser).error(f"unrecognized arguments: {' '.join(extras)}")
        if args.command is None:
            parser.print_help()
            return 2
        args.figure_worker = figures
        args.written = written_options(parser, args.command, argv)
        args.command_line = _command_line(argv)
        made, code = [], 2
        try:
            made = _prepare_out(args)
            module = importlib.import_module(COMMANDS[args.command][0])
            with _compile_watch(module, args):   # the first line of a run that compiles says so
                code = int(module.run(args) or 0)
        except KeyboardInterrupt:           # a command that keeps finished work says where itself
            print(f"wearjoint {args.command}: interrupted", file=sys.stderr)
            code = 130
        except ParameterError as exc:
            print(f"wearjoint {args.command}: error: {as_written(str(exc), parser, args.command, argv)}",
                  file=sys.stderr)
            return 2
        finally:
            if code != 0:                        # a run that stopped before it wrote leaves no folder behind
                remove_empty_folders(made + getattr(args, "out_folders_made", []))   # the studies' own (sweep)
    finally:
        if figures is not None:
            figures.close()
    _report(args, argv)
    return code


def console() -> None:
    """The ``wearjoint`` program (and ``python -m wearjoint``): :func:`main`, then, once the exit handlers
    ran and the output is flushed, the exit without the interpreter's teardown: freeing numba's and LLVM's
    objects took 0.25 s, a sixth of the main job.  With other threads still running, the usual exit.

    numpy's OpenBLAS runs on one thread in the program's processes unless the user's environment says otherwise
    (OPENBLAS_NUM_THREADS): their linear algebra is small, and each process's idle BLAS thread spun for ~0.1 s
    after numpy's import, on the core the figure worker draws on (the main job 0.64 -> 0.58 s, results identical)."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    code = main()
    if threading.active_count() > 1:
        sys.exit(code)
    atexit._run_exitfuncs()          # what the usual exit would run first: stops the helper processes
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):     # a closed pipe (``| head``): nothing more to write there
            pass
    os._exit(code)


# the unit a parameter's API name adds to its option's (``--step`` sets ``step_s``, ``--onset-penetration``
# ``onset_penetration_m``; ``--fmu FILE`` ``fmu_path``)
_UNIT_SUFFIXES = ("s", "m", "N", "deg", "rad", "kg", "Pa", "m_s", "m_s2", "kg_m2", "path", "revolutions")


def as_written(message: str, parser: argparse.ArgumentParser, command: str, argv: list[str]) -> str:
    """A ParameterError's ``message`` naming the parameter and its value as the user wrote them: ``parameter
    step_s=0.0 is invalid: ...`` from ``--step 0`` becomes ``--step=0 (step_s) is invalid: ...``.  Where no option the user gave sets
    that parameter (a default) but its rule names one that does (``--step 2e-4`` against the default max_step_s),
    that option is named: ``--step=2e-4 (step_s) is invalid against max_step_s=0.0001 (not given; --max-step sets
    it): allowed max_step_s >= step_s = 0.0002``; a message that names the option already (``--step=1e-07 is invalid:
    ...``) gets the value as written (``--step=1e-7``); else unchanged (a value from a file, ``--param NAME=...``)."""
    given = {a.split("=", 1)[0] for a in argv if a.startswith("--")}
    actions = next(a for a in parser._actions if a.dest == "command").choices[command]._actions
    named = re.match(r"(--[\w-]+)=(\S+)( .*)$", message, re.DOTALL)
    if named is not None:
        option, value, rest = named.groups()
        action = next((a for a in actions if option in a.option_strings), None)
        return f"{option}={_as_typed(action, option, value, argv) if option in given else value}{rest}"
    match = re.match(r"parameter (\w+)=", message)
    if match is None:
        return message
    name = match.group(1)
    for action in actions:
        option = next((o for o in action.option_strings if o in given), None)
        if option is not None and _sets(action, name):
            value, invalid, allowed = message[match.end():].partition(" is invalid")
            return (f"{option}={_as_typed(action, option, value, argv)} ({name}){invalid}{allowed}"
                    f"{_defaults_named(allowed, name, actions, given)}")
    value, invalid, allowed = message[match.end():].partition(" is invalid: allowed ")
    for action in actions:
        option = next((o for o in action.option_strings if o in given), None)
        other = next((n for n in _set_names(action) if re.search(rf"[<>]=? *{n}\b", allowed)), None)   # "> pin_radius_m"
        if option is not None and other is not None and invalid:
            own = next((a.option_strings[0] for a in actions if a.option_strings and _sets(a, name)), None)
            return (f"{option}={_written_value(option, argv)} ({other}) is invalid against {name}={value} "
                    f"(not given{f'; {own} sets it' if own else ''}): allowed {name} {allowed}")
    return message


def _defaults_named(allowed: str, name: str, actions, given: set) -> str:
    """`` (step_s: not given; --step sets it)`` for each parameter but ``name`` that the rule ``allowed`` compares
    with (``<= step_s = 1e-05``) and that no option the user gave sets: the option to change, as well as this one."""
    notes = []
    for action in actions:
        other = next((n for n in _set_names(action) if n != name and re.search(rf"\b{n} *=", allowed)), None)
        if other is not None and not given.intersection(action.option_strings):
            notes.append(f" ({other}: not given; {action.option_strings[0]} sets it)")
    return "".join(notes)


def _as_typed(action: argparse.Action | None, option: str, value: str, argv: list[str]) -> str:
    """``value`` (a message's, parsed: ``-1.0``) as ``option`` was written in ``argv`` (``-1``) where that is one
    token; a quoted value (a string's repr) stays as it is."""
    typed = _written_value(option, argv)
    if action is None or action.nargs is not None or value[:1] in "'\"" or not typed:
        return value
    return typed


def _sets(action: argparse.Action, name: str) -> bool:
    """True if the option ``action`` sets the parameter ``name`` (its dest, or its dest with a unit's suffix)."""
    return name == action.dest or (name.startswith(action.dest + "_") and name[len(action.dest) + 1:] in _UNIT_SUFFIXES)


def _set_names(action: argparse.Action) -> list[str]:
    """The names the parameter an option sets may have in a message: its dest and its dest with a unit's suffix."""
    return [action.dest, *(f"{action.dest}_{suffix}" for suffix in _UNIT_SUFFIXES)] if action.option_strings else []


def _written_value(option: str, argv: list[str]) -> str:
    """The value of ``option`` as written in ``argv`` (``--x 1e-3`` or ``--x=1e-3``; the last one given)."""
    value = ""
    for k, a in enumerate(argv):
        if a == option and k + 1 < len(argv):
            value = argv[k + 1]
        elif a.startswith(option + "="):
            value = a[len(option) + 1:]
    return value


def written_options(parser: argparse.ArgumentParser, command: str, argv: list[str]) -> frozenset:
    """The dests of ``command``'s options written in ``argv`` (abbreviated or as ``--flag=value`` alike): ``argv``
    parsed again with every default of the command's parser suppressed."""
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    defaults, sub._defaults = sub._defaults, {}
    actions = [(action, action.default) for action in sub._actions]
    try:
        for action, _ in actions:
            action.default = argparse.SUPPRESS
        return frozenset(vars(parser.parse_args(argv))) - {"command"}
    finally:
        sub._defaults = defaults
        for action, default in actions:
            action.default = default


def _prepare_out(args) -> list:
    """The results folder of a command that writes one (out_folder.prepare_out_folder): the folders made."""
    out = getattr(args, "out", None)
    if out is None or args.command not in RESULT_COMMANDS + FILE_COMMANDS:
        return []
    return prepare_out_folder(args.command, out)


def _compile_watch(module, args):
    """The compile notice's watch of the command (:func:`wearjoint._compile.notice.watch_command`; of the kernels
    its module's ``compiled_kernels(args)`` names, if it has one), none where its module says the run compiles no
    numba kernel (``compiles(args)`` false): the watch imports numba."""
    compiles = getattr(module, "compiles", None)
    if compiles is not None and not compiles(args):
        return contextlib.nullcontext()
    from .._compile.notice import watch_command

    kernels = getattr(module, "compiled_kernels", None)
    return watch_command(kernels(args) if kernels is not None else args.command)


def _figure_worker(command: str | None, argv: list[str]):
    """The figure worker of a command of FIGURE_COMMANDS that writes figures, started first; else None."""
    if command not in FIGURE_COMMANDS or any(a in ("--no-plots", "-h", "--help") for a in argv):
        return None
    from ..figure_worker import FigureWorker

    return FigureWorker()


def _report(args, argv: list[str]) -> None:
    """The results folder's report.html with the command line that made it (wearjoint.report), where the
    command wrote a summary into ``--out``."""
    from ..report import summary_path, write_report
    from ..targets import report_facts

    out = getattr(args, "out", None)
    if out is None or args.command == "report" or summary_path(out) is None:
        return
    owners = results_commands(Path(out))
    if not owners or args.command in owners:      # not calibrate's into the study it fits
        summary = json.loads(summary_path(out).read_text()) if getattr(args, "resume", False) else {}
        started = summary.get("command_line") if summary.get("resumed_by") else None   # a resumed wear study's start
        write_report(out, started or _command_line(argv), report_facts(vars(args)))


def _command_line(argv: list[str]) -> str:
    """The command as a shell would run it again."""
    return "wearjoint " + " ".join(shlex.quote(a) for a in argv)


__all__ = ["main", "build_parser", "as_written", "written_options", "COMMANDS"]
