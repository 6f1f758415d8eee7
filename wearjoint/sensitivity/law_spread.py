"""The contact law as an error bar: the study's target run once per contact damping law variant
(:func:`wearjoint.contact_laws.contact_law_variants`: each law, and each law's free parameter at the ends of its
plausible range) at the nominal point of the sampled parameters, every ``--param`` at the middle of its range
(the geometric middle of a log range).  The outputs' values per variant, their spread (max - min over the
variants that ran) and that spread relative to the outputs' spread over the sensitivity's own samples: the
model-form spread to set beside the indices and their sampling intervals (docs/explanation/sensitivity.md).

A variant's joint changes are added to the case's options (dest -> value, the target's own options
``--contact-damping``, ``--restitution-speed-m-s``, ``--impact-velocity-floor-m-s``, ``--effective-mass-kg``).  A
variant that would override a sampled parameter is skipped and says so.  The runs are sweep cases in
``OUT/law_spread/`` (``--resume`` reuses them); ``OUT/law_spread.csv`` holds one row per variant.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..joint_fields import unread_by
from ..mechanism_parameters import mechanism_from_options
from ..sweep.design import variable_actions
from ..sweep.runner import write_csv_atomic
from .problem import Problem
from .report import invalid_reason, output_value

FOLDER = "law_spread"
CSV_NAME = "law_spread.csv"


def nominal_point(problem: Problem) -> dict:
    """{option name: value}: every parameter at the middle of its range (log parameters: the geometric middle)."""
    middle = np.array([[0.5 * (p.bounds[0] + p.bounds[1]) for p in problem.parameters]])
    return problem.points(middle)[0]


def law_variants(base: dict, problem: Problem, point: dict) -> list:
    """[{"label", "changes", "unset", "skipped"}] of :func:`contact_law_variants` for the mechanism at ``point`` (the
    Tsuji masses follow a sampled rod or slider mass); ``unset``: the given options of another law, which the
    variant's law does not read (left out: given, they would be refused); ``skipped`` names the sampled parameters
    a variant would override ('' when it runs)."""
    from ..contact_laws import contact_law_variants

    options = {**base, **{p.dest: point[p.name] for p in problem.parameters}}
    mechanism = mechanism_from_options(options)
    sampled = {p.dest: p.name for p in problem.parameters}
    given = [dest for dest, value in options.items() if value is not None]
    variants = []
    for label, changes in contact_law_variants(mechanism):
        clash = [sampled[dest] for dest in changes if dest in sampled]
        unread = [row.field for row in unread_by(changes["contact_damping"], given)]   # another law's: left out
        variants.append({"label": label, "changes": dict(changes), "unset": unread,
                         "skipped": f"--param {', '.join(clash)} is sampled (the variant would override it)"
                         if clash else ""})
    return variants


def variant_cases(command: str, base: dict, point: dict, variants: list) -> tuple:
    """(the case id of every variant, None where skipped; the distinct cases)."""
    from . import design_cases

    ids, cases = [], {}
    dests = {name: action.dest for name, action in variable_actions(command).items()}
    for v in variants:
        if v["skipped"]:
            ids.append(None)
            continue
        unset = set(v.get("unset", ()))      # the options of the base and the point the variant's law does not read
        kept = {name: value for name, value in point.items() if dests[name] not in unset}
        [cid], [case] = design_cases(command, {**base, **v["changes"], **dict.fromkeys(unset)}, [kept])
        ids.append(cid)
        cases.setdefault(cid, case)
    return ids, list(cases.values())


def _number(value: float):
    return float(value) if math.isfinite(value) else None


def spread_of(variants: list, outputs: list, y: dict) -> dict:
    """Per output: the lowest and highest value over the variants that ran and which variant gave each, the spread
    (max - min; None with fewer than two values), the spread over the sensitivity's samples ``y`` (output -> values
    per design row) and the ratio of the two (None when the samples did not move the output)."""
    spread = {}
    for name in outputs:
        ran = [(v["values"][name], v["label"]) for v in variants if v["values"].get(name) is not None]
        low, high = (min(ran), max(ran)) if ran else ((None, None), (None, None))
        finite = np.asarray(y.get(name, []), dtype=float)
        finite = finite[np.isfinite(finite)]
        sample = float(np.ptp(finite)) if finite.size >= 2 else None
        law = high[0] - low[0] if len(ran) >= 2 else None
        spread[name] = {"min": low[0], "min_variant": low[1], "max": high[0], "max_variant": high[1], "spread": law,
                        "sample_spread": sample,
                        "relative": law / sample if law is not None and sample else None}
    return spread


def run_law_spread(command: str, base: dict, problem: Problem, out, outputs: list, y: dict, client, resume: bool,
                   workers=None, scheduler=None, progress: bool = True) -> dict:
    """Run the variants not yet done in ``OUT/law_spread/`` on ``client()`` (a callable giving the study's Dask
    client, started on first use) and write ``law_spread.csv``; returns the summary's ``law_spread`` object (its
    ``interrupted`` True after Ctrl-C)."""
    from ..sweep.runner import SweepFolder, run_cases

    out = Path(out)
    point = nominal_point(problem)
    variants = law_variants(base, problem, point)
    ids, cases = variant_cases(command, base, point, variants)
    done = {"cases_run": 0, "interrupted": False, "run_wall_time_s": 0.0}
    rows = {}
    if cases:
        folder = SweepFolder(out / FOLDER, cases, resume)
        if folder.todo():
            done = run_cases(folder, no_plots=True, workers=workers, scheduler=scheduler, progress=progress,
                             client=client())
        rows = {r["case_id"]: r for r in folder.table()}
    law = settle(variants, ids, rows, outputs, y)
    write_csv_atomic(out / CSV_NAME, csv_rows(law, outputs), lead=("variant", "case_id", "status", "error", *outputs))
    return {"point": point, **law, "cases_run": done["cases_run"], "run_wall_time_s": done["run_wall_time_s"],
            "interrupted": done["interrupted"], "files": [CSV_NAME, f"{FOLDER}/"]}


def settle(variants: list, ids: list, rows: dict, outputs: list, y: dict) -> dict:
    """The variants' outcomes from their cases' rows (case id -> sweep.csv row): each variant's ``case_id``,
    ``status`` (ok, failed, invalid: ran but its pin went through the bushing wall, skipped, not run), ``error`` (why it was
    skipped, failed or is invalid) and ``values`` (output -> number, None unless ok: a failed run is counted, never
    a number); the counts, the failures and skipped variants named, and :func:`spread_of`."""
    for v, cid in zip(variants, ids):
        row = rows.get(cid) if cid else None
        invalid = invalid_reason(row)
        v["case_id"] = cid or ""
        v["status"] = ("skipped" if v["skipped"] else "not run" if row is None else "invalid" if invalid
                       else row["status"])
        v["error"] = v.pop("skipped") or invalid or (row or {}).get("error", "")
        v["values"] = {name: _number(output_value(row, name)) if v["status"] == "ok" else None for name in outputs}
    count = {s: sum(v["status"] == s for v in variants) for s in ("ok", "failed", "invalid", "skipped", "not run")}
    return {"variants": variants, "spread": spread_of(variants, outputs, y), "ok": count["ok"],
            "failed": count["failed"] + count["invalid"], "skipped": count["skipped"], "not_run": count["not run"],
            "failures": [{"variant": v["label"], "case_id": v["case_id"], "status": v["status"], "error": v["error"]}
                         for v in variants if v["status"] in ("failed", "invalid")],
            "skipped_variants": [{"variant": v["label"], "reason": v["error"]} for v in variants
                                 if v["status"] == "skipped"]}


def csv_rows(law: dict, outputs: list) -> list:
    """law_spread.csv: one row per variant: its label, case, status and why, the outputs (empty unless ok) and its
    joint changes (``changes_FIELD``, every field some variant changes)."""
    fields = sorted({k for v in law["variants"] for k in v["changes"]})
    return [{"variant": v["label"], "case_id": v["case_id"], "status": v["status"], "error": v["error"],
             **{name: "" if v["values"][name] is None else v["values"][name] for name in outputs},
             **{f"changes_{k}": v["changes"].get(k, "") for k in fields}} for v in law["variants"]]


def _g(value, digits: int = 4) -> str:
    return "-" if value is None else f"{value:.{digits}g}"


def spread_lines(law: dict, outputs: list) -> list:
    """The printed table: one line per variant (its outputs, or its status and why), then the spread over the laws,
    the spread over the samples and their ratio."""
    width = max([len(v["label"]) for v in law["variants"]] + [24])
    cols = [max(len(name), 10) + 2 for name in outputs]
    lines = [f"  contact law spread at the nominal point ({len(law['variants'])} variants: {law['ok']} ok, "
             f"{law['failed']} failed, {law['skipped']} skipped, {law['not_run']} not run):",
             f"    {'variant':{width}s}" + "".join(f"{name:>{w}s}" for name, w in zip(outputs, cols))]
    for v in law["variants"]:
        cells = ("".join(f"{_g(v['values'][n]):>{w}s}" for n, w in zip(outputs, cols)) if v["status"] == "ok"
                 else f"  {v['status']}: {v['error']}")
        lines.append(f"    {v['label']:{width}s}{cells}")
    for key, text in (("spread", "spread over the laws"), ("sample_spread", "spread over the samples"),
                      ("relative", "laws / samples")):
        lines.append(f"    {text:{width}s}" + "".join(f"{_g(law['spread'][n][key], 3):>{w}s}"
                                                      for n, w in zip(outputs, cols)))
    return lines


__all__ = ["run_law_spread", "nominal_point", "law_variants", "variant_cases", "settle", "spread_of", "csv_rows",
           "spread_lines", "FOLDER", "CSV_NAME"]
