"""What a sweep's case is and how a sweep reports while it runs (wearjoint/sweep/design.py, worker.py, runner.py):
the contents of the files its options name are part of the case and go with it to its worker; the progress moves
while cases last."""
import json
import subprocess
import sys

from wearjoint.sweep.design import build_cases, command_parser


def test_a_case_carries_the_files_its_options_name(tmp_path):
    """A case is its options and the contents of the files they name: an edited load table is another case (resume
    runs it, not the one computed with the old load), and a worker that cannot read the client's file (another
    folder or machine) runs on the contents the client read."""
    from wearjoint.sweep.design import command_options
    from wearjoint.sweep.worker import run_case

    table = tmp_path / "load.csv"
    rows = "crank_angle_deg,force_N\n0,0\n150,0\n170,{f}\n200,{f}\n220,0\n360,0\n"
    table.write_text(rows.format(f=800))
    args = ["--out", "unused", "--revolutions", "0.02", "--slider-force-table", str(table)]
    base = command_options("simulate", command_parser("simulate").parse_args(args))
    [case] = build_cases("simulate", base)
    table.write_text(rows.format(f=2400))
    [edited] = build_cases("simulate", base)
    assert edited.case_id != case.case_id and edited.options == case.options
    table.unlink()
    result = run_case(case, no_plots=True)
    assert result["status"] == "ok", result["log"][-2000:]
    loaded = json.loads(result["files"]["summary.json"])["parameters"]["mechanism"]["slider_force_table"]
    assert loaded["force_N"] == [0.0, 0.0, 800.0, 800.0, 0.0, 0.0]


def test_a_sweep_says_it_runs_while_its_cases_last(tmp_path):
    """Progress moves on a heartbeat, not only when a case ends: a long wear-study case left a log empty for
    minutes (the log writes a line every 15 s of those updates).  A wear-study case moves the bar by the share of
    revolutions its last checkpoint reached (snapshots.json's checkpointed_revolution; an ensemble had shown 0/4 for
    minutes).  In a process of its own: a Dask cluster's workers do not start inside a test worker."""
    script = f"""
import json
from wearjoint.cli import main
from wearjoint.sweep import runner
updates = []
class Recorded(runner.Progress):
    def update(self, done, eta_s=None):
        updates.append(done)
        super().update(done, eta_s)
runner.Progress, runner.HEARTBEAT_S = Recorded, 0.1
code = main(["wear-study", "--revolutions", "40", "--wear-factor", "10", "--seeds", "2", "--workers", "1",
             "--no-plots", "--quiet", "--out", {str(tmp_path / "s")!r}])
print(json.dumps([code, sorted({{round(u % 1, 3) for u in updates}}), updates[-1], updates.count(0)]))
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    code, shares, last, waiting = json.loads(done.stdout.splitlines()[-1]) if done.stdout else (None, [], None, 0)
    assert (code, last) == (0, 2) and waiting >= 3, done.stdout + done.stderr[-2000:]
    # four simulated revolutions a case, a checkpoint after each (the last one's share shown as 0.999 until the
    # case ends): quarters between the cases' ends
    assert {0.25, 0.5, 0.75} <= set(shares) <= {0.0, 0.25, 0.5, 0.75, 0.999}, (shares, done.stderr[-2000:])


def test_an_ensemble_says_how_many_seeds_reached_the_life_depth(tmp_path, capsys):
    """A --seeds study whose depth stopped short of --life-depth-m printed no life at all (the mean had no numbers):
    each case's row says whether it reached the depth, and the ensemble how many did."""
    from wearjoint.cli.sweep import print_outcome
    from wearjoint.sweep.runner import summary_figures

    assert summary_figures({"life": {"revolutions": None}, "life_revolutions": None})["life_reached"] == 0
    assert summary_figures({"life": {"revolutions": 1090.0}, "life_revolutions": 1090.0})["life_reached"] == 1
    assert "life_reached" not in summary_figures({"max_wear_depth_m": 1e-5})
    (tmp_path / "ensemble.csv").write_text("point,n_ok,n_failed,max_wear_depth_m_mean,max_wear_depth_m_std,"
                                           "life_reached_mean\n0,2,0,1.9e-05,1e-09,0.5\n")
    print_outcome({"cases": 2, "grid_points": 1, "seeds": 2, "ok": 2, "failed": 0, "skipped_as_done": 0,
                   "wall_time_s": 1.0, "failures": []}, tmp_path)
    assert "the life's depth (--life-depth-m) reached by 1 of 2 seeds" in capsys.readouterr().out


def test_a_case_folder_names_itself_as_its_out(tmp_path):
    """A case's summary.json and report.html said --out /tmp/wearjoint-case-8933-0qsdptzu (its worker's folder, gone)
    or cases/ID/running: the client rewrites them, as it records the case, to name the case's folder."""
    import shlex

    from wearjoint.report import write_report
    from wearjoint.sweep.design import command_options
    from wearjoint.sweep.runner import SweepFolder

    base = command_options("simulate", command_parser("simulate").parse_args(["--out", "x", "--revolutions", "0.1"]))
    [case] = build_cases("simulate", base)
    worker = tmp_path / "wearjoint-case-1-x"
    worker.mkdir()
    (worker / "summary.json").write_text(json.dumps({"revolutions": 0.1}))
    write_report(worker, command_line=f"wearjoint simulate --revolutions 0.1 --out {worker} --quiet --no-plots")
    files = {p.name: p.read_bytes() for p in worker.iterdir()}
    folder = SweepFolder(tmp_path / "sweep dir", [case], resume=False)
    folder.record(case, {"status": "ok", "files": files, "log": ""}, no_plots=True)
    here = folder.case_dir(case)
    said = json.loads((here / "summary.json").read_text())["command_line"]
    assert said == f"wearjoint simulate --revolutions=0.1 --out {shlex.quote(str(here))} --quiet --no-plots"
    assert str(worker) not in (here / "report.html").read_text()


def test_a_cases_command_line_gives_back_its_pairs():
    """A case's command line (case.json, its summary's) is the run outside the sweep: gravity's pair had been written
    as two words, `--gravity-m-s2 0.0 -9.81`, which the command refuses ("unrecognized arguments: -9.81")."""
    given = ["--out", "x", "--gravity-m-s2=0,-9.81", "--bushing-offset-m", "-0.11", "0.001"]
    base = {k: v for k, v in vars(command_parser("simulate").parse_args(given)).items()
            if k not in ("out", "quiet", "no_plots")}
    [case] = build_cases("simulate", base)
    assert "--gravity-m-s2=0.0,-9.81" in case.argv()
    parsed = vars(command_parser("simulate").parse_args([*case.argv(), "--out", "x"]))
    assert {k: parsed[k] for k in dict(case.options)} == dict(case.options)
    assert parsed["gravity_m_s2"] == (0.0, -9.81) and list(parsed["bushing_offset_m"]) == [-0.11, 0.001]
