"""`wearjoint calibrate` (wearjoint/studies/calibration.py): k_w from measured max depths on a study's master curve,
checked on master curves whose answers are known in closed form."""
import json
import math

import numpy as np
import pytest

from wearjoint.cli import main as cli_main
from wearjoint.parameters import ParameterError
from wearjoint.studies.calibration import fit_archard, fit_mild_severe, predicted_depth

K0 = 5e-11


def power_growth(rate=1.5e-7, exponent=0.9, reach=4000):
    """A study's growth rows at k0: d = rate * N^exponent [m] (revolutions, max depth, volume)."""
    n = np.linspace(10.0, reach, 400)
    return np.column_stack([n, rate * n ** exponent, np.zeros_like(n)])


def test_one_k_w_is_recovered_with_zero_residuals_when_the_points_lie_on_the_curve():
    growth = power_growth()
    k_true = 2e-13                                   # N k / k0 within the study's 4000 revolutions
    points = [(n, 1.5e-7 * (n * k_true / K0) ** 0.9) for n in (200_000, 400_000, 800_000)]
    fit = fit_archard(growth, K0, points)
    assert fit["wear_coefficient_m2_N"] == pytest.approx(k_true, rel=1e-3)
    assert max(abs(r) for r in fit["residuals_rel"]) < 2e-3 and fit["fits"]
    lo, hi = fit["interval_m2_N"]
    assert lo < k_true < hi and hi / lo < 1.05      # no scatter: a narrow interval
    assert fit["local_growth_exponents"] == pytest.approx([0.9] * 3, abs=0.01)


def test_points_a_power_law_cannot_join_are_reported_as_not_fitting_with_a_wide_interval():
    """The experiment's shape: 2.9 x the depth for 2 x the revolutions, on a curve growing as N^0.9."""
    fit = fit_archard(power_growth(rate=4e-7), K0, [(200_000, 0.19e-3), (400_000, 0.55e-3)], tolerance=0.1)
    assert not fit["fits"]
    low, high = sorted(fit["residuals_rel"])
    assert low < -0.1 and high > 0.1                # one over, one under
    assert fit["degrees_of_freedom"] == 1 and fit["interval_m2_N"][1] / fit["interval_m2_N"][0] > 100
    single = fit_archard(power_growth(rate=4e-7), K0, [(400_000, 0.55e-3)])
    assert single["interval_m2_N"] is None and single["degrees_of_freedom"] == 0


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


@pytest.mark.parametrize("points, message", [
    ([(200_000, 0.0)], "are invalid"),
    ([(-1.0, 1e-4)], "are invalid"),
    ([(200_000, 5e-3)], "beyond the study's max depth"),
])
def test_bad_points_are_refused(points, message):
    with pytest.raises(ParameterError, match=message):
        fit_archard(power_growth(), K0, points)


def test_calibrate_command_writes_its_json_and_figure_and_refuses_a_folder_without_a_study(tmp_path, capsys):
    study = tmp_path / "study"
    study.mkdir()
    growth = power_growth()
    np.savetxt(study / "wear_growth.csv", growth, delimiter=",", header="revolutions,max_wear_depth_m,worn_volume_m3",
               comments="")
    (study / "summary.json").write_text(json.dumps({"parameters": {"joint": {"wear_coefficient_m2_N": K0,
                                                                              "wear_factor": 1.0}}}))
    assert cli_main(["calibrate", "--study", str(study), "--points", "1000:1e-4", "--out", str(tmp_path / "c")]) == 0
    result = json.loads((tmp_path / "c" / "calibration.json").read_text())
    assert result["wear_coefficient_m2_N"] == pytest.approx(K0 * (1e-4 / 1.5e-7) ** (1 / 0.9) / 1000, rel=2e-3)
    assert (tmp_path / "c" / "calibration.png").read_bytes()[:4] == b"\x89PNG"
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
