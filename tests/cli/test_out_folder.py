"""The results folder (``--out``) is checked before a command runs: a file, a folder that cannot be made or one
holding another command's results is refused in one line (exit 2) with nothing written; a command writes over its
own earlier results without leaving that run's figures behind; argparse's errors are one line too."""
import json

import pytest

from wearjoint.cli import main
from wearjoint.cli.out_folder import prepare_out_folder, results_commands


def _one_line_error(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


def test_out_that_is_a_file_is_refused_before_the_run(tmp_path, capsys):
    target = tmp_path / "summary.json"
    target.write_text("{}")
    assert main(["simulate", "--revolutions", "0.01", "--no-plots", "--quiet", "--out", str(target)]) == 2
    err = _one_line_error(capsys)
    assert f"--out='{target}'" in err and "it is a file" in err
    assert target.read_text() == "{}"


def test_out_that_cannot_be_made_is_refused(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["cosim", "--revolutions", "0.01", "--no-plots", "--quiet", "--out", str(blocker / "a" / "b")]) == 2
    err = _one_line_error(capsys)
    assert "--out=" in err and "a folder that can be made" in err and str(blocker) in err
    assert main(["contact-law", "--out", "/proc/wearjoint_no_such/x"]) == 2
    assert "a folder that can be made" in _one_line_error(capsys)


def test_another_commands_results_are_not_overwritten(tmp_path, capsys):
    study = tmp_path / "study"
    study.mkdir()
    summary = {"command_line": f"wearjoint wear-study --revolutions 20 --out {study}"}
    (study / "summary.json").write_text(json.dumps(summary))
    assert main(["simulate", "--revolutions", "0.01", "--no-plots", "--quiet", "--out", str(study)]) == 2
    err = _one_line_error(capsys)
    assert "holds the results of `wearjoint wear-study`" in err and "--out=" in err
    assert sorted(p.name for p in study.iterdir()) == ["summary.json"]
    assert json.loads((study / "summary.json").read_text()) == summary


@pytest.mark.parametrize("marker, command", [("cosim_study.json", "cosim-study"), ("sweep.json", "sweep"),
                                             ("wear_study_checkpoint.pkl", "wear-study"),
                                             ("samples.csv", "sensitivity"), ("calibration.json", "calibrate")])
def test_results_without_a_command_line_are_known_by_their_files(tmp_path, marker, command):
    (tmp_path / marker).write_text("{}")
    assert results_commands(tmp_path) == (command,)
    with pytest.raises(ValueError, match=f"holds the results of `wearjoint {command}`"):
        prepare_out_folder("simulate" if command != "simulate" else "cosim", tmp_path)


def test_calibrate_writes_into_the_study_it_fits_and_a_command_into_its_own_results(tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps({"command_line": "wearjoint wear-study --out x"}))
    assert prepare_out_folder("calibrate", tmp_path) == []
    assert prepare_out_folder("wear-study", tmp_path) == []
    assert results_commands(tmp_path / "nothing") == ()


def test_an_interrupted_wear_study_ensemble_resumes_into_its_folder(tmp_path):
    """A ``wear-study --seeds`` ensemble stopped before its summary has the sweep.json of the wear-study it sweeps."""
    (tmp_path / "sweep.json").write_text(json.dumps({"command": "wear-study", "cases": []}))
    assert results_commands(tmp_path) == ("sweep", "wear-study")
    assert prepare_out_folder("wear-study", tmp_path) == prepare_out_folder("sweep", tmp_path) == []
    with pytest.raises(ValueError, match="holds the results of `wearjoint sweep`"):
        prepare_out_folder("simulate", tmp_path)


def test_a_refused_run_leaves_no_folder_behind(tmp_path, capsys):
    out = tmp_path / "a" / "b"
    assert main(["simulate", "--revolutions", "0", "--out", str(out)]) == 2
    assert "--revolutions=0" in _one_line_error(capsys)
    assert not (tmp_path / "a").exists()


def test_a_run_without_figures_removes_the_earlier_runs_figures(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["simulate", "--revolutions", "0.02", "--quiet", "--out", str(out)]) == 0
    figures = json.loads((out / "summary.json").read_text())["figures"]
    assert len(figures) == 4 and all((out / name).exists() for name in figures)
    (out / "mine.png").write_bytes(b"not the run's")
    assert main(["simulate", "--revolutions", "0.02", "--quiet", "--no-plots", "--out", str(out)]) == 0
    assert not any((out / name).exists() for name in figures) and (out / "mine.png").exists()
    assert "slider_acceleration.png" not in (out / "report.html").read_text()
    capsys.readouterr()


@pytest.mark.parametrize("study", ["sweep", "sensitivity"])
def test_a_study_whose_out_is_a_file_or_another_commands_results_is_refused(tmp_path, capsys, study):
    """sweep's and sensitivity's --out is their target's option, parsed by the study: checked all the same."""
    design = ["--vary", "restitution=0.6"] if study == "sweep" else ["--param", "restitution=0.5,0.9"]
    target = tmp_path / "afile"
    target.write_text("x")
    assert main([study, "simulate", "--revolutions", "0.01", *design, "--out", str(target)]) == 2
    err = _one_line_error(capsys)
    assert f"--out='{target}' is invalid" in err and "it is a file" in err
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "summary.json").write_text(json.dumps({"command_line": "wearjoint simulate --out run"}))
    assert main([study, "simulate", "--revolutions", "0.01", *design, "--out", str(tmp_path / "run")]) == 2
    assert "holds the results of `wearjoint simulate`" in _one_line_error(capsys)
    assert sorted(p.name for p in (tmp_path / "run").iterdir()) == ["summary.json"]


def test_ctrl_c_in_any_command_is_one_line_and_exit_130(tmp_path, monkeypatch, capsys):
    """A command that does not say itself where its finished work is (export-ssp, a third-party master) stops on
    Ctrl-C with one line, no traceback."""
    import wearjoint.cli.contact_law as command

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(command, "run", interrupted)
    assert main(["contact-law", "--out", str(tmp_path / "law")]) == 130
    assert _one_line_error(capsys) == "wearjoint contact-law: interrupted"
    assert not (tmp_path / "law").exists()          # the folder it made, empty, goes


@pytest.mark.parametrize("argv, words", [(["cosim", "--gravity-m-s2=1,2,3", "--out", "x"], "--gravity-m-s2"),
                                         (["calibrate", "--law", "linear"], "invalid choice: 'linear'"),
                                         (["sweep", "simulate", "--seeds", "1.5", "--out", "x"], "--seeds"),
                                         (["sensitivity", "simulate", "--method", "foo", "--out", "x"], "'foo'"),
                                         (["no-such-command"], "invalid choice")])
def test_an_option_argparse_refuses_is_one_line(argv, words, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = _one_line_error(capsys)
    assert words in err and "--help` lists the options" in err


@pytest.mark.parametrize("command", ["wear-study", "sweep"])
def test_a_sweep_of_the_wear_study_gets_its_command_line_and_calibrate_leaves_the_study_s(tmp_path, command):
    """The report records the command line where the folder is the command's (a ``wear-study --seeds`` ensemble's
    and a ``sweep wear-study``'s sweep.json name the wear-study both sweep), not calibrate's into a study."""
    import argparse

    from wearjoint.cli import _report

    (tmp_path / "sweep_summary.json").write_text("{}")
    (tmp_path / "sweep.json").write_text(json.dumps({"command": "wear-study", "cases": []}))
    _report(argparse.Namespace(command=command, out=str(tmp_path)), [command, "--out", str(tmp_path)])
    assert json.loads((tmp_path / "sweep_summary.json").read_text())["command_line"].startswith(f"wearjoint {command}")
    study = tmp_path / "study"
    study.mkdir()
    (study / "summary.json").write_text(json.dumps({"command_line": "wearjoint wear-study --out study"}))
    _report(argparse.Namespace(command="calibrate", out=str(study)), ["calibrate", "--out", str(study)])
    assert json.loads((study / "summary.json").read_text())["command_line"] == "wearjoint wear-study --out study"
