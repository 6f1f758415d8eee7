"""`wearjoint simulate` end to end: the results contract and clean parameter errors."""
import json
import subprocess
import sys
import time

import numpy as np
import pytest

from wearjoint import JointParameters, SliderCrankParameters, paper_joint
from wearjoint.results import RunParameters, new_revolution_stats

SUMMARY_KEYS = {"revolutions", "simulated_time_s", "wall_time_s", "realtime_factor", "max_contact_force_N",
                "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                "max_eccentricity_m", "max_wear_depth_m", "max_wear_angle_deg", "worn_volume_m3", "parameters"}


def wearjoint(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def test_simulate_writes_the_results_contract(tmp_path):
    out = tmp_path / "run"
    done = wearjoint("simulate", "--revolutions", "0.1", "--out", str(out), "--quiet", "--wear-factor", "5")
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= set(summary)
    assert summary["revolutions"] == pytest.approx(0.1)
    # JIT compilation is reported apart: the real-time factor is simulated time per wall time of the simulation
    assert summary["compile_time_s"] >= 0.0 and summary["wall_time_s"] > 0.0
    assert summary["realtime_factor"] == pytest.approx(summary["simulated_time_s"] / summary["wall_time_s"])
    assert summary["parameters"]["joint"]["wear_factor"] == 5.0
    assert summary["max_wear_depth_m"] > 0 and 0 <= summary["max_wear_angle_deg"] < 360
    profile = np.loadtxt(out / "profile.csv", delimiter=",", skiprows=1)
    assert (out / "profile.csv").read_text().startswith("phi_deg,wear_depth_m\n")
    assert profile.shape == (1257, 2) and profile[:, 1].max() == pytest.approx(summary["max_wear_depth_m"])
    series = np.load(out / "timeseries.npz")
    for column in ("time_s", "crank_angle_rad", "slider_x_m", "slider_v_m_s", "slider_a_m_s2",
                   "pin_force_x_N", "pin_force_y_N", "eccentricity_x_m", "eccentricity_y_m"):
        assert series[column].size > 100
    for png in ("slider_acceleration.png", "pin_orbit.png", "contact_force.png", "wear_profile.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("option,value,name", [
    ("--bushing-radius-m", "0.0099", "bushing_radius_m"),
    ("--n-points", "7", "n_points"),
    ("--pin-poisson-ratio", "0.6", "pin_poisson_ratio"),
    ("--restitution", "1.5", "restitution"),
    ("--friction-coefficient", "-0.1", "friction_coefficient"),
    ("--friction-v1-m-s", "0.0005", "friction_v1_m_s"),
    ("--wear-coefficient-m2-N", "-1e-10", "wear_coefficient_m2_N"),
    ("--crank-mass-kg", "0", "crank_mass_kg"),
    ("--rod-length-m", "-0.2", "rod_length_m"),
    ("--bushing-youngs-modulus-Pa", "0", "bushing_youngs_modulus_Pa"),
    ("--pin-radius-m", "nan", "pin_radius_m"),
    ("--revolutions", "0", "revolutions"),
    ("--max-step", "inf", "max_step_s"),
])
def test_bad_parameter_exits_with_a_message_and_no_traceback(tmp_path, option, value, name):
    done = wearjoint("simulate", "--out", str(tmp_path / "x"), "--quiet", f"{option}={value}")
    assert done.returncode == 2
    assert f"error: {option}=" in done.stderr and f"({name})" in done.stderr   # as written, and the API's name
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x" / "summary.json").exists()


@pytest.mark.parametrize("command, options, message", [
    ("cosim", ["--step", "0"], "error: --step=0 (step_s) is invalid: allowed > 0"),
    ("cosim", ["--onset-penetration=-1"], "error: --onset-penetration=-1 (onset_penetration_m) is invalid"),
    # the rule compares with a default the user did not write: the option that sets it named too
    ("cosim", ["--min-step", "1e-4"], "error: --min-step=1e-4 (min_step_s) is invalid: allowed <= step_s = 1e-05 "
                                      "(step_s: not given; --step sets it)\n"),
    ("cosim", ["--min-step", "1e-4", "--step", "2e-5"], "error: --min-step=1e-4 (min_step_s) is invalid: allowed <= "
                                                        "step_s = 2e-05\n"),
    # the bad value is a default the user did not write, its rule against one the user wrote: that option named as
    # written, then the default, the option that sets it and the rule
    ("cosim", ["--step", "2e-4"], "error: --step=2e-4 (step_s) is invalid against max_step_s=0.0001 (not given; "
                                  "--max-step sets it): allowed max_step_s >= step_s = 0.0002"),
    ("simulate", ["--crank-length-m=0.3"], "error: --crank-length-m=0.3 (crank_length_m) is invalid against "
                                           "rod_length_m=0.22 (not given; --rod-length-m sets it): allowed rod_length_m "
                                           "> crank_length_m = 0.3 (the crank must turn fully)"),
    ("simulate", ["--pin-radius-m", "0.02"], "error: --pin-radius-m=0.02 (pin_radius_m) is invalid against "
                                             "bushing_radius_m=0.0101 (not given; --bushing-radius-m sets it): allowed "
                                             "bushing_radius_m > 0 (at most 100 m) and > pin_radius_m"),
    ("build-fmu", ["--n-points", "3"], "error: --n-points=3 (n_points) is invalid: allowed an integer from 8 to 1000000"),
    # a profile no machine holds: refused, not the OOM killer's
    ("simulate", ["--n-points", "1000000000"], "error: --n-points=1000000000 (n_points) is invalid: allowed an integer "
                                               "from 8 to 1000000"),
    ("wear-study", ["--revolutions", "-5"], "error: --revolutions=-5 (revolutions) is invalid: allowed an integer >= 1"),
    # no ensemble of no seeds: refused, not run as one seed
    ("wear-study", ["--revolutions", "10", "--seeds", "0"], "error: --seeds=0 is invalid: allowed an integer from 1 to 10000"),
    # a time series no machine holds: refused before anything is built, not a failed allocation's traceback
    ("simulate", ["--revolutions", "1e12"], "error: --revolutions=1e12 (revolutions) is invalid: allowed <="),
    ("cosim", ["--master", "container", "--revolutions", "1e12"], "(revolutions) is invalid: allowed <="),
    # a fmusim that is not there: refused before the package is built (a FileNotFoundError traceback after 5 s)
    ("cosim", ["--master", "container", "--fmusim", "no/such/fmusim"],
     "error: --fmusim='no/such/fmusim' is invalid: allowed an executable fmusim"),
    # refused before the package is written (it named an internal step_s, after writing the SSP)
    ("export-ssp", ["--container-step", "-1"], "error: --container-step=-1 (container_step_s) is invalid: allowed > 0"),
])
def test_a_bad_option_is_named_as_the_user_wrote_it(tmp_path, command, options, message):
    done = wearjoint(command, "--out", str(tmp_path / "x"), *options)
    assert done.returncode == 2 and message in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "x").exists()


def test_unknown_choice_is_rejected_by_the_parser(tmp_path):
    done = wearjoint("simulate", "--out", str(tmp_path), "--rho-mode", "flat")
    assert done.returncode == 2 and "rho-mode" in done.stderr and "Traceback" not in done.stderr


class _SlowCompilingEngine:
    """An engine (wearjoint.runner.Engine) whose compilation (warm_up) takes 0.5 s and whose simulation
    takes none."""

    t = 0.0
    joint_parameters = JointParameters()

    def __init__(self):
        self.revolution_stats = new_revolution_stats(2)
        self.closed = False

    def warm_up(self):
        time.sleep(0.5)

    def advance_to(self, t_end, samples):
        self.t = t_end
        return 0

    def max_wear_depth_m(self):
        return 0.0

    def wear_profile(self):
        return np.array([180.0, 360.0]), np.array([1e-6, 0.0]), 0.0

    def describe(self):
        return RunParameters("test", paper_joint(), SliderCrankParameters()), {"steps": 3}

    def close(self):
        self.closed = True


def test_compile_time_is_reported_apart_from_the_simulation_wall_time(tmp_path):
    from wearjoint.results import write_results
    from wearjoint.runner import run_engine

    engines = []
    record = run_engine(lambda: engines.append(_SlowCompilingEngine()) or engines[-1], 1.0, 0.01, 1e-3, "test",
                        progress=False)
    assert record.compile_time_s >= 0.5 > record.wall_time_s
    assert engines[0].closed and record.parameters.engine == "test" and record.extra == {"steps": 3}
    write_results(record, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["compile_time_s"] >= 0.5 > summary["wall_time_s"] > 0.0
    assert summary["realtime_factor"] == pytest.approx(0.01 / summary["wall_time_s"])


def test_a_run_whose_time_series_would_not_fit_in_memory_is_refused_first(monkeypatch):
    """On a machine of 1 GiB a quarter holds 55.92 revolutions of the paper's time series (a row of 15 doubles every
    1e-5 s: 40 001 rows, 4.80 MB a revolution): 60 are refused before the engine is built, naming revolutions and
    the bound; 0.01 runs."""
    from wearjoint import runner
    from wearjoint.parameters import ParameterError
    from wearjoint.simulate import SimulationOptions, run_simulation

    pages = {"SC_PAGE_SIZE": 4096, "SC_PHYS_PAGES": 2 ** 30 // 4096}
    monkeypatch.setattr(runner.os, "sysconf", lambda name: pages[name])
    joint = paper_joint(wear_factor=0.0)
    with pytest.raises(ParameterError, match=r"parameter revolutions=60\.0 is invalid: allowed <= 55\.92 with a row "
                                             r"every 1e-05 s \(sample_dt_s\)"):
        run_simulation(joint, None, SimulationOptions(revolutions=60.0), progress=False)
    assert run_simulation(joint, None, SimulationOptions(revolutions=0.01), progress=False).completed
