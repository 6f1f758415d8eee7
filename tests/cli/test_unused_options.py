"""An option the run would ignore is refused (exit 2, one line naming it, its value and where it does something):
an integrator's option given to another integrator, a coupling option to Model Exchange or to a third-party master,
the Model Exchange tolerances to Co-Simulation, a wear option with --no-wear or --ideal.  Left at its default it is not given, and the run goes on."""
import pytest

from wearjoint.cli import build_parser, main
from wearjoint.targets import cosim_config, simulate_config

COSIM_ME = "only with --fmu-interface co-simulation (Model Exchange integrates by Dormand-Prince: --rtol, --atol-*, " \
           "--max-step)"
COSIM_THIRD_PARTY = "only with --master wearjoint (a third-party master steps the SSP's Co-Simulation FMUs, " \
                    "export-ssp's native builds, at the fixed --step)"


@pytest.mark.parametrize("command, args, option, value, allowed", [
    ("simulate", ["--step", "1e-7"], "--step", "1e-7", "only with --integrator rk4 (its fixed step)"),
    ("simulate", ["--integrator", "gear", "--step", "1e-7"], "--step", "1e-7", "only with --integrator rk4 (its fixed "
                                                                               "step)"),
    ("simulate", ["--integrator", "rk4", "--rtol", "1e-3"], "--rtol", "1e-3",
     "only with --integrator dopri or gear (rk4 steps by --step)"),
    ("simulate", ["--integrator", "rk4", "--max-step", "1e-5"], "--max-step", "1e-5",
     "only with --integrator dopri or gear (rk4 steps by --step)"),
    ("simulate", ["--gear-solver", "scipy"], "--gear-solver", "'scipy'", "only with --integrator gear"),
    ("simulate", ["--integrator", "gear", "--free-flight-max-step", "1e-4"], "--free-flight-max-step", "1e-4",
     "only with --integrator dopri"),
    ("cosim", ["--fmu-interface", "model-exchange", "--scheme", "zoh"], "--scheme", "'zoh'", COSIM_ME),
    ("cosim", ["--fmu-interface", "model-exchange", "--step", "2e-6"], "--step", "2e-6", COSIM_ME),
    ("cosim", ["--fmu-interface", "model-exchange", "--coupling-tolerance", "0.1"], "--coupling-tolerance", "0.1",
     COSIM_ME),
    ("cosim", ["--master", "fmpy-ssp", "--fmu-interface", "model-exchange"], "--fmu-interface", "'model-exchange'",
     COSIM_THIRD_PARTY),
    ("cosim", ["--master", "fmpy-ssp", "--scheme", "zoh"], "--scheme", "'zoh'", COSIM_THIRD_PARTY),
    ("cosim", ["--master", "fmpy-ssp", "--coupling-tolerance", "0.5"], "--coupling-tolerance", "0.5",
     COSIM_THIRD_PARTY),
    ("cosim", ["--rtol", "1e-3"], "--rtol", "1e-3",
     "only with --fmu-interface model-exchange (Co-Simulation steps by --scheme)"),
    ("simulate", ["--no-wear", "--wear-factor", "5"], "--wear-factor", "5",
     "only without --no-wear (the run wears nothing)"),
    # a new user's, taken without a word: k_w of a run without wear, a wear factor of the ideal joint
    ("simulate", ["--no-wear", "--wear-coefficient-m2-N", "1e-12"], "--wear-coefficient-m2-N", "1e-12",
     "only without --no-wear (the run wears nothing)"),
    ("cosim", ["--no-wear", "--calibration", "cal"], "--calibration", "'cal'",
     "only without --no-wear (the run wears nothing)"),
    ("wear-study", ["--no-wear", "--wear-coefficient-m2-N", "1e-12"], "--wear-coefficient-m2-N", "1e-12",
     "only without --no-wear (the run wears nothing)"),
    ("simulate", ["--ideal", "--wear-factor", "10"], "--wear-factor", "10",
     "only without --ideal (the run wears nothing)"),
    ("wear-study", ["--rtol", "1e-7"], "--rtol", "1e-7",
     "only with --integrator dopri and the monolithic --engine (rk4 steps by --max-step)"),
    ("wear-study", ["--fmu-backend", "pythonfmu"], "--fmu-backend", "'pythonfmu'", "only with --engine cosim"),
    ("simulate", ["--effective-mass-kg", "1"], "--effective-mass-kg", "1",
     "only with --contact-damping tsuji (--contact-damping hunt-crossley does not read it)"),
    ("cosim", ["--contact-damping", "tsuji", "--restitution-speed-m-s", "0.1"], "--restitution-speed-m-s", "0.1",
     "only with --contact-damping hunt-crossley (--contact-damping tsuji does not read it)"),
    ("wear-study", ["--impact-velocity-floor-m-s", "0.01"], "--impact-velocity-floor-m-s", "0.01",
     "only with --contact-damping lankarani-nikravesh or lankarani-nikravesh-exact (--contact-damping hunt-crossley "
     "does not read it)"),
    ("wear-study", ["--workers", "2"], "--workers", "2", "only with --seeds N, N > 1 (the ensemble's studies spread "
                                                          "over Dask workers; one study runs in this process)"),
    ("wear-study", ["--seeds", "1", "--scheduler", "tcp://h:1"], "--scheduler", "'tcp://h:1'",
     "only with --seeds N, N > 1 (the ensemble's studies spread over Dask workers; one study runs in this process)"),
])
def test_an_option_the_run_would_ignore_is_refused_in_one_line(command, args, option, value, allowed, tmp_path,
                                                               capsys):
    assert main([command, "--out", str(tmp_path), "--revolutions", "0.01", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"wearjoint {command}: error: {option}={value} is invalid: allowed {allowed}"
    assert not (tmp_path / "summary.json").exists()


@pytest.mark.parametrize("command, args, attribute, expected", [
    ("simulate", ["--integrator", "rk4", "--step", "1e-7"], "step_s", 1e-7),
    ("simulate", ["--step", "1e-6", "--rtol", "1e-6"], "rtol", 1e-6),                 # the defaults, written out
    ("simulate", ["--integrator", "gear", "--gear-solver", "scipy", "--rtol", "1e-5"], "gear_solver", "scipy"),
    ("cosim", ["--fmu-interface", "model-exchange", "--rtol", "1e-5", "--max-step", "1e-5"], "rtol", 1e-5),
    ("cosim", ["--scheme", "adaptive", "--step", "2e-6", "--coupling-tolerance", "0.01"], "coupling_tolerance", 0.01),
])
def test_an_option_the_run_uses_is_taken(command, args, attribute, expected, tmp_path):
    options = vars(build_parser(command).parse_args([command, "--out", str(tmp_path), *args]))
    config = (simulate_config if command == "simulate" else cosim_config)(options)
    assert getattr(config.options, attribute) == expected


def test_calibrate_refuses_a_transition_depth_its_archard_law_would_ignore(tmp_path, capsys):
    (tmp_path / "summary.json").write_text('{"parameters": {"joint": {"wear_coefficient_m2_N": 1e-13, '
                                           '"wear_factor": 1.0}}}')
    (tmp_path / "wear_growth.csv").write_text("revolutions,max_wear_depth_m,worn_volume_m3\n1000,1e-5,0\n")
    assert main(["calibrate", "--study", str(tmp_path), "--points", "500:5e-6", "--transition-depth-m", "1e-5"]) == 2
    assert capsys.readouterr().err.strip() == ("wearjoint calibrate: error: --transition-depth-m=1e-5 is "
                                               "invalid: allowed only with --law mild-severe")
    assert not (tmp_path / "calibration.json").exists()


def test_an_ideal_run_says_nothing_of_the_wear_coefficient(tmp_path, capsys):
    """--ideal (no bushing, no wear) on another joint had printed the note that k_w is the paper's, for a run that
    wears nothing; the summary says where k_w came from and no note."""
    import json

    out = tmp_path / "ideal"
    assert main(["simulate", "--ideal", "--pin-radius-m", "0.009", "--revolutions", "0.02", "--no-plots", "--out",
                 str(out)]) == 0
    assert "k_w" not in capsys.readouterr().err
    assert json.loads((out / "summary.json").read_text())["wear_coefficient_note"] is None
