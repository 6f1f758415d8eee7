"""A cold run's second core: what the running command will need next, compiled in a second process.

``python -m wearjoint._compile.prefetch kernels`` (:func:`start`): numba compiles one function at a time, and
a cold ``simulate`` reaches its kernels in one order: the mechanism, the contact, the integrators, then the
wear and the step's record.  This process compiles the wear's accept step, the step's record and the worn
volume with the argument types the engine passes (C-contiguous float64 arrays, a bool mask), so numba's
cache, which the two processes share, serves them to the first when it gets there; one it reaches before
the second has cached it is compiled twice, which costs nothing but the second core.  (The joint FMU a
co-simulation will load is built in a second process likewise: :func:`wearjoint.fmu.ensure.start_fmu_build`.)
"""
from __future__ import annotations

import atexit
import os
import subprocess
import sys


def usable_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system has one, e.g. under taskset)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def start() -> subprocess.Popen | None:
    """The kernels' second process, in the background, stopped when this one exits if it is still running
    (None on one core, or if it cannot start)."""
    if usable_cores() < 2:
        return None
    try:
        process = subprocess.Popen([sys.executable, "-m", __name__, "kernels"], stdin=subprocess.DEVNULL,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except OSError:
        return None
    atexit.register(_stop, process)
    return process


def _stop(process: subprocess.Popen) -> None:
    """Stop the second process (numba writes each cache file whole: stopping it loses nothing cached)."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            process.kill()


def compile_late_kernels() -> None:
    """Call the wear's accept step, the step's record and the worn volume once on
    an unworn joint at rest (nothing in contact): numba compiles them, and caches them."""
    import numpy as np

    from ..core import layout as L
    from ..core.integrators import record_step
    from ..core.wear import accept_contact_refreshing, worn_volume
    from ..joint import ClearanceJoint
    from ..parameters import JointParameters
    from ..results import new_revolution_stats, new_track

    joint = ClearanceJoint(JointParameters())
    at_rest = np.zeros(3)
    accept_contact_refreshing(joint.result, at_rest, at_rest.copy(), at_rest.copy(), at_rest.copy(), 1e-6,
                              joint.parameter_vector, joint.cos_phi, joint.sin_phi, joint.wear_depth, joint.block_min,
                              joint.memory, joint.mask, joint.work)
    y = np.zeros(2 * L.N_COORDINATES)
    record_step(0.0, 1e-6, y, y.copy(), joint.result, np.zeros(L.N_MECHANISM_PARAMETERS), new_revolution_stats(1),
                np.zeros((0, L.N_SAMPLE_COLUMNS)), new_track(1e-3))
    worn_volume(joint.parameter_vector, joint.wear_depth)


if __name__ == "__main__":
    compile_late_kernels()
