"""The one-line check of a parameter value every edge gives (API, CLI, FMU build, exudyn, sweep), and the error of a
run that cannot go on."""
from __future__ import annotations

import math
import numbers
import re
import reprlib
from dataclasses import dataclass


class ParameterError(ValueError):
    """A parameter value outside its allowed range."""


class RunStopped(RuntimeError):
    """A run that cannot go on: an engine's call failed after the run began (an FMU's, say), or
    :class:`RunDiverged`; the message says when and why (the run pipeline keeps what came before,
    ``completed: false``: the ``samples_written`` samples the engine's call wrote before it stopped among them)."""

    def __init__(self, message: str = "", samples_written: int = 0):
        super().__init__(message)
        self.samples_written = samples_written


class RunDiverged(RunStopped):
    """A run that cannot go on: its state left what the joint admits (docs/reference/model.md §3.14) or is not finite; the
    message says when and why (the run pipeline keeps what came before, ``completed: false``)."""


def worn_through_message(when: str, max_depth_m: float, bushing_radius_m: float) -> str:
    """The bushing wore through ``when``: its deepest point ``max_depth_m`` [m] passed its radius, the deepest wear
    a state holds (core.admissibility: a profile that can be neither restored nor continued from)."""
    return f"the bushing wore through {when}: max depth {max_depth_m:.6g} m, its radius {bushing_radius_m:g} m"


def require(name: str, value, ok: bool, allowed: str) -> None:
    """ParameterError naming ``name``, its ``value`` and what is ``allowed`` unless ``ok``: the one-line message
    every edge (API, CLI, FMU build, exudyn, sweep) gives for a bad value; a command-line option (``--master``) is
    named as it is written, without "parameter"."""
    if not ok:
        named = name if name.startswith("-") else f"parameter {name}"
        raise ParameterError(f"{named}={value!r} is invalid: allowed {allowed}")


def with_options(error: ParameterError, options: dict, written: dict | None = None) -> ParameterError:
    """``error`` naming the option as written where its parameter has one in ``options`` (the API's name -> the
    option), with the value as written where ``written`` has it (the API's name -> the option's value):
    ``parameter jump_block_revolutions=0 is invalid: ...`` -> ``--cycle-jump-block=0 (jump_block_revolutions) is
    invalid: ...``; ``error`` itself otherwise."""
    match = re.match(r"parameter (\w+)=(.*?) (?:is|are) invalid", str(error))
    if match is None or match.group(1) not in options:
        return error
    name = match.group(1)
    value = repr(written[name]) if written and name in written else match.group(2)
    return ParameterError(f"{options[name]}={value} ({name}) is invalid{str(error)[match.end():]}")


def shown(value) -> str:
    """``value`` as a message shows it: its repr, abbreviated where long (reprlib), an array as its list."""
    return reprlib.repr(value.tolist() if getattr(value, "ndim", 0) > 0 else value)


def refuse(name: str, value, allowed: str, why: str = "") -> None:
    """The one-line ParameterError naming ``name``, ``value`` (:func:`shown`), ``why`` it fails (optional) and what
    is ``allowed``."""
    raise ParameterError(f"parameter {name}={shown(value)} is invalid{f' ({why})' if why else ''}: allowed {allowed}")


def real_array(name: str, value, allowed: str):
    """``value`` as a float numpy array if it holds real numbers only (no strings, booleans, complex numbers or
    other objects), else :func:`refuse` naming ``name``."""
    import numpy as np      # here: the command line imports this module before numpy

    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):     # a ragged sequence
        raw = np.asarray(None)
    if raw.dtype.kind not in "iuf":
        refuse(name, value, allowed, "not real numbers")
    return raw.astype(float)


class ParameterTypeError(ParameterError, TypeError):
    """A parameter value of a type the parameter does not take (a string for a number, a bool for an integer)."""


def is_real(value) -> bool:
    """Whether ``value`` is a real number: an int, a float or a numpy real scalar (not a bool, a string, bytes, a
    Decimal, a complex, None or an array)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def finite(name: str, value, rule: str = "") -> float:
    """``value`` as a float where it is a finite real number (:func:`is_real`), else :func:`require`'s error naming
    ``name``, stating ``rule`` (the rest of the allowed range, e.g. ``> 0``) after "a finite real number"."""
    allowed = "a finite real number" + (f" {rule}" if rule else "")
    if not is_real(value):
        raise ParameterTypeError(f"parameter {name}={shown(value)} is invalid: allowed {allowed}")
    x = float(value)
    require(name, value, math.isfinite(x), allowed)
    return x


def positive(name: str, value) -> float:
    """``value`` as a float where it is a finite real number > 0, else the error naming ``name``."""
    x = finite(name, value, "> 0")
    require(name, value, x > 0.0, "> 0")
    return x


def non_negative(name: str, value) -> float:
    """``value`` as a float where it is a finite real number >= 0, else the error naming ``name``."""
    x = finite(name, value, ">= 0")
    require(name, value, x >= 0.0, ">= 0")
    return x


def integer(name: str, value, low: int, high: int | None = None) -> int:
    """``value`` as an int where it is an integer (Python's or numpy's, not a bool) from ``low`` (to ``high``), else
    the error naming ``name``."""
    allowed = f"an integer from {low} to {high}" if high is not None else f"an integer >= {low}"
    if not isinstance(value, numbers.Integral) or isinstance(value, bool):
        raise ParameterTypeError(f"parameter {name}={shown(value)} is invalid: allowed {allowed}")
    require(name, value, low <= value and (high is None or value <= high), allowed)
    return int(value)


def flag(name: str, value) -> bool:
    """``value`` as a bool where it is one (Python's or numpy's), else the error naming ``name``: a truthy string
    or number is no answer to a yes-or-no option."""
    import numpy as np      # here: the command line imports this module before numpy

    if not isinstance(value, (bool, np.bool_)):
        raise ParameterTypeError(f"parameter {name}={shown(value)} is invalid: allowed True or False")
    return bool(value)


def finite_pair(name: str, value, allowed: str) -> tuple[float, float]:
    """``value`` as two floats where it is a sequence of two finite real numbers (not a string), else the error
    naming ``name`` and what is ``allowed``."""
    try:
        ok = (not isinstance(value, (str, bytes)) and len(value) == 2
              and all(is_real(v) and math.isfinite(v) for v in value))
    except TypeError:
        ok = False
    if not ok:
        raise ParameterTypeError(f"parameter {name}={shown(value)} is invalid: allowed {allowed}")
    return float(value[0]), float(value[1])


def of_type(name: str, value, cls: type, none_means: str):
    """``value`` where it is a ``cls`` or None (which means ``none_means``), else the error naming ``name`` and the
    type expected (e.g. arguments given in the wrong order)."""
    if value is not None and not isinstance(value, cls):
        raise ParameterTypeError(f"parameter {name}={shown(value)} is invalid: allowed a {cls.__name__} or None "
                                 f"({none_means})")
    return value


def choice(name: str, value, choices) -> None:
    require(name, value, value in choices, "one of " + ", ".join(choices))


@dataclass(frozen=True)
class Allowed:
    """The allowed values of a real parameter: finite, within (or on) ``low`` / ``high`` where given, greater than
    the parameter named ``above``, and ``equal`` where a parameter of ``when`` = ((its name, value, label, the
    condition as the parameter set states it), ...) has that value.  With a ``note`` (ASCII: the native FMU's
    messages carry it) ``low`` (if above 0) and ``high`` are generous, inclusive bounds on a positive (``low`` 0
    and closed: non-negative) quantity, stated after its sign with the note (the unit, why there).  Names are
    those of the table the rule sits in (the FMU's parameter names); the native FMUs check the same rules from
    their generated tables (:func:`wearjoint.fmu.c_tables.parameter_rows`)."""

    low: float | None = None
    low_open: bool = False
    high: float | None = None
    high_open: bool = False
    above: str | None = None
    equal: float | None = None
    when: tuple[tuple[str, float, str, str], ...] = ()
    note: str = ""

    def text(self, names=None, values=None) -> str:
        """The rule as :class:`ParameterError` messages state it, e.g. ``> 0`` or ``in (0, 1]``; ``names`` maps
        the table's names to those the reader knows (the parameter set's fields), and a condition is then
        stated as the parameter set states it; with ``values`` (the table's values by name) only the conditions
        that hold for them."""
        if self.note:
            floor = f"{self.low:g}" if self.low else None
            bounds = (f"from {floor} to {self.high:g}" if floor and self.high is not None
                      else f"at least {floor}" if floor else f"at most {self.high:g}")
            rule = f"{'>= 0' if self.low == 0.0 and not self.low_open else '> 0'} ({bounds} {self.note})"
        elif self.low is not None and self.high is not None:
            rule = f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"
        elif self.low is not None:
            rule = f"{'>' if self.low_open else '>='} {self.low:g}"
        else:
            rule = "a finite real number"
        for other, value, label, stated in self.when:
            if values is not None and values[other] != value:
                continue
            rule += f", and {self.equal!r} with {stated if names else f'{other}={value:g} ({label})'}"
        above = names[self.above] if names and self.above else self.above
        return rule + (f" and > {above}" if self.above else "")

    def admits(self, value: float, values: dict) -> bool:
        """Whether ``value`` keeps the rule, ``values`` the table's other values by name."""
        if not math.isfinite(value):
            return False
        if self.low is not None and not (value > self.low if self.low_open else value >= self.low):
            return False
        if self.high is not None and not (value < self.high if self.high_open else value <= self.high):
            return False
        if self.above is not None and not value > values[self.above]:
            return False
        return all(value == self.equal for other, when, *_ in self.when if values[other] == when)


ANY, POSITIVE, NON_NEGATIVE = Allowed(), Allowed(0.0, True), Allowed(0.0)


def path(text: str):
    """A path the command line takes (argparse's ``type``; its name ``path`` in argparse's message): not empty, which
    ``Path`` reads as the current folder (``--out ''`` wrote the results there)."""
    from pathlib import Path

    if not text.strip():
        raise ValueError("an empty path")
    return Path(text)
