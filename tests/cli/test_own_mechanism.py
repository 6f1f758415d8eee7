"""A slider-crank that is not the paper's (docs/tutorials/own_mechanism.md): its own dimensions, speed and
materials reach the contact in every engine and in what the build writes."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters, SliderCrankParameters
from wearjoint.parameters import paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

# a longer crank and rod at twice the speed, a larger pin with more clearance, a bronze bushing
MECHANISM = SliderCrankParameters(crank_length_m=0.08, rod_length_m=0.3, crank_speed_rpm=300.0, slider_mass_kg=1.2)
MATERIALS = {"pin_radius_m": 0.012, "bushing_radius_m": 0.01215, "contact_length_m": 0.01,
             "bushing_youngs_modulus_Pa": 110e9, "bushing_poisson_ratio": 0.34}
MODEL_OPTIONS = ["--crank-length-m", "0.08", "--rod-length-m", "0.3", "--crank-speed-rpm", "300",
                 "--slider-mass-kg", "1.2", "--pin-radius-m", "0.012", "--bushing-radius-m", "0.01215",
                 "--contact-length-m", "0.01", "--bushing-youngs-modulus-Pa", "110e9", "--bushing-poisson-ratio", "0.34"]


def own_joint(**changes) -> JointParameters:
    return paper_joint(MECHANISM, **{**MATERIALS, **changes})


def k_by_hand(joint: JointParameters) -> float:
    """Eqs. 16-17, internal contact: K = 4/(3 pi (h_i + h_j)) sqrt(R_i R_j / (R_j - R_i)), h = (1 - nu^2)/(pi E)."""
    h = sum((1.0 - nu * nu) / (math.pi * e) for e, nu in ((joint.pin_youngs_modulus_Pa, joint.pin_poisson_ratio),
                                                          (joint.bushing_youngs_modulus_Pa, joint.bushing_poisson_ratio)))
    r = joint.pin_radius_m * joint.bushing_radius_m / (joint.bushing_radius_m - joint.pin_radius_m)
    return 4.0 / (3.0 * math.pi * h) * math.sqrt(r)


def wearjoint(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def _first_impact(joint: JointParameters) -> dict:
    """The first 20 ms (before chaos separates trajectories): the largest normal force."""
    options = SimulationOptions(revolutions=0.02 / MECHANISM.period_s, integrator="rk4", step_s=5e-6)
    record = run_simulation(joint, MECHANISM, options, progress=False)
    return record.summary()


def test_the_bushings_modulus_sets_the_force_and_a_given_stiffness_overrides_it():
    steel = own_joint()
    polymer = own_joint(bushing_youngs_modulus_Pa=3e9, bushing_poisson_ratio=0.4)
    assert steel.stiffness_N_m1_5 == pytest.approx(k_by_hand(steel), rel=1e-12)
    assert polymer.stiffness_N_m1_5 == pytest.approx(k_by_hand(polymer), rel=1e-12)
    stiff, soft = _first_impact(steel), _first_impact(polymer)
    assert stiff["contact_stiffness_N_m1_5"] == pytest.approx(k_by_hand(steel), rel=1e-12)
    # a Hertz impact's peak force grows as K^(2/5): 25x softer, at least 2x less force
    assert soft["max_contact_force_N"] < 0.5 * stiff["max_contact_force_N"]
    # a given K overrides the materials: the same forces whatever the modulus (the foundation wear uses K alone)
    given = {"contact_stiffness_N_m1_5": 5e10}
    a, b = _first_impact(own_joint(**given)), _first_impact(own_joint(bushing_youngs_modulus_Pa=3e9, **given))
    assert a["max_contact_force_N"] == b["max_contact_force_N"]
    assert a["contact_stiffness_N_m1_5"] == 5e10


def test_the_cli_states_the_stiffness_it_uses_and_notes_an_override(tmp_path):
    done = wearjoint("simulate", "--revolutions", "0.05", "--no-plots", "--out", str(tmp_path / "own"),
                     "--bushing-youngs-modulus-Pa", "3e9", *MODEL_OPTIONS[:-4])
    assert done.returncode == 0, done.stderr
    summary = json.loads((tmp_path / "own" / "summary.json").read_text())
    assert summary["parameters"]["joint"]["contact_stiffness_N_m1_5"] is None
    assert summary["contact_stiffness_N_m1_5"] == pytest.approx(k_by_hand(own_joint(bushing_youngs_modulus_Pa=3e9,
                                                                              bushing_poisson_ratio=0.33)),
                                                                rel=1e-12)
    assert "note: --contact-stiffness" not in done.stderr
    done = wearjoint("simulate", "--revolutions", "0.01", "--no-plots", "--out", str(tmp_path / "given"),
                     "--contact-stiffness-N-m1-5", "4e10", *MODEL_OPTIONS)
    assert done.returncode == 0, done.stderr
    assert "note: --contact-stiffness-N-m1-5 4e+10 overrides the" in done.stderr
    summary = json.loads((tmp_path / "given" / "summary.json").read_text())
    assert summary["contact_stiffness_N_m1_5"] == 4e10
    done = wearjoint("simulate", "--revolutions", "0.01", "--out", str(tmp_path / "bad"), "--contact-model", "deepest",
                     "--contact-exponent", "2")
    assert done.returncode == 2 and "--contact-exponent=2 (contact_exponent) is invalid" in done.stderr
    assert len(done.stderr.strip().splitlines()) <= 3 and "Traceback" not in done.stderr


def test_the_paper_joint_keeps_table_2s_stiffness():
    """Table 2 prints K = 7.95e10; its radii and materials give 7.951e10 (docs/reference/model.md §3.1)."""
    assert JointParameters().stiffness_N_m1_5 == pytest.approx(7.95e10, rel=2e-4)
    assert np.isclose(JointParameters().stiffness_N_m1_5, k_by_hand(JointParameters()), rtol=1e-12)


def _starts(fmu_path) -> dict:
    from fmpy import read_model_description

    return {v.name: (int(v.start) if v.type in ("Integer", "Enumeration") else float(v.start))
            for v in read_model_description(str(fmu_path)).modelVariables if v.causality == "parameter"}


def test_build_fmu_writes_the_mechanisms_parameters_as_start_values(tmp_path):
    """The joint FMU built for this mechanism starts with its radii, materials and centres (read back
    through fmpy) and computes with them when the host sets nothing; SliderCrank.fmu with its dimensions."""
    fmpy = pytest.importorskip("fmpy")
    from fmpy_instance import Slave, contact_inputs

    from wearjoint.fmu import slider_crank as sc
    from wearjoint.fmu import variables as fv

    done = wearjoint("build-fmu", "--out", str(tmp_path / "joint"), "--platforms", "linux64", *MODEL_OPTIONS)
    assert done.returncode == 0, done.stderr
    joint_fmu = tmp_path / "joint" / "ClearanceWearJoint.fmu"
    starts = _starts(joint_fmu)
    assert fv.joint_parameters_from_fmi(starts, 1257) == own_joint()
    assert starts["pin_radius"] == 0.012 and starts["bushing_offset_x"] == -0.15 and starts["contact_stiffness"] == 0.0
    assert "start values: pin_radius=0.012" in done.stderr
    from wearjoint.cosim.step_rule import communication_step_rule

    assert communication_step_rule(own_joint(), MECHANISM).text() in done.stderr     # the rule for these parameters
    x = contact_inputs(depth=4e-6, params=own_joint())
    md = fmpy.read_model_description(str(joint_fmu))
    s = Slave({"md": md, "dir": fmpy.extract(str(joint_fmu), unzipdir=str(tmp_path / "unzipped")),
               "vr": fv.value_references(md)}, "own").initialise()
    s.set_inputs(x)
    expected = ClearanceJoint(own_joint()).evaluate(x[:6], x[6:])
    assert expected.normal_force_N > 100.0
    assert s.get(["normal_force"])[0] == pytest.approx(expected.normal_force_N, rel=1e-12)
    s.free()

    done = wearjoint("build-fmu", "--model", "slider-crank", "--out", str(tmp_path / "sc"), "--platforms", "linux64",
                     *MODEL_OPTIONS[:8])
    assert done.returncode == 0, done.stderr
    assert _starts(tmp_path / "sc" / "SliderCrank.fmu") == {**sc.parameter_values(MECHANISM),
                                                           sc.MAX_INTERNAL_STEP_NAME: sc.MAX_INTERNAL_STEP_START,
                                                           sc.LOAD_COUPLING_NAME: float(sc.LOAD_COUPLING_HOLD)}
    done = wearjoint("build-fmu", "--model", "slider-crank", "--out", str(tmp_path / "bad"), "--pin-radius-m", "0.012")
    assert done.returncode == 2
    assert "--pin-radius-m is a joint parameter: it applies to --model joint" in done.stderr


def test_export_ssp_carries_the_mechanisms_parameter_sets(tmp_path):
    """The SSP's parameter sets and its two FMUs' start values are this mechanism's (read back)."""
    pytest.importorskip("fmpy")
    import zipfile
    from xml.etree import ElementTree

    from wearjoint.fmu import slider_crank as sc
    from wearjoint.fmu import ssp
    from wearjoint.fmu import variables as fv

    done = wearjoint("export-ssp", "--out", str(tmp_path), "--platforms", "linux64", *MODEL_OPTIONS)
    assert done.returncode == 0, done.stderr
    assert "note: k_w = 5.05e-10 m^2/N is the paper's" in done.stderr      # this machine wears on the paper's k_w
    with zipfile.ZipFile(tmp_path / ssp.SSP_FILE_NAME) as z:
        z.extractall(tmp_path / "unzipped")
    resources = tmp_path / "unzipped" / "resources"

    def parameter_set(name):
        root = ElementTree.parse(resources / f"{name}.ssv").getroot()
        return {p.get("name"): float(p[0].get("value")) for p in root.iter("{%s}Parameter" % ssp.SSV)}

    joint = {k: float(v) for k, v in fv.fmi_parameter_values(own_joint()).items()}
    assert parameter_set(ssp.JOINT) == joint
    assert parameter_set(ssp.MECHANISM) == {**sc.parameter_values(MECHANISM),
                                            sc.LOAD_COUPLING_NAME: float(sc.LOAD_COUPLING_LINEARISED)}
    assert fv.joint_parameters_from_fmi(_starts(resources / "ClearanceWearJoint.fmu"), 1257) == own_joint()
    mechanism_starts = _starts(resources / "SliderCrank.fmu")
    assert {k: mechanism_starts[k] for k in sc.parameter_values(MECHANISM)} == sc.parameter_values(MECHANISM)
    # the step the package asks for: the paper's measured 5 us (the loads linearised) scaled by the step rule
    # (docs/explanation/cosim_study.md)
    from wearjoint.cosim.step_rule import communication_step_rule

    ssd = ElementTree.parse(tmp_path / "unzipped" / "SystemStructure.ssd").getroot()
    step = float(next(e for e in ssd.iter() if e.tag.endswith("FixedStepAlgorithm")).get("baseStepSize"))
    own, paper = communication_step_rule(own_joint(), MECHANISM), communication_step_rule()
    scale = min(own.on_time_s / paper.on_time_s, own.groove_on_time_s / paper.groove_on_time_s)   # it wears
    assert own_joint().wear_factor > 0.0
    # the scaled step, shortened to a whole number of steps per revolution
    steps = math.ceil(MECHANISM.period_s / (ssp.DEFAULT_STEP_S["linearised"] * scale))
    assert scale < 1.0 and step == pytest.approx(MECHANISM.period_s / steps, rel=1e-12)


def _ideal_pin_force(t, m: SliderCrankParameters):
    """The ideal crank-rod revolute's force on the crank [N] by Newton-Euler on the rod and the slider:
    positions in closed form (theta1 = theta0 - omega t), accelerations by central differences."""
    def positions(time):
        th1 = math.radians(m.initial_crank_angle_deg) - m.omega_rad_s * time
        px, py = m.crank_length_m * np.cos(th1), m.crank_length_m * np.sin(th1)
        xs = px + np.sqrt(m.rod_length_m ** 2 - py ** 2)
        th2 = np.arctan2(-py, xs - px)
        return px, py, xs, 0.5 * (px + xs), 0.5 * py, th2

    h = 1e-5
    before, now, after = positions(t - h), positions(t), positions(t + h)
    acc = [(a - 2 * b + c) / h ** 2 for a, b, c in zip(before, now, after)]
    px, py, xs, gx, gy, _ = now
    _, _, a_s, a_gx, a_gy, alpha2 = acc
    # rod: m2 a_G = F_P + F_S - m2 g e_y, I2 alpha2 = (P - G) x F_P + (S - G) x F_S; slider x: F_S,x = -m3 a_s
    f_sx = -m.slider_mass_kg * a_s
    f_px = m.rod_mass_kg * a_gx - f_sx
    # two unknowns F_P,y, F_S,y: F_P,y + F_S,y = m2 (a_Gy + g); (P-G)_x F_Py - (P-G)_y F_Px + (S-G)_x F_Sy - (S-G)_y F_Sx = I2 alpha2
    rpx, rpy, rsx, rsy = px - gx, py - gy, xs - gx, -gy
    total = m.rod_mass_kg * (a_gy - m.gravity_m_s2[1])       # gravity (0, g_y), g_y = -9.81
    moment = m.rod_inertia_kg_m2 * alpha2 + rpy * f_px + rsy * f_sx
    f_py = (moment - rsx * total) / (rpx - rsx)
    return -f_px, -f_py            # on the crank (the pin body)


def test_ideal_reports_the_ideal_revolutes_reaction():
    options = SimulationOptions(revolutions=0.5, integrator="dopri", rtol=1e-9, atol_position_m=1e-12,
                                atol_velocity_m_s=1e-9, sample_dt_s=1e-3, ideal=True)
    record = run_simulation(own_joint(), MECHANISM, options, progress=False)
    t = record.samples[:, 0]
    fx, fy = _ideal_pin_force(t, MECHANISM)
    scale = np.max(np.hypot(fx, fy))
    assert scale > 100.0
    np.testing.assert_allclose(record.samples[:, 5], fx, atol=1e-4 * scale)
    np.testing.assert_allclose(record.samples[:, 6], fy, atol=1e-4 * scale)
    assert record.summary()["max_contact_force_N"] == pytest.approx(scale, rel=1e-3)


# ------------------------------------------------------------------ the start-up transient and the regimes
def test_the_start_up_transient_is_reported_apart():
    from wearjoint import analysis
    from wearjoint.core import layout as L
    from wearjoint.results import new_revolution_stats

    stats = new_revolution_stats(3)
    for k, (force, ecc) in enumerate(((5400.0, 3e-4), (180.0, 1.6e-4), (200.0, 1.5e-4))):
        stats[k, [L.S_TIME, L.S_FORCE_MAX, L.S_ECC_MAX, L.S_ACC_MAX, L.S_ACC_MIN]] = (0.2, force, ecc, 10.0, -10.0)
    steady = analysis.run_statistics(stats)
    assert steady["max_contact_force_N"] == 200.0 and steady["max_eccentricity_m"] == 1.6e-4
    assert steady["statistics_from_revolution"] == 1 and steady["start_up"]["max_contact_force_N"] == 5400.0
    whole = analysis.run_statistics(stats, settling_revolutions=0)
    assert whole["max_contact_force_N"] == 5400.0 and "start_up" not in whole
    one = analysis.run_statistics(stats[:1])      # a run that has not passed its start-up keeps it, and says so
    assert one["max_contact_force_N"] == 5400.0 and one["statistics_from_revolution"] == 0
    assert "included" in one["start_up"]
    longer = analysis.run_statistics(stats, settling_revolutions=5)    # nor does a run shorter than the start-up
    assert longer["max_contact_force_N"] == 5400.0 and longer["statistics_from_revolution"] == 0
    assert longer["start_up"] == ("included: the run ends in revolution 2, before more than half of revolution 5 (the "
                                  "first after the 5 start-up revolution(s)) is run")
    # a run of 1.3 revolutions ends in revolution 1 (it had said 0: the last counted one)
    sliver = stats[:2].copy()
    sliver[1, L.S_TIME] = 0.3 * 0.2 / 1.0
    assert analysis.run_statistics(sliver)["start_up"].startswith("included: the run ends in revolution 1, ")
    assert analysis.run_statistics(stats, settling_revolutions=2)["statistics_from_revolution"] == 2


def _orbit(rate_rad_s, spin_rad_s, contact=1.0, n=400, dt=1e-5, radius=1e-4):
    from wearjoint.core import layout as L

    t = np.arange(n) * dt
    samples = np.zeros((n, L.N_SAMPLE_COLUMNS))
    samples[:, L.T_TIME] = t
    samples[:, L.T_ECC_X], samples[:, L.T_ECC_Y] = radius * np.cos(rate_rad_s * t), radius * np.sin(rate_rad_s * t)
    samples[:, L.T_RELATIVE_OMEGA] = spin_rad_s
    samples[:, L.T_CONTACT] = contact
    return samples


def test_a_backward_whirl_is_named_and_a_load_following_contact_is_not():
    """A pin rolling inside the bushing turns its contact point at -omega_rel R_i / c (here 100 omega_rel): whirl;
    the contact point following the load back by less than a turn, or turning forward, or the pin in free
    flight: not; a contact no sample leaves is permanent, one that leaves it once impacting."""
    from wearjoint import analysis
    from wearjoint.core import layout as L

    spin = 157.0
    assert analysis.regime(_orbit(-100 * spin, spin)) == {"regime": "backward whirl", "whirl_fraction": 1.0}
    following = _orbit(-0.5 * spin, spin)         # 0.3 rad in the 4 ms, never out of contact
    assert analysis.regime(following)["regime"] == "permanent contact"
    following[200, L.T_CONTACT] = 0.0             # one sample in free flight: it left the contact
    assert analysis.regime(following)["regime"] == "impacting"
    interrupted = _orbit(-100 * spin, spin)
    interrupted[::20, L.T_CONTACT] = 0.0          # contact spells of 0.2 ms, 0.3 turn each
    assert analysis.whirl_fraction(interrupted) == 0.0 and analysis.regime(interrupted)["regime"] == "impacting"
    assert analysis.regime(_orbit(+100 * spin, spin))["whirl_fraction"] == 0.0
    assert analysis.regime(_orbit(-100 * spin, spin, contact=0.0))["whirl_fraction"] == 0.0
    record = run_simulation(options=SimulationOptions(revolutions=0.5, integrator="rk4", step_s=1e-5),
                            progress=False)
    assert record.summary()["regime"] == "impacting"           # the paper's mechanism over half a revolution


# ------------------------------------------------------------------ validate on this mechanism
def test_validate_quick_runs_on_this_mechanism_and_fails_a_perturbed_engine(tmp_path):
    """At 600 rpm a revolution is 0.1 s: the quick plan's 0.1 revolution is 10 ms, its point-wise window scaled
    to the period (3.75 ms, the paper's 15 ms of a 0.4 s turn); the co-simulation passes, and fails with a
    restitution of 0.7 instead of 0.9 (the window's contact forces differ by kN where the scatter is 0.1 kN)."""
    fast = MECHANISM.replace(crank_speed_rpm=600.0)
    common = ["--quick", "--engines", "monolithic,cosim", "--quiet", *MODEL_OPTIONS[:4], "--crank-speed-rpm", "600",
              *MODEL_OPTIONS[6:]]
    done = wearjoint("validate", *common, "--out", str(tmp_path / "same"))
    assert done.returncode == 0, done.stdout + done.stderr
    summary = json.loads((tmp_path / "same" / "summary.json").read_text())
    assert summary["plan"]["window_s"] == pytest.approx(0.015 * fast.period_s / SliderCrankParameters().period_s)
    done = wearjoint("validate", *common, "--perturb", "cosim", "restitution=0.7", "--out", str(tmp_path / "perturbed"))
    assert done.returncode == 1, done.stdout + done.stderr
    failed = json.loads((tmp_path / "perturbed" / "summary.json").read_text())["metrics_failed"]
    assert any("normal_force_max_difference_N" in str(m) for m in failed), failed


# ------------------------------------------------------------------ a given worn profile
def test_a_uniformly_worn_profile_is_a_larger_bushing():
    """A bushing worn 20 um all round is a bushing 20 um larger: with the deepest-point contact (its force
    K delta^n of the penetration alone) and no wear, the two runs agree over the first 20 ms."""
    mechanism = SliderCrankParameters()
    joint = paper_joint(mechanism, contact_model="deepest", contact_stiffness_N_m1_5=7.95e10, wear_factor=0.0)
    options = SimulationOptions(revolutions=0.05, integrator="rk4", step_s=2e-6)
    worn = run_simulation(joint, mechanism, options, progress=False,
                          initial_profile_m=np.full(joint.n_points, 20e-6))
    larger = run_simulation(joint.replace(bushing_radius_m=joint.bushing_radius_m + 20e-6), mechanism, options,
                            progress=False)
    assert worn.summary()["max_wear_depth_m"] == 20e-6 and worn.summary()["max_contact_force_N"] > 100.0
    np.testing.assert_allclose(worn.samples[:, 9:11], larger.samples[:, 9:11], rtol=0, atol=1e-9)   # eccentricity
    np.testing.assert_allclose(worn.samples[:, 7], larger.samples[:, 7], rtol=0,
                               atol=1e-6 * larger.samples[:, 7].max())                          # normal force


def test_simulate_starts_from_a_profile_file_and_refuses_one_that_does_not_fit(tmp_path):
    done = wearjoint("simulate", "--revolutions", "0.05", "--no-plots", "--quiet", "--wear-factor", "20",
                     "--out", str(tmp_path / "first"))
    assert done.returncode == 0, done.stderr
    first = np.loadtxt(tmp_path / "first" / "profile.csv", delimiter=",", skiprows=1)
    done = wearjoint("simulate", "--revolutions", "0.01", "--no-plots", "--quiet", "--no-wear", "--initial-profile",
                     str(tmp_path / "first" / "profile.csv"), "--out", str(tmp_path / "again"))
    assert done.returncode == 0, done.stderr
    again = np.loadtxt(tmp_path / "again" / "profile.csv", delimiter=",", skiprows=1)
    assert first[:, 1].max() > 0.0 and np.array_equal(again, first)          # without wear it stays as given
    said = json.loads((tmp_path / "again" / "summary.json").read_text())["initial_profile"]
    assert said == {"file": str(tmp_path / "first" / "profile.csv"), "max_wear_depth_m": first[:, 1].max()}
    done = wearjoint("simulate", "--ideal", "--revolutions", "0.01", "--initial-profile",
                     str(tmp_path / "first" / "profile.csv"), "--out", str(tmp_path / "ideal"))
    assert done.returncode == 2 and "only without --ideal (the ideal joint has no bushing)" in done.stderr
    done = wearjoint("simulate", "--revolutions", "0.01", "--n-points", "628", "--initial-profile",
                     str(tmp_path / "first" / "profile.csv"), "--out", str(tmp_path / "bad"))
    assert done.returncode == 2 and "--initial-profile" in done.stderr and "628 bushing points" in done.stderr
    assert "Traceback" not in done.stderr


def test_cosim_study_scales_its_window_with_the_period_and_its_steps_with_the_stiffness():
    """15 ms of the paper's 0.4 s turn is 7.5 ms at 300 rpm.  The step rule's on-time limit goes as
    (m/k)^(1/2), k ~ K^(2/3) F^(1/3) and the estimated F ~ K^(2/5): a joint 8x stiffer takes 8^(-0.4) of the
    paper's steps; one that wears 8^(-0.5), its groove's stiffness (pi/2) k_f L R_i ~ K setting the limit once one
    forms; a softer one keeps them."""
    from wearjoint.studies.cosim_study import PAPER_STEPS_S, default_steps_s, pointwise_window_s

    assert pointwise_window_s(MECHANISM) == pytest.approx(0.0075, rel=1e-12)
    paper = paper_joint()
    stiff = paper.replace(contact_stiffness_N_m1_5=8.0 * paper.stiffness_N_m1_5)
    assert default_steps_s(stiff.replace(wear_factor=0.0), SliderCrankParameters()) == pytest.approx(
        [s * 8.0 ** -0.4 for s in PAPER_STEPS_S], rel=2e-3)
    assert default_steps_s(stiff, SliderCrankParameters()) == pytest.approx([s * 8.0 ** -0.5 for s in PAPER_STEPS_S],
                                                                             rel=2e-3)
    soft = paper.replace(contact_stiffness_N_m1_5=paper.stiffness_N_m1_5 / 8.0)
    assert default_steps_s(soft, SliderCrankParameters()) == pytest.approx(PAPER_STEPS_S, rel=1e-12)


@pytest.mark.parametrize("options, named", [(["--no-wear"], "--no-wear"), (["--steps", "1e-6", "0"], "--steps"),
                                            (["--crank-speed-rpm", "-5"], "crank_speed_rpm")])
def test_cosim_study_refuses_what_it_cannot_run_in_one_line(tmp_path, options, named):
    result = wearjoint("cosim-study", "--out", str(tmp_path), *options, timeout=120)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and named in lines[0], result.stderr
    assert not (tmp_path / "cosim_study.json").exists()


@pytest.mark.slow
def test_cosim_study_runs_on_this_mechanism(tmp_path):
    """The study on the own mechanism: its parameters reach every run, and over the point-wise window (before the
    chaotic motion separates the runs) the zero-order-hold coupling converges at first order: half the step,
    half the slider's deviation from the monolithic reference."""
    result = wearjoint("cosim-study", "--out", str(tmp_path), "--revolutions", "0.5", "--schemes", "zoh",
                       "--steps", "1e-6", "5e-7", *MODEL_OPTIONS, timeout=1200)
    assert result.returncode == 0, result.stderr
    study = json.loads((tmp_path / "cosim_study.json").read_text())
    assert study["parameters"]["mechanism"]["crank_speed_rpm"] == 300.0
    assert study["parameters"]["joint"]["bushing_radius_m"] == 0.01215
    assert study["pointwise_window_s"] == pytest.approx(0.0075)
    cosim = {r["step_s"]: r for r in study["rows"] if r["engine"] == "cosim"}
    assert all("failed" not in r for r in cosim.values())
    assert cosim[1e-6]["communication_steps"] >= 0.99 * 0.5 * MECHANISM.period_s / 1e-6
    ratio = cosim[1e-6]["pointwise_slider_x_m"] / cosim[5e-7]["pointwise_slider_x_m"]
    assert 1.6 < ratio < 2.5, ratio


@pytest.mark.parametrize("interface", ["co-simulation", pytest.param("model-exchange", marks=pytest.mark.slow)])
def test_the_fmu_starts_from_a_worn_profile_as_from_a_larger_bushing(interface):
    """The FMU's state carries the profile: started 20 um worn all round (deepest-point contact, no wear) it
    moves as the unworn FMU of a bushing 20 um larger over the first 20 ms, and keeps the profile as given."""
    from wearjoint.cosim import CoSimulationOptions, run_cosimulation
    from wearjoint.cosim.model_exchange import run_model_exchange

    mechanism = SliderCrankParameters()
    joint = paper_joint(mechanism, contact_model="deepest", contact_stiffness_N_m1_5=7.95e10, wear_factor=0.0)
    larger = joint.replace(bushing_radius_m=joint.bushing_radius_m + 20e-6)
    if interface == "co-simulation":
        def run(j, profile=None):
            return run_cosimulation(j, mechanism, CoSimulationOptions(revolutions=0.05, step_s=1e-6), progress=False,
                                    initial_profile_m=profile)
    else:
        def run(j, profile=None):
            return run_model_exchange(j, mechanism, SimulationOptions(revolutions=0.05, integrator="rk4", step_s=2e-6),
                                      progress=False, initial_profile_m=profile)
    worn, reference = run(joint, np.full(joint.n_points, 20e-6)), run(larger)
    assert np.array_equal(worn.wear_depth_m, np.full(joint.n_points, 20e-6))
    assert reference.summary()["max_contact_force_N"] > 100.0
    window = worn.samples[:, 0] <= 0.02
    np.testing.assert_allclose(worn.samples[window, 9:11], reference.samples[window, 9:11], rtol=0, atol=1e-9)


def test_cosim_starts_from_a_profile_file_and_refuses_a_bad_one_in_one_line(tmp_path):
    from wearjoint.core.geometry import bushing_point_angles

    profile, n = tmp_path / "profile.csv", JointParameters().n_points
    angles = np.degrees(bushing_point_angles(n))
    np.savetxt(profile, np.column_stack([angles, np.full(n, 5e-6)]), delimiter=",", header="phi_deg,wear_depth_m",
               comments="")
    done = wearjoint("cosim", "--revolutions", "0.01", "--no-plots", "--quiet", "--no-wear", "--initial-profile",
                     str(profile), "--out", str(tmp_path / "run"))
    assert done.returncode == 0, done.stderr
    assert np.allclose(np.loadtxt(tmp_path / "run" / "profile.csv", delimiter=",", skiprows=1)[:, 1], 5e-6, rtol=0,
                       atol=0)
    np.savetxt(profile, np.column_stack([angles, np.full(n, -5e-6)]), delimiter=",", header="phi_deg,wear_depth_m",
               comments="")
    done = wearjoint("cosim", "--revolutions", "0.01", "--no-plots", "--quiet", "--initial-profile", str(profile),
                     "--out", str(tmp_path / "bad"))
    assert done.returncode != 0 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert "wear" in done.stderr and "Traceback" not in done.stderr
    done = wearjoint("cosim", "--master", "fmpy-ssp", "--initial-profile", str(profile), "--out", str(tmp_path / "x"))
    assert done.returncode == 2 and "--initial-profile" in done.stderr and "only with --master wearjoint" in done.stderr


@pytest.mark.parametrize("clearance_joint, zero", [("crank-rod", "rod frame: 0 = towards the slider"),
                                                   ("rod-slider", "rod frame: 0 = away from the crank pin"),
                                                   ("crank-ground", "ground frame: 0 = along +X")])
def test_the_worn_profiles_axis_names_the_bushing_frame_of_the_joint_that_wears(monkeypatch, tmp_path,
                                                                               clearance_joint, zero):
    """A press wearing its piston pin (rod-slider) got the crank-rod joint's axis, "0 = towards the slider".  The
    frames are docs/reference/model.md §1's table: its bushing body and where angle 0 points."""
    import wearjoint.plots as plots

    figures = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path, **kw: figures.append(fig))
    mechanism = SliderCrankParameters(clearance_joint=clearance_joint)
    record = run_simulation(paper_joint(mechanism), mechanism, SimulationOptions(revolutions=0.01))
    plots.plot_run(record, tmp_path, only=[3])
    (label,) = {ax.get_xlabel() for ax in figures[0].axes if ax.get_xlabel()}
    assert label == f"angle in the bushing frame [deg]\n({zero})"


# a press wearing its piston pin at 2000x the paper's printed k_w: through the bushing within 10 ms
WORN_THROUGH_PRESS = ["--crank-length-m", "0.08", "--rod-length-m", "0.3", "--slider-mass-kg", "2", "--crank-speed-rpm",
                      "600", "--slider-force-N", "-800", "--clearance-joint", "rod-slider", "--wear-factor", "2000",
                      "--revolutions", "0.1", "--no-plots"]


@pytest.mark.parametrize("command", [["simulate"], ["cosim", "--step", "2e-6"],      # the step this wear allows
                                     ["cosim", "--step", "2e-6", "--fmu-backend", "pythonfmu"]])
def test_a_bushing_worn_through_stops_the_run_at_its_radius_saying_so(tmp_path, command):
    """The press ran on with the pin ploughing a groove twice the bushing's radius deep (20 mm in a 10.1 mm
    bushing, no state the joint can hold or restore) until the contact search lost it, and then blamed the step:
    "the inputs put the pin 0.000203 m into the bushing wall ... the communication step is too long".  It stops at
    the first step from a groove deeper than the radius and says the bushing wore through."""
    done = subprocess.run([sys.executable, "-m", "wearjoint", *command, *WORN_THROUGH_PRESS, "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 1, done.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    radius = JointParameters().bushing_radius_m
    assert summary["completed"] is False and "the bushing wore through" in summary["failure"]
    assert "the bushing wore through" in done.stderr.strip().splitlines()[-1]
    assert radius < summary["max_wear_depth_m"] < 1.01 * radius, summary["max_wear_depth_m"]


@pytest.mark.parametrize("options, noted", [([], True), (MODEL_OPTIONS, True), (["--no-wear"], False),
                                             (["--wear-coefficient-m2-N", "2e-10"], False)])
def test_build_fmu_says_when_the_fmu_wears_with_the_papers_coefficient(tmp_path, options, noted):
    """A joint FMU goes into any host: built on the paper's k_w (the default), even with the paper's geometry, it
    says so on stderr, naming the FMU parameter that sets another; not with a k_w given or without wear."""
    done = wearjoint("build-fmu", "--out", str(tmp_path), "--platforms", "linux64", *options)
    assert done.returncode == 0, done.stderr
    assert ("note: k_w = 5.05e-10 m^2/N is the paper's" in done.stderr) == noted, done.stderr
    assert ("the FMU's parameter wear_coefficient sets it" in done.stderr) == noted
