"""The systematic uncertainty a sweep can state: the wear factor's bias on the max wear depth.

A wear factor F > 1 lets one simulated revolution stand for F crank revolutions; its answer differs
from the brute-force run (F = 1) by a bias that the scatter over seeds does not show.
:data:`WEAR_FACTOR_BIAS` holds that bias as measured by ``wearjoint wear-study --convergence``
(:data:`SOURCE`) on the paper's mechanism and joint at k_w 5.576e-11 m^2/N; a run of that case takes its bias
from it where its factor and revolution count match.  Any other run's is unknown: its note says how to measure
it (``wear-study --convergence jump,F``: the factor against the error-controlled cycle-jumping route on the
same mechanism and horizon).  Without wear, or at F = 1 (brute force or cycle jumping, which states its own error
estimate), there is no wear-factor bias (0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..parameters import (PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N, PAPER_JOINT_GEOMETRY, JointParameters,
                          ParameterError, SliderCrankParameters, is_paper_case)

SOURCE = ("docs/explanation/wear_study.md, 'Reaching 4000 revolutions: the wear factor' (F = 10, 50, 100 against 4000 "
          "brute-force revolutions at F = 1; the paper case, k_w 5.576e-11 m^2/N, foundation contact and placement, "
          "Hunt-Crossley damping with the exact coefficient, the relaxed wear update, RK4 at 1e-5 s)")
# F -> {crank revolutions R: max depth at F / max depth at F = 1 - 1}, from SOURCE's table
WEAR_FACTOR_BIAS = {
    10.0: {500: -0.027, 1000: -0.009, 2000: -0.009, 3000: -0.012, 4000: -0.014},
    50.0: {500: -0.021, 1000: -0.066, 2000: -0.082, 3000: -0.085, 4000: -0.086},
    100.0: {500: -0.035, 1000: -0.081, 2000: -0.098, 3000: -0.101, 4000: -0.103},
}
UNKNOWN = "unknown"
MEASURE_IT = ("measure it for this mechanism and horizon: wearjoint wear-study --convergence jump,{F} --revolutions "
              "{R} with the run's model options (docs/tutorials/own_mechanism.md)")


@dataclass(frozen=True)
class Bias:
    """The max depth's relative bias ``rel`` (None: unknown) and where it comes from."""

    rel: float | None
    note: str

    @property
    def text(self) -> str:
        """E.g. ``-8.4 %``, ``0 %`` or ``unknown``."""
        return UNKNOWN if self.rel is None else "0 %" if self.rel == 0.0 else f"{self.rel * 100:+.1f} %"

    @property
    def csv(self):
        """The value for a CSV cell: the relative bias, or ``unknown``."""
        return UNKNOWN if self.rel is None else self.rel

    @classmethod
    def from_csv(cls, cell: str, note: str = "") -> "Bias":
        """The bias a CSV cell (:attr:`csv`) holds."""
        return cls(None if cell == UNKNOWN else float(cell), note)


def wear_factor_bias(wear_factor: float, revolutions: float, cycle_jump: bool = False,
                     measured_case: bool = True) -> Bias:
    """The bias of the max depth after ``revolutions`` crank revolutions at wear factor ``wear_factor``
    (0: no wear); ``cycle_jump``: the run jumped over revolutions (at F = 1: no wear-factor bias; each run states
    its own error estimate in its summary.json, ``cycle_jumping``); ``measured_case``: the run is the case
    :data:`SOURCE` measured (:func:`is_measured_case`)."""
    if not wear_factor > 0.0:
        return Bias(0.0, "none: no wear")
    if wear_factor == 1.0 and not cycle_jump:
        return Bias(0.0, "none: F = 1 (brute force)")
    if wear_factor == 1.0:
        return Bias(0.0, "none: F = 1 (cycle jumping, whose own error estimate is each run's summary.json's "
                         "cycle_jumping)")
    if cycle_jump:
        return Bias(None, "unknown here: cycle jumping states its error estimate in summary.json's cycle_jumping")
    if not measured_case:
        return Bias(None, "unknown: measured on the paper's case only; "
                          + MEASURE_IT.format(F=f"{wear_factor:g}", R=f"{revolutions:g}"))
    for factor, by_revolution in WEAR_FACTOR_BIAS.items():
        for revolution, rel in by_revolution.items():
            if math.isclose(wear_factor, factor, rel_tol=1e-9) and math.isclose(revolutions, revolution, rel_tol=1e-9):
                return Bias(rel, f"measured: {SOURCE}")
    revs = ", ".join(str(r) for r in sorted({r for table in WEAR_FACTOR_BIAS.values() for r in table}))
    return Bias(None, f"unknown: not measured at F = {wear_factor:g} and these revolutions (measured: F = "
                      f"{', '.join(f'{f:g}' for f in WEAR_FACTOR_BIAS)} at {revs} rev)")


def common_bias(biases: set) -> Bias:
    """One :class:`Bias` for several runs' (a set, not empty): theirs where they agree in value (the notes of
    the runs joined by "; " where they differ: no wear in some, F = 1 in others), else unknown."""
    values = {b.rel for b in biases}
    if len(values) != 1 or None in values:
        return Bias(None, "unknown: the runs differ in wear factor or revolutions")
    return Bias(values.pop(), "; ".join(sorted({b.note for b in biases})))


def is_measured_case(joint: dict, mechanism: dict) -> bool:
    """Are a summary's parameter dicts the case :data:`SOURCE` measured: the paper's mechanism and joint geometry
    (:func:`wearjoint.parameters.is_paper_case`) at its wear coefficient?"""
    try:
        mech = SliderCrankParameters.from_dict(mechanism)
        geometry = JointParameters(**{k: joint[k] for k in PAPER_JOINT_GEOMETRY}, **mech.joint_defaults())
    except (KeyError, TypeError, ParameterError):
        return False
    return (is_paper_case(geometry, mech)
            and math.isclose(joint.get("wear_coefficient_m2_N", math.nan), PAPER_CALIBRATED_WEAR_COEFFICIENT_M2_N,
                             rel_tol=1e-9))


def summary_biases(summary: dict) -> dict:
    """{figure column: Bias} for a case's summary.json: ``max_wear_depth_m`` and, for a wear study,
    ``revR_max_wear_depth_m`` per snapshot R (the revolutions the run stands for: R, or F x the
    simulated revolutions of simulate and cosim)."""
    joint = summary.get("parameters", {}).get("joint", {})
    factor = joint.get("wear_factor", 1.0) if joint.get("wear_coefficient_m2_N", 1.0) > 0.0 else 0.0
    measured = is_measured_case(joint, summary.get("parameters", {}).get("mechanism", {}))
    study = summary.get("parameters", {}).get("study")
    if study is None:
        return {"max_wear_depth_m": wear_factor_bias(factor, factor * summary.get("revolutions", math.nan),
                                                     measured_case=measured)}
    jump = study.get("jump_tolerance") is not None
    out = {f"rev{s['revolution']}_max_wear_depth_m": wear_factor_bias(factor, s["revolution"], jump, measured)
           for s in summary.get("snapshots", [])}
    out["max_wear_depth_m"] = wear_factor_bias(factor, summary.get("revolutions", math.nan), jump, measured)
    return out


__all__ = ["Bias", "WEAR_FACTOR_BIAS", "SOURCE", "UNKNOWN", "wear_factor_bias", "summary_biases", "common_bias",
           "is_measured_case"]
