"""Keep numba's on-disk cache consistent with the sources.

numba keys each cached function on its own file's timestamp only, so a kernel
compiled into another module's cache keeps an old copy of a callee (or of a
layout constant) edited since.  Before any kernel is imported, the caches of
the package's kernel folders are dropped whenever any source a kernel can
depend on differs from the ones they were built from: every module of
``core/`` and ``cosim/``, and elsewhere the modules that define kernels
(an edit to ``plots.py`` or ``cli/`` recompiles nothing).
"""
import hashlib
from pathlib import Path

STAMP = "kernels.sha256"
KERNEL_PACKAGES = ("core", "cosim")     # whole: their modules hold kernels and the constants kernels compile in


def kernel_folders() -> list[Path]:
    """Folders holding the package's cached numba kernels (source tree or installed)."""
    root = Path(__file__).parent
    candidates = [root, *(root / name for name in KERNEL_PACKAGES), root / "validation", root.parent / "validation"]
    return [folder for folder in candidates if (folder / "__init__.py").is_file()]


def kernel_sources(folders: list[Path]) -> list[Path]:
    """The sources a compiled kernel can depend on: every module of the KERNEL_PACKAGES folders, and in the
    other folders those that define a kernel (``@kernel``)."""
    sources = []
    for folder in folders:
        for path in sorted(folder.glob("*.py")):
            if folder.name in KERNEL_PACKAGES or b"@kernel" in path.read_bytes():
                sources.append(path)
    return sources


def kernel_digest(folders: list[Path]) -> str:
    """SHA-256 of :func:`kernel_sources` (their names and contents)."""
    digest = hashlib.sha256()
    for path in kernel_sources(folders):
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def drop_stale_numba_cache() -> None:
    folders = kernel_folders()
    digest = kernel_digest(folders)
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
