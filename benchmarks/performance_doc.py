"""Regenerate docs/performance.md from the benchmarks behind the README's "Performance" table.

    python benchmarks/performance_doc.py [--repeats 5] [--base REV] [--skip JOB,...]   # run, then render
    python benchmarks/performance_doc.py --quick                                       # smoke test, ~2 min
    python benchmarks/performance_doc.py --render-only                                 # render the json again

Two steps, each its own function:

1. **run**: every job below as a fresh process of this interpreter, in the repository; each job's raw
   figures, the command line that made them, the start date (UTC), the 1-minute load average before and
   after (``os.getloadavg``) and the commit go to ``benchmarks/results/performance.json`` (``--json``);
2. **render**: docs/performance.md (``--out``) from that json alone, so ``--render-only`` rewrites the page
   without running anything.

The jobs (``--skip`` takes their names):

* ``probes`` -- ``benchmarks/compare.py``'s probes of the main jobs (``main-job``, ``cosim-wear``,
  ``cosim-wear-starts``, ``cosim-wear-long``, ``cosim-groove``, ``monolithic-wear``, ``cosim``, ``monolithic``,
  ``cold``), each ``--repeats`` times in a fresh process (``compare.py --probe NAME``, after one untimed run that
  fills the caches); with ``--base REV`` instead
  ``compare.py --base REV --repeats N --json``, alternating with REV's tree, which adds a "working / REV" column;
* ``exudyn`` -- ``benchmarks/bench_exudyn_joint.py``: the joint in exudyn, microseconds per step;
* ``instructions`` -- ``benchmarks/bench_fmu_instructions.py`` at wear factors 500 and 10: callgrind's
  instructions per native FMU step (one run each: the count does not depend on the load);
* ``floor`` -- ``benchmarks/bench_floor.py``: where a step with wear goes and how fast the engines would run
  if parts of it cost nothing.

``--quick`` (a smoke test of this script, not figures to publish): one repeat, no warm-up runs, no
``cold`` and ``cosim-wear-long`` probes, exudyn over 0.02 s, 2000 trace rows under callgrind; the page it
renders says so at the top.  The machine has two cores: run the full regeneration on an otherwise idle one.
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
BENCHMARKS = REPO / "benchmarks"
DEFAULT_JSON = BENCHMARKS / "results" / "performance.json"
DEFAULT_OUT = REPO / "docs" / "performance.md"
ACCURACY_DIR = BENCHMARKS / "results" / "coupling_accuracy"   # python -m wearjoint.studies.coupling_accuracy --out
JOBS = ("probes", "exudyn", "instructions", "floor")
PROBES = ("main-job", "cosim-wear", "cosim-wear-starts", "cosim-wear-long", "cosim-groove", "monolithic-wear", "cosim",
          "monolithic", "cold")
QUICK_SKIPPED_PROBES = ("cosim-wear-long", "cold")
PROBE_TITLES = {
    "main-job": "the README's first command, warm: `wearjoint cosim --revolutions 1 --out DIR`: wall seconds",
    "cosim-wear": "`wearjoint cosim` with wear: the default master, native FMU, 0.2 s after 0.01 s",
    "cosim-wear-starts": "the same 0.2 s from 8 crank angles spread over a turn: the ensemble's real-time factor "
                         "(one start's 0.2 s may be impacts, another's lasting contact)",
    "cosim-wear-long": "the same over four revolutions (1.6 s: the groove worn in)",
    "cosim-groove": "at equal accuracy on a groove 5.7 clearances deep (0.15 s after 0.01 s; the base at the step its "
                    "ensembles need there, 1.25 µs: compare.py's docstring)",
    "monolithic-wear": "`wearjoint simulate --revolutions 2` with wear (DOPRI)",
    "cosim": "co-simulation without wear (0.2 s after 0.01 s)",
    "monolithic": "monolithic DOPRI, 5 revolutions, no wear",
    "cold": "first runs from empty numba and FMU caches: wall seconds",
}
EXUDYN_CASES = ("ideal revolute", "1 joint, exact Jacobian", "2 joints, exact Jacobian")
SCRIPT_TIMEOUT_S = 3 * 3600


# ------------------------------------------------------------------ run
def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def _git(*args: str) -> str:
    done = subprocess.run(["git", "-C", str(REPO), *args], capture_output=True, text=True)
    return done.stdout.strip() if done.returncode == 0 else ""


def commit() -> str:
    """The short commit, with ``+dirty`` when the code the benchmarks run differs from it."""
    short = _git("rev-parse", "--short", "HEAD") or "unknown"
    changed = _git("status", "--porcelain", "--", "wearjoint", "fmu_src", "validation", "benchmarks", "pyproject.toml",
                   ":(exclude)benchmarks/results")     # the figures it writes are not code
    return short + ("+dirty" if changed else "")


def machine() -> dict:
    model = ""
    try:
        model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                      if line.startswith("model name")), "")
    except OSError:
        pass
    versions = {}
    for module in ("numba", "fmpy", "exudyn"):
        done = subprocess.run([sys.executable, "-c", f"import {module}; print({module}.__version__)"],
                              capture_output=True, text=True, cwd=REPO)
        versions[module] = done.stdout.strip() if done.returncode == 0 else None
    return {"cpus": os.cpu_count(), "cpu_model": model or platform.processor(), "python": platform.python_version(),
            **versions}


def display(argv: list[str]) -> str:
    """A command line as the reader types it (``python`` and the script relative to the repository), without ``--json``."""
    words = ["python", *(str(Path(a).relative_to(REPO)) if a.startswith(str(REPO)) else a for a in argv)]
    if "--json" in words:
        k = words.index("--json")
        del words[k:k + 2]
    return " ".join(words)


def run_script(argv: list[str]) -> tuple[dict, subprocess.CompletedProcess]:
    """One benchmark process: (its command, date, commit, loads and, on failure, the tail of its output; the process)."""
    record = {"command": display(argv), "date": _now(), "commit": commit(), "load": [_load(), None]}
    done = subprocess.run([sys.executable, *argv], cwd=REPO, capture_output=True, text=True, timeout=SCRIPT_TIMEOUT_S)
    record["load"][1] = _load()
    if done.returncode != 0:
        record["error"] = (done.stderr or done.stdout)[-2000:]
    return record, done


def run_probes(probes, repeats: int, warm: bool) -> list[dict]:
    """Each probe ``repeats`` times, each run a fresh ``compare.py --probe`` process."""
    rows = []
    for probe in probes:
        argv = [str(BENCHMARKS / "compare.py"), "--probe", probe]
        if warm and probe != "cold":
            run_script(argv)                                # builds the FMU, fills the numba caches
        runs, row = [], None
        for _ in range(repeats):
            record, done = run_script(argv)
            if row is None:
                row = {**record, "job": "probes", "probe": probe, "repeats": repeats, "loads": []}
            row["loads"].append(record["load"])
            if "error" in record:
                row["error"] = record["error"]
                break
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
        row["load"] = [row["loads"][0][0], row["loads"][-1][1]]
        row["figures"] = {name: {"median": statistics.median(r[name] for r in runs), "runs": [r[name] for r in runs]}
                          for name in (runs[0] if runs else {})}
        rows.append(row)
        medians = ", ".join(f"{name} {figure['median']:.4g}" for name, figure in row["figures"].items())
        print(f"  {probe}: {medians or row.get('error')}", flush=True)
    return rows


def run_probes_paired(probes, repeats: int, base: str) -> list[dict]:
    """``compare.py --base REV``: the probes alternately with REV's tree."""
    with tempfile.TemporaryDirectory(prefix="performance_doc_") as tmp:
        out = Path(tmp) / "compare.json"
        argv = [str(BENCHMARKS / "compare.py"), "--base", base, "--probes", ",".join(probes), "--repeats", str(repeats),
                "--json", str(out)]
        record, _ = run_script(argv)
        result = json.loads(out.read_text()) if out.is_file() else {"probes": {}}
    rows = []
    for probe in probes:
        found = result["probes"].get(probe)
        row = {**record, "job": "probes", "probe": probe, "repeats": repeats, "base": base,
               "base_commit": result.get("base_commit")}
        if found is None:
            row.setdefault("error", "compare.py wrote no figures for this probe")
            row["figures"] = {}
        else:
            row["loads"] = found["loads"]
            row["load"] = [found["loads"][0][0], found["loads"][-1][1]]
            row["figures"] = {name: {"median": f["work"], "runs": f["work runs"], "base": f["base"],
                                     "base runs": f["base runs"]} for name, f in found["figures"].items()}
        rows.append(row)
    return rows


def run_json_script(job: str, script: str, options: list[str]) -> dict:
    with tempfile.TemporaryDirectory(prefix="performance_doc_") as tmp:
        out = Path(tmp) / f"{job}.json"
        record, _ = run_script([str(BENCHMARKS / script), *options, "--json", str(out)])
        record["figures"] = json.loads(out.read_text()) if out.is_file() else None
    record["job"] = job
    print(f"  {record['command']}: {'ok' if 'error' not in record else 'failed'}", flush=True)
    return record


def run_all(args) -> dict:
    quick = args.quick
    repeats = 1 if quick else args.repeats
    skip = set(args.skip)
    rows = []
    if "probes" not in skip:
        probes = [p for p in PROBES if not (quick and p in QUICK_SKIPPED_PROBES)]
        print(f"probes ({repeats} repeat{'s' if repeats > 1 else ''} each):", flush=True)
        rows += run_probes_paired(probes, repeats, args.base) if args.base else run_probes(probes, repeats, not quick)
    if "exudyn" not in skip:
        rows.append(run_json_script("exudyn", "bench_exudyn_joint.py",
                                    ["--repeats", str(repeats)] + (["--end-time", "0.02"] if quick else [])))
    if "instructions" not in skip:
        for factor in ("500", "10"):
            rows.append(run_json_script("instructions", "bench_fmu_instructions.py",
                                        ["--wear-factor", factor, "--repeats", "1"] + (["--rows", "2000"] if quick else [])))
    if "floor" not in skip:
        options = ["--repeats", str(repeats)]
        paired = {r["probe"]: r for r in rows if r.get("job") == "probes" and r.get("base")}
        for probe, option in (("cosim-wear", "--paired-cosim"), ("monolithic-wear", "--paired-simulate")):
            figure = paired.get(probe, {}).get("figures", {}).get("real-time factor")
            if figure and figure.get("base"):
                options += [option, f"{figure['median'] / figure['base']:.4g}"]
        rows.append(run_json_script("floor", "bench_floor.py", options))
    return {"generated": _now(), "commit": commit(), "machine": machine(),
            "options": {"quick": quick, "repeats": repeats, "base": args.base, "skipped": sorted(skip)}, "rows": rows}


# ------------------------------------------------------------------ render
def _num(value, digits: int = 3) -> str:
    """3 significant digits; from 1000 on, whole numbers with thin groups (9 331, 88 200)."""
    if value is None:
        return "–"
    if abs(value) >= 1000:
        rounded = float(f"{value:.{max(digits, len(str(int(abs(value)))) - 1)}g}") if not float(value).is_integer() \
            else value
        return f"{rounded:,.0f}".replace(",", " ")
    return f"{value:.{digits}g}"


def _runs(values) -> str:
    return "" if len(values) < 2 else f" ({', '.join(_num(v) for v in values)})"


def _load_text(load) -> str:
    return f"{load[0]:.2f}→{load[1]:.2f}" if load and load[1] is not None else "–"


def _last_line(row, width: int = 80) -> str:
    text = (row.get("error") or "no figures").strip().splitlines() or ["no output"]
    return text[-1][:width].replace("|", "/")


def _meta(row) -> str:
    return f"{row['date'][:10]} | {_load_text(row.get('load'))} | `{row['commit']}`"


def _meta_text(row) -> str:
    """:func:`_meta` as a sentence's parenthesis: date, load ..., commit ..."""
    return f"{row['date'][:10]}, load {_load_text(row.get('load'))}, commit `{row['commit']}`"


def render_probes(rows) -> list[str]:
    if not rows:
        return []
    paired = rows[0].get("base")
    head = "| run | figure | median (each run) |" + (f" working / {paired} |" if paired else "") + \
        " command | date | load | commit |"
    lines = ["## The main jobs", "",
             "`benchmarks/compare.py`'s probes: each run a fresh process of the working tree, the figure the median of "
             "the runs" + (f", alternating with {paired}'s tree (`{rows[0].get('base_commit', '')[:7]}`)." if paired
                          else "."), "",
             head, "|---|---|---|" + ("---|" if paired else "") + "---|---|---|---|"]
    for row in rows:
        title = PROBE_TITLES.get(row["probe"], row["probe"])
        if row.get("error") or not row["figures"]:
            lines.append(f"| {title} | failed: {_last_line(row)} |" + (" |" if paired else "")
                         + f" `{row['command']}` | {_meta(row)} |")
            continue
        for k, (name, figure) in enumerate(row["figures"].items()):
            ratio = ""
            if paired:
                ratio = f" {figure['median'] / figure['base']:.3f} |" if figure.get("base") else " – |"
            lines.append(f"| {title if k == 0 else ''} | {name} | **{_num(figure['median'])}**{_runs(figure['runs'])} |"
                         f"{ratio} {'`' + row['command'] + '`' if k == 0 else ''} | {_meta(row) if k == 0 else ' | |'} |")
    return lines + [""]


def render_exudyn(rows) -> list[str]:
    lines = []
    for row in rows:
        lines += ["## The joint in exudyn", "",
                  "Bars swinging in the joint (`wearjoint.exudyn.add_clearance_joint`), generalized-α at 10 µs with "
                  "wear; microseconds per step, the median of the runs.", "",
                  f"Command: `{row['command']}` ({_meta_text(row)})",
                  ""]
        if row.get("error") or not row.get("figures"):
            lines += [f"Failed: {_last_line(row, 200)}", ""]
            continue
        fig = row["figures"]
        lines += ["| case | µs per step (each run) | over the ideal joint | Newton iterations / step | Jacobians / step |",
                  "|---|---|---|---|---|"]
        for case in fig["cases"]:
            bold = case["case"] in EXUDYN_CASES[1:]
            value = f"**{case['us per step']:.1f}**" if bold else f"{case['us per step']:.1f}"
            lines.append(f"| {case['case']} | {value}{_runs(case['us per step runs'])} | {case['us over ideal']:.1f} | "
                         f"{case['Newton iterations per step']:.3f} | {case['Jacobians per step']:.4f} |")
        lines += ["", f"The kernels alone (a numba loop): `evaluate_contact` {fig['evaluate_contact_us']:.2f} µs, "
                      f"`contact_jacobian` {fig['contact_jacobian_us']:.2f} µs per evaluation.", ""]
    return lines


def render_instructions(rows) -> list[str]:
    if not rows:
        return []
    lines = ["## Instructions per native FMU step", "",
             "callgrind inside `fmi2GetReal` + `fmi2DoStep` of the native joint FMU driven by the C host over a "
             "kinematic trace of the worn slider–crank (steps of 10 µs, the calibrated k_w): a count the load does "
             "not change.", "",
             "| wear factor | trace rows | instructions per step | the largest shares | command | date | load | commit |",
             "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        fig = row.get("figures")
        if row.get("error") or not fig:
            lines.append(f"| | | failed | | `{row['command']}` | {_meta(row)} |")
            continue
        for fmu in fig["fmus"]:
            top = "; ".join(f"{_num(n)} `{name.strip().split('::')[-1]}`" for n, name in fmu["top"][:3])
            lines.append(f"| {fig['wear_factor']:g} | {fig['rows']} | **{_num(fmu['instructions per step'])}** | {top} | "
                         f"`{row['command']}` | {_meta(row)} |")
    return lines + [""]


def render_floor(rows) -> list[str]:
    lines = []
    for row in rows:
        lines += ["## Where a step with wear goes: the floors", "",
                  f"Command: `{row['command']}` ({_meta_text(row)}); "
                  "medians of its runs.", ""]
        fig = row.get("figures")
        if row.get("error") or not fig:
            lines += [f"Failed: {_last_line(row, 200)}", ""]
            continue
        c, cu, s, su = fig["cosim"], fig["cosim without wear"], fig["simulate"], fig["simulate without wear"]
        lines += ["| main job with wear | steps (without wear) | µs per step (without wear) | real-time factor "
                  "(without wear) | floor: real-time factor if … |", "|---|---|---|---|---|",
                  f"| `cosim`, 0.2 s after 0.01 s | {_num(c['communication steps'])} communication steps "
                  f"({_num(cu['communication steps'])}) | FMI {c['FMI us per step']:.2f} ({cu['FMI us per step']:.2f}), "
                  f"RK4 {c['mechanism us per step']:.2f}, bookkeeping {c['bookkeeping us per step']:.2f} | "
                  f"{c['real-time factor']:.3g} ({cu['real-time factor']:.3g}) | the FMI calls cost nothing: "
                  f"**{c['real-time factor with the FMI calls free']:.3g}** |",
                  f"| `simulate --revolutions 2` | {_num(s['attempted steps'])} attempted DOPRI steps "
                  f"({_num(su['attempted steps'])}) | {s['us per step']:.2f} ({su['us per step']:.2f}) | "
                  f"{s['real-time factor']:.3g} ({su['real-time factor']:.3g}) | every step at the no-wear cost: "
                  f"**{s['real-time factor, each step at the no-wear cost']:.3g}** |", ""]
    return lines


def render_accuracy(folder: Path = ACCURACY_DIR) -> list[str]:
    """The co-simulation's ensembles against monolithic RK4 (wearjoint.studies.coupling_accuracy's table), where
    its files are in ``folder``: not run by this script (about 10 minutes per configuration)."""
    results, run = folder / "coupling_accuracy.json", folder / "coupling_accuracy_run.json"
    if not results.is_file() or not run.is_file():
        return []
    from wearjoint.studies.coupling_accuracy import table

    meta = json.loads(run.read_text())
    command = " ".join(["python -m wearjoint.studies.coupling_accuracy", *meta["options"]])
    commit_of = _git("log", "-1", "--format=%h", "--", str(results.relative_to(REPO)))
    committed = f"its files last committed in `{commit_of}`" if commit_of else "its files not committed yet"
    return ["## The co-simulation's answers against the monolithic engine", "",
            "Ensembles of 8 starts spread over a turn (6 revolutions, the first 2 dropped): each configuration's mean "
            "± standard error per statistic and its difference from monolithic RK4 at 2.5 µs in combined standard "
            "errors (z; |z| ≤ 2: inside the monolithic scatter) and in per cent of its mean; the cases and the "
            "statistics: [cosim_study.md](explanation/cosim_study.md#ensembles-on-worn-grooves) (a joint where the "
            "default is 12 % off: [its fifth case](explanation/cosim_study.md#a-pin-that-whirls-joint-j-tight-joint-"
            "where-the-default-is-12--off)). The speed at that accuracy: "
            "each configuration's real-time factor (the ensemble's simulated time over its simulations' wall time, "
            "loading excluded; one run of the study, on an otherwise idle machine) and its communication steps per "
            "revolution.", "",
            f"Command: `{command}` ({meta.get('started', '?')} to {meta.get('finished', 'unfinished')}, "
            f"{committed}; not run by this script)", "", table(json.loads(results.read_text())), ""]


def render(data: dict) -> str:
    rows = data["rows"]
    options = data["options"]
    m = data["machine"]
    lines = ["# Performance", "",
             "<!-- generated by benchmarks/performance_doc.py from benchmarks/results/performance.json: "
             "edit the script, not this page -->", ""]
    if options["quick"]:
        lines += ["> **Placeholder figures**: a `--quick` smoke run of the generator (one repeat, short jobs, no "
                  "cold-start and four-revolution probes). Not figures to quote: regenerate with "
                  "`python benchmarks/performance_doc.py` on an idle machine.", ""]
    lines += [f"Regenerate: `python benchmarks/performance_doc.py"
              f"{' --base ' + options['base'] if options['base'] else ''}` (runs every benchmark below, writes "
              "`benchmarks/results/performance.json`, renders this page); "
              "`python benchmarks/performance_doc.py --render-only` renders it again from the json.",
              f"Machine: {m.get('cpus')} CPUs ({m.get('cpu_model') or 'unknown CPU'}), Python {m.get('python')}, "
              f"numba {m.get('numba')}, fmpy {m.get('fmpy')}, exudyn {m.get('exudyn')}; generated {data['generated']} "
              f"at `{data['commit']}`. Each table row names the command that made it, its date, the 1-minute load "
              "average before → after it and the commit it ran (`+dirty`: with uncommitted changes to the code). "
              "Medians of repeated runs; this virtual machine's speed varies between runs by up to 2×, so read "
              "ratios taken in one run, not figures from different runs.", "",
              "Which engine, step and master to pick, and what they cost: "
              "[how-to: pick a step and a master](how-to/choose_step_and_master.md); "
              "how the speed came about: [CHANGELOG](../CHANGELOG.md).", ""]
    lines += render_probes([r for r in rows if r.get("job") == "probes"])
    lines += render_accuracy()
    lines += render_exudyn([r for r in rows if r.get("job") == "exudyn"])
    lines += render_instructions([r for r in rows if r.get("job") == "instructions"])
    lines += render_floor([r for r in rows if r.get("job") == "floor"])
    if options.get("skipped"):
        lines += [f"Not run this time: {', '.join(options['skipped'])} (`--skip`).", ""]
    return "\n".join(lines).rstrip() + "\n"


# ------------------------------------------------------------------ driver
def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs per figure (default %(default)s; --quick: 1)")
    parser.add_argument("--base", default=None, help="pair the probes with this revision's tree (compare.py --base)")
    parser.add_argument("--quick", action="store_true", help="smoke test: 1 repeat, short jobs (not figures to quote)")
    parser.add_argument("--skip", type=lambda s: [j for j in s.split(",") if j], default=[],
                        help=f"comma-separated jobs not to run, of {', '.join(JOBS)}")
    parser.add_argument("--render-only", action="store_true", help="only render --out from --json")
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON, help="raw figures (default %(default)s)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="the page (default %(default)s)")
    args = parser.parse_args(argv)
    if args.repeats < 1 or not set(args.skip) <= set(JOBS):
        parser.error(f"--repeats >= 1; --skip of {', '.join(JOBS)}")
    if not args.render_only:
        data = run_all(args)
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(data, indent=1) + "\n")
        print(f"wrote {args.json}")
    if not args.json.is_file():
        parser.error(f"{args.json} does not exist: run without --render-only first")
    text = render(json.loads(args.json.read_text()))
    args.out.write_text(text)
    print(f"wrote {args.out} ({text.count(chr(10))} lines)")
    failed = [r.get("command") for r in json.loads(args.json.read_text())["rows"] if r.get("error")]
    if failed:
        print("failed: " + "; ".join(failed), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
