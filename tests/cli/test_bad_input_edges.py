"""Bad input at the edges a fuzz review found (validate, wear-study --calibrate-max-depth-m, calibrate, export-ssp,
contact-law): one line naming the option as written, its value and the allowed range (exit status 2), nothing run or
written; where the values are admissible but the comparison they ask for is empty (a wear run before the first
contact), the metrics say so instead of a traceback."""
import json

import pytest

from wearjoint.cli import main

FLAGS = ("--no-plots", "--quiet")


def refused(capsys, *argv) -> str:
    """The one error line of ``wearjoint ARGV``, which must exit with status 2 without a traceback."""
    assert main(list(argv)) == 2
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if "error:" in line]
    assert "Traceback" not in err and len(lines) == 1, err
    return lines[0]


# ----------------------------------------------------------------------------- validate
VALIDATE = ("validate", "--engines", "monolithic,cosim", "--ensemble", "2", "--no-law-spread", "--quiet")


@pytest.mark.parametrize("options, message", [
    # a TypeError traceback (1e-6) and a refusal naming --revolutions (1e300)
    (["--revolutions", "0.1", "--wear-revolutions", "1e-6"],
     "--wear-revolutions=1e-6 (wear_revolutions) is invalid: allowed >= 2.5e-05 (one sample interval"),
    (["--revolutions", "0.1", "--wear-revolutions", "1e-300"], "--wear-revolutions=1e-300 (wear_revolutions) is invalid"),
    (["--revolutions", "0.1", "--wear-revolutions", "1e300"],
     "--wear-revolutions=1e300 (wear_revolutions) is invalid: allowed <= "),
    # a ValueError (zero-size array) and an IndexError: a window holding none of the co-simulation's own points
    (["--revolutions", "0.1", "--wear-revolutions", "0.05", "--window", "1e-6"],
     "--window=1e-6 (window_s) is invalid: allowed >= 0.0005 s (5 of the co-simulation's free-flight steps"),
    (["--revolutions", "0.1", "--wear-revolutions", "0.05", "--window", "1e-300"], "--window=1e-300 (window_s) is "
                                                                                  "invalid: allowed >= 0.0005 s"),
    # refused naming window_s, which the user did not write
    (["--revolutions", "1e-300"], "--revolutions=1e-300 (revolutions) is invalid: allowed >= 0.0375 (the no-wear runs "
                                  "cover the point-wise window, window_s = 0.015 s"),
    (["--revolutions", "0.1", "--window", "0.05"], "--window=0.05 (window_s) is invalid: allowed <= the no-wear run"),
])
def test_validate_bounds_its_spans_naming_the_option_written(tmp_path, capsys, options, message):
    out = tmp_path / "v"
    assert message in refused(capsys, *VALIDATE, "--out", str(out), *options)
    assert not out.exists()


def test_a_wear_run_that_wears_nothing_leaves_its_profile_metrics_undefined(tmp_path, capsys):
    """1 ms of wear ends before the first contact: no profile to compare (a TypeError printing a NaN difference)."""
    out = tmp_path / "v"
    assert main([*VALIDATE, "--revolutions", "0.1", "--wear-revolutions", "1e-3", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    summary = json.loads((out / "summary.json").read_text(), parse_constant=lambda c: pytest.fail(f"{c} in JSON"))
    assert sorted(summary["metrics_undefined"]) == sorted(f"cosim: {name}" for name in (
        "max_wear_depth_m", "worn_volume_m3", "lobe_angle_near_0_deg", "lobe_angle_near_180_deg",
        "profile_decorrelation"))
    assert "5 undefined" in captured.out and "wore nothing" in (out / "report.md").read_text()


# ----------------------------------------------------------------------------- wear-study --calibrate-max-depth-m
@pytest.mark.parametrize("depth, message", [
    ("1e-300", "--calibrate-max-depth-m=1e-300 (target_max_depth_m) is invalid: allowed a depth of at least 1e-09 m"),
    ("1e-10", "--calibrate-max-depth-m=1e-10 (target_max_depth_m) is invalid: allowed a depth of at least 1e-09 m"),
    ("1e300", "--calibrate-max-depth-m=1e300 (target_max_depth_m) is invalid: allowed a depth below the bushing "
              "radius"),
])
def test_the_calibration_target_depth_is_bounded(tmp_path, capsys, depth, message):
    """1e-300 died in a ZeroDivisionError, 1e300 was refused naming step_s, an option nobody wrote."""
    out = tmp_path / "w"
    assert message in refused(capsys, "wear-study", "--calibrate-max-depth-m", depth, "--revolutions", "2", "--out",
                              str(out), *FLAGS)
    assert not out.exists()


def test_the_calibration_refuses_a_target_beyond_the_bushing_radius_or_its_reach(tmp_path):
    from wearjoint.checks import ParameterError
    from wearjoint.parameters import SliderCrankParameters, paper_joint
    from wearjoint.studies.wear_calibration import calibrate_wear_coefficient
    from wearjoint.studies.wear_study import WearStudyConfig

    config = WearStudyConfig(joint=paper_joint(), mechanism=SliderCrankParameters(), revolutions=1, snapshots=(1,))
    with pytest.raises(ParameterError, match=r"target_max_depth_m=0.02 is invalid: allowed a depth below the bushing "
                                             r"radius 0.0101 m"):
        calibrate_wear_coefficient(config, 0.02, tmp_path / "radius", progress=False)
    # the largest k_w the joint admits (1e-6 m^2/N) wears 2.5 mm in one revolution: 10 mm is out of its reach
    with pytest.raises(ParameterError, match=r"target_max_depth_m=0.01 is invalid: allowed a depth the study reaches "
                                             r"with k_w at most 1e-06 m2/N: .* m after 1 revolution \("):
        calibrate_wear_coefficient(config, 0.01, tmp_path / "reach", progress=False)


# ----------------------------------------------------------------------------- calibrate
@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """A finished four-revolution wear study (max depth ~15 um)."""
    folder = tmp_path_factory.mktemp("study") / "S"
    assert main(["wear-study", "--revolutions", "4", "--snapshots", "2,4", "--out", str(folder), *FLAGS]) == 0
    return folder


POINTS = ("--points", "2:9e-6,4:1.4e-5")


@pytest.mark.parametrize("options, message", [
    # chi^2 NaN (1e-300), an overflow and an interval of nothing called consistent (1e300)
    ([*POINTS, "--depth-uncertainty-m", "1e-300"], "--depth-uncertainty-m=1e-300 is invalid: allowed from 1e-12 m "
                                                   "(finer than any depth measurement) to 0.0101 m (the bushing radius"),
    ([*POINTS, "--depth-uncertainty-m", "1e300"], "--depth-uncertainty-m=1e300 is invalid: allowed from 1e-12 m"),
    (["--points", "2:9e-6:1e-300,4:1.4e-5:1e-6"], "--points='2:9e-6:1e-300,4:1.4e-5:1e-6' (points) is invalid: "
                                                  "allowed depth uncertainties from 1e-12 m"),
    # "fits": true with k_w 1e-309 and 5e-305
    (["--points", "1e300:1e-5"], "--points='1e300:1e-5' (points) is invalid: allowed revolutions up to 1e+12"),
    (["--points", "2:1e-300"], "--points='2:1e-300' (points) is invalid: allowed revolutions up to 1e+12 (beyond any "
                               "machine's life) and max depths from 1e-09 m"),
    # every residual within 1e300 of its depth: anything fits
    ([*POINTS, "--tolerance", "1e300"], "--tolerance=1e300 (tolerance) is invalid: allowed a share of each measured depth below 1"),
    ([*POINTS, "--predict-revolutions", "1e300"], "--predict-revolutions='1e300' is invalid: allowed N1,N2,... "
                                                  "revolutions up to 1e+12"),
    ([*POINTS, "--life-depth-m", "1e-300"], "--life-depth-m=1e-300 is invalid: allowed a max depth of at least 1e-09 m"),
    # deeper than the bushing (wear-study refused it, calibrate advised a longer study)
    ([*POINTS, "--life-depth-m", "0.1"], "--life-depth-m=0.1 is invalid: allowed a max depth of at least 1e-09 m (a "
                                         "few atomic layers: the least wear Archard's law describes) below the bushing "
                                         "radius 0.0101 m (worn through there)"),
])
def test_calibrate_bounds_its_values_naming_the_option(study, tmp_path, capsys, options, message):
    out = tmp_path / "c"
    assert message in refused(capsys, "calibrate", "--study", str(study), "--no-plots", "--out", str(out), *options)
    assert not (out / "calibration.json").exists()


def test_calibrate_takes_the_ends_of_its_ranges(study, tmp_path, capsys):
    for k, uncertainty in enumerate(("1e-12", "0.0101")):
        out = tmp_path / str(k)
        assert main(["calibrate", "--study", str(study), *POINTS, "--depth-uncertainty-m", uncertainty, "--no-plots",
                     "--out", str(out)]) == 0
        fit = json.loads((out / "calibration.json").read_text(), parse_constant=lambda c: pytest.fail(c))
        assert fit["chi2"] is not None and fit["p_value"] is not None
        assert fit["consistent"] == (uncertainty == "0.0101")
    assert "Warning" not in capsys.readouterr().err


# ----------------------------------------------------------------------------- export-ssp
@pytest.mark.parametrize("options, message", [
    (["--step", "1e-300"], "--step=1e-300 (step_s) is invalid: allowed >= 1e-09 s"),
    (["--container-fmu", "--container-step", "1e-300"], "--container-step=1e-300 (container_step_s) is invalid: "
                                                        "allowed >= 1e-09 s"),
    (["--container-fmu", "--container-step", "1e300"], "--container-step=1e300 (container_step_s) is invalid: "
                                                       "allowed <= the package's stop time 0.4 s"),
    (["--container-step", "1e-4"], "--container-step=1e-4 (container_step_s) is invalid with wear"),
    (["--stop-time", "1e300"], "--stop-time=1e300 (stop_time) is invalid: allowed at most 1e+06 s"),
    # refused naming step_s, which the user did not write
    (["--stop-time", "1e-300"], "--stop-time=1e-300 (stop_time) is invalid: allowed >= the package's communication "
                                "step 5e-06 s"),
])
def test_export_ssp_bounds_its_times_naming_the_option(tmp_path, capsys, options, message):
    out = tmp_path / "ssp"
    assert message in refused(capsys, "export-ssp", "--platforms", "linux64", "--out", str(out), *options)
    assert not out.exists()


# ----------------------------------------------------------------------------- contact-law
@pytest.mark.parametrize("options, option", [
    (["--crank-speed-rpm", "300"], "--crank-speed-rpm=300"),
    (["--crank-length-m", "0.06"], "--crank-length-m=0.06"),
    (["--crank-mass-kg", "5"], "--crank-mass-kg=5"),                  # not in the crank-rod joint's mass
    (["--slider-mass-kg", "5", "--effective-mass-kg", "2"], "--slider-mass-kg=5"),     # the mass is given
])
def test_contact_law_refuses_a_mechanism_option_it_would_ignore(tmp_path, capsys, options, option):
    """--crank-speed-rpm and the others left contact_law.csv byte for byte the same."""
    out = tmp_path / "law"
    line = refused(capsys, "contact-law", "--out", str(out), *FLAGS, *options)
    assert f"{option} is invalid: allowed only with a command that runs the mechanism" in line
    assert not out.exists()


@pytest.mark.parametrize("options, option", [
    (["--pin-radius-m", "0.009"], "--pin-radius-m=0.009"),
    (["--wear-factor", "10"], "--wear-factor=10"),
    (["--friction-coefficient", "0.3"], "--friction-coefficient=0.3"),
    (["--bushing-youngs-modulus-Pa", "1e11"], "--bushing-youngs-modulus-Pa=1e11"),
])
def test_contact_law_refuses_a_joint_option_it_would_ignore(tmp_path, capsys, options, option):
    """A single impact's restitution reads the damping law's options alone: the radii, materials, friction and wear
    left contact_law.csv byte for byte the same."""
    out = tmp_path / "law"
    line = refused(capsys, "contact-law", "--out", str(out), *FLAGS, *options)
    assert f"{option} is invalid: allowed only with a command that runs the joint" in line
    assert not out.exists()


@pytest.mark.parametrize("options", [["--impact-velocity-floor-m-s", "0.01", "--contact-damping", "lankarani-nikravesh"],
                                     ["--contact-model", "deepest", "--contact-exponent", "1.2",
                                      "--contact-stiffness-N-m1-5", "1e10"]])
def test_contact_law_takes_the_joint_options_its_laws_read(tmp_path, options):
    out = tmp_path / "law"
    assert main(["contact-law", "--out", str(out), *FLAGS, *options]) == 0 and (out / "contact_law.csv").exists()


def test_contact_law_takes_the_masses_of_tsujis_effective_mass(tmp_path):
    out = tmp_path / "law"
    assert main(["contact-law", "--out", str(out), *FLAGS, "--slider-mass-kg", "5", "--rod-mass-kg", "1"]) == 0
    assert json.loads((out / "contact_law.json").read_text())["effective_mass_kg"] == pytest.approx(6.0)


def test_a_pin_radius_in_millimetres_runs_with_a_note_saying_the_lengths_are_in_metres(tmp_path, capsys):
    """Every range check passes 10 for a 10 mm pin (a 10 m pin): the run says so on stderr and in summary.json."""
    out = tmp_path / "mm"
    assert main(["simulate", "--pin-radius-m", "10", "--bushing-radius-m", "10.1", "--revolutions", "0.01",
                 "--no-plots", "--out", str(out)]) == 0
    note = json.loads((out / "summary.json").read_text())["joint_size_note"]
    assert note.startswith("pin_radius_m=10 is longer than the mechanism's crank and rod")
    assert f"note: {note}" in capsys.readouterr().err
