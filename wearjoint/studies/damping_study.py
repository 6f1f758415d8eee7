"""The contact damping against the numerics: onset speeds, step independence, a Latin hypercube of runs.

    python -m wearjoint.studies.damping_study onsets [--revolutions 3] [--seeds 4]
    python -m wearjoint.studies.damping_study steps [--revolutions 5] [--seeds 8] [--wear-factor 1]
    python -m wearjoint.studies.damping_study lhs [--sets 64] [--revolutions 20]
    python -m wearjoint.studies.damping_study batches [--revolutions 5] [--seeds 8] [--wear-factor 1]
    python -m wearjoint.studies.damping_study contact-step [--mechanism own] [--revolutions 10] [--seeds 16]

``onsets``: the normal approach speeds at contact onsets of the paper's slider-crank (no wear, DOPRI),
under each damping law: quantiles and the energy-weighted mean sum v^3 / sum v^2, the speed at which
a Hunt-Crossley law dissipates over these impacts what a speed-independent restitution would
(docs/reference/model.md §3.5).  ``steps``: ensembles of ``--seeds`` starts (the crank angle perturbed as in
``wearjoint sweep``), revolutions 2.. (the start-up transient dropped), for RK4 at 2.5, 5 and 10 us and
DOPRI at rtol 1e-6 and 1e-5: mean, standard error and each configuration's distance from the pooled
mean in standard errors.  ``batches``: the same for the wear batches (docs/reference/model.md §3.11): RK4 at 2.5
and 10 us, DOPRI and the co-simulation (native FMU, its default scheme), each with the wear of every
step (``wear_interval_s`` 0) and in batches of the default interval, with the wear's own statistics
beside the dynamics': the depth and volume at the end, and the volume worn after the first revolution
(the starts share their first revolution: its wear is one sample).  ``contact-step``: RK4 at 2.5 us, at 20 us
and at the wear-step limit (30 us), DOPRI's default and DOPRI capped at 20 and 30 us, with wear, on the paper's or
the own-mechanism example's slider-crank (``--mechanism``), the starts spread over a turn (docs/explanation/numerics.md).
``lhs``: runs over a Latin hypercube of restitution, crank speed, wear
factor, k_w, clearance, friction and the rod's and slider's masses (docs/explanation/sensitivity.md's ranges,
restitution down to 0.1, up to 300 rpm), RK4 at the default 10 us and DOPRI, with wear; prints every
diverged run.  Runs go to a pool of one process per
usable core; each table is printed as it completes.
"""
from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from wearjoint import analysis
from wearjoint.core import layout as L
from wearjoint.cosim import CoSimulationOptions, run_cosimulation
from wearjoint.parameters import MAX_WEAR_STEP_S, SliderCrankParameters, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

DAMPINGS = ("hunt-crossley", "lankarani-nikravesh")
SEED_ANGLE_STEP_DEG = 1e-6                   # as validate's starts (wearjoint.sweep.design.START_ANGLE_STEP_DEG)
STATISTICS = ("impacts_per_revolution", "contact_fraction", "max_contact_force_N", "slider_acc_max_m_s2",
              "slider_acc_min_m_s2")
STEP_CONFIGURATIONS = (("rk4", 2.5e-6, None, None), ("rk4", 5e-6, None, None), ("rk4", 1e-5, None, None),
                       ("dopri", None, 1e-6, None), ("dopri", None, 1e-5, None))
# (integrator, step, rtol, wear_interval_s): every step's wear at once, and the default batches
BATCH_CONFIGURATIONS = tuple((integrator, step, rtol, interval) for integrator, step, rtol in
                             (("rk4", 2.5e-6, None), ("rk4", 1e-5, None), ("dopri", None, 1e-6),
                                                         ("cosim", None, None))
                             for interval in (0.0, MAX_WEAR_STEP_S))
WEAR_STATISTICS = ("max_wear_depth_um", "worn_volume_mm3", "late_worn_volume_mm3")
# the step in contact with wear: RK4 up to the wear-step limit and DOPRI's default and longer caps (a DOPRI step here
# is its max_step_s) against RK4 at 2.5 us (docs/explanation/numerics.md)
CONTACT_STEP_CONFIGURATIONS = (("rk4", 2.5e-6, None, None), ("rk4", 2e-5, None, None),
                               ("rk4", MAX_WEAR_STEP_S, None, None), ("dopri", None, None, None),
                               ("dopri", 2e-5, None, None), ("dopri", MAX_WEAR_STEP_S, None, None))
# docs/tutorials/own_mechanism.md's slider-crank: with the paper's joint and wear in contact ~89 % of the time
MECHANISMS = {"paper": {}, "own": {"crank_length_m": 0.08, "rod_length_m": 0.3, "crank_speed_rpm": 300.0,
                                   "slider_mass_kg": 1.2}}
# docs/explanation/sensitivity.md's ranges, restitution down to 0.1 and up to 300 rpm; * sampled log-uniformly
LHS_RANGES = {"restitution": (0.1, 0.95), "crank_speed_rpm": (150.0, 300.0), "wear_factor*": (1.0, 100.0),
              "wear_coefficient_m2_N*": (2.7245e-11, 1.0898e-10), "clearance_m": (0.05e-3, 0.2e-3),
              "friction_coefficient": (0.05, 0.2), "rod_mass_kg": (0.15, 0.25), "slider_mass_kg": (0.5, 0.9)}
JOINT_FIELDS = ("restitution", "wear_factor", "wear_coefficient_m2_N", "friction_coefficient")


def _record(joint, mechanism, options: dict):
    if options.get("integrator") == "cosim":      # the co-simulation's default scheme and steps
        cosim = CoSimulationOptions(revolutions=options["revolutions"], sample_dt_s=options["sample_dt_s"])
        return run_cosimulation(joint, mechanism, cosim, progress=False)
    return run_simulation(joint, mechanism, SimulationOptions(**options), progress=False)


def _run(joint_changes: dict, mechanism_changes: dict, options: dict, late_wear: bool = False):
    """One run (in a worker): its record's revolution statistics, samples, failure and wall time; ``late_wear``:
    also the volume worn after the first revolution (the run's less that of the same start over one revolution,
    the same trajectory: starts 1e-6 deg apart share their first revolution or more, so the first revolution's
    wear is one sample, not an ensemble's)."""
    mechanism = SliderCrankParameters(**mechanism_changes)
    joint = paper_joint(mechanism, **joint_changes)
    start = time.perf_counter()
    record = _record(joint, mechanism, options)
    first = _record(joint, mechanism, options | {"revolutions": 1.0}).worn_volume_m3 if late_wear else math.nan
    return {"stats": record.revolution_stats, "samples": record.samples, "failure": record.failure,
            "wall_s": time.perf_counter() - start, "period_s": record.period_s,
            "max_wear_depth_m": float(record.wear_depth_m.max()), "worn_volume_m3": record.worn_volume_m3,
            "late_worn_volume_m3": record.worn_volume_m3 - first}


def onset_speeds(samples: np.ndarray) -> np.ndarray:
    """Approach speeds [m/s] at the contact onsets of a time series sampled finely enough that the motion
    between the two samples around an onset is free flight: the change of the signed penetration over
    those samples divided by their spacing."""
    contact = samples[:, L.T_CONTACT] > 0.5
    onsets = np.nonzero(contact[1:] & ~contact[:-1])[0] + 1
    dt = samples[onsets, L.T_TIME] - samples[onsets - 1, L.T_TIME]
    return (samples[onsets, L.T_PENETRATION] - samples[onsets - 1, L.T_PENETRATION]) / dt


def _seed_angle(seed: int) -> dict:
    return {"initial_crank_angle_deg": seed * SEED_ANGLE_STEP_DEG}


def onsets(pool, revolutions: float, seeds: int) -> None:
    print(f"onset approach speeds, paper slider-crank, no wear, DOPRI, {revolutions:g} revolutions x {seeds} seeds "
          "(the first revolution dropped) [mm/s]")
    print(f"{'damping':20s} {'onsets':>7s} {'10%':>6s} {'25%':>6s} {'50%':>6s} {'75%':>6s} {'90%':>6s} {'99%':>6s} "
          f"{'sum v3/sum v2':>14s}")
    options = {"revolutions": revolutions, "sample_dt_s": 1e-6}
    for damping in DAMPINGS:
        futures = [pool.submit(_run, {"wear_factor": 0.0, "contact_damping": damping}, _seed_angle(s), options)
                   for s in range(seeds)]
        speeds = []
        for f in futures:
            r = f.result()
            late = r["samples"][r["samples"][:, L.T_TIME] > r["period_s"]]
            speeds.append(onset_speeds(late))
        v = np.concatenate(speeds)
        q = np.percentile(v, (10, 25, 50, 75, 90, 99)) * 1e3
        weighted = (v ** 3).sum() / (v ** 2).sum() * 1e3
        print(f"{damping:20s} {v.size:7d} " + " ".join(f"{x:6.1f}" for x in q) + f" {weighted:14.1f}", flush=True)


def ensemble(runs, names=STATISTICS) -> dict:
    """Mean and standard error over runs of their revolution statistics, the first revolution dropped, and of
    the wear at the end (WEAR_STATISTICS)."""
    rows = [analysis.mean_revolution_statistics(r["stats"][1:], r["period_s"])
            | {"max_wear_depth_um": r["max_wear_depth_m"] * 1e6, "worn_volume_mm3": r["worn_volume_m3"] * 1e9,
               "late_worn_volume_mm3": r["late_worn_volume_m3"] * 1e9}
            for r in runs]
    out = {}
    for name in names:
        x = np.array([row[name] for row in rows])
        out[name] = (float(x.mean()), float(x.std(ddof=1) / math.sqrt(x.size)))
    return out


def steps(pool, revolutions: float, seeds: int, wear_factor: float, damping: str,
          configurations=STEP_CONFIGURATIONS, names=STATISTICS, title: str = "step independence",
          mechanism: str = "paper", spread: bool = False) -> None:
    """Each configuration over ``seeds`` starts (:func:`_seed_angle`, or with ``spread`` spread over a turn) of the
    ``mechanism`` (a key of MECHANISMS)."""
    print(f"\n{title}, {mechanism} mechanism, {damping}, wear factor {wear_factor:g}, {seeds} seeds, revolutions 2-"
          f"{revolutions:g}: mean +- standard error, (distance from the pooled mean in standard errors)")
    print(f"{'integrator':26s} " + " ".join(f"{n:>26s}" for n in names) + f" {'wall s':>7s} failed")
    results = []
    for integrator, step, rtol, interval in configurations:
        options = {"revolutions": revolutions, "integrator": integrator, "sample_dt_s": 1e-4}
        options.update({"step_s" if integrator == "rk4" else "max_step_s": step} if step else {})
        options.update({"rtol": rtol} if rtol else {})
        joint = {"wear_factor": wear_factor, "contact_damping": damping}
        joint.update({} if interval is None else {"wear_interval_s": interval})
        starts = [{"initial_crank_angle_deg": 360.0 * s / seeds} if spread else _seed_angle(s) for s in range(seeds)]
        futures = [pool.submit(_run, joint, MECHANISMS[mechanism] | start, options, "late_worn_volume_mm3" in names)
                   for start in starts]
        runs = [f.result() for f in futures]
        label = (f"{integrator} {step * 1e6:g} us" if step else f"dopri rtol {rtol:g}" if rtol else integrator) + (
            "" if interval is None else f", batch {interval * 1e6:g} us")
        ok = [r for r in runs if not r["failure"]]
        results.append((label, ensemble(ok, names) if len(ok) > 1 else None, sum(r["wall_s"] for r in runs),
                        len(runs) - len(ok)))
    pooled = {n: np.mean([e[n][0] for _, e, _, _ in results if e]) for n in names}
    for label, e, wall, failed in results:
        cells = " ".join(f"{e[n][0]:10.4g} +- {e[n][1]:7.3g} ({(e[n][0] - pooled[n]) / e[n][1]:+4.1f})"
                         if e else f"{'-':>26s}" for n in names)
        print(f"{label:26s} {cells} {wall:7.1f} {failed}", flush=True)


def lhs(pool, sets: int, revolutions: float, seed: int, damping: str) -> None:
    from scipy.stats import qmc

    unit = qmc.LatinHypercube(d=len(LHS_RANGES), seed=seed).random(sets)
    print(f"Latin hypercube, {sets} sets over " + ", ".join(f"{n} {lo:g}-{hi:g}" for n, (lo, hi) in LHS_RANGES.items())
          + f" (* log-uniform), {damping}, {revolutions:g} revolutions with wear, RK4 10 us and DOPRI")
    cases = []
    for row in unit:
        values = {}
        for label, u in zip(LHS_RANGES, row):
            lo, hi = LHS_RANGES[label]
            values[label.rstrip("*")] = lo * (hi / lo) ** u if label.endswith("*") else lo + (hi - lo) * u
        joint = {n: values[n] for n in JOINT_FIELDS} | {"bushing_radius_m": 0.01 + values["clearance_m"],
                                                        "contact_damping": damping}
        mechanism = {n: values[n] for n in ("crank_speed_rpm", "rod_mass_kg", "slider_mass_kg")}
        for integrator in ("rk4", "dopri"):
            options = {"revolutions": revolutions, "integrator": integrator, "step_s": 1e-5, "sample_dt_s": 1e-3}
            cases.append((values, integrator, pool.submit(_run, joint, mechanism, options)))
    failed, start = 0, time.perf_counter()
    for values, integrator, future in cases:
        r = future.result()
        if r["failure"]:
            failed += 1
            print(f"  diverged: {integrator} " + ", ".join(f"{n}={v:.4g}" for n, v in values.items())
                  + f": {r['failure']}", flush=True)
    print(f"{len(cases) - failed} of {len(cases)} runs completed, {failed} diverged "
          f"({time.perf_counter() - start:.0f} s)", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", choices=("onsets", "steps", "batches", "contact-step", "lhs"))
    parser.add_argument("--mechanism", choices=tuple(MECHANISMS), default="paper")
    parser.add_argument("--revolutions", type=float, default=None)
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--wear-factor", type=float, default=1.0)
    parser.add_argument("--damping", choices=DAMPINGS, default=DAMPINGS[0])
    parser.add_argument("--sets", type=int, default=64)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    with ProcessPoolExecutor(args.workers) as pool:
        if args.part == "onsets":
            onsets(pool, args.revolutions or 3.0, args.seeds)
        elif args.part == "steps":
            steps(pool, args.revolutions or 5.0, args.seeds, args.wear_factor, args.damping)
        elif args.part == "batches":
            steps(pool, args.revolutions or 5.0, args.seeds, args.wear_factor, args.damping, BATCH_CONFIGURATIONS,
                  STATISTICS + WEAR_STATISTICS, "wear batches")
        elif args.part == "contact-step":
            steps(pool, args.revolutions or 5.0, args.seeds, args.wear_factor, args.damping,
                  CONTACT_STEP_CONFIGURATIONS, STATISTICS + ("max_wear_depth_um", "worn_volume_mm3"),
                  "the step in contact with wear", args.mechanism, spread=True)
        else:
            lhs(pool, args.sets, args.revolutions or 20.0, args.seed, args.damping)


if __name__ == "__main__":
    main()
