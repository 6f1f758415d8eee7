"""SliderCrankWithClearance.ssp in OpenModelica's OMSimulator (the shared build in
../shared/tools/omsimulator, README there): its command line runs the package with the step, the
result settings and the signal filter the SSD carries, no algebraic loop through the joint (the
slider-crank's state outputs declare no feed-through); `wearjoint cosim --master omsimulator` (its
Python package) steps it and agrees with fmpy's container, the other master that feeds the joint's
loads back at the current kinematics.  Skipped, with the reason, where the build is missing."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fmpy")
from wearjoint.cli import main  # noqa: E402
from wearjoint.cosim import master_trace, masters  # noqa: E402
from wearjoint.fmu import ssp  # noqa: E402
from wearjoint.parameters import SliderCrankParameters, paper_joint  # noqa: E402
from wearjoint.results import RunParameters  # noqa: E402
from third_party_tools import OMSIMULATOR_CLI, OMSIMULATOR_MISSING, OMSIMULATOR_PYTHON  # noqa: E402

CLI, PYTHON_PACKAGE = OMSIMULATOR_CLI, OMSIMULATOR_PYTHON


@pytest.fixture(scope="module")
def omsimulator():
    """The shared build's command line, its Python package importable (skip where absent)."""
    if not CLI.is_file() or not (PYTHON_PACKAGE / "libOMSimulator.so").is_file():
        pytest.skip(OMSIMULATOR_MISSING)
    if str(PYTHON_PACKAGE) not in sys.path:
        sys.path.insert(0, str(PYTHON_PACKAGE))
    missing = masters.master_available("omsimulator")
    if missing:
        pytest.skip(missing)
    return CLI


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    """The paper's package (linux64 binaries), stop time 0.05 s, the default step."""
    return ssp.export_ssp(tmp_path_factory.mktemp("ssp"), stop_time=0.05, platforms="linux64")


def _result_names(path: Path) -> list[str]:
    """The variable names of an OMSimulator MAT (v4, Dymola layout) result file."""
    scipy_io = pytest.importorskip("scipy.io")
    names = scipy_io.loadmat(str(path), chars_as_strings=False)["name"]
    return ["".join(column).strip() for column in names.T]


def test_command_line_runs_the_package_with_its_step_no_loop_and_the_filtered_signals(omsimulator, package,
                                                                                     tmp_path):
    """`OMSimulator --stopTime=0.01 SliderCrankWithClearance.ssp`: exits 0 with no error, no algebraic
    loop logged ("Alg. loop (size n/m)" is OMSimulator's info line), and writes the SSD's result file
    holding time and the recorded signals only, every logging interval."""
    run = subprocess.run([str(omsimulator), "--stopTime=0.01", str(package)], cwd=tmp_path, capture_output=True,
                         text=True, timeout=300)
    log = run.stdout + run.stderr
    assert run.returncode == 0, log[-2000:]
    assert "Alg. loop" not in log and "error:" not in log, log[-2000:]
    result = tmp_path / ssp.RESULT_FILE
    names = _result_names(result)
    assert sorted(names) == sorted(["time", *(f"{ssp.SSP_NAME}.{ssp.SSP_NAME}.{c}.{n}" for c, n in ssp.RECORDED)])
    # 1000 logging intervals, each written twice (before and after the connections move), ~16 bytes a value
    assert result.stat().st_size < 2.5 * 1000 * len(names) * 16


@pytest.mark.slow
def test_command_line_runs_the_package_with_no_options(omsimulator, tmp_path):
    """`OMSimulator SliderCrankWithClearance.ssp`, no options: OMSimulator's command line takes its own
    stop time (1 s, 2.5 revolutions; it overrides the SSD's), the step from the SSD; no loop, and the
    result file stays far below 200 MB (about 30 MB)."""
    package = ssp.export_ssp(tmp_path, stop_time=2 * SliderCrankParameters().period_s, platforms="linux64")
    run = subprocess.run([str(omsimulator), package.name], cwd=tmp_path, capture_output=True, text=True,
                         timeout=1800)
    log = run.stdout + run.stderr
    assert run.returncode == 0 and "Alg. loop" not in log, log[-2000:]
    assert (tmp_path / ssp.RESULT_FILE).stat().st_size < 200e6


def test_cosim_master_omsimulator_agrees_with_fmpys_container(omsimulator, package):
    """0.05 s through OMSimulator's Python API at the default step (5 us, the loads linearised): every traced
    value finite, the statistics of the run record finite, the joint touched; over the first 20 ms (free flight
    and the first impacts) the slider's acceleration equals the container's to 1e-6 of its range.  Both masters
    step both FMUs with the inputs held and then move the connections in the same order (kinematics, then the
    loads evaluated at them), so only the rounding of the accumulated time may differ (measured: 3e-10)."""
    joint, mechanism = paper_joint(), SliderCrankParameters()
    stop, step = 0.05, masters.DEFAULT_STEP_S["linearised"]
    trace = masters.run_omsimulator(package, step, stop, joint.n_points)
    assert trace.time_s[-1] == pytest.approx(stop, abs=0.5 * step)
    assert np.isfinite(trace.values).all() and np.isfinite(trace.wear_depth_m).all()
    assert trace.values[:, master_trace.TRACED.index((ssp.JOINT, "contact"))].max() == 1.0
    record = master_trace.record_from_trace(trace, joint, mechanism, 1e-4, RunParameters("cosim", joint, mechanism))
    assert np.isfinite(record.revolution_stats).all() and record.worn_volume_m3 > 0.0
    window = slice(0, round(0.02 / step) + 1)
    reference = masters.run_container(package, step, 0.02, joint.n_points)
    column = master_trace.TRACED.index((ssp.MECHANISM, "slider_a"))
    got, expected = trace.values[window, column], reference.values[:, column]
    assert got.shape == expected.shape
    assert np.abs(got - expected).max() < 1e-6 * np.ptp(expected)


def test_cosim_master_omsimulator_writes_the_results_folder(omsimulator, tmp_path, monkeypatch):
    """`wearjoint cosim --master omsimulator` writes summary.json naming the master; OMSimulator's log stays where
    it says it saved it (the user's cache: it was a temporary folder, removed), its warnings in the summary."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    out = tmp_path / "out"
    assert main(["cosim", "--out", str(out), "--master", "omsimulator", "--revolutions", "0.005", "--quiet",
                 "--no-plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["master"] == "omsimulator"
    assert summary["simulated_time_s"] == pytest.approx(0.005 * SliderCrankParameters().period_s, rel=1e-3)
    log = (tmp_path / "cache" / "wearjoint" / "omsimulator" / "last_run.log").read_text()
    warned = [line for line in log.splitlines() if "warning" in line.lower() or "error" in line.lower()]
    assert summary.get("master_log_warnings", []) == warned


def _result_signal(path: Path, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, values) of variable ``name`` in an OMSimulator MAT result (data_2: the continuous signals)."""
    scipy_io = pytest.importorskip("scipy.io")
    mat = scipy_io.loadmat(str(path), chars_as_strings=False)
    names = ["".join(column).strip() for column in mat["name"].T]
    table, column = mat["dataInfo"][:2, names.index(name)]
    values = mat[f"data_{table}"][abs(column) - 1] * np.sign(column)
    return mat["data_2"][0], values


@pytest.mark.parametrize("location", ["crank-rod", "rod-slider", "crank-ground"])
def test_command_line_runs_a_loaded_package_and_carries_its_load(omsimulator, tmp_path, location):
    """`export-ssp --slider-force-table FILE --clearance-joint J` (the press of docs/tutorials/own_mechanism.md, gravity along
    the stroke) runs in OMSimulator's command line as exported; over the crank angles where the table presses with
    2 kN the joint carries, on average, what the ideal joint J carries under the same load (1.8 kN) within 5 %,
    where before the table's ramp the ideal joint carries a ninth of it at most: the load reached the mechanism
    through the package's parameter set, and the joint FMU sits where the mechanism FMU opened the joint."""
    from wearjoint.slider_crank import SliderCrank
    from wearjoint.mechanism_parameters import SliderForceTable

    table = Path(__file__).resolve().parents[2] / "docs" / "examples" / "press_load.csv"
    press = SliderCrankParameters(crank_length_m=0.05, rod_length_m=0.25, crank_speed_rpm=120.0, slider_mass_kg=8.0,
                                  rod_mass_kg=1.2, rod_inertia_kg_m2=0.00625, gravity_m_s2=(9.81, 0.0),
                                  initial_crank_angle_deg=30.0, slider_force_table=SliderForceTable.from_csv(table),
                                  clearance_joint=location)
    options = ["--crank-length-m", "0.05", "--rod-length-m", "0.25", "--crank-speed-rpm", "120", "--slider-mass-kg",
               "8", "--rod-mass-kg", "1.2", "--rod-inertia-kg-m2", "0.00625", "--gravity-m-s2=9.81,0",
               "--initial-crank-angle-deg", "30", "--slider-force-table", str(table), "--clearance-joint", location]
    assert main(["export-ssp", "--out", str(tmp_path), "--platforms", "linux64", *options]) == 0
    run = subprocess.run([str(omsimulator), "--stopTime=0.06", ssp.SSP_FILE_NAME], cwd=tmp_path, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, (run.stdout + run.stderr)[-2000:]
    prefix = f"{ssp.SSP_NAME}.{ssp.SSP_NAME}."
    t, force = _result_signal(tmp_path / ssp.RESULT_FILE, prefix + "joint.normal_force")
    _, angle = _result_signal(tmp_path / ssp.RESULT_FILE, prefix + "mechanism.crank_angle")
    degrees = np.degrees(angle) % 360.0
    ideal = SliderCrank(press).ideal_joint_force(t)
    pressing = (degrees > 2.0) & (degrees < 14.0)
    assert pressing.sum() > 100
    assert force[pressing].mean() == pytest.approx(ideal[pressing].mean(), rel=0.05)
    assert ideal[pressing].mean() > 1500.0
    assert ideal[(degrees > 21.0) & (degrees < 28.0)].max() < ideal[pressing].mean() / 8.0
