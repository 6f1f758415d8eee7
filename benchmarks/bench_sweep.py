"""Benchmark: a sweep of 16 short wear studies on a LocalCluster of 1 and of 2 workers.

Goals on the 2-core machine: speed-up >= 1.8x with 2 workers, per-case overhead of the sweep
machinery < 0.2 s.  Baseline: the same 16 cases run one after the other in this process through
``wearjoint.cli.main`` (kernels warm).  Overhead per case = (sweep time from the first submission
to the last case written) minus the cases' own run time and the one-off warm-up measured inside
the worker, over 16 cases, with 1 worker; the difference to the baseline is printed too (it also
holds any change in the machine's load between the runs).  Speed-up = that sweep time with 1 worker / with 2 workers (cluster start-up, a
few seconds once per sweep, reported apart).  "Concurrency" is the workers' busy time over the
sweep's wall time (2 workers on 2 free cores: ~2).  Prints the load average: a load above the core
count means other work shared the CPUs and the speed-up is pessimistic.

    python benchmarks/bench_sweep.py [--cases 16] [--revolutions 40] [--wear-factor 20]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import sys
import tempfile
import time
from pathlib import Path

from wearjoint.cli import main as cli_main
from wearjoint.sweep import build_cases, command_options, run_sweep
from wearjoint.sweep.design import command_parser
from wearjoint.sweep.worker import warm_up


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=16, help="seeds of one wear study")
    parser.add_argument("--revolutions", default="40", help="each study's revolutions")
    parser.add_argument("--wear-factor", default="20", help="each study's acceleration factor")
    args = parser.parse_args()
    study = ["--revolutions", args.revolutions, "--wear-factor", args.wear_factor, "--no-plots"]
    base = command_options("wear-study", command_parser("wear-study").parse_args([*study, "--out", "x"]))
    cases = build_cases("wear-study", base, seeds=args.cases)
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        warm_up("wear-study", base)
        start = time.perf_counter()
        for case in cases:                               # the baseline: one after the other, no Dask
            with contextlib.redirect_stdout(io.StringIO()):
                code = cli_main(["wear-study", *case.argv(), "--out", f"{tmp}/direct/{case.case_id}", "--quiet",
                                 "--no-plots"])
            assert code == 0
        direct_s = time.perf_counter() - start
        runs = {}
        for workers in (1, 2):
            summary = run_sweep("wear-study", base, Path(tmp) / f"w{workers}", seeds=args.cases, no_plots=True,
                                workers=workers, progress=False)
            assert summary["ok"] == args.cases, summary["failures"]
            runs[workers] = summary
    load_after = os.getloadavg()
    one, two = runs[1], runs[2]
    print(f"{args.cases} wear studies ({args.revolutions} revolutions at wear factor {args.wear_factor}, "
          f"{float(args.revolutions) / float(args.wear_factor):g} simulated revolutions each, --no-plots)")
    print(f"  one after the other in one process   {direct_s:7.2f} s  ({direct_s / args.cases:.2f} s per case)")
    for workers, s in runs.items():
        busy = s["case_run_time_s"] + s["warmup_time_s"]
        print(f"  sweep, {workers} worker{'s' if workers > 1 else ' '}                      "
              f"{s['run_wall_time_s']:7.2f} s  (+ cluster start {s['cluster_start_s']:.2f} s, end to end "
              f"{s['wall_time_s']:.2f} s); cases' own time {s['case_run_time_s']:.2f} s + warm-up "
              f"{s['warmup_time_s']:.2f} s inside the workers: concurrency {busy / s['run_wall_time_s']:.2f}")
    speed_up = one["run_wall_time_s"] / two["run_wall_time_s"]
    print(f"  speed-up with 2 workers              {speed_up:7.2f}x (goal >= 1.8x: {'met' if speed_up >= 1.8 else 'NOT met'}); "
          f"end to end {one['wall_time_s'] / two['wall_time_s']:.2f}x")
    machinery = (one["run_wall_time_s"] - one["case_run_time_s"] - one["warmup_time_s"]) / args.cases
    baseline = (one["run_wall_time_s"] - one["warmup_time_s"] - direct_s) / args.cases
    print(f"  per-case overhead of the sweep       {machinery:7.3f} s  (1 worker: wall - cases' own time - warm-up; "
          f"goal < 0.2 s: {'met' if machinery < 0.2 else 'NOT met'})")
    print(f"  per case against the baseline        {baseline:7.3f} s  (includes any change of CPU load between the runs)")
    print(f"  load average (1 min) before {load_before[0]:.2f}, after {load_after[0]:.2f} on {os.cpu_count()} CPUs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
