"""The package's folder in the user's cache, found without importing numba (a warm co-simulation imports none)."""
from __future__ import annotations

import os
import sys
from pathlib import Path


def user_cache_dir() -> Path:
    """wearjoint's folder in the user's cache (compiled kernels and built FMUs live below it)."""
    if sys.platform == "win32":
        return Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local")) / "wearjoint" / "Cache"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "wearjoint"
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "wearjoint"
