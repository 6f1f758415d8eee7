"""`wearjoint calibrate` (wearjoint/studies/calibration.py): k_w from measured max depths on a study's master curve,
checked on master curves whose answers are known in closed form."""
import json
import math
import re

import numpy as np
import pytest

from wearjoint.cli import main as cli_main
from wearjoint.parameters import ParameterError
from wearjoint.studies.wear_study_plots import EXPERIMENT_MAX_DEPTH_M, EXPERIMENT_REVOLUTIONS
from wearjoint.studies.calibration import (
    falling_depths, fit_archard, fit_mild_severe, life, master_curve_check, predicted_depth, predictions,
)

K0 = 5e-11


def power_growth(rate=1.5e-7, exponent=0.9, reach=4000):
    """A study's growth rows at k0: d = rate * N^exponent [m] (revolutions, max depth, volume)."""
    n = np.linspace(10.0, reach, 400)
    return np.column_stack([n, rate * n ** exponent, np.zeros_like(n)])


def written_study(folder, wear_factor=1.0):
    """A finished wear study's files in ``folder`` as calibrate reads them: the growth of :func:`power_growth` at
    k_w = K0 (its revolutions the crank's, as a study writes them at any wear factor)."""
    folder.mkdir()
    np.savetxt(folder / "wear_growth.csv", power_growth(), delimiter=",",
               header="revolutions,max_wear_depth_m,worn_volume_m3", comments="")
    (folder / "summary.json").write_text(json.dumps({"parameters": {"joint": {"wear_coefficient_m2_N": K0,
                                                                               "wear_factor": wear_factor}}}))
    return folder


def test_one_k_w_is_recovered_with_zero_residuals_when_the_points_lie_on_the_curve():
    growth = power_growth()
    k_true = 2e-13                                   # N k / k0 within the study's 4000 revolutions
    points = [(n, 1.5e-7 * (n * k_true / K0) ** 0.9) for n in (200_000, 400_000, 800_000)]
    fit = fit_archard(growth, K0, points)
    assert fit["wear_coefficient_m2_N"] == pytest.approx(k_true, rel=1e-3)
    assert max(abs(r) for r in fit["residuals_rel"]) < 2e-3 and fit["fits"]
    assert fit["interval_95_m2_N"] is None and fit["consistent"] is None   # no uncertainty given: k_w alone
    assert fit["local_growth_exponents"] == pytest.approx([0.9] * 3, abs=0.01)
    certain = fit_archard(growth, K0, [(n, d, 1e-6) for n, d in points])
    lo, hi = certain["interval_95_m2_N"]
    assert lo < k_true < hi and hi / lo < 1.05 and certain["consistent"]       # 1 um on ~0.1 mm: narrow


def test_points_one_k_w_cannot_join_within_their_uncertainty_are_inconsistent_and_get_no_interval():
    """The experiment's shape: 2.9 x the depth for 2 x the revolutions, on a curve growing as N^0.9: with a 10 um
    depth error the one-k_w model is rejected (chi^2 far above its 1 degree of freedom)."""
    points = [(200_000, 0.19e-3, 1e-5), (400_000, 0.55e-3, 1e-5)]
    fit = fit_archard(power_growth(rate=4e-7), K0, points, tolerance=0.1)
    assert not fit["fits"] and fit["consistent"] is False and fit["p_value"] < 0.05 and fit["chi2"] > 50
    assert fit["interval_95_m2_N"] is None and "does not fit" in fit["note"]
    low, high = sorted(fit["residuals_rel"])
    assert low < 0.0 < high and high - low > 0.2    # one over, one under
    single = fit_archard(power_growth(rate=4e-7), K0, [(400_000, 0.55e-3, 1e-5)])
    # one point: nothing to test (it said consistent: true), its own interval, from its uncertainty alone
    assert single["degrees_of_freedom"] == 0 and single["p_value"] is None and single["consistent"] is None
    assert single["fits"] is None and "no test of the model" in single["note"]
    lo, hi = single["interval_95_m2_N"]
    assert lo < single["wear_coefficient_m2_N"] < hi


def test_the_interval_covers_the_truth_and_shrinks_with_the_measurement_uncertainty():
    """Synthetic measurements from the study's own curve at a known k_w with Gaussian depth errors U: the 95 %
    interval covers the truth in at least 90 of 100 draws, is about ten times narrower for U / 10, and the
    model is rejected at 5 % about as often as it should be."""
    growth = power_growth()
    k_true, revolutions = 2e-13, np.array([100_000.0, 300_000.0, 700_000.0])
    depths = 1.5e-7 * (revolutions * k_true / K0) ** 0.9
    rng = np.random.default_rng(11)
    widths, covered, rejected = {}, 0, 0
    for u in (5e-6, 5e-7):
        spans = []
        for _ in range(100):
            drawn = depths + u * rng.standard_normal(3)
            fit = fit_archard(growth, K0, [(n, d, u) for n, d in zip(revolutions, drawn)])
            rejected += not fit["consistent"]
            if fit["interval_95_m2_N"] is None:
                continue
            lo, hi = fit["interval_95_m2_N"]
            spans.append(math.log(hi / lo))
            covered += u == 5e-6 and lo <= k_true <= hi
        widths[u] = float(np.median(spans))
    assert covered >= 90
    assert 5.0 < widths[5e-6] / widths[5e-7] < 20.0
    assert rejected <= 25                           # of 200 fits: 5 % expected (10)


def test_the_curves_own_error_is_common_to_every_point_so_many_points_do_not_average_it_away():
    """Depths drawn from the study's curve times (1 + eps), eps ~ N(0, c) common to all points (the study's error
    of its curve, c = curve_error_rel), plus small Gaussian measurement errors: the 95 % interval covers the truth
    in about 95 % of draws with 12 points (had each point carried its own curve error, it would shrink as
    1/sqrt(12) and cover about half); with exact points 2 % deep the interval's log-width is the curve error's,
    2 x 1.96 c / 0.9 on a curve growing as N^0.9, and covers the truth."""
    growth, c, u = power_growth(), 0.02, 2e-7
    k_true, revolutions = 2e-13, np.linspace(60_000.0, 800_000.0, 12)
    depths = 1.5e-7 * (revolutions * k_true / K0) ** 0.9
    rng = np.random.default_rng(5)
    covered, rejected = 0, 0
    for _ in range(200):
        drawn = depths * (1.0 + c * rng.standard_normal()) + u * rng.standard_normal(revolutions.size)
        interval = fit_archard(growth, K0, [(n, d, u) for n, d in zip(revolutions, drawn)],
                               curve_error_rel=c)["interval_95_m2_N"]
        rejected += interval is None                   # the model's test at 5 %: no interval
        covered += interval is not None and interval[0] <= k_true <= interval[1]
    assert rejected <= 20 and 0.9 <= covered / (200 - rejected) <= 0.99     # 0.95 expected; binomial sd 0.016
    offset = fit_archard(growth, K0, [(n, 1.02 * d, 1e-9) for n, d in zip(revolutions, depths)], curve_error_rel=c)
    lo, hi = offset["interval_95_m2_N"]
    assert lo < k_true < hi and offset["consistent"]
    assert math.log(hi / lo) == pytest.approx(math.log((1 + 1.96 * c) / (1 - 1.96 * c)) / 0.9, rel=0.02)


def test_calibrate_on_a_wear_factor_study_fits_the_same_k_w_and_says_its_bias_is_not_in_the_interval(tmp_path,
                                                                                                      capsys):
    """A study at wear factor F writes its growth in crank revolutions: the same curve gives the same k_w at F 1
    and 100 (it was F times too large); the factor's study has no error estimate, which a note says."""
    fits = []
    for factor in (1.0, 100.0):
        study = written_study(tmp_path / f"study{factor:g}", wear_factor=factor)
        assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5,300000:1.1e-4",
                         "--depth-uncertainty-m", "2e-6", "--no-plots"]) == 0
        fits.append(json.loads((study / "calibration.json").read_text()))
    assert fits[0]["wear_coefficient_m2_N"] == fits[1]["wear_coefficient_m2_N"]
    assert fits[0]["interval_95_m2_N"] == fits[1]["interval_95_m2_N"]
    assert "curve_error_note" not in fits[0]
    assert fits[1]["curve_error_note"].startswith("the study ran at --wear-factor 100, whose curve's error is not")
    assert f"note: {fits[1]['curve_error_note']}" in capsys.readouterr().out


def test_predictions_and_the_life_to_a_depth_carry_the_band_and_say_when_the_study_is_too_short():
    growth = power_growth()
    k_true = 2e-13
    points = [(n, 1.5e-7 * (n * k_true / K0) ** 0.9, 2e-6) for n in (100_000, 300_000)]
    fit = fit_archard(growth, K0, points)
    (near, far) = predictions(growth, K0, fit, [500_000, 2_000_000])
    assert near["depth_m"] == pytest.approx(1.5e-7 * (500_000 * k_true / K0) ** 0.9, rel=0.01)
    assert near["band_95_m"][0] < near["depth_m"] < near["band_95_m"][1]
    assert far["depth_m"] is None and far["study_revolutions_needed"] > 4000     # 2e6 x 2e-13 / 5e-11 = 8000
    span = life(growth, K0, fit, 1.0e-4)
    expected = (1.0e-4 / 1.5e-7) ** (1 / 0.9) * K0 / k_true
    assert span["revolutions"] == pytest.approx(expected, rel=0.01)
    assert span["band_95_revolutions"][0] < span["revolutions"] < span["band_95_revolutions"][1]
    assert life(growth, K0, fit, 1.0)["revolutions"] is None
    hours = life(growth, K0, fit, 1.0e-4, crank_speed_rpm=600.0)      # a life in hours of running at 600 rpm
    assert hours["hours"] == pytest.approx(span["revolutions"] / 36_000.0, rel=1e-12)
    assert hours["band_95_hours"] == pytest.approx([n / 36_000.0 for n in span["band_95_revolutions"]], rel=1e-12)
    assert span["hours"] is None and span["band_95_hours"] is None      # no speed given


def test_mild_severe_recovers_its_two_coefficients_from_two_points():
    n = np.linspace(1.0, 8000.0, 400)
    growth = np.column_stack([n, n * 1.5e-7, np.zeros(400)])   # linear master curve: d = 1.5e-7 N k / k0
    k_mild, k_severe, transition = 1e-13, 3e-13, 0.2e-3
    n_t = transition / 1.5e-7 * K0 / k_mild
    points = [(n_t, transition), (2 * n_t, transition + 1.5e-7 * n_t * k_severe / K0)]
    fit = fit_mild_severe(growth, K0, points, transition)
    assert fit["mild_wear_coefficient_m2_N"] == pytest.approx(k_mild, rel=1e-4)
    assert fit["severe_wear_coefficient_m2_N"] == pytest.approx(k_severe, rel=1e-4)
    assert fit["degrees_of_freedom"] == 0 and fit["transition_revolutions"] == pytest.approx(n_t, rel=1e-4)
    assert predicted_depth(growth, K0, np.array([n_t / 2]), fit)[0] == pytest.approx(transition / 2, rel=1e-4)


def test_depths_that_fall_as_the_revolutions_grow_are_flagged_beyond_their_uncertainty(tmp_path, capsys):
    """A max depth cannot fall as a bushing wears: 0.06 mm at 60 000 revolutions, then 0.03 mm at 150 000 were fitted
    in silence (a 'not a fit' verdict, exit 0)."""
    assert "falls from 6e-05 m at 60000 revolutions to 3e-05 m at 150000" in falling_depths(
        [(150_000, 0.03e-3, 5e-6), (60_000, 0.06e-3, 5e-6)])
    assert falling_depths([(60_000, 0.06e-3, 5e-6), (150_000, 0.05e-3, 5e-6)]) == ""   # within 2 x hypot(U1, U2)
    assert falling_depths([(60_000, 0.06e-3), (150_000, 0.0599e-3)]) != ""           # none given: any fall
    assert falling_depths([(60_000, 0.03e-3), (150_000, 0.06e-3)]) == ""
    study = written_study(tmp_path / "study")
    assert cli_main(["calibrate", "--study", str(study), "--points", "150000:0.03e-3,60000:0.06e-3",
                     "--depth-uncertainty-m", "5e-6", "--out", str(tmp_path / "c"), "--no-plots"]) == 0
    assert "calibrate: warning: the measured max depth falls" in capsys.readouterr().err
    assert "falls" in json.loads((tmp_path / "c" / "calibration.json").read_text())["warning"]


def test_mild_severe_refuses_points_that_never_pass_the_transition():
    """Points at or above the transition depth only measure k_mild: the fit returned its start guess as k_severe
    (equal to k_mild, residuals 0) as if it had been measured."""
    n = np.linspace(1.0, 8000.0, 400)
    growth = np.column_stack([n, n * 1.5e-7, np.zeros(400)])
    transition = 0.2e-3
    n_t = transition / 1.5e-7 * K0 / 1e-13
    points = [(0.5 * n_t, 0.5 * transition), (n_t, transition)]
    with pytest.raises(ParameterError, match=r"needs a point deeper than the transition depth, 0.0002 m "
                                             r"\(the deepest is 0.0002 m\)"):
        fit_mild_severe(growth, K0, points, transition)


@pytest.mark.parametrize("points, message", [
    ([(200_000, 0.0)], "are invalid"),
    ([(-1.0, 1e-4)], "are invalid"),
    ([(200_000, 5e-3)], "beyond the study's max depth"),
])
def test_bad_points_are_refused(points, message):
    with pytest.raises(ParameterError, match=message):
        fit_archard(power_growth(), K0, points)


def test_the_papers_experiment_is_the_default_points_only_on_a_study_of_the_papers_case(tmp_path, capsys):
    """A study of another machine fitted the paper's experiment when --points was left out (and wrote over its
    calibration.json): it needs the machine's own points; a study whose summary carries the experiment (the paper's
    mechanism and joint: wear_study.py) fits it by default."""
    study = tmp_path / "study"
    study.mkdir()
    np.savetxt(study / "wear_growth.csv", power_growth(rate=4e-7), delimiter=",",      # to 0.7 mm: past 0.55 mm
               header="revolutions,max_wear_depth_m,worn_volume_m3", comments="")
    summary = {"parameters": {"joint": {"wear_coefficient_m2_N": K0, "wear_factor": 1.0}}}
    (study / "summary.json").write_text(json.dumps(summary))
    assert cli_main(["calibrate", "--study", str(study), "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--points is required with --study" in err and "not a study of the paper's" in err
    assert not (study / "calibration.json").exists()
    summary["experiment"] = {"revolutions": [200000, 400000], "max_wear_depth_m": [1.9e-4, 5.5e-4]}
    (study / "summary.json").write_text(json.dumps(summary))
    assert cli_main(["calibrate", "--study", str(study), "--no-plots"]) == 0
    fitted = json.loads((study / "calibration.json").read_text())["points"]
    assert [(p["revolutions"], p["max_wear_depth_m"]) for p in fitted] == [(200000, 1.9e-4), (400000, 5.5e-4)]
    assert list(EXPERIMENT_REVOLUTIONS) == [200000, 400000] and list(EXPERIMENT_MAX_DEPTH_M) == [1.9e-4, 5.5e-4]


@pytest.mark.parametrize("tolerance, verdict", [("0.5", "a fit"), ("0.1", "not a fit")])
def test_calibrate_prints_whether_the_residuals_are_within_the_tolerance(tmp_path, capsys, tolerance, verdict):
    """Two depths growing 3x where the study's curve grows 2^0.9 = 1.87x: one k_w misses each by about 24 %."""
    study = written_study(tmp_path / "study")
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000:1e-5,2000:3e-5", "--tolerance", tolerance,
                     "--no-plots", "--out", str(tmp_path / "c")]) == 0
    residuals = next(line for line in capsys.readouterr().out.splitlines() if "residuals" in line)
    assert residuals.endswith(f"--tolerance {tolerance} of its depth, {verdict}"), residuals
    fit = json.loads((tmp_path / "c" / "calibration.json").read_text())
    assert fit["fits"] == (verdict == "a fit") and 0.2 < max(abs(r) for r in fit["residuals_rel"]) < 0.3
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000:1e-5", "--no-plots", "--out",
                     str(tmp_path / "c")]) == 0      # a second fit into the same folder says it replaces the first
    assert f"replacing the fit in {tmp_path / 'c' / 'calibration.json'}" in capsys.readouterr().out


def test_with_depth_uncertainties_the_test_says_whether_it_fits_not_a_share_of_the_depth(tmp_path, capsys):
    """A press designer's two points, 12 and 35 um +- 3 um: chi^2 0.24, p 0.62, "consistent", and then "+11.3 %:
    beyond --tolerance 0.1, not a fit" (the share ignored the uncertainties, here 25 % of 12 um).  The verdict is
    the test's, and --tolerance with uncertainties is refused."""
    study = written_study(tmp_path / "study")
    uncertain = ["--points", "1000:1e-5,2000:2.3e-5", "--depth-uncertainty-m", "3e-6", "--no-plots"]
    assert cli_main(["calibrate", "--study", str(study), *uncertain, "--out", str(tmp_path / "c")]) == 0
    residuals = next(line for line in capsys.readouterr().out.splitlines() if "residuals" in line)
    fit = json.loads((tmp_path / "c" / "calibration.json").read_text())
    assert fit["consistent"] and max(abs(r) for r in fit["residuals_rel"]) > 0.1   # beyond the old 10 % share
    assert fit["fits"] and fit["tolerance_rel"] is None
    assert residuals.endswith("within their uncertainties (the chi^2 test), a fit"), residuals
    assert cli_main(["calibrate", "--study", str(study), *uncertain, "--tolerance", "0.1",
                     "--out", str(tmp_path / "d")]) == 2
    assert "--tolerance=0.1 is invalid: allowed only without depth uncertainties" in capsys.readouterr().err
    assert not (tmp_path / "d").exists()


def test_calibrate_command_writes_its_json_and_figure_and_refuses_a_folder_without_a_study(tmp_path, capsys):
    study = written_study(tmp_path / "study")
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000:1e-4", "--out", str(tmp_path / "c")]) == 0
    result = json.loads((tmp_path / "c" / "calibration.json").read_text())
    assert result["wear_coefficient_m2_N"] == pytest.approx(K0 * (1e-4 / 1.5e-7) ** (1 / 0.9) / 1000, rel=2e-3)
    assert (tmp_path / "c" / "calibration.png").read_bytes()[:4] == b"\x89PNG"
    assert cli_main(["calibrate", "--study", str(study), "--points", "2000:1.2e-4", "--out", str(tmp_path / "c"),
                     "--no-plots"]) == 0
    assert not (tmp_path / "c" / "calibration.png").exists()      # the earlier fit's figure goes with it
    capsys.readouterr()
    assert cli_main(["calibrate", "--study", str(tmp_path / "nothing")]) == 2
    err = capsys.readouterr().err
    assert "not a finished wear study" in err and err.count("\n") == 1
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000-1e-4"]) == 2
    assert "REVOLUTIONS:MAX_DEPTH_M" in capsys.readouterr().err
    (study / "summary.json").write_text(json.dumps({"parameters": {}}))        # a summary without the joint
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000:1e-4"]) == 2
    err = capsys.readouterr().err
    assert "not a finished wear study" in err and err.count("\n") == 1
    assert math.isfinite(result["study_wear_coefficient_m2_N"])


def test_calibrate_command_predicts_with_bands_and_asks_for_a_stated_transition(tmp_path, capsys):
    study = written_study(tmp_path / "study")
    out = tmp_path / "c"
    assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5,300000:1.1e-4:3e-6",
                     "--depth-uncertainty-m", "2e-6", "--predict-revolutions", "500000,5000000",
                     "--life-depth-m", "1e-4", "--out", str(out), "--no-plots"]) == 0
    result = json.loads((out / "calibration.json").read_text())
    assert [p["uncertainty_m"] for p in result["points"]] == [2e-6, 3e-6]        # a point's own value first
    assert result["consistent"] in (True, False) and len(result["interval_95_m2_N"] or [0, 0]) == 2
    near, far = result["predictions"]
    assert near["depth_m"] > 1.1e-4 and far["depth_m"] is None and far["study_revolutions_needed"] > 4000
    assert result["life"]["revolutions"] < 300000
    text = capsys.readouterr().out
    assert "run the study to" in text and "95 % band" in text
    summary = json.loads((study / "summary.json").read_text())          # a study finished by a --resume:
    summary["command_line"] = "wearjoint wear-study --revolutions 4000 --out study --resume"     # advice anew
    (study / "summary.json").write_text(json.dumps(summary))
    assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5", "--predict-revolutions",
                     "5000000", "--out", str(tmp_path / "d"), "--no-plots"]) == 0
    advice = [line for line in capsys.readouterr().out.splitlines() if "run the study to" in line]
    # a resumed study's line may lack its options: the command that made it, with what to change
    assert advice and re.search(r"run the study to (\d+) revolutions \(the fitted k_w's 95 % interval included\): "
                                r"the command that made the study with --revolutions \1 and --out NEW_FOLDER$",
                                advice[0]), advice
    summary["command_line"] = "wearjoint wear-study --revolutions 4000 --crank-speed-rpm 150 --out study"
    (study / "summary.json").write_text(json.dumps(summary))
    assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5", "--predict-revolutions",
                     "5000000", "--out", str(tmp_path / "d"), "--no-plots"]) == 0
    advice = [line for line in capsys.readouterr().out.splitlines() if "run the study to" in line]
    assert re.search(r"run the study to (\d+) revolutions .*: wearjoint wear-study --crank-speed-rpm 150 "
                     r"--revolutions \1 --out NEW_FOLDER$", advice[0]), advice
    assert cli_main(["calibrate", "--study", str(study), "--law", "mild-severe", "--points",
                     "100000:4e-5,300000:1.1e-4", "--out", str(out)]) == 2
    assert "transition_depth_m is missing" in capsys.readouterr().err


def test_a_figure_without_a_band_says_why(tmp_path, capsys):
    """A rejected fit's life said "1.305e+06 revolutions (no band), 181.2 h" as though it were an answer; one point
    said "within their uncertainties (the chi^2 test), a fit", a test that one point cannot make."""
    study = written_study(tmp_path / "study")
    rejected = ["--points", "100000:2e-5,300000:1.5e-4", "--depth-uncertainty-m", "2e-6"]
    assert cli_main(["calibrate", "--study", str(study), *rejected, "--life-depth-m", "1e-4", "--out",
                     str(tmp_path / "r"), "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "not a fit" in text and "revolutions (no band: one k_w does not fit these points (the chi^2 test): the " \
                                   "figure holds only if it did)" in text, text
    assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5", "--life-depth-m", "1e-4",
                     "--out", str(tmp_path / "u"), "--no-plots"]) == 0
    assert "(no band: no interval without the depths' uncertainty (--depth-uncertainty-m))" in capsys.readouterr().out
    assert cli_main(["calibrate", "--study", str(study), "--points", "100000:4.1e-5:2e-6", "--out",
                     str(tmp_path / "one"), "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "chi^2 test" not in text and "no test of the model" in text, text


def test_a_fit_far_from_the_studys_k_w_says_to_run_the_study_at_it():
    """Depth is a function of k_w N alone only within the range that was checked (1/300 to 300 times the study's
    k_w): a fit outside it says so and what to run."""
    assert master_curve_check(K0, {"wear_coefficient_m2_N": K0 / 10})["within"]
    far = master_curve_check(K0, {"wear_coefficient_m2_N": K0 / 1000})
    assert not far["within"] and far["rescaled_by"] == pytest.approx(1e-3) and "run the study" in far["note"]


def test_a_calibration_folder_carries_its_k_w_into_a_run_and_names_itself_as_the_source(tmp_path, capsys):
    folder = tmp_path / "cal"
    folder.mkdir()
    (folder / "calibration.json").write_text(json.dumps({"law": "archard", "wear_coefficient_m2_N": 3.5e-13}))
    out = tmp_path / "run"
    assert cli_main(["simulate", "--revolutions", "0.02", "--calibration", str(folder), "--quiet", "--no-plots",
                     "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["joint"]["wear_coefficient_m2_N"] == 3.5e-13
    assert summary["wear_coefficient_source"] == f"calibration {folder}"
    printed = capsys.readouterr().out         # the console says what the file says (it printed "given")
    assert re.search(rf"^  wear_coefficient_source +calibration {re.escape(str(folder))}$", printed, re.M), printed
    assert cli_main(["simulate", "--revolutions", "0.02", "--calibration", str(folder), "--wear-coefficient-m2-N",
                     "1e-13", "--out", str(tmp_path / "x")]) == 2
    (folder / "calibration.json").write_text(json.dumps({"law": "mild-severe", "mild_wear_coefficient_m2_N": 1e-13}))
    assert cli_main(["simulate", "--revolutions", "0.02", "--calibration", str(folder), "--out",
                     str(tmp_path / "y")]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert errors[-2].endswith("--calibration='" + str(folder) + "' is invalid: allowed only without "
                               "--wear-coefficient-m2-N (one k_w)")
    assert "mild-severe fit" in errors[-1] and not (tmp_path / "y").exists()
    # wear-study --calibrate-max-depth-m writes a calibration.json too: a k_w to reach a depth, not a fit
    (folder / "calibration.json").write_text(json.dumps({"target_max_depth_m": 5.8e-4,
                                                         "effective_wear_coefficient_m2_N": 5.63e-11}))
    assert cli_main(["simulate", "--revolutions", "0.02", "--calibration", str(folder), "--out",
                     str(tmp_path / "z")]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "a wear study's calibration to a depth" in error[0], error
    assert "--wear-coefficient-m2-N 5.63e-11" in error[0] and "mild-severe" not in error[0]


def test_a_calibration_made_on_another_machine_says_what_differs(tmp_path, capsys):
    """k_w absorbs the load, speed and materials of the study it was fitted on: a run of another machine from
    ``--calibration`` gets a note naming what differs (summary.json, the console); the same machine none."""
    from wearjoint.parameters import SliderCrankParameters, paper_joint

    study, folder = tmp_path / "study", tmp_path / "cal"
    study.mkdir()
    folder.mkdir()
    mechanism = SliderCrankParameters(crank_speed_rpm=300.0)
    parameters = {"joint": paper_joint(mechanism).to_dict(), "mechanism": mechanism.to_dict()}
    (study / "summary.json").write_text(json.dumps({"parameters": parameters}))
    (folder / "calibration.json").write_text(json.dumps({"law": "archard", "wear_coefficient_m2_N": 3.5e-13,
                                                         "study": str(study)}))
    notes = []
    for name, extra in (("other", []), ("same", ["--crank-speed-rpm", "300", "--initial-crank-angle-deg", "40"])):
        assert cli_main(["simulate", "--revolutions", "0.01", "--calibration", str(folder), "--no-plots",
                         "--out", str(tmp_path / name), *extra]) == 0
        notes.append(json.loads((tmp_path / name / "summary.json").read_text())["wear_coefficient_note"])
    assert notes[0] == (f"k_w was fitted on the wear study {study}, of another machine (its crank_speed_rpm differs): "
                        "its load, speed and materials set what k_w absorbs; calibrate on a study of this one")
    assert notes[1] is None                  # the start angle is a seed, not another machine
    assert f"note: {notes[0]}" in capsys.readouterr().err


def test_a_load_table_is_the_same_load_from_any_path(tmp_path):
    """A new user's study read its load table as /abs/gas.csv; the same file as gas.csv, or a copy, was "another
    machine (its slider_force_table differs)": the table's rows are the load, not the file's name."""
    from wearjoint.mechanism_parameters import SliderForceTable
    from wearjoint.parameters import SliderCrankParameters, paper_joint
    from wearjoint.run_options import calibration_note

    rows = "crank_angle_deg,force_N\n0,100\n180,900\n360,100\n"
    (tmp_path / "a.csv").write_text(rows)
    (tmp_path / "b.csv").write_text(rows)
    (tmp_path / "c.csv").write_text(rows.replace("900", "950"))

    def machine(csv):
        return SliderCrankParameters(slider_force_table=SliderForceTable.from_csv(csv))

    study, folder = tmp_path / "study", tmp_path / "cal"
    study.mkdir()
    folder.mkdir()
    fitted = machine(tmp_path / "a.csv")
    (study / "summary.json").write_text(json.dumps({"parameters": {"joint": paper_joint(fitted).to_dict(),
                                                                   "mechanism": fitted.to_dict()}}))
    (folder / "calibration.json").write_text(json.dumps({"study": str(study)}))
    assert machine(tmp_path / "b.csv") == fitted
    assert calibration_note(folder, paper_joint(fitted), machine(tmp_path / "b.csv")) is None
    other = machine(tmp_path / "c.csv")
    assert "its slider_force_table differs" in calibration_note(folder, paper_joint(other), other)


def test_build_fmu_takes_the_calibrated_k_w_as_the_fmus_start_value_and_names_its_source(tmp_path):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    folder = tmp_path / "cal"
    folder.mkdir()
    (folder / "calibration.json").write_text(json.dumps({"law": "archard", "wear_coefficient_m2_N": 3.5e-13}))
    assert cli_main(["build-fmu", "--calibration", str(folder), "--platforms", "linux64", "--out",
                     str(tmp_path / "fmu")]) == 0
    fmu = tmp_path / "fmu" / "ClearanceWearJoint.fmu"
    md = read_model_description(str(fmu))
    assert [float(v.start) for v in md.modelVariables if v.name == "wear_coefficient"] == [3.5e-13]
    assert f"calibration {folder}" in md.description and validate_fmu(str(fmu)) == []     # it names its source
    assert cli_main(["build-fmu", "--model", "slider-crank", "--calibration", str(folder), "--out",
                     str(tmp_path / "sc")]) == 2


def test_a_run_on_a_calibration_carries_its_interval_and_says_when_the_fit_was_rejected(tmp_path, capsys):
    """--calibration DIR: summary.json holds the fit's 95 % interval; a fit its test rejected (chi^2 27.4 on 1
    degree of freedom) is still the k_w asked for, with a note saying so (it had none)."""
    notes = {}
    for name, fit in (("kept", {"consistent": True, "interval_95_m2_N": [3.2e-13, 3.9e-13]}),
                      ("rejected", {"consistent": False, "chi2": 27.4, "p_value": 1.6e-7, "interval_95_m2_N": None})):
        folder = tmp_path / f"cal_{name}"
        folder.mkdir()
        (folder / "calibration.json").write_text(json.dumps({"law": "archard", "wear_coefficient_m2_N": 3.5e-13,
                                                             **fit}))
        assert cli_main(["simulate", "--revolutions", "0.01", "--calibration", str(folder), "--no-plots", "--quiet",
                         "--out", str(tmp_path / name)]) == 0
        summary = json.loads((tmp_path / name / "summary.json").read_text())
        assert summary["parameters"]["joint"]["wear_coefficient_m2_N"] == 3.5e-13
        assert summary["wear_coefficient_interval_95_m2_N"] == fit["interval_95_m2_N"]
        notes[name] = summary["wear_coefficient_note"]
    assert notes["kept"] is None
    assert notes["rejected"] == (f"the fit in {tmp_path / 'cal_rejected'} was rejected by its test (chi^2 27.4, p "
                                 "1.6e-07): one k_w does not fit its points within their uncertainties, and it has no "
                                 "interval")
    assert f"note: {notes['rejected']}" in capsys.readouterr().err
