"""`wearjoint validate` (validation/compare.py): the quick cross-check passes and writes its
files, exudyn's own contact judged without wear; a genuinely different model in one engine makes
it fail; the comparison rules (ensemble means against the valid configurations' and the standard
error)."""
import json
from dataclasses import replace
import subprocess
import sys

import numpy as np
import pytest

from wearjoint import SliderCrankParameters, against_ideal, paper_joint
from wearjoint.mechanism_parameters import SliderForceTable
from wearjoint.contact_laws import contact_law_variants
from wearjoint.core import layout as L
from wearjoint.slider_crank import SliderCrank
from wearjoint.validation.report import run_validation
from wearjoint.results import RunParameters, RunRecord, new_revolution_stats

pytest.importorskip("wearjoint.validation.exudyn_model")
cmp = pytest.importorskip("wearjoint.validation.compare")
law_spread = pytest.importorskip("wearjoint.validation.law_spread")
run_monolithic = cmp.run_monolithic

PNG = b"\x89PNG\r\n\x1a\n"


def wearjoint(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def _available_engines():
    """The reference and every engine whose module imports (the FMU co-simulation may be absent)."""
    engines = []
    for engine in cmp.ENGINES:
        try:
            if engine != cmp.REFERENCE:
                cmp.engine_runner(engine, paper_joint(), "pythonfmu")
            engines.append(engine)
        except ImportError:
            pass
    return engines


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("validate")
    engines = _available_engines()
    done = wearjoint("validate", "--quick", "--out", str(out), "--engines", ",".join(engines),
                     "--fmu-backend", "pythonfmu")
    return out, engines, done


def test_quick_validation_passes_and_writes_report_summary_and_figures(quick):
    out, engines, done = quick
    assert done.returncode == 0, done.stdout + done.stderr[-3000:]
    assert "validate: [1/" in done.stderr                                   # progress lines
    summary = json.loads((out / "summary.json").read_text())
    assert summary["passed"] and summary["complete"] and summary["exit_status"] == 0
    assert summary["metrics_failed"] == [] and summary["gaps"] == []
    others = set(engines) - {cmp.REFERENCE}
    by_group = {}
    for m in summary["metrics"]:
        by_group.setdefault(m["group"], []).append(m)
        assert m["passed"] and abs(m["difference"]) <= m["tolerance"]
        assert m["scatter"] >= 0.0 and m["tolerance"] > 0.0 and m["scatter_values"]
    assert {m["engine"] for m in by_group[cmp.GROUP_STATISTICS]} == others
    assert {m["name"] for m in by_group[cmp.GROUP_STATISTICS]} == set(cmp.STATISTICS)
    assert {m["engine"] for m in by_group[cmp.GROUP_POINTWISE]} == others
    assert {m["name"] for m in by_group[cmp.GROUP_POINTWISE]} == set(cmp.POINTWISE)
    assert {m["engine"] for m in by_group[cmp.GROUP_PROFILE]} == others & set(cmp.WEAR_ENGINES)
    assert "exudyn-native" in others and "exudyn-native" not in cmp.WEAR_ENGINES
    assert summary["unworn_engines"] == ["exudyn-native"]
    for m in by_group[cmp.GROUP_STATISTICS]:                             # every valid configuration, and the SE
        assert set(m["scatter_values"]) == set(summary["scatter_run_statistics"]) | {cmp.STANDARD_ERROR}
    assert set(summary["ensemble_std"]) == {cmp.REFERENCE, *summary["scatter_run_statistics"], *others}
    law = summary["law_differences"]["exudyn-native"]                    # traces against its own law's reference
    assert summary["law_references"] == {"exudyn-native": {"contact_model": "deepest", "contact_damping":
                                                           "lankarani-nikravesh-exact", "impact_velocity_floor_m_s": 0.05}}
    assert law["engine"]["eccentricity_max_difference_m"] > 0.0 and law["law"]["eccentricity_max_difference_m"] > 0.0
    native = {m["name"]: m for m in by_group[cmp.GROUP_STATISTICS] if m["engine"] == "exudyn-native"}
    for name, value in summary["law_statistics"]["exudyn-native"].items():   # statistics against its law's ensemble
        assert native[name]["reference"] == pytest.approx(value, nan_ok=True)
    assert {"max_wear_depth_m", "worn_volume_m3", "profile_decorrelation"} <= {
        m["name"] for m in by_group[cmp.GROUP_PROFILE]}
    for m in by_group[cmp.GROUP_POINTWISE]:
        if m["name"] == "eccentricity_max_difference_m":
            assert m["difference"] < 0.02 * 1e-4                            # < 2 % of the clearance: same trajectory
    assert summary["reference_profile"]["max_wear_depth_m"] > 0.0
    rows = {r["run"]: r for r in summary["runs"]}
    n_monolithic = 1 + len(cmp.RK4_STEP_FACTORS) + len(cmp.DOPRI_RTOLS)
    ensemble = summary["plan"]["ensemble"]
    assert ensemble == cmp.QUICK.ensemble >= 2
    assert len(rows) == (ensemble * (n_monolithic + len(others) + len(cmp.LAW_REFERENCES)) + 2 + 2 * len(others)
                         + 2 * len(cmp.LAW_REFERENCES)          # statistics ensembles, windows, the law's ensemble
                         + ensemble * (1 + len(cmp.WEAR_CONFIGURATIONS) + len(others & set(cmp.WEAR_ENGINES))))
    assert all(r["wall_time_s"] > 0 and r["realtime_factor"] > 0 for r in rows.values())
    report = (out / "report.md").read_text()
    verdicts = summary["engines"]
    assert {e: v["role"] for e, v in verdicts.items()} == {**{e: "joint" for e in others - {"exudyn-native"}},
                                                          "exudyn-native": "reference law"}
    passing_engines = sum(v["verdict"] == "pass" for v in verdicts.values())     # the verdict table's rows
    assert "**PASS**" in report and report.count("| pass |") == len(summary["metrics"]) + passing_engines
    assert "exudyn-native: no wear run" in report and "contact_model=deepest" in report
    for name in ("slider_acceleration.png", "pin_orbits.png", "first_impacts.png", "statistics.png",
                 "worn_profiles.png"):
        assert name in summary["figures"] and (out / name).read_bytes()[:8] == PNG


def test_quick_validation_reports_the_contact_law_spread_beside_the_sampling_spread(quick):
    """One value per variant of contact_law_variants, spread = max - min of them, the sampling spread from validate's
    valid monolithic runs; the default law's variant is validate's own DOPRI configuration (the same runs). The
    law moves the answers far more than the sampling does and the run still passes: the stage is not judged."""
    out, _, done = quick
    summary = json.loads((out / "summary.json").read_text())
    spread = summary["law_spread"]
    mechanism = SliderCrankParameters()
    variants = contact_law_variants(mechanism)
    assert spread["variants"] == [label for label, _ in variants]
    assert spread["joint_changes"] == [changes for _, changes in variants]
    assert set(spread["answers"]) == set(law_spread.ANSWERS) and spread["judged"] is False and spread["errors"] == []
    assert spread["runs"] == len(variants) * (summary["plan"]["ensemble"] + 1)      # ensembles and one wear run each
    for name, answer in spread["answers"].items():
        values = answer["values"]
        assert len(values) == len(variants) and all(np.isfinite(v) for v in values), name
        assert answer["spread"] == pytest.approx(max(values) - min(values))
        assert answer["sampling_spread"] > 0.0 and answer["ratio"] == pytest.approx(answer["spread"]
                                                                                   / answer["sampling_spread"])
    joint = paper_joint(mechanism)
    default = next(k for k, (_, changes) in enumerate(variants)
                   if all(getattr(joint, n) == v for n, v in changes.items()))
    dopri = summary["scatter_run_statistics"]["DOPRI rtol 1e-06"]
    for name in ("contact_fraction", "impacts_per_revolution", "max_contact_force_N"):
        assert spread["answers"][name]["values"][default] == dopri[name]
    assert spread["answers"]["contact_fraction"]["ratio"] > 2.0            # 12.7 measured
    assert summary["exit_status"] == 0 and summary["plan"]["law_spread"] is True
    report = (out / "report.md").read_text()
    section = report[report.index("## Model-form spread (contact law)"):report.index("## Runs")]
    assert all(f"| {label} |" in section for label in spread["variants"])
    assert "| **spread** (max − min) |" in section and "| sampling spread |" in section and "| ratio |" in section
    assert "validate: law spread [1/" in done.stderr and "LAW SPREAD contact_fraction:" in done.stdout


def _monolithic_quick(tmp_path, name, *extra):
    """validate --quick --no-wear with the monolithic engine alone (the command needs another engine to compare:
    the plan as the command builds it, through the API)."""
    out = tmp_path / name
    plan = replace(cmp.QUICK, engines=("monolithic",), run_wear=False, law_spread="--no-law-spread" not in extra)
    summary = run_validation(plan, out, paper_joint(), SliderCrankParameters(), {}, progress=False)
    return summary["exit_status"], json.loads((out / "summary.json").read_text()), (out / "report.md").read_text()


def test_law_spread_never_changes_the_exit_status_and_can_be_switched_off(tmp_path, monkeypatch):
    """A variant that raises is listed in the stage's errors (its values None), not in validate's; the verdict and
    exit status are those of the same run with --no-law-spread, which has no law_spread at all."""
    status_off, off, report_off = _monolithic_quick(tmp_path, "off", "--no-law-spread")
    assert "law_spread" not in off and off["plan"]["law_spread"] is False
    assert "Model-form spread" not in report_off

    def tsuji_fails(joint, *args, **kwargs):
        if joint.contact_damping == "tsuji":
            raise RuntimeError("tsuji broke")
        return run_monolithic(joint, *args, **kwargs)

    monkeypatch.setattr(law_spread, "run_monolithic", tsuji_fails)
    status_on, on, report_on = _monolithic_quick(tmp_path, "on")
    assert status_on == status_off == on["exit_status"] == off["exit_status"] == 0
    assert on["errors"] == [] and on["passed"] == off["passed"] and on["metrics"] == off["metrics"]
    spread = on["law_spread"]
    failed = [k for k, label in enumerate(spread["variants"]) if label.startswith("tsuji")]
    assert len(spread["errors"]) == len(failed) == 2 and "tsuji broke" in spread["errors"][0]
    assert "max_wear_depth_m" not in spread["answers"] and spread["wear_run"] is None      # --no-wear
    values = spread["answers"]["contact_fraction"]["values"]
    assert [values[k] for k in failed] == [None, None]
    finite = [v for v in values if v is not None]
    assert spread["answers"]["contact_fraction"]["spread"] == pytest.approx(max(finite) - min(finite))
    assert "- error: tsuji" in report_on


@pytest.mark.parametrize("failure, raised", [("", KeyboardInterrupt), ("diverged at 0.01 s", cmp.RunStoppedShort)])
def test_a_run_that_stopped_short_is_never_judged(tmp_path, monkeypatch, failure, raised):
    """A run ended before its revolutions (Ctrl-C: completed without a failure; a divergence: with one) has
    truncated statistics: the validation stops (the command: 130, or 1 naming the run) instead of judging them."""
    calls = []

    def second_stops(joint, *args, **kwargs):
        record = run_monolithic(joint, *args, **kwargs)
        calls.append(record)
        return replace(record, completed=False, failure=failure) if len(calls) == 2 else record

    monkeypatch.setattr(cmp, "run_monolithic", second_stops)
    with pytest.raises(raised):
        _monolithic_quick(tmp_path, "stopped", "--no-law-spread")
    assert len(calls) == 2 and not (tmp_path / "stopped" / "summary.json").exists()


@pytest.mark.parametrize("name", ["slider_acc_max_m_s2", "slider_acc_min_m_s2", "max_contact_force_N"])
def test_a_statistic_whose_reference_is_zero_is_not_failed_by_round_off(name):
    """A slider at rest (its max acceleration exactly 0 in every run, 7.8e-8 m/s² apart by round-off) or a joint
    without contact: the rule's absolute floor, not 5 % of 0, bounds the tolerance."""
    rule = cmp.STATISTICS[name][1]
    assert rule.tolerance(3.5e-10, 0.0) >= 1.0 and rule.tolerance(1.0, 1000.0) == 50.0


def test_slider_acceleration_error_counts_the_counted_revolutions_against_the_ideal_joint():
    """|a - a_ideal| over the revolutions covering more than half the longest: a sliver after the end is not
    counted; the ideal joint's own acceleration gives 0."""
    mechanism = SliderCrankParameters()
    period = mechanism.period_s
    t = np.arange(0.0, 1.02 * period, 1e-4)
    samples = np.zeros((t.size, L.N_SAMPLE_COLUMNS))
    samples[:, L.T_TIME] = t
    samples[:, L.T_SLIDER_A] = SliderCrank(mechanism).closed_form(t)["slider_a_m_s2"]
    samples[t < 0.5 * period, L.T_SLIDER_A] += 30.0
    samples[t > 1.005 * period, L.T_SLIDER_A] += 500.0              # in the sliver row: ignored
    record = _record([{L.S_TIME: period}, {L.S_TIME: 0.02 * period}], samples, period=period)
    assert against_ideal.slider_acc_error_max(record) == pytest.approx(30.0)
    samples[:, L.T_SLIDER_A] = SliderCrank(mechanism).closed_form(t)["slider_a_m_s2"]
    assert against_ideal.slider_acc_error_max(record) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.slow   # the default run keeps test_own_mechanism.py's perturbed engine
def test_validation_fails_when_one_engine_has_a_different_restitution(tmp_path):
    """exudyn with e_r = 0.5 instead of 0.9: the rebound of the first impact (3 ms) differs,
    so the point-wise traces must fail, and the command must exit 1."""
    done = wearjoint("validate", "--quick", "--no-wear", "--out", str(tmp_path), "--quiet",
                     "--engines", "monolithic,exudyn-discrete", "--perturb", "exudyn-discrete", "restitution=0.5")
    assert done.returncode == 1, done.stdout + done.stderr[-3000:]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert not summary["passed"] and summary["engine_joint_changes"] == {"exudyn-discrete": {"restitution": 0.5}}
    failed = {m["name"] for m in summary["metrics"] if not m["passed"]}
    assert "eccentricity_max_difference_m" in failed
    assert "FAIL" in done.stdout and "**FAIL**" in (tmp_path / "report.md").read_text()


@pytest.mark.parametrize("args,name", [
    (["--engines", "monolithic,adams"], "engines"),
    (["--engines", "exudyn-discrete"], "engines"),
    (["--perturb", "exudyn-discrete", "stiffness=1"], "perturb"),
    (["--perturb", "monolithic", "restitution=0.5"], "perturbed engine"),
    (["--revolutions", "0.01"], "window_s"),
    (["--ensemble", "1"], "ensemble"),
])
def test_bad_options_exit_2_with_a_message(tmp_path, args, name):
    done = wearjoint("validate", "--quick", "--out", str(tmp_path / "v"), "--quiet", *args)
    assert done.returncode == 2 and name in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "v" / "summary.json").exists()


# ---------------------------------------------------------------- the comparison rules
def _record(stats_rows, samples=None, period=0.4):
    stats = new_revolution_stats(len(stats_rows))
    for k, row in enumerate(stats_rows):
        for column, value in row.items():
            stats[k, column] = value
    samples = np.zeros((0, L.N_SAMPLE_COLUMNS)) if samples is None else samples
    return RunRecord(samples=samples, revolution_stats=stats, wear_growth_m=np.zeros(0), phi_deg=np.zeros(4),
                     wear_depth_m=np.zeros(4), worn_volume_m3=0.0, simulated_time_s=0.8, wall_time_s=1.0,
                     revolutions=2.0, period_s=period, clearance_m=1e-4,
                     parameters=RunParameters("test", paper_joint(), SliderCrankParameters()))


def test_revolution_statistics_average_over_revolutions():
    samples = np.zeros((4, L.N_SAMPLE_COLUMNS))
    samples[:, L.T_CONTACT] = [1.0, 0.0, 1.0, 1.0]
    samples[:, L.T_ECC_X] = [3e-5, 9e-5, 0.0, 4e-5]
    samples[:, L.T_ECC_Y] = [4e-5, 0.0, 1e-4, 3e-5]
    rows = [{L.S_IMPACTS: 100, L.S_CONTACT_TIME: 0.2, L.S_TIME: 0.4, L.S_ACC_MAX: 600.0, L.S_ACC_MIN: -1000.0,
             L.S_FORCE_MAX: 900.0, L.S_ECC_MAX: 1.05e-4},
            {L.S_IMPACTS: 140, L.S_CONTACT_TIME: 0.28, L.S_TIME: 0.4, L.S_ACC_MAX: 800.0, L.S_ACC_MIN: -1200.0,
             L.S_FORCE_MAX: 1100.0, L.S_ECC_MAX: 1.07e-4},
            {L.S_IMPACTS: 1, L.S_TIME: 1e-6, L.S_ACC_MAX: 5000.0}]        # a sliver after the end: ignored
    stats = cmp.revolution_statistics(_record(rows, samples))
    assert stats["impacts_per_revolution"] == pytest.approx(120.0)
    assert stats["contact_fraction"] == pytest.approx(0.6)
    assert stats["slider_acc_max_m_s2"] == pytest.approx(700.0)
    assert stats["slider_acc_min_m_s2"] == pytest.approx(-1100.0)
    assert stats["max_contact_force_N"] == pytest.approx(1000.0)
    assert stats["max_eccentricity_m"] == pytest.approx(1.06e-4)
    assert stats["mean_eccentricity_in_contact_m"] == pytest.approx((5e-5 + 1e-4 + 5e-5) / 3)


def test_statistics_are_judged_by_ensemble_means():
    """Means of the starts: the engine's difference from the reference's mean against the largest
    difference of a valid configuration's mean, or the standard error of the difference if larger."""
    def ensemble(*impacts):
        return [_record([{L.S_IMPACTS: i, L.S_TIME: 0.4}]) for i in impacts]

    plan = cmp.ValidationPlan(ensemble=2)
    runs = cmp.Runs(ensemble(100, 110), {"RK4 2 us": ensemble(104, 108)},
                    {"close": ensemble(108, 112), "far": ensemble(120, 130)}, {})
    metrics = {m.engine: m for m in cmp.compare(runs, plan) if m.name == "impacts_per_revolution"}
    standard_error = np.sqrt(50.0 / 2 + 50.0 / 2)        # sample variances 50 (1/rev)^2, two starts each
    assert metrics["far"].value == 125.0 and metrics["far"].reference == 105.0 and metrics["far"].difference == 20.0
    assert metrics["far"].scatter_values == pytest.approx({"RK4 2 us": 1.0, cmp.STANDARD_ERROR: standard_error})
    assert metrics["far"].tolerance == pytest.approx(2.0 * standard_error) and not metrics["far"].passed
    assert metrics["close"].scatter == pytest.approx(np.sqrt(8.0 / 2 + 50.0 / 2)) and metrics["close"].passed


def test_tolerance_is_k_times_scatter_or_the_floor():
    rule = cmp.Rule(k=2.0, floor=1.0, floor_relative=0.05)
    assert rule.tolerance(3.0, 10.0) == 6.0           # k * scatter
    assert rule.tolerance(0.1, 10.0) == 1.0           # absolute floor
    assert rule.tolerance(0.1, -100.0) == 5.0         # relative floor
    metric = cmp._judge("g", "x", "N", rule, "e", 107.0, 100.0, 7.0, {"a": 1.0, "b": 3.0})
    assert metric.scatter == 3.0 and metric.tolerance == 6.0 and not metric.passed
    assert cmp._judge("g", "x", "N", rule, "e", 95.0, 100.0, -5.0, {"a": 3.0}).passed


def test_an_impact_count_is_not_failed_below_one_onset_in_the_span():
    """A new user's `validate --quick` (0.1 revolution, two starts 1e-6 deg apart: scatter 0) failed on 13 against 14
    onsets, 130 against 140 per revolution, with the tolerance 5 % of 130: one onset is the count's resolution."""
    rule = cmp.STATISTICS["impacts_per_revolution"][1]
    assert rule.tolerance(0.0, 130.0, span_revolutions=0.1) == pytest.approx(10.0)      # one onset in 0.1 rev
    assert rule.tolerance(0.0, 130.0, span_revolutions=5.0) == pytest.approx(6.5)       # 5 %: finer than an onset
    assert cmp._judge("g", "impacts_per_revolution", "1/rev", rule, "e", 140.0, 130.0, 10.0, {"a": 0.0},
                      span_revolutions=0.1).passed
    assert not cmp._judge("g", "impacts_per_revolution", "1/rev", rule, "e", 150.0, 130.0, 20.0, {"a": 0.0},
                          span_revolutions=0.1).passed
    assert cmp.STATISTICS["contact_fraction"][1].tolerance(0.0, 0.2, span_revolutions=0.1) == 0.02   # not a count


def test_pointwise_differences_and_profile_quantities():
    t = np.arange(0.0, 0.02, 1e-5)
    ref = np.zeros((t.size, L.N_SAMPLE_COLUMNS))
    ref[:, L.T_TIME] = t
    other = ref.copy()
    other[:, L.T_ECC_X] = np.where(t < 0.01, 3e-7, 1e-3)             # 1 mm off only after the window
    other[:, L.T_ECC_Y] = -4e-7
    other[:, L.T_NORMAL_FORCE] = np.where(np.abs(t - 0.005) < 1e-6, 50.0, 0.0)
    d = cmp.pointwise_differences(_record([{}], other), _record([{}], ref), 0.01 - 1e-9)
    assert d["eccentricity_max_difference_m"] == pytest.approx(5e-7)
    assert d["normal_force_max_difference_N"] == pytest.approx(50.0)
    assert d["slider_acc_max_difference_m_s2"] == 0.0
    record = _record([{}])
    record.phi_deg = np.arange(0.0, 360.0, 1.0)
    record.wear_depth_m = np.zeros(360)
    record.wear_depth_m[[350, 10, 185]] = [2e-6, 1e-6, 3e-6]
    q = cmp.profile_quantities(record)
    assert q["max_wear_depth_m"] == 3e-6
    # depth-weighted mean direction of 2 um at -10 deg and 1 um at +10 deg: tan = -tan(10 deg) / 3
    assert q["lobe_angle_near_0_deg"] == pytest.approx(np.degrees(np.arctan(-np.tan(np.radians(10.0)) / 3.0)))
    assert q["lobe_angle_near_180_deg"] == pytest.approx(185.0)
    record.wear_depth_m[[350, 10]] = 0.0
    assert cmp.profile_quantities(record)["lobe_angle_near_0_deg"] is None      # no wear in that half
    deeper = _record([{}])
    deeper.phi_deg, deeper.wear_depth_m = record.phi_deg, 3.0 * record.wear_depth_m      # 9 um at 185 deg
    mean, std, h = cmp.ensemble_profile([record, deeper])                  # a wear ensemble: per-run means, mean h
    assert mean["max_wear_depth_m"] == pytest.approx(6e-6) and std["max_wear_depth_m"] == pytest.approx(np.sqrt(18) * 1e-6)
    assert mean["lobe_angle_near_180_deg"] == pytest.approx(185.0) and std["lobe_angle_near_180_deg"] == 0.0
    assert mean["lobe_angle_near_0_deg"] is None and std["lobe_angle_near_0_deg"] is None   # a run without that lobe
    assert h[185] == pytest.approx(6e-6) and h[0] == 0.0


def test_a_reference_law_is_reported_per_engine_and_never_fails_the_run():
    """exudyn's own contact law outside its tolerance: listed under its engine as differing, not in the failed
    metrics, exit status 0; the same metric of an engine running the project's joint fails the run."""
    from types import SimpleNamespace

    from wearjoint.validation import report

    def metric(engine, passed):
        return cmp.Metric(cmp.GROUP_POINTWISE, "normal_force_max_difference_N", "N", engine, 10.0, 0.0, 10.0, 1.0,
                          2.0, passed)

    ran = SimpleNamespace(errors=[], gaps=[])
    metrics = [metric("cosim", True), metric("exudyn-native", False)]
    assert report._status(metrics, ran) == 0
    verdicts = report.engine_verdicts(metrics)
    assert verdicts["exudyn-native"] == {"role": "reference law", "metrics": 1, "within_tolerance": 0,
                                         "failed": ["normal_force_max_difference_N"], "verdict": "differs"}
    assert verdicts["cosim"]["verdict"] == "pass"
    assert report._status([metric("cosim", False), metric("exudyn-native", True)], ran) == 1
    assert report.engine_verdicts([metric("exudyn-discrete", False)])["exudyn-discrete"]["verdict"] == "fail"


def test_the_report_states_the_machine_and_what_its_verdicts_cannot_say():
    """A press's quick validate covered crank angles 360 to 324 deg, where its table is 0 N, and its two starts did not
    spread: report.md named neither the load, nor gravity, nor the joint, and said the scatter was measured."""
    from validation.report import _machine_lines

    press = SliderCrankParameters(crank_speed_rpm=100.0, gravity_m_s2=(0.0, -9.81), clearance_joint="rod-slider",
                                  slider_force_table=SliderForceTable((0.0, 3.0, 20.0, 30.0, 360.0),
                                                                      (0.0, 4000.0, 4000.0, 0.0, 0.0), source="press.csv"))
    plan = {"revolutions": 0.1, "ensemble": 2}
    lines = _machine_lines(press.to_dict(), plan, {"impacts_per_revolution": 0.0})
    assert lines[0] == ("Machine: the clearance at the rod-slider joint, 100 rpm, gravity (0, -9.81) m/s², the slider's "
                        "load: press.csv (up to 4000 N).")
    assert any("never reach the load table's load" in line and "(0° back to 324°)" in line for line in lines)
    assert any("perturbed starts did not spread" in line for line in lines)
    # a run over the whole turn meets the load; a spread ensemble is a measured scatter
    whole = _machine_lines(press.to_dict(), {"revolutions": 1.0, "ensemble": 2}, {"impacts_per_revolution": 1.5})
    assert len(whole) == 2 and whole[0] == lines[0]
