"""A sweep's and a sensitivity study's report from their cases' summaries: the parameters the cases ran and which
differ between them."""
import json
import re
import subprocess
import sys


def test_the_sweeps_parameters_say_which_differ_between_its_cases_and_why(tmp_path):
    """Synthetic cases: the swept value, the seeds' angles and a parameter that follows an option of the design, each
    as the list of its values with where they came from; one the cases share as its value; a long numeric list as its
    range; no case finished: nothing."""
    from wearjoint.sweep.report import SHOWN_VALUES, parameter_spread

    rows = []
    for k, (mu, seed) in enumerate((m, s) for m in (0.1, 0.2) for s in range(SHOWN_VALUES + 1)):
        folder = tmp_path / f"cases/{k}"
        folder.mkdir(parents=True)
        mechanism = {"initial_crank_angle_deg": 0.5 * seed, "crank_length_m": 0.05}
        joint = {"friction_coefficient": mu, "wear_factor": 10.0 * mu, "pin_offset_m": [0.05, 0.0]}
        (folder / "summary.json").write_text(json.dumps({"parameters": {"joint": joint, "mechanism": mechanism}}))
        rows.append({"mu": mu, "friction_coefficient": mu, "seed": seed, "status": "ok", "folder": f"cases/{k}"})
    rows.append({"friction_coefficient": 0.3, "seed": 0, "status": "failed", "folder": "cases/none"})
    first, spread = parameter_spread(tmp_path, rows, ["friction_coefficient"])
    assert first == {"joint": {"friction_coefficient": 0.1, "wear_factor": 1.0, "pin_offset_m": [0.05, 0.0]},
                     "mechanism": {"initial_crank_angle_deg": 0.0, "crank_length_m": 0.05}}
    assert spread == {"friction_coefficient": [[0.1, 0.2, 0.3], "swept (--vary)"],
                      "wear_factor": [[1.0, 2.0], "follows an option of the design"],
                      "initial_crank_angle_deg": [f"from 0 to {0.5 * SHOWN_VALUES:g}, {SHOWN_VALUES + 1} values",
                                                  "the seeds' start angles (--seeds)"]}
    assert parameter_spread(tmp_path, rows[-1:], ["friction_coefficient"]) == ({}, {})


def test_a_sensitivity_studys_page_shows_its_sampled_ranges_and_the_parameters_its_runs_held(tmp_path):
    """Morris N = 2 over the restitution (3 runs): its page had the sampled range but not the joint and mechanism the
    runs held; now both, the sampled one as its values and "sampled (--param)", the rest as the runs had them."""
    out = tmp_path / "study"
    done = subprocess.run([sys.executable, "-m", "wearjoint.cli", "sensitivity", "simulate", "--revolutions", "0.02",
                           "--no-plots", "--param", "restitution=0.5,0.9", "--samples", "2", "--workers", "1",
                           "--crank-speed-rpm", "4000", "--out", str(out), "--quiet"], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    sampled = sorted(summary["parameter_spread"]["restitution"][0])
    assert summary["parameter_spread"]["restitution"][1] == "sampled (--param)" and len(sampled) >= 2
    assert 0.5 <= sampled[0] < sampled[-1] <= 0.9 and list(summary["parameter_spread"]) == ["restitution"]
    assert summary["case_parameters"]["mechanism"]["crank_speed_rpm"] == 4000.0
    page = (out / "report.html").read_text()
    tables = {name: [re.findall(r"<td[^>]*>(.*?)</td>", row) for row in re.findall(r"<tr>(.*?)</tr>", body)][1:]
              for name, body in re.findall(r'<table id="([^"]+)">(.*?)</table>', page)}
    assert tables["summary-parameters"] == [["restitution", "restitution", "0.5", "0.9", "False"]]
    joint, mechanism = ({row[0]: row[1:] for row in tables[key]} for key in ("joint", "mechanism"))
    assert joint["restitution"][1] == "sampled (--param)" and mechanism["crank_speed_rpm"] == ["4000.0", "given"]
    assert joint["pin_radius_m"] == ["0.01", "default"]


def test_a_swept_files_ticks_are_its_names_unless_two_share_one(monkeypatch, tmp_path):
    """A swept load table's ticks had been its full paths, running into each other: its file names now, its paths
    where two files share a name."""
    import wearjoint.plots
    from wearjoint.sweep.report import GridPoint, plot_against_parameters

    figures = []
    monkeypatch.setattr(wearjoint.plots, "save_figure", lambda fig, path: figures.append(fig))
    for tables in (["/data/press/a_1kN.csv", "/data/press/b_2kN.csv"], ["/x/load.csv", "/y/load.csv"]):
        points = [GridPoint([{"slider_force_table": t, "status": "ok", "max_wear_depth_m": d}], ["slider_force_table"])
                  for t, d in zip(tables, (1e-6, 2e-6))]
        plot_against_parameters(tmp_path, points)
    labels = [[tick.get_text() for tick in fig.axes[0].get_xticklabels()] for fig in figures]
    assert labels == [["a_1kN.csv", "b_2kN.csv"], ["/x/load.csv", "/y/load.csv"]]
