"""`wearjoint validate`'s model-form spread: the key answers under every contact damping law.

No damping law is singled out by the paper's dynamics (docs/reference/model.md §3.5), so the law is an error bar of its own.
Each variant of :func:`wearjoint.contact_laws.contact_law_variants` (each law, and each law's free parameter at the
ends of its plausible range) is applied to the user's joint (``joint.replace(**changes)``) and run by the monolithic
engine as validate runs its valid DOPRI configuration: the plan's no-wear revolutions over the plan's ensemble of
perturbed starts (answers: the means of the starts), plus one wear run at the plan's wear revolutions and factor (the
wear ensembles' DOPRI options) when the plan wears.  Per answer: the value under each variant, the spread
(max - min over the variants) and beside it the sampling spread, the same max - min over validate's equally valid
monolithic runs (the ensemble means of the reference and of every valid configuration; for the wear depth every
single wear run of the wear ensembles), and their ratio.

The stage informs and is never judged: a variant that raises is listed in its ``errors``, and validate's exit
status stays that of its engine comparisons.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from wearjoint.against_ideal import slider_acc_error_max
from wearjoint.analysis import ensemble_mean_std, revolution_statistics
from wearjoint.contact_laws import contact_law_variants
from wearjoint.parameters import JointParameters, SliderCrankParameters
from wearjoint.sweep.design import perturbed_start
from wearjoint.validation.compare import DOPRI_RTOLS, WEAR_CONFIGURATIONS, Runs, ValidationPlan, _log, run_monolithic

STAGE = "model-form spread (contact law)"
# validate's own DOPRI configurations: the statistics' "DOPRI rtol 1e-06" and the wear ensembles' DOPRI
NO_WEAR_OPTIONS = {"integrator": "dopri", "rtol": DOPRI_RTOLS[0]}
WEAR_OPTIONS = next(o for o in WEAR_CONFIGURATIONS.values() if o["integrator"] == "dopri")
# answer -> unit (SI; the key names it)
ANSWERS = {"contact_fraction": "-", "impacts_per_revolution": "1/rev", "max_contact_force_N": "N",
           "slider_acc_error_max_m_s2": "m/s²", "max_wear_depth_m": "m"}
ENSEMBLE_ANSWERS = ("contact_fraction", "impacts_per_revolution", "max_contact_force_N", "slider_acc_error_max_m_s2")


def run_answers(record) -> dict:
    """The no-wear answers of one run: three :func:`revolution_statistics` and
    :func:`wearjoint.against_ideal.slider_acc_error_max`."""
    stats = revolution_statistics(record)
    return {**{name: stats[name] for name in ENSEMBLE_ANSWERS[:3]},
            "slider_acc_error_max_m_s2": slider_acc_error_max(record)}


def ensemble_answers(records) -> tuple[dict, dict]:
    """(mean, sample standard deviation) over an ensemble's runs of each :func:`run_answers` answer."""
    return ensemble_mean_std([run_answers(r) for r in records])


@dataclass
class LawSpreadRuns:
    """The stage's records: ``variants`` ((label, joint changes), ...), ``ensembles`` label -> the no-wear runs of
    its perturbed starts, ``wear`` label -> its wear run; ``errors`` of variants that raised; ``log`` (label, record)
    of every run; ``wall_time_s`` of the whole stage (compilation included)."""

    variants: tuple
    ensembles: dict = field(default_factory=dict)
    wear: dict = field(default_factory=dict)
    errors: list = field(default_factory=list)
    log: list = field(default_factory=list)
    wall_time_s: float = 0.0


def run_law_spread(plan: ValidationPlan, joint: JointParameters, mechanism: SliderCrankParameters,
                   progress: bool = True) -> LawSpreadRuns:
    """Every variant's no-wear ensemble and (``plan.run_wear``) wear run, one progress line per run on stderr."""
    start_time = time.perf_counter()
    spread = LawSpreadRuns(contact_law_variants(mechanism))
    dt, rev, wrev = plan.sample_dt_s, plan.revolutions, plan.wear_revolutions
    total = len(spread.variants) * (plan.ensemble + (1 if plan.run_wear else 0))
    _log(progress, f"{STAGE}: {len(spread.variants)} variants of contact_law_variants, {total} runs (informs, "
                   "never judged)")

    def run(label, make):
        _log(progress, f"law spread [{len(spread.log) + 1}/{total}] {label} ...")
        record = make()
        spread.log.append((label, record))
        _log(progress, f"law spread [{len(spread.log)}/{total}] {label}: {record.simulated_time_s:.4g} s simulated "
                       f"in {record.wall_time_s:.1f} s wall")
        return record

    def failed(label, exc):
        spread.errors.append(f"{label}: failed ({type(exc).__name__}: {exc})")
        _log(progress, f"{STAGE}: {spread.errors[-1]}")

    for label, changes in spread.variants:
        try:
            j = joint.replace(wear_factor=0.0, **changes)
            spread.ensembles[label] = [
                run(f"monolithic DOPRI rtol {NO_WEAR_OPTIONS['rtol']:g}, {label}, {rev:g} rev, no wear, "
                    f"start {k + 1}/{plan.ensemble}",
                    lambda m=perturbed_start(mechanism, k): run_monolithic(j, m, rev, dt, progress, **NO_WEAR_OPTIONS))
                for k in range(plan.ensemble)]
        except Exception as exc:     # a variant the user's joint cannot take must not stop validate
            failed(label, exc)
        if plan.run_wear:
            try:
                j = joint.replace(wear_factor=plan.wear_factor, **changes)
                spread.wear[label] = run(f"monolithic DOPRI rtol {WEAR_OPTIONS['rtol']:g}, {label}, {wrev:g} rev, "
                                         f"wear factor {plan.wear_factor:g}",
                                         lambda: run_monolithic(j, mechanism, wrev, dt, progress, **WEAR_OPTIONS))
            except Exception as exc:
                failed(f"{label} (wear run)", exc)
    spread.wall_time_s = time.perf_counter() - start_time
    return spread


def _range(values) -> float | None:
    """max - min of the finite values (None with fewer than two)."""
    finite = [v for v in values if v is not None and math.isfinite(v)]
    return float(max(finite) - min(finite)) if len(finite) >= 2 else None


def _answer(unit: str, values: list, sampling: list, std: list | None = None) -> dict:
    spread, sampling_spread = _range(values), _range(sampling)
    out = {"unit": unit, "values": values, "spread": spread, "sampling_spread": sampling_spread,
           "ratio": spread / sampling_spread if spread is not None and sampling_spread else None}
    if std is not None:
        out["std_of_starts"] = std
    return out


def law_spread_summary(spread: LawSpreadRuns, runs: Runs, plan: ValidationPlan) -> dict:
    """summary.json's ``law_spread``: per answer the value under each variant (None where it failed), the spread,
    the sampling spread from validate's valid monolithic runs, their ratio (and the starts' standard deviation)."""
    labels = [label for label, _ in spread.variants]
    stats = {label: ensemble_answers(members) for label, members in spread.ensembles.items()}
    valid = [ensemble_answers(members)[0] for members in (runs.reference_ensemble, *runs.scatter.values())]
    answers = {}
    for name in ENSEMBLE_ANSWERS:
        answers[name] = _answer(ANSWERS[name], [stats[lb][0][name] if lb in stats else None for lb in labels],
                                [v[name] for v in valid],
                                [stats[lb][1][name] if lb in stats else None for lb in labels])
    if plan.run_wear:
        wear_runs = [*runs.wear_reference, *(r for members in runs.wear_scatter.values() for r in members)]
        answers["max_wear_depth_m"] = _answer(
            ANSWERS["max_wear_depth_m"],
            [float(spread.wear[lb].wear_depth_m.max()) if lb in spread.wear else None for lb in labels],
            [float(r.wear_depth_m.max()) for r in wear_runs])
    n_wear = len(runs.wear_reference) + sum(len(members) for members in runs.wear_scatter.values())
    return {
        "stage": STAGE,
        "judged": False,
        "variants": labels,
        "joint_changes": [changes for _, changes in spread.variants],
        "no_wear_runs": {"options": NO_WEAR_OPTIONS, "revolutions": plan.revolutions, "ensemble": plan.ensemble},
        "wear_run": ({"options": WEAR_OPTIONS, "revolutions": plan.wear_revolutions, "wear_factor": plan.wear_factor}
                     if plan.run_wear else None),
        "spread": "max - min of the values over the variants",
        "sampling_spread": "max - min of the same answer over validate's equally valid monolithic runs: the "
                           f"ensemble means of the reference and of {len(runs.scatter)} valid configurations"
                           + (f"; the max wear depth of each of the wear ensembles' {n_wear} single runs"
                              if plan.run_wear else ""),
        "answers": answers,
        "errors": spread.errors,
        "runs": len(spread.log),
        "wall_time_s": spread.wall_time_s,
    }


__all__ = ["STAGE", "ANSWERS", "run_answers", "ensemble_answers", "LawSpreadRuns",
           "run_law_spread", "law_spread_summary"]
