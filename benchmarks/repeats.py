"""Repeat a measurement within one invocation; report its median beside the machine's load.

The benchmarks named in the README's performance table run their measurement ``--repeats``
times and print each figure as the median of the repeats, with the spread and the 1-minute
load average before the first and after the last repeat (2 shared cores: a load above 1
makes the figures pessimistic).
"""
from __future__ import annotations

import argparse
import os
import statistics

DEFAULT_REPEATS = 3


def _repeats(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or value < 1:
        raise argparse.ArgumentTypeError(f"--repeats={text!r} is invalid: allowed an integer >= 1")
    return value


def add_repeats_argument(parser: argparse.ArgumentParser, default: int = DEFAULT_REPEATS) -> None:
    parser.add_argument("--repeats", type=_repeats, default=default,
                        help=f"runs of the measurement in this invocation; figures are their medians "
                             f"(default {default})")


class Load:
    """The 1-minute load average when created and at :meth:`stop`."""

    def __init__(self):
        self.before = os.getloadavg()[0]
        self.after = None

    def stop(self) -> "Load":
        self.after = os.getloadavg()[0]
        return self

    def __str__(self) -> str:
        after = os.getloadavg()[0] if self.after is None else self.after
        return f"load {self.before:.2f} -> {after:.2f} on {os.cpu_count()} CPUs"


def median_text(values, fmt: str = ".3g") -> str:
    """``median (median of n: min..max)`` of ``values``; the median alone for one value."""
    values = list(values)
    median = statistics.median(values)
    if len(values) == 1:
        return f"{median:{fmt}} (1 run)"
    return f"{median:{fmt}} (median of {len(values)}: {min(values):{fmt}}..{max(values):{fmt}})"
