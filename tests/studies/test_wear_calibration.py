"""`wearjoint wear-study --calibrate-max-depth-m`: the k_w whose study ends at a target depth, each trial a study
of its own folder (wearjoint.studies.wear_calibration)."""
import json
import re

from wearjoint.cli import main


def test_the_calibration_reaches_its_target_and_each_trial_folder_names_the_command_and_its_k_w(tmp_path, capsys):
    """The depth grows with k_w across the trials and the chosen one ends within the tolerance of the target.  A
    trial's summary.json and report.html name the command that made them with the trial's k_w: the report had said
    "Made through the API"."""
    out = tmp_path / "cal"
    argv = ["wear-study", "--revolutions", "3", "--calibrate-max-depth-m", "5e-6", "--out", str(out), "--no-plots",
            "--quiet"]
    assert main(argv) == 0
    capsys.readouterr()
    result = json.loads((out / "calibration.json").read_text())
    assert result["converged"] and abs(result["reached_max_depth_m"] / 5e-6 - 1.0) <= result["rel_tolerance"]
    trials = sorted(result["trials"], key=lambda t: t["wear_coefficient_m2_N"])
    depths = [t["max_wear_depth_m"] for t in trials]
    assert len(trials) >= 2 and depths == sorted(depths), trials
    for i, trial in enumerate(result["trials"]):
        folder = out / f"trial_{i}"
        summary = json.loads((folder / "summary.json").read_text())
        assert summary["effective_wear_coefficient_m2_N"] == trial["wear_coefficient_m2_N"]
        said = re.search(r"\(its trial (\d+): k_w ([0-9.e+-]+) m\^2/N\)$", summary["command_line"])
        assert said and int(said[1]) == i and abs(float(said[2]) / trial["wear_coefficient_m2_N"] - 1.0) < 1e-5
        assert summary["command_line"].startswith("wearjoint " + " ".join(argv))
        page = (folder / "report.html").read_text()
        assert "Made through the API" not in page and f"its trial {i}: k_w" in page
