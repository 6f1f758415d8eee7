"""The one-line check of a parameter value every edge gives (API, CLI, FMU build, exudyn, sweep), and the error of a
run that cannot go on."""
from __future__ import annotations

import math


class ParameterError(ValueError):
    """A parameter value outside its allowed range."""


class RunDiverged(RuntimeError):
    """A run that cannot go on: its state left what the joint admits (docs/model.md §3.14) or is not finite; the
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
