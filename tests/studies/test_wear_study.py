"""`wearjoint wear-study`: resume after a kill, outputs, lobes, impact events, factor convergence, bad arguments."""
import json
import math
import subprocess
import sys

import numpy as np

import pytest

from wearjoint.analysis import impact_events
from wearjoint.cli import main as cli_main
from wearjoint.slider_crank import SliderCrank
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters, paper_joint
from wearjoint.studies.cycle_jump import DEFAULT_JUMP_TOLERANCE
from wearjoint.studies.wear_convergence import run_convergence
from wearjoint.studies.wear_study import CHECKPOINT_NAME, WearStudyConfig, run_wear_study, snapshot_statistics
from wearjoint.parameters import is_paper_case

MODEL_SUMMARY_KEYS = {"revolutions", "simulated_time_s", "wall_time_s", "realtime_factor", "max_contact_force_N",
                      "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                      "max_eccentricity_m", "max_wear_depth_m", "max_wear_angle_deg", "worn_volume_m3", "parameters"}
SNAPSHOT_KEYS = {"revolution", "max_wear_depth_m", "max_wear_angle_deg", "lobe_0_angle_deg", "lobe_180_angle_deg",
                 "worn_volume_m3", "impact_events", "impact_peak_max_m_s2", "wall_time_s"}


def wearjoint(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def small_config(**changes) -> WearStudyConfig:
    """10 revolutions at wear factor 10: one simulated revolution (the least a study may simulate)."""
    values = dict(joint=paper_joint(wear_factor=10.0), mechanism=SliderCrankParameters(), revolutions=10,
                  snapshots=(5, 10), checkpoint_every_revolutions=0.125, jump_tolerance=None)
    values.update(changes)
    return WearStudyConfig(**values)


@pytest.mark.parametrize("route", ["wear factor", pytest.param("cycle jumping", marks=pytest.mark.slow)])
def test_killed_study_resumes_to_the_same_profile_bit_for_bit(tmp_path, route):
    config = small_config() if route == "wear factor" else \
        small_config(joint=paper_joint(wear_factor=1.0), jump_tolerance=DEFAULT_JUMP_TOLERANCE)
    whole = run_wear_study(config, tmp_path / "whole", progress=False, plots=False)
    stopped = run_wear_study(config, tmp_path / "killed", progress=False, plots=False,
                             stop_after_checkpoints=5 if route == "wear factor" else 2)
    assert stopped["finished"] is False
    assert not (tmp_path / "killed" / "summary.json").exists()
    # the snapshot passed before the kill is on disk already, as the finished study writes it
    rev5 = (tmp_path / "whole" / "profile_rev5.csv").read_bytes()
    assert (tmp_path / "killed" / "profile_rev5.csv").read_bytes() == rev5
    assert not (tmp_path / "killed" / "profile_rev10.csv").exists()
    index = json.loads((tmp_path / "killed" / "snapshots.json").read_text())
    assert index["status"] == "running" and [s["revolution"] for s in index["snapshots"]] == [5]
    with pytest.raises(ParameterError, match="--resume"):
        run_wear_study(config, tmp_path / "killed", progress=False, plots=False)
    resumed = run_wear_study(config, tmp_path / "killed", resume=True, progress=False, plots=False)
    for name in ("profile_rev5.csv", "profile_rev10.csv", "profile.csv", "wear_growth.csv"):
        assert (tmp_path / "killed" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes(), name
    assert resumed["max_wear_depth_m"] > 0
    for a, b in zip(resumed["snapshots"], whole["snapshots"]):
        assert a["impact_event_list"] == b["impact_event_list"]
    same = ("start_revolution", "revolutions", "passes", "error_estimate_rel")    # the jumps, but for wall times
    assert [[j[k] for k in same] for j in resumed.get("cycle_jumping", {}).get("jump_history", [])] == \
        [[j[k] for k in same] for j in whole.get("cycle_jumping", {}).get("jump_history", [])]


def test_resume_refuses_a_checkpoint_of_other_settings(tmp_path):
    run_wear_study(small_config(), tmp_path, progress=False, plots=False, stop_after_checkpoints=1)
    assert (tmp_path / CHECKPOINT_NAME).exists()
    with pytest.raises(ParameterError, match=r"parameter --wear-factor \(joint.wear_factor\) is 10.0 in its "
                                             r"checkpoint, 5.0 given"):
        run_wear_study(small_config(joint=paper_joint(wear_factor=5.0)), tmp_path, resume=True,
                       progress=False, plots=False)


@pytest.fixture(scope="module")
def cli_study(tmp_path_factory):
    """100 revolutions at wear factor 100 with the printed k_w: one simulated revolution, ~0.2 mm of wear."""
    out = tmp_path_factory.mktemp("study")
    done = wearjoint("wear-study", "--revolutions", "100", "--snapshots", "50,100", "--wear-factor", "100",
                     "--out", str(out), "--quiet")
    assert done.returncode == 0, done.stderr
    return out, json.loads((out / "summary.json").read_text())


def test_study_writes_snapshot_files_figures_and_summary(cli_study):
    out, summary = cli_study
    assert MODEL_SUMMARY_KEYS <= set(summary)
    assert summary["revolutions"] == 100 and summary["simulated_revolutions"] == pytest.approx(1.0)
    assert [s["revolution"] for s in summary["snapshots"]] == [50, 100]
    for s in summary["snapshots"]:
        assert SNAPSHOT_KEYS <= set(s)
        text = (out / f"profile_rev{s['revolution']}.csv").read_text()
        assert text.startswith("phi_deg,wear_depth_m\n")
        profile = np.loadtxt(out / f"profile_rev{s['revolution']}.csv", delimiter=",", skiprows=1)
        assert profile.shape == (1257, 2)
        assert profile[:, 1].max() == pytest.approx(s["max_wear_depth_m"])
    first, last = summary["snapshots"]
    assert last["max_wear_depth_m"] > first["max_wear_depth_m"] and last["worn_volume_m3"] > first["worn_volume_m3"]
    assert summary["max_wear_depth_m"] == pytest.approx(last["max_wear_depth_m"])
    growth = np.loadtxt(out / "wear_growth.csv", delimiter=",", skiprows=1)
    assert np.all(np.diff(growth[:, 1]) >= 0.0) and growth[-1, 0] == pytest.approx(100)
    for png in ("fig7_wear_profiles.png", "fig8_slider_acceleration.png", "wear_growth.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert summary["growth"]["experiment_depth_ratio_full_to_half"] == pytest.approx(0.55 / 0.19)


def test_wear_forms_two_lobes_where_crank_and_rod_are_collinear(cli_study):
    """Paper Sec. 6.2: wear at the bushing's flanks (0 and 180 deg in the rod frame), little at 90/270 deg."""
    _, summary = cli_study
    s = summary["snapshots"][-1]
    deepest = s["max_wear_depth_m"]
    assert abs(s["lobe_0_angle_deg"]) < 30.0 and abs(s["lobe_180_angle_deg"] - 180.0) < 30.0
    assert min(s["lobe_0_depth_m"], s["lobe_180_depth_m"]) > 0.3 * deepest
    assert max(s["depth_at_90_deg_m"], s["depth_at_270_deg_m"]) < 0.1 * deepest


def test_impact_events_are_clusters_of_deviation_from_the_ideal_joint():
    mech = SliderCrankParameters()
    t = np.linspace(0.0, mech.period_s, 40001)
    a = SliderCrank(mech).closed_form(t)["slider_a_m_s2"].copy()
    at_deg = lambda deg: int(round(deg / 360.0 * (t.size - 1)))  # noqa: E731
    a[at_deg(90):at_deg(91)] += 500.0         # one event
    a[at_deg(250)] -= 800.0                   # a second one, made of two spikes 5 deg apart (merge)
    a[at_deg(255)] += 300.0
    a[at_deg(120)] += 50.0                    # below the threshold
    events = impact_events(t, a, mech, threshold_m_s2=100.0, merge_deg=15.0)
    assert len(events) == 2
    assert events[0]["peak_crank_rotation_deg"] == pytest.approx(90.0, abs=1.0)
    assert events[0]["peak_deviation_m_s2"] == pytest.approx(500.0, rel=1e-9)
    assert events[1]["peak_crank_rotation_deg"] == pytest.approx(250.0, abs=0.1)
    assert events[1]["peak_deviation_m_s2"] == pytest.approx(800.0, rel=1e-9)
    assert impact_events(t, SliderCrank(mech).closed_form(t)["slider_a_m_s2"], mech, 100.0, 15.0) == []


@pytest.mark.parametrize("args,message", [
    (("--revolutions", "100", "--snapshots", "50,200"), "beyond"),
    (("--revolutions", "100", "--snapshots", "50.5,100"), "--snapshots='50.5' is invalid: allowed an integer (digits"),
    (("--revolutions", "100.5"), "--revolutions='100.5' is invalid: allowed an integer (digits only"),
    (("--revolutions", "1e999"), "--revolutions='1e999' is invalid: allowed an integer (digits only"),
    # the wear-step limit names the study's option (it said "parameter step_s=0.001", an option wear-study has not)
    (("--revolutions", "100", "--max-step", "1e-3"), "--max-step=1e-3 (max_step_s) is invalid with wear ("),
    (("--revolutions", "100", "--wear-factor=-5"), "wear_factor"),
    (("--revolutions", "1000", "--wear-factor", "1e6"),
     "--wear-factor=1e6 (wear_factor) is invalid with --revolutions 1000: allowed 0.001 <= wear "
     "factor <= 1000"),
    (("--revolutions", "1000", "--wear-factor", "1e-300"),     # 1e302 revolutions' table was allocated
     "--wear-factor=1e-300 (wear_factor) is invalid with --revolutions 1000: allowed 0.001 <= wear factor"),
    (("--revolutions", "100", "--convergence", "1,200"), "--convergence: factor 200: --wear-factor"),
    (("--revolutions", "100", "--cycle-jump-tolerance", "2"), "--cycle-jump-tolerance=2 (jump_tolerance)"),
    (("--revolutions", "100", "--cycle-jump-tolerance", "0.01", "--wear-factor", "10"), "wear_factor=10.0"),
    (("--revolutions", "100", "--cycle-jump-block", "0"), "--cycle-jump-block=0 (jump_block_revolutions)"),
    (("--revolutions", "100", "--convergence", "1,-10"), "factor"),
    (("--revolutions", "100", "--convergence", "jump,x"), "--convergence: 'x' is not a number"),
    (("--revolutions", "100", "--life-depth-m", "0.0101"),          # the bushing wears through at its radius
     "--life-depth-m=0.0101 (life_depth_m) is invalid: allowed a finite real number > 0 below the bushing radius 0.0101 m"),
])
def test_bad_arguments_give_one_clear_error(tmp_path, capsys, args, message):
    assert cli_main(["wear-study", "--out", str(tmp_path / "x"), "--quiet", *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_cycle_jumping_spans_more_revolutions_than_a_study_simulates():
    """A study of 2.1 million strokes (docs/tutorials/life_prediction.md) simulates what its jumps need (150
    revolutions there): it was refused as 2.1e6 simulated revolutions, over the 1e6 a study without jumps may take.
    Without jumps that bound holds; with them the span is bounded at 1e12 revolutions."""
    study = dict(joint=paper_joint(), mechanism=SliderCrankParameters())
    assert WearStudyConfig(**study, revolutions=2_100_000).jump_tolerance == DEFAULT_JUMP_TOLERANCE
    with pytest.raises(ParameterError, match=r"wear_factor\) is invalid with --revolutions 2100000: allowed 2.1 <= "):
        WearStudyConfig(**study, revolutions=2_100_000, jump_tolerance=None)
    with pytest.raises(ParameterError, match=r"^parameter revolutions=2000000000000 is invalid: allowed at most 1e\+12 "
                                             r"with cycle jumping$"):
        WearStudyConfig(**study, revolutions=2 * 10 ** 12)


@pytest.mark.parametrize("changes, message", [
    ({"joint": {}}, "parameter joint={} is invalid: allowed a JointParameters"),
    ({"mechanism": None}, "parameter mechanism=None is invalid: allowed a SliderCrankParameters"),
    ({"max_step_s": "1e-5"}, "parameter max_step_s='1e-5' is invalid: allowed a finite real number > 0"),
    ({"rtol": math.nan}, "parameter rtol=nan is invalid: allowed a finite real number > 0"),
    ({"life_depth_m": 0.02}, "parameter life_depth_m=0.02 is invalid: allowed a finite real number > 0 below the "
                             "bushing radius 0.0101 m"),
])
def test_a_study_configured_from_python_refuses_a_wrong_value_in_one_line(changes, message):
    """A string step died in a TypeError ("must be real number, not str") and a dict for the joint in an
    AttributeError: each is the one-line error of any other bad value."""
    values = dict(joint=paper_joint(), mechanism=SliderCrankParameters()) | changes
    with pytest.raises(ParameterError) as refused:
        WearStudyConfig(**values)
    assert str(refused.value) == message


def test_bad_argument_exit_status_from_the_shell(tmp_path):
    done = wearjoint("wear-study", "--out", str(tmp_path / "x"), "--revolutions", "100", "--snapshots", "0,100")
    assert done.returncode == 2
    assert "snapshots=0" in done.stderr and "Traceback" not in done.stderr


@pytest.mark.slow
def test_accelerated_profiles_agree_with_brute_force(tmp_path):
    """Factor 10 vs factor 1 (brute force) at matched revolutions, within the stated tolerance."""
    config = small_config(revolutions=20, snapshots=(10, 20), checkpoint_every_revolutions=5.0)
    result = run_convergence(config, [1.0, 10.0], tmp_path, progress=False)
    assert result["within_tolerance"]["F=10"], result["rows"]


@pytest.mark.parametrize("placement", ["foundation", "patch"])
def test_one_revolution_at_wear_factor_ten_stands_for_ten(tmp_path, placement):
    """The study's bookkeeping of the wear factor: at a k_w so small that the wear does not move the pin (1e-4
    of the printed one), ten revolutions at wear factor 10 simulate one revolution, the same trajectory as the
    first of a run at wear factor 1, and remove ten times its Archard volume.  (The factor's bias where the wear
    does feed back is measured against cycle jumping over many revolutions: tests/core/test_wear_convergence.py; two
    single chaotic runs over 1 and 10 revolutions, compared before, differed by 18 % with either wear update.)"""
    joint = paper_joint(wear_factor=1.0, wear_placement=placement, wear_coefficient_m2_N=5.05e-14)
    brute = run_wear_study(small_config(joint=joint, revolutions=1, snapshots=(1,)), tmp_path / "brute",
                           progress=False, plots=False)
    factor = run_wear_study(small_config(joint=joint.replace(wear_factor=10.0), snapshots=(10,)), tmp_path / "factor",
                            progress=False, plots=False)
    assert brute["simulated_revolutions"] == pytest.approx(1.0)
    assert factor["simulated_revolutions"] == pytest.approx(1.0)
    assert factor["worn_volume_m3"] == pytest.approx(10.0 * brute["worn_volume_m3"], rel=1e-3)


def test_resume_refuses_a_corrupted_checkpoint_and_a_bad_profile(tmp_path):
    import pickle

    from wearjoint.studies.wear_study_recovery import crc32c

    config = small_config()
    run_wear_study(config, tmp_path, progress=False, plots=False, stop_after_checkpoints=5)   # past snapshot 5
    path = tmp_path / CHECKPOINT_NAME
    good = path.read_bytes()
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x20
    path.write_bytes(bytes(flipped))
    with pytest.raises(ParameterError, match="CRC-32C is 0x[0-9a-f]{8}, its .* bytes give 0x[0-9a-f]{8}: the file is"):
        run_wear_study(config, tmp_path, resume=True, progress=False, plots=False)
    state = pickle.loads(good[:-4])
    state["snapshots"][0]["wear_depth_m"][3] = -1e-9
    data = pickle.dumps(state)
    path.write_bytes(data + crc32c(data).to_bytes(4, "little"))
    with pytest.raises(ParameterError, match=r"snapshot 5 wear_depth_m: wear profile: wear_depth\[4\]=-1e-09 m is negative"):
        run_wear_study(config, tmp_path, resume=True, progress=False, plots=False)


def _revolutions_csv(out) -> list:
    import csv

    with open(out / "revolutions.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_a_snapshot_states_the_slider_acceleration_of_its_revolutions_csv_row(tmp_path):
    """One definition: each snapshot's slider acceleration extremes are revolutions.csv's row of the simulated
    revolution ending at it (every accepted step; the 1e-5 s samples of Fig. 8 miss impact peaks).  The summary's
    extremes are the final state's, the last simulated revolution's (revolution 20 of the study: the first of the
    ten it stands for); its impact events follow the study's threshold, in summary.json and revolutions.csv."""
    summary = run_wear_study(small_config(revolutions=30, snapshots=(10, 20, 30), impact_threshold_m_s2=1e9),
                             tmp_path, progress=False, plots=False)
    rows = _revolutions_csv(tmp_path)
    assert len(rows) == 3
    for key in ("max_contact_force_N", "max_eccentricity_m"):
        assert summary[key] == pytest.approx(float(rows[2][key]), rel=1e-9), key
    assert max(float(row["max_contact_force_N"]) for row in rows[1:]) > summary["max_contact_force_N"]  # not the max
    assert summary["impact_event_revolutions"] == [20] and summary["impact_events_per_revolution"] == 0.0
    assert float(rows[2]["impact_events"]) == 0.0 and "> 1e+09 m/s^2" in summary["impact_event_definition"]
    for snap, expected_row in zip(summary["snapshots"], (0, 1, 2)):     # wear factor 10: revolution R = row R/10 - 1
        assert snap["statistics_revolution"] == expected_row
        row = rows[expected_row]
        assert float(row["revolution"]) == 10 * expected_row        # the first of the ten revolutions it stands for
        for key in ("slider_acc_max_m_s2", "slider_acc_min_m_s2"):
            assert snap[key] == pytest.approx(float(row[key]), rel=1e-9), key
    samples = np.load(tmp_path / "timeseries.npz")        # the last revolution's samples: within the extremes
    last = samples["time_s"] > 2 * SliderCrankParameters().period_s
    assert samples["slider_a_m_s2"][last].max() <= summary["snapshots"][-1]["slider_acc_max_m_s2"]
    assert summary["paper_max_depth_at_4000_rev_m"] == 0.58e-3 and "experiment" in summary   # the paper's case


def test_a_snapshot_before_the_first_complete_revolution_states_no_acceleration():
    stats = np.zeros((2, 8))
    assert snapshot_statistics(stats, 0.5) == {"statistics_revolution": None, "slider_acc_max_m_s2": None,
                                               "slider_acc_min_m_s2": None}


def test_paper_comparisons_only_on_the_paper_mechanism_and_joint(tmp_path):
    paper = SliderCrankParameters()
    assert is_paper_case(paper_joint(wear_coefficient_m2_N=1e-12, wear_factor=10.0), paper)   # k_w may differ
    assert is_paper_case(JointParameters(), paper.replace(initial_crank_angle_deg=1.5))          # a seed's start
    assert not is_paper_case(JointParameters(), paper.replace(crank_speed_rpm=300.0))
    assert not is_paper_case(JointParameters(), paper.replace(rod_length_m=0.3))
    assert not is_paper_case(JointParameters(bushing_radius_m=0.0102), paper)
    assert not is_paper_case(JointParameters(contact_length_m=0.01), paper)
    other = SliderCrankParameters(crank_speed_rpm=300.0)
    summary = run_wear_study(small_config(mechanism=other, joint=paper_joint(other, wear_factor=10.0)), tmp_path,
                             progress=False, plots=False)
    assert summary["status"] == "finished"
    assert "paper_max_depth_at_4000_rev_m" not in summary and "experiment" not in summary
    assert not any(key.startswith("experiment") for key in summary["growth"])
    assert "experiment" not in summary["growth"]["note"]
    written = json.loads((tmp_path / "summary.json").read_text())
    assert "paper_max_depth_at_4000_rev_m" not in written and "experiment" not in written


def test_the_life_to_a_depth_is_the_growth_curves_and_a_resumed_study_may_ask_another(tmp_path):
    """--life-depth-m: the revolutions where wear_growth.csv's max depth reaches the depth (linear between its rows,
    as calibrate reads a study) and the hours at the crank's speed; a depth the study does not reach has none and
    says so; the depth is no physical setting: a study resumed with another one states that one."""
    whole = run_wear_study(small_config(), tmp_path / "a", progress=False, plots=False)
    growth = np.loadtxt(tmp_path / "a" / "wear_growth.csv", delimiter=",", skiprows=1)
    revolutions, depth = np.r_[0.0, growth[:, 0]], np.r_[0.0, growth[:, 1]]
    target = 0.6 * depth[-1]
    expected = float(np.interp(target, depth, revolutions))
    stopped = run_wear_study(small_config(life_depth_m=target), tmp_path / "b", progress=False, plots=False,
                             stop_after_checkpoints=5)
    assert stopped["finished"] is False and "life" not in stopped
    summary = run_wear_study(small_config(life_depth_m=target), tmp_path / "b", resume=True, progress=False,
                             plots=False)
    assert summary["life_revolutions"] == pytest.approx(expected, rel=1e-9) and 0.0 < expected < 10.0
    assert summary["life_hours"] == pytest.approx(expected / (60.0 * SliderCrankParameters().crank_speed_rpm),
                                                  rel=1e-12)
    assert summary["life"]["depth_m"] == target and "at the study's k_w" in summary["life"]["note"]
    assert "life" not in whole
    deeper = run_wear_study(small_config(life_depth_m=2.0 * depth[-1]), tmp_path / "b", resume=True,
                            progress=False, plots=False)
    assert deeper["life_revolutions"] is None and "beyond the study's max depth" in deeper["life"]["note"]
