"""`wearjoint sweep`: cases as Dask tasks on a real LocalCluster (and, slow, on a scheduler and two
workers started by hand), failed cases recorded, --resume, same case same numbers, bad input."""
import csv
import json
import os
import shutil
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from wearjoint.parameters import ParameterError
from wearjoint.sweep.bias import WEAR_FACTOR_BIAS, wear_factor_bias
from wearjoint.sweep.design import SEED_ANGLE_STEP_DEG, build_cases, command_parser, parse_vary, read_design

TINY = ("--revolutions", "0.02", "--no-plots")


def wearjoint(*args, timeout=900):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """2 slider loads (one far too large: the run diverges as it runs) x 2 seeds of a tiny simulate on a
    LocalCluster of 2 workers."""
    out = tmp_path_factory.mktemp("sweep") / "out"
    done = wearjoint("sweep", "simulate", *TINY, "--vary", "slider-force-N=0,1e8", "--seeds", "2", "--workers", "2",
                     "--out", str(out), "--quiet")
    return out, done


def test_a_failed_case_is_reported_failed_and_the_others_finish(sweep):
    out, done = sweep
    assert done.returncode == 1, done.stderr          # some cases failed
    rows = read_csv(out / "sweep.csv")
    assert [(r["slider_force_N"], r["seed"]) for r in rows] == [("0.0", "0"), ("0.0", "1"), ("100000000.0", "0"),
                                                                ("100000000.0", "1")]
    for r in rows[2:]:
        assert r["status"] == "failed"
        assert r["error"].startswith("the run diverged at t = ") and "into the bushing wall" in r["error"]
        assert r["max_wear_depth_m"] == ""
    for r in rows[:2]:
        assert r["status"] == "ok" and r["error"] == ""
        summary = json.loads((out / r["folder"] / "summary.json").read_text())
        assert float(r["max_wear_depth_m"]) == summary["max_wear_depth_m"] > 0
        assert summary["parameters"]["mechanism"]["slider_force_N"] == 0.0
    angles = [json.loads((out / r["folder"] / "summary.json").read_text())["parameters"]["mechanism"]
              ["initial_crank_angle_deg"] for r in rows[:2]]
    assert angles == [0.0, SEED_ANGLE_STEP_DEG]
    assert "failed" in done.stdout and "Traceback" not in done.stderr
    # the sweep's folder and each case's carry a report (wearjoint.report; tests/cli/test_report.py checks one)
    sweep_summary = json.loads((out / "sweep_summary.json").read_text())
    assert sweep_summary["command_line"].startswith("wearjoint sweep simulate") and (out / "report.html").is_file()
    assert all((out / r["folder"] / "report.html").is_file() for r in rows[:2])
    # its parameters: each swept one over the grid, the failed point's value too (the report had none)
    assert sweep_summary["parameter_spread"] == {"slider_force_N": [[0.0, 1e8], "swept (--vary)"],
                                                 "initial_crank_angle_deg": [[0.0, SEED_ANGLE_STEP_DEG],
                                                                             "the seeds' start angles (--seeds)"]}
    page = (out / "report.html").read_text()
    assert ('<td class="">slider_force_N</td><td class="">[0.0, 100000000.0]</td><td class="">swept (--vary)'
            in page)


def test_ensemble_holds_mean_std_min_max_per_grid_point(sweep):
    out, _ = sweep
    rows = read_csv(out / "sweep.csv")
    ensemble = read_csv(out / "ensemble.csv")
    assert [(e["slider_force_N"], e["n_ok"], e["n_failed"]) for e in ensemble] == [("0.0", "2", "0"),
                                                                                  ("100000000.0", "0", "2")]
    for key in ("max_wear_depth_m", "max_contact_force_N", "impacts_per_revolution"):
        values = np.array([float(r[key]) for r in rows[:2]])
        assert float(ensemble[0][f"{key}_mean"]) == pytest.approx(values.mean(), rel=1e-12)
        assert float(ensemble[0][f"{key}_std"]) == pytest.approx(values.std(ddof=1), rel=1e-9, abs=1e-300)
        assert float(ensemble[0][f"{key}_min"]) == values.min() and float(ensemble[0][f"{key}_max"]) == values.max()
    band = np.loadtxt(out / "bands" / "point0_final.csv", delimiter=",", skiprows=1)
    profiles = np.stack([np.loadtxt(out / r["folder"] / "profile.csv", delimiter=",", skiprows=1)[:, 1]
                         for r in rows[:2]])
    assert np.allclose(band[:, 1], profiles.mean(axis=0), rtol=1e-9, atol=0)
    for png in ("vs_slider_force_N.png", "profile_bands_1.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert float(ensemble[0]["max_wear_depth_m_bias_rel"]) == 0.0     # F = 1 is the brute-force reference
    assert "point 0 (slider_force_N=0.0)" in sweep[1].stdout
    assert "point 1 (slider_force_N=100000000.0)" in sweep[1].stdout


def test_case_in_the_sweep_equals_the_same_case_run_alone(sweep, tmp_path):
    out, _ = sweep
    row = read_csv(out / "sweep.csv")[1]                 # seed 1: perturbed initial crank angle
    case = json.loads((out / row["folder"] / "case.json").read_text())
    assert case["command_line"][:2] == ["wearjoint", "simulate"]
    alone = tmp_path / "alone"
    done = wearjoint(*case["command_line"][1:], "--out", str(alone), "--quiet", "--no-plots")
    assert done.returncode == 0, done.stderr
    assert (alone / "profile.csv").read_bytes() == (out / row["folder"] / "profile.csv").read_bytes()
    a = json.loads((alone / "summary.json").read_text())
    b = json.loads((out / row["folder"] / "summary.json").read_text())
    timing = {"wall_time_s", "compile_time_s", "realtime_factor", "command_line"}     # and where it was written
    assert {k: v for k, v in a.items() if k not in timing} == {k: v for k, v in b.items() if k not in timing}
    series_a, series_b = np.load(alone / "timeseries.npz"), np.load(out / row["folder"] / "timeseries.npz")
    for name in series_a.files:
        assert np.array_equal(series_a[name], series_b[name])


def test_resume_runs_nothing_that_finished(sweep, tmp_path):
    out, _ = sweep
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    shutil.rmtree(copy / read_csv(copy / "sweep.csv")[1]["folder"])     # one case not done
    stamps = {p: p.stat().st_mtime_ns for p in (copy / "cases").glob("*/case.json")}
    done = wearjoint("sweep", "simulate", *TINY, "--vary", "slider-force-N=0,1e8", "--seeds", "2", "--workers", "1",
                     "--out", str(copy), "--quiet", "--resume")
    assert done.returncode == 1, done.stderr
    summary = json.loads((copy / "sweep_summary.json").read_text())
    assert summary["cases_run"] == 1 and summary["skipped_as_done"] == 3
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps          # finished cases untouched
    assert [r["status"] for r in read_csv(copy / "sweep.csv")] == ["ok", "ok", "failed", "failed"]
    again = wearjoint("sweep", "simulate", *TINY, "--vary", "slider-force-N=0,1e8", "--seeds", "2",
                      "--out", str(copy), "--quiet", "--resume")
    assert json.loads((copy / "sweep_summary.json").read_text())["cases_run"] == 0, again.stderr


def test_existing_sweep_needs_resume(sweep):
    out, _ = sweep
    done = wearjoint("sweep", "simulate", *TINY, "--out", str(out), "--quiet")
    assert done.returncode == 2 and "--resume" in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("args,named", [
    (("--vary", "frobnication=1,2"), "frobnication"),
    (("--vary", "restitution=0.5,abc"), "restitution='abc'"),
    (("--vary", "restitution"), "--vary 'restitution'"),
    (("--vary", "rho-mode=flat"), "rho-mode='flat'"),
    (("--vary", "restitution=0.6,1.5"), "--vary restitution=0.6,1.5: restitution=1.5 is invalid: allowed in [0.001, 1]"),
    (("--seeds", "0"), "--seeds=0"),
    (("--workers", "0"), "--workers=0"),
])
def test_bad_sweep_input_gives_one_line_and_status_2(tmp_path, args, named):
    done = wearjoint("sweep", "simulate", *TINY, *args, "--out", str(tmp_path / "x"))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert named in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x").exists()


def test_design_file_grid_points_and_seeds(tmp_path):
    design = tmp_path / "design.toml"
    design.write_text('seeds = 3\n[vary]\nrestitution = [0.6, 0.9]\ncrank-speed-rpm = [100, 150]\n'
                      '[[case]]\nrestitution = 0.75\n')
    d = read_design("simulate", design)
    base = {k: v for k, v in vars(command_parser("simulate").parse_args(["--out", "x"])).items()
            if k not in ("out", "quiet", "no_plots")}
    cases = build_cases("simulate", base, d["vary"], d["points"], d["seeds"])
    assert len(cases) == 5 * 3 and len({c.case_id for c in cases}) == 15
    assert [dict(c.point) for c in cases[::3]] == [
        {"restitution": 0.6, "crank-speed-rpm": 100.0}, {"restitution": 0.6, "crank-speed-rpm": 150.0},
        {"restitution": 0.9, "crank-speed-rpm": 100.0}, {"restitution": 0.9, "crank-speed-rpm": 150.0},
        {"restitution": 0.75, "crank-speed-rpm": 150.0}]                 # a point lacking a name keeps the default
    for c in cases:                                  # the command line gives back the case's full options
        parsed = vars(command_parser("simulate").parse_args([*c.argv(), "--out", "x"]))
        assert {k: parsed[k] for k in dict(c.options)} == dict(c.options)
    assert dict(cases[2].options)["initial_crank_angle_deg"] == 2 * SEED_ANGLE_STEP_DEG


def test_import_wearjoint_does_not_import_dask():
    code = ("import sys, wearjoint, wearjoint.sweep, wearjoint.cli.sweep, wearjoint.cli.wear_study; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stderr


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_sweep_on_a_scheduler_and_two_workers_started_by_hand(tmp_path):
    address = f"tcp://127.0.0.1:{_free_port()}"
    dask = shutil.which("dask") or pytest.skip("no dask command")
    logs = open(tmp_path / "dask.log", "w")
    # the scheduler's and workers' scratch space and lock files in this test's folder, not TMPDIR/dask-scratch-space
    env = {**os.environ, "DASK_TEMPORARY_DIRECTORY": str(tmp_path)}
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
                               "--no-dashboard"], stdout=logs, stderr=logs, env=env)]
    try:
        time.sleep(3)
        procs += [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-dashboard", "--name", f"w{k}"],
                                   stdout=logs, stderr=logs, env=env) for k in range(2)]
        time.sleep(3)
        out = tmp_path / "out"
        done = wearjoint("sweep", "simulate", *TINY, "--vary", "slider-force-N=0,100,1e8", "--seeds", "2",
                         "--scheduler", address, "--out", str(out), "--quiet")
        assert done.returncode == 1, done.stderr
        rows = read_csv(out / "sweep.csv")
        assert [r["status"] for r in rows] == ["ok"] * 4 + ["failed"] * 2
        client_pid = str(os.getpid())
        assert all(not r["worker"].endswith(f":{client_pid}") for r in rows)
        assert json.loads((out / "sweep_summary.json").read_text())["workers"] == 2
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)
        logs.close()


@pytest.mark.slow      # ensembles over seeds and their bands are in the default run (the sweep fixture, profile bands)
def test_wear_study_seeds_reports_fig7_with_bands(tmp_path):
    out = tmp_path / "ensemble"
    done = wearjoint("wear-study", "--revolutions", "20", "--wear-factor", "20", "--snapshots", "10,20", "--seeds", "2",
                     "--workers", "2", "--no-plots", "--out", str(out), "--quiet")
    assert done.returncode == 0, done.stderr
    rows = read_csv(out / "sweep.csv")
    assert [(r["seed"], r["status"]) for r in rows] == [("0", "ok"), ("1", "ok")]
    ensemble = read_csv(out / "ensemble.csv")[0]
    for revolution in (10, 20):
        depths = [json.loads((out / r["folder"] / "summary.json").read_text())["snapshots"][revolution // 10 - 1]
                  ["max_wear_depth_m"] for r in rows]
        assert float(ensemble[f"rev{revolution}_max_wear_depth_m_mean"]) == pytest.approx(np.mean(depths), rel=1e-12)
        assert (out / "bands" / f"point0_rev{revolution}.csv").is_file()
    assert (out / "fig7_bands_point0.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "rev20_max_wear_depth_m" in done.stdout
    assert ensemble["max_wear_depth_m_bias_rel"] == ensemble["rev10_max_wear_depth_m_bias_rel"] == "unknown"
    # the printed k_w: not the measured case; the note says how to measure it
    assert "--convergence jump,20" in ensemble["wear_factor_bias_note"] and "(bias unknown)" in done.stdout


# ------------------------------------------------------------------ names, the wear factor's bias, figures
def test_vary_and_design_take_the_api_name_and_the_option_name(tmp_path):
    base = {k: v for k, v in vars(command_parser("simulate").parse_args(["--out", "x"])).items()
            if k not in ("out", "quiet", "no_plots")}
    api, option = parse_vary("simulate", ["friction_coefficient=0.05,0.2"]), parse_vary("simulate",
                                                                                        ["friction-coefficient=0.05,0.2"])
    assert api == option == {"friction-coefficient": [0.05, 0.2]}
    design = tmp_path / "design.toml"
    design.write_text("[vary]\nfriction_coefficient = [0.05, 0.2]\n[[case]]\ncrank_speed_rpm = 100\n")
    d = read_design("simulate", design)
    assert d["vary"] == option and d["points"] == [{"crank-speed-rpm": 100.0}]
    ids = [c.case_id for c in build_cases("simulate", base, option)]
    assert ids == [c.case_id for c in build_cases("simulate", base, {"friction_coefficient": [0.05, 0.2]})]
    with pytest.raises(ParameterError, match="already varied"):
        parse_vary("simulate", ["friction_coefficient=0.1", "friction-coefficient=0.2"])


def test_unknown_vary_name_names_the_option_the_value_and_the_allowed_names(tmp_path):
    done = wearjoint("sweep", "simulate", *TINY, "--vary", "friction_coeficient=0.1,0.2", "--out", str(tmp_path / "x"))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    line = done.stderr.strip()
    assert "--vary 'friction_coeficient=0.1,0.2'" in line and "did you mean friction_coefficient" in line
    allowed = line.rsplit(": ", 1)[1].split(", ")
    parser = command_parser("simulate")
    one_value = [a.option_strings[-1][2:] for a in parser._actions if a.option_strings and a.nargs is None
                 and type(a).__name__ == "_StoreAction" and a.dest not in ("out", "fmu")]
    assert set(allowed) == set(one_value)


@pytest.mark.slow
def test_a_friction_sweep_shows_the_wear_factor_bias_next_to_the_answer(tmp_path):
    """The issue's sweep, small: F = 100 at 500 revolutions and k_w 5.576e-11, where the convergence study
    measured the bias."""
    out = tmp_path / "friction"
    done = wearjoint("sweep", "wear-study", "--revolutions", "500", "--snapshots", "500", "--wear-factor", "100",
                     "--wear-coefficient-m2-N=5.576e-11",
                     "--vary", "friction_coefficient=0.05,0.2", "--seeds", "1", "--workers", "2", "--no-plots",
                     "--out", str(out), "--quiet")
    assert done.returncode == 0, done.stderr
    with open(out / "ensemble.csv", newline="") as f:
        columns = next(csv.reader(f))
    for key in ("max_wear_depth_m", "rev500_max_wear_depth_m"):   # beside the answer
        assert columns.index(f"{key}_bias_rel") == columns.index(f"{key}_max") + 1
    for k, row in enumerate(read_csv(out / "ensemble.csv")):
        assert float(row["max_wear_depth_m_bias_rel"]) == WEAR_FACTOR_BIAS[100.0][500]
        assert float(row["rev500_max_wear_depth_m_bias_rel"]) == WEAR_FACTOR_BIAS[100.0][500]
        assert "docs/explanation/wear_study.md" in row["wear_factor_bias_note"]
        line = next(x for x in done.stdout.splitlines() if x.strip().startswith(f"point {k} "))
        assert f"friction_coefficient={row['friction_coefficient']}" in line
        assert f"(bias {WEAR_FACTOR_BIAS[100.0][500] * 100:+.1f} %)" in line
    assert "docs/explanation/wear_study.md" in done.stdout


def _points(values_by_x: dict, bias_rel):
    """Grid points of one swept parameter 'mu' whose ok seeds have these max wear depths."""
    from wearjoint.sweep.bias import Bias
    from wearjoint.sweep.report import GridPoint

    points = []
    for x, depths in values_by_x.items():
        point = GridPoint([{"mu": x, "status": "ok", "max_wear_depth_m": d} for d in depths], ["mu"])
        point.bias = {"max_wear_depth_m": Bias(bias_rel, "test")}
        points.append(point)
    return points


def _captured_figures(monkeypatch) -> list:
    import wearjoint.plots

    figures = []
    monkeypatch.setattr(wearjoint.plots, "save_figure", lambda fig, path: figures.append(fig))
    return figures


def test_figure_shows_the_relative_change_against_the_bias_band(monkeypatch, tmp_path):
    from wearjoint.sweep.report import plot_against_parameters

    figures = _captured_figures(monkeypatch)
    depths = {0.05: [100e-6, 101e-6], 0.1: [101e-6, 102e-6], 0.2: [102e-6, 103e-6]}   # a 2 % change
    plot_against_parameters(tmp_path, _points(depths, -0.084))
    ax = figures[0].axes[0]
    mean_line = next(line for line in ax.get_lines() if len(line.get_xdata()) == 3)
    ref = np.mean(depths[0.05])
    assert np.allclose(mean_line.get_ydata(), [(np.mean(d) / ref - 1) * 100 for d in depths.values()])
    low, high = ax.get_ylim()
    assert low <= -8.4 and high >= 8.4 and "%" in ax.get_ylabel()          # the bias band is on the axis


def test_a_grid_over_decades_is_drawn_on_a_log_axis(monkeypatch, tmp_path):
    """k_w over 1e-12..1e-9 on a linear axis: three of four points together at the left, their labels overlapping."""
    from wearjoint.sweep.report import plot_against_parameters

    figures = _captured_figures(monkeypatch)
    plot_against_parameters(tmp_path, _points({1e-12: [1e-6], 1e-11: [2e-6], 1e-10: [3e-6], 1e-9: [4e-6]}, None))
    plot_against_parameters(tmp_path, _points({0.05: [1e-6], 0.1: [2e-6], 0.2: [3e-6]}, None))
    assert [fig.axes[0].get_xscale() for fig in figures] == ["log", "linear"]


def test_two_swept_parameters_give_each_lines_reference_in_the_title(monkeypatch, tmp_path):
    """Against mu, one line per value of the second parameter, each relative to its own first point: the title named
    no reference (one was shown only for a single line), so the percentages could not be read back as depths."""
    from wearjoint.sweep.bias import Bias
    from wearjoint.sweep.report import GridPoint, plot_against_parameters

    figures = _captured_figures(monkeypatch)
    points = []
    for load, scale in ((100.0, 1.0), (200.0, 2.0)):
        for mu in (0.05, 0.1):
            depths = [scale * (100e-6 + mu * 1e-5), scale * (101e-6 + mu * 1e-5)]
            point = GridPoint([{"mu": mu, "load": load, "status": "ok", "max_wear_depth_m": d} for d in depths],
                              ["mu", "load"])
            point.bias = {"max_wear_depth_m": Bias(None, "test")}
            points.append(point)
    plot_against_parameters(tmp_path, points)
    title = figures[0].axes[0].get_title()
    first = [np.mean([scale * (100e-6 + 0.05e-5), scale * (101e-6 + 0.05e-5)]) for scale in (1.0, 2.0)]
    assert title == f"max_wear_depth_m (0 % = {first[0]:.4g} | {first[1]:.4g})"
    labels = [t.get_text() for t in figures[0].axes[0].get_legend().get_texts()]
    assert labels == ["load=100", "load=200"]


def test_profile_bands_are_overlaid_in_one_panel_with_a_legend(monkeypatch, tmp_path):
    from wearjoint.sweep.report import plot_profile_bands

    figures = _captured_figures(monkeypatch)
    points = _points({0.05: [1e-6], 0.1: [1e-6], 0.2: [1e-6]}, None)
    phi = np.linspace(1, 360, 16)
    bands = {k: {"final": (phi, np.vstack([np.sin(np.radians(phi)) ** 2 * (k + 1)] * 2))} for k in range(3)}
    assert plot_profile_bands(tmp_path, points, bands) == ["profile_bands_1.png"]
    (ax,) = [a for a in figures[0].axes if a.get_visible()]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert len(labels) == 3 and all("bias unknown" in t for t in labels)
    assert [label.split(" ")[0] for label in labels] == ["mu=0.05", "mu=0.1", "mu=0.2"]


def test_the_profile_bands_axis_is_the_bushing_frame_of_the_points_joint(monkeypatch, tmp_path):
    """Points wearing the crank's main bearing (crank-ground) are drawn in the ground frame (the axis said "rod
    frame, 0 = towards the slider" for every sweep); a panel of points at different joints names no frame's zero."""
    from wearjoint.sweep.report import plot_profile_bands

    figures = _captured_figures(monkeypatch)
    points = _points({0.05: [1e-6], 0.1: [1e-6]}, None)
    phi = np.linspace(1, 360, 16)
    bands = {k: {"final": (phi, np.vstack([np.sin(np.radians(phi)) ** 2] * 2))} for k in range(2)}
    for point in points:
        point.clearance_joint = "crank-ground"
    plot_profile_bands(tmp_path, points, bands)
    points[1].clearance_joint = "rod-slider"
    plot_profile_bands(tmp_path, points, bands)
    labels = [next(a for a in figure.axes if a.get_visible()).get_xlabel() for figure in figures]
    assert labels == ["angle in the bushing frame [deg] (ground frame: 0 = along +X)",
                      "angle in the bushing frame [deg] (each point's own clearance joint)"]


def test_ensemble_reports_the_fraction_of_starts_in_each_regime(tmp_path):
    """Synthetic summaries through the report: 2 of 8 starts in backward whirl give 0.25, in ensemble.csv,
    in the report's per-point regimes and in the printed table's regime note; a point in one regime is
    not mixed."""
    from wearjoint.sweep.report import regime_line, write_reports
    from wearjoint.sweep.runner import summary_figures

    rows = []
    for mu, regimes in ((0.1, ["impacting"] * 6 + ["backward whirl"] * 2), (0.2, ["impacting"] * 8)):
        for seed, regime in enumerate(regimes):
            summary = {"max_wear_depth_m": 1e-6 * (1 + seed), "regime": regime,
                       "whirl_fraction": 0.5 if regime == "backward whirl" else 0.0}
            rows.append({"case_id": f"{mu}-{seed}", "mu": mu, "seed": seed, "status": "ok", "error": "",
                         **summary_figures(summary), "folder": f"cases/{mu}-{seed}"})
    report = write_reports(tmp_path, rows, ["mu"], plots=False)
    ensemble = read_csv(tmp_path / "ensemble.csv")
    assert float(ensemble[0]["regime_backward_whirl_fraction"]) == 0.25
    assert float(ensemble[0]["regime_impacting_fraction"]) == 0.75
    assert ensemble[0]["regimes"] == "backward whirl 2/8, impacting 6/8" and ensemble[0]["mixed_regimes"] == "1"
    assert float(ensemble[1]["regime_backward_whirl_fraction"]) == 0.0
    assert ensemble[1]["regimes"] == "impacting 8/8" and ensemble[1]["mixed_regimes"] == "0"
    assert report["regimes"][0]["regimes"] == {"backward whirl": 2, "impacting": 6} and report["regimes"][0]["mixed"]
    assert not report["regimes"][1]["mixed"]
    assert "backward whirl 2/8" in regime_line(ensemble[0]) and "MIXED" in regime_line(ensemble[0])
    assert "MIXED" not in regime_line(ensemble[1])
    assert "regime" not in read_csv(tmp_path / "ensemble.csv")[0]      # the string is counted, not averaged


def test_seeds_start_the_crank_half_a_degree_apart_reproducibly():
    """The documented perturbation (docs/how-to/sweep_on_dask.md): seed s starts the crank s x 0.5 deg further, the same
    every time; validate's perturbed starts keep their own 1e-6 deg."""
    from wearjoint.parameters import SliderCrankParameters
    from wearjoint.sweep.design import perturbed_start

    angles = [dict(c.options)["initial_crank_angle_deg"] for c in build_cases("simulate", _base(), seeds=4)]
    assert angles[0] in (None, 0.0) and angles[1:] == [0.5, 1.0, 1.5]      # seed 0: the command's default 0
    again = [dict(c.options)["initial_crank_angle_deg"] for c in build_cases("simulate", _base(), seeds=4)]
    assert again == angles
    assert perturbed_start(SliderCrankParameters(), 3).initial_crank_angle_deg == 3e-6


def _base() -> dict:
    from wearjoint.sweep.design import command_options

    return command_options("simulate", command_parser("simulate").parse_args(["--out", "unused"]))


def test_each_bias_note_names_the_figures_it_is_about():
    """A wear study's final depth measured, its early snapshots not: the notes said 'unknown' and 'measured' side
    by side with nothing to tell which figure each was about."""
    from wearjoint.sweep.report import BIAS_NOTE, GridPoint, ensemble_rows

    point = GridPoint([{"status": "ok", "seed": 0, "max_wear_depth_m": 1e-5}], [])
    point.bias = {"max_wear_depth_m": wear_factor_bias(100.0, 500.0),
                  "rev250_max_wear_depth_m": wear_factor_bias(100.0, 250.0),
                  "rev500_max_wear_depth_m": wear_factor_bias(100.0, 500.0)}
    notes = ensemble_rows([point])[0][BIAS_NOTE].split(" | ")
    assert len(notes) == 2
    assert notes[0].startswith("max_wear_depth_m, rev500_max_wear_depth_m: measured: ")
    assert notes[1].startswith("rev250_max_wear_depth_m: unknown: not measured at F = 100")


def test_the_next_case_removes_the_folders_of_workers_that_are_gone(tmp_path):
    """A sweep stopped by ending its workers leaves each running case's temporary folder (results files and all):
    the next case on the machine removes those of processes that no longer exist, and only those."""
    from wearjoint.sweep.worker import CASE_FOLDER_PREFIX, DASK_FOLDER_PREFIX, new_case_folder

    ended = subprocess.Popen([sys.executable, "-c", "pass"])
    ended.wait()
    orphan = tmp_path / f"{CASE_FOLDER_PREFIX}{ended.pid}-abc"
    running = tmp_path / f"{CASE_FOLDER_PREFIX}{os.getppid()}-def"      # the process that started this one
    unnamed = tmp_path / f"{CASE_FOLDER_PREFIX}ghi"                     # no process id in its name: not ours to judge
    scratch = tmp_path / f"{DASK_FOLDER_PREFIX}{ended.pid}-jkl"         # a killed study's cluster's scratch space
    for folder in (orphan, running, unnamed, scratch):
        folder.mkdir()
        (folder / "last_revolution.csv").write_text("t\n0\n")
    folder = new_case_folder(tmp_path)
    assert not orphan.exists() and not scratch.exists() and running.exists() and unnamed.exists()
    assert folder.parent == tmp_path and folder.name.startswith(f"{CASE_FOLDER_PREFIX}{os.getpid()}-")



def test_a_swept_parameters_close_values_are_labelled_apart():
    """vs_PARAMETER.png labels each of a few values with the fewest digits that tell them apart (matplotlib's own
    ticks ran 0.00603, 0.006035, 0.00604 together into one string)."""
    from wearjoint.sweep.report import _distinct_labels

    assert _distinct_labels([0.00603, 0.006035, 0.00604]) == ["0.00603", "0.006035", "0.00604"]
    assert _distinct_labels([0.0100303, 0.0100304]) == ["0.0100303", "0.0100304"]
    assert _distinct_labels([0.1, 0.2, 1e-5]) == ["0.1", "0.2", "1e-05"]


def test_an_ensembles_wear_angle_is_a_circular_mean():
    """Seeds with their deepest point at 8.3, 185.6, 185.6 and 185.9 deg had an ensemble mean of 141 deg, where no
    lobe is; angles across 0/360 deg average to 0, not 180."""
    from wearjoint.sweep.report import circular_mean_std_deg, ensemble_rows

    mean, std = circular_mean_std_deg(np.array([359.0, 1.0]))
    assert min(mean, 360.0 - mean) == pytest.approx(0.0, abs=1e-9) and std == pytest.approx(1.0, rel=1e-3)
    point = _points({0.1: [1e-6] * 4}, None)[0]
    for row, angle in zip(point.ok, (8.3, 185.6, 185.6, 185.9)):
        row["max_wear_angle_deg"] = angle
    row = ensemble_rows([point])[0]
    assert 180.0 < row["max_wear_angle_deg_mean"] < 186.0 and (row["max_wear_angle_deg_min"],
                                                               row["max_wear_angle_deg_max"]) == (8.3, 185.9)
