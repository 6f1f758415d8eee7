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
import re
from dataclasses import dataclass
from pathlib import Path

from .. import targets
from .limits import check_seeds
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
    inputs: tuple = ()      # ((dest, file name, bytes), ...): the files the options name (INPUT_FILES), shipped

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
        elif isinstance(value, (list, tuple)) and action.nargs is None:     # one argument holding a pair (gravity)
            argv.append(f"{flag}={','.join(map(_text, value))}")
        elif isinstance(value, (list, tuple)):
            argv += [flag, *map(_text, value)]
        else:
            argv.append(f"{flag}={_text(value)}")
    return argv


# the options that name an input file (dest -> the file read in the folder it names, None: the file itself): a case
# carries their contents, so that an edited file is another case and a worker on another machine reads them
INPUT_FILES = {"slider_force_table": None, "initial_profile": None, "calibration": "calibration.json"}


def case_inputs(options: dict) -> tuple:
    """((dest, file name, contents), ...) of the INPUT_FILES ``options`` name (a file that cannot be read: left to
    the run, which refuses it naming the option)."""
    inputs = []
    for dest, inner in INPUT_FILES.items():
        if options.get(dest) is not None:
            path = Path(options[dest]) / inner if inner else Path(options[dest])
            try:
                inputs.append((dest, path.name, path.read_bytes()))
            except OSError:
                pass
    return tuple(inputs)


def case_id(command: str, options: dict, inputs: tuple = ()) -> str:
    """16 hex digits of the SHA-256 of the command, the options that differ from its defaults (an option a later
    version adds leaves the cases of a study it does not use as they were: ``--resume`` finds them) and the contents
    of the files they name (``inputs``, :func:`case_inputs`: an edited load table is another case)."""
    defaults = {dest: action.default for dest, action in _option_actions(command_parser(command)).items()}
    given = {dest: value for dest, value in options.items() if dest not in defaults or value != defaults[dest]}
    contents = {dest: hashlib.sha256(data).hexdigest() for dest, _, data in inputs}
    text = json.dumps({"command": command, "options": given, **({"inputs": contents} if contents else {})},
                      sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# ------------------------------------------------------------------ the design
# options whose one value is a comma-separated list (GX,GY; R1,R2,...): --vary would split it into grid points
LIST_DESTS = ("gravity_m_s2", "snapshots")


def variable_actions(command: str) -> dict:
    """Option name as written without dashes -> action, for every option of ``command`` that
    takes one value and may be swept."""
    skip = set(SWEEP_DESTS) | set(OUTPUT_DESTS) | set(NOT_IN_A_SWEEP) | {"fmu"}
    return {action.option_strings[-1].lstrip("-"): action
            for dest, action in _option_actions(command_parser(command)).items()
            if dest not in skip and action.nargs is None and isinstance(action, argparse._StoreAction)}


def parse_value(name: str, text, action, where: str):
    """A value of option ``name`` converted as the command's parser would (ParameterError if not); a list (a design
    file's) is one value only of an option of LIST_DESTS, written with commas."""
    if isinstance(text, (list, dict)) and not (isinstance(text, list) and action.dest in LIST_DESTS):
        raise ParameterError(f"{where}: {name}={text!r} is invalid: allowed one value")
    text = ",".join(map(str, text)) if isinstance(text, list) else str(text).strip()
    convert = action.type or str
    try:
        value = convert(text)
    except (TypeError, ValueError, argparse.ArgumentTypeError):
        kind = {int: "an integer", float: "a number"}.get(convert, f"a value of --{name} ({action.metavar or 'text'})")
        raise ParameterError(f"{where}: {name}={text!r} is invalid: allowed {kind}") from None
    if action.choices is not None and value not in action.choices:
        raise ParameterError(f"{where}: {name}={value!r} is invalid: allowed one of {', '.join(action.choices)}")
    return value


def parse_values(name: str, texts: list, action, where: str) -> list:
    """The values of a varied option ``name`` (:func:`parse_value`): one or more, each once."""
    if not texts:
        raise ParameterError(f"{where}: {name}=[] is invalid: allowed one or more values")
    values = []
    for text in texts:
        value = parse_value(name, text, action, where)
        if value in values:
            raise ParameterError(f"{where}: {name}={value!r} is given twice: allowed each value once")
        values.append(value)
    return values


def _vary_items(command: str, items) -> tuple:
    """({option name: values}, {option name: the item as written, '--vary NAME=V1,V2'}) of ``--vary`` items."""
    variables = variable_actions(command)
    grid, written = {}, {}
    for item in items or ():
        name, sep, values = str(item).partition("=")
        name = name.strip().lstrip("-")
        if not sep or not values.strip():
            raise ParameterError(f"--vary {item!r} is invalid: allowed NAME=V1,V2,... (e.g. restitution=0.6,0.9)")
        name = canonical_name(command, variables, name, f"--vary {item!r}")
        if name in grid:
            raise ParameterError(f"--vary {item!r} is invalid: {name} is already varied (give its values once)")
        if variables[name].dest in LIST_DESTS:
            raise ParameterError(f"--vary {item!r} is invalid: a value of {name} may hold commas, which --vary "
                                 f"reads as a list of values; allowed: vary it in a --design file, [vary] {name} = "
                                 '["V1", "V2", ...] (each value as the command line writes it) or one [[case]] '
                                 "table per value")
        written[name] = f"--vary {item}"
        grid[name] = parse_values(name, values.split(","), variables[name], written[name])
    return grid, written


def parse_vary(command: str, items) -> dict:
    """``["restitution=0.6,0.9", ...]`` -> {"restitution": [0.6, 0.9], ...} (values typed; a name may be the
    option's (``friction-coefficient``) or the API's (``friction_coefficient``), keyed by the option's)."""
    return _vary_items(command, items)[0]


def canonical_name(command: str, variables: dict, name: str, where: str, allowed: dict | None = None,
                   kind: str = "takes one value") -> str:
    """The option name (without dashes) that ``name`` spells: the option's own name, its API name (the
    option's dest: the JointParameters / SliderCrankParameters field, the CSV column) or either in
    another letter case; else a one-line ParameterError naming ``where``, the name and the allowed names (those of
    ``allowed``, default ``variables``: options that ``kind``)."""
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
    raise ParameterError(f"{where} is invalid: {name!r} is not an option of wearjoint {command} that {kind}{hint}; "
                         "allowed, as the option's name or its API name with underscores: "
                         + ", ".join(variables if allowed is None else allowed))


def read_design(command: str, path) -> dict:
    """A TOML design: ``seeds = N``, a ``[vary]`` table (name = [values]: a full grid) and/or
    ``[[case]]`` tables (one grid point each).  Returns {"seeds", "vary", "points", "where"} (``where``: each
    varied name's and each point's key in the file, {"vary": {name: key}, "points": [key, ...]})."""
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
    tables, cases = data.get("vary", {}), data.get("case", [])
    if not isinstance(tables, dict):
        raise ParameterError(f"--design {path}: vary={tables!r} is invalid: allowed a [vary] table of "
                             "name = [values]")
    if not (isinstance(cases, list) and all(isinstance(table, dict) for table in cases)):
        raise ParameterError(f"--design {path}: case={cases!r} is invalid: allowed [[case]] tables of "
                             "name = value")
    variables = variable_actions(command)
    vary, where = {}, {"vary": {}, "points": []}
    for name, values in tables.items():
        key = f"--design {path} [vary] {name}"
        name = canonical_name(command, variables, name, key)
        if name in vary:
            raise ParameterError(f"{key} is invalid: {name} is already in [vary] (give its values once)")
        vary[name] = parse_values(name, values if isinstance(values, list) else [values], variables[name], key)
        where["vary"][name] = key
    points = []
    for k, table in enumerate(cases):
        key = f"--design {path} [[case]] {k + 1}"
        point = {}
        for name, v in table.items():
            name = canonical_name(command, variables, name, f"{key} {name}")
            if name in point:
                raise ParameterError(f"{key} {name} is invalid: {name} is already in this [[case]] (give it once)")
            point[name] = parse_value(name, v, variables[name], key)
        points.append(point)
        where["points"].append(key)
    seeds = data.get("seeds")
    if seeds is not None:
        check_seeds(seeds, f"--design {path}: seeds")
    return {"seeds": seeds, "vary": vary, "points": points, "where": where}


def sweep_design(command: str, items, path=None) -> dict:
    """The design of ``--vary`` ``items`` and the ``--design`` file ``path`` together (:func:`read_design`'s dict):
    their grids merged into one; a name varied in both is refused, as a name given twice in either."""
    design = read_design(command, path) if path else {"seeds": None, "vary": {}, "points": [],
                                                      "where": {"vary": {}, "points": []}}
    grid, written = _vary_items(command, items)
    for name in grid:
        if name in design["vary"]:
            raise ParameterError(f"{written[name]} is invalid: {name} is already varied in "
                                 f"{design['where']['vary'][name]} (give its values once)")
    design["vary"].update(grid)
    design["where"]["vary"].update(written)
    return design


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
    vary, points = by_option_name(command, vary, points)
    grid = [dict(zip(vary, values)) for values in itertools.product(*vary.values())] if vary else []
    grid = grid + points or [{}]
    names = list(dict.fromkeys(name for point in grid for name in point))
    defaults = {dest: action.default for dest, action in _option_actions(command_parser(command)).items()}
    twice = [name for name in names             # options given beside a design that sets them at every point
             if all(name in point for point in grid)
             and base.get(variables[name].dest, defaults.get(variables[name].dest)) != defaults.get(variables[name].dest)]
    if twice:                                   # all in one line (one at a time took a run each)
        raise ParameterError(f"{' and '.join(f'--{n}={base[variables[n].dest]!r}' for n in twice)} "
                             f"{'is' if len(twice) == 1 else 'are'} invalid beside a design that sets "
                             f"{' and '.join(twice)} at every point (--vary, --param, --design): allowed one of the two"
                             f"{'' if len(twice) == 1 else ' for each'}")
    cases, seen, read = [], set(), {}
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
            files = tuple(str(opts.get(dest)) for dest in INPUT_FILES)    # each set of files read once
            if files not in read:
                read[files] = case_inputs(opts)
            inputs = read[files]
            cid = case_id(command, opts, inputs)
            if cid in seen:
                continue
            seen.add(cid)
            cases.append(Case(command, full_point, seed, tuple(sorted(opts.items())), cid, inputs))
    return cases


def by_option_name(command: str, vary: dict | None, points=()) -> tuple[dict, list]:
    """``vary`` (name -> values) and ``points`` (name -> value each) keyed by option name (:func:`canonical_name`)."""
    variables = variable_actions(command)
    return ({canonical_name(command, variables, name, f"vary {name}"): values for name, values in (vary or {}).items()},
            [{canonical_name(command, variables, name, f"point {name}"): v for name, v in p.items()} for p in points])


def given_options(command: str, base: dict) -> list[tuple]:
    """(dest, flag, value) of each of ``command``'s options in ``base`` that differs from its default (sweep and
    output options left out)."""
    skip = set(SWEEP_DESTS) | set(OUTPUT_DESTS)
    actions = _option_actions(command_parser(command))
    return [(dest, action.option_strings[-1], base[dest]) for dest, action in actions.items()
            if dest in base and dest not in skip and base[dest] != action.default]


def configure(command: str, options: dict):
    """``command``'s configuration of ``options`` (the ``config`` of :func:`wearjoint.targets.target`) with the checks
    its run makes before it starts: a monolithic engine's options resolved for the joint, which refuses a step beyond
    the wear-step limit (:meth:`wearjoint.simulation_options.SimulationOptions.for_joint`)."""
    from ..simulation_options import SimulationOptions

    config = targets.target(command).config(options)
    if isinstance(getattr(config, "options", None), SimulationOptions):
        config.options.for_joint(config.joint, config.mechanism)
    return config


def check_grid(command: str, base: dict, vary: dict | None = None, points=(), where: dict | None = None) -> None:
    """Every case the grid of ``vary`` and ``points`` runs through :func:`configure` before any runs: each value
    of a single varied option, each combination of several, each point (``base`` alone where nothing varies; a
    base value a varied option replaces is never checked alone: a small pin's bushing against the default pin).
    A bad one raises a one-line ParameterError naming where it was written (``where``: :func:`read_design`'s, else
    ``vary NAME`` and ``point K``; the option that set a bad base value), the value and what is allowed.  A case
    that passes may still fail as it runs (a diverged run): the sweep records it as failed."""
    variables, where = variable_actions(command), where or {}
    vary, points = by_option_name(command, vary, points)
    named = {name: where.get("vary", {}).get(name, f"vary {name}") for name in vary}
    trials = [(", ".join(named.values()), dict(zip(vary, values)))     # the cases build_cases makes
              for values in itertools.product(*vary.values())] if vary else []
    labels = where.get("points") or [f"point {k + 1}" for k in range(len(points))]
    trials += list(zip(labels, points))
    for label, point in trials or [("", {})]:
        try:
            configure(command, {**base, **{variables[name].dest: value for name, value in point.items()}})
        except ParameterError as exc:
            raise ParameterError(_refusal(command, base, label, point, variables, str(exc))) from None


def _refusal(command: str, base: dict, where: str, point: dict, variables: dict, message: str) -> str:
    """The one line of a case refused with ``message``: the point's value it is about (``WHERE: NAME=VALUE is
    invalid: allowed ...``), else the base option it is about (``--FLAG=VALUE is invalid...``), else the point and
    the message."""
    for name, value in point.items():
        reason = _reason(message, variables[name].dest, value)
        if reason:
            return f"{_named_where(where, name, point)}: {_shown({name: value})} is invalid{reason}"
    for dest, flag, value in given_options(command, base):
        reason = _reason(message, dest, value)
        if reason and dest not in {variables[name].dest for name in point}:   # with the point's value it cites
            cited = {n: v for n, v in point.items() if variables[n].dest in reason}
            return f"{flag}={value!r} is invalid{f' with {_shown(cited)} ({where})' if cited else ''}{reason}"
    if not point:
        return message
    return f"{where}: {'the grid point ' if len(point) > 1 else ''}{_shown(point)} is invalid: {message}"


def _named_where(where: str, name: str, point: dict) -> str:
    """``where`` (a combination's, ``vary A, vary B``) cut to the part naming ``name`` where it lists one per
    varied option."""
    parts = where.split(", ")
    return parts[list(point).index(name)] if len(parts) == len(point) > 1 else where


def _shown(point: dict) -> str:
    return ", ".join(f"{name}={str(value) if isinstance(value, Path) else repr(value)}"   # a file as the user wrote it
                     for name, value in point.items())


def _reason(message: str, dest: str, value) -> str | None:
    """What ``message`` (a ParameterError's, ``parameter NAME=VALUE is invalid...`` or ``--FLAG=VALUE is
    invalid...``) says after ``is invalid`` (e.g. ``: allowed > 0``), if it is about option ``dest`` (NAME its API
    name: ``step`` sets ``step_s``) at ``value``; else None."""
    subject = re.match(r"(?:parameter |(?=--))(\S+?)=(.*?) is invalid(\W.*)", message)
    if (subject is not None and dest in subject.group(1).lstrip("-").replace("-", "_")
            and subject.group(2) in (repr(value), str(value), repr(str(value)))):   # a file: its path quoted
        return subject.group(3)
    return None


def design_record(command: str, base: dict, vary: dict | None = None, points=(), seeds: int = 1) -> dict:
    """A sweep's design as its sweep.json records it and ``--resume`` compares it (:func:`design_changes`): the
    command, its options that differ from their defaults (by flag), the grid and the points (by option name),
    the seeds; as JSON reads it back."""
    vary, points = by_option_name(command, vary, points)
    record = {"command": command, "options": {flag: value for _, flag, value in given_options(command, base)},
              "vary": vary, "points": points, "seeds": seeds}
    return json.loads(json.dumps(record, default=str))


def design_changes(old: dict, new: dict) -> list[str]:
    """What differs from design ``old`` in ``new`` (:func:`design_record`), each as the user sets it, e.g.
    ``--vary restitution: [0.6] there, [0.7] now``."""
    def shown(value):
        return "not given" if value is None else repr(value)

    changes = [f"COMMAND: {old['command']} there, {new['command']} now"] if old["command"] != new["command"] else []
    for key, label in (("options", "{}"), ("vary", "--vary {}")):
        for name in dict.fromkeys([*old[key], *new[key]]):
            if old[key].get(name) != new[key].get(name):
                changes.append(f"{label.format(name)}: {shown(old[key].get(name))} there, "
                               f"{shown(new[key].get(name))} now")
    if old["points"] != new["points"]:
        changes.append(f"[[case]] points: {old['points']!r} there, {new['points']!r} now")
    if old["seeds"] != new["seeds"]:
        changes.append(f"--seeds: {old['seeds']} there, {new['seeds']} now")
    return changes


__all__ = ["Case", "TARGETS", "SEED_ANGLE_STEP_DEG", "build_cases", "parse_vary", "read_design", "case_id",
           "command_parser", "command_options", "options_to_argv", "variable_actions", "canonical_name",
           "check_grid", "sweep_design", "parse_values", "LIST_DESTS",
           "design_record", "design_changes", "configure",
           "by_option_name", "given_options"]


def perturbed_start(mechanism: SliderCrankParameters, start: int) -> SliderCrankParameters:
    """The mechanism of validate's perturbed start number ``start`` (0: unperturbed): the initial crank
    angle moved by ``start`` times START_ANGLE_STEP_DEG (1e-6 deg; two starts part by 10 um after ~80 ms).
    Kept apart from the sweep's seed step (SEED_ANGLE_STEP_DEG): validate's ensembles and their
    tolerances were measured with these starts."""
    return mechanism.replace(initial_crank_angle_deg=mechanism.initial_crank_angle_deg
                             + start * START_ANGLE_STEP_DEG)
