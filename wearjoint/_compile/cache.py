"""numba's on-disk cache of the package's kernels: outside the source tree, one folder per version of
the kernels' sources.

numba keys a cached function on its own file's contents only, so a kernel compiled into another
module's cache would keep an old copy of a callee or of a layout constant edited since.  The package's
kernels are therefore cached in a folder named by a digest of every source a kernel can depend on
(:func:`kernel_sources`: every module of ``core/`` and ``cosim/``, elsewhere the modules that define a
kernel): an edit to one of them starts a new folder, an edit to ``plots.py`` or ``cli/`` recompiles
nothing.  The folders are under ``$NUMBA_CACHE_DIR/wearjoint`` when that is set, else in the folder
``numba`` of the package's user cache (:func:`user_cache_dir`); importing the package writes nothing
under the package.  The :data:`KEEP` most recently used folders are kept (two installs side by side),
older ones removed when a new one is started.
"""
from __future__ import annotations

import hashlib
import re
from pathlib import Path

from numba.core import caching, config

from .user_cache import mark_used, prune_least_recently_used, user_cache_dir

KERNEL_PACKAGES = ("core", "cosim")     # whole: their modules hold kernels and the constants kernels compile in
KEEP = 4
KERNEL_DECORATOR = re.compile(rb"^\s*@kernel\b", re.MULTILINE)     # a line decorating a kernel, not a mention
PACKAGE = Path(__file__).resolve().parent.parent


def kernel_sources(package: Path = PACKAGE) -> list[Path]:
    """The sources a compiled kernel can depend on: every module of the :data:`KERNEL_PACKAGES` folders,
    and in the package's other folders those that define a kernel (``@kernel``)."""
    folders = [package, *sorted(init.parent for init in package.glob("*/__init__.py"))]
    return [path for folder in folders for path in sorted(folder.glob("*.py"))
            if folder.name in KERNEL_PACKAGES or KERNEL_DECORATOR.search(path.read_bytes())]


def kernel_digest(package: Path = PACKAGE) -> str:
    """SHA-256 (16 hex digits) of :func:`kernel_sources`: their paths in the package and contents."""
    digest = hashlib.sha256()
    for path in kernel_sources(package):
        digest.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:16]


def cache_root() -> Path:
    """The folder holding one cache folder per kernel digest."""
    return Path(config.CACHE_DIR) / "wearjoint" if config.CACHE_DIR else user_cache_dir() / "numba"


class KernelCacheLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """numba's cache locator for the package's modules: ``<cache_root>/<digest>/<module's folder>`` (numba's
    locator classes are private: the pinned numba 0.68's, as :mod:`wearjoint.core.jit` relies on its ``_nrt``)."""
    digest = ""

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        folder = Path(py_file).resolve().parent.relative_to(PACKAGE)
        self._cache_path = str(cache_root() / self.digest / folder)

    def get_cache_path(self) -> str:
        return self._cache_path

    @classmethod
    def from_function(cls, py_func, py_file):
        if not Path(py_file).resolve().is_relative_to(PACKAGE):
            return None
        return super().from_function(py_func, py_file)


def install() -> None:
    """Make numba cache the package's kernels through :class:`KernelCacheLocator`, the digest of this
    source version; mark its folder used and, when it is new, prune the old ones."""
    KernelCacheLocator.digest = kernel_digest()
    if KernelCacheLocator not in caching.CacheImpl._locator_classes:
        caching.CacheImpl._locator_classes.insert(0, KernelCacheLocator)
    folder = cache_root() / KernelCacheLocator.digest
    try:
        if folder.is_dir():
            mark_used(folder)
        elif folder.parent.is_dir():
            prune_least_recently_used(folder.parent, folder.name, KEEP)
    except OSError:      # a read-only cache: numba's own locators then apply
        pass
