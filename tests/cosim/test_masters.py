"""Third-party masters (wearjoint.cosim.masters) run SliderCrankWithClearance.ssp closed-loop: OSP
libcosim, ecos, fmpy's SSP simulator, OMSimulator (the shared build's Python package, put on the path
here when ../shared/tools/omsimulator has it), and the container FMU in fmpy and in fmusim.  Over the first
impacts each one's slider converges to the monolithic engine's as its communication step shrinks
(first order: every one holds the inputs over a step), and with the mechanism linearising the joint's loads is
closer at ten times the step; `wearjoint cosim --master` writes the usual
results folder and refuses bad options in one line.  Slow: 2 revolutions per master inside the
monolithic scatter, judged as `wearjoint validate` judges an engine."""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fmpy")
from wearjoint.cli import main  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.cosim import master_trace, masters  # noqa: E402
from wearjoint.fmu import ssp  # noqa: E402
from wearjoint.parameters import SliderCrankParameters, paper_joint  # noqa: E402
from wearjoint.simulate import Simulation, SimulationOptions, run_simulation  # noqa: E402
from third_party_tools import FMUSIM, OMSIMULATOR_PYTHON  # noqa: E402

WINDOW_S, SAMPLE_S = 6e-3, 1e-4      # free flight, then the first impacts (the first near 2-3 ms)
CASES = ("libcosim", "ecos", "fmpy-ssp", "omsimulator", "container", "container-fmusim")
if OMSIMULATOR_PYTHON.is_dir() and str(OMSIMULATOR_PYTHON) not in sys.path:
    sys.path.insert(0, str(OMSIMULATOR_PYTHON))
SUMMARY_KEYS = ("revolutions", "simulated_time_s", "wall_time_s", "realtime_factor", "max_contact_force_N",
                "contact_fraction", "impacts_per_revolution", "slider_acc_max_m_s2", "slider_acc_min_m_s2",
                "max_eccentricity_m", "max_wear_depth_m", "max_wear_angle_deg", "worn_volume_m3", "parameters")


def _master_or_skip(case: str) -> tuple[str, str | None]:
    """(master, fmusim binary or None) of a test case; skipped when it cannot run here."""
    master, fmusim = ("container", FMUSIM) if case == "container-fmusim" else (case, None)
    missing = masters.master_available(master)
    if missing:
        pytest.skip(missing)
    if fmusim and not Path(fmusim).is_file():
        pytest.skip(f"no fmusim at {fmusim} ($FMUSIM; ../shared/tools/fmusim builds it)")
    return master, fmusim


@pytest.fixture(scope="module")
def packages(tmp_path_factory):
    """The paper's package, its mechanism holding the joint's loads over a step and linearising them (linux64
    binaries)."""
    return {coupling: ssp.export_ssp(tmp_path_factory.mktemp("ssp"), platforms="linux64", load_coupling=coupling)
            for coupling in ssp.LOAD_COUPLINGS}


@pytest.fixture(scope="module")
def reference():
    """The monolithic engine's slider x [m] every SAMPLE_S over WINDOW_S (DOPRI, tight tolerances)."""
    options = SimulationOptions(rtol=1e-9, atol_position_m=1e-12, atol_velocity_m_s=1e-8, max_step_s=1e-6)
    simulation = Simulation(options=options)
    samples = np.zeros((round(SAMPLE_S / options.sample_dt_s) + 10, L.N_SAMPLE_COLUMNS))
    xs = []
    for k in range(round(WINDOW_S / SAMPLE_S)):
        simulation.advance_to((k + 1) * SAMPLE_S, samples)
        xs.append(simulation.y[L.SLIDER])
    assert simulation.revolution_stats[0, L.S_IMPACTS] >= 1
    return np.array(xs)


@pytest.mark.parametrize("case", CASES)
def test_each_master_converges_to_the_monolithic_engine_over_the_first_impacts(case, packages, reference):
    """At 2, 1 and 0.5 us the master's slider (the package's parameters applied, the loads held) approaches the
    monolithic engine's over the first impacts at first order in the step; the joint touched.  With the loads
    linearised (the package's default) the master at 5 us is closer than with them held at 0.5 us (measured: 8x
    closer for the masters that set the kinematics before they read the loads, 1.7x for those one step late)."""
    master, fmusim = _master_or_skip(case)
    extra = {"fmusim": fmusim} if fmusim else {}
    times = (np.arange(reference.size) + 1) * SAMPLE_S
    column = master_trace.TRACED.index((ssp.MECHANISM, "slider_x"))
    contact = master_trace.TRACED.index((ssp.JOINT, "contact"))
    sliding = master_trace.TRACED.index((ssp.JOINT, "tangential_velocity"))
    errors = {}
    for coupling, step in (("hold", 2e-6), ("hold", 1e-6), ("hold", 5e-7), ("linearised", 5e-6)):
        trace = masters.RUNNERS[master](packages[coupling], step, WINDOW_S, paper_joint().n_points, **extra)
        assert trace.time_s[-1] == pytest.approx(WINDOW_S, abs=0.5 * step)
        assert trace.values[:, contact].max() == 1.0
        touching = trace.values[:, contact] == 1.0      # the joint's v_T traced: sliding in contact, 0 out of it
        assert np.all(trace.values[~touching, sliding] == 0.0) and np.abs(trace.values[touching, sliding]).max() > 0.01
        errors[coupling, step] = np.abs(np.interp(times, trace.time_s, trace.values[:, column]) - reference).max()
    held = [errors["hold", step] for step in (2e-6, 1e-6, 5e-7)]
    assert held[0] > held[1] > held[2], errors
    assert held[0] / held[1] > 1.6 and held[1] / held[2] > 1.6, errors
    assert held[2] < 1e-6, errors    # m, of a 100 mm stroke
    assert errors["linearised", 5e-6] < held[2], errors


@pytest.fixture(scope="module")
def fast_wearing_package(tmp_path_factory):
    """The package of a joint at wear factor 1e5 (linux64 binaries)."""
    return ssp.export_ssp(tmp_path_factory.mktemp("ssp_wear"), joint=paper_joint(wear_factor=1e5), platforms="linux64",
                          step_s=5e-8)         # its steps within the wear-step limit; the masters run it at 1 us


@pytest.mark.parametrize("case", CASES)
def test_each_master_runs_through_the_joints_wear_step_warning(case, fast_wearing_package):
    """At wear factor 1e5 the first contact's 1 us steps wear more than 4 of the penetration's share (the
    wear-step limit, docs/reference/model.md §7): the joint logs it once and returns fmi2OK, so every master goes on
    (OMSimulator ended the run on the fmi2Warning it used to return) and the bushing wears."""
    master, fmusim = _master_or_skip(case)
    trace = masters.RUNNERS[master](fast_wearing_package, 1e-6, 4e-3, paper_joint().n_points,
                                    **({"fmusim": fmusim} if fmusim else {}))
    assert trace.time_s[-1] == pytest.approx(4e-3, abs=0.5e-6)
    depth = trace.values[:, master_trace.TRACED.index((ssp.JOINT, "max_wear_depth"))]
    # the first contact (near 3.1 ms) wears at once: masters reading the loads one step late never see it open
    assert depth[-1] > 1e-6 and np.all(np.isfinite(trace.values))


def test_ecos_leaves_nothing_in_the_temporary_folder(packages, tmp_path, monkeypatch):
    """ecos unpacks the package into $TMPDIR/ecos_ssp_<uuid> and keeps it (1.2 MB a run, 100 of them after a day's
    tests): the master runs it in a folder of its own and removes that."""
    import tempfile

    _master_or_skip("ecos")
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", None)     # gettempdir() reads TMPDIR again
    trace = masters.run_ecos(packages["linearised"], 5e-6, 1e-4, paper_joint().n_points)
    assert trace.time_s[-1] == pytest.approx(1e-4)
    assert list(tmp_path.iterdir()) == []


def test_container_fmu_from_export_ssp_runs_in_fmpy_and_fmusim_alike(tmp_path):
    """`export-ssp --container-fmu`'s container runs in fmusim and in fmpy's FMU2Slave through the
    same communication points to the same slider motion."""
    _master_or_skip("container-fmusim")
    assert main(["export-ssp", "--out", str(tmp_path), "--platforms", "linux64", "--container-fmu"]) == 0
    stop, step = 2e-3, ssp.CONTAINER_STEP_S
    names = [ssp.container_variable(c, n) for c, n in master_trace.TRACED]
    fmu = tmp_path / ssp.CONTAINER_FILE_NAME
    in_fmusim = masters._fmusim(FMUSIM, fmu, names, step, round(stop / step), 0.0)
    in_fmpy = masters.run_container(tmp_path / ssp.SSP_FILE_NAME, step, stop, paper_joint().n_points)
    np.testing.assert_allclose(in_fmusim.time_s, in_fmpy.time_s, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(in_fmusim.values, in_fmpy.values, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("case", [c if c == "fmpy-ssp" else pytest.param(c, marks=pytest.mark.slow) for c in CASES])
def test_cosim_master_writes_the_results_folder(case, tmp_path):
    """`wearjoint cosim --master X` writes summary.json with the results contract's keys, measured
    by the master it names, and the time series (one path for every master, record_from_trace: the default
    run checks it through fmpy's SSP master; each master's runner is exercised by the tests above)."""
    master, fmusim = _master_or_skip(case)
    out = tmp_path / "out"
    args = ["cosim", "--out", str(out), "--master", master, "--revolutions", "0.005", "--quiet", "--no-plots"]
    assert main(args + (["--fmusim", fmusim] if fmusim else [])) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(SUMMARY_KEYS) <= set(summary)
    assert summary["master"] == ("container-fmusim" if fmusim else master)
    assert summary["parameters"]["load_coupling"] == "linearised"      # the package's, which sets the step
    assert "communication_step_note" not in summary                     # its own step is the checked one
    assert summary["simulated_time_s"] == pytest.approx(0.005 * SliderCrankParameters().period_s, rel=1e-3)
    assert summary["communication_steps"] == 400        # 2 ms at the paper's 5 us, whether the trace holds t = 0
    series = np.load(out / "timeseries.npz")
    assert series["time_s"][-1] == pytest.approx(summary["simulated_time_s"], abs=1e-5)
    # the crank's rate minus the rod's, the ideal slider-crank's closed form within the clearance's play (it had been
    # 0: the bodies' rates were not traced, and the regime could never be a whirl)
    m = SliderCrankParameters()
    theta, rate = series["crank_angle_rad"], -m.omega_rad_s       # driven clockwise
    rod_rate = -m.crank_length_m * np.cos(theta) * rate / (m.rod_length_m * np.sqrt(
        1.0 - (m.crank_length_m * np.sin(theta) / m.rod_length_m) ** 2))
    np.testing.assert_allclose(series["relative_omega_rad_s"], rate - rod_rate, atol=0.03 * m.omega_rad_s)
    profiled = case not in ("fmpy-ssp", "container-fmusim")     # their masters give no worn profile: no NaN file
    assert (out / "profile.csv").is_file() == profiled and ("wear_profile" not in summary) == profiled


@pytest.mark.parametrize("args, option, value, allowed", [
    (["--master", "nope"], "--master", "'nope'", "one of wearjoint, libcosim, ecos, fmpy-ssp, omsimulator, container"),
    (["--master", "libcosim", "--step", "0"], "--step", "0", "a communication step > 0 [s] and at most the run's 0.8 s"),
    (["--master", "libcosim", "--step=-1e-6"], "--step", "-1e-6",
     "a communication step > 0 [s] and at most the run's 0.8 s"),
    (["--master", "container", "--step=1", "--revolutions", "0.05"], "--step", "1",
     "a communication step > 0 [s] and at most the run's 0.02 s"),
    (["--master", "libcosim", "--revolutions", "0"], "--revolutions", "0", "> 0 crank revolutions"),
    (["--master", "container", "--fmu", "x.fmu"], "--fmu", "'x.fmu'", "only with --master wearjoint (a third-party "
     "master steps the SSP's Co-Simulation FMUs, export-ssp's native builds, at the fixed --step)"),
    (["--master", "ecos", "--fmu-backend", "pythonfmu"], "--fmu-backend", "'pythonfmu'", "only with --master "
     "wearjoint (a third-party master steps the SSP's Co-Simulation FMUs, export-ssp's native builds, at the fixed "
     "--step)"),
    (["--load-coupling", "hold"], "--load-coupling", "'hold'",
     "only with a third-party --master (this package's master couples by --scheme)"),
])
def test_cosim_master_refuses_bad_options_in_one_line(args, option, value, allowed, tmp_path, capsys):
    """Unknown master, a step <= 0 or a load coupling for this package's master: exit status 2, one line naming the
    option, its value and what is allowed."""
    assert main(["cosim", "--out", str(tmp_path), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"wearjoint cosim: error: {option}={value} is invalid: allowed {allowed}"
    assert not (tmp_path / "summary.json").exists()


def test_a_third_party_masters_step_is_held_to_the_wear_step_limit_and_defaults_to_the_packages(tmp_path, capsys):
    """As this package's master: a step past the wear-step limit (5.5e-8 s at wear factor 1e5) is refused, naming
    --step; left out, the step is the package's (the measured 5 us scaled by the step rule for this machine)."""
    from wearjoint.cosim.step_rule import paper_step_scale
    from wearjoint.simulation_options import wear_step_limit_s
    from wearjoint.targets import cosim_config

    assert main(["cosim", "--out", str(tmp_path), "--master", "container", "--wear-factor", "1e5", "--step",
                 "1e-6"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("wearjoint cosim: error: --step=1e-6 (step_s) is invalid with wear") and \
        "allowed at most 5.52e-08 s" in err
    mechanism = SliderCrankParameters(crank_speed_rpm=300.0)
    options = {**vars(_cosim_parser().parse_args(["--out", "x", "--master", "container", "--crank-speed-rpm", "300"]))}
    config = cosim_config(options)
    scale = paper_step_scale(paper_joint(mechanism), mechanism)
    steps = -(-mechanism.period_s // (masters.DEFAULT_STEP_S["linearised"] * scale))    # whole steps per revolution
    assert scale < 1.0 and config.step_s == pytest.approx(mechanism.period_s / steps, rel=1e-12)
    fast = cosim_config({**options, "wear_factor": 1e5})        # a wear-step limit below it: the limit, to whole steps
    limit, steps = wear_step_limit_s(fast.joint, mechanism), mechanism.period_s / fast.step_s
    assert limit < 1e-7 and steps == pytest.approx(round(steps), abs=1e-6) and fast.step_s <= limit < \
        mechanism.period_s / (round(steps) - 1)


def _cosim_parser():
    from wearjoint.cli import build_parser

    return next(a for a in build_parser("cosim")._actions if a.dest == "command").choices["cosim"]


def test_cosim_master_that_is_not_installed_is_refused_in_one_line(tmp_path, capsys, monkeypatch):
    """A master whose package is missing: exit status 2, one line saying which package it needs."""
    from wearjoint.cosim import masters

    monkeypatch.setattr(masters, "master_available",
                        lambda m: f"{m} needs ecospy and tbb (ImportError: no ecospy)" if m == "ecos" else None)
    assert main(["cosim", "--out", str(tmp_path), "--master", "ecos"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("wearjoint cosim: error: --master='ecos' is invalid: allowed one of the masters "
                   "installed here, wearjoint, libcosim, fmpy-ssp, omsimulator, container (ecos needs ecospy and tbb "
                   "(ImportError: no ecospy))")


# the slow test's step per master on the default package (its mechanism integrates the joint's published
# linearisation; docs/explanation/cosim_study.md): 5 us for the masters that pass the loads one step late, 10 us for
# the container and OMSimulator (on time), the steps its ensembles hold at
SLOW_STEP_S = {"libcosim": 5e-6, "ecos": 5e-6, "fmpy-ssp": 5e-6, "omsimulator": 1e-5, "container": 1e-5,
               "container-fmusim": 1e-5}


@pytest.fixture(scope="module")
def study():
    """Every installed master at its SLOW_STEP_S over 2 revolutions from two starts, judged against the
    monolithic scatter."""
    from wearjoint.studies.masters_study import run_study

    rows = run_study(2.0, sorted(set(SLOW_STEP_S.values())), CASES, FMUSIM, log=lambda m: None,
                     skip=lambda case, step: None if SLOW_STEP_S[case] == step else "another step")["rows"]
    return {row["master"]: row for row in rows if "skipped" not in row or row["skipped"] != "another step"}


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_two_revolutions_of_each_master_stay_inside_the_monolithic_scatter(case, study):
    """At its step the per-revolution statistics of the master's 2 revolutions, the mean of two perturbed
    starts (masters_study.ENSEMBLE), are within validate's tolerance of the monolithic reference built from
    ensembles of the same size: all but at most one, which (a sample near its tolerance: equally valid runs
    fall on either side, docs/explanation/cosim_study.md) stays within twice it; an unstable coupling is off by orders
    of magnitude."""
    _master_or_skip(case)
    row = study[case]
    assert "metrics" in row, row
    outside = {name: m for name, m in row["metrics"].items() if not m["passed"]}
    assert len(outside) <= 1, outside
    assert all(abs(m["difference"]) <= 2.0 * m["tolerance"] for m in outside.values()), outside


@pytest.fixture(scope="module")
def fast_wear():
    """The paper's joint at wear factor 100: its package (linux64 binaries) and RK4's worn volume over one revolution
    at 10 us [m^3] (the pin settles in its groove: the same trajectory in every engine; the volume moves with neither
    the step nor the engine, docs/explanation/numerics.md)."""
    import tempfile

    joint = paper_joint(wear_factor=100.0)
    rk4 = run_simulation(joint, None, SimulationOptions(revolutions=1, integrator="rk4", step_s=1e-5), progress=False)
    with tempfile.TemporaryDirectory(prefix="wearjoint_fast_wear_") as tmp:
        yield ssp.export_ssp(Path(tmp), joint=joint, platforms="linux64"), rk4.worn_volume_m3, joint.n_points


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_each_master_wears_the_monolithic_volume_at_accelerated_wear(case, fast_wear):
    """One revolution at wear factor 100, each master at its SLOW_STEP_S: the worn volume within 1.5 % of RK4's.  The
    package's mechanism applies the joint's loads linearised over a step, and the joint wears with that linear normal
    force's mean whether the master read the loads' derivatives at the step's inputs (the container, OMSimulator:
    +0.40 %, measured) or before it set them (libcosim, fmpy's SSP master: +0.99 % at 5 us; with the force held
    there, as before the FMU evaluated the derivatives at the step's inputs itself, 10.9 % short)."""
    master, fmusim = _master_or_skip(case)
    package, volume, n_points = fast_wear
    trace = masters.RUNNERS[master](package, SLOW_STEP_S[case], 0.4, n_points,
                                    **({"fmusim": fmusim} if fmusim else {}))
    worn = trace.values[-1, master_trace.TRACED.index((ssp.JOINT, "worn_volume"))]
    assert worn == pytest.approx(volume, rel=0.015)


@pytest.mark.parametrize("case", ["own-zoh", "libcosim", "ecos", "omsimulator", "container"])
def test_a_step_that_blows_the_coupling_up_ends_as_a_failed_run(case, tmp_path, capsys):
    """At a 20 us communication step the held coupling blows up in the first impacts (the pin through the bushing
    wall, docs/reference/model.md §3.14): every route, wearjoint's own fixed-step master and each third-party one (whether
    it stops at the joint's fmi2Discard, libcosim, or steps on, ecos and OMSimulator, whose trace shows the pin past
    the wall), ends with exit status 1 and one line, `completed: false` and the failure in summary.json, and the
    results up to there written."""
    options = ["--scheme", "zoh"] if case == "own-zoh" else ["--master", _master_or_skip(case)[0], "--load-coupling",
                                                             "hold"]
    out = tmp_path / "out"
    code = main(["cosim", *options, "--step", "2e-5", "--revolutions", "0.05", "--quiet", "--no-plots",
                 "--out", str(out)])
    errors = [line for line in capsys.readouterr().err.splitlines() if line.startswith("wearjoint cosim: error:")]
    assert code == 1 and len(errors) == 1 and "the run diverged" in errors[0], errors
    summary = json.loads((out / "summary.json").read_text())
    failure = summary["failure"]
    assert summary["completed"] is False and ("bushing wall" in failure or "admissible" in failure), failure
    assert 0.0 < summary["simulated_time_s"] < 0.05 * 0.4
    # the time series up to the failure (the in-process master's had been empty: its chunk's samples were dropped),
    # nothing past it (ecos stepped on to 0.02 s and had written an eccentricity of 3e7 m and 4.5e8 N)
    failed_at = float(re.search(r"t = ([0-9.e+-]+) s", failure).group(1))
    series = np.load(out / "timeseries.npz")["time_s"]
    assert summary["simulated_time_s"] <= failed_at and 0.0 < series[-1] <= failed_at and series.size > 100, series
    joint = paper_joint()
    if case != "own-zoh":   # the in-process master accounts the point whose step the joint refused (its force past)
        assert summary["max_contact_force_N"] <= joint.admissible_force_N, summary
    assert summary["max_eccentricity_m"] <= joint.clearance_m + joint.admissible_penetration_m + 1e-6, summary


def test_the_in_process_master_refuses_an_fmi3_fmu_naming_its_version(shared_build, tmp_path, capsys):
    """`cosim --fmu` takes FMI 2.0: an FMI 3.0 build is refused in one line saying so (it had said to rebuild with
    --profile-stride 1, which it was)."""
    fmi3_fmu = shared_build(backend="native", fmi_version=3)
    assert main(["cosim", "--fmu", str(fmi3_fmu), "--revolutions", "0.05", "--out", str(tmp_path / "r"),
                 "--quiet", "--no-plots"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("is invalid: allowed an FMI 2.0 FMU (it is FMI 3.0; this master takes FMI 2.0: build-fmu "
                        "--fmi-version 2)") and err.count("\n") == 0


def test_a_step_past_the_checked_one_is_noted_in_the_output_and_summary(tmp_path, capsys):
    """A package at 10 times its step completed without a word with a third of the contact: a --step more than
    twice the checked step of its load coupling is noted on stderr and in summary.json; the checked step is not."""
    from wearjoint.cosim.step_rule import unchecked_step_note

    joint, mechanism = paper_joint(), SliderCrankParameters()
    assert unchecked_step_note(1e-5, "linearised", joint, mechanism) == ""          # twice 5 us: checked
    assert "4 times the checked step of --load-coupling linearised here (5e-06 s" in unchecked_step_note(
        2e-5, "linearised", joint, mechanism)
    _master_or_skip("fmpy-ssp")
    out = tmp_path / "out"
    assert main(["cosim", "--master", "fmpy-ssp", "--step", "2e-5", "--revolutions", "0.005", "--no-plots",
                 "--out", str(out)]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if line.startswith("note: --step 2e-05 s is 4 times")]
    assert len(said) == 1
    assert json.loads((out / "summary.json").read_text())["communication_step_note"] == said[0][len("note: "):]
