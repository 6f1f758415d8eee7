"""A command that compiles says so first (wearjoint.compile_notice): one line on stderr naming what
compiles and about how long it takes, before anything else; nothing when nothing compiles."""
import json

import numpy as np
from numba import njit

from wearjoint import compile_notice
from wearjoint.cosim import cosimulation


def _fresh_kernel():
    """A function numba has not compiled yet (a new one per call)."""
    return njit(lambda x: np.sqrt(x) + 1.0)


def test_the_first_compilation_announces_what_compiles_and_its_time(capsys):
    kernel = _fresh_kernel()
    with compile_notice.watching("simulate") as watch:
        kernel(4.0)
        kernel(2)                                   # a second specialisation: counted, not announced again
    err = capsys.readouterr().err
    text, seconds, _ = compile_notice.ESTIMATES["simulate"]
    assert err.splitlines()[0] == (f"wearjoint: compiling {text}: about {seconds} s on first use, "
                                   "cached for later runs")
    assert err.count("wearjoint: compiling") == 1 and watch.count == 2


def test_nothing_is_said_when_nothing_compiles(capsys):
    kernel = _fresh_kernel()
    kernel(4.0)
    capsys.readouterr()
    with compile_notice.watch_command("cosim") as watch:
        kernel(9.0)
    assert capsys.readouterr().err == "" and watch.count == 0


def test_the_profile_lists_each_compilation_with_its_own_time(tmp_path, monkeypatch):
    profile = tmp_path / "compile.jsonl"
    monkeypatch.setenv(compile_notice.PROFILE_ENV, str(profile))
    kernel = _fresh_kernel()
    with compile_notice.watching("kernels", quiet=True):
        kernel(4.0)
    rows = [json.loads(line) for line in profile.read_text().splitlines()]
    assert [row[0].rsplit(".", 1)[-1] for row in rows] == ["<lambda>"] and rows[0][2] > 0.0


def test_a_cached_or_given_fmu_starts_no_build(tmp_path):
    given = tmp_path / "given.fmu"
    assert cosimulation._start_fmu_build(1257, given, "native") is None
