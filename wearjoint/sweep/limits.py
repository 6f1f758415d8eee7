"""The sizes a sweep may ask for: its seeds (an ensemble's starts) and its local Dask cluster's workers."""
from __future__ import annotations

from ..parameters import ParameterError

MAX_SEEDS = 10_000          # an ensemble's starts (1e9 made the sweep silent for minutes while it listed its cases)
WORKERS_PER_CORE = 4        # a LocalCluster's worker processes per usable core (1e9 workers: killed for its memory)


def check_seeds(seeds, where: str = "--seeds") -> int:
    if isinstance(seeds, bool) or not isinstance(seeds, int) or not 1 <= seeds <= MAX_SEEDS:
        raise ParameterError(f"{where}={seeds!r} is invalid: allowed an integer from 1 to {MAX_SEEDS}")
    return seeds


def check_workers(workers, where: str = "--workers") -> int:
    """The local Dask cluster's worker processes: at most WORKERS_PER_CORE per core this process may use (a larger
    cluster: a scheduler of its own, ``--scheduler``)."""
    from .._compile.prefetch import usable_cores

    most = WORKERS_PER_CORE * usable_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= most:
        raise ParameterError(f"{where}={workers!r} is invalid: allowed an integer from 1 to {most} ({WORKERS_PER_CORE} "
                             "per usable core; a larger cluster through --scheduler ADDRESS)")
    return workers


def check_cluster(workers, scheduler) -> None:
    """``--workers`` sizes a cluster of this machine: refused with ``--scheduler``, whose workers run the cases (it had
    been ignored, and sweep_summary.json gave the scheduler's count)."""
    if workers is not None and scheduler is not None:
        raise ParameterError(f"--workers={workers!r} is invalid with --scheduler={scheduler!r}: allowed without it (the "
                             "scheduler's own workers run the cases; --workers sizes a cluster on this machine)")


__all__ = ["MAX_SEEDS", "WORKERS_PER_CORE", "check_cluster", "check_seeds", "check_workers"]
