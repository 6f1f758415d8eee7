"""`wearjoint wear-study --out DIR --resume`: a study stopped part-way continues with the settings of its checkpoint
where the command line leaves them out (a mechanism, its load and the study's horizon need not be repeated), to the
same answer as the study that ran through; an option written anew still counts (a numerical setting is taken, a
physical one that differs refused naming it)."""
import json

import pytest

from wearjoint.cli import build_parser, main
from wearjoint.studies.wear_study import run_wear_study
from wearjoint.targets import wear_study_config

# a machine of its own: a loaded slider at another speed, the clearance at the rod-slider joint, its own k_w
STUDY = ["--revolutions", "12", "--snapshots", "6,12", "--crank-speed-rpm", "200", "--slider-force-N", "40",
         "--clearance-joint", "rod-slider", "--wear-coefficient-m2-N", "2e-12", "--life-depth-m", "4e-7"]
ANSWER = ("max_wear_depth_m", "worn_volume_m3", "simulated_revolutions", "max_contact_force_N", "life")


def _stopped(out, stop_after_checkpoints: int = 2) -> None:
    """The study of STUDY stopped after that many checkpoints, as a kill would leave it."""
    config = wear_study_config(vars(build_parser("wear-study").parse_args(["wear-study", *STUDY, "--out", str(out)])))
    assert run_wear_study(config, out, progress=False, plots=False,
                          stop_after_checkpoints=stop_after_checkpoints)["finished"] is False


@pytest.fixture(scope="module")
def through(tmp_path_factory):
    """summary.json of the study that ran through."""
    out = tmp_path_factory.mktemp("through")
    assert main(["wear-study", *STUDY, "--out", str(out), "--no-plots", "--quiet"]) == 0
    return json.loads((out / "summary.json").read_text())


def test_resume_alone_continues_the_checkpointed_study_to_the_same_answer(through, tmp_path):
    _stopped(tmp_path)
    assert main(["wear-study", "--out", str(tmp_path), "--resume", "--no-plots", "--quiet"]) == 0
    resumed = json.loads((tmp_path / "summary.json").read_text())
    assert {k: resumed[k] for k in ANSWER} == {k: through[k] for k in ANSWER}
    assert resumed["parameters"]["mechanism"]["slider_force_N"] == 40.0
    assert resumed["parameters"]["mechanism"]["clearance_joint"] == "rod-slider"
    assert [s["revolution"] for s in resumed["snapshots"]] == [6, 12]


def test_resume_takes_a_written_numerical_setting(tmp_path):
    _stopped(tmp_path)
    assert main(["wear-study", "--out", str(tmp_path), "--resume", "--cycle-jump-tolerance", "0.01", "--no-plots",
                 "--quiet"]) == 0
    segments = json.loads((tmp_path / "summary.json").read_text())["numerical_settings"]
    assert [s["jump_tolerance"] for s in segments] == [0.003, 0.01]


def test_resume_refuses_a_written_physical_setting_that_differs(tmp_path, capsys):
    _stopped(tmp_path, 1)
    assert main(["wear-study", "--out", str(tmp_path), "--resume", "--slider-force-N", "60", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "parameter --slider-force-N (mechanism.slider_force_N) is 40.0 in its checkpoint, 60.0 given" in err
    assert main(["wear-study", "--out", str(tmp_path), "--resume", "--slider-force-N", "40", "--no-plots",
                 "--quiet"]) == 0       # the same value written again
