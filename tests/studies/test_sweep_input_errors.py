"""Bad sweep and sensitivity input is refused before anything runs or is written, with one line naming the option as
written, its value and what is allowed (exit 2): a --resume of a folder without a sweep or of a sweep of another
design, design files of the wrong shape, repeated values, options whose value holds commas, grid values the run
would refuse, a --scheduler that cannot be reached, a negative --seed.  (A case that fails as it runs, a diverged
run, is still recorded as failed, exit 1: tests/studies/test_sweep.py's sweep.)"""
import json
import subprocess
import sys

import pytest

from wearjoint import targets
from wearjoint.checks import ParameterError
from wearjoint.cli import main
from wearjoint.sweep import runner
from wearjoint.sweep.design import (build_cases, check_grid, command_options, design_record, read_design,
                                    sweep_design)
from wearjoint.sweep.runner import SweepFolder

TINY = ("--revolutions", "0.02", "--no-plots", "--quiet")


def refused(capsys, *args) -> str:
    """The one line of a command refused with exit status 2."""
    code = main(list(args))
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


def sweep(tmp_path, *args) -> list:
    return ["sweep", "simulate", *TINY, *args, "--out", str(tmp_path / "out")]


def base(command="simulate", *args):
    return command_options(command, targets.parser(command).parse_args(["--out", "x", *args]))


def finished_sweep(out, vary, seeds=2) -> SweepFolder:
    """A sweep of the design --revolutions 0.02 --vary ... --seeds N in ``out`` with its cases recorded ok (no run:
    each case's summary.json holds a max wear depth)."""
    options = base("simulate", "--revolutions", "0.02")
    cases = build_cases("simulate", options, vary, seeds=seeds)
    folder = SweepFolder(out, cases, resume=False, design=design_record("simulate", options, vary, (), seeds))
    for k, case in enumerate(cases):
        summary = json.dumps({"max_wear_depth_m": 1e-7 * (1 + k), "regime": "impacting"}).encode()
        folder.record(case, {"status": "ok", "files": {"summary.json": summary}, "log": ""})
    return folder


def snapshot(out) -> dict:
    return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


# ------------------------------------------------------------------ --resume
@pytest.mark.parametrize("args,named", [
    (("--vary", "restitution=0.7", "--seeds", "2"), "--vary restitution: [0.6] there, [0.7] now"),
    (("--vary", "restitution=0.6", "--seeds", "3"), "--seeds: 2 there, 3 now"),
    (("--vary", "restitution=0.6", "--seeds", "2", "--friction-coefficient", "0.2"),
     "--friction-coefficient: not given there, 0.2 now"),
    (("--vary", "restitution=0.6", "--vary", "crank-speed-rpm=100", "--seeds", "2"),
     "--vary crank-speed-rpm: not given there, [100.0] now"),
])
def test_resume_of_another_design_is_refused_naming_what_differs(tmp_path, capsys, args, named):
    out = tmp_path / "out"
    finished_sweep(out, {"restitution": [0.6]})
    before = snapshot(out)
    line = refused(capsys, *sweep(tmp_path, *args, "--resume"))
    assert line.startswith(f"wearjoint sweep: error: --resume is invalid: the sweep in {out} has another design: ")
    assert named in line and "allowed the sweep's own design" in line
    assert snapshot(out) == before                            # sweep.json, sweep.csv and every case kept as they were


def test_resume_of_the_same_design_written_otherwise_is_not_refused(tmp_path):
    """The API name and the option's name, values written otherwise: the same design (nothing left to run)."""
    out = tmp_path / "out"
    finished_sweep(out, {"restitution": [0.6, 0.9]})
    assert main(sweep(tmp_path, "--vary", "restitution=.6,0.90", "--seeds", "2", "--resume")) == 0
    summary = json.loads((out / "sweep_summary.json").read_text())
    assert (summary["cases_run"], summary["skipped_as_done"]) == (0, 4)


@pytest.mark.parametrize("command,args,what", [
    ("sweep", ("--vary", "restitution=0.6"), "sweep"),
    ("sensitivity", ("--param", "restitution=0.6,0.9"), "sensitivity study"),
])
@pytest.mark.parametrize("exists", [False, True])
def test_resume_of_a_folder_without_a_run_is_refused(tmp_path, capsys, command, args, what, exists):
    out = tmp_path / "out"
    if exists:
        out.mkdir()
        (out / "notes.txt").write_text("mine")
    line = refused(capsys, command, "simulate", *TINY, *args, "--resume", "--out", str(out))
    assert f"--resume is invalid: {out} holds no {what} to resume" in line
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"] if exists else not out.exists()


# ------------------------------------------------------------------ design files and --vary
@pytest.mark.parametrize("text,named", [
    ("[vary]\nrestitution = []\n", "[vary] restitution: restitution=[] is invalid: allowed one or more values"),
    ("[vary]\nrestitution = [0.6, 0.6]\n", "[vary] restitution: restitution=0.6 is given twice"),
    ("vary = 3\n", ": vary=3 is invalid: allowed a [vary] table"),
    ('vary = "x"\n', ": vary='x' is invalid: allowed a [vary] table"),
    ("case = 3\n", ": case=3 is invalid: allowed [[case]] tables"),
    ("case = [1, 2]\n", ": case=[1, 2] is invalid: allowed [[case]] tables"),
    ('seeds = "two"\n', ": seeds='two' is invalid: allowed an integer from 1 to 10000"),
    ("[[case]]\nrestitution = [0.6, 0.9]\n", "[[case]] 1: restitution=[0.6, 0.9] is invalid: allowed one value"),
    ("[[case]]\nrestitution = 0.6\nRestitution = 0.7\n", "[[case]] 1 restitution is invalid: restitution is already"),
    ("[[case]]\ngravity-m-s2 = [0, -9.81, 1]\n", "[[case]] 1: gravity-m-s2='0,-9.81,1' is invalid: allowed"),
    ("[[case]]\nrestitution = 5\n", "[[case]] 1: restitution=5.0 is invalid: allowed in [0.001, 1]"),
])
def test_a_bad_design_file_names_the_file_and_its_key(tmp_path, capsys, text, named):
    design = tmp_path / "design.toml"
    design.write_text(text)
    line = refused(capsys, *sweep(tmp_path, "--design", str(design)))
    assert f"--design {design}" in line and named in line
    assert not (tmp_path / "out").exists()


def test_a_name_in_the_design_and_in_vary_is_refused_and_other_names_merge(tmp_path, capsys):
    design = tmp_path / "design.toml"
    design.write_text("[vary]\nrestitution = [0.6]\n")
    line = refused(capsys, *sweep(tmp_path, "--design", str(design), "--vary", "restitution=0.9"))
    assert f"--vary restitution=0.9 is invalid: restitution is already varied in --design {design} [vary]" in line
    merged = sweep_design("simulate", ["crank_speed_rpm=100,150"], design)
    assert merged["vary"] == {"restitution": [0.6], "crank-speed-rpm": [100.0, 150.0]}
    assert merged["where"]["vary"] == {"restitution": f"--design {design} [vary] restitution",
                                       "crank-speed-rpm": "--vary crank_speed_rpm=100,150"}


@pytest.mark.parametrize("args,named", [
    (("--vary", "restitution=0.6,0.6"), "--vary restitution=0.6,0.6: restitution=0.6 is given twice: allowed each "
                                        "value once"),
    (("--vary", "gravity-m-s2=0,-9.81"), "--vary 'gravity-m-s2=0,-9.81' is invalid: a value of gravity-m-s2 may hold "
                                         "commas"),
    (("--vary", "gravity-m-s2=a"), "gravity-m-s2"),
])
def test_repeated_values_and_options_written_with_commas_are_refused_on_vary(tmp_path, capsys, args, named):
    line = refused(capsys, *sweep(tmp_path, *args))
    assert named in line and not (tmp_path / "out").exists()


def test_wear_study_snapshots_are_varied_in_a_design_file_not_on_vary(tmp_path, capsys):
    line = refused(capsys, "sweep", "wear-study", "--vary", "snapshots=2,4", "--out", str(tmp_path / "out"))
    assert "--vary 'snapshots=2,4' is invalid" in line and "--design" in line and "[[case]]" in line
    design = tmp_path / "design.toml"
    design.write_text('[vary]\nsnapshots = ["5,10", [4, 10]]\n[[case]]\ngravity-m-s2 = [0, -1.62]\n')
    d = read_design("wear-study", design)
    assert d["vary"] == {"snapshots": ["5,10", "4,10"]} and d["points"] == [{"gravity-m-s2": (0.0, -1.62)}]
    cases = build_cases("wear-study", base("wear-study", "--revolutions", "10"), d["vary"], d["points"])
    assert [targets.target("wear-study").snapshots(dict(c.options)) for c in cases] == [(5, 10), (4, 10), (2, 5, 7, 10)]
    assert targets.target("wear-study").config(dict(cases[2].options)).mechanism.gravity_m_s2 == (0.0, -1.62)


# ------------------------------------------------------------------ grid values checked before any case runs
@pytest.mark.parametrize("command,args,named", [
    ("simulate", ("--vary", "restitution=5,0.9"), "--vary restitution=5,0.9: restitution=5.0 is invalid: allowed "
                                                  "in [0.001, 1]"),
    ("simulate", ("--vary", "restitution=nan"), "--vary restitution=nan: restitution=nan is invalid: allowed a finite"),
    ("simulate", ("--vary", "revolutions=0"), "--vary revolutions=0: revolutions=0.0 is invalid: allowed > 0"),
    ("simulate", ("--integrator", "rk4", "--vary", "step=1e-5,2e-4"),
     "--vary step=1e-5,2e-4: step=0.0002 is invalid with wear"),
    ("simulate", ("--restitution=5", "--vary", "friction_coefficient=0.1"), "--restitution=5.0 is invalid: allowed "
                                                                            "in [0.001, 1]"),
    # a base value refused against a varied one: the point named (a new user's line named --rod-length-m alone)
    ("simulate", ("--rod-length-m", "0.28", "--vary", "crank-length-m=0.06,0.3"),
     "--rod-length-m=0.28 is invalid with crank-length-m=0.3 (--vary crank-length-m=0.06,0.3): allowed > "
     "crank_length_m"),
    ("simulate", ("--vary", "bushing-radius-m=0.01005,0.0101", "--vary", "pin-radius-m=0.0099,0.01008"),
     # each value fine alone (with the other radius's default), not together: named with the other's value
     "--vary bushing-radius-m=0.01005,0.0101: bushing-radius-m=0.01005 is invalid: allowed > 0 (at most 100 m) and "
     "> pin_radius_m (pin_radius_m = 0.01008)"),
    ("simulate", ("--bushing-radius-m", "0.00603", "--vary", "pin-radius-m=0.006,-0.006"),   # the bad value, named
     "--vary pin-radius-m=0.006,-0.006: pin-radius-m=-0.006 is invalid: allowed > 0"),
    ("simulate", ("--vary", "slider-force-table=no_such_table.csv"),      # a file as written, not a PosixPath
     "--vary slider-force-table=no_such_table.csv: slider-force-table=no_such_table.csv is invalid: allowed a text "
     "CSV file; cannot read it"),
    ("cosim", ("--vary", "master=foo"), "--vary master=foo: master='foo' is invalid: allowed one of wearjoint"),
    ("cosim", ("--vary", "step=0"), "--vary step=0: step=0.0 is invalid: allowed > 0"),
    ("wear-study", ("--vary", "revolutions=10,0"), "--vary revolutions=10,0: revolutions='0' is invalid: allowed an "
                                                   "integer >= 1"),
])
def test_a_bad_grid_value_is_refused_before_any_case_runs(tmp_path, capsys, command, args, named):
    length = [] if "revolutions=" in " ".join(args) else ["--revolutions", "1" if command == "wear-study" else "0.02"]
    line = refused(capsys, "sweep", command, *length, *args, "--out", str(tmp_path / "out"))
    assert named in line and "_s=" not in line, line        # the option as written, not the API's step_s
    assert not (tmp_path / "out").exists()


def test_only_the_cases_that_run_are_checked_not_the_base_a_varied_option_replaces(tmp_path):
    """A 6 mm pin in a 6.03 mm bushing: the base's bushing is narrower than the default 10 mm pin, which no case
    runs with (the pin radius is varied); a sensitivity box of both radii valid at every corner, though its bushing
    is narrower than the default pin.  Neither is refused; a box one of whose corners puts the pin past the bushing
    is, naming that corner's value."""
    from wearjoint.sensitivity.problem import check_ranges, parse_params

    small = base("simulate", "--revolutions", "0.02", "--bushing-radius-m", "0.00603")
    check_grid("simulate", small, {"pin-radius-m": [0.006, 0.00601]})
    check_grid("simulate", small, points=[{"pin-radius-m": 0.006}, {"pin-radius-m": 0.00602}])   # a design's points
    box = parse_params("simulate", ["pin-radius-m=0.0050,0.0055", "bushing-radius-m=0.0060,0.0065"])
    check_ranges(box, base("simulate", "--revolutions", "0.02"))
    crossing = parse_params("simulate", ["pin-radius-m=0.0050,0.0062", "bushing-radius-m=0.0060,0.0065"])
    with pytest.raises(ParameterError, match=r"^--param 'bushing-radius-m=0.0060,0.0065': bushing-radius-m=0.006 is "
                                             r"invalid: .* > pin_radius_m \(pin_radius_m = 0.0062\)$"):
        check_ranges(crossing, base("simulate", "--revolutions", "0.02"))


# ------------------------------------------------------------------ --scheduler, --seed
@pytest.mark.parametrize("command,args", [("sweep", ("--vary", "restitution=0.6")),
                                          ("sensitivity", ("--param", "restitution=0.6,0.9"))])
@pytest.mark.parametrize("address,named", [("notanaddress", "missing port number"),
                                           ("tcp://127.0.0.1:1", "Timed out")])
def test_a_scheduler_that_cannot_be_reached_is_refused_before_anything_is_written(tmp_path, capsys, monkeypatch,
                                                                                   command, args, address, named):
    monkeypatch.setattr(runner, "CONNECT_TIMEOUT_S", 1)
    line = refused(capsys, command, "simulate", *TINY, *args, "--scheduler", address, "--out", str(tmp_path / "out"))
    # on a loaded machine distributed's client may fail to start its event loop before it tries the address: refused
    # the same way, with that reason instead of the address's
    assert f"--scheduler={address!r} is invalid: cannot connect: " in line
    assert named in line or "the Dask client's event loop did not start" in line, line
    assert "allowed the address of a running Dask scheduler" in line and not (tmp_path / "out").exists()


@pytest.mark.parametrize("seed", ["-1", "4294967296"])
def test_a_sensitivity_seed_out_of_range_is_refused(tmp_path, capsys, seed):
    line = refused(capsys, "sensitivity", "simulate", *TINY, "--param", "restitution=0.6,0.9", f"--seed={seed}",
                   "--out", str(tmp_path / "out"))
    assert f"--seed={seed} is invalid: allowed an integer in [0, 4294967295]" in line
    assert not (tmp_path / "out").exists()


def test_a_sensitivity_range_the_run_refuses_names_param(tmp_path, capsys):
    line = refused(capsys, "sensitivity", "simulate", *TINY, "--param", "revolutions=0,1", "--out",
                   str(tmp_path / "out"))
    assert "--param 'revolutions=0,1': revolutions=0.0 is invalid: allowed > 0" in line     # as the user wrote it


def test_refused_addresses_one_after_another_in_one_process_do_not_hang():
    """A client that failed to connect is left in a reference cycle; collected during the next client's start it
    waited for ever on that start (distributed's LoopRunner): the second refusal in one process hung.  In a
    subprocess with a time limit, so that a hang fails the test instead of stopping the suite."""
    code = ("from wearjoint.sweep import runner\nfrom wearjoint.checks import ParameterError\n"
            "runner.CONNECT_TIMEOUT_S = 1\n"
            "for address in ('notanaddress', 'tcp://127.0.0.1:1', 'notanaddress'):\n"
            "    try:\n        runner.start_client(None, address)\n"
            "    except ParameterError:\n        print('refused', flush=True)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=90)
    assert done.returncode == 0 and done.stdout.split() == ["refused"] * 3, done.stderr[-2000:]


@pytest.mark.parametrize("study", ["sweep", "sensitivity"])
def test_an_option_given_beside_a_design_that_sets_it_everywhere_is_refused(tmp_path, capsys, study):
    """`--vary restitution=0.6 --restitution 0.7` ran at 0.6 and dropped 0.7 without a word; a design whose points
    set an option only where they name it keeps the given value as the others' (sweep_design's [[case]])."""
    design = ["--vary", "restitution=0.6"] if study == "sweep" else ["--param", "restitution=0.5,0.9"]
    err = refused(capsys, study, "simulate", *TINY, *design, "--restitution", "0.7", "--out", str(tmp_path / "o"))
    assert err.endswith("--restitution=0.7 is invalid beside a design that sets restitution at every point (--vary, "
                        "--param, --design): allowed one of the two")
    cases = build_cases("simulate", base("simulate", "--restitution", "0.7"),
                        points=[{"restitution": 0.6}, {"friction-coefficient": 0.2}])
    assert [dict(c.options)["restitution"] for c in cases] == [0.6, 0.7]
    assert not (tmp_path / "o").exists()
    err = refused(capsys, study, "simulate", *TINY, *design, "--restitution", "0.7", "--friction-coefficient", "0.2",
                  *(["--vary", "friction-coefficient=0.1"] if study == "sweep" else
                    ["--param", "friction-coefficient=0.05,0.2"]), "--out", str(tmp_path / "o"))
    assert err.endswith("--restitution=0.7 and --friction-coefficient=0.2 are invalid beside a design that sets "
                        "restitution and friction-coefficient at every point (--vary, --param, --design): allowed one "
                        "of the two for each")     # both in one line: one at a time took a run each


@pytest.mark.parametrize("args, line", [
    (("sweep", "simulate", "--vary", "restitution=0.6", "--retry-failed"),
     "--retry-failed is invalid without --resume: allowed with --resume"),
    (("sensitivity", "simulate", "--param", "restitution=0.5,0.9", "--max-samples", "20"),
     "--max-samples=20 is invalid: allowed only with --target-interval"),
    (("sensitivity", "simulate", "--param", "restitution=0.5,0.9", "--outputs", ""),
     "--outputs='' is invalid: allowed A,B,... numbers of the runs' summary.json"),
])
def test_a_study_option_that_would_do_nothing_is_refused(tmp_path, capsys, args, line):
    err = refused(capsys, *args, *TINY, "--out", str(tmp_path / "o"))
    assert line in err
    assert not (tmp_path / "o").exists()


def test_a_scheduler_without_workers_is_refused_after_waiting_and_a_sweep_with_workers_and_scheduler_too(
        tmp_path, capsys):
    """A sweep on a scheduler with no worker had waited for ever, saying 0/1 case every 16 s: it is refused after
    NO_WORKER_WAIT_S, naming the scheduler.  In a subprocess (a scheduler of its own, no worker); --workers with
    --scheduler, which had been ignored, is refused before anything starts."""
    out = tmp_path / "out"
    code = ("import sys, dask\nfrom distributed import LocalCluster\nfrom wearjoint.cli import main\n"
            "from wearjoint.sweep import runner\nrunner.NO_WORKER_WAIT_S = 1\n"
            # the scheduler's lock files in this test's folder, not TMPDIR/dask-scratch-space
            f"dask.config.set({{'temporary-directory': {str(tmp_path)!r}}})\n"
            "with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:\n"
            f"    code = main(['sweep', 'simulate', '--revolutions', '0.01', '--vary', 'restitution=0.6', '--out', "
            f"{str(out)!r}, '--scheduler', cluster.scheduler_address])\n"
            "print(code, cluster.scheduler_address)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    returned, address = done.stdout.split()[-2:]
    errors = [line for line in done.stderr.splitlines() if "error:" in line]
    assert returned == "2" and len(errors) == 1, done.stderr[-2000:]
    assert errors[0].endswith(f"--scheduler={address!r} is invalid: the scheduler has no worker (waited 1 s); "
                              f"allowed a scheduler with workers (start one: dask worker {address})"), errors
    line = refused(capsys, "sweep", "simulate", *TINY, "--vary", "restitution=0.6", "--workers", "1", "--scheduler",
                   "tcp://127.0.0.1:1", "--out", str(tmp_path / "both"))
    assert "--workers=1 is invalid with --scheduler='tcp://127.0.0.1:1': allowed without it" in line
    assert not (tmp_path / "both").exists()
