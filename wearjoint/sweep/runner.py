"""Run a sweep's cases as Dask tasks and keep every finished case on disk as it completes.

Cluster: a ``distributed.LocalCluster`` of ``workers`` processes with one thread each, or the
existing cluster at ``scheduler``.  Each task is :func:`wearjoint.sweep.worker.run_case` (the case's
target, :mod:`wearjoint.targets`); its results folder comes back to the client (no shared file system
needed) and is written to ``OUT/cases/CASE_ID/`` with ``log.txt`` and, last, ``case.json`` (the case,
its status and summary figures): a case with ``case.json`` is done.  ``sweep.csv`` is rewritten after every
case.  Ctrl-C cancels the cases still running and keeps the finished ones.
"""
from __future__ import annotations

import csv
import gc
import json
import logging
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
import weakref
from pathlib import Path

from .. import targets
from ..parameters import ParameterError
from ..progress import Progress
from ..results import write_json_atomic
from .design import SEED_ANGLE_STEP_DEG, Case, design_changes, variable_actions

SPEC_NAME = "sweep.json"
CASE_NAME = "case.json"
LEAD_COLUMNS = ("case_id", "seed", "status", "error")
PENDING = "pending"   # the status of a case not finished (never written to sweep.csv)
CONNECT_TIMEOUT_S = 30   # how long --scheduler's address may take to answer
NO_WORKER_WAIT_S = 30.0   # how long a scheduler without workers is waited for before the sweep is refused
TAIL_COLUMNS = ("run_time_s", "warmup_time_s", "worker", "folder")
SNAPSHOT_FIGURES = ("max_wear_depth_m", "worn_volume_m3", "lobe_0_depth_m", "lobe_180_depth_m", "impact_events",
                    "impact_peak_max_m_s2")


def summary_figures(summary: dict) -> dict:
    """The numbers of a case's summary.json as flat columns: every top-level number, the run's ``regime``
    (:func:`wearjoint.analysis.regime`), and for a wear study ``rev{R}_{figure}`` per snapshot, the
    growth exponent and with a life's depth ``life_reached`` (1 or 0)."""
    row = {k: v for k, v in summary.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    if isinstance(summary.get("regime"), str):
        row["regime"] = summary["regime"]
    for snap in summary.get("snapshots", []):
        for key in SNAPSHOT_FIGURES:
            if isinstance(snap.get(key), (int, float)):
                row[f"rev{snap['revolution']}_{key}"] = snap[key]
    growth = summary.get("growth", {})
    if isinstance(growth.get("growth_exponent"), (int, float)):
        row["growth_exponent"] = growth["growth_exponent"]
    if isinstance(summary.get("life"), dict):     # --life-depth-m: 0 where the study stopped short of the depth
        row["life_reached"] = int(summary["life"].get("revolutions") is not None)
    return row


def point_columns(case: Case) -> dict:
    """The case's swept values keyed by parameter name (the option's dest, e.g. crank_speed_rpm)."""
    actions = variable_actions(case.command)
    return {actions[name].dest: value for name, value in case.point}


def case_row(case: Case, status: str = PENDING, error=None, figures=None, extra=None) -> dict:
    """The case's row of sweep.csv (the one place rows are built): its id, swept values (columns
    :func:`point_columns`), seed, status, error, summary figures, timings and folder."""
    return {"case_id": case.case_id, **point_columns(case), "seed": case.seed, "status": status,
            "error": error or "", **(figures or {}), **(extra or {}), "folder": f"cases/{case.case_id}"}


def write_csv_atomic(path: Path, rows: list[dict], lead=()) -> None:
    """Rows as CSV (columns: ``lead`` first, then in order of first appearance)."""
    columns = list(dict.fromkeys([*lead, *(k for r in rows for k in r)]))
    tail = [c for c in TAIL_COLUMNS if c in columns]
    columns = [c for c in columns if c not in tail] + tail
    tmp = path.with_suffix(path.suffix + ".tmp")
    with open(tmp, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns, restval="")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, path)


def refuse_existing(out) -> None:
    """A one-line ParameterError if ``out`` holds a sweep or a sensitivity study already (a run without
    ``--resume``)."""
    if (Path(out) / SPEC_NAME).exists():
        raise ParameterError(f"--out {out} already holds a sweep or sensitivity study ({SPEC_NAME}); pass --resume to "
                             "continue it or choose another --out")


def resumed(out, what: str = "sweep") -> dict:
    """The sweep.json of the ``what`` (a sweep, a sensitivity study) in ``out`` that ``--resume`` continues; a
    one-line ParameterError naming --resume and the folder where it holds none."""
    try:
        spec = json.loads((Path(out) / SPEC_NAME).read_text())
    except (OSError, ValueError):
        spec = None
    if not isinstance(spec, dict):
        raise ParameterError(f"--resume is invalid: {out} holds no {what} to resume (no readable {SPEC_NAME}); "
                             f"allowed the --out of an earlier {what}, or leave out --resume to start one")
    return spec


def check_resumed_design(out, design: dict, cases: list[Case]) -> None:
    """A one-line ParameterError naming what differs if the sweep in ``out`` has another design than ``design``
    (:func:`.design.design_record`; a sweep.json of an earlier version, without one: other cases)."""
    spec = resumed(out)
    if "design" in spec:
        changes = design_changes(spec["design"], design)
    else:
        changes = [] if {c.get("case_id") for c in spec.get("cases", [])} == {c.case_id for c in cases} else \
            [f"the cases: {len(spec.get('cases', []))} there, {len(cases)} now, not the same (its sweep.json, of an "
             "earlier version, records no design)"]
    if changes:
        raise ParameterError(f"--resume is invalid: the sweep in {out} has another design: {'; '.join(changes)}; "
                             "allowed the sweep's own design (the options that started it, again, with --resume: its "
                             "sweep.json's design), or another --out for a new sweep")


class SweepFolder:
    """``OUT``: sweep.json, cases/CASE_ID/, sweep.csv."""

    def __init__(self, out, cases: list[Case], resume: bool, retry_failed: bool = False, design: dict | None = None):
        """``design``: the sweep's (:func:`.design.design_record`), recorded in sweep.json for ``--resume``."""
        self.out = Path(out)
        self.cases = cases
        self.point_names = list(point_columns(cases[0])) if cases else []   # the swept values' columns
        if not resume:
            refuse_existing(self.out)
        self.out.mkdir(parents=True, exist_ok=True)
        write_json_atomic(self.out / SPEC_NAME, {
            "command": cases[0].command if cases else None, "cases": [c.to_dict() for c in cases],
            "seed_angle_step_deg": SEED_ANGLE_STEP_DEG, **({"design": design} if design is not None else {})})
        self.rows = {}
        for case in cases:
            record = self.case_dir(case) / CASE_NAME
            if resume and record.is_file():
                row = json.loads(record.read_text())["row"]
                if not (retry_failed and row["status"] != "ok"):
                    self.rows[case.case_id] = row

    def case_dir(self, case: Case) -> Path:
        return self.out / "cases" / case.case_id

    def todo(self) -> list[Case]:
        return [c for c in self.cases if c.case_id not in self.rows]

    def record(self, case: Case, result: dict, no_plots: bool = False) -> dict:
        """Write a finished case's folder (files, log.txt, then case.json; ``no_plots``: the case ran without its
        figures) and sweep.csv; returns its row."""
        from .worker import command_line

        folder = self.case_dir(case)
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        for name, data in result.get("files", {}).items():
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            (folder / name).write_bytes(data)
        (folder / "log.txt").write_text(result.get("log", ""))
        _moved_report(folder, command_line(case, folder, no_plots))
        figures = {}
        if result["status"] == "ok" and (folder / targets.RECORD_NAME).is_file():
            figures = summary_figures(targets.read_record(folder))
        extra = {k: result[k] for k in ("run_time_s", "warmup_time_s", "worker") if k in result}
        row = case_row(case, result["status"], result.get("error"), figures, extra)
        write_json_atomic(folder / CASE_NAME, {**case.to_dict(), "row": row})
        self.rows[case.case_id] = row
        self.write_table()
        return row

    def table(self, pending: bool = False) -> list[dict]:
        """The rows of the finished cases in design order (``pending``: and a PENDING row for every other)."""
        return [self.rows[c.case_id] if c.case_id in self.rows else case_row(c) for c in self.cases
                if pending or c.case_id in self.rows]

    def write_table(self) -> None:
        write_csv_atomic(self.out / "sweep.csv", self.table(),
                         lead=("case_id", *self.point_names, "seed", "status", "error"))


# ------------------------------------------------------------------ Dask
def _wait_for_a_worker(client, scheduler: str) -> None:
    """Return once the scheduler has a worker; ParameterError (the client closed) after NO_WORKER_WAIT_S without
    one (a sweep had waited for ever, saying 0/1 case every 16 s)."""
    try:
        client.wait_for_workers(1, timeout=NO_WORKER_WAIT_S)
    except TimeoutError:
        client.close()
        raise ParameterError(f"--scheduler={scheduler!r} is invalid: the scheduler has no worker (waited "
                             f"{NO_WORKER_WAIT_S:g} s); allowed a scheduler with workers (start one: dask worker "
                             f"{scheduler})") from None


def start_client(workers: int | None, scheduler: str | None):
    """(client, cluster or None): the cluster at ``scheduler``, or a LocalCluster of processes."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT_S)
        except (OSError, TimeoutError, ValueError, AssertionError) as exc:
            # AssertionError: distributed's client thread did not start its event loop within its 10 s (seen on a
            # loaded machine, distributed/utils.py LoopRunner); nothing is connected either way
            reason = "the Dask client's event loop did not start" if isinstance(exc, AssertionError) else str(exc)
        else:
            _wait_for_a_worker(client, scheduler)
            return client, None
        # the failed client, left in a reference cycle, is closed now: collected later, inside the next client's
        # start in this process, its close waited for ever on that start (distributed's LoopRunner; seen in the tests)
        gc.collect()
        raise ParameterError(f"--scheduler={scheduler!r} is invalid: cannot connect: {reason}; allowed the address "
                             "of a running Dask scheduler (e.g. tcp://HOST:8786)")
    # the worker processes ignore Ctrl-C (they inherit SIG_IGN): the client stops them itself
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        # the workers' own log: critical only.  A case's failure comes back through its future; at ERROR a worker
        # whose heartbeat crossed the scheduler's shutdown printed a traceback after a finished sweep.  The
        # scheduler's HTTP server on a free port of this machine alone, no dashboard: without an address it takes
        # 8787, and a second study running at once warned on stderr that the port was in use
        # the workers' scratch space in a folder of this cluster's own, removed with it (Dask's default,
        # TMPDIR/dask-scratch-space, stayed behind after every study), or by a later study if this process is killed
        from .worker import DASK_FOLDER_PREFIX, remove_orphan_case_folders

        remove_orphan_case_folders()
        scratch = tempfile.mkdtemp(prefix=f"{DASK_FOLDER_PREFIX}{os.getpid()}-")
        try:
            with dask.config.set({"temporary-directory": scratch}):    # the nannies' lock files too
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": False},
                                       silence_logs=logging.CRITICAL, local_directory=scratch)
        except BaseException:
            shutil.rmtree(scratch, ignore_errors=True)
            raise
        weakref.finalize(cluster, shutil.rmtree, scratch, ignore_errors=True)
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    return Client(cluster), cluster


def _prepare_fmus(cases: list[Case]) -> None:
    """Build the FMUs co-simulating cases load once, here, before the workers start on them."""
    from ..cosim import ensure_fmu
    from ..parameters import JointParameters

    needed = set()
    for case in cases:
        o = dict(case.options)
        if targets.target(case.command).engine(o)[0] == "cosim" and o.get("fmu") is None:
            needed.add((o.get("n_points") or JointParameters().n_points, o["fmu_backend"]))
    for n_points, backend in sorted(needed):
        try:
            ensure_fmu(n_points, None, backend=backend)
        except (ParameterError, RuntimeError, OSError):
            pass                              # the cases report it


HEARTBEAT_S = 2.0     # s: how often a sweep waiting for its cases updates its progress (a log writes every 15 s)


RUNNING_NAME = "running"      # a wear-study case's folder while it runs: cases/CASE_ID/running


def kept_folder(folder: SweepFolder, case: Case, scheduler: str | None) -> str | None:
    """Where a wear-study case runs on this machine's workers (no ``scheduler``): ``cases/CASE_ID/running``, kept
    through Ctrl-C, so that ``--resume`` continues it from its checkpoint; None (a worker's temporary folder) for
    other cases and remote workers."""
    if scheduler is not None or case.command != "wear-study":
        return None
    return str(folder.case_dir(case) / RUNNING_NAME)


def _say_no_worker(client, scheduler: str, told: bool) -> bool:
    """Whether the scheduler has no worker now, said once on stderr when it starts having none (the sweep had
    waited silently, its ETA growing, after its workers were killed)."""
    if client.nthreads():
        return False
    if not told:
        print(f"wearjoint: the scheduler {scheduler} has no worker now: the sweep waits for one (start one: dask "
              f"worker {scheduler}; Ctrl-C stops the sweep, --resume continues it)", file=sys.stderr, flush=True)
    return True


def _moved_report(folder: Path, command: str) -> None:
    """A case's summary.json and report.html written by its worker name the worker's folder (a temporary one, gone;
    or cases/CASE_ID/running) as --out: rewritten with ``command``, the case's command into the folder they are in
    now."""
    from ..report import summary_path, write_report

    if summary_path(folder) is not None and (folder / "report.html").is_file():
        write_report(folder, command_line=command)


def running_share(kept: str | None) -> float:
    """The share [0, 1) of a running wear-study case done, by its last checkpoint (``checkpointed_revolution`` in its
    kept folder's snapshots.json); 0 for other cases, remote ones and a study before its first checkpoint."""
    if kept is None:
        return 0.0
    from ..studies.wear_study_recovery import SNAPSHOTS_NAME
    try:
        index = json.loads((Path(kept) / SNAPSHOTS_NAME).read_text())
        return min(max(float(index["checkpointed_revolution"]) / float(index["revolutions"]), 0.0), 0.999)
    except (OSError, ValueError, KeyError, TypeError, ZeroDivisionError):
        return 0.0


def run_cases(folder: SweepFolder, no_plots: bool = False, workers: int | None = None, scheduler: str | None = None,
              progress: bool = True, client=None) -> dict:
    """Run the cases not yet done; returns timings and whether Ctrl-C stopped the sweep.  ``client``: a
    running Dask client to use (and leave open; e.g. across the rounds of a sensitivity study), else one
    is started from ``workers`` / ``scheduler`` and closed."""
    from .worker import run_case

    todo = folder.todo()
    timing = {"cases_run": 0, "interrupted": False, "cluster_start_s": 0.0, "run_wall_time_s": 0.0,
              "case_run_time_s": 0.0, "warmup_time_s": 0.0, "workers": workers}
    if not todo:
        return timing
    if scheduler is None:
        _prepare_fmus(todo)
    start = time.perf_counter()
    own = client is None
    client, cluster = start_client(workers, scheduler) if own else (client, None)
    bar = None
    try:
        from distributed import wait

        timing["cluster_start_s"] = time.perf_counter() - start
        timing["workers"] = len(client.nthreads()) if scheduler or not own else workers
        run_start = time.perf_counter()
        kept = {case.case_id: kept_folder(folder, case, scheduler) for case in todo}
        futures = {client.submit(run_case, case, no_plots, kept[case.case_id],
                                 key=f"wearjoint-case-{case.case_id}", pure=False): case for case in todo}
        bar = Progress(len(todo), "sweep", enabled=progress, unit="case", delay_s=0.0)
        pending, k, told = set(futures), 0, False
        try:
            while pending:
                try:      # a wait that ends every HEARTBEAT_S: the progress says the sweep runs while cases last
                    done, pending = wait(pending, timeout=HEARTBEAT_S, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    done = ()
                    told = scheduler is not None and _say_no_worker(client, scheduler, told)
                for future in done:
                    k += 1
                    try:
                        result = future.result()
                    except Exception as exc:          # the worker died, the task could not run, ...
                        result = {"status": "failed", "error": f"{type(exc).__name__}: {exc}", "log": repr(exc)}
                    if result["status"] != "interrupted":
                        folder.record(futures[future], result, no_plots)
                    timing["cases_run"] += 1
                    timing["case_run_time_s"] += result.get("run_time_s", 0.0)
                    timing["warmup_time_s"] += result.get("warmup_time_s", 0.0)
                # wear studies count by their checkpoints: a case takes minutes
                bar.update(k + sum(running_share(kept[futures[f].case_id]) for f in pending))
        except KeyboardInterrupt:
            timing["interrupted"] = True
            client.cancel(list(futures))
        timing["run_wall_time_s"] = time.perf_counter() - run_start
    finally:
        if bar is not None:
            bar.close()
        if own:
            client.close()
        if cluster is not None:
            cluster.close()
    return timing


__all__ = ["SweepFolder", "run_cases", "start_client", "summary_figures", "write_csv_atomic", "refuse_existing",
           "resumed", "check_resumed_design"]
