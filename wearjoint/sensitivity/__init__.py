"""Global sensitivity of ``simulate``, ``cosim`` or ``wear-study`` outputs to model parameters (SALib).

Sample (:mod:`.sample`, SALib's Morris or Sobol' design over the ranges of :mod:`.problem`), evaluate
(every design row one case of the sweep's Dask runner, :mod:`wearjoint.sweep.runner`: same workers,
failures, ``--resume`` and ``--scheduler``; equal rows share one case), analyse (:mod:`.analyse`,
bootstrap 95 % intervals) and report (:mod:`.report`) with the wear factor's bias beside the answer.
With a target interval the design doubles until the widest interval meets it.  Then, on the same Dask client,
the target runs once per contact damping law variant at the nominal point (:mod:`.law_spread`: the model-form
spread beside the sampling intervals; docs/explanation/sensitivity.md).
"""
from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from ..parameters import ParameterError
from ..results import write_json_atomic
from .analyse import CONF_LEVEL, RESAMPLES, convergence, until_target
from .law_spread import CSV_NAME as LAW_CSV, run_law_spread
from .problem import Problem, parse_params
from .report import (BIAS_EFFECT, invalid_reason, output_biases, output_value, parse_outputs, plot_indices, write_indices,
                     write_samples)
from .sample import DEFAULT_SAMPLES, METHODS, check_samples, check_seed, few_samples_note, group_size

SUMMARY_NAME = "summary.json"


def design_cases(command: str, base: dict, points: list) -> tuple:
    """(the case id of every design row, the distinct cases in design order)."""
    from ..sweep import build_cases

    ids, cases = [], {}
    for point in points:
        case = build_cases(command, base, points=[point])[0]
        ids.append(case.case_id)
        cases.setdefault(case.case_id, case)
    return ids, list(cases.values())


def check_target(target, samples: int, max_samples) -> None:
    """--target-interval in (0, 1) and --max-samples >= --samples (one-line ParameterErrors)."""
    if target is not None and not (math.isfinite(target) and 0.0 < target < 1.0):
        raise ParameterError(f"--target-interval={target!r} is invalid: allowed a number in (0, 1)")
    if max_samples is not None and max_samples < samples:
        raise ParameterError(f"--max-samples={max_samples!r} is invalid: allowed an integer >= --samples={samples}")


def run_sensitivity(command: str, base: dict, problem: Problem, out, method: str = "morris", samples: int | None = None,
                    seed: int = 0, outputs=None, target_interval: float | None = None, max_samples: int | None = None,
                    workers: int | None = None, scheduler: str | None = None, resume: bool = False,
                    progress: bool = True, command_line: str | None = None, law_spread: bool = True,
                    plots: bool = True) -> dict:
    """Sample ``problem`` (``samples`` Morris trajectories or Sobol' base samples, drawn with ``seed``), run
    every row as a case of ``command`` (options ``base``, dest -> value) into ``out``, analyse ``outputs``
    (names, default :data:`.report.DEFAULT_OUTPUTS`); with ``target_interval`` double the samples (up to
    ``max_samples``, default 8 x ``samples``) until the widest interval meets it; with ``law_spread`` then run
    every contact law variant at the nominal point (:func:`.law_spread.run_law_spread`); ``plots``: the indices'
    figures (an earlier analysis's go whenever this one is written, or without them).  Returns summary.json's content."""
    from ..sweep.report import parameter_spread
    from ..sweep.runner import SweepFolder, refuse_existing, resumed, run_cases, start_client

    n = check_samples(method, DEFAULT_SAMPLES.get(method) if samples is None else samples)
    check_seed(seed)
    max_samples = max_samples if max_samples is not None else 8 * n
    check_target(target_interval, n, max_samples)
    outputs = parse_outputs(command, base, outputs)
    out, start = Path(out), time.perf_counter()
    state = {"client": None, "cluster": None, "cluster_start_s": 0.0, "run_wall_time_s": 0.0, "case_run_time_s": 0.0,
             "warmup_time_s": 0.0, "workers": workers, "rounds": 0}

    def client():
        """The study's Dask client, started on first use."""
        if state["client"] is None:
            t0 = time.perf_counter()
            state["client"], state["cluster"] = start_client(workers, scheduler)
            state["cluster_start_s"] = time.perf_counter() - t0
        return state["client"]

    def evaluate(x):
        """Run the design's rows not yet done in ``out``; their outputs (NaN where a run failed or is missing)."""
        ids, cases = design_cases(command, base, problem.points(x))
        folder = SweepFolder(out, cases, resume or state["rounds"] > 0)
        skipped = len(cases) - len(folder.todo())
        done = run_cases(folder, no_plots=True, workers=workers, scheduler=scheduler, progress=progress,
                         client=client() if folder.todo() else None)
        for key in ("run_wall_time_s", "case_run_time_s", "warmup_time_s"):
            state[key] += done[key]
        if done["cases_run"]:
            state["workers"] = done["workers"]
        state.update(rounds=state["rounds"] + 1, ids=ids, cases=cases, folder=folder)
        rows = {r["case_id"]: r for r in folder.table()}
        y = {name: np.array([output_value(rows.get(cid), name) for cid in ids]) for name in outputs}
        return y, {"cases": len(cases), "cases_run": done["cases_run"], "skipped_as_done": skipped}, done["interrupted"]

    if resume:
        resumed(out, "sensitivity study")
        check_resumed_study(out, {"command": command, "method": method, "seed": seed,
                                  "parameters": problem.to_dict()})
    else:
        refuse_existing(out)
    law = None
    try:
        if scheduler:
            client()                                         # refused before anything is written
        study = until_target(problem, method, n, seed, evaluate, target_interval, max_samples)
        if law_spread and not study["stopped"]:
            law = run_law_spread(command, base, problem, out, outputs, study["y"], client, resume, workers, scheduler,
                                 progress)
        elif not law_spread:
            (out / LAW_CSV).unlink(missing_ok=True)          # a stale table from an earlier run of this folder
    finally:
        for key in ("client", "cluster"):
            if state[key] is not None:
                state[key].close()
    x, n, results = study["x"], study["samples"], study["results"]
    interrupted = study["stopped"] or bool(law and law["interrupted"])
    ids, cases, table = state["ids"], state["cases"], state["folder"].table()
    write_samples(out, problem, problem.points(x), group_size(method, len(problem.parameters)), ids,
                  {r["case_id"]: r for r in table}, outputs)
    biases = output_biases(out, table, outputs)
    case_parameters, spread = parameter_spread(out, table, [p.dest for p in problem.parameters], "sampled (--param)")
    figures = []
    if not plots or not study["stopped"]:     # an earlier analysis's (other --outputs or --samples) go: not mixed
        for stale in out.glob("sensitivity_*.png"):
            stale.unlink()
    if not study["stopped"]:
        write_indices(out, method, results, biases)
        for name, result in results.items():
            if result["indices"] and plots:
                title = (f"{command}: {name}, {method} N = {n} ({len(ids)} runs), seed {seed}\n"
                         f"wear-factor bias {biases[name].text}; 95 % intervals")
                figures.append(plot_indices(out, method, name, result, title))
    summary = {
        "command": command, "method": method, "samples": n, "runs": len(ids), "cases": len(cases), "seed": seed,
        "parameters": problem.to_dict(), "outputs": outputs,
        "ok": sum(r["status"] == "ok" and not invalid_reason(r) for r in table),
        "failed": sum(r["status"] == "failed" for r in table), "invalid": sum(bool(invalid_reason(r)) for r in table),
        "not_run": len(cases) - len(table), "skipped_as_done": study["rounds"][0]["skipped_as_done"],
        "interrupted": interrupted, "target_interval": target_interval, "target_met": study["met"],
        "rounds": study["rounds"], "confidence_level": CONF_LEVEL, "bootstrap_resamples": RESAMPLES,
        "analysis": {name: {k: r[k] for k in ("groups", "dropped", "constant")} for name, r in results.items()},
        "widest_interval": study["rounds"][-1]["widest_interval"],
        "intervals_note": few_samples_note(method, n),
        "convergence": {} if study["stopped"] else
        {name: [{"samples": k, "widest_interval": w} for k, w in convergence(problem, method, x, study["y"][name], seed)]
         for name in outputs},
        "wear_factor_bias": {name: {"rel": b.rel, "text": b.text, "note": b.note} for name, b in biases.items()},
        "wear_factor_bias_effect": BIAS_EFFECT,
        **{k: state[k] for k in ("cluster_start_s", "run_wall_time_s", "case_run_time_s", "warmup_time_s", "workers")},
        "wall_time_s": time.perf_counter() - start, "command_line": command_line,
        "failures": [{"case_id": r["case_id"], "error": r["error"] or invalid_reason(r)} for r in table
                     if r["status"] == "failed" or invalid_reason(r)],
        "law_spread": law,
        "files": ["samples.csv", "indices.csv", "sweep.csv", "sweep.json", "cases/", *figures,
                  *(law["files"] if law else ())],
        "case_parameters": case_parameters, "parameter_spread": spread,
    }
    write_json_atomic(out / SUMMARY_NAME, summary)
    summary["results"] = results
    return summary


def check_resumed_study(out: Path, design: dict) -> None:
    """A one-line ParameterError naming what differs if the study whose summary.json ``out`` holds had another
    command, method, seed or parameters (names, ranges) than ``design``: --resume continues a study (with more
    --samples, other --outputs), it does not start another in its folder."""
    try:
        earlier = json.loads((out / SUMMARY_NAME).read_text())
    except (OSError, ValueError):
        return                                 # stopped before its summary: its sweep.json's cases decide
    differ = [f"{key}: {earlier.get(key)!r} there, {value!r} now" for key, value in design.items()
              if json.loads(json.dumps(value)) != earlier.get(key)]
    if differ:
        raise ParameterError(f"--resume is invalid: the study in {out} has another design: {'; '.join(differ)}; "
                             "allowed its own command, --method, --seed and --param (more --samples and other "
                             "--outputs are fine), or another --out for a new study")


__all__ = ["run_sensitivity", "check_resumed_study", "parse_params", "Problem", "METHODS", "design_cases", "check_target"]
