"""What a Dask worker runs for one case: the command's own ``wearjoint.cli.main`` in this
process, into a temporary folder whose files go back to the client.

The first case of each worker process warms the numba kernels of its engine (loads them
from numba's cache, compiling them if the cache is cold); later cases reuse them.  A
process runs one case at a time (a lock: the commands print to stdout and draw with
matplotlib, neither safe across threads), so give workers one thread (``--nthreads 1``).
"""
from __future__ import annotations

import contextlib
import importlib
import io
import os
import shutil
import socket
import tempfile
import threading
import time
import traceback
from pathlib import Path

_LOCK = threading.Lock()
_WARM_ENGINES: set = set()
NOT_SHIPPED = ("wear_study_checkpoint.pkl",)     # a finished case needs no checkpoint


def _engine(command: str, options: dict) -> tuple:
    if command == "cosim" or options.get("engine") == "cosim":
        return ("cosim", options.get("fmu_backend"), str(options.get("fmu")))
    return ("monolithic",)


def warm_up(command: str, options: dict) -> float:
    """Compile (or load from numba's cache) the kernels of the case's engine, once per process
    and engine; returns the seconds it took (0 when already warm)."""
    key = _engine(command, options)
    if key in _WARM_ENGINES:
        return 0.0
    start = time.perf_counter()
    from ..cli import COMMANDS

    importlib.import_module(COMMANDS[command][0])          # the command's imports, once
    if key[0] == "monolithic":
        from ..simulate import Simulation

        Simulation().warm_up()
    else:
        from ..cosim import CoSimulation

        with CoSimulation(fmu_path=options.get("fmu"), fmu_backend=options["fmu_backend"]) as sim:
            sim.warm_up()
    _WARM_ENGINES.add(key)
    return time.perf_counter() - start


def _error_line(log: str) -> str:
    """The command's one-line error ("wearjoint CMD: error: MESSAGE" -> MESSAGE), else the last line."""
    lines = [line.strip() for line in log.splitlines() if line.strip()]
    for line in reversed(lines):
        if "error:" in line:
            return line.split("error:", 1)[1].strip()
    return lines[-1] if lines else "no message"


def run_case(command: str, argv: list, no_plots: bool = False) -> dict:
    """Run ``wearjoint COMMAND *argv`` here; returns status ("ok", "failed" or "interrupted"),
    the error message, the captured output, the results folder's files (relative path -> bytes),
    ``run_time_s`` (the command), ``warmup_time_s`` and the worker's name."""
    from ..cli import main
    from .design import command_parser

    with _LOCK:
        warmup_s, error = 0.0, None
        log = io.StringIO()
        folder = Path(tempfile.mkdtemp(prefix="wearjoint-case-"))
        try:
            with contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
                try:
                    warmup_s = warm_up(command, vars(command_parser(command).parse_args([*argv, "--out", "."])))
                except (Exception, SystemExit):  # the case itself reports what is wrong
                    traceback.print_exc()
                start = time.perf_counter()
                try:
                    code = main([command, *argv, "--out", str(folder), "--quiet", *(["--no-plots"] if no_plots else [])])
                except SystemExit as exc:        # argparse
                    code = exc.code if isinstance(exc.code, int) else 2
                except Exception as exc:         # numerical failure, FMU error, ...
                    traceback.print_exc()
                    code, error = 1, f"{type(exc).__name__}: {exc}"
                run_time_s = time.perf_counter() - start
            text = log.getvalue()
            status = "ok" if code == 0 else ("interrupted" if code == 130 else "failed")
            if status != "ok" and error is None:
                error = _error_line(text)
            files = {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
                     if p.is_file() and p.name not in NOT_SHIPPED}
        finally:
            shutil.rmtree(folder, ignore_errors=True)
    return {"status": status, "error": error, "log": text, "files": files, "run_time_s": run_time_s,
            "warmup_time_s": warmup_s, "worker": f"{socket.gethostname()}:{os.getpid()}"}


__all__ = ["run_case", "warm_up"]
