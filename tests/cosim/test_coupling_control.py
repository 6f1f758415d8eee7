"""The coupling error of the adaptive scheme (and of the default, linearised): its estimate (the relative miss of the
predicted contact force) in every run's record and summary.json, and the contact step controlled to a tolerance
(``coupling_tolerance``)."""
import numpy as np
import pytest

from wearjoint.core import layout as L
from wearjoint.cosim import CoSimulation, CoSimulationOptions, run_cosimulation
from wearjoint.cosim.master_layout import (B_FORCES, B_LAST_STEP, B_OUTPUT, B_PREVIOUS_FORCES, O_CONTACT,
                                           buffer_views)
from wearjoint.cosim.master_loop import communication_step
from wearjoint.parameters import ParameterError, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

REVOLUTIONS = 0.15        # 60 ms: the first impacts and a stretch of contact on the paper's mechanism
NO_WEAR = paper_joint(wear_factor=0.0)


def run(native_fmu, scheme="adaptive", **options):
    return run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=REVOLUTIONS, scheme=scheme, **options),
                            fmu_path=native_fmu, progress=False)


@pytest.fixture(scope="module")
def fixed_rule(native_fmu):
    return run(native_fmu)


def test_every_adaptive_run_reports_its_force_miss(fixed_rule):
    extra = fixed_rule.extra
    assert extra["coupling_controlled_steps"] > 100          # steps in contact, each with an estimate
    assert 0.0 < extra["coupling_force_miss_rms"] <= extra["coupling_force_miss_max"]
    assert extra["coupling_controlled_steps"] <= extra["communication_steps"] - extra["free_steps"]


def test_a_tolerance_shortens_the_contact_steps_that_miss_it(native_fmu, fixed_rule):
    tolerance = 0.2 * fixed_rule.extra["coupling_force_miss_rms"]
    controlled = run(native_fmu, coupling_tolerance=tolerance)
    assert controlled.completed
    # (jumps of the force -- friction reversing, the deepest point moving on -- miss at any step: the rms falls less)
    assert controlled.extra["coupling_force_miss_rms"] < 0.9 * fixed_rule.extra["coupling_force_miss_rms"]
    assert controlled.extra["shrunk_steps"] > 0.2 * controlled.extra["coupling_controlled_steps"]
    assert fixed_rule.extra["shrunk_steps"] < 0.01 * fixed_rule.extra["coupling_controlled_steps"]


def test_a_loose_tolerance_keeps_the_fixed_rules_answer_within_its_scatter(native_fmu, fixed_rule):
    """Over 60 ms, before the runs part (chaos): the slider's path agrees to the micrometre."""
    loose = run(native_fmu, coupling_tolerance=0.3)
    t = fixed_rule.samples[:, 0]
    window = t < 0.02
    x_fixed = fixed_rule.samples[window, 2]
    x_loose = np.interp(t[window], loose.samples[:, 0], loose.samples[:, 2])
    assert np.max(np.abs(x_loose - x_fixed)) < 1e-6


@pytest.mark.parametrize("options, words", [({"coupling_tolerance": -0.1}, "coupling_tolerance=-0.1"),
                                            ({"coupling_tolerance": float("nan")}, "coupling_tolerance=nan"),
                                            ({"coupling_tolerance": 0.1, "scheme": "zoh"},
                                             "scheme is adaptive or linearised")])
def test_a_bad_tolerance_is_refused_naming_it(options, words):
    with pytest.raises(ParameterError, match="coupling_tolerance") as error:
        CoSimulationOptions(**options)
    assert words in str(error.value)


def test_the_defaults_contact_step_follows_its_tolerance(native_fmu):
    """The default (linearised) chooses its contact steps by the miss of its linear prediction: over the first four
    impacts (12 ms, before the runs part), ten times its tolerance takes under 0.6x the contact steps and misses over
    twice as much, a tenth of it over 1.5x the steps and under 0.8x the miss (1.77x and 0.68x: force jumps miss at
    any step, and no controlled step is shorter than step_s / 8, so the rms falls slower than the tolerance)."""
    assert CoSimulationOptions().scheme == "linearised" and CoSimulationOptions().coupling_tolerance == 0.003

    def first_impacts(tolerance):
        return run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=0.03, coupling_tolerance=tolerance),
                                fmu_path=native_fmu, progress=False)

    loose, default, tight = (first_impacts(0.003 * factor) for factor in (10.0, 1.0, 0.1))
    assert loose.extra["rollbacks"] == default.extra["rollbacks"] == tight.extra["rollbacks"] >= 3   # same onsets
    steps = [r.extra["communication_steps"] - r.extra["free_steps"] for r in (loose, default, tight)]
    miss = [r.extra["coupling_force_miss_rms"] for r in (loose, default, tight)]
    assert steps[0] < 0.6 * steps[1] and steps[2] > 1.5 * steps[1]
    assert miss[0] > 2.0 * miss[1] and miss[2] < 0.8 * miss[1]
    assert default.extra["shrunk_steps"] > 0.5 * steps[1]      # below step_s where the miss asked


def test_the_wear_of_a_step_does_not_drive_the_contact_step_below_an_eighth_of_step_s(native_fmu):
    """At 500x the paper's k_w the force a step's wear removes is a miss of the linear prediction at any step (rms
    0.027 at step_s / 16, 0.05 at step_s / 8): the control stops at step_s / 8 (at step_s / 16 it took 8x the steps
    of the adaptive scheme, 43 031 contact steps; now 21 517), so 30 ms take at most 30 ms / 1.25 us contact steps."""
    options = CoSimulationOptions(revolutions=0.075)      # 30 ms
    record = run_cosimulation(paper_joint(wear_factor=500.0), None, options, fmu_path=native_fmu, progress=False)
    contact_steps = record.extra["communication_steps"] - record.extra["free_steps"]
    assert record.extra["coupling_force_miss_rms"] > 0.01          # the wear's miss: over 3x the tolerance
    assert contact_steps <= record.simulated_time_s / (options.step_s / 8) + 1


@pytest.mark.parametrize("scheme", ["linearised", "adaptive"])
def test_at_accelerated_wear_the_cosimulation_wears_the_monolithic_volume(native_fmu, scheme):
    """Wear factor 100, one revolution (the pin settles in its groove; a 10 us step wears up to 0.7 of the
    penetration: docs/explanation/numerics.md's lambda): RK4 at 10 us (whose volume does not move with the step: docs/explanation/numerics.md) against the
    co-simulation, within 0.3 %.  The linearised coupling's wear takes the mean of the force it applies over a step
    (the FMU's step, its derivatives read: core.wear.accept_linearised_contact); with the force at the step's start
    it wore 4.4 % short here, the adaptive scheme's extrapolated force 0.01 % (measured)."""
    joint = paper_joint(wear_factor=100.0)
    monolithic = run_simulation(joint, None, SimulationOptions(revolutions=1, integrator="rk4", step_s=1e-5),
                                progress=False)
    cosim = run_cosimulation(joint, None, CoSimulationOptions(revolutions=1, scheme=scheme), fmu_path=native_fmu,
                             progress=False)
    assert cosim.worn_volume_m3 == pytest.approx(monolithic.worn_volume_m3, rel=3e-3)


@pytest.mark.parametrize("scheme", ["adaptive", "extrapolation"])
def test_a_step_after_a_much_shorter_one_holds_its_forces(native_fmu, scheme):
    """The forces' slope over a step shortened to end a span (1e-12 s, say) is rounding noise, or a wear batch's
    drop over no time: extrapolated over a whole step it threw the pin 0.5 mm into the wall of a wearing joint
    (the own-mechanism case of wearjoint.studies.coupling_accuracy from 90 degrees, at a chunk's end, with a wear
    batching under trial).  A step
    after one shorter than half of it holds the forces at t; after one of its own length it extrapolates them."""
    options = CoSimulationOptions(revolutions=REVOLUTIONS, scheme=scheme, step_s=5e-6)
    with CoSimulation(NO_WEAR, None, options, fmu_path=native_fmu) as sim:
        samples = np.zeros((20000, L.N_SAMPLE_COLUMNS))
        t = 0.03
        sim.advance_to(t, samples)
        while sim.outputs[O_CONTACT] < 0.5:          # on to a point in contact
            t += 1e-5
            sim.advance_to(t, samples)
        held = {}
        for last_step in (1e-12, 5e-6):
            buf = sim.buf.copy()
            buf[B_LAST_STEP] = last_step
            buf[B_PREVIOUS_FORCES:B_PREVIOUS_FORCES + 6] = buf[B_OUTPUT:B_OUTPUT + 6] - 1000.0    # a jump
            communication_step(sim.t, 5e-6, False, buf, *buffer_views(buf), sim.mechanism.workspace, samples)
            held[last_step] = buf[B_FORCES:B_FORCES + 6] - buf[B_OUTPUT:B_OUTPUT + 6]
    np.testing.assert_array_equal(held[1e-12], 0.0)
    np.testing.assert_allclose(held[5e-6], 0.5 * 1000.0)       # the mean of the extrapolation over the step
