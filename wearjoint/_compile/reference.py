"""Write the compile notice's reference (:data:`wearjoint._compile.notice.REFERENCE_FILE`) on this machine.

``python -m wearjoint._compile.reference [ENGINE ...]`` runs each engine's command cold (an empty numba cache in a
temporary folder; the other caches as they are) with :data:`~wearjoint._compile.notice.PROFILE_ENV` set, and keeps
each compilation's own seconds: ``simulate-helped`` is ``wearjoint simulate`` on two cores (its second process
compiles the wear's kernels), ``simulate`` the same on one core, ``simulate-gear`` with ``--integrator gear`` on two
cores, ``cosim`` ``wearjoint cosim`` where the master's
library cannot be loaded, ``validate`` ``wearjoint validate --quick``, ``exudyn`` the README's exudyn example
(Linux: the runs are pinned to their cores).
The kernels compiled ahead of time (:data:`~wearjoint._compile.notice.AHEAD_OF_TIME`: ``fmu``, ``slider-crank-fmu``,
``master``) are each model's IR compiled afresh as a build without shipped IR does (two processes side by side on two
cores), and their wall seconds are kept too, as ``simulate-helped``'s (its command's: the compilations of its two
processes overlap; ``simulate-gear``'s likewise).  About ten minutes; run it on an idle machine after a large change to
the kernels (the bar scales the reference by the speed of the compilations it matches, so kernels added or renamed
since make its time left vaguer, not wrong).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .notice import AHEAD_OF_TIME, PROFILE_ENV, REFERENCE_FILE

RUN = ("--revolutions", "0.01", "--no-plots", "--out")
# the cosim command with the master's library unavailable: numba compiles the master's kernels
_COSIM_WITHOUT_LIBRARY = ("import sys; from wearjoint.cosim import native_master; native_master._failed = True; "
                          "from wearjoint.cli import main; sys.exit(main(sys.argv[1:]))")
# a model's IR compiled afresh (the build's own function, an empty numba cache), its wall seconds printed
_AHEAD_OF_TIME_BUILD = ("import sys, time; from pathlib import Path; from wearjoint.fmu.kernel_ir import "
                        "_compile_ir_fresh; out = Path(sys.argv[2]); out.mkdir(); start = time.perf_counter(); "
                        "_compile_ir_fresh(out, sys.argv[1], fresh=True); print(time.perf_counter() - start)")
# the README's exudyn example (a bar hung through a wearing joint), 10 ms: the joint's force, Jacobian and step kernels
_EXUDYN = ("import exudyn as exu; from exudyn.itemInterface import LoadMassProportional, MarkerBodyMass, "
           "NodeRigidBody2D, ObjectGround, ObjectRigidBody2D; from wearjoint import JointParameters; "
           "from wearjoint.exudyn import add_clearance_joint, simulation_settings, solve_dynamic; "
           "mbs = exu.SystemContainer().AddSystem(); bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=mbs.AddNode("
           "NodeRigidBody2D(referenceCoordinates=[0, -0.1001, 0])), mass=1.0, inertia=1e-3)); "
           "mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)), "
           "loadVector=[0, -9.81, 0])); handle = add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), bar, "
           "JointParameters(bushing_offset_m=(0.0, 0.1), wear_factor=100)); mbs.Assemble(); "
           "solve_dynamic(mbs, simulation_settings(0.01, 1e-5, [handle]))")
ENGINES = {
    "simulate-helped": ([sys.executable, "-m", "wearjoint", "simulate", *RUN], 2),
    "simulate": ([sys.executable, "-m", "wearjoint", "simulate", *RUN], 1),
    "simulate-gear": ([sys.executable, "-m", "wearjoint", "simulate", "--integrator", "gear", *RUN], 2),
    "cosim": ([sys.executable, "-c", _COSIM_WITHOUT_LIBRARY, "cosim", *RUN], 1),
    "cosim-me": ([sys.executable, "-m", "wearjoint", "cosim", "--fmu-interface", "model-exchange", *RUN], 1),
    "validate": ([sys.executable, "-m", "wearjoint", "validate", "--quick", "--out"], 1),
    "exudyn": ([sys.executable, "-c", _EXUDYN], 1),
    **{key: ([sys.executable, "-c", _AHEAD_OF_TIME_BUILD, model], 2) for key, model in AHEAD_OF_TIME.items()},
}


def profile_cold_run(command: list[str], cores: int) -> tuple[list[list], str, float]:
    """([[function, seconds], ...] of ``command``'s compilations from an empty numba cache, on ``cores`` cores;
    what it printed; its wall seconds)."""
    available = sorted(os.sched_getaffinity(0))
    if len(available) < cores:
        raise SystemExit(f"this machine offers {len(available)} core(s); the run needs {cores}")
    with tempfile.TemporaryDirectory(prefix="wearjoint_reference_") as tmp:
        profile = Path(tmp) / "compile.jsonl"
        env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(tmp) / "numba"), PROFILE_ENV: str(profile)}
        start = time.perf_counter()
        done = subprocess.run([*command, str(Path(tmp) / "out")], env=env, check=True, stdout=subprocess.PIPE,
                              text=True, preexec_fn=lambda: os.sched_setaffinity(0, available[:cores]))
        wall = time.perf_counter() - start
        rows = [json.loads(line) for line in profile.read_text().splitlines()]
    return [[name, round(seconds, 4)] for name, _, seconds in rows], done.stdout, wall


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wearjoint._compile.reference",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("engines", nargs="*", metavar="ENGINE", help=f"of {', '.join(ENGINES)} (default: all)")
    args = parser.parse_args(argv)
    unknown = [name for name in args.engines if name not in ENGINES]
    if unknown:
        parser.error(f"ENGINE={unknown[0]!r} is invalid: allowed one of {', '.join(ENGINES)}")
    old = json.loads(REFERENCE_FILE.read_text()) if REFERENCE_FILE.is_file() else {}
    runs, walls = dict(old.get("runs", {})), dict(old.get("walls", {}))
    for name in args.engines or ENGINES:
        command, cores = ENGINES[name]
        runs[name], printed, wall = profile_cold_run(command, cores)
        if name in AHEAD_OF_TIME:
            walls[name] = round(float(printed.split()[-1]), 2)
        elif cores > 1:     # two processes compiling side by side: their compilations' seconds add up to more
            walls[name] = round(wall, 2)
        seconds = walls.get(name, sum(s for _, s in runs[name]))
        print(f"{name}: {len(runs[name])} compilations, {seconds:.1f} s", flush=True)
    import numba

    machine = (f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, Python "
               f"{platform.python_version()}, numba {numba.__version__}")
    REFERENCE_FILE.write_text(json.dumps({
        "written": f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC by python -m "
                   f"wearjoint._compile.reference", "machine": machine, "runs": runs, "walls": walls}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
