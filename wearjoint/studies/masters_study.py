"""Third-party co-simulation masters on SliderCrankWithClearance.ssp: accuracy, wall time, real-time factor.

Each master (:mod:`wearjoint.cosim.masters`: OSP libcosim, ecos, fmpy's SSP simulator, OMSimulator, the fmpy
container FMU in fmpy and in fmusim) runs the package (no wear) for ``--revolutions`` crank
revolutions at each communication step, from ``--ensemble`` perturbed starts (a package each); the
mean of its per-revolution statistics is judged exactly as ``wearjoint validate`` judges an engine
(:func:`wearjoint.validation.compare.compare`: the difference from the monolithic reference ensemble
against k x the largest difference of the other valid monolithic configurations' ensembles of the same
size, with the same floors).  Prints one table; ``--out DIR`` also writes ``masters_study.json``.

    python -m wearjoint.studies.masters_study [--revolutions 2] [--steps 0.5e-6 1e-6 2e-6 4e-6]
        [--masters libcosim ecos fmpy-ssp container container-fmusim] [--ensemble 2] [--fmusim PATH] [--out DIR]
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

from wearjoint.cosim import masters
from wearjoint.fmu import ssp
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.sweep.design import perturbed_start
from wearjoint.validation.compare import GROUP_STATISTICS, STATISTICS, ValidationPlan, compare, run_engines

STEPS_S = (0.5e-6, 1e-6, 2e-6, 4e-6)
STUDY_MASTERS = ("libcosim", "ecos", "fmpy-ssp", "omsimulator", "container", "container-fmusim")
SAMPLE_DT_S = 1e-5
ENSEMBLE = 2        # perturbed starts per master and per monolithic configuration (validate: 8; a master's
                    # run at 0.5 us takes 40 s to 3 min): a single run against means of 8 is judged too strictly


def run_study(revolutions: float, steps, names, fmusim: str | None, log=print, skip=None,
              ensemble: int = ENSEMBLE) -> dict:
    """Every (master, step) ensemble of ``ensemble`` perturbed starts judged against the monolithic scatter;
    ``skip(master, step)`` -> a reason not to run that pair (or None)."""
    mechanism = SliderCrankParameters()
    joint = paper_joint(mechanism, wear_factor=0.0)
    plan = ValidationPlan(revolutions=revolutions, engines=("monolithic",), run_wear=False, sample_dt_s=SAMPLE_DT_S,
                          ensemble=ensemble)
    start = time.perf_counter()
    runs = run_engines(plan, joint, mechanism, progress=False)
    log(f"monolithic reference and scatter: {len(runs.scatter) + 1} configurations of {ensemble} starts in "
        f"{time.perf_counter() - start:.0f} s")
    rows = []
    with tempfile.TemporaryDirectory(prefix="masters_study_") as tmp:
        starts = [perturbed_start(mechanism, k) for k in range(ensemble)]
        packages = [ssp.export_ssp(Path(tmp) / str(k), mechanism=perturbed, joint=joint,
                                   stop_time=revolutions * mechanism.period_s, platforms="linux64")
                    for k, perturbed in enumerate(starts)]
        for name in names:
            master, host = ("container", fmusim) if name == "container-fmusim" else (name, None)
            missing = masters.master_available(master) or (
                None if master != "container" or name == "container" or (fmusim and Path(fmusim).is_file())
                else "no fmusim binary (--fmusim PATH or $FMUSIM)")
            for step in steps:
                reason = missing or (skip(name, step) if skip else None)
                if reason:
                    rows.append({"master": name, "step_s": step, "skipped": reason})
                    log(f"{name} {step * 1e6:g} us: skipped ({reason})")
                    continue
                try:
                    records = [masters.run_package(master, package, joint, perturbed, revolutions, step, SAMPLE_DT_S,
                                                   fmusim=host) for perturbed, package in zip(starts, packages)]
                except Exception as exc:      # an unstable step ends in a non-finite state or an FMU error
                    rows.append({"master": name, "step_s": step, "failed": f"{type(exc).__name__}: {exc}"[:200]})
                    log(f"{name} {step * 1e6:g} us: failed ({rows[-1]['failed']})")
                    continue
                label = f"{name} {step * 1e6:g} us"
                runs.engines = {label: records}
                metrics = [m for m in compare(runs, plan) if m.group == GROUP_STATISTICS]
                wall = sum(r.wall_time_s for r in records) / len(records)
                rows.append({"master": name, "step_s": step, "wall_time_s": wall,
                             "realtime_factor": records[0].simulated_time_s / wall,
                             "inside": sum(m.passed for m in metrics), "of": len(metrics),
                             "metrics": {m.name: {"value": m.value, "difference": m.difference,
                                                  "tolerance": m.tolerance, "passed": m.passed} for m in metrics}})
                log(f"{label}: {rows[-1]['inside']}/{len(metrics)} inside, wall {wall:.1f} s per start")
    return {"revolutions": revolutions, "reference": "monolithic RK4 1 us", "scatter_runs": list(runs.scatter),
            "rows": rows}


def largest_step_inside(study: dict) -> dict:
    """Per master, the largest step whose run has every statistic inside the scatter (None if none)."""
    out = {}
    for row in study["rows"]:
        inside = "inside" in row and row["inside"] == row["of"]
        best = out.get(row["master"])
        out[row["master"]] = max(best or 0.0, row["step_s"]) if inside else best
    return out


def table(study: dict) -> str:
    """The study as a markdown table: difference / tolerance per statistic (<= 1 is inside)."""
    names = list(STATISTICS)
    head = ["master", "step [us]", "wall [s]", "real-time factor", "inside"] + names
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in study["rows"]:
        cells = [r["master"], f"{r['step_s'] * 1e6:g}"]
        if "metrics" not in r:
            cells += [r.get("skipped") and f"skipped: {r['skipped']}" or f"failed: {r['failed']}"]
            lines.append("| " + " | ".join(cells) + " |" + " |" * (len(head) - 3))
            continue
        cells += [f"{r['wall_time_s']:.1f}", f"{r['realtime_factor']:.4f}", f"{r['inside']}/{r['of']}"]
        cells += [f"{abs(r['metrics'][n]['difference']) / r['metrics'][n]['tolerance']:.2f}" for n in names]
        lines.append("| " + " | ".join(cells) + " |")
    best = largest_step_inside(study)
    lines.append("")
    lines.append(f"{study['revolutions']:g} revolutions, no wear; each statistic: |master - reference| / tolerance "
                 "(validate's rule: max(2 x scatter, floor)); <= 1 is inside the monolithic scatter.  Largest step "
                 "inside on every statistic: " + ", ".join(f"{m} {'none' if s is None else f'{s * 1e6:g} us'}"
                                                          for m, s in best.items()) + ".")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=2.0)
    parser.add_argument("--steps", type=float, nargs="+", default=list(STEPS_S), help="communication steps [s]")
    parser.add_argument("--masters", nargs="+", default=list(STUDY_MASTERS), choices=STUDY_MASTERS)
    parser.add_argument("--ensemble", type=int, default=ENSEMBLE,
                        help="perturbed starts per master and per monolithic configuration (default %(default)s)")
    parser.add_argument("--fmusim", default=os.environ.get("FMUSIM"), help="fmusim binary (default $FMUSIM)")
    parser.add_argument("--skip", nargs=2, action="append", default=[], metavar=("MASTER", "STEP"),
                        help="do not run MASTER at STEP [s] (e.g. a run that would take too long)")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    skipped = {(m, float(s)) for m, s in args.skip}
    study = run_study(args.revolutions, args.steps, args.masters, args.fmusim, log=lambda m: print(m, flush=True),
                      skip=lambda m, s: "not run in this study (--skip)" if (m, s) in skipped else None,
                      ensemble=args.ensemble)
    text = table(study)
    print(text)
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "masters_study.json").write_text(json.dumps(study, indent=2, default=str))
        (args.out / "masters_study.md").write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
