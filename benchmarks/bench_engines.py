"""Simulated seconds per wall second of every engine, measured in one run.

    python benchmarks/bench_engines.py [--revolutions 0.5] [--json FILE]

Paper case, no wear, the same interval for each engine: monolithic RK4 at 1 us and
DOPRI (default tolerances), exudyn (generalized-alpha, our joint and exudyn's own
contact) at 10 us, the FMU co-simulation (adaptive, 2 us in contact)
when ``wearjoint.cosim`` is importable.  Each engine first runs 5 ms untimed
(numba compilation, imports, FMU extraction).  Prints a table; ``--json`` also
writes it.  The machine's other load is not controlled: compare within one run.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from wearjoint.fmu.fmi import BACKENDS, DEFAULT_BACKEND
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.validation.compare import run_monolithic, engine_runner

WARM_UP_S = 0.005
SAMPLE_DT_S = 1e-5


def engines(fmu_backend: str = DEFAULT_BACKEND):
    """(label, run(revolutions) -> RunRecord) of every engine available here."""
    joint = paper_joint(wear_factor=0.0)
    table = [
        ("monolithic RK4 1 us", lambda rev: run_monolithic(joint, None, rev, SAMPLE_DT_S, False, integrator="rk4",
                                                        step_s=1e-6)),
        ("monolithic DOPRI (rtol 1e-6, max step 100 us)",
         lambda rev: run_monolithic(joint, None, rev, SAMPLE_DT_S, False, integrator="dopri")),
    ]
    for engine, step in (("exudyn-discrete", 1e-5), ("exudyn-native", 1e-5), ("cosim", 2e-6)):
        try:
            runner = engine_runner(engine, joint, fmu_backend)
        except ImportError as exc:
            print(f"{engine}: not available ({exc})", file=sys.stderr)
            continue
        label = f"{engine} {'adaptive, ' if engine == 'cosim' else ''}step {step * 1e6:g} us"
        table.append((label, lambda rev, runner=runner, step=step: runner(joint, None, rev, step, SAMPLE_DT_S, False)))
    return table


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=0.5, help="crank revolutions timed per engine")
    parser.add_argument("--json", type=Path, default=None, help="also write the table as JSON")
    parser.add_argument("--fmu-backend", choices=BACKENDS, default=DEFAULT_BACKEND, help="the co-simulation's FMU")
    args = parser.parse_args(argv)
    period = SliderCrankParameters().period_s
    rows = []
    for label, run in engines(args.fmu_backend):
        run(WARM_UP_S / period)
        record = run(args.revolutions)
        rate = record.simulated_time_s / record.wall_time_s
        rows.append({"engine": label, "simulated_time_s": record.simulated_time_s, "wall_time_s": record.wall_time_s,
                     "simulated_s_per_wall_s": rate, "wall_s_per_revolution": period / rate})
        print(f"  {label}: {rate:.3g} simulated s per wall s", file=sys.stderr, flush=True)
    load = os.getloadavg()[0]
    print(f"\nno wear, paper case, {args.revolutions:g} rev per engine; load average {load:.2f} on "
          f"{os.cpu_count()} cores (shared machine: figures are under that load)\n")
    print(f"| {'engine':48s} | simulated s / wall s | wall s per revolution |")
    print(f"|{'-' * 50}|----------------------|-----------------------|")
    for r in rows:
        print(f"| {r['engine']:48s} | {r['simulated_s_per_wall_s']:20.3g} | {r['wall_s_per_revolution']:21.3g} |")
    if args.json:
        args.json.write_text(json.dumps({"revolutions": args.revolutions, "load_average_1min": load,
                                         "cores": os.cpu_count(), "engines": rows}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
