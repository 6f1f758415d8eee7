"""The joint FMU's Model Exchange interface (docs/reference/fmu.md §5) inside the monolithic
integrator: no coupling error, so it must reproduce ``wearjoint simulate --integrator dopri``.  These test
the FMI glue: both sides run the same kernels, whose physics has its own tests (tests/core/)."""
import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")

from wearjoint import ClearanceJoint, JointParameters, paper_joint  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.cosim.model_exchange import ModelExchangeSimulation  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy_instance import Joint, contact_inputs, enter_initialisation  # noqa: E402
from wearjoint.simulate import Simulation, SimulationOptions  # noqa: E402


def _pair(native_fmu, joint, options):
    mono = Simulation(joint, None, options)
    me = ModelExchangeSimulation(joint, None, options, fmu_path=native_fmu, fmu_backend="native")
    return mono, me


def test_model_exchange_equals_the_monolithic_run_pointwise_over_15_ms(native_fmu):
    """With wear: the same steps and the same states through the first 15 ms (many impacts), up to
    rounding that the chaos grows (the FMU's wear step is a difference of its times, and the foundation
    sums an unworn window in closed form, 1e-13 from the sum point by point, so a rounding-level wear
    difference can change the path): measured 5.6e-6 N of ~1000 N at 12.6 ms."""
    options = SimulationOptions(revolutions=1, integrator="dopri", max_step_s=1e-5)
    mono, me = _pair(native_fmu, paper_joint(), options)
    try:
        a, b = np.zeros((4000, L.N_SAMPLE_COLUMNS)), np.zeros((4000, L.N_SAMPLE_COLUMNS))
        na, nb = mono.advance_to(0.015, a), me.advance_to(0.015, b)
        assert (mono.accepted, mono.rejected) == (me.accepted, me.rejected)
        assert na == nb and a[:na, L.T_CONTACT].any()
        ecc = np.hypot(a[:na, L.T_ECC_X] - b[:nb, L.T_ECC_X], a[:na, L.T_ECC_Y] - b[:nb, L.T_ECC_Y])
        assert ecc.max() <= 1e-9
        force = a[:na, L.T_NORMAL_FORCE]
        assert np.abs(force - b[:nb, L.T_NORMAL_FORCE]).max() <= 1e-6 * force.max()
    finally:
        me.close()


def test_without_wear_every_step_and_statistic_is_the_monolithic_runs(native_fmu):
    """Two revolutions: identical step counts, per-revolution statistics and final state; one
    event iteration at every contact onset the monolithic run counts."""
    options = SimulationOptions(revolutions=2, integrator="dopri")
    mono, me = _pair(native_fmu, paper_joint(wear_factor=0.0), options)
    try:
        samples = np.zeros((200_000, L.N_SAMPLE_COLUMNS))
        period = mono.mechanism.params.period_s
        mono.advance_to(2 * period, samples)
        me.advance_to(2 * period, samples)
        assert (mono.accepted, mono.rejected) == (me.accepted, me.rejected)
        assert np.array_equal(mono.revolution_stats, me.revolution_stats)
        assert np.array_equal(mono.y, me.y)
        onsets = int(mono.revolution_stats[:2, L.S_IMPACTS].sum())
        assert onsets > 100 and me.events[0] == onsets
    finally:
        me.close()


def test_wear_is_applied_only_at_completed_integrator_steps(native_fmu, tmp_path):
    """Stage evaluations (setTime/setReal/getReal) change nothing; fmi2CompletedIntegratorStep
    wears the bushing over the time since the last completed step, like ClearanceJoint.advance."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model

    joint = paper_joint()
    md = read_model_description(str(native_fmu))
    vr = fv.value_references(md)
    fmu = FMU2Model(guid=md.guid, unzipDirectory=extract(str(native_fmu), unzipdir=str(tmp_path)),
                    modelIdentifier=fv.MODEL_NAME, instanceName="me")
    fmu.instantiate()
    try:
        enter_initialisation(fmu, vr, joint)
        fmu.exitInitializationMode()
        fmu.newDiscreteStates()
        fmu.enterContinuousTimeMode()
        # the pin pressed 5 um into the bushing at the slider-crank's joint, crank at 0 rad
        pin = [0.0, 0.0, 0.0, 0.0, 0.0, -15.7]
        bushing = [0.025 - joint.bushing_offset_m[0] - (joint.clearance_m + 5e-6), 0.0, 0.0, 0.0, 0.0, 0.0]
        inputs = [vr[v.name] for v in fv.INPUTS]
        wear = [vr["max_wear_depth"], vr["worn_volume"]]
        for t in (1e-5, 2e-5, 1.5e-5):                  # trial stages, one of them "rejected"
            fmu.setTime(t)
            fmu.setReal(inputs, pin + bushing)
            assert fmu.getReal([vr["contact"]]) == [1.0]
            assert fmu.getReal(wear) == [0.0, 0.0]
        import ctypes

        indicator = (ctypes.c_double * 1)()
        fmu.getEventIndicators(indicator, 1)
        assert indicator[0] == pytest.approx(5e-6, rel=1e-9)      # the signed penetration
        fmu.setTime(3e-5)                                # a step of the whole wear interval (docs/reference/model.md §3.11)
        fmu.completedIntegratorStep()
        reference = ClearanceJoint(joint)
        reference.advance(pin, bushing, 3e-5)
        assert fmu.getReal(wear) == [reference.max_wear_depth_m, reference.worn_volume_m3]
        assert reference.max_wear_depth_m > 0.0
    finally:
        fmu.terminate()
        fmu.freeInstance()


def test_cli_runs_the_model_exchange_interface(native_fmu, tmp_path, capsys):
    import json

    from wearjoint import cli

    out = tmp_path / "me"
    code = cli.main(["cosim", "--fmu-interface", "model-exchange", "--revolutions", "0.05", "--out", str(out),
                     "--quiet", "--no-plots", "--fmu", str(native_fmu)])
    assert code == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["fmu_interface"] == "model-exchange"
    assert summary["integrator_accepted_steps"] > 0 and summary["max_wear_depth_m"] > 0.0


def test_cli_refuses_the_pythonfmu_backend_for_model_exchange(tmp_path, capsys):
    from wearjoint import cli

    code = cli.main(["cosim", "--fmu-interface", "model-exchange", "--fmu-backend", "pythonfmu", "--revolutions",
                     "0.01", "--out", str(tmp_path / "x"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "--fmu-backend='pythonfmu' (fmu_backend) is invalid" in err and "allowed native" in err
    assert len(err.strip().splitlines()) == 1



@pytest.mark.parametrize("version", [2, 3])
def test_a_time_before_the_last_completed_step_by_rounding_is_a_step_of_none(fmus, version):
    """CVODE's event location in fmusim set a time 1.4e-16 s before the last completed one, and the run ended with
    "step size -1.4e-16 s is not a finite value >= 0": rounding is a step of none, nothing worn; a time truly before
    it is refused, naming both times."""
    params = JointParameters(wear_factor=100.0)
    joint = Joint(fmus[version], version, "me").start(params)
    try:
        joint.set([v.name for v in fv.INPUTS], contact_inputs(params=params))
        t = 1e-5
        joint.fmu.setTime(t)
        joint.fmu.completedIntegratorStep()
        depth = joint.get(["max_wear_depth"])[0]
        joint.fmu.setTime(t - 1.4e-16)
        joint.fmu.completedIntegratorStep()
        assert depth > 0.0 and joint.get(["max_wear_depth"])[0] == depth and joint.errors() == ""
        joint.fmu.setTime(t - 1e-6)
        with pytest.raises(FMICallException):
            joint.fmu.completedIntegratorStep()
        assert "step rejected: the time t=9.0000000000000002e-06 s is before the last completed step's end, " \
               "9.99999999986" in joint.errors()
    finally:
        joint.free()
