"""`wearjoint sensitivity`: the analysis path against closed forms (Ishigami's Sobol' indices, Morris on a
linear function), the designs' prefix property that --resume and --target-interval rely on, bad input, and
tiny studies of the model on a LocalCluster: a parameter with no physical effect (the driven crank's
inertia) gets intervals holding 0, Morris and Sobol' put k_w first for the wear depth, stopped studies
resume, the contact law's spread (one run per law variant at the nominal point; skipped where a --param names
the law's field; off with --no-law-spread).  Slow: a running scheduler with two workers; the doc's study ranks
alike in both methods."""
import json
import math
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from terminal_signals import default_sigint
from test_sweep import read_csv, wearjoint
from test_sweep_faults import _finished, _stop, _wait_for
from wearjoint.cli import main
from wearjoint.contact_laws import contact_law_variants
from wearjoint.parameters import ParameterError, SliderCrankParameters
from wearjoint.sensitivity.law_spread import nominal_point, settle
from wearjoint.sensitivity.analyse import analyse, until_target, widest_interval
from wearjoint.sensitivity.problem import Parameter, Problem, parse_params
from wearjoint.sensitivity.report import invalid_reason, output_value
from wearjoint.sensitivity.sample import group_size, sample

A, B = 7.0, 0.1                                        # Ishigami's constants (Ishigami & Homma 1990)
PI = math.pi
TINY = ("--revolutions", "0.05", "--no-plots")
# k_w over two decades (Archard: depth proportional to it), restitution, and the driven crank's inertia (no effect)
PARAMS = ("--param", "wear-coefficient-m2-N=1e-11,1e-9,log", "--param", "restitution=0.6,0.95",
          "--param", "crank_inertia_kg_m2=0.004,0.015")
DUMMY = "crank-inertia-kg-m2"


def ishigami(x):
    return np.sin(x[:, 0]) + A * np.sin(x[:, 1]) ** 2 + B * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices():
    """Closed-form S1 and ST of the Ishigami function on [-pi, pi]^3."""
    v1 = 0.5 * (1.0 + B * PI ** 4 / 5.0) ** 2
    v2 = A ** 2 / 8.0
    v13 = B ** 2 * PI ** 8 * (1.0 / 18.0 - 1.0 / 50.0)
    v = v1 + v2 + v13
    return [v1 / v, v2 / v, 0.0], [(v1 + v13) / v, v2 / v, v13 / v]


ISHIGAMI = Problem("simulate", tuple(Parameter(f"x{i}", f"x{i}", -PI, PI) for i in range(3)))


def contains(value, centre, half):
    return centre - half <= value <= centre + half


def covered(result):
    """(intervals holding the closed form, intervals) of an Ishigami analysis."""
    s1, st = ishigami_indices()
    hits = [contains(s1[k], r["S1"], r["S1_conf"]) for k, r in enumerate(result["indices"])]
    hits += [contains(st[k], r["ST"], r["ST_conf"]) for k, r in enumerate(result["indices"])]
    return sum(hits), len(hits)


def test_ishigami_indices_lie_within_their_own_intervals():
    x = sample(ISHIGAMI, "sobol", 1024, seed=0)
    assert covered(analyse(ISHIGAMI, "sobol", x, ishigami(x), seed=0)) == (6, 6)


def test_ishigami_intervals_cover_the_closed_form_at_their_level():
    hits = total = 0
    for seed in range(20):
        x = sample(ISHIGAMI, "sobol", 256, seed=seed)
        h, n = covered(analyse(ISHIGAMI, "sobol", x, ishigami(x), seed=seed))
        hits, total = hits + h, total + n
    assert hits / total >= 0.9                         # 95 % intervals; 0.9 leaves room for 120 draws


def test_morris_of_a_linear_function_is_the_slope_times_the_range():
    problem = Problem("simulate", (Parameter("a", "a", 2.0, 5.0), Parameter("b", "b", 1e-3, 1e1, log=True),
                                   Parameter("c", "c", 0.0, 1.0)))
    x = sample(problem, "morris", 6, seed=3)
    values = np.array([[p["a"], p["b"], p["c"]] for p in problem.points(x)])
    y = 3.0 * values[:, 0] - 2.0 * np.log10(values[:, 1])            # c has no effect
    rows = analyse(problem, "morris", x, y, seed=3)["indices"]
    assert [r["mu_star"] for r in rows] == pytest.approx([3.0 * 3.0, 2.0 * 4.0, 0.0], rel=1e-9, abs=1e-12)
    assert [r["mu"] for r in rows] == pytest.approx([9.0, -8.0, 0.0], rel=1e-9, abs=1e-12)
    assert [r["sigma"] for r in rows] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    assert rows[2]["mu_star_conf"] == 0.0
    assert all(1e-3 <= p["b"] <= 1e1 and 2.0 <= p["a"] <= 5.0 for p in problem.points(x))


@pytest.mark.parametrize("method,n", [("morris", 3), ("sobol", 8)])
def test_designs_are_prefixes_of_larger_designs(method, n):
    small, large = sample(ISHIGAMI, method, n, seed=5), sample(ISHIGAMI, method, 4 * n, seed=5)
    assert len(small) == n * group_size(method, 3) and len(large) == 4 * len(small)
    assert np.array_equal(small, large[:len(small)])


def evaluate_ishigami(x):
    return {"y": ishigami(x)}, {}, False


def test_target_interval_doubles_the_samples_until_it_is_met():
    study = until_target(ISHIGAMI, "sobol", 8, 0, evaluate_ishigami, target=0.15, max_samples=4096)
    sizes = [r["samples"] for r in study["rounds"]]
    widest = [r["widest_interval"]["y"] for r in study["rounds"]]
    assert sizes == [8 * 2 ** k for k in range(len(sizes))] and study["met"] is True
    assert widest[-1] <= 0.15 < min(widest[:-1])
    assert widest_interval("sobol", study["results"]["y"]) == widest[-1]


def test_target_interval_stops_at_max_samples():
    study = until_target(ISHIGAMI, "sobol", 8, 0, evaluate_ishigami, target=1e-6, max_samples=40)
    assert [r["samples"] for r in study["rounds"]] == [8, 16, 32] and study["met"] is False


def test_groups_with_a_failed_run_are_left_out():
    x = sample(ISHIGAMI, "sobol", 64, seed=1)
    y = ishigami(x)
    size = group_size("sobol", 3)
    y[[5, 3 * size + 1, 40 * size + 4]] = np.nan       # runs of groups 1, 3 and 40
    keep = np.setdiff1d(np.arange(64), [1, 3, 40])
    rows = (keep[:, None] * size + np.arange(size)).ravel()
    result = analyse(ISHIGAMI, "sobol", x, y, seed=1)
    assert (result["groups"], result["dropped"]) == (61, 3)
    assert result["indices"] == analyse(ISHIGAMI, "sobol", x[rows], y[rows], seed=1)["indices"]


def test_a_run_whose_pin_left_the_bushing_is_not_analysed():
    groove = {"status": "ok", "clearance_m": 1e-4, "max_wear_depth_m": 5e-4, "max_eccentricity_m": 6.05e-4,
              "admissible_penetration_m": 2e-4}
    apart = {**groove, "max_eccentricity_m": 1.46e4}
    through = {**groove, "max_eccentricity_m": 8.05e-4}                # 0.205 mm into the wall: past the 0.2 mm
    assert invalid_reason(groove) == "" and output_value(groove, "max_wear_depth_m") == 5e-4
    pressed = {**groove, "max_contact_force_N": 3e5, "admissible_force_N": 2.25e5}   # a blown-up damping force
    for row in (apart, through, pressed):
        assert invalid_reason(row) and math.isnan(output_value(row, "max_wear_depth_m"))
    assert "admissible" in invalid_reason(pressed) and "into the bushing wall" in invalid_reason(through)
    assert math.isnan(output_value({**groove, "status": "failed"}, "max_wear_depth_m"))


def test_an_unknown_parameter_lists_only_the_real_valued_options_a_study_can_sample():
    """The list named options a sensitivity study refuses (integrator, clearance-joint, initial-profile, ...)."""
    with pytest.raises(ParameterError) as refused:
        parse_params("simulate", ["frobnication=1,2"])
    allowed = str(refused.value).partition("allowed, as the option's name or its API name with underscores: ")[2]
    listed = set(allowed.split(", "))
    assert {"restitution", "crank-speed-rpm", "wear-coefficient-m2-N"} <= listed
    assert not listed & {"integrator", "clearance-joint", "initial-profile", "calibration", "contact-damping"}
    with pytest.raises(ParameterError, match=r"integrator is not a real-valued option"):
        parse_params("simulate", ["integrator=1,2"])


def test_a_parameter_takes_either_spelling():
    a = parse_params("wear-study", ["crank-speed-rpm=100,200", "wear_coefficient_m2_N=1e-11,1e-10,log"])
    b = parse_params("wear-study", ["crank_speed_rpm=100,200", "wear-coefficient-m2-N=1e-11,1e-10,log"])
    assert a == b and a.names == ["crank-speed-rpm", "wear-coefficient-m2-N"]
    assert a.salib()["bounds"] == [[100.0, 200.0], [-11.0, -10.0]]


@pytest.mark.parametrize("args,named", [
    (("--param", "frobnication=1,2"), "--param 'frobnication=1,2'"),
    (("--param", "restitution=0.9,0.6"), "--param 'restitution=0.9,0.6'"),
    (("--param", "restitution=0.7,0.7"), "LOW=0.7 >= HIGH=0.7"),
    (("--param", "wear-coefficient-m2-N=-1e-10,1e-10,log"), "--param 'wear-coefficient-m2-N=-1e-10,1e-10,log'"),
    (("--param", "wear-coefficient-m2-N=0,1e-10,log"), "LOW=0.0"),
    (("--param", "restitution=0.5,1.5"), "restitution=1.5"),
    (("--param", "restitution=0.6,0.9", "--samples", "1"), "--samples=1"),
    (("--param", "restitution=0.6,0.9", "--method", "sobol", "--samples", "4"), "--samples=4"),
    (("--param", "restitution=0.6,0.9", "--method", "sobol", "--samples", "24"), "--samples=24"),
    (("--param", "restitution=0.6,0.9", "--outputs", "max_wear_depth_m,depth"), "--outputs 'depth'"),
    (("--param", "restitution=0.6,0.9", "--target-interval", "0"), "--target-interval=0.0"),
    (("--param", "restitution=0.6,0.9", "--workers", "0"), "--workers=0"),
    (("--param", "restitution=0.6,0.9", "--seeds", "2"), "--seeds=2 is invalid here"),
    ((), "--param is missing"),
])
def test_bad_input_gives_one_line_naming_the_option_and_the_value(tmp_path, capsys, args, named):
    code = main(["sensitivity", "simulate", *TINY, *args, "--out", str(tmp_path / "x")])
    err = capsys.readouterr().err
    assert code == 2 and named in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("target", ["simulate", "wear-study"])
def test_every_number_a_runs_summary_states_is_an_output(tmp_path, capsys, target):
    """The answers against the ideal joint and the impact-event statistics are numbers of every run's summary.json,
    as the how-to says the outputs are: they were refused (the error for an unknown one lists those allowed)."""
    names = ["slider_acc_error_rms_m_s2", "slider_acc_error_max_m_s2", "ideal_joint_force_max_N",
             "joint_force_over_ideal", "impact_events_per_revolution", "chattering_revolution_share", "whirl_fraction"]
    assert main(["sensitivity", target, "--revolutions", "1", "--param", "restitution=0.6,0.9", "--outputs",
                 "unknown_thing", "--out", str(tmp_path / "x")]) == 2
    allowed = capsys.readouterr().err.split("allowed (comma separated) ")[1].strip().split(", ")
    assert set(names) <= set(allowed)


@pytest.mark.parametrize("target", ["simulate", "wear-study"])
def test_the_help_lists_no_seeds_option_which_a_study_refuses(capsys, target):
    with pytest.raises(SystemExit):
        main(["sensitivity", target, "--help"])
    help_text = capsys.readouterr().out
    assert "--param" in help_text and "--seeds" not in help_text


def test_importing_the_command_imports_neither_salib_nor_dask():
    code = ("import sys, wearjoint.sensitivity, wearjoint.cli.sensitivity; "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'SALib', 'dask', 'distributed'}))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stderr


# ------------------------------------------------------------------ the model, tiny runs on a LocalCluster
@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    """Sobol' N = 8 and Morris N = 4 of a 0.05-revolution simulate over k_w, restitution and the crank's inertia."""
    root = tmp_path_factory.mktemp("sensitivity")
    done = {}
    for method, n in (("sobol", "8"), ("morris", "4")):          # Sobol' with its figures, Morris without
        options = [a for a in TINY if a != "--no-plots" or method == "morris"]
        done[method] = wearjoint("sensitivity", "simulate", *options, *PARAMS, "--method", method, "--samples", n,
                                 "--seed", "7", "--workers", "2", "--out", str(root / method), "--quiet")
    return root, done


def indices(out):
    table = {}
    for r in read_csv(out / "indices.csv"):
        table.setdefault(r["output"], []).append(r)
    return table


def test_study_writes_its_results(studies):
    root, done = studies
    for method, n, d_rows in (("sobol", 8, 5), ("morris", 4, 4)):
        out = root / method
        assert done[method].returncode == 0, done[method].stderr
        summary = json.loads((out / "summary.json").read_text())
        assert (summary["method"], summary["samples"], summary["seed"], summary["runs"]) == (method, n, 7, n * d_rows)
        assert summary["wear_factor_bias"]["max_wear_depth_m"]["text"] == "0 %"        # F = 1: no factor
        # fewer groups than the method's default: the intervals are said to be rough (Morris N = 2 said nothing)
        assert summary["intervals_note"].startswith(f"N = {n} ") and "rough" in summary["intervals_note"]
        assert f"note: {summary['intervals_note']}" in done[method].stdout
        assert summary["command_line"].startswith("wearjoint sensitivity simulate --revolutions 0.05")
        samples = read_csv(out / "samples.csv")
        assert len(samples) == n * d_rows and all(r["status"] == "ok" for r in samples)
        for r in samples[:3]:                          # each row holds its run's outputs
            run = json.loads((out / "cases" / r["case_id"] / "summary.json").read_text())
            assert float(r["max_wear_depth_m"]) == run["max_wear_depth_m"]
            assert float(r["slider_acc_peak_m_s2"]) == max(abs(run["slider_acc_max_m_s2"]),
                                                           abs(run["slider_acc_min_m_s2"]))
            assert run["parameters"]["joint"]["restitution"] == float(r["restitution"])
        for output in summary["outputs"]:      # the runs' own figures are never drawn; the indices' unless --no-plots
            assert (out / f"sensitivity_{output}.png").is_file() == (method == "sobol")
        assert "Traceback" not in done[method].stderr


def test_a_parameter_without_physical_effect_gets_intervals_holding_zero(studies):
    root, _ = studies
    for output, rows in indices(root / "sobol").items():
        dummy = next(r for r in rows if r["parameter"] == DUMMY)
        for key in ("S1", "ST"):
            assert float(dummy[f"{key}_low"]) <= 0.0 <= float(dummy[f"{key}_high"]), (output, key)
    for output, rows in indices(root / "morris").items():
        dummy = next(r for r in rows if r["parameter"] == DUMMY)
        assert float(dummy["mu_star_low"]) <= 0.0 <= float(dummy["mu_star_high"]), output


def test_morris_and_sobol_put_k_w_first_for_the_wear_depth(studies):
    root, _ = studies
    for method in ("sobol", "morris"):
        rows = indices(root / method)["max_wear_depth_m"]
        assert [r["rank"] for r in rows] == ["1", "2", "3"]
        assert rows[0]["parameter"] == "wear-coefficient-m2-N", method


@pytest.mark.slow      # resume is in the default run: test_a_stopped_study_keeps_its_finished_runs_and_resume_reuses_them
def test_more_samples_resume_reuses_every_finished_run(studies, tmp_path):
    root, _ = studies
    out = tmp_path / "sobol"
    shutil.copytree(root / "sobol", out)
    first = json.loads((out / "summary.json").read_text())
    refused = wearjoint("sensitivity", "simulate", *TINY, *PARAMS, "--method", "sobol", "--samples", "16",
                        "--seed", "7", "--out", str(out), "--quiet")
    assert refused.returncode == 2 and "--resume" in refused.stderr
    done = wearjoint("sensitivity", "simulate", *TINY, *PARAMS, "--method", "sobol", "--samples", "16",
                     "--seed", "7", "--workers", "2", "--out", str(out), "--quiet", "--resume")
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["skipped_as_done"] == first["cases"] and summary["rounds"][0]["cases_run"] == summary["cases"] - first["cases"]
    assert [r["case_id"] for r in read_csv(out / "samples.csv")][:first["runs"]] == \
        [r["case_id"] for r in read_csv(root / "sobol" / "samples.csv")]


def test_a_resumed_analysis_of_fewer_outputs_leaves_no_earlier_figure(studies, tmp_path):
    """--resume with other --outputs rewrote indices.csv and summary.json but left the earlier analysis's figures,
    which report.html embedded beside the new ones."""
    root, _ = studies
    out = tmp_path / "sobol"
    shutil.copytree(root / "sobol", out)
    assert len(list(out.glob("sensitivity_*.png"))) > 1
    done = wearjoint("sensitivity", "simulate", *(a for a in TINY if a != "--no-plots"), *PARAMS, "--method", "sobol",
                     "--samples", "8", "--seed", "7", "--outputs", "max_wear_depth_m", "--out", str(out), "--quiet",
                     "--resume")
    assert done.returncode == 0, done.stderr
    assert [p.name for p in out.glob("sensitivity_*.png")] == ["sensitivity_max_wear_depth_m.png"]


def test_a_stopped_study_keeps_its_finished_runs_and_resume_reuses_them(tmp_path):
    out = tmp_path / "out"
    # 12 runs of ~0.5 s (RK4 at 1 us over a quarter revolution) one after the other: the study is still running
    # when 2 are done (on two workers all 12 could finish between two looks at the results folder)
    args = ["sensitivity", "simulate", "--revolutions", "0.25", "--integrator", "rk4", "--step", "1e-6", "--no-plots",
            "--param", "restitution=0.6,0.95", "--param", "friction-coefficient=0.05,0.2", "--samples", "4",
            "--outputs", "max_wear_depth_m", "--workers", "1", "--out", str(out), "--quiet"]
    here = signal.getsignal(signal.SIGINT)
    client = subprocess.Popen([sys.executable, "-m", "wearjoint.cli", *args], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True, preexec_fn=default_sigint)
    try:
        _wait_for(lambda: len(_finished(out)) >= 2 or client.poll() is not None, 900, "two finished runs")
        finished_before = len(_finished(out))
        client.send_signal(signal.SIGINT)
        status = client.wait(timeout=120)
        assert status == 130, (f"exit {status} with {finished_before} runs done at the stop (SIGINT here: {here!r}): "
                               f"{client.stderr.read()}")
    finally:
        _stop([client])
    kept = {p.parent.name for p in _finished(out)}
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] and 2 <= len(kept) < summary["cases"], "the study finished before the stop"
    other = [a if a != "restitution=0.6,0.95" else "restitution=0.5,0.95" for a in args]
    refused = wearjoint(*other, "--resume")         # another study in its folder: refused, nothing changed
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1, refused.stderr
    assert "--resume is invalid: the study in" in refused.stderr and "'low': 0.6" in refused.stderr
    assert {p.parent.name for p in _finished(out)} == kept
    done = wearjoint(*args, "--resume")
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["skipped_as_done"] == len(kept) and summary["ok"] == summary["cases"]


# ------------------------------------------------------------------ the contact law's spread
LAWS = [label for label, _ in contact_law_variants(SliderCrankParameters())]


def test_the_contact_laws_spread_runs_every_variant_at_the_nominal_point(studies):
    root, done = studies
    for method in ("sobol", "morris"):
        out = root / method
        summary = json.loads((out / "summary.json").read_text())
        law, rows = summary["law_spread"], read_csv(out / "law_spread.csv")
        assert [r["variant"] for r in rows] == [v["label"] for v in law["variants"]] == LAWS
        assert (law["ok"], law["failed"], law["skipped"], law["not_run"]) == (len(LAWS), 0, 0, 0)
        assert law["point"] == pytest.approx({"wear-coefficient-m2-N": 1e-10, "restitution": 0.775,
                                              DUMMY: 0.0095}, rel=1e-12)
        samples = read_csv(out / "samples.csv")
        for name in summary["outputs"]:
            values = [float(r[name]) for r in rows]
            spread = law["spread"][name]
            assert spread["spread"] == max(values) - min(values)
            assert (spread["min"], spread["max"]) == (min(values), max(values))
            assert spread["sample_spread"] == pytest.approx(np.ptp([float(r[name]) for r in samples]), rel=1e-12)
            assert spread["relative"] == pytest.approx(spread["spread"] / spread["sample_spread"], rel=1e-12)
        for r, (_, changes) in zip(rows, contact_law_variants(SliderCrankParameters())):
            run = json.loads((out / "law_spread" / "cases" / r["case_id"] / "summary.json").read_text())
            joint = run["parameters"]["joint"]
            assert {k: joint[k] for k in changes} == changes
            assert (joint["restitution"], joint["wear_coefficient_m2_N"]) == pytest.approx((0.775, 1e-10), rel=1e-12)
            assert float(r["max_wear_depth_m"]) == run["max_wear_depth_m"]
        assert "contact law spread at the nominal point (8 variants: 8 ok" in done[method].stdout
        assert "laws / samples" in done[method].stdout


def test_a_param_naming_a_law_field_skips_the_variants_that_would_override_it(tmp_path):
    out = tmp_path / "out"
    done = wearjoint("sensitivity", "simulate", *TINY, "--param", "restitution-speed-m-s=0.0125,0.2,log",
                     "--samples", "2", "--outputs", "max_contact_force_N", "--workers", "2", "--out", str(out),
                     "--quiet")
    assert done.returncode == 0, done.stderr
    law = json.loads((out / "summary.json").read_text())["law_spread"]
    clash = {label: ["restitution-speed-m-s"] if "restitution_speed_m_s" in changes else []
             for label, changes in contact_law_variants(SliderCrankParameters())}
    rows = read_csv(out / "law_spread.csv")
    assert [r["variant"] for r in rows] == LAWS and law["skipped"] == 3 and law["ok"] == 5
    for r in rows:
        if clash[r["variant"]]:
            assert r["status"] == "skipped" and f"--param {clash[r['variant']][0]} is sampled" in r["error"]
            assert r["case_id"] == r["max_contact_force_N"] == ""
        else:
            assert r["status"] == "ok" and float(r["max_contact_force_N"]) > 0.0
    assert [s["variant"] for s in law["skipped_variants"]] == [label for label in LAWS if clash[label]]
    assert law["point"] == pytest.approx({"restitution-speed-m-s": 0.05}, rel=1e-12)
    assert "skipped: --param restitution-speed-m-s is sampled" in done.stdout
    assert len(list((out / "law_spread" / "cases").iterdir())) == 5
    # the other laws run without the Hunt-Crossley speed, which they do not read (given, it would be refused)
    assert all(v["unset"] == ["restitution_speed_m_s"] for v in law["variants"] if v["status"] == "ok")


def test_no_law_spread_runs_no_variant(tmp_path):
    out = tmp_path / "out"
    done = wearjoint("sensitivity", "simulate", *TINY, "--param", "restitution=0.6,0.95", "--samples", "2",
                     "--outputs", "max_contact_force_N", "--workers", "1", "--no-law-spread", "--out", str(out),
                     "--quiet")
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["law_spread"] is None and "law_spread.csv" not in summary["files"]
    assert not (out / "law_spread.csv").exists() and not (out / "law_spread").exists()
    assert "contact law" not in done.stdout and len(list((out / "cases").iterdir())) == summary["cases"]


def test_a_failed_variant_is_counted_not_a_number():
    variants = [{"label": label, "changes": {}, "skipped": ""} for label in ("a", "b", "c", "d")]
    variants[3]["skipped"] = "--param x is sampled (the variant would override it)"
    ok = {"status": "ok", "error": "", "max_contact_force_N": 10.0}
    rows = {"A": ok, "B": {**ok, "max_contact_force_N": 14.0}, "C": {"status": "failed", "error": "diverged"}}
    law = settle(variants, ["A", "B", "C", None], rows, ["max_contact_force_N"], {"max_contact_force_N": [0.0, 8.0]})
    assert [v["status"] for v in law["variants"]] == ["ok", "ok", "failed", "skipped"]
    assert law["variants"][2]["values"] == {"max_contact_force_N": None}
    assert (law["ok"], law["failed"], law["skipped"]) == (2, 1, 1)
    assert law["failures"] == [{"variant": "c", "case_id": "C", "status": "failed", "error": "diverged"}]
    assert law["spread"]["max_contact_force_N"] == {"min": 10.0, "min_variant": "a", "max": 14.0, "max_variant": "b",
                                                    "spread": 4.0, "sample_spread": 8.0, "relative": 0.5}
    apart = {**ok, "clearance_m": 1e-4, "max_wear_depth_m": 0.0, "max_eccentricity_m": 1.0}
    law = settle([{"label": "e", "changes": {}, "skipped": ""}], ["E"], {"E": apart}, ["max_contact_force_N"], {})
    assert law["variants"][0]["status"] == "invalid" and law["failed"] == 1
    assert "into the bushing wall" in law["failures"][0]["error"]


def test_the_nominal_point_is_the_middle_of_each_range():
    problem = Problem("simulate", (Parameter("a", "a", 2.0, 5.0), Parameter("b", "b", 1e-3, 1e1, log=True)))
    assert nominal_point(problem) == pytest.approx({"a": 3.5, "b": 0.1}, rel=1e-12)


# ------------------------------------------------------------------ slow
@pytest.mark.slow
def test_study_on_a_running_scheduler_with_two_workers(tmp_path):
    """--scheduler: the runs go to a cluster the study did not start (here one started by this test)."""
    import dask
    from distributed import LocalCluster

    scratch = str(tmp_path / "dask")             # the cluster's scratch space and lock files, not TMPDIR's
    with dask.config.set({"temporary-directory": scratch}), LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
            local_directory=scratch) as cluster:
        out = tmp_path / "out"
        done = wearjoint("sensitivity", "simulate", *TINY, *PARAMS, "--samples", "3", "--scheduler",
                         cluster.scheduler_address, "--out", str(out), "--quiet")
        assert done.returncode == 0, done.stderr
        workers = {r["worker"] for r in read_csv(out / "sweep.csv")}
        assert len(workers) == 2 and json.loads((out / "summary.json").read_text())["workers"] == 2


DOC = Path(__file__).resolve().parents[2] / "docs" / "explanation" / "sensitivity.md"


@pytest.mark.slow
def test_the_docs_study_ranks_the_dominant_parameters_alike_in_morris_and_sobol(tmp_path):
    """The doc's two commands, as printed (~20 min on 2 cores): the two parameters with the largest effect on
    the wear depth agree, and the control (the driven crank's inertia) comes last with no effect in both."""
    text = DOC.read_text().replace("\\\n", " ")          # shell continuation lines joined
    commands = re.findall(r"^(wearjoint sensitivity wear-study .*?--method (morris|sobol).*?)$", text, flags=re.M)
    assert sorted(m for _, m in commands) == ["morris", "sobol"]
    tables = {}
    for line, method in commands:
        argv = line.split()[1:]
        argv[argv.index("--out") + 1] = str(tmp_path / method)
        done = wearjoint(*argv, "--quiet", timeout=3600)
        assert done.returncode in (0, 1), done.stderr        # 1: some runs' pin left the bushing (the doc says)
        summary = json.loads((tmp_path / method / "summary.json").read_text())
        # the runs that fail are those whose pin left the bushing: stopped as diverged (docs/reference/model.md §7)
        assert all("diverged" in f["error"] or "into the bushing wall" in f["error"] for f in summary["failures"])
        tables[method] = indices(tmp_path / method)
    top = {m: {r["parameter"] for r in t["max_wear_depth_m"][:2]} for m, t in tables.items()}
    assert top["morris"] == top["sobol"]
    for method, table in tables.items():
        for rows in table.values():
            assert rows[-1]["parameter"] == DUMMY and float(rows[-1]["ST" if method == "sobol" else "mu_star"]) == 0.0


def test_an_interval_of_an_index_that_cannot_be_negative_stops_at_zero():
    """μ* (a mean of absolute changes) and Sobol's shares of a variance: a new user's indices.csv said mu_star_low
    -7.87e-08; μ, a signed mean, keeps its symmetric interval."""
    from wearjoint.sensitivity.report import interval

    assert interval({"mu_star": 3.8e-8, "mu_star_conf": 1.2e-7}, "mu_star") == (0.0, pytest.approx(1.58e-7))
    assert interval({"S1": -0.02, "S1_conf": 0.05}, "S1") == (0.0, pytest.approx(0.03))
    assert interval({"ST": 0.5, "ST_conf": 0.1}, "ST") == (pytest.approx(0.4), pytest.approx(0.6))
    assert interval({"mu": -1.0, "mu_conf": 0.5}, "mu") == (-1.5, -0.5)
    assert interval({"S1": 0.9, "S1_conf": 0.83}, "S1") == (pytest.approx(0.07), 1.0)     # a share of the variance
    assert interval({"mu_star": 0.9, "mu_star_conf": 0.83}, "mu_star")[1] == pytest.approx(1.73)   # not a share

