"""Where the co-simulation master spends its time, measured in one run.

    python benchmarks/bench_cosim.py [--duration 0.2] [--scheme adaptive] [--step 2e-6]

Two passes over the same interval (the second restores a checkpoint taken
before the first, so both take exactly the same steps):

1. as shipped: wall time, communication steps, the master's own split of FMI
   calls vs. the rest, and simulated seconds per wall second;
2. instrumented: every FMI call (setReal, getReal, doStep, FMU state calls) and
   the master's numba step (record + RK4 over the step) timed separately.

The master's bookkeeping per step = (pass-1 time outside FMI calls - pass-2 time
in the numba step) / steps.  Prints the figures in microseconds per communication step.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from wearjoint import cosim
from wearjoint.core import layout as L
from wearjoint.cosim import CoSimulation, CoSimulationOptions
from wearjoint.parameters import JointParameters

WARM_UP_S = 0.01   # past the first impacts; compiles everything


class CallTimer:
    """Wraps a callable, accumulating its wall time [s] and call count."""

    def __init__(self, function):
        self.function = function
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, *args):
        t0 = time.perf_counter()
        result = self.function(*args)
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        return result


def main(argv=None) -> int:
    defaults = CoSimulationOptions()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.2, help="simulated interval measured [s]")
    parser.add_argument("--scheme", choices=cosim.SCHEMES, default=defaults.scheme)
    parser.add_argument("--step", type=float, default=defaults.step_s, help="communication step [s]")
    parser.add_argument("--fmu", default=None, help="FMU to use (default: the cached build)")
    args = parser.parse_args(argv)

    t_end = WARM_UP_S + args.duration
    options = CoSimulationOptions(revolutions=t_end / 0.4 + 0.1, scheme=args.scheme, step_s=args.step)
    samples = np.zeros((int(t_end / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    with CoSimulation(JointParameters(wear_factor=0.0), None, options, fmu_path=args.fmu) as sim:
        sim.advance_to(WARM_UP_S, samples)
        start = sim.checkpoint()
        before = (sim.communication_steps, sim.rollbacks, sim.fmi_time_s, sim.master_time_s)

        wall0 = time.perf_counter()
        sim.advance_to(t_end, samples)
        wall = time.perf_counter() - wall0
        steps = sim.communication_steps - before[0]
        rollbacks = sim.rollbacks - before[1]
        fmi = sim.fmi_time_s - before[2]
        master = sim.master_time_s - before[3]
        end_state = sim.buf.copy()

        sim.restore(start)
        slave = sim._slave
        timers = {name: CallTimer(getattr(slave, attr)) for name, attr in
                  (("setReal", "set_real"), ("getReal", "get_real"), ("doStep", "do_step"))}
        slave.set_real, slave.get_real, slave.do_step = timers["setReal"], timers["getReal"], timers["doStep"]
        for name in ("save_state", "restore_state"):
            timers[name] = CallTimer(getattr(slave, name))
            setattr(slave, name, timers[name])
        kernel = CallTimer(cosim.communication_step)
        cosim.communication_step = kernel
        try:
            sim.advance_to(t_end, samples)
        finally:
            cosim.communication_step = kernel.function
        if not np.array_equal(sim.buf, end_state):
            raise SystemExit("instrumented pass diverged from the first pass (not a like-for-like measurement)")

    us = 1e6 / steps
    print(f"scheme {args.scheme}, step {args.step:g} s, {args.duration:g} s simulated after {WARM_UP_S:g} s warm-up")
    print(f"communication steps {steps}, rollbacks {rollbacks}, mean step {args.duration / steps * 1e6:.2f} us")
    print("per communication step [us]:")
    for name in ("setReal", "getReal", "doStep", "save_state", "restore_state"):
        timer = timers[name]
        label = {"save_state": "getFMUstate+free", "restore_state": "setFMUstate"}.get(name, name)
        print(f"  FMI {label:18s} {timer.seconds * us:8.2f}   ({timer.calls} calls, "
              f"{timer.seconds / max(timer.calls, 1) * 1e6:.2f} us per call)")
    bookkeeping = master - kernel.seconds
    print(f"  master numba step (record + RK4)  {kernel.seconds * us:8.2f}")
    print(f"  master bookkeeping (Python loop)  {bookkeeping * us:8.2f}")
    print(f"  master total (pass 1)             {master * us:8.2f}")
    print(f"  FMI total (pass 1)                {fmi * us:8.2f}")
    print(f"  wall (pass 1)                     {wall * us:8.2f}")
    print(f"master share of wall time: {master / wall:.3f}")
    print(f"simulated seconds per wall second (real-time factor): {args.duration / wall:.4f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
