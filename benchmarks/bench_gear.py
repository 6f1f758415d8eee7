"""``--integrator gear`` (BDF) on the paper case: exact vs numerical Jacobian, scipy vs CVODE.

For each case (one revolution without wear, and with wear factor 100) and each solver
(``gear_solver``: SUNDIALS CVODE through scikit-sundae, scipy's BDF) and Jacobian (``gear_jacobian``:
exact, :mod:`wearjoint.core.slider_crank_jacobian`; numerical, the solver's finite differences), prints
accepted and rejected steps, right-hand-side evaluations (outside finite-difference Jacobians, and
with them: 18 per numerical Jacobian), Jacobian evaluations, LU decompositions, wall time
(compilation excluded; the median of ``--repeats`` runs, all in this invocation) and the run's
statistics, with the machine's load.

Rejected steps of scipy's BDF are counted from its Newton solves (each attempt solves once, plus
once more after each Jacobian update that a failed Newton iteration asks for): rejected = solves -
(Jacobian evaluations - solvers) - accepted.  scikit-sundae exposes neither CVODE's rejected steps
nor its LU count (n/a).

    python benchmarks/bench_gear.py [--revolutions 1] [--repeats 3]
"""
from __future__ import annotations

import argparse
import statistics

import scipy.integrate._ivp.bdf as scipy_bdf

from wearjoint.core.layout import N_COORDINATES
from wearjoint.parameters import paper_joint
from wearjoint.simulate import GEAR_JACOBIANS, GEAR_SOLVERS, SimulationOptions, run_simulation

from repeats import Load, add_repeats_argument, median_text

CASES = (("no wear", 0.0), ("wear factor 100", 100.0))


class ScipyCounts:
    """Counts scipy BDF's solvers and Newton solves while installed (a benchmark-only patch)."""

    def __init__(self):
        self.solvers = self.solves = 0
        self._solve, self._init = scipy_bdf.solve_bdf_system, scipy_bdf.BDF.__init__

    def __enter__(self):
        def solve(*args, **kwargs):
            self.solves += 1
            return self._solve(*args, **kwargs)

        def init(solver, *args, **kwargs):
            self.solvers += 1
            self._init(solver, *args, **kwargs)
        scipy_bdf.solve_bdf_system, scipy_bdf.BDF.__init__ = solve, init
        return self

    def __exit__(self, *exc):
        scipy_bdf.solve_bdf_system, scipy_bdf.BDF.__init__ = self._solve, self._init


def run(wear_factor: float, revolutions: float, solver: str, jacobian: str) -> dict:
    options = SimulationOptions(revolutions=revolutions, integrator="gear", gear_solver=solver, gear_jacobian=jacobian)
    with ScipyCounts() as counts:
        s = run_simulation(paper_joint(wear_factor=wear_factor), options=options, progress=False).summary()
    row = {"wall": s["wall_time_s"], "steps": s["integrator_accepted_steps"], "rhs": s["integrator_rhs_evaluations"],
           "jac": s["integrator_jacobian_evaluations"], "lu": s.get("integrator_lu_decompositions"),
           "impacts": s["impacts_per_revolution"], "force": s["max_contact_force_N"],
           "wear": s["max_wear_depth_m"], "rejected": None}
    row["all_rhs"] = row["rhs"] + (2 * N_COORDINATES * row["jac"] if jacobian == "numerical" else 0)
    if solver == "scipy":
        row["rejected"] = counts.solves - (row["jac"] - counts.solvers) - row["steps"]
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=1.0, help="revolutions per run (default 1)")
    add_repeats_argument(parser)
    args = parser.parse_args()
    configurations = [(case, wear, solver, jacobian) for case, wear in CASES for solver in GEAR_SOLVERS
                      for jacobian in GEAR_JACOBIANS]
    for case, wear, solver, jacobian in configurations:     # compile (numba) before the timed runs
        run(wear, 1e-3, solver, jacobian)
    load = Load()
    runs = {c: [] for c in configurations}
    for _ in range(args.repeats):
        for c in configurations:
            runs[c].append(run(c[1], args.revolutions, c[2], c[3]))
    load.stop()
    print(f"paper case, gear (BDF), {args.revolutions:g} revolution(s), rtol 1e-6, max step 1e-4 s (1e-5 s with "
          f"wear); wall time the median of {args.repeats} runs; {load}")
    print(f"{'case':16s} {'solver':6s} {'jacobian':9s} {'steps':>7s} {'rejected':>8s} {'rhs':>7s} {'rhs+FD':>7s} "
          f"{'jac':>6s} {'LU':>6s} {'wall s':>7s} {'impacts/rev':>11s} {'F_max N':>8s} {'wear um':>8s}   "
          "wall s of each run")
    for c in configurations:
        r = runs[c][0]         # deterministic: every repeat has the same counts
        wall = statistics.median(each["wall"] for each in runs[c])
        text = lambda value: "n/a" if value is None else str(value)   # noqa: E731
        print(f"{c[0]:16s} {c[2]:6s} {c[3]:9s} {r['steps']:7d} {text(r['rejected']):>8s} {r['rhs']:7d} "
              f"{r['all_rhs']:7d} {r['jac']:6d} {text(r['lu']):>6s} {wall:7.2f} {r['impacts']:11d} "
              f"{r['force']:8.0f} {r['wear'] * 1e6:8.2f}   " + median_text([each["wall"] for each in runs[c]], ".2f"))


if __name__ == "__main__":
    main()
