"""Values past any meaningful run are refused at the edge, in one line naming the option as written and its range
(exit status 2, nothing written): they used to run for minutes, be killed for their memory, or finish with numbers
that mean nothing (a fuzz review's cases).  And no results file holds NaN, which is not JSON."""
import json

import pytest

from wearjoint.cli import main
from wearjoint.results import write_json_atomic

RUN = ["--no-plots", "--quiet"]


@pytest.mark.parametrize("argv, message", [
    (["simulate", "--revolutions", "1e-300"], "--revolutions=1e-300 (revolutions) is invalid: allowed >= 2.5e-05 (one "
                                              "sample interval"),       # ran, and reported zeros
    (["cosim", "--revolutions", "1e-300"], "--revolutions=1e-300 (revolutions) is invalid: allowed >= 2.5e-05"),
    (["cosim", "--master", "container", "--revolutions", "1e-300"],      # named the --step it never wrote
     "--revolutions=1e-300 is invalid: allowed >= 1.25e-05 (one communication step of the package"),
    (["cosim", "--onset-penetration", "1e300"], "--onset-penetration=1e300 (onset_penetration_m) is invalid: allowed "
                                                "<= 1e-05 m (0.1 of the clearance 0.0001 m)"),
    (["simulate", "--integrator", "rk4", "--step", "1e-300"], "--step=1e-300 (step_s) is invalid: allowed >= "
                                                              "min_step_s = 1e-10"),        # never finished
    (["simulate", "--rtol", "1e300"], "--rtol=1e300 (rtol) is invalid: allowed in [1e-12, 0.1]"),
    (["simulate", "--atol-position", "1e300"], "--atol-position=1e300 (atol_position_m) is invalid: allowed <= 0.001 m"),
    (["cosim", "--coupling-tolerance", "1e300"], "--coupling-tolerance=1e300 (coupling_tolerance) is invalid: allowed "
                                                 "in [0, 1]"),
    (["simulate", "--contact-length-m", "1e300"], "--contact-length-m=1e300 (contact_length_m) is invalid: allowed > 0 "
                                                  "(from 1e-06 to 100 m)"),     # wore nothing: depth 0
    (["simulate", "--crank-mass-kg", "1e300"], "--crank-mass-kg=1e300 (crank_mass_kg) is invalid: allowed > 0 (from "
                                               "1e-06 to 1e+06 kg)"),           # the ideal joint's force NaN
    (["simulate", "--crank-speed-rpm", "1e-300"], "--crank-speed-rpm=1e-300 (crank_speed_rpm) is invalid: allowed > 0 "
                                                  "(from 0.001 to 100000 rpm)"),
    (["sweep", "simulate", "--vary", "restitution=0.6,0.9", "--workers", "1000000000"],
     "--workers=1000000000 is invalid: allowed an integer from 1 to "),          # killed for its memory
    (["sweep", "simulate", "--vary", "restitution=0.6,0.9", "--seeds", "1000000000"],
     "--seeds=1000000000 is invalid: allowed an integer from 1 to 10000"),      # silent for minutes
])
def test_a_value_past_any_meaningful_run_is_refused_naming_the_option(tmp_path, capsys, argv, message):
    out = tmp_path / "run"
    assert main([*argv, "--out", str(out), *RUN]) == 2
    err = capsys.readouterr().err
    assert message in err and len([line for line in err.splitlines() if "error:" in line]) == 1, err
    assert not out.exists()


def test_a_number_that_is_not_finite_is_written_as_null(tmp_path):
    """JSON has no NaN or infinity: a statistic that is undefined reads as null in every results file."""
    import numpy as np

    path = tmp_path / "summary.json"
    write_json_atomic(path, {"a_N": float("nan"), "b": np.float64("inf"), "c": [1.5, np.nan], "d": np.arange(2),
                             "e": {"f": -np.inf, "g": np.int64(3)}})

    def refuse(constant):
        raise AssertionError(f"{constant} in {path}")

    assert json.loads(path.read_text(), parse_constant=refuse) == {"a_N": None, "b": None, "c": [1.5, None],
                                                                  "d": [0, 1], "e": {"f": None, "g": 3}}


@pytest.mark.parametrize("argv, message", [
    (["simulate", "--n-points", "1.5"], "--n-points='1.5' is invalid: allowed an integer"),
    (["simulate", "--revolutions", "abc"], "--revolutions='abc' is invalid: allowed a finite real number > 0 ("),
    (["sweep", "simulate", "--seeds", "nan"], "--seeds='nan' is invalid: allowed an integer"),
    # a joint's or a mechanism's parameter: its table's range too (it said "allowed a number" alone)
    (["simulate", "--pin-radius-m", "abc"], "--pin-radius-m='abc' is invalid: allowed a number > 0 (from 1e-06 to "
                                            "100 m) ("),
    (["cosim", "--restitution", "x"], "--restitution='x' is invalid: allowed a number in [0.001, 1] ("),
    (["simulate", "--rod-length-m", "x"], "--rod-length-m='x' is invalid: allowed a number > 0 (from 1e-06 to 100 m) "
                                          "and > crank_length_m (the crank must turn fully) ("),
    (["simulate", "--crank-speed-rpm", "x"], "--crank-speed-rpm='x' is invalid: allowed a number > 0 (from 0.001 to "
                                             "100000 rpm) ("),
    # a run option: the range its class's own check states (it said "allowed a number" alone)
    (["simulate", "--step", "x"], "--step='x' is invalid: allowed a finite real number > 0 ("),
    (["cosim", "--coupling-tolerance", "x"], "--coupling-tolerance='x' is invalid: allowed a finite real number >= 0 ("),
    (["wear-study", "--life-depth-m", "x"], "--life-depth-m='x' is invalid: allowed a finite real number > 0 below the "
                                            "bushing radius 0.0101 m ("),
    (["wear-study", "--checkpoint-every", "x"], "--checkpoint-every='x' is invalid: allowed a finite real number > 0 ("),
    (["wear-study", "--max-step", "x"], "--max-step='x' is invalid: allowed a finite real number > 0 ("),
])
def test_a_value_of_the_wrong_kind_is_named_as_the_other_errors_name_theirs(tmp_path, capsys, argv, message):
    """argparse said "argument --n-points: invalid int value: '1.5'": no "is invalid: allowed" as every other error."""
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--out", str(tmp_path / "run")])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and message in err and err.count("\n") == 1, err


def test_an_empty_initial_profile_is_one_line_without_numpys_warning(tmp_path, capsys):
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    assert main(["simulate", "--initial-profile", str(empty), "--out", str(tmp_path / "run"), *RUN]) == 2
    err = capsys.readouterr().err
    assert "Warning" not in err and err.count("\n") == 1 and f"--initial-profile='{empty}' is invalid" in err, err


@pytest.mark.parametrize("argv, option", [
    (["simulate", "--out", ""], "--out"),            # Path('') is the current folder: the results went there
    (["simulate", "--slider-force-table", "", "--out", "OUT"], "--slider-force-table"),
    (["report", ""], "folder"),
])
def test_an_empty_path_is_refused_not_read_as_the_current_folder(tmp_path, capsys, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path / "run") if a == "OUT" else a for a in argv])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and f"{option}='' is invalid: allowed a path, not an empty one" in err, err
    assert not any(tmp_path.iterdir())
