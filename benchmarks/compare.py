"""The README's headline speed figures of a base revision and of the working tree, run alternately.

    python benchmarks/compare.py --base REV [--repeats 3] [--probes cosim-wear,monolithic-wear,cosim,...] [--keep DIR]
                                 [--json FILE]

Run it by hand before figures are published (it takes minutes; not in CI).  REV's tree
(``git archive``: the repository itself is left alone) goes into a temporary folder with a venv
that sees this interpreter's packages (``--system-site-packages``) and ``pip install --no-deps -e``
of that tree: the dependencies are the same, the package is REV's; the working tree gets a venv of
its own the same way (whichever tree this interpreter has installed).  Each probe runs in a fresh
process of either interpreter, base and working tree alternately (``--repeats`` pairs, after one
untimed run of each that builds the FMU and fills the numba caches), through API both trees have:

* ``cosim-wear`` -- the README's first command's engine (``wearjoint cosim``: the paper's joint, which
  wears): its default master, 0.2 s after 0.01 s, native FMU: real-time factor, communication steps (they follow the
  chaotic trajectory: a last-digit change in the mechanism moves them by several per cent), wall and FMI
  time per step; ``cosim-wear-long``: the same over four revolutions (1.6 s: the groove worn in, where a long
  study spends its time; the step count over 0.2 s swings by 2x with the trajectory); ``cosim-wear-starts``: the
  same 0.2 s from :data:`STARTS` initial crank angles spread over a turn, the ensemble's real-time factor (their
  simulated time over their wall time: one start's trajectory may spend its 0.2 s in impacts, another in lasting
  contact, whose costs per simulated second differ several-fold), steps and wall time per step; ``cosim``: the same
  without wear (``benchmarks/bench_cosim.py``'s run);
* ``monolithic-wear`` -- ``wearjoint simulate --revolutions 2``'s engine (DOPRI default, with wear):
  real-time factor, accepted steps; ``monolithic``: 5 revolutions without wear;
* ``main-job`` -- the README's first command after its first run (warm caches): wall seconds of ``wearjoint cosim
  --revolutions 1 --out DIR`` as a fresh process, with its figures and without (``--no-plots``);
* ``cold`` -- ``wearjoint simulate --revolutions 0.05``, ``wearjoint build-fmu`` and ``wearjoint cosim
  --revolutions 0.02`` (the FMU and the master), each from empty numba and FMU caches: wall seconds
  (several minutes per pair; not run by default);
* ``export-ssp`` -- ``wearjoint export-ssp --platforms linux64 --out DIR`` as a fresh process after an earlier run
  (warm caches): wall seconds with the same parameters as that run, and with a crank speed no run has built yet
  (new start values: the FMUs' kernels unchanged);
* ``cosim-groove`` -- the co-simulation at equal accuracy where the coupling sets the steps: the case ``groove`` of
  ``wearjoint.studies.coupling_accuracy`` (a slider-crank whose bushing holds a conforming groove 5.7 clearances
  deep, no further wear; its mechanism, joint and profile in ``benchmarks/data/groove_case.npz``, written by
  ``--write-groove-case``), 0.15 s after 0.01 s, each tree in the configuration whose 8-start ensembles sit within 2
  standard errors of monolithic RK4 there: a tree with the error-controlled coupling its default, one without (no
  ``CoSimulationOptions.coupling_tolerance``: 674f94f) its adaptive scheme at :data:`GROOVE_UNCONTROLLED_STEP_S`.

Prints each figure's median per tree, working / base, and the 1-minute load before and after
each pair (2 shared cores: compare ratios taken at similar loads); ``--json FILE`` also writes them as JSON
(benchmarks/performance_doc.py reads it).  ``--probe NAME`` runs one probe in this process and prints its
figures as one JSON line.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PROBES = ("main-job", "cosim-wear", "cosim-wear-starts", "cosim-wear-long", "monolithic-wear", "cosim", "monolithic",
          "cold", "cosim-groove", "export-ssp")
# cosim-wear-starts: this many starts, the initial crank angle spread over a turn (the accuracy ensembles' spread)
STARTS = 8
GROOVE_CASE = REPO / "benchmarks" / "data" / "groove_case.npz"
# the adaptive scheme's contact step on the groove at the ensembles' accuracy (coupling_accuracy --cases groove
# --no-default --cosim-steps 5e-6 2.5e-6 1.25e-6: impacts z +2.4 at 5 us, the largest force +2.5 at 2.5 us, every |z|
# <= 1.3 at 1.25 us)
GROOVE_UNCONTROLLED_STEP_S = 1.25e-6
DEFAULT_PROBES = ("cosim-wear", "monolithic-wear", "cosim", "monolithic")


# ------------------------------------------------------------------ probes (run by either interpreter)
def probe_cosim(wear: bool = False, duration: float = 0.2) -> dict:
    import numpy as np

    from wearjoint.core import layout as L
    from wearjoint.cosim import CoSimulation, CoSimulationOptions
    from wearjoint.parameters import paper_joint

    warm_up = 0.01
    options = CoSimulationOptions(revolutions=(warm_up + duration) / 0.4 + 0.1)
    samples = np.zeros((int((warm_up + duration) / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    with CoSimulation(paper_joint() if wear else paper_joint(wear_factor=0.0), None, options) as sim:
        sim.advance_to(warm_up, samples)
        steps, fmi = sim.communication_steps, sim.fmi_time_s
        t0 = time.perf_counter()
        sim.advance_to(warm_up + duration, samples)
        wall = time.perf_counter() - t0
        steps = sim.communication_steps - steps
        return {"real-time factor": duration / wall, "communication steps": steps,
                "wall us per step": 1e6 * wall / steps, "FMI us per step": 1e6 * (sim.fmi_time_s - fmi) / steps}


def probe_cosim_wear_starts(warm_up: float = 0.01, duration: float = 0.2) -> dict:
    import dataclasses

    import numpy as np

    from wearjoint.core import layout as L
    from wearjoint.cosim import CoSimulation, CoSimulationOptions
    from wearjoint.parameters import SliderCrankParameters, paper_joint

    options = CoSimulationOptions(revolutions=(warm_up + duration) / 0.4 + 0.1)
    samples = np.zeros((int((warm_up + duration) / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    wall, steps = 0.0, 0
    for k in range(STARTS):
        mechanism = dataclasses.replace(SliderCrankParameters(), initial_crank_angle_deg=360.0 * k / STARTS)
        with CoSimulation(paper_joint(), mechanism, options) as sim:
            sim.advance_to(warm_up, samples)
            before = sim.communication_steps
            t0 = time.perf_counter()
            sim.advance_to(warm_up + duration, samples)
            wall += time.perf_counter() - t0
            steps += sim.communication_steps - before
    return {"real-time factor": STARTS * duration / wall, "communication steps": steps,
            "wall us per step": 1e6 * wall / steps}


def probe_monolithic(wear: bool = False) -> dict:
    from wearjoint.parameters import paper_joint
    from wearjoint.simulate import SimulationOptions, run_simulation

    joint, revolutions = (paper_joint(), 2.0) if wear else (paper_joint(wear_factor=0.0), 5.0)
    summary = run_simulation(joint, options=SimulationOptions(revolutions=revolutions), progress=False).summary()
    return {"real-time factor": summary["realtime_factor"], "accepted steps": summary["integrator_accepted_steps"]}


def probe_cosim_wear() -> dict:
    return probe_cosim(wear=True)


def probe_cosim_wear_long() -> dict:
    return probe_cosim(wear=True, duration=4 * 0.4)


def probe_monolithic_wear() -> dict:
    return probe_monolithic(wear=True)


def probe_main_job() -> dict:
    """Wall seconds of the README's first command (warm: the caller ran it once), with and without figures."""
    figures = {}
    for name, extra in (("main job s", []), ("main job without figures s", ["--no-plots"])):
        with tempfile.TemporaryDirectory(prefix="compare_main_") as tmp:
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "wearjoint", "cosim", "--revolutions", "1", "--out", f"{tmp}/out",
                            *extra], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            figures[name] = time.perf_counter() - t0
    return figures


def probe_export_ssp() -> dict:
    """Wall seconds of ``export-ssp`` for linux64 (warm: the caller ran it once), again and with new start values."""
    figures = {}
    new_speed = f"{1000.0 + (time.time_ns() // 1000) % 10**9 * 1e-9:.9f}"     # a crank speed [rpm] no run has built
    for name, extra in (("export-ssp again s", []), ("export-ssp new parameters s", ["--crank-speed-rpm", new_speed])):
        with tempfile.TemporaryDirectory(prefix="compare_ssp_") as tmp:
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "wearjoint", "export-ssp", "--platforms", "linux64", "--out",
                            f"{tmp}/out", *extra], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            figures[name] = time.perf_counter() - t0
    return figures


def write_groove_case(path: Path = GROOVE_CASE) -> None:
    """The groove case's mechanism and joint changes (JSON) and its initial profile, from the working tree's study."""
    import numpy as np

    from wearjoint.studies import coupling_accuracy as study

    profile = study.case_setup("groove", 0.0)[2]
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, profile_m=profile, mechanism=json.dumps(study.GROOVE_MECHANISM), joint=json.dumps(study.GROOVE_JOINT))


def probe_cosim_groove(warm_up: float = 0.01, duration: float = 0.15) -> dict:
    import dataclasses

    import numpy as np

    from wearjoint.core import layout as L
    from wearjoint.cosim import CoSimulation, CoSimulationOptions
    from wearjoint.parameters import SliderCrankParameters, paper_joint

    case = np.load(GROOVE_CASE)
    mechanism = SliderCrankParameters(**json.loads(str(case["mechanism"])))
    joint = paper_joint(mechanism, wear_factor=0.0, **json.loads(str(case["joint"])))
    controlled = "coupling_tolerance" in {f.name for f in dataclasses.fields(CoSimulationOptions)}
    options = CoSimulationOptions(revolutions=(warm_up + duration) / mechanism.period_s + 0.1,
                                  **({} if controlled else {"scheme": "adaptive", "step_s": GROOVE_UNCONTROLLED_STEP_S}))
    samples = np.zeros((int((warm_up + duration) / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    with CoSimulation(joint, mechanism, options, initial_profile_m=case["profile_m"]) as sim:
        sim.advance_to(warm_up, samples)
        steps = sim.communication_steps
        t0 = time.perf_counter()
        sim.advance_to(warm_up + duration, samples)
        wall = time.perf_counter() - t0
        steps = sim.communication_steps - steps
    return {"real-time factor": duration / wall, "communication steps": steps, "wall us per step": 1e6 * wall / steps}


def probe_cold() -> dict:
    """Wall seconds of the two commands, each in a fresh process with empty numba and FMU caches."""
    figures = {}
    commands = {"cold simulate s": ["simulate", "--revolutions", "0.05", "--no-plots", "--quiet"],
                "cold build-fmu s": ["build-fmu"],
                "cold cosim s": ["cosim", "--revolutions", "0.02", "--no-plots", "--quiet"]}
    for name, command in commands.items():
        with tempfile.TemporaryDirectory(prefix="compare_cold_") as tmp:
            env = {**os.environ, "NUMBA_CACHE_DIR": f"{tmp}/numba", "XDG_CACHE_HOME": f"{tmp}/cache"}
            out = ["--out", f"{tmp}/out"]
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "wearjoint", *command, *out], env=env, check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            figures[name] = time.perf_counter() - t0
    return figures


# ------------------------------------------------------------------ the driver
def tree_interpreter(tree: Path, venv: Path) -> Path:
    """A venv whose ``wearjoint`` is ``tree``'s (whatever this interpreter has installed)."""
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--no-deps", "-e", str(tree)], check=True)
    found = subprocess.run([str(python), "-c", "import wearjoint; print(wearjoint.__file__)"], check=True,
                           capture_output=True, text=True, cwd=tempfile.gettempdir()).stdout.strip()
    if not Path(found).is_relative_to(tree):
        raise RuntimeError(f"the venv {venv} imports wearjoint from {found}, not from {tree}")
    return python


def base_tree(rev: str, tree: Path) -> Path:
    """REV's files in ``tree``."""
    tree.mkdir(parents=True)
    archive = subprocess.run(["git", "-C", str(REPO), "archive", rev], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
    return tree


def run_probe(python, probe: str) -> dict:
    """One probe in a fresh process of ``python``: its figures."""
    done = subprocess.run([str(python), __file__, "--probe", probe], capture_output=True, text=True,
                          cwd=tempfile.gettempdir())
    if done.returncode != 0:
        raise RuntimeError(f"probe {probe} with {python} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def compare(base_python, work_python, probes, repeats: int) -> dict:
    """Runs the probes alternately and prints them; returns {probe: {"loads": [[before, after]...],
    "figures": {figure: {"base": median, "work": median, "base runs": [...], "work runs": [...]}}}}."""
    trees = {"base": base_python, "work": work_python}
    results = {}
    for probe in probes:
        if probe != "cold":
            for python in trees.values():     # builds the FMU, fills the numba caches
                run_probe(python, probe)
        runs = {name: [] for name in trees}
        loads = []
        for _ in range(repeats):
            load = os.getloadavg()[0]
            for name, python in trees.items():
                runs[name].append(run_probe(python, probe))
            loads.append((load, os.getloadavg()[0]))
        results[probe] = {"loads": loads, "figures": {}}
        print(f"{probe}: {repeats} alternating pairs, load per pair "
              f"{', '.join(f'{a:.2f}->{b:.2f}' for a, b in loads)} ({os.cpu_count()} CPUs)")
        print(f"  {'figure':24s} {'base':>12s} {'work':>12s} {'work/base':>10s}   work runs")
        for figure in runs["work"][0]:
            base = statistics.median(r[figure] for r in runs["base"])
            work = statistics.median(r[figure] for r in runs["work"])
            each = " ".join(f"{r[figure]:.4g}" for r in runs["work"])
            print(f"  {figure:24s} {base:12.4g} {work:12.4g} {work / base:10.3f}   {each}", flush=True)
            results[probe]["figures"][figure] = {"base": base, "work": work,
                                                 "base runs": [r[figure] for r in runs["base"]],
                                                 "work runs": [r[figure] for r in runs["work"]]}
    return results


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", help="revision to compare with (a commit, tag or branch)")
    parser.add_argument("--repeats", type=int, default=3, help="alternating pairs per probe (default 3)")
    parser.add_argument("--probes", default=",".join(DEFAULT_PROBES),
                        help=f"comma-separated, of {', '.join(PROBES)} (default %(default)s)")
    parser.add_argument("--keep", type=Path, default=None, help="build the base in DIR and keep it (default: a "
                                                                 "temporary folder, removed)")
    parser.add_argument("--json", type=Path, default=None, help="also write the medians to this JSON file")
    parser.add_argument("--probe", choices=PROBES, help=argparse.SUPPRESS)
    parser.add_argument("--write-groove-case", action="store_true",
                        help=f"write {GROOVE_CASE.relative_to(REPO)} (the probe cosim-groove's case) and stop")
    args = parser.parse_args(argv)
    if args.write_groove_case:
        write_groove_case()
        return 0
    if args.probe:
        print(json.dumps(globals()[f"probe_{args.probe.replace('-', '_')}"]()))
        return 0
    probes = [p.strip() for p in args.probes.split(",") if p.strip()]
    if args.base is None or args.repeats < 1 or not set(probes) <= set(PROBES):
        parser.error(f"--base REV is required, --repeats >= 1, --probes of {', '.join(PROBES)}")
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--verify", f"{args.base}^{{commit}}"],
                            check=True, capture_output=True, text=True).stdout.strip()
    folder = args.keep or Path(tempfile.mkdtemp(prefix="compare_base_"))
    try:
        base, work = folder / "venv" / "bin" / "python", folder / "work-venv" / "bin" / "python"
        kept = (folder / "commit").read_text() if (folder / "commit").is_file() else None
        if kept not in (None, commit):
            parser.error(f"--keep {folder} holds {kept}, not {args.base} ({commit})")
        if kept is None:
            base = tree_interpreter(base_tree(commit, folder / "tree"), folder / "venv")
            (folder / "commit").write_text(commit)
        if not work.exists():
            work = tree_interpreter(REPO, folder / "work-venv")
        print(f"base {args.base} ({folder / 'tree'}) against the working tree {REPO}", flush=True)
        results = compare(base, work, probes, args.repeats)
        if args.json:
            args.json.write_text(json.dumps({"base": args.base, "base_commit": commit, "repeats": args.repeats,
                                             "cpus": os.cpu_count(), "probes": results}, indent=1))
    finally:
        if args.keep is None:
            shutil.rmtree(folder, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
