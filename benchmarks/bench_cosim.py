"""Where the co-simulation master spends its time: the median of ``--repeats`` runs in one invocation.

    python benchmarks/bench_cosim.py [--duration 0.2] [--scheme adaptive] [--step 5e-6] [--repeats 3]
                                     [--wear-factor 0] [--fmu-backend native|pythonfmu] [--fmu PATH] [--callgrind]

Each run, on a fresh co-simulation of the paper's slider-crank (the joint without wear unless ``--wear-factor``):

1. As shipped: wall time, communication steps, rollbacks, and the master loop's
   own split (``CoSimulation.fmi_time_s``: wall time inside the FMI calls, read
   with clock_gettime around them in one iteration of 16 of the numba loop and
   scaled; the rest is the master).
2. The mechanism integration alone: ``communication_step`` (record + RK4 over
   the step with held forces) run from numba as many times as there were steps,
   at the mean step, on a copy of the master's buffer (no FMI calls); the
   fastest of REPLAYS replays.

Master bookkeeping per step = (master time of 1. - mechanism time of 2.) / steps.
Prints microseconds per communication step and the real-time factor, each the median
of the runs, with the machine's load, and how the steps split: started in free flight,
in contact at ``--step``, in contact shorter (the force missed its extrapolation).

``--callgrind``: instead, one run under ``valgrind --tool=callgrind`` counting the instructions
inside the FMU's fmi2* functions (the native FMU's: they have symbols): per call of each, and per
communication step (warm-up included) -- figures the machine's load does not change.
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np
from numba import njit

from wearjoint.core import layout as L
from wearjoint.cosim import SCHEMES, CoSimulation, CoSimulationOptions, communication_step
from wearjoint.cosim.master_layout import B_TRACK, buffer_views
from wearjoint.fmu.fmi import BACKENDS, DEFAULT_BACKEND
from wearjoint.parameters import paper_joint

from repeats import Load, add_repeats_argument, median_text

WARM_UP_S = 0.01   # past the first impacts; compiles everything
REPLAYS = 5        # the mechanism replay is timed this often; the fastest counts


@njit  # not cached: numba's cache would keep an old copy of communication_step (it checks this file only)
def _mechanism_steps(buf, stats, stages, n_steps, h, ws, samples):
    t = 0.0
    for _ in range(n_steps):
        t = communication_step(t, h, True, buf, stats, stages, ws, samples)
    return t


def measure(args) -> dict:
    """One run on a fresh co-simulation: steps, rollbacks and seconds per communication step."""
    t_end = WARM_UP_S + args.duration
    options = CoSimulationOptions(revolutions=t_end / 0.4 + 0.1, scheme=args.scheme, step_s=args.step)
    samples = np.zeros((int(t_end / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    with CoSimulation(paper_joint(wear_factor=args.wear_factor), None, options, fmu_path=args.fmu,
                      fmu_backend=args.fmu_backend) as sim:
        sim.advance_to(WARM_UP_S, samples)
        before = (sim.communication_steps, sim.rollbacks, sim.fmi_time_s, sim.master_time_s, sim.free_steps,
                  sim.shrunk_steps)
        buffer_at_start = sim.buf.copy()
        wall0 = time.perf_counter()
        sim.advance_to(t_end, samples)
        wall = time.perf_counter() - wall0
        free = sim.free_steps - before[4]
        shrunk = sim.shrunk_steps - before[5]
        steps = sim.communication_steps - before[0]
        rollbacks = sim.rollbacks - before[1]
        fmi = sim.fmi_time_s - before[2]
        master = sim.master_time_s - before[3]
        ws = sim.mechanism.workspace

    mean_step = args.duration / steps
    scratch = np.zeros((4, L.N_SAMPLE_COLUMNS))
    warm = buffer_at_start.copy()
    _mechanism_steps(warm, *buffer_views(warm), 2, mean_step, ws, scratch)   # compile / load outside the timing
    replays = []
    for _ in range(REPLAYS):
        buf = buffer_at_start.copy()
        buf[B_TRACK + L.K_SAMPLE_DT] = 1e9                          # no samples
        t0 = time.perf_counter()
        _mechanism_steps(buf, *buffer_views(buf), steps + rollbacks, mean_step, ws, scratch)
        replays.append(time.perf_counter() - t0)
    mechanism = min(replays)
    return {"steps": steps, "rollbacks": rollbacks, "free": free, "shrunk": shrunk, "fmi": fmi / steps,
            "mechanism": mechanism / steps, "bookkeeping": (master - mechanism) / steps,
            "replay_spread": (max(replays) - mechanism) / steps,
            "wall": wall / steps, "rtf": args.duration / wall}


def callgrind(argv) -> int:
    """One run under callgrind, collecting inside the fmi2* functions: instructions per call and per step."""
    with tempfile.TemporaryDirectory(prefix="bench_cosim_") as tmp:
        out = Path(tmp) / "callgrind.out"
        argv = [a for a in argv if a != "--callgrind"]
        load = Load()
        done = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", "--toggle-collect=fmi2*",
                               sys.executable, __file__, "--measure-once", "--repeats", "1", *argv],
                              capture_output=True, text=True)
        if done.returncode != 0:
            print(done.stderr[-3000:], file=sys.stderr)
            return 1
        calls, inclusive = fmi_calls(out.read_text())
    steps = calls["fmi2DoStep"]
    print(f"instructions inside the FMI calls (callgrind), {steps} doStep calls with the warm-up and rollbacks; "
          f"{load.stop()} (the counts do not depend on it)")
    for prefix in ("fmi2", "wearjoint_"):   # the FMI calls, then the compiled kernels they ran
        for function in sorted((f for f in calls if f.startswith(prefix)), key=lambda f: -inclusive[f]):
            print(f"  {function:30s} {calls[function]:7d} calls {inclusive[function] / calls[function]:9,.0f} per call "
                  f"{inclusive[function] / steps:8,.0f} per doStep")
    total = sum(inclusive[f] for f in calls if f.startswith("fmi2"))
    print(f"  {'all FMI calls':30s} {total / steps:44,.0f} per doStep")
    return 0


def fmi_calls(text: str) -> tuple[Counter, Counter]:
    """Calls and inclusive instructions of each function a callgrind file names as called (cfn=)."""
    names, calls, inclusive, callee = {}, Counter(), Counter(), None
    for line in text.splitlines():
        named = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
        if named:
            if named[3]:
                names[named[2]] = named[3]
            callee = names[named[2]] if named[1] == "cfn" else None
        elif callee and line.startswith("calls="):
            calls[callee] += int(line.split("=")[1].split()[0])
        elif callee and re.match(r"[+-]?\d+ \d+", line):
            inclusive[callee] += int(line.split()[1])
            callee = None
    return calls, inclusive


def main(argv=None) -> int:
    defaults = CoSimulationOptions()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.2, help="simulated interval measured [s]")
    parser.add_argument("--scheme", choices=SCHEMES, default=defaults.scheme)
    parser.add_argument("--step", type=float, default=defaults.step_s, help="communication step [s]")
    parser.add_argument("--wear-factor", type=float, default=0.0,
                        help="the joint's wear factor (default %(default)g; the README's main job wears at 1)")
    parser.add_argument("--fmu", default=None, help="FMU to use (default: the cached build of --fmu-backend)")
    parser.add_argument("--fmu-backend", choices=BACKENDS, default=DEFAULT_BACKEND, help="FMU backend")
    parser.add_argument("--callgrind", action="store_true", help="count the instructions in the FMI calls instead")
    parser.add_argument("--measure-once", action="store_true", help=argparse.SUPPRESS)   # the run under valgrind
    add_repeats_argument(parser)
    args = parser.parse_args(argv)
    if not args.wear_factor >= 0.0:       # NaN too
        parser.error(f"--wear-factor={args.wear_factor!r} is invalid: allowed >= 0")
    if args.measure_once:
        run = measure(args)
        print(f"communication steps {run['steps']} (after the warm-up)")
        return 0
    if args.callgrind:
        return callgrind(argv or sys.argv[1:])

    load = Load()
    runs = [measure(args) for _ in range(args.repeats)]
    load.stop()

    def median(key, scale=1e6, fmt="8.2f"):
        return median_text([run[key] * scale for run in runs], fmt)

    print(f"wear factor {args.wear_factor:g}, scheme {args.scheme}, step {args.step:g} s, {args.duration:g} s simulated "
          f"after {WARM_UP_S:g} s warm-up, "
          f"FMU {args.fmu or args.fmu_backend + ' (cached build)'}; {load}")
    print(f"communication steps {median('steps', 1, '.0f')}, rollbacks {median('rollbacks', 1, '.0f')}; "
          f"started in free flight {median('free', 1, '.0f')}, in contact shorter than the step "
          f"{median('shrunk', 1, '.0f')}")
    print("per communication step [us]:")
    print(f"  FMI calls (doStep, setReal, getReal, FMU states)  {median('fmi')}")
    print(f"  mechanism integration (record + RK4, numba)       {median('mechanism')}")
    print(f"  master bookkeeping (loop, rollback copies)        {median('bookkeeping')}"
          f"   (replay spread {median('replay_spread', fmt='.2f')}: less is timing noise)")
    print(f"  wall                                              {median('wall')}")
    print(f"simulated seconds per wall second (real-time factor): {median('rtf', 1, '.3f')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
