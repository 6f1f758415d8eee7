"""Say what compiles before it does: a command never sits silent for a minute.

numba compiles the kernels on a command's first run (an empty cache, changed sources) and a native
FMU's kernels are compiled ahead of time on its first build.  The first time either starts, one line
on stderr names what compiles and roughly how long it takes here; on a terminal a progress bar
(:mod:`wearjoint.progress`) then counts the compilations against the number a cold run makes.
The notice's time is a cold run's on the project's machine (:data:`REFERENCE_FILE`: each compilation's own seconds
there, written by :mod:`.reference`) less what numba's cache holds of it already; the bar's time left is the
reference's compilations not yet done, scaled by how long those done took here against there
(:class:`SpeedCalibration`: a count of functions said "2 s left" where one function of 39 took 23 s more).  The
notice itself is not scaled: the first seconds of compiling load numba's modules, and ran 1.6-2.8x slower than the
reference where the whole run took 0.9-1.9x.
"""
from __future__ import annotations

import contextlib
import functools
import json
import os
import sys
import threading
import time
from pathlib import Path

# key -> (what compiles, seconds, numba compilations) of a cold run on the project's machine (one core; the
# "-helped" one: the first of two processes, prefetch), and the cache file (a glob below the digest's folder) of a
# kernel only that engine compiles: where it exists the engine's kernels are cached, and what compiles is what the
# command adds (a wear study right after simulate: 18 functions in 2.3 s, where the cold figure said 33 s).  None:
# the seconds and the count of the engine's cold run in REFERENCE_FILE.  cosim compiles nothing where its library is
# built (cosim.native_master: its loop and the run's kernels compiled ahead of time; cold, 3.5 s in all); "fmu",
# "slider-crank-fmu" and "master" are compiled ahead of time in other processes (:data:`AHEAD_OF_TIME`): their
# figures are the wall seconds of the reference's cold build and its count of compilations, not scaled
ESTIMATES = {
    "simulate": ("the monolithic engine's numba kernels", None, None, "core/integrators._integrate_steps-*.nbi"),
    "simulate-helped": ("the monolithic engine's numba kernels (the wear's in a second process)", None, None,
                        "core/integrators._integrate_steps-*.nbi"),
    "simulate-gear": ("the monolithic engine's numba kernels for BDF (`--integrator gear`: with the mechanism's "
                      "Jacobian; the wear's in a second process)", None, None,
                      "core/slider_crank_jacobian.state_jacobian-*.nbi"),
    "cosim": ("the co-simulation master's numba kernels (no library of them could be built here)", None, None,
              "cosim/master_loop.master_loop-*.nbi"),
    "cosim-me": ("the monolithic engine's numba kernels, around the FMU's Model Exchange interface", None, None,
                 "cosim/fmu_joint._accept-*.nbi"),
    # a third-party master's trace made the run's record (cli/cosim.compiled_kernels): cold, `cosim --master container
    # --no-plots` compiled 6 functions in 0.9 s, under the reference's sanity bound of a cold run (1 s), so measured
    # once and written here as "kernels" is
    "cosim-trace": ("the numba kernels that make the master's trace the run's record", 0.9, 6,
                    "core/integrators.record_points-*.nbi"),
    "validate": ("the compared engines' numba kernels (the monolithic engine's, through the FMU too, and exudyn's "
                 "joint)", None, None, "cosim/fmu_joint._accept-*.nbi"),
    "fmu": ("the joint FMU's kernels, ahead of time (once per source version; two processes)", None, None, None),
    "slider-crank-fmu": ("the slider-crank FMU's kernels, ahead of time (once per source version; two processes)",
                         None, None, None),
    "master": ("the co-simulation master's kernels, ahead of time (once per source version; two processes)", None,
               None, None),
    "exudyn": ("the exudyn joint's numba kernels", None, None, "core/generalized_coordinates.accept_step-*.nbi"),
    "kernels": ("the numba kernels", 20, 90, None),
}
# each compilation (function, its own seconds) of a cold run of the engines with None above, in order
REFERENCE_FILE = Path(__file__).with_name("compile_reference.json")
# the speed here is measured once the compilations matched in the reference took this many seconds there; the
# factor is kept within these bounds
CALIBRATE_AFTER_S = 0.5
SPEED_FACTOR_RANGE = (0.2, 5.0)
# the keys of the kernels compiled ahead of time -> their model (:data:`wearjoint.fmu.aot.ENTRY_POINTS`)
AHEAD_OF_TIME = {"fmu": "joint", "slider-crank-fmu": "slider-crank", "master": "master"}
COMMAND_KERNELS = {"simulate": "simulate", "simulate-gear": "simulate-gear", "cosim": "cosim", "cosim-me": "cosim-me",
                   "cosim-trace": "cosim-trace", "cosim-study": "cosim", "validate": "validate"}
# commands (or their kernels' keys) of the monolithic engine -> the key of their run on two cores, where a second
# process compiles the wear's kernels (prefetch)
HELPED_COMMANDS = {"simulate": "simulate-helped", "wear-study": "simulate-helped", "simulate-gear": "simulate-gear"}
# a file to append each compilation to (JSON lines: function, argument types, seconds exclusive of nested ones)
PROFILE_ENV = "WEARJOINT_COMPILE_PROFILE"
# compilations shorter than this say nothing (a few kernels of a new specialisation, not a cold run: a notice of
# the cold run's time would be wrong by tenfold); the notice and the count start once compiling has lasted it
ANNOUNCE_AFTER_S = 2.0
# while compiling, the notice (once due) and the bar's elapsed time are brought up to date this often by a thread of
# their own: numba's events come when a compilation starts or ends, and one may last 16 s (a cold simulate said
# nothing for its first 17.7 s, then nothing more until its results at 34.6 s)
TICK_S = 0.5


def _now() -> float:
    """The clock of the announcement's delay (a module function so that tests can set it)."""
    return time.perf_counter()


def _clock() -> float:
    """The clock of each compilation's seconds (a module function so that tests can set it)."""
    return time.perf_counter()


@functools.cache
def _reference() -> dict:
    """:data:`REFERENCE_FILE` ({} while :mod:`.reference` writes the file for the first time)."""
    return json.loads(REFERENCE_FILE.read_text()) if REFERENCE_FILE.is_file() else {}


def reference_runs() -> dict:
    """Engine key -> [[function, seconds], ...], its cold run's compilations in order (:data:`REFERENCE_FILE`)."""
    return _reference().get("runs", {})


def reference_walls() -> dict:
    """Key of :data:`AHEAD_OF_TIME`, and ``simulate-helped`` -> the wall seconds of its cold build or command in the
    reference (its processes run side by side: their compilations' seconds add up to more)."""
    return _reference().get("walls", {})


def cold_run(what: str) -> tuple[float, int]:
    """(seconds, compilations) of ``what``'s cold run on the project's machine (:data:`ESTIMATES`; an engine the
    reference lacks: the generic figures)."""
    _, seconds, count, _ = ESTIMATES[what]
    if seconds is None:
        run = reference_runs().get(what)
        if run is None:
            return cold_run("kernels")
        return reference_walls().get(what, sum(s for _, s in run)), len(run)
    return seconds, count


def reference_seconds(what: str) -> dict[str, float]:
    """function -> its mean seconds per compilation in ``what``'s reference run (every engine's for a key without
    one)."""
    runs = reference_runs()
    rows = runs[what] if what in runs else [row for run in runs.values() for row in run]
    sums: dict[str, list[float]] = {}
    for name, seconds in rows:
        sums.setdefault(name, []).append(seconds)
    return {name: sum(values) / len(values) for name, values in sums.items()}


def cached_in_reference(what: str) -> tuple[float, int]:
    """(seconds, compilations) of ``what``'s reference run whose compiled code numba's cache holds for these sources
    already (a function compiled n times there and cached in m specialisations counts min(n, m) times at its
    mean): a command after another that shares kernels compiles only the rest (validate after simulate)."""
    from .cache import PACKAGE, KernelCacheLocator, cache_root

    digest = getattr(KernelCacheLocator, "digest", None)
    if not digest:
        return 0.0, 0
    folder = cache_root() / digest
    occurrences: dict[str, int] = {}
    for name, _ in reference_runs().get(what, []):
        occurrences[name] = occurrences.get(name, 0) + 1
    means = reference_seconds(what)
    seconds, count = 0.0, 0
    for name, n in occurrences.items():
        parts = name.split(".")
        if parts[0] != PACKAGE.name or len(parts) < 3:
            continue                               # numba's own functions: compiled afresh by every process
        # a kernel of a subpackage (wearjoint.core.integrators._integrate_steps) is cached in its folder (core) as
        # integrators._integrate_steps-<line>.py311.<k>.nbc, one file per specialisation
        inside = (PACKAGE / parts[1]).is_dir()
        stem = ".".join(parts[2:] if inside else parts[1:])
        cached = min(n, sum(1 for _ in (folder / parts[1] if inside else folder).glob(f"{stem}-*.nbc")))
        seconds += cached * means[name]
        count += cached
    return seconds, count


def _function_name(event) -> str:
    """module.qualname of the function a "numba:compile" event compiles."""
    function = getattr(event.data["dispatcher"], "py_func", None)
    return f"{function.__module__}.{function.__qualname__}" if function else str(event.data["dispatcher"])


class SpeedCalibration:
    """How fast compiling goes here against the reference run: the seconds the finished compilations took here
    over their seconds there (those the reference has), and from it the time left.  :meth:`leave_out` takes away
    what the cache holds already."""

    def __init__(self, what: str):
        self.total_s, self.count = cold_run(what)
        self._reference = reference_seconds(what)
        self.here_s = 0.0          # the matched compilations' seconds here
        self.there_s = 0.0         # ... and in the reference run

    def leave_out(self, seconds: float, count: int) -> None:
        """The reference's compilations that will not happen here (cached already): off the total."""
        self.total_s = max(0.0, self.total_s - seconds)
        self.count = max(1, self.count - count)

    def add(self, name: str, seconds: float) -> None:
        there = self._reference.get(name)
        if there is not None:
            self.here_s += seconds
            self.there_s += there

    def factor(self) -> float:
        """Seconds here per second there (1 until CALIBRATE_AFTER_S of the reference is matched)."""
        if self.there_s < CALIBRATE_AFTER_S:
            return 1.0
        low, high = SPEED_FACTOR_RANGE
        return min(high, max(low, self.here_s / self.there_s))

    def left_s(self) -> float:
        """The seconds the compilations not yet matched take at this speed."""
        return max(0.0, self.total_s - self.there_s) * self.factor()


def engine_cached(what: str) -> bool:
    """Whether the kernel that marks ``what``'s engine (:data:`ESTIMATES`) is in numba's cache for these sources."""
    from .cache import KernelCacheLocator, cache_root

    pattern = ESTIMATES[what][3]
    digest = getattr(KernelCacheLocator, "digest", None)
    return pattern is not None and digest is not None and any((cache_root() / digest).glob(pattern))


def announce(what: str, stream=None, cached: bool = False, seconds: float | None = None) -> None:
    """The one line: what compiles and about how long it takes (``what`` a key of :data:`ESTIMATES`; ``cached``:
    its engine's kernels are, and only what the command adds compiles; ``seconds``: the reference's time of what
    is not cached, else a cold run's)."""
    text = ESTIMATES[what][0]
    seconds = cold_run(what)[0] if seconds is None else seconds
    line = ("the kernels this command adds (its engine's are cached): a few seconds" if cached else
            f"{text}: about {seconds:.0f} s on first use")
    print(f"wearjoint: compiling {line}, cached for later runs", file=stream or sys.stderr, flush=True)


class CompileWatch:
    """What :func:`watching` does with numba's "numba:compile" events: at the first, ``on_first()``
    (optional) and what the cache holds of the reference run left out (:func:`cached_in_reference`); once
    compiling has lasted ANNOUNCE_AFTER_S, :func:`announce` and a progress bar of the compilations with the time
    left at the speed measured so far (:class:`SpeedCalibration`; unless ``quiet``); with :data:`PROFILE_ENV` set,
    each compilation's own time appended there.  ``on_compile`` (optional) is called with the count after each
    compilation."""

    def __init__(self, what: str, on_compile=None, quiet: bool = False, on_first=None):
        self.what = what
        self.quiet = quiet
        self.count = 0
        self._bar = None
        self._on_compile = on_compile
        self._on_first = on_first
        self._stack = []
        self._profile = os.environ.get(PROFILE_ENV)
        self._first = None          # when the first compilation started (clock _now)
        self._announced = False
        self._cached = False        # the engine's kernels were cached when compiling started
        self.speed = SpeedCalibration(what)
        self._lock = threading.RLock()      # the events' thread and the ticker's
        self._stopped = threading.Event()

    def on_start(self, event) -> None:
        with self._lock:
            if self.count == 0 and not self._stack and self._first is None:
                self._first = _now()
                self._cached = not self.quiet and engine_cached(self.what)   # before this command caches anything
                if not self.quiet and not self._cached:
                    self.speed.leave_out(*cached_in_reference(self.what))
                if self._on_first is not None:
                    self._on_first()
                    self._on_first = None
                if not self.quiet:
                    threading.Thread(target=self._tick, name="wearjoint-compile-notice", daemon=True).start()
            self._announce_when_due()
            self._stack.append([_clock(), 0.0])

    def _tick(self) -> None:
        """Every TICK_S until :meth:`close`, while a compilation runs: the notice once due, and the bar again (its
        elapsed time moves)."""
        while not self._stopped.wait(TICK_S):
            with self._lock:
                if self._stopped.is_set():
                    return
                if self._stack:
                    self._announce_when_due()
                    if self._bar is not None:
                        self._update_bar()

    def _announce_when_due(self) -> None:
        """The notice and the count, once compiling has lasted ANNOUNCE_AFTER_S."""
        if not self.quiet and not self._announced and _now() - self._first >= ANNOUNCE_AFTER_S:
            self._announced = True
            self._bar = announced_progress(self.what, self._cached, self.speed)
            self._update_bar()

    def _update_bar(self) -> None:
        if not self._cached and self.count >= self._bar.total:
            # more compilations than the reference run's (the second process had not cached one of its kernels yet):
            # the bar must not say 100 % while a kernel compiles (it said so for the last 21 s of a 61 s run)
            self._bar.set_total(self.count + 1)
        # past the reference run's count the compilations are not the reference's: the time left is the count's
        # rate (the reference's seconds said "ETA ~0:00:26" at 31 of 32, 3 s before the end)
        beyond = self.count >= self.speed.count
        self._bar.update(self.count, None if self._cached or beyond else self.speed.left_s())

    def on_end(self, event) -> None:
        with self._lock:
            start, nested = self._stack.pop()
            seconds = _clock() - start
            if self._stack:
                self._stack[-1][1] += seconds
            self.count += 1
            name = _function_name(event)
            self.speed.add(name, seconds - nested)
            self._announce_when_due()
            if self._bar is not None:
                self._update_bar()
        if self._on_compile is not None:
            self._on_compile(self.count)
        if self._profile:
            with open(self._profile, "a") as out:
                out.write(json.dumps([name, str(event.data["args"]), seconds - nested]) + "\n")

    def close(self, final_line: bool = True) -> None:
        """Close the progress bar (compiling is over: what compiled is the whole count) and stop the ticker;
        without ``final_line`` (the command has ended) a log writes no last line."""
        with self._lock:
            self._stopped.set()
            if self._bar is not None:
                if not self._cached and self.count > 0:
                    self._bar.set_total(self.count)
                self._bar.close(final_line)
                self._bar = None


_ACTIVE: list[CompileWatch] = []


@contextlib.contextmanager
def watching(what: str, on_compile=None, quiet: bool = False, on_first=None):
    """Announce and count numba's compilations inside the block (``what``: a key of :data:`ESTIMATES`;
    ``on_first``: called as the first compilation starts)."""
    from numba.core import event     # here, not at the module's import: a command that compiles nothing needs none

    watch = CompileWatch(what, on_compile, quiet, on_first)

    class Listener(event.Listener):
        on_start, on_end = watch.on_start, watch.on_end

    listener = Listener()
    event.register("numba:compile", listener)
    _ACTIVE.append(watch)
    try:
        yield watch
    finally:        # a bar still open here counted compilations of the run itself: no line after its results
        _ACTIVE.remove(watch)
        event.unregister("numba:compile", listener)
        watch.close(final_line=False)


def watch_command(command: str):
    """:func:`watching` for a command of the CLI (its kernels' estimate, or the generic one; ``cosim-me``: cosim
    through the FMU's Model Exchange interface); a command
    of :data:`HELPED_COMMANDS` on two cores or more starts :mod:`.prefetch` as it starts compiling."""
    from . import prefetch

    if command in HELPED_COMMANDS and prefetch.usable_cores() > 1:
        return watching(HELPED_COMMANDS[command], on_first=prefetch.start)
    return watching(COMMAND_KERNELS.get(command, "kernels"))


def announced_progress(what: str, cached: bool = False, speed: SpeedCalibration | None = None,
                       seconds: float | None = None):
    """:func:`announce` and a progress bar of ``what``'s compilations, counted by the caller (none where only what
    the command adds compiles: their number is not known); with ``speed``, or for a build ahead of time
    (:data:`AHEAD_OF_TIME`: its last functions take most of its time, so a count's rate says "1 s left" for 30),
    the caller gives the bar the time left.  ``seconds``: the time to announce (a build ahead of time beside others:
    their references summed, :mod:`.concurrent_builds`), else the reference's or ``speed``'s."""
    from ..progress import Progress

    announce(what, cached=cached, seconds=seconds if seconds is not None else None if speed is None else speed.total_s)
    count = cold_run(what)[1] if speed is None else speed.count
    return Progress(0 if cached else count, "compiling", unit="functions", delay_s=0.0,
                    caller_eta=speed is not None or what in AHEAD_OF_TIME)


def watched() -> bool:
    """True while a :func:`watching` block runs (a command's: a library's first calls inside it need no watch)."""
    return bool(_ACTIVE)


def compiled() -> None:
    """Compilation is over (the run starts): close the progress bars of :func:`watching`."""
    for watch in _ACTIVE:
        watch.close()


# a library's first kernel calls in the process (the exudyn helper's: from its first force until its first accepted
# step): [(ExitStack, watch)] while they run, [None] once over or watched by a command (validate: its own notice)
_first_use: list = []


def first_use_starts(what: str) -> None:
    """Watch the process's first kernel calls of ``what`` (:func:`watching`), once; none inside a command's watch."""
    if _first_use:
        return
    if watched():
        _first_use.append(None)
        return
    stack = contextlib.ExitStack()
    _first_use.append((stack, stack.enter_context(watching(what))))


def first_use_over() -> None:
    """Close the first use's watch if it is open (its count's last line: the compilation is over)."""
    if not _first_use or _first_use[-1] is None:
        return
    stack, watch = _first_use.pop()
    watch.close()
    stack.close()
    _first_use.append(None)
