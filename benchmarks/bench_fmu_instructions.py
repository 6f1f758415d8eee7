"""Instructions per step of the native FMU (callgrind): a speed figure that the machine's load does not change.

    python benchmarks/bench_fmu_instructions.py [--rows 20000] [--wear-factor 500] [--fmu A.fmu ...] [--repeats 3]
                                                [--json FILE]

Drives the native FMU (default: the cached build of this tree; ``--fmu`` for others, e.g. a build
of an older commit, compared in the same run) with the C host of tests/c_host over a kinematic
trace of the slider-crank with wear (every 10 us; with the default wear factor the bushing is about
0.06 mm deep at the end), under ``valgrind --tool=callgrind`` collecting only inside
fmi2GetReal + fmi2DoStep.  Prints instructions per step, the median of ``--repeats`` runs (the
count does not depend on the machine's load, printed beside it; the runs should agree), and the
functions that take most of them.  Two builds whose last outputs differ are reported (they should
be bit-identical).  ``--json FILE`` also writes the figures as JSON (benchmarks/performance_doc.py reads it).
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from fmi_host import CLEAN_ENV, build_c_host, write_trace_file  # noqa: E402
from kinematic_trace import slider_crank_trace  # noqa: E402
from repeats import Load, add_repeats_argument, median_text  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.parameters import PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.ensure import ensure_fmu  # noqa: E402

STEP_S = 1e-5
TOP_FUNCTIONS = 8


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=20000, help="trace rows (steps of 10 us)")
    parser.add_argument("--wear-factor", type=float, default=500.0,
                        help="wear acceleration of the trace (default %(default)s)")
    parser.add_argument("--fmu", action="append", default=None, help="FMU file (repeatable; default: this tree's)")
    add_repeats_argument(parser)
    parser.add_argument("--json", type=Path, default=None, help="also write the figures to this JSON file")
    args = parser.parse_args()
    if shutil.which("valgrind") is None:
        print("bench_fmu_instructions: error: valgrind is not installed", file=sys.stderr)
        return 2
    joint = paper_joint(wear_factor=args.wear_factor, wear_coefficient_m2_N=PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N)
    fmus = [Path(f) for f in args.fmu] if args.fmu else [ensure_fmu(joint.n_points, None, backend="native")]
    work = Path(tempfile.mkdtemp(prefix="bench_instructions_"))
    try:
        trace = write_trace_file(work / "trace.txt", slider_crank_trace(joint, args.rows, STEP_S))
        host = build_c_host(work / "host")
        last_outputs = {}
        figures = []
        for k, fmu in enumerate(fmus):
            load = Load()
            runs = [count(host, fmu, joint, trace, args.rows, work / f"fmu{k}_{r}") for r in range(args.repeats)]
            per_step = [run[0] for run in runs]
            _, top, last_outputs[fmu] = runs[-1]
            print(f"{fmu}: {median_text(per_step, ',.0f')} instructions per step (fmi2GetReal + fmi2DoStep), "
                  f"{args.rows} steps; {load.stop()}")
            for instructions, function in top:
                print(f"  {instructions / args.rows:9,.0f}  {function}")
            figures.append({"fmu": str(fmu), "instructions per step": statistics.median(per_step),
                            "instructions per step runs": per_step, "load": [load.before, load.after],
                            "top": [[instructions / args.rows, function] for instructions, function in top]})
        if len(set(last_outputs.values())) > 1:
            print("the builds' last outputs differ:", last_outputs)
        if args.json:
            args.json.write_text(json.dumps({"rows": args.rows, "wear_factor": args.wear_factor,
                                             "repeats": args.repeats, "fmus": figures,
                                             "outputs_differ": len(set(last_outputs.values())) > 1}, indent=1))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


def count(host: Path, fmu: Path, joint, trace: Path, rows: int, work: Path):
    """(instructions per step, [(instructions, function)] of the top functions, last output row)."""
    from fmpy import extract, read_model_description

    directory = Path(extract(str(fmu), unzipdir=str(work)))
    md = read_model_description(str(fmu))
    vr = fv.value_references(md)
    real_values, integer_values = fv.fmi_parameter_values_by_type(joint)
    # an older build may lack a parameter (or name it otherwise): it runs at that FMU's own default
    reals = " ".join(f"{vr[k]}={v!r}" for k, v in real_values.items() if k in vr)
    ints = " ".join(f"{vr[k]}={v}" for k, v in integer_values.items() if k in vr)
    script = work / "script.txt"
    script.write_text(f"instantiate joint\nsetup 0\nenter_init\nset_real {reals}\nset_integer {ints}\nexit_init\n"
                      f"trace {trace} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
                      f"{vr['normal_force']},{vr['penetration']}\nterminate\nfree\n")
    out = work / "callgrind.out"
    proc = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                           "--toggle-collect=fmi2DoStep", "--toggle-collect=fmi2GetReal", str(host), str(directory),
                           fv.MODEL_NAME, md.guid, str(script)], capture_output=True, text=True, env=CLEAN_ENV)
    collected = re.search(r"Collected : (\d+)", proc.stderr)
    if proc.returncode != 0 or collected is None:
        raise RuntimeError(f"the C host under callgrind failed:\n{proc.stderr[-2000:]}")
    annotated = subprocess.run(["callgrind_annotate", str(out)], capture_output=True, text=True).stdout
    top = [(int(m.group(1).replace(",", "")), re.sub(r"\[abi:[^]]*\]|\(.*$", "", m.group(2)))
           for m in re.finditer(r"^\s*([\d,]+) \([ \d.]+%\)\s+\S*?:(\S.*)$", annotated, flags=re.M)]
    last = [line for line in proc.stdout.splitlines() if line.startswith("out ")][-1]
    return int(collected.group(1)) / rows, top[:TOP_FUNCTIONS], last.split(maxsplit=2)[2]


if __name__ == "__main__":
    sys.exit(main())
