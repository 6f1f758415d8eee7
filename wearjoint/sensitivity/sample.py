"""SALib's designs: Morris trajectories and Saltelli's extension of the Sobol' sequence.

``--samples N`` is the number of Morris trajectories, N (D + 1) runs for D parameters, or the
Sobol' base sample, N (D + 2) runs (first-order and total indices; no second order).  Both
designs are prefixes of their larger selves: the rows of N are the first rows of 2N with the
same seed, so a larger N (``--target-interval``, ``--resume``) reruns nothing (tested).
"""
from __future__ import annotations

import numpy as np

from ..parameters import ParameterError
from .problem import Problem

METHODS = ("morris", "sobol")
MIN_SAMPLES = {"morris": 2, "sobol": 8}        # fewer leave no spread to bootstrap an interval from
DEFAULT_SAMPLES = {"morris": 10, "sobol": 64}
MORRIS_LEVELS = 4                              # the Morris grid: 4 levels per parameter, steps of 2/3 of the range


def group_size(method: str, n_parameters: int) -> int:
    """Runs per Morris trajectory (D + 1) or per Sobol' base sample (D + 2)."""
    return n_parameters + (1 if method == "morris" else 2)


def check_samples(method: str, n) -> int:
    """N, or a one-line ParameterError naming ``--samples``: an integer >= the method's minimum (Sobol':
    a power of 2, which keeps the Sobol' sequence balanced)."""
    if method not in METHODS:
        raise ParameterError(f"--method={method!r} is invalid: allowed one of {', '.join(METHODS)}")
    least = MIN_SAMPLES[method]
    if isinstance(n, bool) or not isinstance(n, int) or n < least:
        raise ParameterError(f"--samples={n!r} is invalid for --method {method}: allowed an integer >= {least}")
    if method == "sobol" and n & (n - 1):
        raise ParameterError(f"--samples={n!r} is invalid for --method sobol: allowed a power of 2 "
                             f"(e.g. {1 << (n.bit_length() - 1)} or {1 << n.bit_length()})")
    return n


def few_samples_note(method: str, n: int) -> str:
    """What the 95 % intervals of N groups are worth below the method's default N ('' from it on)."""
    if n >= DEFAULT_SAMPLES[method]:
        return ""
    return (f"N = {n} {'trajectories' if method == 'morris' else 'base samples'}: intervals bootstrapped from so "
            f"few are rough (a screening, not an answer); N >= {DEFAULT_SAMPLES[method]} for intervals to rely on")


def check_seed(seed) -> int:
    """``seed``, or a one-line ParameterError naming ``--seed``: an integer SALib's samplers take, 0 .. 2**32 - 1."""
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2 ** 32:
        raise ParameterError(f"--seed={seed!r} is invalid: allowed an integer in [0, {2 ** 32 - 1}]")
    return seed


def sample(problem: Problem, method: str, n: int, seed: int) -> np.ndarray:
    """SALib's sample matrix (rows x parameters, log parameters in log10) of ``n`` trajectories or base
    samples, drawn with ``seed``."""
    check_samples(method, n)
    if method == "morris":
        from SALib.sample import morris

        return morris.sample(problem.salib(), n, num_levels=MORRIS_LEVELS, seed=seed)
    from SALib.sample import sobol

    return sobol.sample(problem.salib(), n, calc_second_order=False, scramble=True, seed=seed)


__all__ = ["METHODS", "MIN_SAMPLES", "DEFAULT_SAMPLES", "MORRIS_LEVELS", "group_size", "check_samples", "check_seed",
           "few_samples_note", "sample"]
