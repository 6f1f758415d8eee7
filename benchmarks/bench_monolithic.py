"""Monolithic engine speed on the paper case: the median of ``--repeats`` runs in one invocation.

Prints simulated seconds per wall second (real-time factor) for RK4 at 1 us and
for the adaptive Dormand-Prince integrator, without and with wear, next to the
per-revolution statistics of each run (the adaptive run must fall inside the
scatter of the RK4 run; the runs are deterministic, so every repeat has the same
statistics), and the first-call compile time (fresh numba cache) against a
warm-cache start.  Times are medians of the repeats, printed with the machine's
load.  One core: the kernels are single-threaded.

    python benchmarks/bench_monolithic.py [--revolutions 5] [--repeats 3]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

from wearjoint.analysis import REVOLUTION_COLUMNS
from wearjoint.parameters import paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

from repeats import Load, add_repeats_argument, median_text

STARTUP = ("import time; t0 = time.perf_counter(); "
           "from wearjoint.simulate import run_simulation, SimulationOptions; "
           "run_simulation(options=SimulationOptions(revolutions=0.001), progress=False); "
           "run_simulation(options=SimulationOptions(revolutions=0.001, integrator='rk4'), progress=False); "
           "print(time.perf_counter() - t0)")


def startup_seconds(cache_dir: str) -> float:
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    out = subprocess.run([sys.executable, "-c", STARTUP], env=env, capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


STATISTICS = {label: REVOLUTION_COLUMNS.index(column) for label, column in (
    ("impacts", "impacts"), ("contact", "contact_fraction"), ("acc_max", "slider_acc_max_m_s2"),
    ("acc_min", "slider_acc_min_m_s2"), ("force", "max_contact_force_N"))}


def run(label: str, wear: bool, revolutions: float, **options) -> dict:
    joint = paper_joint(wear_factor=1.0 if wear else 0.0)
    rec = run_simulation(joint, options=SimulationOptions(revolutions=revolutions, **options), progress=False)
    table = rec.revolution_table()[1:] if rec.revolution_table().shape[0] > 1 else rec.revolution_table()
    s = rec.summary()
    row = {"label": label, "rtf": s["realtime_factor"], "wall": s["wall_time_s"],
           "steps": s["integrator_accepted_steps"], "rejected": s["integrator_rejected_steps"],
           "wear": s["max_wear_depth_m"], "per_revolution": {}}
    for name, column in STATISTICS.items():
        row[name] = table[:, column].mean()
        row["per_revolution"][name] = table[:, column]
    return row


def inside_scatter(reference: dict, candidate: dict) -> str:
    """Per statistic: does the candidate's mean over revolutions lie inside the reference
    run's revolution-to-revolution range [min, max] (the scatter of the RK4 run)?"""
    verdicts = []
    for name in STATISTICS:
        spread = reference["per_revolution"][name]
        mean = candidate["per_revolution"][name].mean()
        inside = spread.min() <= mean <= spread.max()
        verdicts.append(f"{name} {mean:.4g} {'inside' if inside else 'OUTSIDE'} [{spread.min():.4g}, {spread.max():.4g}]")
    return "; ".join(verdicts)


CONFIGURATIONS = (("rk4 1e-6 s, no wear", False, dict(integrator="rk4", step_s=1e-6)),
                  ("dopri (default), no wear", False, {}),
                  ("rk4 1e-6 s, wear", True, dict(integrator="rk4", step_s=1e-6)),
                  ("dopri max step 1e-5 s, wear", True, dict(max_step_s=1e-5)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=5.0, help="revolutions per run (default 5)")
    add_repeats_argument(parser)
    args = parser.parse_args()
    load = Load()
    compile_s, warm_s = [], []
    for _ in range(args.repeats):
        with tempfile.TemporaryDirectory() as cold:
            compile_s.append(startup_seconds(cold))
            warm_s.append(startup_seconds(cold))
    print(f"first call, empty numba cache: {median_text(compile_s, '.1f')} s; with the cache filled: "
          f"{median_text(warm_s, '.1f')} s; {load}")
    n = args.revolutions
    runs = {label: [] for label, _, _ in CONFIGURATIONS}
    for _ in range(args.repeats):
        for label, wear, options in CONFIGURATIONS:
            runs[label].append(run(label, wear, n, **options))
    load.stop()
    rows = [dict(runs[label][0], rtf=statistics.median(r["rtf"] for r in runs[label]),
                 wall=statistics.median(r["wall"] for r in runs[label])) for label, _, _ in CONFIGURATIONS]
    print(f"\npaper case, {n:g} revolutions each, real-time factor and wall time the median of {args.repeats} "
          f"runs ({load}); statistics are means over revolutions 2..{int(np.ceil(n))}")
    head = (f"{'run':30s} {'real-time':>9s} {'wall s':>7s} {'steps':>8s} {'rejected':>8s} {'impacts/rev':>11s} "
            f"{'contact':>7s} {'a_max':>7s} {'a_min':>8s} {'F_max N':>8s} {'wear um':>8s}   "
            "real-time factor of each run")
    print(head)
    for r in rows:
        print(f"{r['label']:30s} {r['rtf']:9.3f} {r['wall']:7.2f} {r['steps']:8d} {r['rejected']:8d} "
              f"{r['impacts']:11.1f} {r['contact']:7.3f} {r['acc_max']:7.0f} {r['acc_min']:8.0f} "
              f"{r['force']:8.0f} {r['wear'] * 1e6:8.2f}   "
              + " ".join(f"{each['rtf']:.3f}" for each in runs[r['label']]))
    print(f"\nadaptive / rk4 speed-up: no wear {rows[1]['rtf'] / rows[0]['rtf']:.1f}x, "
          f"wear {rows[3]['rtf'] / rows[2]['rtf']:.1f}x")
    print("adaptive vs rk4 1e-6 s, no wear: " + inside_scatter(rows[0], rows[1]))
    print("adaptive vs rk4 1e-6 s, wear:    " + inside_scatter(rows[2], rows[3]))


if __name__ == "__main__":
    main()
