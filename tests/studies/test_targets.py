"""The sweeps' targets (wearjoint.targets): each takes its command's options, turns them into the library's
configuration and runs it; a case's failure is an exception whose message reaches the sweep's record (never
text scraped from what the case printed)."""
import csv
import dataclasses
import json

import pytest

from wearjoint import targets
from wearjoint.checks import RunDiverged, RunStopped
from wearjoint.cli import build_parser
from wearjoint.parameters import ParameterError
from wearjoint.sweep import worker
from wearjoint.sweep.design import build_cases, command_options
from wearjoint.sweep.runner import SweepFolder

ENSEMBLE = ("seeds", "workers", "scheduler")      # wear-study's own ensemble options: the command's, not the target's


def _actions(parser) -> list:
    return [(a.option_strings, a.dest, a.default, a.type, a.choices, a.nargs, a.const, a.required, type(a), a.help,
             a.metavar) for a in parser._actions if a.dest not in ENSEMBLE]


@pytest.mark.parametrize("name", list(targets.TARGETS))
def test_each_target_takes_its_commands_options(name):
    """Names, types, defaults, choices and help: a sweep's --vary, design file and --param take what the command
    takes."""
    command = next(a for a in build_parser(name)._actions if a.dest == "command").choices[name]
    assert _actions(targets.parser(name)) == _actions(command)


def _case(**options):
    base = command_options("simulate", targets.parser("simulate").parse_args(["--out", "x", "--revolutions", "0.02"]))
    return build_cases("simulate", {**base, **options})[0]


def _record(tmp_path, case, result) -> tuple:
    folder = SweepFolder(tmp_path / "sweep", [case], resume=False)
    row = folder.record(case, result)
    with open(tmp_path / "sweep" / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    return row, table[0], json.loads((folder.case_dir(case) / "case.json").read_text())["row"]


def _simulate_runs(monkeypatch, run) -> None:
    """The simulate target with ``run`` in place of the monolithic run."""
    monkeypatch.setitem(targets.TARGETS, "simulate", dataclasses.replace(targets.TARGETS["simulate"], run=run))


@pytest.fixture
def no_warm_up(monkeypatch):
    monkeypatch.setattr(worker, "warm_up", lambda command, options: 0.0)


def test_a_failed_case_records_its_exceptions_message_not_what_it_printed(tmp_path, monkeypatch, no_warm_up):
    message = "the run diverged at t = 0.0123 s: a test's own words"

    def diverging_run(config, out, plots=True, progress=False):
        print("wearjoint simulate: error: printed text the record must not take")
        raise RunDiverged(message)

    _simulate_runs(monkeypatch, diverging_run)
    case = _case(restitution=0.6)
    result = worker.run_case(case, no_plots=True)
    assert (result["status"], result["error"]) == ("failed", message)
    assert "printed text the record must not take" in result["log"]
    row, csv_row, case_row = _record(tmp_path, case, result)
    assert row["error"] == csv_row["error"] == case_row["error"] == message
    assert csv_row["status"] == case_row["status"] == "failed"


def test_a_bad_value_records_the_parameter_error_and_a_fault_its_type(tmp_path, monkeypatch, no_warm_up):
    result = worker.run_case(_case(restitution=1.5), no_plots=True)
    assert (result["status"], result["error"]) == ("failed", "parameter restitution=1.5 is invalid: allowed in [0.001, 1]")
    assert result["files"] == {}

    def broken_run(config, out, plots=True, progress=False):
        return 1 / 0

    _simulate_runs(monkeypatch, broken_run)
    result = worker.run_case(_case(), no_plots=True)
    assert (result["status"], result["error"]) == ("failed", "ZeroDivisionError: division by zero")
    assert "Traceback" in result["log"]


def test_a_target_raises_its_failure_after_writing_what_the_run_keeps(tmp_path):
    """A real diverged run (RK4 at a far too long step, without wear: with wear the step is refused up front):
    RunStopped with the record's failure, the results before it written, the report states the command line."""
    options = dict(_case(integrator="rk4", step=2e-4, revolutions=0.05, no_wear=True).options)
    with pytest.raises(RunStopped, match="the run diverged at t = ") as failure:
        targets.run("simulate", options, tmp_path, plots=False, command_line="wearjoint simulate --step=0.0002")
    record = targets.read_record(tmp_path)
    assert record["completed"] is False and record["failure"] == str(failure.value)
    assert record["command_line"] == "wearjoint simulate --step=0.0002" and (tmp_path / "report.html").is_file()


def test_unknown_target_and_bad_options_are_parameter_errors():
    with pytest.raises(ParameterError, match="sweep command 'validate' is invalid: allowed one of simulate, cosim, "
                                             "wear-study"):
        targets.target("validate")
    options = dict(_case().options)
    with pytest.raises(ParameterError, match=r"--revolutions takes one integer"):
        targets.target("wear-study").config({**command_options("wear-study", targets.parser("wear-study").parse_args(
            ["--out", "x"])), "revolutions": "10,20"})
    assert targets.target("simulate").config(options).options.revolutions == 0.02


def test_an_interrupted_wear_study_case_resumes_from_its_kept_folder(tmp_path, no_warm_up, monkeypatch):
    """A wear-study case runs (on this machine's workers) in the sweep's cases/CASE_ID/running: Ctrl-C after two of
    its three simulated revolutions keeps the folder and its checkpoint; the case run again resumes there and ends
    with the files of a run never stopped, then leaves no running folder."""
    from wearjoint.studies.wear_study import CHECKPOINT_NAME, run_wear_study
    from wearjoint.sweep.runner import kept_folder

    base = command_options("wear-study", targets.parser("wear-study").parse_args(
        ["--out", "x", "--revolutions", "30", "--snapshots", "10,20,30", "--wear-factor", "10"]))
    case = build_cases("wear-study", base)[0]
    sweep = SweepFolder(tmp_path / "sweep", [case], resume=False)
    running = kept_folder(sweep, case, None)
    assert running == str(sweep.case_dir(case) / "running") and kept_folder(sweep, case, "tcp://host:8786") is None
    assert kept_folder(sweep, _case(), None) is None               # a simulate case: a worker's temporary folder

    def interrupted(config, out, plots=True, progress=False):
        run_wear_study(config, out, progress=False, plots=plots, stop_after_checkpoints=2)
        raise KeyboardInterrupt

    study = targets.TARGETS["wear-study"]
    monkeypatch.setitem(targets.TARGETS, "wear-study", dataclasses.replace(study, run=interrupted))
    assert worker.run_case(case, no_plots=True, kept_folder=running)["status"] == "interrupted"
    assert (sweep.case_dir(case) / "running" / CHECKPOINT_NAME).is_file()
    monkeypatch.setitem(targets.TARGETS, "wear-study", study)
    resumed = worker.run_case(case, no_plots=True, kept_folder=running)
    whole = worker.run_case(case, no_plots=True)
    assert resumed["status"] == whole["status"] == "ok"
    for name in ("profile_rev10.csv", "profile_rev20.csv", "profile.csv", "wear_growth.csv"):
        assert resumed["files"][name] == whole["files"][name], name
    assert not (sweep.case_dir(case) / "running").exists()
