"""SALib's analyses of a design's outputs, with bootstrap confidence intervals.

Sobol' (Saltelli 2010 first-order, Jansen total estimators): S1 and ST per parameter and their 95 %
half-intervals ``S1_conf``, ``ST_conf`` (dimensionless).  Morris: the mean absolute elementary
effect mu* (the output's change over a parameter's full range, in the output's unit; a log
parameter's range is its log10 range), its 95 % half-interval ``mu_star_conf``, sigma and mu.
Groups with a failed or missing run (a Sobol' base sample's D + 2 runs, a Morris trajectory's
D + 1) are left out: the analysis uses the complete ones.
"""
from __future__ import annotations

import numpy as np

from .problem import Problem
from .sample import MIN_SAMPLES, group_size

CONF_LEVEL = 0.95
RESAMPLES = 1000
EFFECT = {"sobol": "ST", "morris": "mu_star"}              # what ranks the parameters
COLUMNS = {"sobol": ("S1", "S1_conf", "ST", "ST_conf"), "morris": ("mu_star", "mu_star_conf", "sigma", "mu")}


def complete_groups(method: str, n_parameters: int, y: np.ndarray) -> np.ndarray:
    """Indices of the groups (trajectories / base samples) whose runs all have a finite output ``y``."""
    size = group_size(method, n_parameters)
    finite = np.isfinite(np.asarray(y, dtype=float)).reshape(-1, size)
    return np.flatnonzero(finite.all(axis=1))


def analyse(problem: Problem, method: str, x: np.ndarray, y: np.ndarray, seed: int) -> dict:
    """The indices of one output: ``{"groups": used, "dropped": left out, "constant": bool, "indices":
    [{"parameter", "api_name", *COLUMNS[method]}, ...]}`` (``indices`` empty when fewer complete groups than
    the method's minimum remain).  ``x``: SALib's sample matrix; ``y``: the output per row (NaN: no value)."""
    d = len(problem.parameters)
    size = group_size(method, d)
    keep = complete_groups(method, d, y)
    rows = (keep[:, None] * size + np.arange(size)).ravel()
    xs, ys = np.asarray(x, dtype=float)[rows], np.asarray(y, dtype=float)[rows]
    result = {"groups": int(keep.size), "dropped": int(len(y) // size - keep.size), "constant": False, "indices": []}
    if keep.size < MIN_SAMPLES[method]:
        return result
    if np.ptp(ys) == 0.0:                        # no variance to share out: every index is 0
        result["constant"] = True
        values = {c: np.zeros(d) for c in COLUMNS[method]}
    elif method == "sobol":
        from SALib.analyze import sobol

        # seed + 1: SALib's Sobol' bootstrap is unseeded for a seed of 0
        values = sobol.analyze(problem.salib(), ys, calc_second_order=False, num_resamples=RESAMPLES,
                               conf_level=CONF_LEVEL, seed=seed + 1)
    else:
        from SALib.analyze import morris
        from .sample import MORRIS_LEVELS

        values = morris.analyze(problem.salib(), xs, ys, num_resamples=RESAMPLES, conf_level=CONF_LEVEL,
                                num_levels=MORRIS_LEVELS, seed=seed + 1)
    result["indices"] = [{"parameter": p.name, "api_name": p.dest, **{c: float(values[c][k]) for c in COLUMNS[method]}}
                         for k, p in enumerate(problem.parameters)]
    return result


def widest_interval(method: str, result: dict) -> float:
    """The widest 95 % half-interval of an analysis: Sobol', the largest S1_conf or ST_conf; Morris, the
    largest mu_star_conf as a share of the largest mu* (0 for a constant output; NaN without indices)."""
    rows = result["indices"]
    if not rows:
        return float("nan")
    if method == "sobol":
        return max(max(r["S1_conf"], r["ST_conf"]) for r in rows)
    top = max(r["mu_star"] for r in rows)
    return 0.0 if top == 0.0 else max(r["mu_star_conf"] for r in rows) / top


def convergence(problem: Problem, method: str, x: np.ndarray, y: np.ndarray, seed: int) -> list:
    """The widest interval of the analysis of the design's first n groups, n = the method's minimum, doubling,
    up to all groups: ``[(n, widest), ...]`` (the designs are prefixes of their larger selves)."""
    size = group_size(method, len(problem.parameters))
    total = len(y) // size
    counts, n = [], MIN_SAMPLES[method]
    while n < total:
        counts.append(n)
        n *= 2
    counts.append(total)
    return [(n, widest_interval(method, analyse(problem, method, x[:n * size], y[:n * size], seed))) for n in counts]


def until_target(problem: Problem, method: str, n: int, seed: int, evaluate, target: float | None = None,
                 max_samples: int | None = None) -> dict:
    """Sample ``n`` groups with ``seed``, evaluate and analyse them; with ``target`` double ``n`` (at most to
    ``max_samples``) until every output's :func:`widest_interval` is <= ``target``.  ``evaluate(x)`` returns
    ({output: value per row of x}, a dict of facts for the round's record, whether to stop now).  Returns the
    last round's ``samples``, ``x``, ``y``, ``results`` (output -> :func:`analyse`), all ``rounds``, ``met``
    (None without a target) and ``stopped``."""
    from .sample import sample

    rounds = []
    while True:
        x = sample(problem, method, n, seed)
        y, facts, stop = evaluate(x)
        results = {name: analyse(problem, method, x, values, seed) for name, values in y.items()}
        widest = {name: widest_interval(method, r) for name, r in results.items()}
        rounds.append({"samples": n, "runs": len(x), **facts, "widest_interval": widest})
        met = None if target is None else all(w <= target for w in widest.values())
        if stop or not target or met or max_samples is None or 2 * n > max_samples:
            return {"samples": n, "x": x, "y": y, "results": results, "rounds": rounds, "met": met, "stopped": stop}
        n *= 2


__all__ = ["until_target", "analyse", "widest_interval", "convergence", "complete_groups", "CONF_LEVEL", "RESAMPLES", "EFFECT",
           "COLUMNS"]
