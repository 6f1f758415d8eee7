"""A run whose pin goes further into the bushing wall than the joint admits stops there, says why, and keeps what
came before (wearjoint.runner.divergence, analysis.pin_left_bushing; docs/reference/model.md §3.14): never `completed: true`
with a pin through the wall."""
import math

import numpy as np
import pytest

from wearjoint import analysis
from wearjoint.checks import RunDiverged
from wearjoint.cli.options import exit_status
from wearjoint.core import layout as L
from wearjoint.parameters import JointParameters
from wearjoint.results import new_revolution_stats
from wearjoint.runner import divergence, run_in_chunks

JOINT = JointParameters(pin_radius_m=0.01, bushing_radius_m=0.0101)
CLEARANCE_M = 1e-4
ADMISSIBLE_M = 2e-4            # 2 % of the pin's 10 mm radius
PERIOD_S = 0.4


class EngineLeavingTheBushing:
    """A stand-in engine whose pin circles at the clearance plus 1 um, until ``diverge_at_s``, after which
    its eccentricity doubles every sample (a numerical blow-up); the bushing has worn ``wear_m``."""

    def __init__(self, diverge_at_s, wear_m=0.0):
        self.t, self.diverge_at_s, self.wear_m = 0.0, diverge_at_s, wear_m
        self.revolution_stats = new_revolution_stats(2)
        self.joint_parameters = JOINT

    def warm_up(self):
        pass

    def advance_to(self, t_end, samples):
        times = self.t + 1e-3 * np.arange(1, round((t_end - self.t) / 1e-3) + 1)
        e = (CLEARANCE_M + self.wear_m + 1e-6) * np.where(times > self.diverge_at_s,
                                                           2.0 ** np.minimum(60, (times - self.diverge_at_s) / 1e-3),
                                                           1.0)
        n = len(times)
        samples[:n] = 0.0
        samples[:n, L.T_TIME] = times
        samples[:n, L.T_ECC_X] = e * np.cos(times)
        samples[:n, L.T_ECC_Y] = e * np.sin(times)
        self.t = t_end
        return n

    def max_wear_depth_m(self):
        return self.wear_m

    def close(self):
        pass


@pytest.mark.parametrize("wear_m", [0.0, 3e-4])
def test_the_pin_may_sit_in_its_groove_but_not_past_the_admissible_penetration(wear_m):
    assert JOINT.admissible_penetration_m == pytest.approx(ADMISSIBLE_M)
    limit = CLEARANCE_M + wear_m + ADMISSIBLE_M
    assert analysis.pin_left_bushing(limit * (1 - 1e-9), CLEARANCE_M, wear_m, ADMISSIBLE_M) == ""
    assert "into the bushing wall" in analysis.pin_left_bushing(limit * (1 + 1e-9), CLEARANCE_M, wear_m, ADMISSIBLE_M)
    assert "not finite" in analysis.pin_left_bushing(math.nan, CLEARANCE_M, wear_m, ADMISSIBLE_M)


def test_an_excursion_between_samples_is_caught_by_the_revolutions_largest_eccentricity():
    """The per-revolution statistics hold the largest eccentricity of every accepted point: a blow-up that the
    samples (every 10 us) miss is still a divergence."""
    engine = EngineLeavingTheBushing(diverge_at_s=math.inf)
    samples = np.zeros((4, L.N_SAMPLE_COLUMNS))
    samples[:, L.T_TIME] = [1e-3, 2e-3, 3e-3, 4e-3]
    assert divergence(engine, samples, JOINT) == ""
    engine.revolution_stats[0, L.S_TIME] = 4e-3
    engine.revolution_stats[0, L.S_ECC_MAX] = 0.01                       # 10 mm: through the wall
    assert "into the bushing wall" in divergence(engine, samples, JOINT)


def test_a_diverging_run_stops_after_the_chunk_keeping_the_chunks_before():
    run = run_in_chunks(lambda: EngineLeavingTheBushing(diverge_at_s=0.12), revolutions=1.0, period_s=PERIOD_S,
                        sample_dt_s=1e-3, label="test", progress=False)
    assert not run.completed and "diverged at t = 0.122 s" in run.failure and "into the bushing wall" in run.failure
    assert run.engine.t == pytest.approx(0.15)                   # the third chunk of 0.05 s, not the eighth
    times = run.samples[:, L.T_TIME]                              # the chunks before are kept
    assert times[-1] == pytest.approx(0.15) and times[0] <= 1e-3 and np.all(np.diff(times) > 0)


class EngineRefusedMidChunk(EngineLeavingTheBushing):
    """A stand-in engine whose call stops at ``stop_at_s`` inside a chunk, as an engine whose joint refused a step
    does (RunDiverged), with the samples it wrote before."""

    def __init__(self, stop_at_s):
        super().__init__(diverge_at_s=math.inf)
        self.stop_at_s = stop_at_s

    def advance_to(self, t_end, samples):
        if t_end < self.stop_at_s:
            return super().advance_to(t_end, samples)
        n = super().advance_to(self.stop_at_s, samples)
        raise RunDiverged(f"the run diverged at t = {self.stop_at_s:g} s: a step refused", n)


def test_a_run_stopped_inside_a_chunk_keeps_that_chunks_samples_before_it():
    """A co-simulation whose coupling blew up 9 ms into its first chunk wrote an empty time series."""
    run = run_in_chunks(lambda: EngineRefusedMidChunk(stop_at_s=0.07), revolutions=1.0, period_s=PERIOD_S,
                        sample_dt_s=1e-3, label="test", progress=False)
    assert not run.completed and "diverged at t = 0.07 s" in run.failure
    times = run.samples[:, L.T_TIME]
    assert times.size == 70 and times[-1] == pytest.approx(0.07) and np.all(np.diff(times) > 0)


def test_a_physical_run_completes_and_a_worn_groove_is_no_divergence():
    run = run_in_chunks(lambda: EngineLeavingTheBushing(diverge_at_s=math.inf, wear_m=5e-4), revolutions=1.0,
                        period_s=PERIOD_S, sample_dt_s=1e-3, label="test", progress=False)
    assert run.completed and run.failure == "" and run.engine.t == pytest.approx(PERIOD_S)


def test_non_finite_samples_are_a_divergence():
    engine = EngineLeavingTheBushing(diverge_at_s=math.inf)
    samples = np.zeros((4, L.N_SAMPLE_COLUMNS))
    samples[2, L.T_NORMAL_FORCE] = math.nan
    assert "not finite" in divergence(engine, samples, JOINT)


def test_the_command_exits_1_naming_the_failure(capsys):
    class Record:
        failure, completed = "the run diverged by t = 0.15 s: the pin left the bushing", False
    assert exit_status(Record(), "simulate") == 1
    assert capsys.readouterr().err == "wearjoint simulate: error: the run diverged by t = 0.15 s: the pin left the bushing\n"


@pytest.mark.parametrize("command", ["simulate", "cosim"])
@pytest.mark.parametrize("option, allowed", [("--slider-force-N=1e300", "allowed in [-1e+09, 1e+09]"),
                                             ("--gravity-m-s2=1e300", "allowed one finite value g in [0, 10000]")])
def test_a_load_too_large_for_double_precision_is_refused_naming_its_option(tmp_path, capsys, command, option, allowed):
    """A finite slider load or gravity of 1e300 overflowed the state on the first step ("put the pin nan m into the
    wall ... take a shorter step"; through the FMU "fmi2GetReal returned fmi2Error ... non-finite inputs" and no
    results): refused before the run, naming the option and its range."""
    from wearjoint.cli import main

    assert main([command, option, "--revolutions", "0.01", "--no-plots", "--quiet", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"wearjoint {command}: error: {option} (") and allowed in err, err
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("command", ["simulate", "cosim"])
def test_a_load_beyond_the_joint_is_named_not_blamed_on_the_step(tmp_path, capsys, command):
    """300 kN on the paper's slider: the ideal joint carries up to 3.08e5 N, beyond the 2.25e5 N the paper's joint
    admits (K delta_adm^1.5): the run stops, exit 1, saying no step helps (it said "take a shorter step or an adaptive
    integrator" to a run already adaptive); 2 kN: none of it."""
    from wearjoint import SliderCrankParameters, paper_joint
    from wearjoint.cli import main
    from wearjoint.runner import overload_advice
    from wearjoint.slider_crank import SliderCrank

    heavy = SliderCrank(SliderCrankParameters(slider_force_N=3e5))
    advice = overload_advice(paper_joint(), heavy)
    ideal = float(heavy.ideal_joint_force(np.linspace(0.0, heavy.params.period_s, 2001)).max())
    assert ideal > paper_joint().admissible_force_N and f"up to {ideal:.3g} N" in advice
    assert overload_advice(paper_joint(), SliderCrank(SliderCrankParameters(slider_force_N=2e3))) is None
    assert main([command, "--slider-force-N=3e5", "--revolutions", "0.05", "--no-plots", "--quiet", "--out",
                 str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "no step helps: the machine's own loads put up to" in err and "shorter step or an adaptive" not in err


def test_a_pin_past_the_whole_bushing_is_said_to_have_left_the_joint():
    """RK4 at 0.3 ms put the pin 902 m "into the bushing wall with a normal force of 0 N": the contact law is no
    measure that far out, and the message says the joint came apart instead."""
    from wearjoint.runner import inadmissible_message

    far = inadmissible_message(0.0036, 902.0, 0.0, JOINT, "an accepted step", 0.0)
    assert "put the pin 902 m past the bushing wall, more than the bushing's radius" in far and "came apart" in far
    near = inadmissible_message(0.0036, 5e-4, 3e5, JOINT, "an accepted step", 0.0)
    assert "put the pin 0.0005 m into the bushing wall" in near and "came apart" not in near
