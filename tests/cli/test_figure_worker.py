"""wearjoint.figure_worker: a run's figures drawn by a second process are the ones the first draws (same files,
same bytes), and every way the second process can fail leaves the first to draw them."""
import json
import os
import pickle
import subprocess
import sys

import numpy as np
import pytest

from wearjoint import figure_worker, plots
from wearjoint.figure_worker import FigureData, FigureWorker
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.results import write_results
from wearjoint.simulate import SimulationOptions, run_simulation


@pytest.fixture(scope="module")
def record():
    return run_simulation(paper_joint(), SliderCrankParameters(), SimulationOptions(revolutions=0.05), progress=False)


def _figures(folder, summary):
    return {name: (folder / name).read_bytes() for name in summary["figures"]}


def test_the_workers_figures_are_the_first_process_figures(record, tmp_path, monkeypatch):
    monkeypatch.setattr(figure_worker, "_cores", lambda: 2)
    worker = FigureWorker()
    assert worker.process is not None
    with monkeypatch.context() as m:                   # this process cannot draw: the worker must have
        m.setattr(plots, "plot_run", lambda *a: pytest.fail("the first process drew the figures"))
        drawn_there = write_results(record, tmp_path / "worker", figure_worker=worker)
    assert worker.process is None                       # it answered and ended
    drawn_here = write_results(record, tmp_path / "here")
    assert drawn_there["figures"] == drawn_here["figures"] == json.loads(
        (tmp_path / "worker" / "summary.json").read_text())["figures"]
    assert _figures(tmp_path / "worker", drawn_there) == _figures(tmp_path / "here", drawn_here)


def test_a_run_without_a_worn_profile_writes_neither_profile_nor_its_figure(record, tmp_path, monkeypatch):
    """A third-party master that gives no worn profile (fmpy's SSP simulator: NaN) gets no profile.csv and no
    profile figure, from the worker or from this process, and an earlier run's profile.csv in the folder goes."""
    import dataclasses

    blind = dataclasses.replace(record, wear_depth_m=np.full_like(record.wear_depth_m, np.nan))
    monkeypatch.setattr(figure_worker, "_cores", lambda: 2)
    for folder, worker in ((tmp_path / "worker", FigureWorker()), (tmp_path / "here", None)):
        write_results(record, folder)                                   # an earlier run with its profile
        summary = write_results(blind, folder, figure_worker=worker)
        assert summary["figures"] == ["slider_acceleration.png", "pin_orbit.png", "contact_force.png"], folder
        assert not {"profile.csv", "wear_profile.png"} & set(os.listdir(folder)), folder
        assert all((folder / name).stat().st_size > 0 for name in summary["figures"])


def test_a_worker_that_died_leaves_the_figures_to_the_first_process(record, tmp_path, monkeypatch):
    monkeypatch.setattr(figure_worker, "_cores", lambda: 2)
    worker = FigureWorker()
    worker.process.kill()
    worker.process.wait()
    summary = write_results(record, tmp_path, figure_worker=worker)
    assert len(summary["figures"]) == 4 and all((tmp_path / name).stat().st_size > 0 for name in summary["figures"])


def test_a_worker_that_answers_nonsense_leaves_the_figures_to_the_first_process(record, tmp_path, monkeypatch):
    monkeypatch.setattr(figure_worker, "_cores", lambda: 2)
    monkeypatch.setattr(figure_worker, "_command", lambda: ["python", "-c", "print('not a list')"])
    summary = write_results(record, tmp_path, figure_worker=FigureWorker())
    assert len(summary["figures"]) == 4 and all((tmp_path / name).is_file() for name in summary["figures"])


def test_on_one_core_there_is_no_second_process(monkeypatch):
    monkeypatch.setattr(figure_worker, "_cores", lambda: 1)
    worker = FigureWorker()
    assert worker.process is None and worker.names() is None


def test_the_package_and_the_command_line_load_without_numba():
    # the figure worker starts before numba loads, and unpickles what it is sent without loading it
    code = ("import sys, wearjoint, wearjoint.cli, wearjoint.figure_worker, wearjoint.plots\n"
            "assert 'numba' not in sys.modules, 'numba loaded'\n"
            "from wearjoint import ClearanceJoint, paper_joint\n"
            "assert 'numba' in sys.modules and ClearanceJoint(paper_joint()).params.clearance_m > 0")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_figure_data_are_what_the_figures_read_of_the_record(record):
    data = pickle.loads(pickle.dumps(FigureData.of(record)))
    assert data.last_revolution() == record.last_revolution()
    for name in ("samples", "phi_deg", "wear_depth_m"):
        assert np.array_equal(getattr(data, name), getattr(record, name))
    assert (data.period_s, data.clearance_m, data.revolutions) == (record.period_s, record.clearance_m,
                                                                    record.revolutions)


def test_the_program_runs_the_exit_handlers_and_exits_with_the_commands_code(tmp_path):
    marker = tmp_path / "exit_handlers_ran"
    code = ("import atexit, sys\n"
            f"atexit.register(lambda: open({str(marker)!r}, 'w').write('ran'))\n"
            "sys.argv = ['wearjoint', 'simulate', '--revolutions=-1', '--out', 'x']\n"
            "from wearjoint.cli import console\n"
            "console()")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 2
    assert "revolutions" in done.stderr and "-1" in done.stderr
    assert marker.read_text() == "ran"


@pytest.mark.parametrize("users_setting, expected", [(None, "1"), ("2", "2")])
def test_the_program_runs_blas_on_one_thread_unless_the_user_says_otherwise(tmp_path, users_setting, expected):
    # the program's processes (the figure worker's included) see OPENBLAS_NUM_THREADS before numpy loads
    code = ("import os, sys\n"
            "from wearjoint import cli\n"
            "cli.main = lambda: print(os.environ.get('OPENBLAS_NUM_THREADS'), 'numpy' in sys.modules) or 0\n"
            "cli.console()")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if users_setting is not None:
        env["OPENBLAS_NUM_THREADS"] = users_setting
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [expected, "False"]


def test_a_run_without_figures_lists_none_and_leaves_none(record, tmp_path):
    """--no-plots: summary.json's figures is [] (a new user found no key where results.md lists the figures
    written), and an earlier run's figures in the folder go."""
    write_results(record, tmp_path)
    summary = write_results(record, tmp_path, plots=False)
    assert summary["figures"] == [] and json.loads((tmp_path / "summary.json").read_text())["figures"] == []
    assert not list(tmp_path.glob("*.png"))
