"""Does the co-simulation's coupling answer what the monolithic engine answers?  Ensembles on five cases.

For each case, ``--starts`` runs (the initial crank angle spread over a turn) of the monolithic reference
(RK4 at ``--reference-step``) and of each co-simulation configuration (the co-simulation's default first,
unless ``--no-default``; ``--cosim-steps``: the adaptive scheme's contact step; ``--tolerances``: its
``coupling_tolerance``; ``--linearised-steps``: the linearised scheme's fixed contact step; ``--options``: any
other :class:`~wearjoint.cosim.CoSimulationOptions`, e.g.
``scheme=linearised,step_s=2e-5,coupling_tolerance=0.01``; ``--masters``: third-party masters on the SSP
package at each of
``--master-steps`` with its ``--load-coupling``, on the cases that start unworn), over ``--revolutions``
revolutions of which the first
``--settling`` are dropped.  Per run the mean over its revolutions of: impacts per revolution, contact
fraction, largest normal force, share of chattering revolutions (more than
:data:`wearjoint.analysis.CHATTER_IMPACTS_PER_REVOLUTION` onsets).  Per configuration the ensemble's mean
and standard error, and the difference from the reference in combined standard errors
(|z| <= 2: inside the monolithic scatter) and in per cent of the reference's mean (what counts where the runs
settle on one periodic motion and the standard errors vanish: ``tight-joint``).

Cases (``--cases``): ``paper`` (the paper's slider-crank, unworn, no wear); ``paper-worn`` (its bushing
with a conforming groove 0.58 mm deep, the depth of the paper's 4000-revolution study, no further wear);
``own-wear`` (the own-mechanism example of docs/how-to/validate_own_mechanism.md, wearing; wear factor
``--wear-factor``); ``tight-joint`` (the paper's mechanism with joint J of docs/how-to/choose_step_and_master.md: a
15 mm pin in a bronze bushing with 0.05 mm clearance, 10 mm long, friction 0.15; unworn, no wear); ``groove`` (a
third slider-crank with a conforming groove 5.7 clearances deep, no further wear).  A conforming groove: the
bushing worn to the pin's circle pushed ``depth`` past the clearance along the direction in which an unworn run wore
most (:data:`LOADED_DIRECTION_RAD`, :func:`conforming_groove`).

    python -m wearjoint.studies.coupling_accuracy [--cases paper paper-worn own-wear tight-joint groove] [--starts 8]
        [--revolutions 6] [--settling 2] [--no-default] [--cosim-steps 5e-6 2.5e-6] [--tolerances 0.03]
        [--linearised-steps 5e-6 1e-5] [--masters libcosim ecos fmpy-ssp omsimulator container]
        [--master-steps 5e-6] [--load-coupling linearised] [--out DIR]

``--out DIR``: coupling_accuracy.json and coupling_accuracy.md (the table), rewritten as each configuration
finishes, and coupling_accuracy_run.json (the options, when it started and finished).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from wearjoint.analysis import chattering, contact_fraction, covered
from wearjoint.core import layout as L
from wearjoint.core.geometry import bushing_point_angles
from wearjoint.cosim.cosimulation import CoSimulationOptions, run_cosimulation
from wearjoint.cosim.masters import THIRD_PARTY, run_master
from wearjoint.fmu.ssp import LOAD_COUPLINGS
from wearjoint.parameters import JointParameters, SliderCrankParameters, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

SAMPLE_DT_S = 1e-4       # a third-party master's time series (the statistics come from every communication point)
STATISTICS = ("impacts_per_revolution", "contact_fraction", "max_normal_force_N", "chattering_share")
CASES = ("paper", "paper-worn", "own-wear", "tight-joint", "groove")
PAPER_WORN_DEPTH_M = 0.58e-3
GROOVE_CLEARANCES = 5.7
OWN_MECHANISM = dict(crank_length_m=0.08, rod_length_m=0.3, crank_speed_rpm=300.0, slider_mass_kg=1.2)
OWN_JOINT = dict(pin_radius_m=0.012, bushing_radius_m=0.01215, contact_length_m=0.01,
                 bushing_youngs_modulus_Pa=110e9, bushing_poisson_ratio=0.34)
TIGHT_JOINT = dict(pin_radius_m=0.015, bushing_radius_m=0.01505, contact_length_m=0.01, bushing_youngs_modulus_Pa=110e9,
                   bushing_poisson_ratio=0.34, friction_coefficient=0.15)
GROOVE_MECHANISM = dict(crank_length_m=0.06, rod_length_m=0.25, crank_speed_rpm=200.0, slider_mass_kg=1.5,
                        rod_mass_kg=0.3, rod_inertia_kg_m2=0.0018)
GROOVE_JOINT = dict(pin_radius_m=0.008, bushing_radius_m=0.00812, contact_length_m=0.008)
# the bushing-frame angle [rad] where two revolutions of the case's unworn joint wore most, the groove's direction: its
# bushing points 590 and 620 of 1257 (RK4 at 2.5 us, wear factor 1e4, a step 5x over the wear-step limit that RK4
# now refuses: the cases of docs/performance.md's ensembles, kept as they were)
LOADED_DIRECTION_RAD = {"paper-worn": 2.954146791203767, "groove": 3.1041034811125883}


def conforming_groove(joint: JointParameters, depth_m: float, direction_rad: float) -> np.ndarray:
    """Wear depths [m] of a bushing worn to the pin's circle with its centre at c + ``depth_m`` along
    ``direction_rad`` (bushing frame): depth(phi) = max(0, r(phi) - R_j), r(phi) = e cos(a) + sqrt(R_i^2 - e^2 sin^2 a)
    the pin's surface along phi, a = phi - direction, e = c + depth."""
    phi = bushing_point_angles(joint.n_points)
    e = joint.bushing_radius_m - joint.pin_radius_m + depth_m
    a = phi - direction_rad
    chord = joint.pin_radius_m ** 2 - (e * np.sin(a)) ** 2
    surface = np.where(chord >= 0.0, e * np.cos(a) + np.sqrt(np.maximum(chord, 0.0)), 0.0)
    return np.maximum(0.0, surface - joint.bushing_radius_m)


def case_setup(name: str, wear_factor: float) -> tuple[JointParameters, SliderCrankParameters, np.ndarray | None]:
    """(joint, mechanism, initial profile) of case ``name``."""
    if name == "paper":
        mechanism = SliderCrankParameters()
        return paper_joint(mechanism, wear_factor=0.0), mechanism, None
    if name == "own-wear":
        mechanism = SliderCrankParameters(**OWN_MECHANISM)
        return paper_joint(mechanism, wear_factor=wear_factor, **OWN_JOINT), mechanism, None
    if name == "tight-joint":
        mechanism = SliderCrankParameters()
        return paper_joint(mechanism, wear_factor=0.0, **TIGHT_JOINT), mechanism, None
    if name == "paper-worn":
        mechanism, changes, depth = SliderCrankParameters(), {}, PAPER_WORN_DEPTH_M
    elif name == "groove":
        mechanism, changes = SliderCrankParameters(**GROOVE_MECHANISM), GROOVE_JOINT
        depth = GROOVE_CLEARANCES * (GROOVE_JOINT["bushing_radius_m"] - GROOVE_JOINT["pin_radius_m"])
    else:
        raise ValueError(f"case {name!r}: allowed one of {', '.join(CASES)}")
    joint = paper_joint(mechanism, wear_factor=0.0, **changes)
    return joint, mechanism, conforming_groove(joint, depth, LOADED_DIRECTION_RAD[name])


def run_statistics(stats: np.ndarray, settling: int) -> dict:
    """The means over the revolutions after ``settling`` of :data:`STATISTICS`."""
    rows = stats[covered(stats)][settling:]
    rows = rows[rows[:, L.S_TIME] > 0.0]
    return {"impacts_per_revolution": float(rows[:, L.S_IMPACTS].mean()),
            "contact_fraction": float(contact_fraction(rows).mean()),
            "max_normal_force_N": float(rows[:, L.S_FORCE_MAX].mean()),
            "chattering_share": float(chattering(rows).mean())}


def ensemble(run, mechanism: SliderCrankParameters, starts: int, settling: int) -> dict:
    """Mean and standard error over ``starts`` crank angles spread over a turn of the statistics of
    ``run(mechanism)``, its wall time (``wall_s``, loading and compiling included), the real-time factor of the
    simulations alone (their simulated time over their ``wall_time_s``) and its communication steps per revolution
    (co-simulation)."""
    values, wall, simulating, simulated, steps = [], 0.0, 0.0, 0.0, 0.0
    for k in range(starts):
        start = time.perf_counter()
        record = run(mechanism.replace(initial_crank_angle_deg=360.0 * k / starts))
        wall += time.perf_counter() - start
        if not record.completed:
            raise RuntimeError(f"start {k}: {record.failure}")
        values.append(run_statistics(record.revolution_stats, settling))
        simulating += record.wall_time_s
        simulated += record.simulated_time_s
        steps += record.extra.get("communication_steps", 0) / record.revolutions / starts
    out = {"wall_s": wall, "realtime_factor": simulated / simulating, "steps_per_revolution": steps}
    for name in STATISTICS:
        x = np.array([v[name] for v in values])
        out[name] = {"mean": float(x.mean()), "se": float(x.std(ddof=1) / math.sqrt(x.size))}
    return out


def z_scores(row: dict, reference: dict) -> dict:
    """The differences from the reference in combined standard errors (0 where both scatter nil)."""
    out = {}
    for name in STATISTICS:
        a, b = row[name], reference[name]
        se = math.hypot(a["se"], b["se"])
        out[name] = (a["mean"] - b["mean"]) / se if se > 0 else 0.0
    return out


def relative_differences(row: dict, reference: dict) -> dict:
    """The differences of the means from the reference's in per cent of the reference's mean (0 where both are 0)."""
    out = {}
    for name in STATISTICS:
        a, b = row[name]["mean"], reference[name]["mean"]
        out[name] = 100.0 * (a - b) / abs(b) if b != 0.0 else (0.0 if a == 0.0 else math.copysign(math.inf, a))
    return out


def _cosim_options(text: str) -> tuple[str, dict]:
    """``NAME=VALUE,...`` as (the text, CoSimulationOptions keyword arguments: numbers where they parse)."""
    options = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        try:
            options[name.strip()] = float(value)
        except ValueError:
            options[name.strip()] = value.strip()
    try:
        CoSimulationOptions(**options)
    except (TypeError, ValueError) as exc:
        raise argparse.ArgumentTypeError(f"{text}: {exc}") from None
    return text, options


def run_case(name: str, args, log=print, save=lambda case: None) -> dict:
    joint, mechanism, profile = case_setup(name, args.wear_factor)
    revolutions = args.revolutions

    def monolithic(m):
        return run_simulation(joint, m, SimulationOptions(revolutions=revolutions, integrator="rk4",
                                                          step_s=args.reference_step), progress=False,
                              initial_profile_m=profile)

    reference = ensemble(monolithic, mechanism, args.starts, args.settling)
    rows = {f"monolithic rk4 {args.reference_step * 1e6:g} us": reference}
    log(f"{name}: reference {reference['wall_s']:.0f} s")
    configurations = [("cosim default", {})] if args.default else []
    configurations += [(f"cosim adaptive {step * 1e6:g} us", {"scheme": "adaptive", "step_s": step})
                       for step in args.cosim_steps]
    configurations += [(f"cosim adaptive tolerance {tolerance:g}", {"scheme": "adaptive", "coupling_tolerance": tolerance})
                       for tolerance in args.tolerances]
    configurations += [(f"cosim linearised {step * 1e6:g} us",
                        {"scheme": "linearised", "step_s": step, "coupling_tolerance": 0.0})
                       for step in args.linearised_steps]
    configurations += [(f"cosim {text}", options) for text, options in args.options]
    runs = [(label, lambda m, options=options: run_cosimulation(
        joint, m, CoSimulationOptions(revolutions=revolutions, **options), progress=False, initial_profile_m=profile))
        for label, options in configurations]
    if profile is None:         # the SSP's masters start unworn
        runs += [(f"{master} {args.load_coupling} {step * 1e6:g} us",
                  lambda m, master=master, step=step: run_master(master, joint, m, revolutions, step, SAMPLE_DT_S,
                                                                 load_coupling=args.load_coupling))
                 for master in args.masters for step in args.master_steps]
    depth = None if profile is None else float(profile.max())
    case = {"case": name, "groove_depth_m": depth, "clearance_m": joint.bushing_radius_m - joint.pin_radius_m,
            "rows": rows}
    save(case)                      # every finished row on disk before the next starts
    for label, run in runs:
        row = ensemble(run, mechanism, args.starts, args.settling)
        row["z"] = z_scores(row, reference)
        rows[label] = row
        save(case)
        log(f"{name}: {label} {row['wall_s']:.0f} s, {row['realtime_factor']:.3g}x real time, "
            f"{row['steps_per_revolution']:.0f} steps/rev, z " +
            " ".join(f"{k}={v:+.1f}" for k, v in row["z"].items()))
    return case


def table(results: list) -> str:
    """A markdown table: per case and configuration, the real-time factor of the simulations (compilation and
    loading excluded; the wall times with them are in the JSON), the communication steps per revolution and the
    mean ± standard error, z and the relative difference from the case's reference (its first row) of each
    statistic."""
    head = ("| case | configuration | real-time factor | steps/rev | " + " | ".join(STATISTICS) + " |\n|"
            + " --- |" * (4 + len(STATISTICS)))
    lines = [head]
    for case in results:
        reference = next(iter(case["rows"].values()))
        for label, row in case["rows"].items():
            cells = []
            relative = relative_differences(row, reference) if "z" in row else {}
            for name in STATISTICS:
                text = f"{row[name]['mean']:.3g} ± {row[name]['se']:.2g}"
                if "z" in row:
                    text += f" (z {row['z'][name]:+.1f}, {relative[name]:+.1f} %)"
                cells.append(text)
            steps = f"{row['steps_per_revolution']:.0f}" if row["steps_per_revolution"] else ""
            speed = f"{row['realtime_factor']:.3g}" if "realtime_factor" in row else ""
            lines.append(f"| {case['case']} | {label} | {speed} | {steps} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wearjoint.studies.coupling_accuracy", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    parser.add_argument("--starts", type=int, default=8)
    parser.add_argument("--revolutions", type=float, default=6.0)
    parser.add_argument("--settling", type=int, default=2)
    parser.add_argument("--reference-step", type=float, default=2.5e-6)
    parser.add_argument("--no-default", dest="default", action="store_false",
                        help="leave out the co-simulation's default configuration")
    parser.add_argument("--cosim-steps", type=float, nargs="*", default=[5e-6])
    parser.add_argument("--tolerances", type=float, nargs="*", default=[])
    parser.add_argument("--linearised-steps", type=float, nargs="*", default=[])
    parser.add_argument("--options", type=_cosim_options, nargs="*", default=[], metavar="NAME=VALUE,...",
                        help="further co-simulation configurations, each CoSimulationOptions fields, e.g. "
                             "scheme=linearised,step_s=2e-5,coupling_tolerance=0.01")
    parser.add_argument("--masters", nargs="*", choices=THIRD_PARTY, default=[])
    parser.add_argument("--master-steps", type=float, nargs="+", default=[5e-6])
    parser.add_argument("--load-coupling", choices=LOAD_COUPLINGS, default="linearised")
    parser.add_argument("--wear-factor", type=float, default=1.0)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    results = []
    run = {"options": list(sys.argv[1:] if argv is None else argv), "started": time.strftime("%Y-%m-%d %H:%M UTC",
                                                                                              time.gmtime())}

    def save(case=None) -> None:
        """coupling_accuracy.json and .md of the finished cases and rows (and ``case``'s so far)."""
        if args.out is not None:
            done = results + ([case] if case is not None else [])
            args.out.mkdir(parents=True, exist_ok=True)
            (args.out / "coupling_accuracy.json").write_text(json.dumps(done, indent=1))
            (args.out / "coupling_accuracy.md").write_text(table(done) + "\n")
            (args.out / "coupling_accuracy_run.json").write_text(json.dumps(run, indent=1))

    for name in args.cases:
        results.append(run_case(name, args, log=lambda text: print(text, file=sys.stderr, flush=True), save=save))
    run["finished"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    save()
    print(table(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
