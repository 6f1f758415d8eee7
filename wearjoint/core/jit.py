"""How the kernels are compiled.

:func:`kernel` is numba's ``njit(cache=True)`` without its reference-counted
memory management (NRT).  The kernels never allocate; under NRT every array
argument, view and tuple element a compiled function touches is reference
counted with atomic increments and decrements, and in the integrators' loop
those cost more than the physics: with NRT, 57 % of the samples of a
Dormand-Prince run were in NRT's two reference-count helpers, and a step took
4.3 us instead of 2.0 us (``perf record`` on this machine).  Functions that
allocate arrays keep plain ``njit(cache=True)``; numba refuses to compile an
allocation in a kernel ("NRT required but not enabled").
"""
from numba import njit

from .._compile import cache

cache.install()   # before the first kernel is decorated: numba picks a kernel's cache locator then


def kernel(function=None, *, inline="never"):
    """Decorator: ``@kernel`` or ``@kernel(inline='always')``."""
    decorate = njit(cache=True, inline=inline, _nrt=False, error_model="numpy")
    return decorate if function is None else decorate(function)
