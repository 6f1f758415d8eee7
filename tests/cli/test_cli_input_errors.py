"""Bad input to validate, cosim-study, calibrate, wear-study and report: one line naming the option as written, its
value and what is allowed (exit status 2), nothing run or written; a cosim-study whose co-simulation diverged says
which and exits 1."""
import json

import numpy as np
import pytest

from wearjoint.cli import main


def refused(capsys, *argv) -> str:
    """The stderr of ``wearjoint ARGV``, which must exit with status 2 with one error line and no traceback."""
    assert main(list(argv)) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len([line for line in err.splitlines() if "error:" in line]) == 1, err
    return err


# ----------------------------------------------------------------------------- validate
@pytest.mark.parametrize("options, message", [
    (["--window", "0"], "--window=0 (window_s) is invalid: allowed > 0"),
    (["--revolutions", "0"], "--revolutions=0 (revolutions) is invalid: allowed > 0"),
    (["--wear-revolutions", "0"], "--wear-revolutions=0 (wear_revolutions) is invalid: allowed > 0"),
    (["--engines", "monolithic"], "--engines='monolithic' is invalid: allowed a comma-separated list of distinct "
                                  "names from monolithic, cosim"),
    (["--engines", "monolithic,monolithic"], "--engines='monolithic,monolithic' is invalid: allowed"),
    (["--engines", "monolithic,cosim,cosim"], "--engines='monolithic,cosim,cosim' is invalid: allowed"),
    (["--perturb", "foo", "restitution=0.5"], "--perturb foo restitution=0.5 is invalid: allowed a perturbed engine "
                                              "(ENGINE) from --engines other than the reference monolithic: cosim"),
    (["--perturb", "cosim", "restitution=5"],
     "--perturb cosim restitution=5 is invalid: allowed restitution in [0.001, 1]"),
    (["--perturb", "cosim", "n_points=7.5"], "--perturb cosim n_points=7.5 is invalid: allowed n_points an integer"),
    (["--perturb", "cosim", "effective_mass_kg=50"],     # Hunt-Crossley never reads it: the validation could not fail
     "--perturb cosim effective_mass_kg=50 is invalid: allowed effective_mass_kg only with contact_damping tsuji"),
])
def test_validate_refuses_what_it_used_to_replace_or_run_as_nothing(tmp_path, capsys, options, message):
    """0 was silently the default, one engine compared nothing ("PASS: 0 of 0"), --perturb named an internal."""
    out = tmp_path / "v"
    assert message in refused(capsys, "validate", "--quick", "--out", str(out), *options)
    assert not out.exists()


# ----------------------------------------------------------------------------- cosim-study
@pytest.mark.parametrize("options, message", [
    (["--schemes", "foo"], "--schemes='foo' (scheme) is invalid: allowed one of zoh, extrapolation, adaptive"),
    (["--schemes", "zoh", "zoh"], "--schemes='zoh zoh' is invalid: allowed distinct names"),
    (["--fmu", "/nope.fmu"], "--fmu='/nope.fmu' (fmu_path) is invalid: allowed an existing FMU file"),
    (["--steps", "nan"], "--steps=nan (step_s) is invalid: allowed a finite real number"),
    (["--steps", "10"], "--steps=10.0 (step_s) is invalid with wear"),      # beyond the wear-step limit
])
def test_cosim_study_checks_its_options_before_any_run(tmp_path, capsys, options, message):
    out = tmp_path / "s"
    err = refused(capsys, "cosim-study", "--revolutions", "0.02", "--out", str(out), *options)
    assert message in err and "monolithic" not in err      # no reference run was started
    assert not out.exists()


def test_cosim_study_replot_refuses_a_missing_broken_or_foreign_json_and_copies_nothing(tmp_path, capsys):
    broken, foreign = tmp_path / "broken.json", tmp_path / "summary.json"
    broken.write_text('{"rows": [')
    foreign.write_text(json.dumps({"revolutions": 1.0, "parameters": {}}))      # another command's summary
    out = tmp_path / "s"
    for path, why in ((tmp_path / "missing.json", "FileNotFoundError"), (broken, "JSONDecodeError"),
                      (foreign, "KeyError")):
        line = refused(capsys, "cosim-study", "--replot", str(path), "--out", str(out))
        assert f"--replot='{path}' is invalid: allowed a cosim_study.json that cosim-study wrote ({why}" in line
        assert not (out / "cosim_study.json").exists()


def test_cosim_study_flags_a_diverged_co_simulation_and_exits_1(tmp_path, capsys, native_fmu):
    """A zero-order hold at 30 us diverges at 6 ms: its row says so, with no numbers (it was a table row of results
    with the pin 0.7 mm deep in a 0.1 mm clearance and 5e5 N)."""
    out = tmp_path / "s"
    assert main(["cosim-study", "--revolutions", "0.02", "--steps", "3e-5", "--schemes", "zoh", "--fmu",
                 str(native_fmu), "--out", str(out)]) == 1
    captured = capsys.readouterr()
    errors = [line for line in captured.err.splitlines() if "error:" in line]
    assert len(errors) == 1 and "1 of 1 co-simulations failed" in errors[0]
    assert "zoh 3e-05: the run diverged" in errors[0]
    row = json.loads((out / "cosim_study.json").read_text())["rows"][-1]
    assert row["run"] == "zoh 3e-05" and row["completed"] is False and "diverged" in row["failed"]
    assert not any(key.endswith("_rel") or key.startswith("pointwise_") for key in row)
    assert "| cosim zoh 3e-05 | failed, no results: the run diverged" in (out / "cosim_study.md").read_text()


# ----------------------------------------------------------------------------- calibrate
@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """A finished two-revolution wear study (max depth ~10 µm)."""
    folder = tmp_path_factory.mktemp("study") / "study"
    assert main(["wear-study", "--revolutions", "2", "--quiet", "--no-plots", "--out", str(folder)]) == 0
    return folder


POINTS = ["--points", "1000:5e-6,2000:8e-6"]


@pytest.mark.parametrize("options, message", [
    (["--life-depth-m=-1"], "--life-depth-m=-1 is invalid: allowed a max depth > 0 [m]"),
    (["--life-depth-m", "nan"], "--life-depth-m=nan is invalid: allowed a max depth > 0 [m]"),
    (["--tolerance", "nan"], "--tolerance=nan is invalid: allowed a share > 0"),
    (["--tolerance=-1"], "--tolerance=-1 is invalid: allowed a share > 0"),
    (["--depth-uncertainty-m", "0"], "--depth-uncertainty-m=0 is invalid: allowed > 0 [m]"),
    (["--predict-revolutions", "x"], "--predict-revolutions='x' is invalid: allowed N1,N2,... revolutions > 0"),
    (["--points", "1000:5e-6:nan"], "--points='1000:5e-6:nan' is invalid: allowed REVOLUTIONS:MAX_DEPTH_M"),
    (["--points", "1000:-5e-6"], "--points='1000:-5e-6' (points) is invalid: allowed REVOLUTIONS:DEPTH_M pairs, "
                                 "both finite and > 0"),
    (["--points", "1000:1e-3"], "--points='1000:1e-3' (points) is invalid: allowed max depths up to the study's"),
    # argparse said "expected one argument": a negative first number was an option
    (["--points", "-1:1e-5"], "--points='-1:1e-5' (points) is invalid: allowed REVOLUTIONS:DEPTH_M pairs"),
    (["--law", "mild-severe"], "--transition-depth-m is required with --law mild-severe"),
    (["--law", "mild-severe", "--transition-depth-m", "1"], "--transition-depth-m=1 (transition_depth_m) is "
                                                            "invalid: allowed in (0, "),
    (["--law", "mild-severe", "--transition-depth-m", "5e-6", "--life-depth-m", "1e-6"],
     "--life-depth-m=1e-6 is invalid: allowed only with --law archard"),
])
def test_calibrate_refuses_bad_values_naming_the_option(study, tmp_path, capsys, options, message):
    """-1 m gave "0 revolutions", nan wrote NaN into calibration.json, messages named points=, transition_depth_m=."""
    out = tmp_path / "c"
    options = options if any(o.startswith("--points") for o in options) else POINTS + options
    line = refused(capsys, "calibrate", "--study", str(study), "--no-plots", "--out", str(out), *options)
    assert message in line
    assert not (out / "calibration.json").exists()


def test_calibrate_points_beyond_the_study_say_what_reaches_them(study, tmp_path, capsys):
    """--resume cannot extend a study: the advice is a new study with more --revolutions."""
    line = refused(capsys, "calibrate", "--study", str(study), "--out", str(tmp_path / "c"))     # the paper's points
    assert "--points='200000:0.00019,400000:0.00055' (points) is invalid" in line
    assert "a new wear study with more --revolutions" in line and "--resume continues a study" in line
    assert main(["calibrate", "--study", str(study), *POINTS, "--life-depth-m", "1e-3", "--no-plots",
                 "--out", str(tmp_path / "c")]) == 0
    assert "beyond the study's max depth" in capsys.readouterr().out
    assert json.loads((tmp_path / "c" / "calibration.json").read_text())["life"]["revolutions"] is None


@pytest.mark.parametrize("growth", ["revolutions,max_wear_depth_m,worn_volume_m3\n", "revolutions\nfoo,bar\n",
                                    "revolutions\n1\n2\n", "revolutions\n2,1e-6\n1,2e-6\n", "r\n1,nan\n"])
def test_calibrate_refuses_a_study_whose_growth_curve_is_empty_or_garbage(study, tmp_path, capsys, growth):
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "summary.json").write_text((study / "summary.json").read_text())
    (broken / "wear_growth.csv").write_text(growth)
    line = refused(capsys, "calibrate", "--study", str(broken), *POINTS, "--out", str(tmp_path / "c"))
    assert f"--study='{broken}' is invalid: not a finished wear study" in line
    assert not (tmp_path / "c" / "calibration.json").exists()


# ----------------------------------------------------------------------------- wear-study
@pytest.mark.parametrize("options, message", [
    (["--cycle-jump-block", "0"], "--cycle-jump-block=0 (jump_block_revolutions) is invalid: allowed an integer >= 1"),
    (["--checkpoint-every", "0"], "--checkpoint-every=0 (checkpoint_every_revolutions) is invalid: allowed a finite "
                                  "real number > 0"),
    (["--impact-threshold-m-s2=-1"], "--impact-threshold-m-s2=-1 (impact_threshold_m_s2) is invalid"),
    (["--cycle-jump-tolerance", "2"], "--cycle-jump-tolerance=2 (jump_tolerance) is invalid: allowed in (0, 1)"),
    (["--calibrate-max-depth-m=-1"], "--calibrate-max-depth-m=-1 (target_max_depth_m) is invalid: allowed a finite "
                                     "depth > 0 m"),
    (["--calibrate-max-depth-m=nan"], "--calibrate-max-depth-m=nan (target_max_depth_m) is invalid: allowed a finite "
                                      "depth > 0 m"),
])
def test_wear_study_names_its_settings_as_options(tmp_path, capsys, options, message):
    out = tmp_path / "w"
    assert message in refused(capsys, "wear-study", "--revolutions", "2", "--out", str(out), *options)
    assert not out.exists()


def test_wear_study_resume_never_starts_afresh_and_single_and_ensemble_folders_do_not_mix(study, tmp_path, capsys):
    missing, empty, ensemble = tmp_path / "missing", tmp_path / "empty", tmp_path / "ensemble"
    empty.mkdir()
    ensemble.mkdir()
    (ensemble / "sweep.json").write_text("{}")          # an ensemble's (wear-study --seeds N) folder
    (ensemble / "sweep_summary.json").write_text(json.dumps({"command_line": f"wearjoint wear-study --seeds 2 "
                                                                             f"--out {ensemble}"}))
    line = refused(capsys, "wear-study", "--revolutions", "2", "--resume", "--out", str(missing))
    assert f"--resume is invalid with --out '{missing}': it holds no study to continue" in line
    assert not missing.exists()
    assert "it holds no study to continue (no wear_study_checkpoint.pkl)" in refused(
        capsys, "wear-study", "--revolutions", "2", "--resume", "--out", str(empty))
    assert not any(empty.iterdir())
    assert f"--out='{ensemble}' is invalid without --seeds: it holds an ensemble (sweep.json)" in refused(
        capsys, "wear-study", "--revolutions", "2", "--resume", "--out", str(ensemble))
    before = sorted(p.name for p in study.iterdir())
    assert f"--out='{study}' is invalid with --seeds 2: it holds a single wear study" in refused(
        capsys, "wear-study", "--revolutions", "2", "--seeds", "2", "--out", str(study))
    assert sorted(p.name for p in study.iterdir()) == before


# ----------------------------------------------------------------------------- report
@pytest.mark.parametrize("text, why", [('{"revolutions": ', "not JSON"), ("[1, 2]", "not a JSON object")])
def test_report_names_a_corrupt_summary(tmp_path, capsys, text, why):
    (tmp_path / "summary.json").write_text(text)
    line = refused(capsys, "report", str(tmp_path))
    assert f"{tmp_path / 'summary.json'} is invalid: {why}" in line and not (tmp_path / "report.html").exists()


def test_report_names_a_folder_that_does_not_exist(tmp_path, capsys):
    """It had said "no summary.json or sweep_summary.json: not a results folder" of a folder that is not there."""
    line = refused(capsys, "report", str(tmp_path / "nowhere"))
    assert f"FOLDER='{tmp_path / 'nowhere'}' is invalid: no such folder; allowed a results folder" in line


def test_the_study_fixture_is_a_real_study(study):
    growth = np.loadtxt(study / "wear_growth.csv", delimiter=",", skiprows=1, ndmin=2)
    assert growth.shape == (2, 3) and 5e-6 < growth[-1, 1] < 2e-5      # the points above lie on its curve


# ----------------------------------------------------------------------------- --initial-profile
def _profile_file(path, header="phi_deg,wear_depth_m", angles=None, depths=None):
    """A profile.csv of the paper joint's 1257 points (its angles, no wear) with ``angles``/``depths`` changed."""
    from wearjoint.core.geometry import bushing_point_angles

    phi = np.degrees(bushing_point_angles(1257)) if angles is None else angles
    depth = np.zeros(1257) if depths is None else depths
    np.savetxt(path, np.column_stack([phi, depth]), delimiter=",", header=header, comments="", fmt="%.17g")
    return str(path)


@pytest.mark.parametrize("command", ["cosim", "simulate"])
@pytest.mark.parametrize("change, message", [
    (dict(depths=np.r_[-1e-6, np.zeros(1256)]), "wear_depth_m in [0, 0.0101] m (the bushing radius): row 1 has -1e-06"),
    (dict(depths=np.r_[np.zeros(4), np.nan, np.zeros(1252)]), "row 5 has nan"),
    (dict(depths=np.r_[0.02, np.zeros(1256)]), "row 1 has 0.02"),
    (dict(header="a,b"), "a profile.csv whose header is phi_deg,wear_depth_m, got 'a,b'"),
    (dict(angles=np.arange(1257)[::-1] * 360.0 / 1257), "phi_deg at this joint's bushing points' angles"),
])
def test_an_initial_profile_is_checked_when_read(tmp_path, capsys, command, change, message):
    """Negative, NaN or deeper-than-radius depths ended in the FMU's state restore (exit 1, wear_depth[1]); reversed
    angles were 'got 1257 rows'; any header was taken."""
    profile = _profile_file(tmp_path / "profile.csv", **change)
    err = refused(capsys, command, "--revolutions", "0.01", "--initial-profile", profile, "--out",
                  str(tmp_path / "run"))
    assert f"--initial-profile='{profile}' is invalid" in err and message in err
    assert not (tmp_path / "run").exists()


# ----------------------------------------------------------------------------- negative numbers
@pytest.mark.parametrize("options, message", [
    (["--step", "-1e-6", "--integrator", "rk4"], "--step=-1e-6 (step_s) is invalid: allowed > 0"),
    (["--wear-coefficient-m2-N", "-1E-14"], "--wear-coefficient-m2-N=-1E-14 (wear_coefficient_m2_N) is invalid: "
                                            "allowed >= 0"),
    (["--restitution", "-inf"], "--restitution=-inf (restitution) is invalid: allowed a finite real number in [0.001, 1]"),
    (["--gravity-m-s2", "-9.81"], "--gravity-m-s2=-9.81 (gravity_m_s2) is invalid: allowed one finite value g in [0, 10000]"),
])
def test_a_negative_value_in_any_notation_is_read_as_the_options_value(tmp_path, capsys, options, message):
    """argparse took -1e-6, -inf and -9.81,0 for options ("expected one argument": no value, no range named); the
    `=` the docs asked for is not needed."""
    err = refused(capsys, "simulate", *options, "--out", str(tmp_path / "run"))
    assert message in err
    assert not (tmp_path / "run").exists()
    from wearjoint.cli import build_parser
    args = build_parser("simulate").parse_args(["simulate", "--gravity-m-s2", "-9.81,0", "--out", "x"])
    assert args.gravity_m_s2 == (-9.81, 0.0)


@pytest.mark.parametrize("text, meant", [("9,81", "9.81"), ("-9,81", "-9.81"), ("5,0", "5.0")])
def test_a_gravity_written_with_a_decimal_comma_is_refused_not_read_as_a_pair(tmp_path, capsys, text, meant):
    """--gravity-m-s2=9,81 ran with gravity (9, 81) m/s^2, 81.5 m/s^2 along the slide's normal: a European 9.81."""
    with pytest.raises(SystemExit) as exited:          # argparse's exit, as at any other option it refuses
        main(["simulate", f"--gravity-m-s2={text}", "--out", str(tmp_path / "run")])
    err = capsys.readouterr().err
    assert exited.value.code == 2 and err.count("\n") == 1, err
    assert f"--gravity-m-s2: '{text}' is ambiguous" in err and f"write {meant} for G" in err
    assert not (tmp_path / "run").exists()
    from wearjoint.cli import build_parser
    for given, read in (("9.81,0", (9.81, 0.0)), ("0,-9", (0.0, -9.0)), ("0,0", (0.0, 0.0)), ("9.0,81", (9.0, 81.0))):
        assert build_parser("simulate").parse_args(["simulate", f"--gravity-m-s2={given}", "--out", "x"]).gravity_m_s2 \
            == read


def test_calibrate_on_an_ensemble_folder_points_to_its_cases(study, tmp_path, capsys):
    """A --seeds folder holds its studies under cases/: it had been refused as "not a finished wear study
    (FileNotFoundError: ...summary.json)" although it had finished."""
    ensemble = tmp_path / "seeds"
    case = ensemble / "cases" / "0123456789abcdef"
    case.mkdir(parents=True)
    (ensemble / "sweep.json").write_text("{}")
    for name in ("summary.json", "wear_growth.csv"):
        (case / name).write_text((study / name).read_text())
    line = refused(capsys, "calibrate", "--study", str(ensemble), *POINTS, "--out", str(tmp_path / "c"))
    assert line.rstrip().endswith(f"--study='{ensemble}' is invalid: it holds an ensemble of wear studies (--seeds; sweep.json);"
                         f" allowed one wear study's folder, e.g. one of its cases: {case}"), line
    assert main(["calibrate", "--study", str(case), *POINTS, "--no-plots", "--out", str(tmp_path / "c")]) == 0


@pytest.mark.parametrize("integrator", ["dopri", "rk4"])
def test_a_cosim_wear_study_refuses_an_integrator_it_does_not_use(tmp_path, capsys, integrator):
    """--engine cosim steps by the co-simulation's master: --integrator dopri (the default's value, written) had been
    taken without a word and recorded in summary.json as the study's integrator."""
    line = refused(capsys, "wear-study", "--engine", "cosim", "--wear-factor", "100", "--integrator", integrator,
                   "--revolutions", "100", "--out", str(tmp_path / "w"))
    assert line.rstrip().endswith(f"--integrator={integrator!r} is invalid: allowed only with the monolithic --engine "
                                  "(the co-simulation steps by its adaptive master, --max-step its longest step in "
                                  "contact)"), line


@pytest.mark.parametrize("options,said", [
    (("--calibrate-max-depth-m", "1e-4", "--convergence", "jump,10"),
     "--calibrate-max-depth-m=1e-4 is invalid: allowed without --convergence"),
    (("--convergence", "jump,10", "--wear-factor", "10"), "--wear-factor=10 is invalid: allowed without --convergence"),
    (("--convergence", "jump,10", "--life-depth-m", "1e-3"), "--life-depth-m=1e-3 is invalid: allowed without "
                                                             "--convergence"),
    (("--no-cycle-jump", "--cycle-jump-block", "4"), "--cycle-jump-block=4 is invalid: allowed only with cycle jumping"),
    (("--wear-factor", "100", "--cycle-jump-block", "4"), "--cycle-jump-block=4 is invalid: allowed only with cycle "
                                                          "jumping")])
def test_a_wear_study_refuses_what_its_task_leaves_unread(tmp_path, capsys, options, said):
    """Each had run with the option ignored: the convergence study without the calibration, its F = 10 row the same
    without --wear-factor, no life stated, the block recorded though nothing jumped."""
    line = refused(capsys, "wear-study", "--revolutions", "200", *options, "--out", str(tmp_path / "w"))
    assert said in line and not (tmp_path / "w").exists(), line


@pytest.mark.parametrize("argv,named", [(("cosim", "--ideal"), "wearjoint cosim: error: unrecognized arguments: --ideal"),
                                        (("cosim-study", "--quiet"), "wearjoint cosim-study: error: unrecognized "
                                                                     "arguments: --quiet"),
                                        (("cosim-study", "--no-wear"), "wearjoint cosim-study: error: unrecognized "
                                                                       "arguments: --no-wear")])
def test_an_unknown_option_is_named_by_its_command(tmp_path, capsys, argv, named):
    """The command's own parser says it: the top-level parser's "wearjoint: error: unrecognized arguments" did not
    name the command whose --help lists the options.  cosim-study sets its own wear factor: its --help had listed
    --no-wear, which it then refused."""
    with pytest.raises(SystemExit) as exited:          # argparse's exit, as at any other option it refuses
        main([*argv, "--out", str(tmp_path / "o")])
    line = capsys.readouterr().err
    assert exited.value.code == 2 and line.count("\n") == 1, line
    assert line.startswith(named) and f"`wearjoint {argv[0]} --help` lists the options" in line, line
