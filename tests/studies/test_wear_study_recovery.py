"""`wearjoint wear-study`: a study that diverges keeps what it finished and says where to continue from; a
resume may change the numerical settings, not the physical ones; --convergence runs what was asked; the
default route completes on a mechanism that is not the paper's (slow)."""
import json
import shutil
import subprocess
import sys

import numpy as np
import pytest

from wearjoint.cli import build_parser
from wearjoint.cli import main as cli_main
from wearjoint.cli.study_options import config_from_args
from wearjoint.core import layout as L
from wearjoint.parameters import ParameterError, SliderCrankParameters, paper_joint
from wearjoint.studies import wear_study
from wearjoint.studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
from wearjoint.studies.wear_convergence import run_convergence
from wearjoint.studies.wear_study import CHECKPOINT_NAME, StudyDiverged, WearStudyConfig, run_wear_study


def small_config(**changes) -> WearStudyConfig:
    """10 revolutions at wear factor 10: one simulated revolution, a checkpoint every eighth of it."""
    values = dict(joint=paper_joint(wear_factor=10.0), mechanism=SliderCrankParameters(), revolutions=10,
                  snapshots=(5, 10), checkpoint_every_revolutions=0.125, jump_tolerance=None)
    values.update(changes)
    return WearStudyConfig(**values)


class DivergingEngine:
    """The study's engine, whose samples put the pin 1 m off the bushing centre once its time passes
    ``after_s`` while it integrates with ``integrator``: the study sees a divergence through its own check
    (:func:`wearjoint.runner.divergence`), as it would see a real one."""

    def __init__(self, engine, after_s: float, integrator: str = "rk4"):
        self._engine, self._after_s, self._integrator = engine, after_s, integrator

    def __getattr__(self, name):
        return getattr(self._engine, name)

    def advance_to(self, t_end, samples):
        n = self._engine.advance_to(t_end, samples)
        if self._engine.options.integrator == self._integrator and self._engine.t > self._after_s:
            samples[:n, L.T_ECC_X] = 1.0
        return n


def diverge_after(monkeypatch, simulated_revolutions: float, when=lambda config: True) -> None:
    """Studies whose config satisfies ``when`` diverge (with RK4) once past that many simulated revolutions."""
    make = wear_study.make_engine

    def make_engine(config):
        engine = make(config)
        return DivergingEngine(engine, simulated_revolutions * config.mechanism.period_s) if when(config) else engine
    monkeypatch.setattr(wear_study, "make_engine", make_engine)


def test_diverged_study_keeps_its_snapshots_and_resumes_with_dopri(tmp_path, monkeypatch):
    """Diverges after 0.7 simulated revolutions (revolution 7): snapshot 5 and a summary are written, the
    message names where and what next; resumed from the checkpoint at revolution 6.25 with DOPRI it ends."""
    diverge_after(monkeypatch, 0.7)
    config = small_config()
    with pytest.raises(StudyDiverged) as caught:
        run_wear_study(config, tmp_path, progress=False, plots=False)
    message = str(caught.value)
    assert "\n" not in message
    assert "diverged at revolution 7.5 of 10 (simulated time 0.3 s, rk4 at max step 1e-05 s): the run diverged " \
           "at t = " in message and "into the bushing wall" in message
    assert f"the last good checkpoint is at revolution 6.25 ({tmp_path / CHECKPOINT_NAME})" in message
    assert "--resume and --integrator dopri or --max-step 5e-06" in message
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "diverged" and summary["finished"] is False and summary["completed"] is False
    assert summary["failure"] == message
    assert summary["reached_revolution"] == pytest.approx(7.5)
    assert summary["last_good_checkpoint_revolution"] == pytest.approx(6.25)
    assert summary["revolutions"] == pytest.approx(6.25)          # the final-state keys: at the last good checkpoint
    assert [s["revolution"] for s in summary["snapshots"]] == [5]
    assert (tmp_path / "profile_rev5.csv").is_file() and not (tmp_path / "profile_rev10.csv").exists()
    rev5 = np.loadtxt(tmp_path / "profile_rev5.csv", delimiter=",", skiprows=1)[:, 1]
    assert rev5.max() == pytest.approx(summary["snapshots"][0]["max_wear_depth_m"]) and rev5.max() > 0
    assert json.loads((tmp_path / "snapshots.json").read_text())["status"] == "diverged"
    growth = np.loadtxt(tmp_path / "wear_growth.csv", delimiter=",", skiprows=1)
    assert growth[-1, 0] == pytest.approx(6.25) and np.all(np.isfinite(growth))   # the stops that passed the check

    with pytest.raises(StudyDiverged):        # the same settings diverge again: RK4 resumes bit for bit
        run_wear_study(config, tmp_path, resume=True, progress=False, plots=False)
    done = run_wear_study(config.replace(integrator="dopri"), tmp_path, resume=True, progress=False, plots=False)
    assert done["status"] == "finished" and done["finished"] is True
    assert [s["revolution"] for s in done["snapshots"]] == [5, 10]
    assert done["snapshots"][1]["max_wear_depth_m"] > done["snapshots"][0]["max_wear_depth_m"] > 0
    assert np.isfinite(done["max_wear_depth_m"])
    settings = [(s["integrator"], s["from_revolution"], s["to_revolution"]) for s in done["numerical_settings"]]
    assert settings == [("rk4", 0.0, 6.25), ("dopri", 6.25, 10.0)]
    assert np.loadtxt(tmp_path / "profile_rev5.csv", delimiter=",", skiprows=1)[:, 1].tolist() == rev5.tolist()


def test_diverged_cycle_jumping_study_names_the_block_that_diverged(tmp_path, monkeypatch):
    """Cycle jumping: blocks of 2 simulated revolutions (0-2, a jump to 3, 3-5: snapshot 5 is simulated
    revolution 4), checkpointed after each block and its jump; diverging in simulated revolution 5, the
    first of the block after the jump that follows snapshot 5, it stops one revolution past that checkpoint."""
    diverge_after(monkeypatch, 4.5)
    config = small_config(joint=paper_joint(wear_factor=1.0), jump_tolerance=DEFAULT_JUMP_TOLERANCE)
    with pytest.raises(StudyDiverged, match=r"diverged at revolution \d+ of 10 .*the last good checkpoint is at "
                                            r"revolution \d+ .*--resume and --integrator dopri"):
        run_wear_study(config, tmp_path, progress=False, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "diverged" and [s["revolution"] for s in summary["snapshots"]] == [5]
    assert summary["reached_revolution"] == summary["last_good_checkpoint_revolution"] + 1 > 5
    assert summary["cycle_jumping"]["simulated_revolutions"] == 5
    assert (tmp_path / "profile_rev5.csv").is_file() and not (tmp_path / "profile_rev10.csv").exists()


def test_diverged_study_from_the_command_line(tmp_path, monkeypatch, capsys):
    diverge_after(monkeypatch, 0.3)
    assert cli_main(["wear-study", "--out", str(tmp_path), "--quiet", "--no-plots", "--revolutions", "10",
                     "--snapshots", "2,10", "--wear-factor", "10", "--checkpoint-every", "0.125"]) == 1
    err = capsys.readouterr().err.splitlines()[-1]       # (a cold numba cache says so in a line before)
    assert err.startswith("wearjoint wear-study: error: the wear study diverged at revolution 3.75 of 10 ")
    assert "last good checkpoint is at revolution 2.5" in err and "--resume and --integrator dopri" in err
    assert (tmp_path / "profile_rev2.csv").is_file()


def test_a_bushing_worn_through_stops_the_study_before_its_checkpoint(tmp_path, monkeypatch):
    """A profile deeper than the bushing's radius is neither continued nor checkpointed (it could not be
    restored): the study stops with what it had, and says that a resume cannot help."""
    make = wear_study.make_engine

    class WornThrough(DivergingEngine):
        def wear_profile(self):
            phi, depth, volume = self._engine.wear_profile()
            return phi, depth * (1e6 if self._engine.t > self._after_s else 1.0), volume

    monkeypatch.setattr(wear_study, "make_engine", lambda config: WornThrough(make(config), 0.6 * 0.4, "none"))
    with pytest.raises(StudyDiverged, match=r"stopped at revolution 6.25 of 10 .*: the bushing wore through by "
                                            r"revolution 6.25: .*at revolution 5 .* a resume cannot help: lower "
                                            r"--wear-coefficient-m2-N, --wear-factor or --revolutions$"):
        run_wear_study(small_config(), tmp_path, progress=False, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "worn through" and summary["last_good_checkpoint_revolution"] == 5.0
    with pytest.raises(StudyDiverged, match="stopped at revolution 6.25"):     # its checkpoint restores
        run_wear_study(small_config(), tmp_path, resume=True, progress=False, plots=False)


def test_divergence_before_any_checkpoint_says_so(tmp_path, monkeypatch):
    diverge_after(monkeypatch, 0.05)
    with pytest.raises(StudyDiverged, match="no checkpoint was reached; .* run it again with --integrator dopri"):
        run_wear_study(small_config(), tmp_path, progress=False, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "diverged" and summary["snapshots"] == [] and summary["growth"] is None


def test_resume_with_dopri_and_a_smaller_step_after_an_rk4_checkpoint(tmp_path):
    config = small_config()
    run_wear_study(config, tmp_path, progress=False, plots=False, stop_after_checkpoints=6)
    done = run_wear_study(config.replace(integrator="dopri", max_step_s=5e-6, rtol=1e-5), tmp_path, resume=True,
                          progress=False, plots=False)
    assert done["finished"] and done["max_wear_depth_m"] > done["snapshots"][0]["max_wear_depth_m"] > 0
    assert [(s["integrator"], s["max_step_s"], s["rtol"], s["from_revolution"], s["to_revolution"])
            for s in done["numerical_settings"]] == [("rk4", 1e-5, 1e-6, 0.0, 7.5), ("dopri", 5e-6, 1e-5, 7.5, 10.0)]
    assert done["parameters"]["study"]["integrator"] == "dopri"
    index = json.loads((tmp_path / "snapshots.json").read_text())
    assert index["status"] == "finished" and index["numerical_settings"] == done["numerical_settings"]


@pytest.fixture(scope="module")
def checkpointed(tmp_path_factory):
    """A study killed after its first checkpoint (an eighth of a simulated revolution)."""
    out = tmp_path_factory.mktemp("checkpointed")
    run_wear_study(small_config(), out, progress=False, plots=False, stop_after_checkpoints=1)
    return out


@pytest.mark.parametrize("change,message", [
    (dict(mechanism=SliderCrankParameters(crank_speed_rpm=160.0)),
     "parameter --crank-speed-rpm (mechanism.crank_speed_rpm) is 150.0 in its checkpoint, 160.0 given"),
    (dict(joint=paper_joint(wear_factor=10.0, wear_coefficient_m2_N=1e-10)),
     "parameter --wear-coefficient-m2-N (joint.wear_coefficient_m2_N) is 5.05e-10 in its checkpoint, 1e-10 given"),
    (dict(revolutions=20, snapshots=(5, 20)), "parameter --revolutions (revolutions) is 10 in its checkpoint, 20 given "
                                              "(also changed: --snapshots (snapshots))"),
    (dict(joint=paper_joint(wear_factor=1.0), jump_tolerance=0.003),
     "parameter --wear-factor (joint.wear_factor) is 10.0 in its checkpoint, 1.0 given (also changed: "
     "--cycle-jump-tolerance (jump_tolerance) (None: the wear-factor route))"),
])
def test_resume_refuses_a_changed_physical_setting(checkpointed, tmp_path, change, message):
    shutil.copytree(checkpointed, tmp_path, dirs_exist_ok=True)
    with pytest.raises(ParameterError) as caught:
        run_wear_study(small_config(**change), tmp_path, resume=True, progress=False, plots=False)
    assert message in str(caught.value) and "\n" not in str(caught.value)
    assert "may change only its numerical settings (--integrator, --max-step" in str(caught.value)


def test_resume_refusal_from_the_command_line(tmp_path, capsys):
    options = ["wear-study", "--out", str(tmp_path), "--quiet", "--no-plots", "--revolutions", "10",
               "--snapshots", "5,10", "--wear-factor", "10", "--checkpoint-every", "0.125"]
    config = config_from_args(build_parser("wear-study").parse_args(options))
    run_wear_study(config, tmp_path, progress=False, plots=False, stop_after_checkpoints=1)
    capsys.readouterr()
    assert cli_main([*options, "--resume", "--crank-length-m", "0.06"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "parameter --crank-length-m (mechanism.crank_length_m) is 0.05 in its checkpoint, 0.06 given" in err
    # --snapshots left out follows --revolutions (its quarters): the refusal names --revolutions only
    longer = [o for o in options if o not in ("--snapshots", "5,10")]
    longer[longer.index("--revolutions") + 1] = "20"
    assert cli_main([*longer, "--resume"]) == 2
    err = capsys.readouterr().err
    assert "parameter --revolutions (revolutions) is 10 in its checkpoint, 20 given;" in err and "also" not in err
    # left out with the same --revolutions, the checkpoint's own snapshots: the study continues
    assert cli_main([*[o for o in options if o not in ("--snapshots", "5,10")], "--resume"]) == 0


def test_convergence_runs_the_listed_factors_and_keeps_those_that_finish(tmp_path, monkeypatch):
    """Factors 5 and 10 (2 and 1 simulated revolutions); 10 diverges after 0.7: no run but those two, F=5's
    rows written, F=10's reached snapshot marked."""
    diverge_after(monkeypatch, 0.7, when=lambda config: config.joint.wear_factor == 10.0)
    calls = []
    run = wear_study.run_wear_study

    def counted(config, *args, **kwargs):
        calls.append((config.joint.wear_factor, config.integrator))
        return run(config, *args, **kwargs)
    monkeypatch.setattr("wearjoint.studies.wear_convergence.run_wear_study", counted)
    result = run_convergence(small_config(checkpoint_every_revolutions=1.0), [5.0, 10.0], tmp_path, progress=False)
    assert calls == [(5.0, "rk4"), (10.0, "rk4")]
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == ["F10", "F5"]
    assert result["runs"] == {"F=5": "finished", "F=10": "diverged"}
    assert "diverged at revolution" in result["diverged"]["F=10"]
    assert result["within_tolerance"] == {"F=5": True, "F=10": None}
    rows = [(r["run"], r["status"], r["revolution"]) for r in result["rows"]]
    assert rows == [("F=5", "finished", 5), ("F=5", "finished", 10), ("F=10", "diverged", 5)]
    assert (tmp_path / "convergence.csv").read_text().count("\n") == 4
    assert json.loads((tmp_path / "convergence.json").read_text())["runs"]["F=10"] == "diverged"


def test_convergence_against_the_jump_route_runs_it_at_the_real_wear_rate():
    """``jump`` in the list is the default route: wear factor 1 with cycle jumping (the config's tolerance, or
    the default one); the factors run without it; a repeated entry is refused in one line."""
    from wearjoint.studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
    from wearjoint.studies.wear_convergence import convergence_runs

    runs = convergence_runs(small_config(revolutions=100, snapshots=(100,)), ["jump", 10.0])
    assert list(runs) == ["jump", "F=10"]
    assert (runs["jump"].joint.wear_factor, runs["jump"].jump_tolerance) == (1.0, DEFAULT_JUMP_TOLERANCE)
    assert (runs["F=10"].joint.wear_factor, runs["F=10"].jump_tolerance) == (10.0, None)
    tighter = convergence_runs(small_config(revolutions=100, snapshots=(100,), jump_tolerance=0.001,
                                            joint=paper_joint(wear_factor=1.0)), ["jump"])
    assert tighter["jump"].jump_tolerance == 0.001
    with pytest.raises(ParameterError, match="jump,10,jump repeats one"):
        convergence_runs(small_config(revolutions=100, snapshots=(100,)), ["jump", 10.0, "jump"])


def test_wear_factor_leaving_less_than_one_simulated_revolution_is_refused():
    with pytest.raises(ParameterError) as caught:
        small_config(revolutions=1000, snapshots=(1000,), joint=paper_joint(wear_factor=1e6))
    assert str(caught.value) == ("--wear-factor=1000000.0 (wear_factor) is invalid with --revolutions 1000: "
                                 "allowed 0.001 <= wear factor <= 1000 (0.001 simulated revolutions; from 1 to 1e6)")
    assert small_config(revolutions=20, snapshots=(20,), joint=paper_joint(wear_factor=20.0)).simulated_revolutions == 1


# a slider-crank that is not the paper's: longer crank and rod, twice the speed, a larger pin with 0.15 mm
# clearance, a bronze bushing and its own wear coefficient (the printed 5.05e-10 wears it through)
OWN_MECHANISM = ("--crank-length-m", "0.08", "--rod-length-m", "0.3", "--crank-speed-rpm", "300",
                 "--pin-radius-m", "0.012", "--bushing-radius-m", "0.01215", "--contact-length-m", "0.01",
                 "--bushing-youngs-modulus-Pa", "1.1e11", "--bushing-poisson-ratio", "0.34",
                 "--wear-coefficient-m2-N", "5e-13")


@pytest.mark.slow
def test_default_route_completes_50000_revolutions_on_another_mechanism(tmp_path):
    """The default wear-study route (cycle jumping, RK4 at the wear-step limit) to 50 000 revolutions."""
    done = subprocess.run([sys.executable, "-m", "wearjoint.cli", "wear-study", *OWN_MECHANISM, "--revolutions",
                           "50000", "--snapshots", "10000,20000,30000,40000,50000", "--out", str(tmp_path),
                           "--quiet", "--no-plots"], capture_output=True, text=True, timeout=3 * 3600)
    assert done.returncode == 0, done.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"] == "finished" and summary["revolutions"] == 50000
    assert summary["parameters"]["mechanism"]["crank_speed_rpm"] == 300.0
    depths = [s["max_wear_depth_m"] for s in summary["snapshots"]]
    assert [s["revolution"] for s in summary["snapshots"]] == [10000, 20000, 30000, 40000, 50000]
    assert np.all(np.isfinite(depths)) and np.all(np.diff(depths) > 0) and depths[0] > 0
    growth = np.loadtxt(tmp_path / "wear_growth.csv", delimiter=",", skiprows=1)
    assert np.all(np.isfinite(growth)) and np.all(np.diff(growth[:, 1]) >= 0) and growth[-1, 0] == 50000


@pytest.mark.parametrize("arguments, message", [
    (dict(target_max_depth_m="1e-3"), r"^parameter target_max_depth_m='1e-3' is invalid: allowed a finite depth > 0 m$"),
    (dict(target_max_depth_m=0.0), r"^parameter target_max_depth_m=0.0 is invalid: allowed a finite depth > 0 m$"),
    (dict(target_max_depth_m=1e-3, rel_tolerance=0.0), r"^parameter rel_tolerance=0.0 is invalid: allowed in \(0, 1\)$"),
    (dict(target_max_depth_m=1e-3, max_trials=0), r"^parameter max_trials=0 is invalid: allowed an integer >= 1$"),
    (dict(target_max_depth_m=1e-3, max_trials=2.0), r"^parameter max_trials=2.0 is invalid: allowed an integer >= 1$"),
])
def test_the_calibration_refuses_bad_arguments_before_it_runs_or_writes(tmp_path, arguments, message):
    """The library function names its own parameters (the command line names --calibrate-max-depth-m: its test in
    tests/cli/test_cli_input_errors.py); max_trials=0 died in min() of no trials after running nothing."""
    from wearjoint.studies.wear_calibration import calibrate_wear_coefficient

    with pytest.raises(ParameterError, match=message):
        calibrate_wear_coefficient(small_config(), out_dir=tmp_path / "c", progress=False, **arguments)
    assert not (tmp_path / "c").exists()


def test_a_resume_on_another_mechanism_names_its_option_not_the_joint_fields_that_follow_it(tmp_path):
    """The joint's offsets and effective mass follow the mechanism where they are left to it: a resume with another
    clearance joint names --clearance-joint alone (it also listed --pin-offset-m, --bushing-offset-m and
    --effective-mass-kg, which the user never gave); a given offset that differs is still named."""
    from wearjoint.parameters import SliderCrankParameters, paper_joint
    from wearjoint.studies.wear_study_recovery import settings_changes

    def settings(mechanism, **joint):
        return {"mechanism": mechanism.to_dict(), "joint": paper_joint(mechanism, **joint).to_dict()}

    paper, rod_slider = SliderCrankParameters(), SliderCrankParameters(clearance_joint="rod-slider")
    with pytest.raises(ParameterError) as caught:
        settings_changes(settings(rod_slider), settings(paper), tmp_path / "wear_study_checkpoint.pkl")
    assert "parameter --clearance-joint (mechanism.clearance_joint) is 'rod-slider' in its checkpoint" in \
        str(caught.value) and "also changed" not in str(caught.value)
    with pytest.raises(ParameterError, match=r"also changed: --effective-mass-kg"):
        settings_changes(settings(rod_slider), settings(paper, effective_mass_kg=0.5), tmp_path / "x.pkl")


def test_a_resume_with_the_load_table_read_from_another_path_is_the_same_study(tmp_path):
    """The checkpoint records the load table's rows and the file they came from: the same rows from another path
    (a relative one, a copy) continue the study; other rows are refused, naming --slider-force-table."""
    from wearjoint.mechanism_parameters import SliderForceTable
    from wearjoint.studies.wear_study_recovery import settings_changes

    def settings(csv, rows="crank_angle_deg,force_N\n0,100\n180,900\n360,100\n"):
        (tmp_path / csv).write_text(rows)
        mechanism = SliderCrankParameters(slider_force_table=SliderForceTable.from_csv(tmp_path / csv))
        return {"mechanism": mechanism.to_dict(), "joint": paper_joint(mechanism).to_dict()}

    assert settings_changes(settings("a.csv"), settings("b.csv"), tmp_path / "x.pkl") == []
    with pytest.raises(ParameterError, match=r"parameter --slider-force-table"):
        settings_changes(settings("a.csv"), settings("c.csv", "crank_angle_deg,force_N\n0,1\n360,1\n"),
                         tmp_path / "x.pkl")


def test_a_resumed_study_keeps_the_command_that_started_it(tmp_path):
    """summary.json's and report.html's command line was the resuming one (``--out X --resume``), the study's
    options gone: it is the starting one, kept in the checkpoint, and ``resumed_by`` lists the others."""
    out = tmp_path / "study"
    started = ["wear-study", "--revolutions", "2", "--snapshots", "1,2", "--no-plots", "--quiet", "--out", str(out)]
    assert cli_main(started) == 0
    assert cli_main(["wear-study", "--out", str(out), "--resume", "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["command_line"] == "wearjoint " + " ".join(started)
    assert summary["resumed_by"] == [f"wearjoint wear-study --out {out} --resume --quiet"]
    assert "--snapshots 1,2" in (out / "report.html").read_text()
