"""The parameters of a sensitivity study: ``--param NAME=LOW,HIGH[,log]`` as a SALib problem.

``NAME`` is any numeric option of the target command that takes one value, in either spelling
(the option's, ``crank-speed-rpm``, or the API's, ``crank_speed_rpm``), resolved by the sweep's
design module.  A ``log`` parameter is sampled uniformly in log10 of its value (SALib sees
``[log10 LOW, log10 HIGH]``); the others uniformly in ``[LOW, HIGH]``, in the option's SI unit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..parameters import ParameterError
from ..sweep.design import canonical_name, check_grid, parse_value, variable_actions

FORM = "NAME=LOW,HIGH[,log] (e.g. restitution=0.6,0.95 or wear-coefficient-m2-N=2e-11,1e-10,log)"


@dataclass(frozen=True)
class Parameter:
    """One sampled option: ``name`` as written on the command line (no dashes), ``dest`` (the API name,
    the CSV column), its range ``low``..``high`` in the option's unit and whether it is sampled in log10."""

    name: str
    dest: str
    low: float
    high: float
    log: bool = False
    written: str = field(default="", compare=False)     # the --param item as the user wrote it (for messages)

    @property
    def bounds(self) -> list:
        """The range SALib samples: [LOW, HIGH], or [log10 LOW, log10 HIGH] for a log parameter."""
        return [math.log10(self.low), math.log10(self.high)] if self.log else [self.low, self.high]

    def values(self, column: np.ndarray) -> np.ndarray:
        """SALib's samples of this parameter -> the option's values (kept inside [LOW, HIGH] against rounding)."""
        return np.clip(10.0 ** column if self.log else column, self.low, self.high)

    def text(self) -> str:
        """The ``--param`` item as written (else NAME=LOW,HIGH[,log] from the values)."""
        return self.written or f"{self.name}={self.low!r},{self.high!r}" + (",log" if self.log else "")


@dataclass(frozen=True)
class Problem:
    """The sampled parameters of a study of ``command``."""

    command: str
    parameters: tuple

    @property
    def names(self) -> list:
        return [p.name for p in self.parameters]

    def salib(self) -> dict:
        """SALib's problem dict (names are the option names)."""
        return {"num_vars": len(self.parameters), "names": self.names, "bounds": [p.bounds for p in self.parameters]}

    def points(self, x: np.ndarray) -> list:
        """SALib's sample matrix (rows x parameters) -> one {option name: value} per row."""
        columns = [p.values(np.asarray(x[:, k], dtype=float)) for k, p in enumerate(self.parameters)]
        return [{p.name: float(c[i]) for p, c in zip(self.parameters, columns)} for i in range(x.shape[0])]

    def to_dict(self) -> list:
        return [{"name": p.name, "api_name": p.dest, "low": p.low, "high": p.high, "log": p.log}
                for p in self.parameters]


def parse_param(command: str, item: str, variables: dict) -> Parameter:
    """``NAME=LOW,HIGH[,log]`` -> :class:`Parameter`; a one-line ParameterError naming ``--param`` and the value."""
    where = f"--param {item!r}"
    name, sep, rest = str(item).partition("=")
    fields = [f.strip() for f in rest.split(",")]
    if not sep or len(fields) not in (2, 3) or (len(fields) == 3 and fields[2] != "log"):
        raise ParameterError(f"{where} is invalid: allowed {FORM}")
    real = {option: action for option, action in variables.items() if action.type is float}
    name = canonical_name(command, variables, name.strip().lstrip("-"), where, real, "takes a real value")
    action = variables[name]
    if action.type is not float:
        raise ParameterError(f"{where} is invalid: {name} is not a real-valued option (a sensitivity study "
                             "samples real numbers)")
    low, high = (parse_value(name, f, action, where) for f in fields[:2])
    log = len(fields) == 3
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ParameterError(f"{where} is invalid: LOW and HIGH must be finite numbers")
    if not low < high:
        raise ParameterError(f"{where} is invalid: LOW={low!r} >= HIGH={high!r}; allowed LOW < HIGH")
    if log and not low > 0.0:
        raise ParameterError(f"{where} is invalid: a log range must lie above 0 (LOW={low!r}); allowed 0 < LOW < HIGH")
    return Parameter(name, action.dest, low, high, log, str(item))


def parse_params(command: str, items, base: dict | None = None) -> Problem:
    """The problem of ``--param`` items (at least one, each named once); with ``base`` (the command's
    options, dest -> value), each parameter's LOW and HIGH are checked by the parameter sets' own
    validation, the others at theirs (:func:`check_ranges`)."""
    variables = variable_actions(command)
    parameters = []
    for item in items or ():
        parameter = parse_param(command, item, variables)
        if parameter.name in [p.name for p in parameters]:
            raise ParameterError(f"--param {item!r} is invalid: {parameter.name} is already sampled (give it once)")
        parameters.append(parameter)
    if not parameters:
        raise ParameterError(f"--param is missing: give at least one {FORM}")
    problem = Problem(command, tuple(parameters))
    if base is not None:
        check_ranges(problem, base)
    return problem


CORNERS_CHECKED = 1024      # a box of up to 10 parameters is checked at every corner (a few ms each)


def check_ranges(problem: Problem, base: dict) -> None:
    """The corners of the parameters' box (every combination of their LOW and HIGH, up to CORNERS_CHECKED of them;
    beyond, each parameter's LOW and HIGH with the others at ``base``) through the target's configuration (the checks
    its run makes before it starts; :func:`wearjoint.sweep.design.check_grid`): a one-line ParameterError naming
    ``--param`` as written, the value and what is allowed.  The rules between parameters are orderings (a bushing
    wider than its pin): kept at the corners, they hold inside."""
    where = {"vary": {p.name: f"--param {p.text()!r}" for p in problem.parameters}}
    if 2 ** len(problem.parameters) <= CORNERS_CHECKED:
        check_grid(problem.command, base, {p.name: [p.low, p.high] for p in problem.parameters}, where=where)
        return
    for p in problem.parameters:
        check_grid(problem.command, base, {p.name: [p.low, p.high]}, where=where)


__all__ = ["Parameter", "Problem", "parse_param", "parse_params", "check_ranges", "FORM"]
