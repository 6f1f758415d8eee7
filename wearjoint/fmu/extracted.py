"""An FMU's files and parsed modelDescription, extracted once per FMU file and shared by its instances.

fmpy extracts an FMU into a new temporary folder for each instance and parses its modelDescription (1300
variables) in each process: 0.03 s and 0.04 s of the main job's second.  :func:`extracted_fmu` extracts an FMU
once per file (its resolved path, size and modification time) into the user's cache (``fmu-extracted/``), with
the parsed modelDescription pickled beside it; instances only read the folder (the binary is loaded from there:
the FMU keeps its state in each instance, none in globals).  The :data:`KEEP` folders used last are kept.  Where
the cache cannot be written the FMU is extracted into a temporary folder its instance owns, as before.
"""
from __future__ import annotations

import hashlib
import os
import pickle
import shutil
import tempfile
from pathlib import Path

from .._compile.user_cache import mark_used, prune_least_recently_used, user_cache_dir

KEEP = 8                          # extracted FMUs kept (the most recently used)
_COMPLETE = "wearjoint-extracted"  # written last: the folder is whole
_DESCRIPTION = "modelDescription.pickle"


def extraction_root() -> Path:
    return user_cache_dir() / "fmu-extracted"


def _key(fmu_path: Path) -> str:
    stat = fmu_path.stat()
    text = f"{fmu_path.resolve()}|{stat.st_size}|{stat.st_mtime_ns}"
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _extract_into(fmu_path: Path, folder: Path):
    """Extract ``fmu_path`` into ``folder`` (created) and parse its modelDescription."""
    from fmpy import extract, read_model_description

    extract(str(fmu_path), unzipdir=str(folder))
    return read_model_description(str(folder / "modelDescription.xml"))


def extracted_fmu(fmu_path) -> tuple[str, object, bool]:
    """(the folder of ``fmu_path``'s files, fmpy's parsed modelDescription, whether the caller owns the folder and
    removes it when done: True only where the cache could not be used)."""
    fmu_path = Path(fmu_path)
    root = extraction_root()
    folder = root / _key(fmu_path)
    try:
        if not (folder / _COMPLETE).is_file():
            root.mkdir(parents=True, exist_ok=True)
            staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=root))
            try:
                description = _extract_into(fmu_path, staging)
                (staging / _DESCRIPTION).write_bytes(pickle.dumps(description, protocol=pickle.HIGHEST_PROTOCOL))
                (staging / _COMPLETE).write_text(str(fmu_path.resolve()))
                try:
                    os.replace(staging, folder)   # atomic
                except OSError:
                    if not (folder / _COMPLETE).is_file():
                        raise
                    # another process's extraction came first: ours is dropped, theirs used
            finally:
                shutil.rmtree(staging, ignore_errors=True)   # gone once renamed
            prune_least_recently_used(root, folder.name, KEEP)
        description = pickle.loads((folder / _DESCRIPTION).read_bytes())
        mark_used(folder)
        return str(folder), description, False
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError):
        own = Path(tempfile.mkdtemp(prefix="wearjoint-fmu-"))
        try:
            return str(own), _extract_into(fmu_path, own), True
        except BaseException:
            shutil.rmtree(own, ignore_errors=True)    # the caller never learns of the folder: not left behind
            raise

