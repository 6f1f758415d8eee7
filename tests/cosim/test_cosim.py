"""The fmpy co-simulation master (wearjoint.cosim) against the monolithic engine.

The FMUs are built once per session (fixtures ``native_fmu``, ``built_fmu`` for pythonfmu).  Pointwise agreement is
checked only over the first 15 ms (the motion is chaotic afterwards), with the
tolerance taken from two equally valid monolithic runs (RK4 1 us and DOPRI).
"""
import json
import pickle
import re

import numpy as np
import pytest

pytest.importorskip("fmpy")

from wearjoint import cli  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.cosim import CoSimulation, CoSimulationError, CoSimulationOptions, run_cosimulation  # noqa: E402
from wearjoint.cosim import cosimulation, master_layout  # noqa: E402
from wearjoint.cosim.model_exchange import ModelExchangeSimulation, run_model_exchange  # noqa: E402
from wearjoint.checks import RunStopped  # noqa: E402
from wearjoint.parameters import JointParameters, SliderCrankParameters, paper_joint  # noqa: E402
from wearjoint.results import write_results  # noqa: E402
from wearjoint.simulate import SimulationOptions, run_simulation  # noqa: E402

WINDOW_S = 0.015
PERIOD_S = SliderCrankParameters().period_s
NO_WEAR = paper_joint(wear_factor=0.0)


def pin_path(record):
    """(time, [eccentricity x, eccentricity y, slider x]) of a run's samples [s, m]."""
    s = record.samples
    return s[:, L.T_TIME], s[:, [L.T_ECC_X, L.T_ECC_Y, L.T_SLIDER_X]]


def max_deviation(record, reference):
    """Max |difference| per column over the reference's samples (record interpolated) [m]."""
    t_ref, ref = pin_path(reference)
    t, values = pin_path(record)
    return np.max(np.abs(np.column_stack([np.interp(t_ref, t, values[:, k]) for k in range(3)]) - ref), axis=0)


@pytest.fixture(scope="module")
def monolithic_window():
    """Valid monolithic runs over the first 15 ms: (reference RK4 1 us, [DOPRI, RK4 2 us])."""
    rev = WINDOW_S / PERIOD_S
    rk4 = run_simulation(NO_WEAR, None, SimulationOptions(revolutions=rev, integrator="rk4", step_s=1e-6),
                         progress=False)
    others = [run_simulation(NO_WEAR, None, SimulationOptions(revolutions=rev, **options), progress=False)
              for options in ({"integrator": "dopri", "max_step_s": 1e-5}, {"integrator": "rk4", "step_s": 2e-6})]
    return rk4, others


@pytest.mark.parametrize("scheme", ["extrapolation", "adaptive"])
def test_cosimulation_reproduces_the_monolithic_run_over_the_first_15_ms(any_fmu, monolithic_window, scheme):
    backend, built_fmu = any_fmu
    rk4, others = monolithic_window
    assert rk4.samples[:, L.T_CONTACT].any(), "the window must contain impacts"
    records = [run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=WINDOW_S / PERIOD_S, scheme=scheme,
                                                                   step_s=step), fmu_path=built_fmu, progress=False,
                                fmu_backend=backend) for step in (1e-6, 2e-6)]
    record = records[0]
    assert record.simulated_time_s == pytest.approx(WINDOW_S)
    # the scatter of valid monolithic runs (DOPRI, the RK4 step refinement) plus the co-simulation's own
    # step refinement (it holds the forces over a step: first order), as wearjoint validate
    tolerance = np.max([max_deviation(other, rk4) for other in others], axis=0) + max_deviation(records[1], record)
    deviation = max_deviation(record, rk4)
    assert np.all(deviation <= tolerance), (deviation, tolerance)


def test_the_cosimulations_tangential_velocity_is_the_monolithic_runs(native_fmu, monolithic_window):
    """The joint FMU publishes v_T (Eq. 14): the co-simulation's column is 0 out of contact and in contact slides as
    the monolithic engine's does over the first impacts (largest and mean |v_T|, about 0.19 and 0.08 m/s)."""
    rk4, _ = monolithic_window
    record = run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=WINDOW_S / PERIOD_S), fmu_path=native_fmu,
                              progress=False)
    speeds = []
    for run in (record, rk4):
        contact = run.samples[:, L.T_CONTACT] > 0.5
        sliding = np.abs(run.samples[:, L.T_TANGENTIAL_VELOCITY])
        assert contact.any() and np.all(sliding[~contact] == 0.0)
        speeds.append((sliding[contact].max(), sliding[contact].mean()))
    np.testing.assert_allclose(speeds[0], speeds[1], rtol=0.02)
    assert speeds[1][0] > 0.1


def test_zero_order_hold_and_the_adaptive_scheme_both_run(native_fmu):
    """Both schemes go through contact; the adaptive one needs far fewer steps in free flight."""
    rev = 0.02                                      # 8 ms: free flight, then the first impacts
    runs = {scheme: run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=rev, scheme=scheme, step_s=2e-6),
                                     fmu_path=native_fmu, progress=False, fmu_backend="native")
            for scheme in ("zoh", "adaptive")}
    for record in runs.values():
        assert record.completed and record.samples[:, L.T_CONTACT].any()
        assert np.all(np.isfinite(record.samples))
        ecc = np.hypot(record.samples[:, L.T_ECC_X], record.samples[:, L.T_ECC_Y])
        assert ecc.max() < NO_WEAR.clearance_m * 1.1     # penetrations stay micrometres
    assert runs["zoh"].extra["communication_steps"] == round(rev * PERIOD_S / 2e-6)
    assert runs["adaptive"].extra["communication_steps"] < 0.5 * runs["zoh"].extra["communication_steps"]
    assert runs["adaptive"].extra["rollbacks"] >= 1


def test_checkpoint_restore_continues_bit_identically(native_fmu):
    """With wear on, through pickle, across contact onsets and rollbacks (adaptive)."""
    options = CoSimulationOptions(revolutions=0.05, scheme="adaptive", step_s=2e-6)
    joint = paper_joint()
    samples_a = np.zeros((400, L.N_SAMPLE_COLUMNS))
    samples_b = np.zeros_like(samples_a)
    with CoSimulation(joint, None, options, fmu_path=native_fmu, fmu_backend="native") as a:
        a.advance_to(0.004, samples_a)                 # past the first impact (~3.1 ms)
        saved = pickle.loads(pickle.dumps(a.checkpoint()))
        n_a = a.advance_to(0.009, samples_a)
        wear_a = a.wear_profile()[1]
        buf_a = a.buf.copy()
        assert a.max_wear_depth_m() > 0.0
    with CoSimulation(joint, None, options, fmu_path=native_fmu, fmu_backend="native") as b:
        b.restore(saved)
        n_b = b.advance_to(0.009, samples_b)
        np.testing.assert_array_equal(b.buf, buf_a)
        np.testing.assert_array_equal(b.wear_profile()[1], wear_a)
    assert n_a == n_b and n_a > 0
    np.testing.assert_array_equal(samples_a[:n_a], samples_b[:n_b])



def test_rollbacks_on_one_reused_fmu_state_run_as_on_fresh_states(native_fmu):
    """The native FMU's rollback snapshot is overwritten in place (C_REUSE_STATE); freeing it and
    taking a new one each free-flight step gives the same run, to the last bit, with wear on."""
    options = CoSimulationOptions(revolutions=0.03, scheme="adaptive", step_s=2e-6)
    runs = []
    for reuse in (1.0, 0.0):
        samples = np.zeros((1400, L.N_SAMPLE_COLUMNS))
        with CoSimulation(paper_joint(), None, options, fmu_path=native_fmu, fmu_backend="native") as sim:
            sim._settings[master_layout.C_REUSE_STATE] = reuse
            n = sim.advance_to(0.012, samples)
            runs.append((sim.buf.copy(), sim.wear_profile()[1], samples[:n].copy(), sim.rollbacks, sim.free_steps,
                         sim.communication_steps))
    (buf, wear, samples, rollbacks, free, steps), other = runs
    np.testing.assert_array_equal(buf, other[0])
    np.testing.assert_array_equal(wear, other[1])
    np.testing.assert_array_equal(samples, other[2])
    assert (rollbacks, free, steps) == other[3:] and rollbacks >= 1 and 0 < free < steps and wear.max() > 0.0

SUMMARY_KEYS = ("revolutions", "simulated_time_s", "wall_time_s", "realtime_factor", "max_contact_force_N",
                "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                "max_eccentricity_m", "max_wear_depth_m", "max_wear_angle_deg", "worn_volume_m3", "parameters",
                "communication_steps", "rollbacks", "fmi_time_s", "master_time_s", "compile_time_s")


def test_cli_writes_the_results_contract(native_fmu, tmp_path, capsys):
    out = tmp_path / "run"
    code = cli.main(["cosim", "--revolutions", "0.02", "--out", str(out), "--quiet", "--fmu", str(native_fmu),
                     "--fmu-backend", "native", "--wear-factor", "0.1"])
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(SUMMARY_KEYS) <= set(summary)
    assert summary["parameters"]["engine"] == "cosim" and summary["parameters"]["fmu_backend"] == "native"
    # FMU loading and JIT compilation are reported apart: the real-time factor is the simulation's alone
    assert summary["compile_time_s"] > 0.0 and summary["wall_time_s"] > 0.0
    # the FMI time, estimated from a sample of the steps, never passes the run's wall time (150 steps here)
    assert summary["fmi_time_s"] >= 0.0 and summary["master_time_s"] >= 0.0
    assert summary["fmi_time_s"] + summary["master_time_s"] <= summary["wall_time_s"] * (1.0 + 1e-9)
    assert summary["realtime_factor"] == pytest.approx(summary["simulated_time_s"] / summary["wall_time_s"])
    assert summary["parameters"]["joint"]["wear_factor"] == 0.1
    assert summary["simulated_time_s"] == pytest.approx(0.02 * PERIOD_S)
    assert summary["max_wear_depth_m"] > 0.0 and summary["worn_volume_m3"] > 0.0
    profile = np.loadtxt(out / "profile.csv", delimiter=",", skiprows=1)
    assert profile.shape == (JointParameters().n_points, 2)
    assert profile[:, 1].max() == pytest.approx(summary["max_wear_depth_m"])
    with np.load(out / "timeseries.npz") as series:
        assert series["time_s"].size > 100 and "eccentricity_x_m" in series
    assert list(out.glob("*.png"))


@pytest.mark.parametrize("option, value, name", [("--friction-coefficient", "-1", "friction_coefficient"),
                                                 ("--step", "-1e-6", "step_s"),
                                                 ("--coupling-tolerance", "-0.1", "coupling_tolerance")])
def test_cli_bad_parameter_exits_nonzero_naming_it(native_fmu, tmp_path, capsys, option, value, name):
    code = cli.main(["cosim", "--revolutions", "0.01", "--out", str(tmp_path / "x"), "--quiet",
                     "--fmu", str(native_fmu), "--fmu-backend", "native", f"{option}={value}"])
    err = capsys.readouterr().err
    assert code != 0
    assert name in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


def test_fmu_error_gives_a_clear_message_and_frees_the_instance(native_fmu, monkeypatch):
    """Non-finite kinematics: the FMU rejects the call; the error carries its log; the instance is freed."""
    closed = []
    original_close = cosimulation.FmuInstance.close

    def spy_close(self):
        original_close(self)
        closed.append(self.instantiated)

    monkeypatch.setattr(cosimulation.FmuInstance, "close", spy_close)
    monkeypatch.setattr(cosimulation.SliderCrank, "initial_state", lambda self: np.full(2 * L.N_COORDINATES, np.nan))
    with pytest.raises(CoSimulationError, match=r"FMU call fmi2\w+ returned fmi2(Error|Discard).*non-finite inputs"):
        run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu, progress=False,
                         fmu_backend="native")
    assert closed == [False]


def test_fmu_error_inside_the_communication_loop_stops_there_with_the_fmus_message(native_fmu):
    """The numba master loop checks every FMI status: non-finite kinematics from step 1 on
    make getReal fail; the run stops at that point with the FMU's log in the error."""
    with CoSimulation(NO_WEAR, None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu,
                      fmu_backend="native") as sim:
        samples = np.zeros((1000, L.N_SAMPLE_COLUMNS))
        sim.advance_to(1e-4, samples)
        t_good = sim.t
        sim.buf[master_layout.B_Y:master_layout.B_Y + L.N_COORDINATES] = np.nan
        with pytest.raises(RunStopped, match=r"fmi2GetReal returned fmi2Error at t=.*non-finite inputs"):
            sim.advance_to(2e-4, samples)
        assert sim.t == t_good


@pytest.mark.parametrize("interface", ["co-simulation", "model-exchange"])
def test_a_run_an_fmu_error_stops_keeps_and_writes_what_came_before(native_fmu, tmp_path, monkeypatch, interface):
    """An FMU call that fails mid-run (getReal of non-finite kinematics, from the third chunk on) stops the run
    there: its first two chunks (25 ms of the paper's 0.4 s revolution each) are the record, ``completed: false``
    with the FMU's message, and the results folder is written."""
    engine, run = ((CoSimulation, lambda: run_cosimulation(paper_joint(), None, CoSimulationOptions(revolutions=0.5),
                                                           fmu_path=native_fmu, progress=False))
                   if interface == "co-simulation" else
                   (ModelExchangeSimulation, lambda: run_model_exchange(paper_joint(), None,
                                                                        SimulationOptions(revolutions=0.5),
                                                                        fmu_path=native_fmu, progress=False)))
    advance = engine.advance_to
    calls = []

    def poisoned(self, t_end, samples):
        calls.append(t_end)
        if len(calls) == 3:
            self.y[0] = np.nan
        return advance(self, t_end, samples)

    monkeypatch.setattr(engine, "advance_to", poisoned)
    record = run()
    assert not record.completed
    assert re.search(r"fmi2GetReal returned fmi2Error at t=0\.1\d* s.*non-finite inputs.*results before it are "
                     r"written", record.failure)
    assert record.simulated_time_s == pytest.approx(0.1) and record.samples[-1, L.T_TIME] == pytest.approx(0.1)
    assert record.worn_volume_m3 > 0.0
    summary = write_results(record, tmp_path / "out", plots=False)
    on_disk = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert on_disk["completed"] is False and on_disk["failure"] == record.failure == summary["failure"]


def test_fmu_engine_refuses_to_set_the_wear_profile():
    # the FMU has no input or parameter for its profile: cycle jumping must fail clearly, not silently
    from wearjoint.parameters import ParameterError
    with pytest.raises(ParameterError, match="wear profile"):
        CoSimulation.set_wear_profile(None, np.zeros(1257))
