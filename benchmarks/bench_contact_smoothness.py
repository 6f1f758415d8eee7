"""The deepest-point contact against the elastic-foundation contact, measured in one run.

    python benchmarks/bench_contact_smoothness.py [--revolutions 2] [--rest-s 0.05] [--swing-s 0.5]

For ``contact_model`` = ``deepest`` (the paper's) and ``foundation`` (the default):

1. Paper slider-crank (``paper_joint()``, no wear and with the default wear factor), adaptive
   Dormand-Prince (``SimulationOptions(integrator="dopri")``): accepted and rejected steps and
   wall time, monolithic (:class:`~wearjoint.simulate.Simulation`) and through the native joint
   FMU's Model Exchange interface (:class:`~wearjoint.cosim.model_exchange.ModelExchangeSimulation`).
   Both engines are compiled untimed first; one timed run each.
2. exudyn, generalized-alpha with Newton at its default tolerances, 10 us nominal step, on the bar
   pendulum of :mod:`wearjoint.validation.exudyn_pendulum`: at rest (released touching at 0 deg,
   wear on) and swinging (released at 6 deg, without and with wear): completion, steps halved
   after a failed Newton iteration, the shortest step, Newton iterations, the largest |omega| over
   the last half (rocking) and the wear.

3. fmusim (the Reference-FMUs' importer, ``--fmusim PATH`` or ``$FMUSIM``; /work/shared/tools/fmusim
   builds it), CVODE on the joint FMU's Model Exchange interface driven by 0.1 s of the slider-crank's
   kinematics from a CSV (linearly interpolated): integrator steps (fmi2CompletedIntegratorStep),
   events (fmi2EnterEventMode, located contact onsets and separations) and event-indicator
   evaluations, from fmusim's log of FMI calls.  Skipped, saying so, without fmusim.

2 shared cores: the load average is printed; wall times above a load of 1 are pessimistic.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from wearjoint.core import layout as L
from wearjoint.cosim.model_exchange import ModelExchangeSimulation
from wearjoint.parameters import CONTACT_MODELS, SliderCrankParameters, paper_joint
from wearjoint.simulate import Simulation, SimulationOptions
from wearjoint.validation.exudyn_pendulum import pendulum_joint, run_pendulum

ORDER = ("deepest", "foundation")      # the paper's, the default
assert set(ORDER) == set(CONTACT_MODELS)


def _engine(kind, joint, options):
    if kind == "monolithic":
        return Simulation(joint, None, options)
    return ModelExchangeSimulation(joint, None, options, fmu_backend="native")


def dopri_run(kind: str, joint, revolutions: float) -> dict:
    """One timed DOPRI run over ``revolutions`` on a fresh engine (compiled by an untimed short run)."""
    options = SimulationOptions(integrator="dopri", revolutions=revolutions)
    t_end = revolutions * SliderCrankParameters().period_s
    samples = np.zeros((int(t_end / options.sample_dt_s) + 16, L.N_SAMPLE_COLUMNS))
    for end, timed in ((0.002, False), (t_end, True)):
        sim = _engine(kind, joint, options)
        try:
            sim.warm_up()
            start = time.perf_counter()
            sim.advance_to(end, samples)
            wall = time.perf_counter() - start
            accepted, rejected = sim.accepted, sim.rejected
        finally:
            sim.close()
    return {"wall_s": wall, "accepted": accepted, "rejected": rejected, "t_end": t_end}


def fmusim_run(fmusim: str, fmu: Path, inputs: Path, joint, folder: Path) -> dict:
    """fmusim's CVODE on the ME FMU with ``joint``'s parameters over the inputs in ``inputs``."""
    from wearjoint.fmu import variables as fv

    reals, integers = fv.fmi_parameter_values_by_type(joint)
    starts = [arg for name, value in {**reals, **integers}.items() for arg in ("--start-value", name, repr(value))]
    log = folder / f"calls_{joint.contact_model}.log"
    cmd = [fmusim, "--interface-type", "me", "--solver", "cvode", "--stop-time", "0.0999", "--output-interval", "1e-4",
           "--input-file", str(inputs), "--log-fmi-calls", "--fmi-log-file", str(log), *starts,
           "--output-variable", "normal_force", "--output-file", str(folder / "out.csv"), str(fmu)]
    start = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    calls = log.read_text()
    return {"exit": done.returncode, "wall_s": wall, "steps": calls.count("fmi2CompletedIntegratorStep"),
            "events": calls.count("fmi2EnterEventMode"), "indicators": calls.count("fmi2GetEventIndicators")}


def fmusim_section(fmusim: str | None) -> None:
    print("\n3. fmusim CVODE on the joint FMU's Model Exchange interface, 0.1 s of slider-crank kinematics, no wear")
    if not fmusim or not Path(fmusim).is_file():
        print("   skipped: no fmusim (--fmusim PATH or $FMUSIM; /work/shared/tools/fmusim builds it)")
        return
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from kinematic_trace import slider_crank_trace

    from wearjoint.fmu import variables as fv
    from wearjoint.fmu.build import build_fmu

    with tempfile.TemporaryDirectory(prefix="bench_fmusim_") as tmp:
        folder = Path(tmp)
        rows = slider_crank_trace(paper_joint(wear_factor=0.0), 10000, 1e-5)
        inputs = folder / "inputs.csv"
        inputs.write_text("time," + ",".join(v.name for v in fv.INPUTS) + "\n" + "".join(
            ",".join(repr(float(x)) for x in (r[0], *r[2:])) + "\n" for r in rows))
        fmu = build_fmu(folder / "fmu", platforms="linux64")
        print(f"{'contact':8s} {'exit':>4s} {'steps':>7s} {'events':>7s} {'indicator calls':>16s} {'wall s':>7s}")
        for cp in ORDER:
            r = fmusim_run(fmusim, fmu, inputs, paper_joint(contact_model=cp, wear_factor=0.0), folder)
            print(f"{cp:8s} {r['exit']:4d} {r['steps']:7d} {r['events']:7d} {r['indicators']:16d} {r['wall_s']:7.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=2.0)
    parser.add_argument("--rest-s", type=float, default=0.05, help="simulated time of the pendulum at rest [s]")
    parser.add_argument("--swing-s", type=float, default=0.5, help="simulated time of the swinging pendulum [s]")
    parser.add_argument("--fmusim", default=os.environ.get("FMUSIM"), help="fmusim binary (default $FMUSIM)")
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    print(f"\n1. slider-crank, DOPRI, {args.revolutions:g} revolutions")
    print(f"{'contact':8s} {'wear':5s} {'engine':11s} {'accepted':>9s} {'rejected':>9s} {'rejected %':>10s} {'wall s':>8s}")
    for wear in (0.0, 1.0):
        for cp in ORDER:
            joint = paper_joint(contact_model=cp, wear_factor=wear)
            for kind in ("monolithic", "ME FMU"):
                r = dopri_run(kind, joint, args.revolutions)
                share = 100.0 * r["rejected"] / (r["accepted"] + r["rejected"])
                print(f"{cp:8s} {'on' if wear else 'off':5s} {kind:11s} {r['accepted']:9d} {r['rejected']:9d} "
                      f"{share:10.1f} {r['wall_s']:8.2f}", flush=True)
    print("\n2. exudyn generalized-alpha (default Newton), bar pendulum in the joint, 10 us nominal step")
    print(f"{'contact':8s} {'case':16s} {'done':>5s} {'t reached':>9s} {'halved':>7s} {'min step':>9s} "
          f"{'Newton it':>9s} {'late |w|':>9s} {'wear m':>9s} {'wall s':>7s}")
    cases = (("at rest, wear", 0.0, args.rest_s, 1.0), ("swing 6deg", 6.0, args.swing_s, 0.0),
             ("swing 6deg, wear", 6.0, args.swing_s, 1.0))
    for label, angle, end, wear in cases:
        for cp in ORDER:
            r = run_pendulum(pendulum_joint(contact_model=cp, wear_factor=wear), angle, end)
            print(f"{cp:8s} {label:16s} {str(r['completed']):>5s} {r['time_reached_s']:9.4f} {r['reduced_steps']:7d} "
                  f"{r['min_step_s']:9.2e} {r['newton_iterations']:9d} {r['late_max_abs_omega_rad_s']:9.1e} "
                  f"{r['max_wear_depth_m']:9.1e} {r['wall_time_s']:7.2f}", flush=True)
    fmusim_section(args.fmusim)
    print(f"\nload average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
