"""`wearjoint validate`: the cross-check of the engines (:mod:`wearjoint.validation.compare`)."""
from __future__ import annotations

import sys
from dataclasses import replace

from ..joint_fields import unread_by
from ..parameters import JointParameters, ParameterError, SliderCrankParameters
from ..validation.compare import ENGINES, FULL, QUICK, REFERENCE, RunStoppedShort
from ..validation.report import run_validation
from ..validation.spans import WINDOW_POINTS, check_spans, default_window_s, min_window_s
from .options import add_fmu_arguments, add_model_arguments, add_output_arguments, model_from_args, restate_default


def _engine_list(text: str) -> tuple:
    """``--engines`` as names: known, none twice, the reference and at least one engine to compare with it."""
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    allowed = (f"a comma-separated list of distinct names from {', '.join(ENGINES)}, with {REFERENCE} (the "
               "reference) and at least one engine to compare with it")
    ok = (all(name in ENGINES for name in names) and len(set(names)) == len(names) and REFERENCE in names
          and len(names) > 1)
    if not ok:
        raise ParameterError(f"--engines={text!r} is invalid: allowed {allowed}")
    return names


def _joint_change(engine: str, assignment: str, engines: tuple, joint: JointParameters) -> dict:
    """``--perturb ENGINE NAME=VALUE`` -> {name: value typed as the JointParameters field}, refused in one line
    naming --perturb unless ENGINE is one of ``engines`` besides the reference and ``joint`` admits the value."""
    written = f"--perturb {engine} {assignment}"
    compared = [e for e in engines if e != REFERENCE]
    if engine not in compared:
        raise ParameterError(f"{written} is invalid: allowed a perturbed engine (ENGINE) from --engines other than "
                             f"the reference {REFERENCE}: {', '.join(compared)}")
    name, sep, text = assignment.partition("=")
    defaults = JointParameters()
    if not sep or not hasattr(defaults, name) or name.endswith("offset_m"):
        raise ParameterError(f"{written} is invalid: allowed NAME=VALUE with NAME a scalar JointParameters "
                             "field, e.g. restitution=0.5")
    default = getattr(defaults, name)
    kind = float if default is None else type(default)     # a stiffness given instead of the materials'
    try:
        value = kind(text)
        perturbed = joint.replace(**{name: value})
    except ValueError as exc:   # a ParameterError too: the joint refuses the value
        allowed = str(exc).partition(" is invalid: allowed ")[2] or ("an integer" if kind is int else "a number")
        raise ParameterError(f"{written} is invalid: allowed {name} {allowed}") from None
    for row in unread_by(perturbed.contact_damping, [name]):    # a change the engine's law never reads
        raise ParameterError(f"{written} is invalid: allowed {name} only with contact_damping "
                             f"{' or '.join(row.read_by)} (the run's {perturbed.contact_damping} does not read it, "
                             "so the validation could not fail)")
    return {name: value}


def _number(value, spec: str = ".3g") -> str:
    """``value`` as ``spec`` formats it, "—" for None (summary.json's for a value that is not a number)."""
    return "—" if value is None else f"{value:{spec}}"


def add_arguments(parser) -> None:
    add_output_arguments(parser, plots=False)
    parser.add_argument("--quick", action="store_true",
                        help=f"short smoke version: {QUICK.revolutions:g} rev without wear, {QUICK.wear_revolutions:g} "
                             f"rev of wear at factor {QUICK.wear_factor:g}")
    parser.add_argument("--revolutions", type=float, default=None,
                        help=f"revolutions of the no-wear runs (default {FULL.revolutions:g}, --quick {QUICK.revolutions:g})")
    parser.add_argument("--ensemble", type=int, default=None,
                        help=f"perturbed starts per engine and valid configuration in the no-wear runs (default "
                             f"{FULL.ensemble}, --quick {QUICK.ensemble}; at least 2)")
    parser.add_argument("--wear-revolutions", type=float, default=None,
                        help=f"revolutions of the wear run (default {FULL.wear_revolutions:g}, "
                             f"--quick {QUICK.wear_revolutions:g}); --wear-factor sets its factor "
                             f"(default {FULL.wear_factor:g}, --quick {QUICK.wear_factor:g}); --no-wear skips it")
    parser.add_argument("--window", type=float, default=None,
                        help=f"point-wise comparison over the first WINDOW seconds (default {FULL.window_s:g}; for the "
                             f"paper's {SliderCrankParameters().period_s:g} s revolution, scaled to the mechanism's "
                             f"period: the same share of a turn; at least {min_window_s():g} s, {WINDOW_POINTS} of the "
                             "co-simulation's free-flight steps)")
    parser.add_argument("--engines", type=str, default=",".join(ENGINES),
                        help="comma-separated engines to run (default %(default)s; monolithic is the reference)")
    parser.add_argument("--no-law-spread", action="store_true",
                        help="skip the model-form spread: the answers under every contact damping law and its free "
                             "parameter's range (wearjoint.contact_laws; informs, never judged)")
    parser.add_argument("--perturb", nargs=2, action="append", default=[], metavar=("ENGINE", "NAME=VALUE"),
                        help="self-check: give ENGINE a different joint parameter; the validation must then fail")
    add_fmu_arguments(parser, fmu_file=False, when="the cosim engine")
    add_model_arguments(parser)
    restate_default(parser, "wear_factor", f"{FULL.wear_factor:g}, --quick {QUICK.wear_factor:g}; the wear run's, "
                                           "the no-wear runs use 0")


def run(args) -> int:
    """Exit status: 0 all metrics pass, 1 a metric fails or an engine raised, 3 an engine is
    not available, 2 bad parameters."""
    joint, mechanism = model_from_args(args)
    base = QUICK if args.quick else FULL
    compared = _engine_list(args.engines)
    changes = {}
    for engine, assignment in args.perturb:
        changes.setdefault(engine, {}).update(_joint_change(engine, assignment, compared, joint))
    window_s = args.window if args.window is not None else \
        default_window_s(base.window_s, mechanism.period_s, SliderCrankParameters().period_s)   # a turn's share
    given = {"revolutions": args.revolutions, "ensemble": args.ensemble, "wear_revolutions": args.wear_revolutions,
             "wear_factor": args.wear_factor}
    plan = replace(base, **{name: value for name, value in given.items() if value is not None}, window_s=window_s,
                   engines=compared, run_wear=not args.no_wear, fmu_backend=args.fmu_backend,
                   law_spread=not args.no_law_spread)
    check_spans(plan, mechanism, getattr(args, "written", frozenset()))    # named as written, before any run
    try:     # Ctrl-C (here, or a run it cut short) ends as cli.main says: one line, exit 130
        summary = run_validation(plan, args.out, joint, mechanism, changes, progress=not args.quiet)
    except RunStoppedShort as exc:      # a monolithic run the comparison needs: nothing to judge against
        print(f"wearjoint validate: error: {exc} (a monolithic run the comparison needs)", file=sys.stderr)
        return 1
    engines = summary["engines"]
    for m in summary["metrics"]:
        if not m["passed"]:
            tag = "FAIL" if engines[m["engine"]]["role"] == "joint" else "DIFFERS (its own contact law, not judged)"
            print(f"{tag} {m['group']}: {m['engine']} {m['name']}: difference {_number(m['difference'], '.6g')} > "
                  f"tolerance {_number(m['tolerance'], '.6g')} (scatter {_number(m['scatter'], '.4g')})")
    spread = summary.get("law_spread")
    for name, answer in (spread["answers"] if spread else {}).items():     # informs, never judged
        unit = "" if answer["unit"] == "-" else f" {answer['unit']}"
        print(f"LAW SPREAD {name}: {_number(answer['spread'])}{unit} over {len(spread['variants'])} "
              f"contact-law variants, sampling spread {_number(answer['sampling_spread'])} (ratio "
              f"{_number(answer['ratio'])})")
    for gap in summary["gaps"]:
        print(f"GAP {gap}")
    for error in summary["errors"]:
        print(f"ERROR {error}")
    references = "".join(f"; {engine} (its own contact law, a reference, not judged): {v['within_tolerance']} of "
                         f"{v['metrics']} within tolerance" for engine, v in engines.items() if v["role"] != "joint")
    print(f"{'PASS' if summary['passed'] else 'FAIL'}: {summary['metrics_total'] - len(summary['metrics_failed'])} of "
          f"{summary['metrics_total']} metrics of the engines running the project's joint within tolerance"
          + (f" ({len(undefined)} undefined: {', '.join(undefined)})" if (undefined := summary["metrics_undefined"])
             else "") + f"{references}; report in {args.out / 'report.md'}")
    return summary["exit_status"]


__all__ = ["add_arguments", "run"]
