"""The FMU's Model Exchange engine against the monolithic engine, measured in one run.

    python benchmarks/bench_model_exchange.py [--revolutions 8] [--repeats 5] [--wear both|on|off]
                                              [--fmu PATH]

Paper case (``paper_joint()``), ``SimulationOptions(integrator="dopri")``: the same interval
integrated by ``wearjoint simulate`` (:class:`~wearjoint.simulate.Simulation`) and by the
joint FMU's Model Exchange interface inside the same integrator
(:class:`~wearjoint.cosim.model_exchange.ModelExchangeSimulation`, native FMU), with wear
(the default factor) and/or without (``wear_factor=0``).  Both engines are compiled untimed
first; then each is timed ``--repeats`` times on fresh engines, alternating, and the median
run of each counts.  Prints wall times, accepted/rejected steps (equal without wear; with wear
the FMU's wear over t - t_last can differ from the in-process wear over h in the last digits,
and the runs part after some impacts), real-time factors (simulated s per wall s), the ratio
of the medians ME / monolithic (target 1.5) and the load average before and after (2 shared
cores: above 1 the figures are pessimistic and noisy).

Split (an estimate): one joint evaluation timed in a compiled loop over the states of the
first SPLIT_S of the run, in process (the contact kernel) and through the FMU (``fmi2SetTime``
+ ``fmi2SetReal`` + ``fmi2GetReal``, the FMU's kernel included), times the 6 evaluations per
attempted DOPRI step: the part of the ME wall time in FMI calls.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
from numba import njit

from wearjoint.core import layout as L
from wearjoint.core.joint_access import contact_at
from wearjoint.cosim.model_exchange import ModelExchangeSimulation
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions

from repeats import add_repeats_argument, median_text

TARGET = 1.5
EVALUATIONS = 100_000  # joint evaluations per timed loop in the split
SPLIT_S = 0.05         # the split evaluates the joint at the states of this first interval [s]


@njit(cache=True)
def _evaluate_repeatedly(joint, t, states, n):
    for i in range(n):
        contact_at(joint, t, states[i % states.shape[0]])
    return joint.result[L.R_CONTACT]


def _engine(kind, joint, options, fmu):
    if kind == "monolithic":
        return Simulation(joint, None, options)
    return ModelExchangeSimulation(joint, None, options, fmu_path=fmu, fmu_backend="native")


def _time_run(kind, joint, options, fmu, t_end, samples):
    """(wall time [s], accepted, rejected, engine) of one run 0 -> t_end on a fresh engine (closed)."""
    sim = _engine(kind, joint, options, fmu)
    try:
        sim.warm_up()
        start = time.perf_counter()
        sim.advance_to(t_end, samples)
        return time.perf_counter() - start, sim.accepted, sim.rejected, sim
    finally:
        sim.close()


def _evaluation_costs(joint, options, fmu, samples):
    """Wall time of one joint evaluation [s], (in process, through the FMU): the fastest of 5
    loops over the states every 0.1 ms of the first SPLIT_S of the ME run."""
    mono = Simulation(joint, None, options)
    with ModelExchangeSimulation(joint, None, options, fmu_path=fmu, fmu_backend="native") as me:
        states = []
        while me.t < SPLIT_S:
            me.advance_to(me.t + 1e-4, samples)
            states.append(me.y.copy())
        states = np.array(states)
        costs = []
        for target in (mono._joint_arrays, me._fmu_joint):
            _evaluate_repeatedly(target, me.t, states, 10)
            best = np.inf
            for _ in range(5):
                start = time.perf_counter()
                _evaluate_repeatedly(target, me.t, states, EVALUATIONS)
                best = min(best, time.perf_counter() - start)
            costs.append(best / EVALUATIONS)
    return costs


def bench(label, joint, options, fmu, repeats):
    """Time both engines (alternating, median of ``repeats``), print the figures; the ratio ME / monolithic."""
    period = SliderCrankParameters().period_s
    t_end = options.revolutions * period
    samples = np.zeros((int(t_end / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    walls = {"monolithic": [], "model-exchange": []}
    steps = {}
    for kind in ("monolithic", "model-exchange"):     # untimed: compile / load both
        _time_run(kind, joint, SimulationOptions(integrator="dopri", revolutions=0.01), fmu, 0.002, samples)
    for _ in range(repeats):
        for kind in ("monolithic", "model-exchange"):
            wall, accepted, rejected, sim = _time_run(kind, joint, options, fmu, t_end, samples)
            walls[kind].append(wall)
            steps[kind] = (accepted, rejected)
            if kind == "model-exchange":
                events = sim.events
    median = {kind: statistics.median(runs) for kind, runs in walls.items()}
    print(f"{label}: {options.revolutions:g} revolutions ({t_end:g} s simulated), DOPRI, median of {repeats}")
    for kind in ("monolithic", "model-exchange"):
        accepted, rejected = steps[kind]
        print(f"  {kind:15s} wall {median_text(walls[kind], '.3f')} s   steps accepted {accepted:7d} "
              f"rejected {rejected:6d}   real-time factor {t_end / median[kind]:6.2f}   "
              f"{median[kind] / accepted * 1e6:6.2f} us per accepted step")
    same = steps["monolithic"] == steps["model-exchange"]
    print(f"  steps equal: {'yes' if same else 'NO'}; ME event iterations (onsets, separations) {events}")
    in_process, through_fmu = _evaluation_costs(joint, options, fmu, samples)
    evaluations = 6 * sum(steps["model-exchange"])
    fmi = evaluations * through_fmu
    print(f"  one joint evaluation: through the FMU {through_fmu * 1e9:.0f} ns, in process {in_process * 1e9:.0f} ns "
          "(with its own cos/sin; in the run it shares them with the mechanism)")
    print(f"  ME split ({evaluations} stage evaluations): FMI calls ~{fmi:.3f} s, the rest "
          f"~{median['model-exchange'] - fmi:.3f} s; "
          f"ME - monolithic {median['model-exchange'] - median['monolithic']:.3f} s")
    ratio = median["model-exchange"] / median["monolithic"]
    print(f"  ME / monolithic wall time: {ratio:.2f} (target {TARGET}: {'met' if ratio <= TARGET else 'NOT met'})")
    return ratio


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=8.0, help="crank revolutions timed per run")
    add_repeats_argument(parser, default=5)
    parser.add_argument("--wear", choices=("both", "on", "off"), default="both",
                        help="with the paper's wear factor, without wear (wear_factor=0), or both")
    parser.add_argument("--fmu", default=None, help="native FMU to use (default: the cached build)")
    args = parser.parse_args(argv)
    options = SimulationOptions(integrator="dopri", revolutions=args.revolutions)
    cases = {"on": [("with wear", paper_joint())], "off": [("no wear", paper_joint(wear_factor=0.0))]}
    cases["both"] = cases["on"] + cases["off"]
    load_before = os.getloadavg()
    ratios = [bench(label, joint, options, args.fmu, args.repeats) for label, joint in cases[args.wear]]
    load_after = os.getloadavg()
    print(f"load average (1 min) before {load_before[0]:.2f}, after {load_after[0]:.2f} on {os.cpu_count()} CPUs "
          "(shared machine: above 1 the figures are pessimistic)")
    print(f"target {TARGET}: {'met' if max(ratios) <= TARGET else 'NOT met'} "
          f"(ratios {', '.join(f'{r:.2f}' for r in ratios)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
