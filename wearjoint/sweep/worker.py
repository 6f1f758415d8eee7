"""What a Dask worker runs for one case: the case's target (:mod:`wearjoint.targets`: options -> config -> run ->
record) in this process, into a temporary folder whose files go back to the client.

A case that fails raises one of its target's ``failures`` (a bad option value, a diverged run, a failed FMU): the
case's error is that exception's message.  Anything else is a fault of the program: its type and message, the
traceback in the case's log.  The log holds what the case printed (and its error line).

The first case of each worker process warms the numba kernels of its engine (loads them
from numba's cache, compiling them if the cache is cold); later cases reuse them.  A
process runs one case at a time (a lock: runs print to stdout and draw with
matplotlib, neither safe across threads), so give workers one thread (``--nthreads 1``).
"""
from __future__ import annotations

import contextlib
import io
import os
import shlex
import shutil
import socket
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path

from .. import targets
from ..processes import process_alive

_LOCK = threading.Lock()
_WARM_ENGINES: set = set()
NOT_SHIPPED = ("wear_study_checkpoint.pkl",)     # a finished case needs no checkpoint
# a case's temporary results folder: this prefix, the worker's process id, "-", a random part
CASE_FOLDER_PREFIX = "wearjoint-case-"
INPUTS_FOLDER_PREFIX = "wearjoint-inputs-"       # and of the input files written for it
DASK_FOLDER_PREFIX = "wearjoint-dask-"           # and of a local cluster's scratch space (the process that started it)


def remove_orphan_case_folders(root: Path | None = None) -> None:
    """Remove the case and input folders (under ``root``, default the temporary folder) of worker processes that are
    gone, and the scratch spaces of local clusters whose process is: a sweep stopped by ending its workers left each
    running case's folder behind, results files included (11 MB for one wear-study case), one killed its cluster's.
    Process ids are this machine's: workers in containers that share one temporary folder need a TMPDIR each."""
    for prefix in (CASE_FOLDER_PREFIX, INPUTS_FOLDER_PREFIX, DASK_FOLDER_PREFIX):
        for folder in Path(root or tempfile.gettempdir()).glob(f"{prefix}*-*"):
            pid = folder.name[len(prefix):].split("-", 1)[0]
            if pid.isdigit() and int(pid) != os.getpid() and not process_alive(int(pid)):
                shutil.rmtree(folder, ignore_errors=True)


def new_case_folder(root: Path | None = None) -> Path:
    """A case's temporary folder, named by this process (:func:`remove_orphan_case_folders` first)."""
    remove_orphan_case_folders(root)
    return Path(tempfile.mkdtemp(prefix=f"{CASE_FOLDER_PREFIX}{os.getpid()}-", dir=root))


def warm_up(command: str, options: dict) -> float:
    """Compile (or load from numba's cache) the kernels of the case's engine, once per process
    and engine; returns the seconds it took (0 when already warm)."""
    start = time.perf_counter()
    key = targets.target(command).engine(options)
    if key in _WARM_ENGINES:
        return 0.0
    if key[0] == "monolithic":
        from ..simulate import Simulation

        Simulation().warm_up()
    else:
        from ..cosim import CoSimulation

        with CoSimulation(fmu_path=options.get("fmu"), fmu_backend=options["fmu_backend"]) as sim:
            sim.warm_up()
    _WARM_ENGINES.add(key)
    return time.perf_counter() - start


def command_line(case, folder, no_plots: bool = False) -> str:
    """The command the case's run equals (its report and summary.json state it)."""
    argv = [case.command, *case.argv(), "--out", str(folder), "--quiet", *(["--no-plots"] if no_plots else [])]
    return "wearjoint " + " ".join(shlex.quote(a) for a in argv)


def _written_inputs(options: dict, inputs: tuple, folder: Path) -> dict:
    """The case's input files where this worker does not read them as the client did (another folder or machine)
    written into ``folder`` (one subfolder each): dest -> the path its option takes (a calibration's folder, a
    table's file)."""
    from .design import case_inputs, INPUT_FILES

    paths, here = {}, dict((dest, data) for dest, _, data in case_inputs(options))
    for k, (dest, name, data) in enumerate(inputs):
        if here.get(dest) == data:                  # the user's own file, as the client read it
            continue
        (folder / str(k)).mkdir()
        (folder / str(k) / name).write_bytes(data)
        paths[dest] = str(folder / str(k) if INPUT_FILES[dest] else folder / str(k) / name)
    return paths


def _run(case, folder: Path, no_plots: bool) -> tuple:
    """(status, error) of the case's run into ``folder``: "ok"; "failed" and the message of the exception that
    failed it; "interrupted"."""
    from .._compile.notice import watch_command

    spec = targets.target(case.command)
    try:
        with watch_command(case.command), tempfile.TemporaryDirectory(
                prefix=f"{INPUTS_FOLDER_PREFIX}{os.getpid()}-") as inputs:
            options = dict(case.options)
            options.update(_written_inputs(options, case.inputs, Path(inputs)))    # as the client read them
            targets.run(case.command, options, folder, plots=not no_plots,
                        command_line=command_line(case, folder, no_plots))
    except spec.failures as exc:                     # the case's failure: its message is the error
        print(f"wearjoint {case.command}: error: {exc}", file=sys.stderr)
        return "failed", str(exc)
    except KeyboardInterrupt:
        return "interrupted", None
    except Exception as exc:                         # a fault: its type too, and the traceback in the log
        traceback.print_exc()
        return "failed", f"{type(exc).__name__}: {exc}"
    return "ok", None


def run_case(case, no_plots: bool = False, kept_folder: str | None = None) -> dict:
    """Run ``case`` (a :class:`wearjoint.sweep.design.Case`) here; returns status ("ok", "failed" or "interrupted"),
    the error message, the captured output, the results folder's files (relative path -> bytes),
    ``run_time_s`` (the run), ``warmup_time_s`` and the worker's name.  ``kept_folder``: run in this folder
    (a wear study's on the client's machine), kept if the run is interrupted, so that the case resumes there
    from its checkpoint (:func:`wearjoint.targets.wear_study_run`); else a temporary one."""
    with _LOCK:
        warmup_s = 0.0
        log = io.StringIO()
        folder = Path(kept_folder) if kept_folder else new_case_folder()
        folder.mkdir(parents=True, exist_ok=True)
        status = "interrupted"
        try:
            with contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
                try:
                    warmup_s = warm_up(case.command, dict(case.options))
                except Exception:                    # the case itself reports what is wrong
                    traceback.print_exc()
                start = time.perf_counter()
                status, error = _run(case, folder, no_plots)
                run_time_s = time.perf_counter() - start
            files = {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
                     if p.is_file() and p.name not in NOT_SHIPPED}
        finally:
            if not (kept_folder and status == "interrupted"):
                shutil.rmtree(folder, ignore_errors=True)
    return {"status": status, "error": error, "log": log.getvalue(), "files": files, "run_time_s": run_time_s,
            "warmup_time_s": warmup_s, "worker": f"{socket.gethostname()}:{os.getpid()}"}


__all__ = ["run_case", "warm_up", "command_line"]
