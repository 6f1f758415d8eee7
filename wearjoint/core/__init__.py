"""Numba kernels: pure functions on plain arrays (no FMI, no I/O).

``contact`` (Eqs. 1-23), ``wear`` (Eqs. 24-35), ``mechanism`` (Eqs. 38-44),
``integrators`` (RK4, Dormand-Prince 5(4) and the per-step bookkeeping);
``layout`` names the positions in the shared arrays.  numba caches them outside the
source tree, one folder per version of their sources (:mod:`wearjoint._compile.cache`).
"""
