"""The slider's load and gravity in any direction (docs/reference/model.md §3.12): the table's interpolation, its checks, and
the quasi-static closed form.

A slowly driven slider-crank (12 rpm: the slider's inertia force is below 0.1 N) without gravity under a constant
load F on the slider: the rod is a two-force member, so each of its joints (and the crank's pivot) carries
F / cos(beta) (beta the rod's angle, sin beta = l1 sin theta / l2) and Archard's worn volume is k_w times the
integral of F / cos(beta) over the sliding distance R_j |omega_pin - omega_bushing| dt of the joint with the
clearance (docs/reference/model.md §3.8).  With gravity along the slide the statics
of rod and slider give the joint force by hand (below).  The contact rings at a few per cent about its mean (weak
damping of a resting contact, docs/reference/model.md §3.5): the force is compared in 0.1 s means, in the monolithic
engine, the co-simulation (native joint FMU) and exudyn.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from wearjoint.core import layout as L
from wearjoint.core.slider_load import slider_load
from wearjoint.slider_crank import SliderCrank
from wearjoint.parameters import ParameterError, SliderCrankParameters, SliderForceTable, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

START_DEG = 80.0
SLOW = dict(crank_speed_rpm=12.0, initial_crank_angle_deg=START_DEG)


def _time_at(mechanism, angle_deg):
    """The time [s] at which the clockwise crank reaches theta1 = angle_deg (mod 360), in the first turn."""
    turned = (mechanism.initial_crank_angle_deg - angle_deg) % 360.0
    return math.radians(turned) / mechanism.omega_rad_s


def test_table_interpolates_linearly_and_is_periodic():
    table = SliderForceTable((0.0, 20.0, 40.0, 360.0), (100.0, 2100.0, 100.0, 100.0))
    mechanism = SliderCrankParameters(slider_force_table=table, slider_force_N=-50.0, initial_crank_angle_deg=30.0)
    mp = SliderCrank(mechanism).parameter_vector
    for angle, expected in ((0.0, 100.0), (10.0, 1100.0), (20.0, 2100.0), (25.0, 1600.0), (40.0, 100.0),
                            (200.0, 100.0), (359.0, 100.0)):
        for turn in (0, 2):
            t = _time_at(mechanism, angle) + turn * mechanism.period_s
            assert slider_load(t, mp) == pytest.approx(expected - 50.0, abs=1e-6), (angle, turn)
    mp[L.MP_SLIDER_FORCE_INPUT] = 7.0          # a master's input adds to both
    assert slider_load(_time_at(mechanism, 10.0), mp) == pytest.approx(1057.0)


@pytest.mark.parametrize("text,problem", [
    ("crank_angle_deg,force_N\n0,0\n90,abc\n360,0\n", "line 3: force_N='abc' is not a number"),
    ("crank_angle_deg,force_N\n0,0\n90,nan\n360,0\n", "line 3: force_N=nan is not a finite number"),
    ("crank_angle_deg,force_N\n0,0\n90,5\n350,0\n", "line 4: crank_angle_deg=350.0: the last row is not at 360"),
    ("crank_angle_deg,force_N\n10,0\n90,5\n360,0\n", "line 2: crank_angle_deg=10.0: the first row is not at 0"),
    ("crank_angle_deg,force_N\n0,0\n90,5\n\n80,5\n360,0\n", "line 5: crank_angle_deg=80.0: the crank angle does "
                                                                 "not rise"),
    ("crank_angle_deg,force_N\n0,0\n90,5\n360,3\n", "line 4: force_N=3.0: the load at 360 deg differs"),
    ("angle,force\n0,0\n360,0\n", "line 1: header"),
    ("crank_angle_deg,force_N\n0,0,1\n360,0\n", "line 2: 3 columns"),
    ("crank_angle_deg,force_N\n\n", ": no rows after the header: allowed 2 to 361 rows"),
])
def test_a_bad_table_file_is_refused_in_one_line_naming_file_line_and_problem(tmp_path, text, problem):
    path = tmp_path / "load.csv"
    path.write_text(text)
    with pytest.raises(ParameterError) as error:
        SliderForceTable.from_csv(path)
    message = str(error.value)
    assert "\n" not in message and str(path) in message and problem in message, message


def test_a_spreadsheets_csv_with_a_byte_order_mark_reads(tmp_path):
    path = tmp_path / "load.csv"
    path.write_bytes("\ufeffcrank_angle_deg,force_N\r\n0,5\r\n180,-5\r\n360,5\r\n".encode())
    table = SliderForceTable.from_csv(path)
    assert table.crank_angle_deg == (0.0, 180.0, 360.0) and table.force_N == (5.0, -5.0, 5.0)


def test_gravity_is_a_vector_and_a_single_value_is_its_magnitude_across_the_slide():
    assert SliderCrankParameters(gravity_m_s2=9.81).gravity_m_s2 == (0.0, -9.81)
    assert SliderCrankParameters(gravity_m_s2=(9.81, 0.0)).gravity_m_s2 == (9.81, 0.0)
    with pytest.raises(ParameterError, match="gravity_m_s2"):
        SliderCrankParameters(gravity_m_s2=(1.0, 2.0, 3.0))
    # a magnitude below 0 would point gravity up: a user writing -9.81 for "down" got (0, +9.81); the pair says up
    with pytest.raises(ParameterError, match=r"gravity_m_s2=-9\.81 is invalid: allowed one finite value g in \[0, 10000\]"):
        SliderCrankParameters(gravity_m_s2=-9.81)
    assert SliderCrankParameters(gravity_m_s2=(0.0, 9.81)).gravity_m_s2 == (0.0, 9.81)
    with pytest.raises(ParameterError, match="slider_force_N"):
        SliderCrankParameters(slider_force_N=math.inf)


def _static_joint_force(mechanism, time, load_N):
    """|force of the crank on the rod| of the rod and slider under the slider's load and gravity (g_x, g_y), the
    rod's inertia neglected (0.19 kg), the slider's kept (d'Alembert, a_3 the ideal slider-crank's):
    slider along x, -B_x + m3 (g_x - a_3) - F = 0; rod moments about the crank pin; A = -B - m2 g."""
    gx, gy = mechanism.gravity_m_s2
    m2, m3 = mechanism.rod_mass_kg, mechanism.slider_mass_kg
    ideal = SliderCrank(mechanism).closed_form(time)
    beta = -ideal["rod_angle_rad"]
    dx, dy = mechanism.rod_length_m * np.cos(beta), -mechanism.rod_length_m * np.sin(beta)   # crank pin -> slider pin
    bx = m3 * (gx - ideal["slider_a_m_s2"]) - load_N
    by = (dy * bx - 0.5 * m2 * (dx * gy - dy * gx)) / dx
    return np.hypot(bx + m2 * gx, by + m2 * gy)


def _window_means(record, width_s=0.1, skip_s=0.1):
    """(mean of |joint force| from the samples, the samples' times) over windows of ``width_s`` after ``skip_s``."""
    s = record.samples
    t = s[:, L.T_TIME]
    force = np.hypot(s[:, L.T_PIN_FX], s[:, L.T_PIN_FY])
    out = []
    for start in np.arange(skip_s, t[-1] - width_s + 1e-12, width_s):
        w = (t >= start) & (t < start + width_s)
        out.append((force[w].mean(), t[w]))
    return out


@pytest.mark.parametrize("load_N,gravity", [(1000.0, 0.0), (-600.0, 0.0), (0.0, (9.81, 0.0))],
                         ids=["compressing", "pulling", "vertical press under its own weight"])
def test_quasi_static_joint_force_is_the_closed_form(load_N, gravity):
    slider_mass = 60.0 if load_N == 0.0 else 0.70          # the weight then is the load: 589 N along the slide
    mechanism = SliderCrankParameters(**SLOW, slider_force_N=load_N, gravity_m_s2=gravity, slider_mass_kg=slider_mass)
    joint = paper_joint(mechanism, wear_factor=0.0)
    options = dict(revolutions=0.15, sample_dt_s=1e-3)
    ideal = run_simulation(joint, mechanism, SimulationOptions(ideal=True, **options), progress=False)
    clearance = run_simulation(joint, mechanism, SimulationOptions(integrator="dopri", **options), progress=False)
    for name, record, tolerance in (("ideal", ideal, 0.002), ("clearance", clearance, 0.02)):
        windows = _window_means(record)
        assert len(windows) >= 5, name
        for mean_force, times in windows:
            expected = _static_joint_force(mechanism, times, load_N).mean()
            assert mean_force == pytest.approx(expected, rel=tolerance), (name, times[0])
        # a load towards the pivot compresses the rod: the rod pushes the crank's pin back towards the pivot (-x)
        pushed_back = record.samples[record.samples[:, L.T_TIME] > 0.1, L.T_PIN_FX] < 0.0
        assert pushed_back.all() if load_N > 0.0 else not pushed_back.any(), name


def _rod_angle_and_relative_rate(mechanism, t):
    """beta [rad] (sin beta = l1 sin theta / l2; the rod's angle is -beta) and |omega_pin - omega_bushing| [rad/s]
    of the clearance joint at time t [s] on the ideal slider-crank: crank and rod, rod and slider (which does not
    turn), crank and ground."""
    l1, l2 = mechanism.crank_length_m, mechanism.rod_length_m
    w1 = -mechanism.omega_rad_s
    theta = math.radians(mechanism.initial_crank_angle_deg) + w1 * t
    beta = math.asin(l1 * math.sin(theta) / l2)
    w2 = -l1 * math.cos(theta) * w1 / (l2 * math.cos(beta))
    return beta, {"crank-rod": abs(w1 - w2), "rod-slider": abs(w2), "crank-ground": abs(w1)}[mechanism.clearance_joint]


def _archard_volume(mechanism, joint, load_N, duration_s):
    """k_w times the integral of F / cos(beta) R_j |omega_pin - omega_bushing| dt over [0, duration_s] [m^3]."""
    def rate(t):
        beta, relative = _rod_angle_and_relative_rate(mechanism, t)
        return load_N / math.cos(beta) * joint.bushing_radius_m * relative

    return joint.wear_coefficient_m2_N * quad(rate, 0.0, duration_s, limit=200)[0]


def _two_force_member_load(mechanism, times, load_N):
    """F / cos(beta) [N] at ``times``: what every joint carries, slowly, without gravity."""
    return np.array([load_N / math.cos(_rod_angle_and_relative_rate(mechanism, t)[0]) for t in times])


def _loaded_slowly(location):
    return SliderCrankParameters(**SLOW, slider_force_N=1000.0, gravity_m_s2=0.0, clearance_joint=location)


def _wearing(mechanism):
    return paper_joint(mechanism, wear_coefficient_m2_N=5.576e-11)


def _assert_quasi_static(record, mechanism, force_tolerance):
    windows = _window_means(record)
    assert len(windows) >= 5
    for mean_force, times in windows:
        expected = _two_force_member_load(mechanism, times, 1000.0).mean()
        assert mean_force == pytest.approx(expected, rel=force_tolerance), times[0]


@pytest.mark.parametrize("location", L.CLEARANCE_JOINTS)
def test_every_joint_carries_the_two_force_members_load_and_wears_archards_volume(location):
    """The monolithic engine with the clearance at each joint (the other two ideal): the ideal mechanism's
    reaction there within 0.2 %, the clearance joint's force within 2 %, its worn volume within 5 %."""
    mechanism = _loaded_slowly(location)
    joint = _wearing(mechanism)
    options = dict(revolutions=0.15, sample_dt_s=1e-3, integrator="dopri")
    ideal = run_simulation(joint, mechanism, SimulationOptions(ideal=True, **options), progress=False)
    _assert_quasi_static(ideal, mechanism, 0.002)
    record = run_simulation(joint, mechanism, SimulationOptions(**options), progress=False)
    _assert_quasi_static(record, mechanism, 0.02)
    archard = _archard_volume(mechanism, joint, 1000.0, record.simulated_time_s)
    assert record.worn_volume_m3 == pytest.approx(archard, rel=0.05)


@pytest.fixture(scope="module")
def engines(native_fmu):
    """The compressing case with the clearance at each joint, wearing, through the co-simulation (native joint
    FMU) and exudyn (its generalized-alpha, the kernels' joint and the slider's load as an exudyn load user
    function)."""
    from validation.exudyn_model import run_exudyn
    from wearjoint.cosim import CoSimulationOptions, run_cosimulation

    runs = {}
    for location in L.CLEARANCE_JOINTS:
        mechanism = _loaded_slowly(location)
        joint = _wearing(mechanism)
        runs["co-simulation", location] = run_cosimulation(
            joint, mechanism, CoSimulationOptions(revolutions=0.15, sample_dt_s=1e-3), fmu_path=native_fmu,
            progress=False, fmu_backend="native")
        runs["exudyn", location] = run_exudyn(joint, mechanism, 0.15, sample_dt_s=1e-3, progress=False)
    return runs


@pytest.mark.parametrize("location", L.CLEARANCE_JOINTS)
@pytest.mark.parametrize("engine", ["co-simulation", "exudyn"])
def test_every_engine_carries_the_quasi_static_load_and_wears_archards_volume(engines, engine, location):
    record = engines[engine, location]
    mechanism = _loaded_slowly(location)
    _assert_quasi_static(record, mechanism, 0.02)
    archard = _archard_volume(mechanism, _wearing(mechanism), 1000.0, record.simulated_time_s)
    assert record.worn_volume_m3 == pytest.approx(archard, rel=0.05)


@pytest.mark.parametrize("text, problem", [
    ("crank_angle_deg,force_N\n0,0\n90,x\n360,0\n", "line 3: force_N='x' is not a number"),
    (None, "cannot read it"),
])
def test_the_cli_refuses_a_bad_table_in_one_line_and_exit_2(tmp_path, capsys, text, problem):
    from wearjoint.cli import main

    path = tmp_path / "load.csv"
    if text is not None:
        path.write_text(text)
    code = main(["simulate", "--revolutions", "0.01", "--slider-force-table", str(path), "--out",
                 str(tmp_path / "out")])
    error = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(error) == 1 and problem in error[0], error
    assert f"--slider-force-table={str(path)!r} (slider_force_table) is invalid" in error[0], error
    assert not (tmp_path / "out").exists()


def test_a_loaded_wear_study_completes_with_its_error_estimate(tmp_path):
    """Cycle jumping on the press of docs/tutorials/own_mechanism.md (the table, gravity along the stroke): the study runs
    to its horizon, its jumps carry error estimates and their replays wear the blocks' volumes."""
    from wearjoint.cli import main

    table = Path(__file__).resolve().parents[2] / "docs" / "examples" / "press_load.csv"
    out = tmp_path / "press"
    assert main(["wear-study", "--crank-length-m", "0.05", "--rod-length-m", "0.25", "--crank-speed-rpm", "120",
                 "--slider-mass-kg", "8", "--rod-mass-kg", "1.2", "--rod-inertia-kg-m2", "0.00625",
                 "--gravity-m-s2=9.81,0", "--slider-force-table", str(table), "--wear-coefficient-m2-N", "2e-15",
                 "--revolutions", "300", "--snapshots", "100,300", "--no-plots", "--quiet", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    jumping = summary["cycle_jumping"]
    assert summary["completed"] and summary["failure"] is None
    assert jumping["jumps"] >= 1 and 0.0 < jumping["error_estimate_summed_rel_to_final_depth"] < 0.05
    assert all(abs(ratio - 1.0) < 0.01 for ratio in jumping["replay_volume_ratio_range"])
    assert summary["parameters"]["mechanism"]["slider_force_table"]["force_N"][1] == 2000.0
