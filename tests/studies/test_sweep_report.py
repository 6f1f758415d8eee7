"""A sweep's report from its cases' summaries: the parameters the cases ran and which differ between them."""
import json


def test_the_sweeps_parameters_say_which_differ_between_its_cases_and_why(tmp_path):
    """Synthetic cases: the swept value, the seeds' angles and a parameter that follows a swept option each as the
    list of their values with where they came from; one the cases share as its value; a long numeric list as its
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
                      "wear_factor": [[1.0, 2.0], "follows a swept option"],
                      "initial_crank_angle_deg": [f"from 0 to {0.5 * SHOWN_VALUES:g}, {SHOWN_VALUES + 1} values",
                                                  "the seeds' start angles (--seeds)"]}
    assert parameter_spread(tmp_path, rows[-1:], ["friction_coefficient"]) == ({}, {})
