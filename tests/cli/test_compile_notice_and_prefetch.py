"""A command that compiles says so first (wearjoint._compile.notice): one line on stderr naming what
compiles and about how long it takes, before anything else; nothing when nothing compiles."""
import json
import os
import subprocess
import sys
import time
from types import SimpleNamespace

import numpy as np
import pytest
from numba import njit

from wearjoint._compile import notice
from wearjoint._compile import prefetch
from wearjoint.fmu import ensure


def _fresh_kernel():
    """A function numba has not compiled yet (a new one per call)."""
    return njit(lambda x: np.sqrt(x) + 1.0)


CACHED_IN_REFERENCE = notice.cached_in_reference


@pytest.fixture(autouse=True)
def cold_engines(monkeypatch):
    """The engines' kernels as on first use (the suite's own runs have cached them)."""
    monkeypatch.setattr(notice, "engine_cached", lambda what: False)
    monkeypatch.setattr(notice, "cached_in_reference", lambda what: (0.0, 0))


def test_with_the_engines_kernels_cached_the_notice_says_a_few_seconds_and_counts_nothing(capsys, monkeypatch):
    """A wear study right after simulate compiles only its own kernels (18 in 2.3 s): "about 33 s" was 14x off."""
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    monkeypatch.setattr(notice, "engine_cached", lambda what: True)
    kernel = _fresh_kernel()
    with notice.watching("simulate") as watch:
        kernel(4.0)
    err = capsys.readouterr().err
    assert err.splitlines() == ["wearjoint: compiling the kernels this command adds (its engine's are cached): "
                                "a few seconds, cached for later runs"]
    assert watch.count == 1


def test_an_engine_is_cached_where_its_marking_kernel_is(tmp_path, monkeypatch):
    from wearjoint._compile import cache

    monkeypatch.undo()      # the real engine_cached
    monkeypatch.setattr(cache, "cache_root", lambda: tmp_path)
    monkeypatch.setattr(cache.KernelCacheLocator, "digest", "d1")
    assert not notice.engine_cached("cosim") and not notice.engine_cached("fmu")
    marker = tmp_path / "d1" / "cosim" / "master_loop.master_loop-350.py311.nbi"
    marker.parent.mkdir(parents=True)
    marker.write_bytes(b"")
    assert notice.engine_cached("cosim") and not notice.engine_cached("simulate")
    monkeypatch.setattr(cache.KernelCacheLocator, "digest", "d2")      # other sources: not theirs
    assert not notice.engine_cached("cosim")


def test_a_compilation_that_lasts_announces_what_compiles_and_its_time(capsys, monkeypatch):
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    kernel = _fresh_kernel()
    with notice.watching("simulate") as watch:
        kernel(4.0)
        kernel(2)                                   # a second specialisation: counted, not announced again
    err = capsys.readouterr().err
    text, seconds = notice.ESTIMATES["simulate"][0], notice.cold_run("simulate")[0]
    assert err.splitlines()[0] == (f"wearjoint: compiling {text}: about {seconds:.0f} s on first use, "
                                   "cached for later runs")
    assert err.count("wearjoint: compiling") == 1 and watch.count == 2


def test_a_short_compilation_says_nothing_and_a_long_one_says_it_once_due(capsys, monkeypatch):
    """A few kernels of a new specialisation (a wear study after the tests) said "about 33 s" for 1.7 s: below
    ANNOUNCE_AFTER_S of compiling nothing is said; past it the notice comes once, counting what compiled."""
    clock = iter([0.0, 0.5, 1.0, 1.5, 2.5, 3.0, 3.5, 4.0])
    monkeypatch.setattr(notice, "_now", lambda: next(clock))
    monkeypatch.setattr(notice, "TICK_S", 3600.0)   # the clock's readings are the events' alone (no ticker's)
    short, long = _fresh_kernel(), _fresh_kernel()
    with notice.watching("simulate") as watch:
        short(4.0)                                  # clock 0 (first), 0.5 (its start), 1.0 (its end)
    assert capsys.readouterr().err == "" and watch.count == 1
    clock = iter([0.0, 0.5, 1.0, 1.5, 2.5, 3.0, 3.5, 4.0])
    with notice.watching("simulate") as watch:
        short(2)                                    # 0, 0.5, 1.0
        long(4.0)                                   # 1.5: not yet; 2.5 at its end: due
    err = capsys.readouterr().err
    assert err.count("wearjoint: compiling") == 1 and watch.count == 2


def test_a_count_still_open_when_the_command_ends_writes_no_line_after_its_results(capsys, monkeypatch):
    """A command that compiles during its run (a wear study's replay) never closes the count at its start: the
    count's last line must not follow the command's own last line ("results in ...").  The clock runs 100 s a
    reading, so the count's log writes at every compilation."""
    from wearjoint import progress

    clock = iter(range(0, 10**6, 100))
    monkeypatch.setattr(progress, "_now", lambda: float(next(clock)))
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    kernel = _fresh_kernel()
    with notice.watching("kernels"):
        kernel(4.0)
        print("results in somewhere", file=sys.stderr)
    assert capsys.readouterr().err.strip().splitlines()[-1] == "results in somewhere"


def _compile_event(module: str, name: str):
    """A "numba:compile" event's data as :class:`wearjoint._compile.notice.CompileWatch` reads it, for function
    module.name."""
    def function():
        pass
    function.__module__, function.__qualname__ = module, name
    return SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=function), "args": "()"})


REFERENCE = {"simulate": [["m.a", 1.0], ["m.b", 2.0], ["m.c", 7.0]], "cosim": [["m.d", 0.4], ["m.e", 3.6]]}


def _stderr_until(capsys, text: str, timeout_s: float = 5.0) -> str:
    """What stderr received until ``text`` came (or ``timeout_s`` passed)."""
    err, deadline = "", time.monotonic() + timeout_s
    while text not in err and time.monotonic() < deadline:
        time.sleep(0.01)
        err += capsys.readouterr().err
    return err


def test_a_long_compilation_is_announced_while_it_runs_and_a_finished_one_not(capsys, monkeypatch):
    """numba's events come as a compilation starts or ends, and one may last 16 s (a cold simulate said nothing for
    its first 17.7 s): the watch's own thread says the notice once due while a compilation runs and moves the bar;
    after the compilations have ended nothing is said however long the command goes on, and after close nothing."""
    import itertools

    from wearjoint import progress

    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.2)
    monkeypatch.setattr(notice, "TICK_S", 0.02)
    monkeypatch.setattr(notice, "reference_runs", lambda: REFERENCE)
    clock = itertools.count(0.0, 100.0)                    # the log's clock: a line at every update
    monkeypatch.setattr(progress, "_now", lambda: next(clock))
    event = _compile_event("m", "a")
    quick = notice.CompileWatch("simulate")
    quick.on_start(event)
    quick.on_end(event)
    time.sleep(0.5)
    quick.close()
    assert capsys.readouterr().err == ""
    watch = notice.CompileWatch("simulate")
    watch.on_start(event)                                  # and no event for the next 5 s at most
    assert "wearjoint: compiling" in _stderr_until(capsys, "wearjoint: compiling")
    assert "compiling: " in _stderr_until(capsys, "compiling: ")     # the bar (a log here: stderr is no terminal)
    watch.on_end(event)
    watch.close()
    capsys.readouterr()
    time.sleep(0.2)
    assert capsys.readouterr().err == ""


def test_the_time_left_is_the_references_rest_at_the_speed_so_far(monkeypatch):
    """The reference's compilations take 10 s; those done here took twice theirs: 2 x the rest is left."""
    monkeypatch.setattr(notice, "reference_runs", lambda: REFERENCE)
    assert notice.cold_run("simulate") == (10.0, 3)
    speed = notice.SpeedCalibration("simulate")
    assert speed.left_s() == 10.0                   # nothing done: the reference's time
    speed.add("m.a", 2.0)
    assert speed.factor() == 2.0 and speed.left_s() == 18.0
    speed.add("elsewhere.unknown", 50.0)            # not in the reference: says nothing of the speed
    speed.add("m.b", 4.0)
    assert speed.factor() == 2.0 and speed.left_s() == 14.0
    speed.add("m.c", 700.0)                         # 706 s for 10: the factor stops at its bound
    assert speed.factor() == notice.SPEED_FACTOR_RANGE[1] and speed.left_s() == 0.0
    short = notice.SpeedCalibration("cosim")
    short.add("m.d", 4.0)                           # 0.4 s of the reference: too little to measure a speed
    assert short.factor() == 1.0 and short.left_s() == 3.6


def test_the_watch_measures_each_compilations_own_seconds(monkeypatch):
    """m.c compiles for 10 s, m.a inside it for 2 of them: 2 s against 1, 8 against 7, so the speed is 10/8 and
    nothing of the reference is left; an engine the reference lacks gets the generic figures."""
    monkeypatch.setattr(notice, "reference_runs", lambda: REFERENCE)
    times = iter([0.0, 1.0, 3.0, 10.0])
    monkeypatch.setattr(notice, "_clock", lambda: next(times))
    watch = notice.CompileWatch("simulate", quiet=True)
    outer, inner = _compile_event("m", "c"), _compile_event("m", "a")
    watch.on_start(outer)
    watch.on_start(inner)
    watch.on_end(inner)
    watch.on_end(outer)
    assert watch.count == 2 and watch.speed.factor() == 1.25 and watch.speed.left_s() == 2.5
    monkeypatch.setattr(notice, "reference_runs", lambda: {})
    assert notice.cold_run("simulate") == tuple(notice.ESTIMATES["kernels"][1:3])


def test_the_bar_says_100_percent_only_once_compiling_is_over(capsys, monkeypatch):
    """A run that compiles more functions than the reference's 2 (the second process had not cached one yet) counts
    on past them: 0/2 at the notice, 1/2, 2/3, 3/4 while compiling, then 100 % of 3.  (It said 100 % for the last
    21 s of a 61 s run.)
    The log's clock runs 100 s a reading, so it writes a line at every compilation."""
    from wearjoint import progress

    monkeypatch.setattr(notice, "reference_runs", lambda: {"simulate": [["m.a", 1.0], ["m.b", 1.0]]})
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    clock = iter(range(0, 10**6, 100))
    monkeypatch.setattr(progress, "_now", lambda: float(next(clock)))
    monkeypatch.setattr(notice, "TICK_S", 3600.0)   # a line per compilation, none of a ticker's
    watch = notice.CompileWatch("simulate")
    for name in ("a", "b", "c"):
        event = _compile_event("m", name)
        watch.on_start(event)
        watch.on_end(event)
    watch.close()
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("compiling:")]
    counts = [line.split("(")[1].split(")")[0] for line in lines]
    assert counts[:4] == ["0/2 functions", "1/2 functions", "2/3 functions", "3/4 functions"], lines
    assert lines[-1].startswith("compiling: 100.0% (3 functions) in ") and "100.0%" not in "".join(lines[:-1])
    # past the reference's count the time left is the count's rate, not the reference's seconds (a new user's run
    # said "ETA ~0:00:26" at 31 of 32, 3 s before its end)
    assert "ETA ~" in lines[0] and not any("ETA ~" in line for line in lines[2:4]), lines
    assert all(", ETA 0:" in line for line in lines[2:4]), lines


def test_what_the_cache_holds_is_left_out_of_the_time(tmp_path, monkeypatch):
    """validate after simulate: of the reference's _integrate_steps twice (30 and 28 s) the cache holds one
    specialisation, and exudyn's kernel; numba's own functions always compile.  Left out: 29 + 2 s, 2 compilations,
    and the notice says the 29.5 s that remain."""
    from wearjoint._compile import cache

    monkeypatch.setattr(notice, "reference_runs", lambda: {"validate": [
        ["wearjoint.core.integrators._integrate_steps", 30.0], ["wearjoint.core.integrators._integrate_steps", 28.0],
        ["wearjoint.exudyn.generalized_contact_forces", 2.0], ["numba.cpython.builtins.ol_int.<locals>.impl", 0.5]]})
    monkeypatch.setattr(cache, "cache_root", lambda: tmp_path)
    monkeypatch.setattr(cache.KernelCacheLocator, "digest", "d1")
    monkeypatch.setattr(notice, "cached_in_reference", CACHED_IN_REFERENCE)      # the real one, not cold_engines'
    assert notice.cached_in_reference("validate") == (0.0, 0)
    for path in ("d1/core/integrators._integrate_steps-228.py311.1.nbc",
                 "d1/exudyn.generalized_contact_forces-80.py311.1.nbc",
                 "d1/core/integrators.record_step-79.py311.1.nbc"):       # a kernel the reference does not name
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_bytes(b"")
    assert notice.cached_in_reference("validate") == (31.0, 2)
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    watch = notice.CompileWatch("validate")
    event = _compile_event("numba.cpython.builtins", "ol_int.<locals>.impl")
    watch.on_start(event)
    watch.on_end(event)
    watch.close(final_line=False)
    assert watch.speed.total_s == 29.5 and watch.speed.count == 2


def test_validate_announces_its_own_engines_kernels():
    with notice.watch_command("validate") as watch:
        assert watch.what == "validate"


def test_the_shipped_reference_holds_each_engines_cold_run():
    """Every engine without figures of its own has a cold run in the reference, which compiled the kernel that
    marks the engine (ESTIMATES; the kernels compiled ahead of time: a kernel of the package) and took a positive
    time; those ahead of time, and the monolithic engine helped by a second process, also their wall seconds, which
    are their figure (the two processes' compilations overlap)."""
    runs, walls = notice.reference_runs(), notice.reference_walls()
    for what, (_, seconds, _, marker) in notice.ESTIMATES.items():
        if seconds is not None:
            continue
        names = [name for name, _ in runs[what]]
        kernel = "wearjoint." if marker is None else marker.split("/")[1].split("-")[0]   # core/integrators._integ...
        assert any(kernel in name for name in names), (what, kernel)
        assert all(isinstance(s, float) and s >= 0.0 for _, s in runs[what]) and notice.cold_run(what)[0] > 1.0
        if what in walls:
            assert notice.cold_run(what) == (walls[what], len(runs[what])) and walls[what] > 1.0
    assert set(walls) == {*notice.AHEAD_OF_TIME, "simulate-helped", "simulate-gear"}


def _ahead_of_time_build(tmp_path, monkeypatch, announce_after_s):
    """kernel_ir's ahead-of-time build of the master with each of its (two) processes a stand-in that prints a
    count of 1 to 5 compilations over 0.5 s, as wearjoint.fmu.aot does; its stderr."""
    from wearjoint.fmu import kernel_ir

    counting = "import time\nfor k in range(1, 6):\n    print(k, flush=True)\n    time.sleep(0.1)\n"
    popen = subprocess.Popen
    monkeypatch.setattr(kernel_ir, "usable_cores", lambda: 2)
    monkeypatch.setattr(subprocess, "Popen", lambda command, **kw: popen([sys.executable, "-c", counting], **kw))
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", announce_after_s)
    kernel_ir._compile_ir_fresh(tmp_path, "master", fresh=True)


def test_an_ahead_of_time_build_that_lasts_says_the_references_wall_time_and_counts_its_processes(
        tmp_path, monkeypatch, capfd):
    """The master's build took 3 s where its notice said "about 13 s" (a hand-typed figure; a cold build here took
    30 s): the notice gives the reference's wall seconds, once the build has lasted ANNOUNCE_AFTER_S, and the count
    is both processes' (5 + 5), and the time left is the reference's wall seconds less those gone (a count's rate said
    "1 s left" for 30 s of the slider-crank FMU's last function).  The log's clock runs 100 s a reading, so it
    writes its lines."""
    from wearjoint import progress

    clock = iter(range(0, 10**6, 100))
    monkeypatch.setattr(progress, "_now", lambda: float(next(clock)))
    _ahead_of_time_build(tmp_path, monkeypatch, 0.2)
    err = capfd.readouterr().err.splitlines()
    seconds = notice.reference_walls()["master"]
    assert err[0] == ("wearjoint: compiling the co-simulation master's kernels, ahead of time (once per source "
                      f"version; two processes): about {seconds:.0f} s on first use, cached for later runs"), err
    assert err[-1].startswith("compiling: 100.0% (10 functions) in "), err
    left = [sum(int(part) * 60**k for k, part in enumerate(reversed(line.split("ETA ~")[1].split(":"))))
            for line in err[1:-1]]
    assert left and all(seconds - 3.5 <= s <= seconds + 0.5 for s in left), (seconds, err)   # shown to the second


def test_a_build_beside_another_running_build_says_their_time_together(tmp_path, monkeypatch, capfd):
    """A change to the kernels rebuilt the joint FMU (another process) and the master at once: their notices said
    18 s and 13 s, their references alone, where they took 35 s and 29 s sharing the cores.  With another live
    process's FMU build marked in the cache, the master's notice gives the two references summed."""
    from wearjoint._compile import concurrent_builds

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        folder = concurrent_builds._folder()
        folder.mkdir(parents=True)
        (folder / f"fmu.{other.pid}").touch()
        _ahead_of_time_build(tmp_path, monkeypatch, 0.2)
    finally:
        other.kill()
        other.wait()
    first = capfd.readouterr().err.splitlines()[0]
    together = notice.reference_walls()["master"] + notice.reference_walls()["fmu"]
    assert f": about {together:.0f} s on first use" in first, first
    assert [marker.name for marker in folder.iterdir()] == [f"fmu.{other.pid}"]   # its own marker gone with it


def test_only_other_live_builds_count_and_a_dead_ones_marker_is_removed(tmp_path, monkeypatch):
    from wearjoint._compile import concurrent_builds

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    finished = subprocess.Popen([sys.executable, "-c", "pass"])
    finished.wait()
    folder = concurrent_builds._folder()
    folder.mkdir(parents=True)
    (folder / f"slider-crank-fmu.{finished.pid}").touch()
    (folder / f"fmu.{os.getppid()}").touch()               # this process's parent: alive
    with concurrent_builds.running("master"):
        assert (folder / f"master.{os.getpid()}").is_file()
        assert concurrent_builds.others("master") == ["fmu"]
        assert concurrent_builds.others("fmu") == ["fmu", "master"]   # the parent's build is another process's
    assert sorted(marker.name for marker in folder.iterdir()) == [f"fmu.{os.getppid()}"]


def test_a_short_ahead_of_time_build_says_nothing(tmp_path, monkeypatch, capfd):
    _ahead_of_time_build(tmp_path, monkeypatch, 5.0)
    assert capfd.readouterr().err == ""


def test_nothing_is_said_when_nothing_compiles(capsys):
    kernel = _fresh_kernel()
    kernel(4.0)
    capsys.readouterr()
    with notice.watch_command("cosim") as watch:
        kernel(9.0)
    assert capsys.readouterr().err == "" and watch.count == 0


def test_the_profile_lists_each_compilation_with_its_own_time(tmp_path, monkeypatch):
    profile = tmp_path / "compile.jsonl"
    monkeypatch.setenv(notice.PROFILE_ENV, str(profile))
    kernel = _fresh_kernel()
    with notice.watching("kernels", quiet=True):
        kernel(4.0)
    rows = [json.loads(line) for line in profile.read_text().splitlines()]
    assert [row[0].rsplit(".", 1)[-1] for row in rows] == ["<lambda>"] and rows[0][2] > 0.0


def test_a_cached_or_given_fmu_starts_no_build_and_a_missing_one_is_built_beside(tmp_path, monkeypatch):
    from wearjoint.fmu.build import default_fmu_path

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert ensure.start_fmu_build(64, tmp_path / "given.fmu", "native") is None
    cached = default_fmu_path(64, "native")
    assert not cached.exists()
    process = ensure.start_fmu_build(64, None, "native")       # missing: a second process builds it
    assert process is not None and process.wait(timeout=600) == 0 and cached.is_file()
    assert ensure.start_fmu_build(64, None, "native") is None   # cached now


def test_a_cold_engine_command_starts_the_second_compiling_process_at_its_first_compilation(monkeypatch, capsys):
    started = []
    monkeypatch.setattr(prefetch, "usable_cores", lambda: 2)
    monkeypatch.setattr(prefetch, "start", lambda: started.append(True))
    monkeypatch.setattr(notice, "ANNOUNCE_AFTER_S", 0.0)
    kernel = _fresh_kernel()
    with notice.watch_command("simulate"):
        assert started == []                        # nothing compiled yet: nothing started
        kernel(4.0)
        kernel(2)
    assert started == [True]
    text = notice.ESTIMATES["simulate-helped"][0]
    assert f"wearjoint: compiling {text}" in capsys.readouterr().err
    with notice.watch_command("simulate"):  # a warm run starts nothing
        kernel(3.0)
    assert started == [True]


def test_one_core_compiles_alone(monkeypatch):
    monkeypatch.setattr(prefetch, "usable_cores", lambda: 1)
    assert prefetch.start() is None
    with notice.watch_command("simulate") as watch:
        assert watch.what == "simulate"


@pytest.mark.slow
def test_a_cold_engine_compiles_none_of_what_the_second_process_cached(tmp_path):
    """Cold, in fresh processes sharing an empty numba cache: the second process first, then a short
    simulate: the engine compiles none of the second process's kernels."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "XDG_CACHE_HOME": str(tmp_path / "cache"),
           notice.PROFILE_ENV: str(tmp_path / "engine.jsonl")}
    helper_env = {k: v for k, v in env.items() if k != notice.PROFILE_ENV}
    subprocess.run([sys.executable, "-m", "wearjoint._compile.prefetch", "kernels"], env=helper_env, check=True)
    subprocess.run([sys.executable, "-c", "from wearjoint.simulate import SimulationOptions, run_simulation; "
                    "from wearjoint._compile.notice import watching\n"
                    "with watching('kernels', quiet=True): "
                    "run_simulation(options=SimulationOptions(revolutions=0.002), progress=False)"],
                   env=env, check=True)
    compiled = {json.loads(line)[0].rsplit(".", 1)[-1] for line in (tmp_path / "engine.jsonl").read_text().splitlines()}
    assert "_integrate_steps" in compiled                       # the engine did compile (a cold cache)
    assert not compiled & {"accept_contact_refreshing", "apply_wear", "foundation_wear", "record_step",
                           "worn_volume"}, compiled


@pytest.mark.parametrize("cores", [1, 2])
def test_the_fmu_build_splits_its_kernels_by_the_cores_it_may_use(monkeypatch, cores):
    """Every entry point is compiled by exactly one ahead-of-time process; a second only where this
    process may run on two cores (its CPU affinity, as `taskset` sets it, not the machine's count)."""
    from wearjoint.fmu import aot, kernel_ir

    monkeypatch.setattr(kernel_ir, "usable_cores", lambda: cores)
    parts = kernel_ir._aot_parts("joint")
    assert len(parts) == cores
    assert sorted(s for part in parts for s in part) == sorted(aot.ENTRY_POINTS["joint"][1])


@pytest.mark.parametrize("options,kernels", [
    ((), "cosim"), (("--fmu-interface", "model-exchange"), "cosim-me"), (("--master", "libcosim"), "cosim-trace")])
def test_cosim_announces_the_kernels_its_interface_compiles(options, kernels):
    """cosim through the FMU's Model Exchange interface compiles the monolithic engine around the FMU (93 functions,
    about 3 minutes on a loaded machine), where its notice had said the master's 29 functions in 15 s; in libcosim
    it compiles what makes the trace the run's record (6 functions, 0.9 s), where it said the master's, 18 s."""
    from wearjoint.cli import build_parser, cosim

    args = build_parser("cosim").parse_args(["cosim", "--out", "unused", *options])
    assert cosim.compiled_kernels(args) == kernels
    assert notice.ESTIMATES[kernels][0].startswith({"cosim-me": "the monolithic engine's", "cosim": "the co-simulation "
                                                    "master's", "cosim-trace": "the numba kernels that make the "
                                                    "master's trace"}[kernels])


@pytest.mark.parametrize("argv,kernels", [
    (("simulate",), "simulate"), (("simulate", "--integrator", "gear"), "simulate-gear")])
def test_bdf_announces_its_own_kernels_and_is_helped_on_two_cores(monkeypatch, argv, kernels):
    """BDF compiles the mechanism's Jacobian and the contact's (30 s after a plain simulate had cached the rest),
    where its notice had said "a few seconds": its own reference run, whose cached part is left out."""
    from wearjoint.cli import build_parser, simulate

    args = build_parser(argv[0]).parse_args([*argv, "--out", "unused"])
    assert simulate.compiled_kernels(args) == kernels
    monkeypatch.setattr(prefetch, "usable_cores", lambda: 2)
    with notice.watch_command(kernels) as watch:
        assert watch.what == {"simulate": "simulate-helped", "simulate-gear": "simulate-gear"}[kernels]
    assert notice.ESTIMATES["simulate-gear"][0].startswith("the monolithic engine's numba kernels for BDF")
    names = {name.rsplit(".", 1)[-1] for name, _ in notice.reference_runs()["simulate-gear"]}
    assert {"state_jacobian", "contact_jacobian"} <= names
