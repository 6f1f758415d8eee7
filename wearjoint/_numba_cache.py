"""Keep numba's on-disk cache consistent with the sources.

numba keys each cached function on its own file's timestamp only, so a kernel
compiled into another module's cache keeps an old copy of a callee (or of a
layout constant) edited since.  Before any kernel is imported, the caches of
the package's kernel folders are dropped whenever any of their sources differ
from the ones they were built from.
"""
import hashlib
from pathlib import Path

STAMP = "kernels.sha256"


def kernel_folders() -> list[Path]:
    """Folders holding the package's cached numba kernels (source tree or installed)."""
    root = Path(__file__).parent
    candidates = [root, root / "core", root / "cosim", root / "validation", root.parent / "validation"]
    return [folder for folder in candidates if (folder / "__init__.py").is_file()]


def drop_stale_numba_cache() -> None:
    folders = kernel_folders()
    digest = hashlib.sha256(b"".join(p.read_bytes() for folder in folders
                                     for p in sorted(folder.glob("*.py")))).hexdigest()
    for folder in folders:
        cache = folder / "__pycache__"
        stamp = cache / STAMP
        try:
            if stamp.read_text() == digest:
                continue
        except OSError:
            pass
        try:
            for stale in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
                stale.unlink()
            cache.mkdir(exist_ok=True)
            stamp.write_text(digest)
        except OSError:  # read-only install: numba then compiles in memory or uses NUMBA_CACHE_DIR
            pass
