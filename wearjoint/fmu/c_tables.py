"""C text of the generated model tables (``model_variables.h`` of each native FMU model)."""
from __future__ import annotations

import json


def c_string(text: str) -> str:
    """A valid C string literal for the ASCII texts used here."""
    return json.dumps(text)


def c_double(value: float) -> str:
    return repr(float(value))


def parameter_rows(parameters) -> list[str]:
    """The rows of a ``ParameterInfo`` table (fmu_src/fmi/fmu_model.h) for ``parameters`` =
    (name, slot, start, number of choices, :class:`~wearjoint.checks.Allowed`, index of the
    parameter it must exceed or -1, the allowed values as the error message states them); an
    ``Allowed.when`` names parameters of the same table (at most two)."""
    names = [row[0] for row in parameters]
    rows = []
    for name, slot, start, n_choices, a, above, text in parameters:
        if len(a.when) > 2:
            raise ValueError(f"parameter {name}: at most two conditions (Allowed.when), got {len(a.when)}")
        when = [(names.index(other), value) for other, value, *_ in a.when] + [(-1, 0.0)] * (2 - len(a.when))
        rows.append("    {%s, %d, %s, %d, %d, %d, %s, %d, %d, %s, %d, {%d, %d}, {%s, %s}, %s, %s}," % (
            c_string(name), slot, c_double(start), n_choices, a.low is not None, a.low_open, c_double(a.low or 0.0),
            a.high is not None, a.high_open, c_double(a.high or 0.0), above, when[0][0], when[1][0],
            c_double(when[0][1]), c_double(when[1][1]), c_double(a.equal or 0.0), c_string(text)))
    return rows


def state_problem_tables() -> str:
    """The message of each problem a state check reports (core/state_format.py), as printf formats of
    the values as text, and the kinds (d, g, x) of those values: ``STATE_PROBLEMS``, ``STATE_PROBLEM_KINDS``."""
    from ..core import state_format   # numba's kernels: the package's co-simulation imports none

    problems = state_format.printf_problems()
    return (f"#define STATE_N_PROBLEMS {len(problems)}\n"
            "static const char *const STATE_PROBLEMS[STATE_N_PROBLEMS] = {\n"
            + "".join(f"    {c_string(text)},\n" for text, _ in problems) + "};\n"
            "static const char *const STATE_PROBLEM_KINDS[STATE_N_PROBLEMS] = {"
            + ", ".join(c_string(kinds) for _, kinds in problems) + "};")
