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

from wearjoint.sweep.design import SEED_ANGLE_STEP_DEG, build_cases, command_parser, read_design

TINY = ("--revolutions", "0.02", "--no-plots")


def wearjoint(*args, timeout=900):
    return subprocess.run([sys.executable, "-m", "wearjoint.cli", *args], capture_output=True, text=True,
                          timeout=timeout)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """2 restitutions (one invalid) x 2 seeds of a tiny simulate on a LocalCluster of 2 workers."""
    out = tmp_path_factory.mktemp("sweep") / "out"
    done = wearjoint("sweep", "simulate", *TINY, "--vary", "restitution=0.6,1.5", "--seeds", "2", "--workers", "2",
                     "--out", str(out), "--quiet")
    return out, done


def test_invalid_case_is_reported_failed_and_the_others_finish(sweep):
    out, done = sweep
    assert done.returncode == 1, done.stderr          # some cases failed
    rows = read_csv(out / "sweep.csv")
    assert [(r["restitution"], r["seed"]) for r in rows] == [("0.6", "0"), ("0.6", "1"), ("1.5", "0"), ("1.5", "1")]
    for r in rows[2:]:
        assert r["status"] == "failed"
        assert "restitution" in r["error"] and "1.5" in r["error"] and "(0, 1]" in r["error"]
        assert r["max_wear_depth_m"] == ""
    for r in rows[:2]:
        assert r["status"] == "ok" and r["error"] == ""
        summary = json.loads((out / r["folder"] / "summary.json").read_text())
        assert float(r["max_wear_depth_m"]) == summary["max_wear_depth_m"] > 0
        assert summary["parameters"]["joint"]["restitution"] == 0.6
    angles = [json.loads((out / r["folder"] / "summary.json").read_text())["parameters"]["mechanism"]
              ["initial_crank_angle_deg"] for r in rows[:2]]
    assert angles == [0.0, SEED_ANGLE_STEP_DEG]
    assert "failed" in done.stdout and "Traceback" not in done.stderr


def test_ensemble_holds_mean_std_min_max_per_grid_point(sweep):
    out, _ = sweep
    rows = read_csv(out / "sweep.csv")
    ensemble = read_csv(out / "ensemble.csv")
    assert [(e["restitution"], e["n_ok"], e["n_failed"]) for e in ensemble] == [("0.6", "2", "0"), ("1.5", "0", "2")]
    for key in ("max_wear_depth_m", "max_contact_force_N", "impacts_per_revolution"):
        values = np.array([float(r[key]) for r in rows[:2]])
        assert float(ensemble[0][f"{key}_mean"]) == pytest.approx(values.mean(), rel=1e-12)
        assert float(ensemble[0][f"{key}_std"]) == pytest.approx(values.std(ddof=1), rel=1e-9, abs=1e-300)
        assert float(ensemble[0][f"{key}_min"]) == values.min() and float(ensemble[0][f"{key}_max"]) == values.max()
    band = np.loadtxt(out / "bands" / "point0_final.csv", delimiter=",", skiprows=1)
    profiles = np.stack([np.loadtxt(out / r["folder"] / "profile.csv", delimiter=",", skiprows=1)[:, 1]
                         for r in rows[:2]])
    assert np.allclose(band[:, 1], profiles.mean(axis=0), rtol=1e-9, atol=0)
    for png in ("vs_restitution.png", "profile_bands_1.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


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
    timing = {"wall_time_s", "compile_time_s", "realtime_factor"}
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
    done = wearjoint("sweep", "simulate", *TINY, "--vary", "restitution=0.6,1.5", "--seeds", "2", "--workers", "1",
                     "--out", str(copy), "--quiet", "--resume")
    assert done.returncode == 1, done.stderr
    summary = json.loads((copy / "sweep_summary.json").read_text())
    assert summary["cases_run"] == 1 and summary["skipped_as_done"] == 3
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps          # finished cases untouched
    assert [r["status"] for r in read_csv(copy / "sweep.csv")] == ["ok", "ok", "failed", "failed"]
    again = wearjoint("sweep", "simulate", *TINY, "--vary", "restitution=0.6,1.5", "--seeds", "2",
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
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
                               "--no-dashboard"], stdout=logs, stderr=logs)]
    try:
        time.sleep(3)
        procs += [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-dashboard", "--name", f"w{k}"],
                                   stdout=logs, stderr=logs) for k in range(2)]
        time.sleep(3)
        out = tmp_path / "out"
        done = wearjoint("sweep", "simulate", *TINY, "--vary", "restitution=0.6,0.9,1.5", "--seeds", "2",
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


def test_wear_study_seeds_reports_fig7_with_bands(tmp_path):
    out = tmp_path / "ensemble"
    done = wearjoint("wear-study", "--revolutions", "10", "--wear-factor", "20", "--snapshots", "5,10", "--seeds", "2",
                     "--workers", "2", "--no-plots", "--out", str(out), "--quiet")
    assert done.returncode == 0, done.stderr
    rows = read_csv(out / "sweep.csv")
    assert [(r["seed"], r["status"]) for r in rows] == [("0", "ok"), ("1", "ok")]
    ensemble = read_csv(out / "ensemble.csv")[0]
    for revolution in (5, 10):
        depths = [json.loads((out / r["folder"] / "summary.json").read_text())["snapshots"][revolution // 5 - 1]
                  ["max_wear_depth_m"] for r in rows]
        assert float(ensemble[f"rev{revolution}_max_wear_depth_m_mean"]) == pytest.approx(np.mean(depths), rel=1e-12)
        assert (out / "bands" / f"point0_rev{revolution}.csv").is_file()
    assert (out / "fig7_bands_point0.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "rev10_max_wear_depth_m" in done.stdout
