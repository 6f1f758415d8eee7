"""The cases of a sweep: a grid of option values (``--vary``, a TOML design file) times an
ensemble of seeds, each case one run of a command, identified by a hash of its configuration.

A case is the target command's full option set (``dest -> value``, as its parser gives them: the
target's options, :mod:`wearjoint.targets`); its command line (:meth:`Case.argv`) names only the
options that differ from the command's defaults, so ``wearjoint COMMAND *case.argv() --out DIR`` is
the same run outside the sweep.  Seed s > 0 adds ``s * SEED_ANGLE_STEP_DEG`` (0.5 deg) to the initial
crank angle; seed 0 is the unperturbed run.  The step is large enough that the starts differ from the
first revolution (the pin starts centred at full speed, and the crank angle at the start decides where the
start-up impacts fall), so an ensemble samples the regimes a start can fall into (impacting, backward whirl:
docs/how-to/sweep_on_dask.md); the 1e-6 deg of earlier versions left starts that part only after ~80 ms of chaotic growth.
"""
from __future__ import annotations

import argparse
import dataclasses
import difflib
import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from pathlib import Path

from .. import targets
from ..parameters import JointParameters, ParameterError, SliderCrankParameters

TARGETS = tuple(targets.TARGETS)
SEED_ANGLE_STEP_DEG = 0.5           # seed s starts the crank at initial_crank_angle_deg + s * 0.5 deg
START_ANGLE_STEP_DEG = 1e-6         # validate's perturbed starts (:func:`perturbed_start`), not the sweep's
SEED_OPTION = "initial_crank_angle_deg"
# options the sweep sets itself or that name another task: never forwarded, never varied, not hashed
SWEEP_DESTS = ("vary", "design", "seeds", "workers", "scheduler", "resume", "retry_failed")
OUTPUT_DESTS = ("out", "quiet", "no_plots")
NOT_IN_A_SWEEP = ("convergence", "calibrate_max_depth_m")


@dataclass(frozen=True)
class Case:
    """One run of ``command``: ``point`` (swept option as written -> value), ``seed``, and the
    command's full ``options`` (dest -> value, outputs excluded)."""

    command: str
    point: tuple            # ((name, value), ...) in the order of the design's parameters
    seed: int
    options: tuple          # ((dest, value), ...) sorted by dest
    case_id: str

    def argv(self) -> list[str]:
        """The command's options that differ from its defaults (``--out`` not included)."""
        return options_to_argv(command_parser(self.command), dict(self.options))

    def to_dict(self) -> dict:
        return {"case_id": self.case_id, "command": self.command, "point": dict(self.point), "seed": self.seed,
                "command_line": ["wearjoint", self.command, *self.argv()]}


def command_parser(command: str) -> argparse.ArgumentParser:
    """A parser holding ``command``'s own options (the target's, :func:`wearjoint.targets.parser`); shared, read
    only."""
    return targets.parser(command)


def _option_actions(parser: argparse.ArgumentParser) -> dict:
    """dest -> action of every optional argument."""
    return {a.dest: a for a in parser._actions if a.option_strings and a.dest != "help"}


def command_options(command: str, namespace: argparse.Namespace) -> dict:
    """The command's options from a namespace (sweep and output options left out)."""
    skip = set(SWEEP_DESTS) | set(OUTPUT_DESTS)
    return {dest: getattr(namespace, dest, action.default)
            for dest, action in _option_actions(command_parser(command)).items() if dest not in skip}


def _text(value) -> str:
    return repr(value) if isinstance(value, float) else str(value)


def options_to_argv(parser: argparse.ArgumentParser, options: dict) -> list[str]:
    """The shortest command line giving ``options`` (``--name=value`` for each non-default value)."""
    argv = []
    for dest, action in _option_actions(parser).items():
        if dest not in options or dest in OUTPUT_DESTS:
            continue
        value = options[dest]
        if value == action.default or (value is None and action.default is None):
            continue
        flag = action.option_strings[-1]
        if isinstance(action, argparse._StoreTrueAction):
            argv.append(flag)
        elif isinstance(value, (list, tuple)):
            argv += [flag, *map(_text, value)]
        else:
            argv.append(f"{flag}={_text(value)}")
    return argv


def case_id(command: str, options: dict) -> str:
    """16 hex digits of the SHA-256 of the command and the options that differ from its defaults (an option a later
    version adds leaves the cases of a study it does not use as they were: ``--resume`` finds them)."""
    defaults = {dest: action.default for dest, action in _option_actions(command_parser(command)).items()}
    given = {dest: value for dest, value in options.items() if dest not in defaults or value != defaults[dest]}
    text = json.dumps({"command": command, "options": given}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# ------------------------------------------------------------------ the design
def variable_actions(command: str) -> dict:
    """Option name as written without dashes -> action, for every option of ``command`` that
    takes one value and may be swept."""
    skip = set(SWEEP_DESTS) | set(OUTPUT_DESTS) | set(NOT_IN_A_SWEEP) | {"fmu"}
    return {action.option_strings[-1].lstrip("-"): action
            for dest, action in _option_actions(command_parser(command)).items()
            if dest not in skip and action.nargs is None and isinstance(action, argparse._StoreAction)}


def parse_value(name: str, text, action, where: str):
    """A value of option ``name`` converted as the command's parser would (ParameterError if not)."""
    convert = action.type or str
    try:
        value = convert(str(text).strip())
    except (TypeError, ValueError):
        kind = {int: "an integer", float: "a number"}.get(convert, "a value of this option")
        raise ParameterError(f"{where}: {name}={str(text).strip()!r} is invalid: allowed {kind}") from None
    if action.choices is not None and value not in action.choices:
        raise ParameterError(f"{where}: {name}={value!r} is invalid: allowed one of {', '.join(action.choices)}")
    return value


def parse_vary(command: str, items) -> dict:
    """``["restitution=0.6,0.9", ...]`` -> {"restitution": [0.6, 0.9], ...} (values typed; a name may be the
    option's (``friction-coefficient``) or the API's (``friction_coefficient``), keyed by the option's)."""
    variables = variable_actions(command)
    grid = {}
    for item in items or ():
        name, sep, values = str(item).partition("=")
        name = name.strip().lstrip("-")
        if not sep or not values.strip():
            raise ParameterError(f"--vary {item!r} is invalid: allowed NAME=V1,V2,... (e.g. restitution=0.6,0.9)")
        name = canonical_name(command, variables, name, f"--vary {item!r}")
        if name in grid:
            raise ParameterError(f"--vary {item!r} is invalid: {name} is already varied (give its values once)")
        grid[name] = [parse_value(name, v, variables[name], f"--vary {item}") for v in values.split(",")]
    return grid


def canonical_name(command: str, variables: dict, name: str, where: str) -> str:
    """The option name (without dashes) that ``name`` spells: the option's own name, its API name (the
    option's dest: the JointParameters / SliderCrankParameters field, the CSV column) or either in
    another letter case; else a one-line ParameterError naming ``where``, the name and the allowed names."""
    aliases = {}
    for option, action in variables.items():
        aliases.update({option: option, action.dest: option})
    if name in aliases:
        return aliases[name]
    folded = {alias.casefold(): option for alias, option in aliases.items()}
    if name.casefold() in folded:
        return folded[name.casefold()]
    close = difflib.get_close_matches(name, list(aliases), n=1)
    hint = f" (did you mean {close[0]}?)" if close else ""
    raise ParameterError(f"{where} is invalid: {name!r} is not an option of wearjoint {command} that takes one "
                         f"value{hint}; allowed, as the option's name or its API name with underscores: "
                         + ", ".join(variables))


def read_design(command: str, path) -> dict:
    """A TOML design: ``seeds = N``, a ``[vary]`` table (name = [values]: a full grid) and/or
    ``[[case]]`` tables (one grid point each).  Returns {"seeds", "vary", "points"}."""
    try:
        import tomllib
    except ModuleNotFoundError:                  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError:
            raise ParameterError(f"--design {path}: reading TOML needs Python >= 3.11 or the tomli package") from None
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise ParameterError(f"--design {path}: cannot read it: {exc}") from None
    unknown = set(data) - {"seeds", "vary", "case"}
    if unknown:
        raise ParameterError(f"--design {path}: unknown key(s) {', '.join(sorted(unknown))}: allowed seeds, "
                             "[vary], [[case]]")
    variables = variable_actions(command)
    vary = {}
    for name, values in dict(data.get("vary", {})).items():
        where = f"--design {path} [vary] {name}"
        name = canonical_name(command, variables, name, where)
        if name in vary:
            raise ParameterError(f"{where} is invalid: {name} is already in [vary] (give its values once)")
        values = values if isinstance(values, list) else [values]
        vary[name] = [parse_value(name, v, variables[name], where) for v in values]
    points = []
    for k, table in enumerate(data.get("case", [])):
        where = f"--design {path} [[case]] {k + 1}"
        point = {}
        for name, v in table.items():
            name = canonical_name(command, variables, name, f"{where} {name}")
            point[name] = parse_value(name, v, variables[name], where)
        points.append(point)
    seeds = data.get("seeds")
    return {"seeds": seeds, "vary": vary, "points": points}


def check_seeds(seeds, where: str = "--seeds") -> int:
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 1:
        raise ParameterError(f"{where}={seeds!r} is invalid: allowed an integer >= 1")
    return seeds


def effective_values(command: str, options: dict) -> dict:
    """dest -> value of every model option as the command's run resolves it (an option left unset, None,
    stands for what the run uses: e.g. wear-study's wear factor, the slider-crank's joint offsets);
    the parameter sets' defaults where the options are invalid (the case then reports the error)."""
    try:
        joint, mechanism = targets.target(command).model(options)
    except (ParameterError, AttributeError, KeyError, TypeError, ValueError):
        joint, mechanism = JointParameters(), SliderCrankParameters()
    return {**dataclasses.asdict(mechanism), **dataclasses.asdict(joint)}


def _value(options: dict, resolved: dict, dest: str):
    value = options[dest]
    return resolved.get(dest, value) if value is None else value


def build_cases(command: str, base: dict, vary: dict | None = None, points=(), seeds: int = 1) -> list[Case]:
    """The cases of a design: the full grid of ``vary`` plus the explicit ``points``, each with
    seeds 0 .. seeds-1, on top of the command options ``base`` (dest -> value)."""
    targets.target(command)                     # ParameterError unless a target
    check_seeds(seeds)
    for dest in NOT_IN_A_SWEEP:
        if base.get(dest) is not None:
            raise ParameterError(f"--{dest.replace('_', '-')} is not available in a sweep (it is another task)")
    variables = variable_actions(command)
    vary = {canonical_name(command, variables, name, f"vary {name}"): values for name, values in (vary or {}).items()}
    grid = [dict(zip(vary, values)) for values in itertools.product(*vary.values())] if vary else []
    grid += [{canonical_name(command, variables, name, f"point {name}"): v for name, v in p.items()} for p in points]
    grid = grid or [{}]
    names = list(dict.fromkeys(name for point in grid for name in point))
    cases, seen = [], set()
    for point in grid:
        options = dict(base)
        for name in names:                        # a point lacking a name keeps the base value
            if name in point:
                options[variables[name].dest] = point[name]
        resolved = effective_values(command, options) if any(options[variables[n].dest] is None for n in names) else {}
        full_point = tuple((name, _value(options, resolved, variables[name].dest)) for name in names)
        for seed in range(seeds):
            opts = dict(options)
            if seed > 0:
                angle = opts.get(SEED_OPTION)
                angle = SliderCrankParameters().initial_crank_angle_deg if angle is None else float(angle)
                opts[SEED_OPTION] = angle + seed * SEED_ANGLE_STEP_DEG
                if not math.isfinite(opts[SEED_OPTION]):
                    raise ParameterError(f"initial-crank-angle-deg={angle!r} is invalid: allowed a finite number")
            cid = case_id(command, opts)
            if cid in seen:
                continue
            seen.add(cid)
            cases.append(Case(command, full_point, seed, tuple(sorted(opts.items())), cid))
    return cases


__all__ = ["Case", "TARGETS", "SEED_ANGLE_STEP_DEG", "build_cases", "parse_vary", "read_design", "case_id",
           "command_parser", "command_options", "options_to_argv", "variable_actions", "canonical_name",
           "check_seeds"]


def perturbed_start(mechanism: SliderCrankParameters, start: int) -> SliderCrankParameters:
    """The mechanism of validate's perturbed start number ``start`` (0: unperturbed): the initial crank
    angle moved by ``start`` times START_ANGLE_STEP_DEG (1e-6 deg; two starts part by 10 um after ~80 ms).
    Kept apart from the sweep's seed step (SEED_ANGLE_STEP_DEG): validate's ensembles and their
    tolerances were measured with these starts."""
    return mechanism.replace(initial_crank_angle_deg=mechanism.initial_crank_angle_deg
                             + start * START_ANGLE_STEP_DEG)
