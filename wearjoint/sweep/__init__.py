"""Parameter sweeps and seed ensembles of ``simulate``, ``cosim`` and ``wear-study`` on Dask.

:func:`run_sweep` builds the cases (:mod:`.design`), runs each as a Dask task (:mod:`.runner`,
:mod:`.worker`) and writes the ensemble statistics and figures (:mod:`.report`) with the
systematic uncertainty the run can state beside them (the wear factor's bias, :mod:`.bias`).  Dask is
imported only when cases run, never by ``import wearjoint`` (docs/how-to/sweep_on_dask.md).
"""
from __future__ import annotations

import time
from pathlib import Path

from ..results import write_json_atomic
from .design import (SEED_ANGLE_STEP_DEG, TARGETS, Case, build_cases, check_grid, command_options,
                     design_record)

SUMMARY_NAME = "sweep_summary.json"


def run_sweep(command: str, base: dict, out, vary: dict | None = None, points=(), seeds: int = 1,
              no_plots: bool = False, workers: int | None = None, scheduler: str | None = None,
              resume: bool = False, retry_failed: bool = False, progress: bool = True,
              where: dict | None = None) -> dict:
    """Run the cases of ``command`` (options ``base``, dest -> value) over the grid ``vary``
    (name -> values) plus ``points``, ``seeds`` seeds each, into ``out``; returns
    sweep_summary.json's content (counts, failures, timings, file names).  ``no_plots`` skips
    the cases' own PNGs (the sweep's figures are always drawn).  ``resume``
    skips the cases already done in ``out`` (``retry_failed``: except the failed ones); a sweep of another
    design is refused.  Before anything is written, every grid point's options are checked (:func:`check_grid`;
    ``where`` names where each was written) and ``scheduler`` is connected to."""
    from .report import write_reports
    from .runner import SweepFolder, check_resumed_design, refuse_existing, run_cases, start_client

    start = time.perf_counter()
    cases = build_cases(command, base, vary, points, seeds)
    check_grid(command, base, vary, points, where)
    design = design_record(command, base, vary, points, seeds)
    if resume:
        check_resumed_design(out, design, cases)
    else:
        refuse_existing(out)
    connect_start = time.perf_counter()
    client = start_client(workers, scheduler)[0] if scheduler else None
    connect_s = time.perf_counter() - connect_start
    try:
        folder = SweepFolder(out, cases, resume, retry_failed, design)
        skipped = len(cases) - len(folder.todo())
        timing = run_cases(folder, no_plots=no_plots, workers=workers, scheduler=scheduler, progress=progress,
                           client=client)
    finally:
        if client is not None:
            client.close()
    timing["cluster_start_s"] += connect_s
    folder.write_table()
    report = write_reports(folder.out, folder.table(pending=True), folder.point_names)
    table = folder.table()
    summary = {
        "command": command, "cases": len(cases), "grid_points": len(report["ensemble"]), "seeds": seeds,
        "ok": sum(r["status"] == "ok" for r in table), "failed": sum(r["status"] == "failed" for r in table),
        "not_run": len(cases) - len(table), "skipped_as_done": skipped, **timing,
        "wall_time_s": time.perf_counter() - start, "seed_angle_step_deg": SEED_ANGLE_STEP_DEG,
        "wear_factor_bias": report["wear_factor_bias"],
        "regimes": report["regimes"],     # per grid point: the starts in each regime (ensemble.csv: regime_*)
        "failures": [{"case_id": r["case_id"], "seed": r["seed"], "error": r["error"]}
                     for r in table if r["status"] == "failed"],
        "files": ["sweep.csv", "ensemble.csv", "sweep.json", "bands/", "cases/", *report["figures"]],
        "case_parameters": report["case_parameters"], "parameter_spread": report["parameter_spread"],
    }
    write_json_atomic(Path(out) / SUMMARY_NAME, summary)
    return summary


__all__ = ["run_sweep", "build_cases", "command_options", "Case", "TARGETS", "SEED_ANGLE_STEP_DEG"]
