"""The one-line check of a parameter value every edge gives (API, CLI, FMU build, exudyn, sweep), and the error of a
run that cannot go on."""
from __future__ import annotations

import math
from dataclasses import dataclass


class ParameterError(ValueError):
    """A parameter value outside its allowed range."""


class RunDiverged(RuntimeError):
    """A run that cannot go on: its state left what the joint admits (docs/reference/model.md §3.14) or is not finite; the
    message says when and why (the run pipeline keeps what came before, ``completed: false``)."""


def require(name: str, value, ok: bool, allowed: str) -> None:
    """ParameterError naming ``name``, its ``value`` and what is ``allowed`` unless ``ok``: the one-line message
    every edge (API, CLI, FMU build, exudyn, sweep) gives for a bad value."""
    if not ok:
        raise ParameterError(f"parameter {name}={value!r} is invalid: allowed {allowed}")


def finite(name: str, value) -> float:
    """``value`` as a finite float, else :func:`require`'s error naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"parameter {name}={value!r} is invalid: allowed a finite real number") from None
    require(name, value, math.isfinite(x), "a finite real number")
    return x


def is_finite_pair(value) -> bool:
    try:
        return len(value) == 2 and all(math.isfinite(float(v)) for v in value)
    except (TypeError, ValueError):
        return False


def positive(name: str, value) -> None:
    require(name, value, finite(name, value) > 0.0, "> 0")


def choice(name: str, value, choices) -> None:
    require(name, value, value in choices, "one of " + ", ".join(choices))


@dataclass(frozen=True)
class Allowed:
    """The allowed values of a real parameter: finite, within (or on) ``low`` / ``high`` where given, greater than
    the parameter named ``above``, and ``equal`` where a parameter of ``when`` = ((its name, value, label, the
    condition as the parameter set states it), ...) has that value.  Names are those of the table the rule sits in
    (the FMU's parameter names); the native FMUs check
    the same rules from their generated tables (:func:`wearjoint.fmu.c_tables.parameter_rows`)."""

    low: float | None = None
    low_open: bool = False
    high: float | None = None
    high_open: bool = False
    above: str | None = None
    equal: float | None = None
    when: tuple[tuple[str, float, str, str], ...] = ()

    def text(self, names=None) -> str:
        """The rule as :class:`ParameterError` messages state it, e.g. ``> 0`` or ``in (0, 1]``; ``names`` maps
        the table's names to those the reader knows (the parameter set's fields), and a condition is then
        stated as the parameter set states it."""
        if self.low is not None and self.high is not None:
            rule = f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"
        elif self.low is not None:
            rule = f"{'>' if self.low_open else '>='} {self.low:g}"
        else:
            rule = "a finite real number"
        for other, value, label, stated in self.when:
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
