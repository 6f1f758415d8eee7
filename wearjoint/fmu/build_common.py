"""What both FMU backends' builds share (:mod:`wearjoint.fmu.build_native`,
:mod:`wearjoint.fmu.build_pythonfmu`; :mod:`wearjoint.fmu.build` dispatches between them): where the
sources are, the user cache where built FMUs live, the build keys that say whether an FMU there is
current, the C compiler and the FMI 2.0 headers.  It imports neither backend nor the dispatcher."""
from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
import platform
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

from .._compile.user_cache import mark_used, prune_least_recently_used
from .._compile.user_cache import user_cache_dir as user_cache_dir   # built FMUs live below it
from . import variables as fv

FMU_FILE_NAME = f"{fv.MODEL_NAME}.fmu"
FMU_BUILDS_KEPT = 32     # FMU builds the user cache keeps (fmu/<build key>/), the most recently used (0.4-1.2 MB)
PACKAGE_DIR = Path(__file__).resolve().parent.parent   # wearjoint/
# fmu_src is the package wearjoint.fmu_src (the folder fmu_src/ in the source tree)
FMU_SOURCE_DIR = Path(importlib.util.find_spec("wearjoint.fmu_src").origin).resolve().parent


def source_digest(paths, root: Path) -> str:
    """Hash of the files (their paths relative to ``root`` and contents): part of a build key."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).relative_to(root).as_posix().encode() + b"\0" + Path(path).read_bytes())
    return digest.hexdigest()[:16]


def current_build(out_dir, key: str, force: bool, file_name: str = FMU_FILE_NAME) -> tuple[Path, bool]:
    """``out_dir``'s FMU file ``file_name``, and whether it already is the build ``key`` (and no ``force``)."""
    target = Path(out_dir) / file_name
    return target, not force and existing_build_key(target) == key


def write_whole(path: Path, data: bytes) -> None:
    """``data`` into ``path`` whole or not at all, through a temporary file beside it (another process may be
    reading or writing the same file), readable as a file the user writes (the umask's permissions, not the
    temporary file's private ones)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, partial = tempfile.mkstemp(prefix=path.name + ".", dir=path.parent)
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(partial, 0o666 & ~umask)
        os.replace(partial, path)
    except BaseException:
        Path(partial).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def replaced_whole(path: Path):
    """A path beside ``path`` (``NAME.partial``) for the block to write, moved onto ``path`` when the block ends
    and removed if it raises (Ctrl-C included): ``path`` is written whole or not at all."""
    partial = path.with_name(path.name + ".partial")
    try:
        yield partial
        partial.replace(path)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


def keep_in_cache(path: Path, data: bytes) -> None:
    """``data`` into the user-cache file ``path`` (:func:`write_whole`); a cache that cannot be written is skipped
    (the build goes on without it)."""
    try:
        write_whole(path, data)
    except OSError:
        pass


def keep_build_in_cache(kept: Path, built: Path) -> None:
    """The FMU ``built`` kept at ``kept`` (the user cache's ``fmu/<build key>/``) for the next build of its key,
    wherever it goes; the cache's builds pruned to the :data:`FMU_BUILDS_KEPT` most recently used."""
    if kept.resolve() != built.resolve():
        keep_in_cache(kept, built.read_bytes())
    prune_least_recently_used(kept.parent.parent, kept.parent.name, FMU_BUILDS_KEPT)


def copy_kept_build(kept: Path, target: Path) -> None:
    """The build the user cache keeps at ``kept`` copied to ``target``, and marked used."""
    write_whole(target, kept.read_bytes())
    mark_used(kept.parent)


def existing_build_key(fmu_path: Path) -> str | None:
    """The build key an FMU was built with (resources/wearjoint_fmu.json), None if unreadable."""
    try:
        with zipfile.ZipFile(fmu_path) as zf:
            return json.loads(zf.read(f"resources/{fv.BUILD_CONFIG_FILE}"))["build_key"]
    except (OSError, KeyError, ValueError, zipfile.BadZipFile):
        return None


def c_compiler(purpose: str) -> str:
    """The C compiler (``$CC``, default gcc) on Linux x86_64; RuntimeError naming ``purpose`` otherwise."""
    if not sys.platform.startswith("linux") or platform.machine() != "x86_64":
        raise RuntimeError(f"{purpose} is built for binaries/linux64 only; this is {sys.platform} "
                           f"{platform.machine()} (build the FMU on Linux x86_64)")
    compiler = os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        raise RuntimeError(f"{purpose} needs a C compiler: {compiler!r} not found (install gcc or set CC)")
    return compiler


def fmi2_headers() -> Path:
    """The FMI 2.0 headers shipped with fmpy (fmpy/c-code); RuntimeError if missing."""
    fmpy = importlib.util.find_spec("fmpy")
    headers = Path(next(iter(fmpy.submodule_search_locations))) / "c-code" if fmpy else None
    if headers is None or not (headers / "fmi2Functions.h").is_file():
        raise RuntimeError("building the FMU needs the FMI 2.0 headers shipped with fmpy (fmpy/c-code/fmi2Functions.h)")
    return headers
