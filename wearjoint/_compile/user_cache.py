"""The package's folder in the user's cache, found without importing numba (a warm co-simulation imports none)."""
from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path


def user_cache_dir() -> Path:
    """wearjoint's folder in the user's cache (compiled kernels and built FMUs live below it)."""
    if sys.platform == "win32":
        return Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local")) / "wearjoint" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "wearjoint"
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "wearjoint"


def prune_least_recently_used(root: Path, current: str, keep: int) -> None:
    """Remove all but the ``keep`` most recently used (modified) folders under ``root``: ``current`` (a folder
    name) is always kept, hidden folders (another process's partial writes) are left alone, and a folder another
    process removes meanwhile, or one that cannot be removed, is skipped."""
    def used(folder: Path) -> float:
        try:
            return folder.stat().st_mtime
        except OSError:
            return 0.0

    try:
        folders = [f for f in root.iterdir() if f.is_dir() and f.name != current and not f.name.startswith(".")]
    except OSError:
        return
    for stale in sorted(folders, key=used, reverse=True)[keep - 1:]:
        shutil.rmtree(stale, ignore_errors=True)


def mark_used(folder: Path) -> None:
    """Mark a cache folder used now, so :func:`prune_least_recently_used` keeps it (a read-only cache: left as it is)."""
    try:
        os.utime(folder)
    except OSError:
        pass
