"""How fast the main jobs with wear could run at the steps they take: measured floors beside the speed targets.

    python benchmarks/bench_floor.py [--repeats 3] [--paired-cosim 1.66] [--paired-simulate 1.81] [--json FILE]

The speed issue asks, with wear, for ``wearjoint cosim`` at 5x and ``wearjoint simulate --revolutions 2`` at
10x the real-time factors of f74ef9c.  ``--paired-*``: this tree's speed against f74ef9c's as
``benchmarks/compare.py --base f74ef9c --probes cosim-wear,monolithic-wear`` measured it (2026-11-27, 3 pairs,
load 0.8-0.9; CHANGELOG.md); a target in this run's terms is then this run's real-time factor times
target / paired, whatever the machine's speed (it varies by up to 1.5x here).  Both engines' steps in contact
are set by the contact's accuracy (docs/reference/model.md §7: the co-simulation's 5 us, DOPRI's 1e-5 s with wear); from
each run's own counters this prints what the target leaves for a step and how fast each engine would run at its
step count if parts of its work cost nothing:

* ``cosim`` (compare.py's ``cosim-wear`` probe: 0.2 s after 0.01 s, the paper's joint at wear factor 1):
  ``bench_cosim.measure``'s split per communication step, with wear and without; the floor with the FMI
  calls free (the master's RK4 and bookkeeping left); the FMI time per step the target leaves, beside the FMI
  time per step of the run without wear.
* ``simulate`` (the ``monolithic-wear`` probe: ``simulate --revolutions 2``, DOPRI default): with and without
  wear; the floor: the run with wear, each attempted step at the cost of a step of the run without wear (the
  same integrator and mechanism; the contact on the unworn bushing, nothing to wear).

Each figure is the median of ``--repeats`` runs, printed with the machine's load; ``--json FILE`` also writes
the medians as JSON (benchmarks/performance_doc.py reads it).
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path
from types import SimpleNamespace

from wearjoint.cosim import CoSimulationOptions
from wearjoint.fmu.fmi import DEFAULT_BACKEND
from wearjoint.parameters import paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

import bench_cosim
from repeats import Load, add_repeats_argument, median_text

COSIM_TARGET = 5.0       # the issue's targets: this many times f74ef9c's real-time factor
SIMULATE_TARGET = 10.0


def simulate_run(wear_factor: float) -> dict:
    """``simulate --revolutions 2``'s engine: real-time factor and wall seconds per attempted step."""
    record = run_simulation(paper_joint(wear_factor=wear_factor), options=SimulationOptions(revolutions=2.0),
                            progress=False)
    s = record.summary()
    attempted = s["integrator_accepted_steps"] + s["integrator_rejected_steps"]
    return {"rtf": s["realtime_factor"], "attempted": attempted, "per_step": s["wall_time_s"] / attempted,
            "simulated": s["simulated_time_s"]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paired-cosim", type=float, default=1.66,
                        help="this tree's cosim-wear real-time factor / f74ef9c's (default %(default)g)")
    parser.add_argument("--paired-simulate", type=float, default=1.81,
                        help="this tree's monolithic-wear real-time factor / f74ef9c's (default %(default)g)")
    add_repeats_argument(parser)
    parser.add_argument("--json", type=Path, default=None, help="also write the medians to this JSON file")
    args = parser.parse_args()
    for name in ("paired_cosim", "paired_simulate"):
        value = getattr(args, name)
        if not value > 0.0:       # NaN too
            parser.error(f"--{name.replace('_', '-')}={value!r} is invalid: allowed a ratio > 0")

    load = Load()
    worn_args = SimpleNamespace(duration=0.2, scheme=CoSimulationOptions().scheme, step=CoSimulationOptions().step_s,
                                fmu=None, fmu_backend=DEFAULT_BACKEND, wear_factor=1.0)
    cosim, cosim_unworn, worn, unworn = [], [], [], []
    for _ in range(args.repeats):          # alternately: each pair sees the same machine
        cosim.append(bench_cosim.measure(worn_args))
        cosim_unworn.append(bench_cosim.measure(SimpleNamespace(**{**vars(worn_args), "wear_factor": 0.0})))
        worn.append(simulate_run(1.0))
        unworn.append(simulate_run(0.0))
    load.stop()
    for run in cosim:
        run["no_fmi"] = worn_args.duration / ((run["mechanism"] + run["bookkeeping"]) * run["steps"])
        target_wall = run["wall"] * args.paired_cosim / COSIM_TARGET           # per step, at the target
        run["fmi_budget"] = target_wall - run["mechanism"] - run["bookkeeping"]
    for run, free in zip(worn, unworn):
        run["floor"] = run["simulated"] / (run["attempted"] * free["per_step"])
        run["target"] = run["rtf"] * SIMULATE_TARGET / args.paired_simulate

    def med(runs, key, scale=1.0, fmt=".2f"):
        return median_text([run[key] * scale for run in runs], fmt)

    def ratio(runs, key, others, other_key):
        return statistics.median(run[key] / other[other_key] for run, other in zip(runs, others))

    print(f"{load}")
    print(f"cosim with wear (0.2 s after 0.01 s): {med(cosim, 'steps', fmt='.0f')} communication steps, real-time "
          f"factor {med(cosim, 'rtf')}; per step [us] FMI {med(cosim, 'fmi', 1e6)}, mechanism RK4 "
          f"{med(cosim, 'mechanism', 1e6)}, bookkeeping {med(cosim, 'bookkeeping', 1e6)}")
    print(f"  without wear: {med(cosim_unworn, 'steps', fmt='.0f')} communication steps, real-time factor "
          f"{med(cosim_unworn, 'rtf')}; FMI {med(cosim_unworn, 'fmi', 1e6)} us per step")
    print(f"  with the FMI calls free: real-time factor {med(cosim, 'no_fmi')}")
    print(f"  at {COSIM_TARGET:g}x f74ef9c ({COSIM_TARGET / args.paired_cosim:.2f}x this run) the FMI calls may take "
          f"{med(cosim, 'fmi_budget', 1e6)} us per step: {ratio(cosim, 'fmi_budget', cosim_unworn, 'fmi'):.2f} of "
          f"their time per step without wear")
    print(f"simulate --revolutions 2 with wear: {med(worn, 'attempted', fmt='.0f')} attempted steps, "
          f"{med(worn, 'per_step', 1e6)} us each, real-time factor {med(worn, 'rtf')}")
    print(f"  without wear: {med(unworn, 'attempted', fmt='.0f')} attempted steps, {med(unworn, 'per_step', 1e6)} us "
          f"each, real-time factor {med(unworn, 'rtf')}")
    print(f"  with wear, each step at the no-wear cost: real-time factor {med(worn, 'floor')}; "
          f"{SIMULATE_TARGET:g}x f74ef9c is {med(worn, 'target')} in this run: the floor is "
          f"{ratio(worn, 'floor', worn, 'target'):.2f} of it")
    if args.json:
        def median(runs, key, scale=1.0):
            return statistics.median(run[key] * scale for run in runs)
        args.json.write_text(json.dumps({
            "repeats": args.repeats, "load": [load.before, load.after],
            "paired_cosim": args.paired_cosim, "paired_simulate": args.paired_simulate,
            "cosim": {"communication steps": median(cosim, "steps"), "real-time factor": median(cosim, "rtf"),
                      "FMI us per step": median(cosim, "fmi", 1e6),
                      "mechanism us per step": median(cosim, "mechanism", 1e6),
                      "bookkeeping us per step": median(cosim, "bookkeeping", 1e6),
                      "real-time factor with the FMI calls free": median(cosim, "no_fmi"),
                      "FMI us per step at the target": median(cosim, "fmi_budget", 1e6)},
            "cosim without wear": {"communication steps": median(cosim_unworn, "steps"),
                                   "real-time factor": median(cosim_unworn, "rtf"),
                                   "FMI us per step": median(cosim_unworn, "fmi", 1e6)},
            "simulate": {"attempted steps": median(worn, "attempted"), "us per step": median(worn, "per_step", 1e6),
                         "real-time factor": median(worn, "rtf"),
                         "real-time factor, each step at the no-wear cost": median(worn, "floor"),
                         "target real-time factor in this run": median(worn, "target")},
            "simulate without wear": {"attempted steps": median(unworn, "attempted"),
                                      "us per step": median(unworn, "per_step", 1e6),
                                      "real-time factor": median(unworn, "rtf")}}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
