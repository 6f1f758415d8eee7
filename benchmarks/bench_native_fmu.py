"""The native FMU against the pythonfmu FMU and the in-process kernels, measured in one run.

    python benchmarks/bench_native_fmu.py [--steps 200000] [--repeats 3]

1. Start-up: load + instantiate + initialise in a fresh process (fmpy child process, as in
   bench_fmu_calls.py; and for the native FMU also the C host of tests/c_host, no Python).
2. Resident memory: what loading and initialising the FMU adds to the fresh Python child's
   resident set; and the resident set of the whole C host process with one live instance.
3. Per communication step, from compiled code: the C host's ``trace`` loop (setReal of the
   12 inputs, getReal of the 6 forces, doStep) over the same input rows as the in-process
   kernels in a numba loop (evaluate_contact for the forces, accept_contact for the step) --
   the work the FMU does per step, without the FMI layer.  The pythonfmu FMU runs in the C
   host with libpython preloaded and the package on PYTHONPATH (the only way a C host can
   load it).

Prints each figure per backend as the median of ``--repeats`` runs in this invocation, the ratios,
and the machine's load.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent / "tests")]
from bench_fmu_calls import input_trajectory  # noqa: E402
from fmi_host import build_c_host, run_c_host, stderr_value  # noqa: E402
from repeats import add_repeats_argument  # noqa: E402

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.core.contact import evaluate_contact  # noqa: E402
from wearjoint.core.wear import accept_contact  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.ensure import ensure_fmu  # noqa: E402

STEP_S = 5e-6
FORCES = ("pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque")

CHILD = """
import json, sys, time
def rss_kb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = read_model_description(path)
directory = extract(path)
before = rss_kb()
t0 = time.perf_counter()
fmu = FMU2Slave(guid=md.guid, unzipDirectory=directory, modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="bench")
fmu.instantiate()
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
seconds = time.perf_counter() - t0
print(json.dumps({"startup_s": seconds, "rss_growth_kb": rss_kb() - before}))
fmu.terminate()
fmu.freeInstance()
"""


@njit(cache=True)
def _kernel_steps(rows, h, jp, cos_phi, sin_phi, wear_depth, block_min, memory, mask, work, result):
    """evaluate + accept per row: what the FMU computes per communication step (its doStep accepts
    the evaluation the forces were read from)."""
    total = 0.0
    for k in range(rows.shape[0]):
        r = rows[k]
        evaluate_contact(r[0:3], r[3:6], r[6:9], r[9:12], jp, cos_phi, sin_phi, wear_depth, block_min, memory,
                         result)
        total += result[0]
        accept_contact(result, r[0:3], r[3:6], r[6:9], r[9:12], h, True, jp, cos_phi, sin_phi, wear_depth, block_min,
                       memory, mask, work)
    return total


def in_process_seconds_per_step(rows: np.ndarray) -> float:
    _kernel_steps(rows[:10], STEP_S, *ClearanceJoint(JointParameters()).arrays)   # compile
    arrays = ClearanceJoint(JointParameters()).arrays
    t0 = time.perf_counter()
    _kernel_steps(rows, STEP_S, *arrays)
    return (time.perf_counter() - t0) / len(rows)


def fresh_python_child(fmu: Path) -> dict:
    done = subprocess.run([sys.executable, "-c", CHILD, str(fmu)], capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"the start-up child for {fmu} failed:\n{done.stderr.strip()[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def python_host_environment() -> dict:
    """What a C host needs to load the pythonfmu FMU: libpython preloaded, the packages on the path."""
    libpython = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var("LDLIBRARY")
    paths = [str(HERE.parent), *(p for p in sys.path if p.endswith("site-packages"))]
    return {"LD_PRELOAD": str(libpython), "PYTHONPATH": os.pathsep.join(paths), "PYTHONHOME": sys.base_prefix}


def c_host_run(host: Path, fmu_dir: Path, guid: str, script: str, environment: dict | None) -> str:
    """stderr of one C host run (timings, resident set, the FMU's log)."""
    if environment is None:
        code, stdout, stderr = run_c_host(host, fmu_dir, fv.MODEL_NAME, guid, script)
    else:   # run_c_host's clean environment cannot load pythonfmu; same host, same script
        with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
            f.write(script)
        done = subprocess.run([str(host), str(fmu_dir), fv.MODEL_NAME, guid, f.name], capture_output=True,
                              text=True, env={"PATH": "/usr/bin:/bin", **environment})
        os.unlink(f.name)
        code, stdout, stderr = done.returncode, done.stdout, done.stderr
    if code != 0:
        raise SystemExit(f"C host run on {fmu_dir} failed ({code}):\n{stdout[-1000:]}{stderr[-2000:]}")
    return stderr


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200_000, help="communication steps of the timed loops")
    add_repeats_argument(parser)
    args = parser.parse_args(argv)
    n_points = JointParameters().n_points
    fmus = {backend: ensure_fmu(n_points, backend=backend) for backend in ("native", "pythonfmu")}
    rows = input_trajectory(4096)
    rows = np.ascontiguousarray(np.resize(rows, (args.steps, 12)))
    work = Path(tempfile.mkdtemp(prefix="bench_native_"))
    host = build_c_host(work / "host")
    trace = work / "trace.txt"
    trace.write_text("".join(f"{k * STEP_S!r} {STEP_S!r} " + " ".join(repr(float(v)) for v in row) + "\n"
                             for k, row in enumerate(rows)))
    results = {b: {"startup_s": [], "rss_growth_kb": [], "c_startup_s": [], "c_rss_kb": [], "step_s": []}
               for b in fmus}
    kernels = []
    load_before = os.getloadavg()
    for _ in range(args.repeats):
        kernels.append(in_process_seconds_per_step(rows))
        for backend, fmu in fmus.items():
            child = fresh_python_child(fmu)
            results[backend]["startup_s"].append(child["startup_s"])
            results[backend]["rss_growth_kb"].append(child["rss_growth_kb"])
            fmu_dir = work / backend
            if not fmu_dir.exists():
                from fmpy import extract, read_model_description

                extract(str(fmu), unzipdir=str(fmu_dir))
                (fmu_dir / "guid").write_text(read_model_description(str(fmu)).guid)
            guid = (fmu_dir / "guid").read_text()
            environment = None if backend == "native" else python_host_environment()
            # the resident set while the time_load instance lives (cycle 1 prints it at its end)
            stderr = c_host_run(host, fmu_dir, guid, "time_load\ncycle 1\nfree\n", environment)
            results[backend]["c_startup_s"].append(stderr_value(stderr, "startup_seconds"))
            results[backend]["c_rss_kb"].append(stderr_value(stderr, "rss_kb_after"))
            vr = fv.value_references(read_md(fmu))
            script = ("time_load\n" + f"trace {trace} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
                      f"{','.join(str(vr[n]) for n in FORCES)}\nfree\n")
            stderr = c_host_run(host, fmu_dir, guid, script, environment)
            results[backend]["step_s"].append(stderr_value(stderr, "trace_seconds") / len(rows))
    load_after = os.getloadavg()

    def median(backend, key):
        return statistics.median(results[backend][key])

    kernel = statistics.median(kernels)
    print(f"medians of {args.repeats} runs, {len(rows)} steps per loop, {os.cpu_count()} cores, "
          f"load average {load_before[0]:.2f} before, {load_after[0]:.2f} after")
    print(f"{'figure':48s}{'native':>14s}{'pythonfmu':>14s}{'pythonfmu/native':>18s}")
    for label, key, scale, unit in (("load + instantiate + initialise, fresh Python", "startup_s", 1e3, "ms"),
                                    ("  same, C host (no Python for native)", "c_startup_s", 1e3, "ms"),
                                    ("resident memory added, fresh Python", "rss_growth_kb", 1e-3, "MB"),
                                    ("resident memory of the C host process", "c_rss_kb", 1e-3, "MB"),
                                    ("per step: setReal(12)+getReal(6)+doStep, C", "step_s", 1e6, "us")):
        a, b = median("native", key) * scale, median("pythonfmu", key) * scale
        print(f"{label + ' [' + unit + ']':48s}{a:14.3f}{b:14.3f}{b / a:18.2f}")
    step = median("native", "step_s")
    print(f"in-process kernels per step (evaluate + accept, numba loop): {kernel * 1e6:.3f} us; "
          f"native FMU / in-process = {step / kernel:.2f}")
    return 0


def read_md(fmu: Path):
    from fmpy import read_model_description

    return read_model_description(str(fmu))


if __name__ == "__main__":
    raise SystemExit(main())
