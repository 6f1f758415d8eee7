"""Each binary of the multi-platform native FMU, measured in one run: linux64 natively, win64 under
wine, aarch64-linux under qemu-aarch64 (user-mode emulation), each driven by the C host of
tests/c_host built for its platform.

    python benchmarks/bench_platforms.py [--steps 20000] [--repeats 3]

Per binary: start-up (``time_load``: the host's main() to the return of exitInitializationMode:
loading the library, instantiate, initialise; for wine and qemu this includes the emulator's own
loading of the host's libraries, not the emulator's start) and the cost of one FMI 2.0
Co-Simulation step (setReal of the 12 inputs, getReal of the scalar outputs, doStep) over a worn
slider-crank trace, from the host's ``trace_seconds``.  Medians over ``--repeats`` runs; the
machine's load average is printed beside them.  The emulated figures say what the emulators cost
here, not what the FMU costs on a real Windows or ARM machine.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from fmi_host import (  # noqa: E402
    build_c_host, missing_platform_tool, run_c_host, start_script, stderr_value, trace_command, write_trace_file,
)
from kinematic_trace import slider_crank_trace  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.build import build_fmu  # noqa: E402

PLATFORMS = ("linux64", "win64", "aarch64-linux")
RUNNER = {"linux64": "native", "win64": "wine", "aarch64-linux": "qemu-aarch64"}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=20000, help="trace rows (default %(default)s)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per binary; medians printed (default %(default)s)")
    args = parser.parse_args(argv)
    if args.steps < 100 or args.repeats < 1:
        parser.error(f"--steps={args.steps} must be >= 100 and --repeats={args.repeats} >= 1")
    from fmpy import extract, read_model_description

    joint = paper_joint(wear_factor=100.0)
    with tempfile.TemporaryDirectory(prefix="bench_platforms_") as tmp:
        work = Path(tmp)
        fmu = build_fmu(work / "fmu", backend="native")
        md = read_model_description(str(fmu))
        folder = Path(extract(str(fmu), unzipdir=str(work / "unzipped")))
        vr = fv.value_references(md)
        trace = write_trace_file(work / "trace.txt", slider_crank_trace(joint, args.steps, 1e-5))
        script = start_script(2, vr, joint) + trace_command(vr, trace) + "free\n"
        print(f"load average before: {os.getloadavg()[0]:.2f}; {args.steps} steps of 10 us, medians of {args.repeats}")
        print(f"{'binary':<15} {'run by':<13} {'start-up [ms]':>14} {'per step [us]':>14} {'vs linux64':>11}")
        per_step = {}
        for platform in PLATFORMS:
            if not (folder / "binaries" / platform).is_dir():
                print(f"{platform:<15} not in the FMU (its cross toolchain is not installed)")
                continue
            missing = missing_platform_tool(platform)
            if missing:
                print(f"{platform:<15} skipped: {missing}")
                continue
            host = build_c_host(work / f"host_{platform}", platform=platform)
            startup, step = [], []
            for _ in range(args.repeats):
                code, out, err = run_c_host(host, folder, fv.MODEL_NAME, md.guid, "time_load\nfree\n", platform=platform)
                assert code == 0, err[-2000:]
                startup.append(stderr_value(err, "startup_seconds"))
                code, out, err = run_c_host(host, folder, fv.MODEL_NAME, md.guid, script, platform=platform)
                assert code == 0, err[-2000:]
                step.append(stderr_value(err, "trace_seconds") / args.steps)
            per_step[platform] = statistics.median(step)
            ratio = per_step[platform] / per_step["linux64"] if "linux64" in per_step else float("nan")
            print(f"{platform:<15} {RUNNER[platform]:<13} {1e3 * statistics.median(startup):>14.2f} "
                  f"{1e6 * per_step[platform]:>14.2f} {ratio:>10.1f}x")
        print(f"load average after: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
