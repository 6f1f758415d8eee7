"""Cost of each FMI call of the ClearanceWearJoint FMU, per call, measured in one run.

    python benchmarks/bench_fmu_calls.py [--fmu NEW.fmu] [--baseline OLD.fmu] [--rounds 3] [--steps 20000]

Drives the FMU like the co-simulation master does (fmpy's raw FMI functions on
pre-allocated ctypes arrays): per communication step setReal of the 12 inputs,
getReal of the master's 12 outputs, doStep; every 10th step getFMUstate (plus
freeFMUstate of the previous state) and setFMUstate of the state just taken.
The inputs follow the pin around the bushing, in and out of contact.

Each FMU runs in its own child process (two builds of the slave cannot share one
process: the slave module and wearjoint are imported once per process), the
rounds alternate baseline / new so both see the same machine load; the table
gives the median over rounds of the mean per call, the baseline/new ratio, and
the load average before and after.  The first row is the wall time of the first
instantiate..exitInitializationMode in the fresh process: the child imports no
wearjoint module, so the FMU loads its own copy and numba compiles its kernels.
"""
from __future__ import annotations

import argparse
import ctypes
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

STATE_EVERY = 10          # steps between getFMUstate/setFMUstate pairs
STEP_S = 5e-6             # communication step in contact (the adaptive scheme's)
WARM_UP_STEPS = 2000
CALLS = ("first init [s]", "setReal(12)", "getReal(12)", "doStep", "getFMUstate", "freeFMUstate", "setFMUstate")


def input_trajectory(n: int):
    """n input rows: the pin centre circling the bushing centre at clearance -2..+4 um, spinning."""
    import numpy as np

    from wearjoint.parameters import JointParameters

    p = JointParameters()
    k = np.arange(n)
    direction = 2 * math.pi * k / 997.0
    eccentricity = p.clearance_m + 1e-6 + 3e-6 * np.sin(2 * math.pi * k / 131.0)
    bushing_centre = np.array(p.bushing_offset_m)   # bushing body at the origin, angle 0
    rows = np.zeros((n, 12))
    rows[:, 0] = bushing_centre[0] + eccentricity * np.cos(direction) - p.pin_offset_m[0]
    rows[:, 1] = bushing_centre[1] + eccentricity * np.sin(direction) - p.pin_offset_m[1]
    rows[:, 3] = -0.05 * np.sin(direction)
    rows[:, 4] = 0.05 * np.cos(direction)
    rows[:, 5] = 10.0
    return rows


def child(fmu_path: str, steps: int, setup: dict) -> dict:
    """Time the calls on one fresh instance of ``fmu_path``; seconds per call by name.

    Imports no wearjoint module: the FMU must load (and compile) its own copy.
    """
    import numpy as np
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave, fmi2FMUstate, fmi2Real, fmi2ValueReference

    INPUT_NAMES, OUTPUT_NAMES = setup["inputs"], setup["outputs"]
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    t0 = time.perf_counter()
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_path), modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="bench")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    first_init = time.perf_counter() - t0

    dll, c = fmu.dll, fmu.component
    set_real, get_real, do_step = dll.fmi2SetReal, dll.fmi2GetReal, dll.fmi2DoStep
    get_state, set_state, free_state = dll.fmi2GetFMUstate, dll.fmi2SetFMUstate, dll.fmi2FreeFMUstate
    input_vrs = (fmi2ValueReference * 12)(*(vr[n] for n in INPUT_NAMES))
    output_vrs = (fmi2ValueReference * len(OUTPUT_NAMES))(*(vr[n] for n in OUTPUT_NAMES))
    outputs = (fmi2Real * len(OUTPUT_NAMES))()
    rows = np.array(setup["trajectory"])
    inputs = [(fmi2Real * 12).from_buffer(row) for row in rows]
    state, previous = fmi2FMUstate(), fmi2FMUstate()
    clock = time.perf_counter
    seconds = dict.fromkeys(CALLS[1:], 0.0)
    counts = dict.fromkeys(CALLS[1:], 0)

    def check(status, call):
        if status != 0:
            raise SystemExit(f"{call} returned status {status}")

    for k in range(WARM_UP_STEPS + steps):
        timed = k >= WARM_UP_STEPS
        row = inputs[k % len(inputs)]
        t_a = clock()
        status_set = set_real(c, input_vrs, 12, row)
        t_b = clock()
        status_get = get_real(c, output_vrs, len(OUTPUT_NAMES), outputs)
        t_c = clock()
        status_step = do_step(c, k * STEP_S, STEP_S, 1)
        t_d = clock()
        check(status_set, "fmi2SetReal"), check(status_get, "fmi2GetReal"), check(status_step, "fmi2DoStep")
        if timed:
            seconds["setReal(12)"] += t_b - t_a
            seconds["getReal(12)"] += t_c - t_b
            seconds["doStep"] += t_d - t_c
        if k % STATE_EVERY == 0:
            t_a = clock()
            check(get_state(c, ctypes.byref(state)), "fmi2GetFMUstate")
            t_b = clock()
            if previous:
                check(free_state(c, ctypes.byref(previous)), "fmi2FreeFMUstate")
            t_c = clock()
            check(set_state(c, state), "fmi2SetFMUstate")
            t_d = clock()
            state, previous = fmi2FMUstate(), state
            if timed:
                seconds["getFMUstate"] += t_b - t_a
                seconds["freeFMUstate"] += t_c - t_b
                seconds["setFMUstate"] += t_d - t_c
                for name in ("getFMUstate", "freeFMUstate", "setFMUstate"):
                    counts[name] += 1
    for name in ("setReal(12)", "getReal(12)", "doStep"):
        counts[name] = steps
    free_state(c, ctypes.byref(previous))
    fmu.terminate()
    fmu.freeInstance()
    per_call = {name: seconds[name] / counts[name] for name in seconds}
    per_call["first init [s]"] = first_init
    return per_call


def run_child(fmu: Path, steps: int, setup: str) -> dict:
    done = subprocess.run([sys.executable, __file__, "--child", str(fmu), "--steps", str(steps)],
                          input=setup, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"benchmark child for {fmu} failed:\n{done.stderr.strip()}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default=None, help="FMU to measure (default: the cached build of this tree)")
    parser.add_argument("--baseline", default=None, help="FMU to compare with (e.g. a build of an older commit)")
    parser.add_argument("--rounds", type=int, default=3, help="child processes per FMU, alternating")
    parser.add_argument("--steps", type=int, default=20000, help="timed communication steps per child")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child is not None:
        print(json.dumps(child(args.child, args.steps, json.loads(sys.stdin.read()))))
        return 0

    if args.fmu is None:
        from wearjoint.fmu.ensure import ensure_fmu
        from wearjoint.parameters import JointParameters

        args.fmu = ensure_fmu(JointParameters().n_points)
    fmus = {"new": Path(args.fmu)}
    if args.baseline is not None:
        fmus = {"baseline": Path(args.baseline), **fmus}
    from wearjoint.cosim import INPUT_NAMES, OUTPUT_NAMES

    setup = json.dumps({"inputs": list(INPUT_NAMES), "outputs": list(OUTPUT_NAMES),
                        "trajectory": input_trajectory(4096).tolist()})
    load_before = os.getloadavg()
    runs = {label: [] for label in fmus}
    for _ in range(args.rounds):
        for label, fmu in fmus.items():
            runs[label].append(run_child(fmu, args.steps, setup))
    load_after = os.getloadavg()

    print(f"{args.rounds} rounds x {args.steps} steps per FMU (median of the per-round means), "
          f"{os.cpu_count()} cores, load average {load_before[0]:.2f} before, {load_after[0]:.2f} after")
    for label, fmu in fmus.items():
        print(f"  {label}: {fmu}")
    header = f"{'call':16s}" + "".join(f"{label + ' [us]':>16s}" for label in fmus)
    print(header + (f"{'baseline/new':>14s}" if len(fmus) == 2 else ""))
    for name in CALLS:
        scale = 1.0 if name.endswith("[s]") else 1e6
        medians = {label: statistics.median(run[name] for run in runs[label]) * scale for label in fmus}
        line = f"{name:16s}" + "".join(f"{medians[label]:16.3f}" for label in fmus)
        if len(fmus) == 2:
            line += f"{medians['baseline'] / medians['new']:14.2f}"
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
