"""Which contact damping law reproduces what the paper reports: ensembles of the paper's slider-crank under each law.

    python -m wearjoint.studies.contact_law_study [--seeds 8] [--revolutions 4] [--worn-profile PROFILE.csv]
        [--worn-only] [--merge-deg 15] [--laws 0,3,...]

The paper (Sec. 7, Figs. 8 and 13) reports two impact-vibration events per crank revolution, when the slider
reaches the ends of its travel (the dead centres), growing with wear.  Each law and the plausible range of its free
parameter (:func:`wearjoint.contact_laws.contact_law_variants`; ``--laws`` picks some by index) runs ``--seeds`` starts spread over a turn, DOPRI, without wear, on the unworn bushing and on ``--worn-profile``
(e.g. the 4000-revolution profile of `wearjoint wear-study`); revolutions 2.. are counted.  Per configuration: the
impact-vibration events per revolution (analysis.impact_events: |a - a_ideal| > 100 m/s^2, clusters within
``--merge-deg`` merged) and the major ones (peaking at >= 25 % of their revolution's largest), where their peaks fall (crank rotation past the preceding dead centre), the share of chattering
revolutions (> 120 contact onsets), and the revolution statistics; mean +- standard error over the starts.
"""
from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from wearjoint import analysis
from wearjoint.core import layout as L
from wearjoint.contact_laws import contact_law_variants
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation

MAJOR_SHARE = 0.25             # a major event peaks at >= this share of its revolution's largest
MECHANISM = SliderCrankParameters()
LAWS = contact_law_variants(MECHANISM)
COLUMNS = ("events_per_revolution", "major_events_per_revolution", "event_past_dead_centre_deg", "chattering_share",
           "impacts_per_revolution", "contact_fraction", "max_contact_force_N", "slider_acc_max_m_s2")


def run_case(changes: dict, start_deg: float, revolutions: float, profile, merge_deg: float) -> dict:
    """One start (in a worker): the counted revolutions' statistics of :data:`COLUMNS`."""
    mechanism = MECHANISM.replace(initial_crank_angle_deg=start_deg)
    joint = paper_joint(mechanism, wear_factor=0.0, **changes)
    options = SimulationOptions(revolutions=revolutions, integrator="dopri", sample_dt_s=5e-5)
    record = run_simulation(joint, mechanism, options, progress=False, initial_profile_m=profile)
    period = mechanism.period_s
    samples = record.samples[record.samples[:, L.T_TIME] >= period]
    events = analysis.impact_events(samples[:, L.T_TIME], samples[:, L.T_SLIDER_A], mechanism, merge_deg=merge_deg)
    # the crank turns clockwise from start_deg: its rotation past the preceding dead centre (theta1 = 0 or 180 deg)
    past = [(e["peak_crank_rotation_deg"] - start_deg) % 180.0 for e in events]
    stats = record.revolution_stats[1:]
    counted = stats[stats[:, L.S_TIME] > 0.5 * period]
    mean = analysis.mean_revolution_statistics(counted, period)
    revolution = np.array([int(0.5 * (e["start_s"] + e["end_s"]) // period) for e in events])
    peak = np.array([e["peak_deviation_m_s2"] for e in events])
    major = sum(int(np.sum(peak[revolution == r] >= MAJOR_SHARE * peak[revolution == r].max()))
                for r in set(revolution.tolist()))
    return {"events_per_revolution": len(events) / (revolutions - 1.0),
            "major_events_per_revolution": major / (revolutions - 1.0),
            "event_past_dead_centre_deg": float(np.mean(past)) if past else math.nan,
            "chattering_share": float(np.mean(analysis.chattering(counted))),
            **{name: mean[name] for name in COLUMNS[4:]}, "failure": record.failure}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wearjoint.studies.contact_law_study",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--revolutions", type=float, default=4.0)
    parser.add_argument("--worn-profile", default=None, help="a profile.csv (phi_deg,wear_depth_m)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--merge-deg", type=float, default=analysis.IMPACT_EVENT_MERGE_DEG,
                        help="clusters at most this much crank rotation apart are one event (default %(default)s)")
    parser.add_argument("--worn-only", action="store_true", help="only the worn profile")
    parser.add_argument("--laws", default=None, help="comma-separated indices into LAWS (default all)")
    args = parser.parse_args(argv)
    profiles = [] if args.worn_only else [("unworn", None)]
    if args.worn_profile:
        depth = np.loadtxt(args.worn_profile, delimiter=",", skiprows=1)[:, 1]
        profiles.append((f"worn {depth.max() * 1e3:.2f} mm", depth))
    print(f"paper slider-crank, DOPRI, no wear, {args.seeds} starts spread over a turn x {args.revolutions:g} "
          "revolutions (revolutions 2.. counted): mean +- standard error")
    print("| profile | law | " + " | ".join(COLUMNS) + " | wall s |")
    print("|---|---|" + "---|" * (len(COLUMNS) + 1))
    with ProcessPoolExecutor(args.workers) as pool:
        for profile_label, profile in profiles:
            for label, changes in [LAWS[int(i)] for i in args.laws.split(",")] if args.laws else LAWS:
                start = time.perf_counter()
                futures = [pool.submit(run_case, changes, 360.0 * s / args.seeds, args.revolutions, profile,
                                           args.merge_deg)
                           for s in range(args.seeds)]
                rows = [f.result() for f in futures]
                failed = sum(bool(r["failure"]) for r in rows)
                cells = []
                for name in COLUMNS:
                    x = np.array([r[name] for r in rows if not r["failure"]], dtype=float)
                    x = x[np.isfinite(x)]
                    cells.append(f"{x.mean():.3g} ± {x.std(ddof=1) / math.sqrt(x.size):.2g}" if x.size > 1 else "-")
                print(f"| {profile_label} | {label}{f' ({failed} failed)' if failed else ''} | " + " | ".join(cells)
                      + f" | {time.perf_counter() - start:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
