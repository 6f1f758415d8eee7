"""`wearjoint sensitivity COMMAND --param NAME=LOW,HIGH[,log]... --out DIR`: which parameters drive
COMMAND's outputs (SALib's Morris or Sobol' design, every row a Dask case of :mod:`wearjoint.sweep`;
:mod:`wearjoint.sensitivity`, docs/explanation/sensitivity.md), and how far the contact damping laws move them at the
nominal point (the model-form spread; ``--no-law-spread`` leaves it out).  Exit status 0 when every run is ok,
1 when some (a law variant's included) failed or gave numbers that are not physical (the pin through the bushing wall),
2 for bad input, 130 after Ctrl-C (finished runs kept; continue with --resume)."""
from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from ..parameters import ParameterError
from ..sensitivity.sample import DEFAULT_SAMPLES, METHODS, MIN_SAMPLES
from ..sweep.design import TARGETS, command_options
from ..sweep.limits import check_cluster, check_workers
from .out_folder import prepare_out_folder
from .sweep import study_parser


def add_arguments(parser) -> None:
    parser.add_argument("target", choices=TARGETS, metavar="COMMAND",
                        help="the command each run is: " + ", ".join(TARGETS))
    parser.add_argument("options", nargs=argparse.REMAINDER,
                        help="sensitivity options and COMMAND's options (wearjoint sensitivity COMMAND --help)")


def target_parser(target: str) -> argparse.ArgumentParser:
    """The parser of ``wearjoint sensitivity TARGET``: TARGET's own options plus the study's."""
    parser = study_parser("sensitivity", target, f"global sensitivity of wearjoint {target}'s outputs to its "
                                                 "parameters (SALib), every run a Dask task")
    g = parser.add_argument_group("sensitivity (SALib)")
    g.add_argument("--param", action="append", default=[], metavar="NAME=LOW,HIGH[,log]",
                   help="a sampled parameter: any real option of COMMAND, as the option's name without dashes or "
                        "its API name, its range in the option's unit, ',log' to sample log10 uniformly; repeat")
    g.add_argument("--method", choices=METHODS, default="morris", help="design and analysis (default %(default)s)")
    g.add_argument("--samples", type=int, default=None,
                   help=f"Morris trajectories (N(D+1) runs, N >= {MIN_SAMPLES['morris']}) or Sobol' base samples "
                        f"(N(D+2) runs, a power of 2 >= {MIN_SAMPLES['sobol']}) for D parameters "
                        f"(default: morris {DEFAULT_SAMPLES['morris']}, sobol {DEFAULT_SAMPLES['sobol']})")
    g.add_argument("--seed", type=int, default=0, help="seed of SALib's sampling and bootstrap (default %(default)s)")
    g.add_argument("--outputs", default=None, metavar="A,B,...",
                   help="summary.json numbers to analyse (default max_wear_depth_m, worn_volume_m3, "
                        "max_contact_force_N, impacts_per_revolution, slider_acc_peak_m_s2)")
    g.add_argument("--target-interval", type=float, default=None, metavar="W",
                   help="double --samples until every output's widest 95%% half-interval is <= W (Sobol': of S1 "
                        "and ST; Morris: of mu* as a share of the largest mu*)")
    g.add_argument("--max-samples", type=int, default=None,
                   help="with --target-interval: the most samples to reach (default 8 x --samples)")
    g.add_argument("--no-law-spread", action="store_true",
                   help="skip the contact law's spread: the run of every contact damping law variant at the nominal "
                        "point (every --param at the middle of its range) after the study (it costs one run per "
                        "variant)")
    if "--resume" not in parser._option_string_actions:
        g.add_argument("--resume", action="store_true", help="reuse the runs finished in --out")
    parser._option_string_actions["--seeds"].help = argparse.SUPPRESS    # refused (run): a design row is one run
    return parser


def run(args) -> int:
    from ..sensitivity import parse_params, run_sensitivity

    a = target_parser(args.target).parse_args(args.options)
    args.out = a.out                             # the results folder, for its report (wearjoint.cli.main)
    # --out is the target's option: checked once parsed; the folders it makes go if the run is refused
    args.out_folders_made = prepare_out_folder("sensitivity", a.out, "--out")
    if a.seeds is not None:
        raise ParameterError(f"--seeds={a.seeds!r} is invalid here: each design row is one run (--seed seeds the "
                             "sampling)")
    check_cluster(a.workers, a.scheduler)
    if a.workers is not None:
        check_workers(a.workers)
    if a.max_samples is not None and a.target_interval is None:
        raise ParameterError(f"--max-samples={a.max_samples!r} is invalid: allowed only with --target-interval")
    if a.outputs is not None and not a.outputs.strip(" ,"):
        raise ParameterError(f"--outputs={a.outputs!r} is invalid: allowed A,B,... numbers of the runs' summary.json")
    base = command_options(args.target, a)
    problem = parse_params(args.target, a.param, base)
    command_line = shlex.join(["wearjoint", "sensitivity", args.target, *args.options])
    try:
        summary = run_sensitivity(args.target, base, problem, a.out, method=a.method, samples=a.samples, seed=a.seed,
                                  outputs=a.outputs, target_interval=a.target_interval, max_samples=a.max_samples,
                                  workers=a.workers, scheduler=a.scheduler, resume=a.resume, progress=not a.quiet,
                                  command_line=command_line, law_spread=not a.no_law_spread, plots=not a.no_plots)
    except KeyboardInterrupt:
        summary = {"interrupted": True}
    if summary["interrupted"]:
        print(f"wearjoint sensitivity: interrupted; finished runs are kept in {a.out} (continue with --resume)",
              file=sys.stderr)
        return 130
    print_outcome(summary, a.out)
    failure = failure_line(summary, a.out)
    if failure:
        print(failure, file=sys.stderr)
    return 1 if failure else 0


def failure_line(summary: dict, out) -> str:
    """The one line on stderr of a study some of whose runs (a law variant's included) failed or gave numbers that
    are not physical: how many, where each is listed with its error, the first one's error; '' when none did."""
    parts = []
    if summary["failed"] or summary["invalid"]:
        first = summary["failures"][0]["error"].split(";")[0] if summary["failures"] else ""
        invalid = f", {summary['invalid']} gave numbers that are not physical" if summary["invalid"] else ""
        parts.append(f"{summary['failed']} of {summary['cases']} runs failed{invalid} (each with its error: "
                     f"{Path(out) / 'samples.csv'}, summary.json's failures; the first: {first})")
    law = summary.get("law_spread")
    if law and law["failed"]:
        parts.append(f"{law['failed']} of {len(law['variants'])} contact law variants failed or are not physical "
                     f"(each with its error: {Path(out) / 'law_spread.csv'})")
    return f"wearjoint sensitivity: error: {'; '.join(parts)}" if parts else ""


def print_outcome(summary: dict, out) -> None:
    """Counts, then per output its parameters by effect with their 95 % intervals and the wear factor's bias, then
    the contact law's spread."""
    from ..sensitivity.report import ranked

    method = summary["method"]
    print(f"  {method} N = {summary['samples']}, seed {summary['seed']}: {summary['runs']} runs "
          f"({summary['cases']} distinct): {summary['ok']} ok, {summary['failed']} failed, {summary['invalid']} invalid, "
          f"{summary['skipped_as_done']} already done; {summary['wall_time_s']:.1f} s")
    if summary["intervals_note"]:
        print(f"  note: {summary['intervals_note']}")
    if summary["target_interval"] is not None:
        print(f"  target interval {summary['target_interval']:g}: {'met' if summary['target_met'] else 'NOT met'}")
    for name, result in summary["results"].items():
        bias = summary["wear_factor_bias"][name]["text"]
        print(f"  {name} (wear-factor bias {bias}; {result['groups']} complete groups"
              + (", constant" if result["constant"] else "") + "):")
        for r in ranked(method, result):
            if method == "sobol":
                text = f"ST {r['ST']:.3f} ± {r['ST_conf']:.3f}   S1 {r['S1']:.3f} ± {r['S1_conf']:.3f}"
            else:
                text = f"mu* {r['mu_star']:.4g} ± {r['mu_star_conf']:.2g}   sigma {r['sigma']:.3g}"
            print(f"    {r['parameter']:28s} {text}")
    for failure in summary["failures"][:10]:
        print(f"  failed or invalid {failure['case_id']}: {failure['error']}")
    if summary.get("law_spread"):
        from ..sensitivity.law_spread import spread_lines

        print("\n".join(spread_lines(summary["law_spread"], summary["outputs"])))
    print(f"results in {out}")


__all__ = ["add_arguments", "run", "target_parser", "print_outcome", "failure_line"]
