"""Numba kernels: pure functions on plain arrays (no FMI, no I/O).

``contact`` (Eqs. 1-23), ``wear`` (Eqs. 24-35), ``mechanism`` (Eqs. 38-44),
``integrators`` (RK4, Dormand-Prince 5(4) and the per-step bookkeeping);
``layout`` names the positions in the shared arrays.

numba's on-disk cache is keyed on each file's own timestamp, so a kernel
compiled into another module's cache keeps an old copy of a callee edited
since.  Before any kernel is imported, the cache of this package is dropped
when the kernels' sources differ from the ones it was built from.
"""
import hashlib
from pathlib import Path


def _drop_stale_numba_cache() -> None:
    here = Path(__file__).parent
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(here.glob("*.py")))).hexdigest()
    cache = here / "__pycache__"
    stamp = cache / "kernels.sha256"
    try:
        if stamp.read_text() == digest:
            return
    except OSError:
        pass
    try:
        for stale in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            stale.unlink()
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:  # read-only install: numba then compiles in memory or uses NUMBA_CACHE_DIR
        pass


_drop_stale_numba_cache()
