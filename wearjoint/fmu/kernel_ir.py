"""A native FMU's kernels as LLVM IR: compiled ahead of time, kept, shipped, turned into objects.

:func:`compile_kernel_ir` gives a model's IR (one ``<symbol>.ll`` per entry point of
:data:`aot.ENTRY_POINTS`) from the first of:

1. the user cache, where an earlier build left it (``reuse``);
2. the package (``reuse``): ``wearjoint/fmu/shipped_ir/<model>.tar.xz`` holds the IR of each model,
   compiled from this tree's kernels with the numba and llvmlite it names, as a Cython package
   ships its generated C.  Taken only where :func:`kernel_key` (those versions and a hash of the
   kernels' sources) is the archive's, so it is never stale; ``python -m wearjoint.fmu.ship_ir``
   writes it anew after a change to the kernels (``tests/fmu/test_kernel_ir.py`` fails until then);
3. numba, in fresh processes for a generic CPU (:mod:`wearjoint.fmu.aot`; ``build-fmu --force``
   always does this).

:func:`kernel_objects` turns the IR into one platform's objects, :func:`emit_objects` into several
platforms' on two cores.  The user cache keeps each object under a hash of its IR, the platform's triple and CPU
and llvmlite's version (the same IR always gives the same object): a build after the first, whatever its start
values, emits none (2.5 s of `export-ssp`'s 6 s on linux64 alone, measured).
"""
from __future__ import annotations

import hashlib
import io
import json
import math
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
from pathlib import Path

from .._compile.prefetch import usable_cores
from . import aot, platforms
from .build_common import FMU_SOURCE_DIR, PACKAGE_DIR, keep_in_cache, source_digest, user_cache_dir

# what every model's kernel IR depends on (with its own modules, the numba and llvmlite versions): every kernel
# module (all of core/, so that a new one cannot be left out) and the modules that fix the parameter vectors
IR_SOURCES = (*sorted(f"core/{path.name}" for path in (PACKAGE_DIR / "core").glob("*.py")), "joint.py",
              "joint_fields.py", "parameters.py", "mechanism_parameters.py", "fmu/aot.py")
# the process that compiles the kernels: a generic CPU (numba's cache keeps these apart from the
# in-process kernels, which are compiled for this machine's CPU)
AOT_ENVIRONMENT = {"NUMBA_CPU_NAME": "generic", "NUMBA_CPU_FEATURES": "", "NUMBA_DISABLE_JIT": "0"}
SHIPPED_DIR = Path(__file__).parent / "shipped_ir"
_KEY_MEMBER = "kernel_key.json"   # the archive's member naming what its IR was compiled from


def kernel_digest(spec) -> str:
    """Hash of what the IR of ``spec`` (a :class:`build_native.NativeModel`, or the master's
    :data:`wearjoint.cosim.native_master.MASTER`) is compiled from: the kernels' sources and its kernel header
    (the master has none), named as in the source tree (``wearjoint/...``,
    ``fmu_src/...``) wherever the package is installed."""
    python = source_digest([PACKAGE_DIR / name for name in (*IR_SOURCES, *spec.ir_modules)], PACKAGE_DIR.parent)
    header = (source_digest([FMU_SOURCE_DIR / spec.folder / spec.kernel_header], FMU_SOURCE_DIR.parent)
              if spec.kernel_header else "")
    return hashlib.sha256(f"{python}{header}".encode()).hexdigest()[:16]


def kernel_key(spec) -> str:
    """What the kernel IR of ``spec`` depends on: numba and llvmlite versions, :func:`kernel_digest`."""
    from importlib.metadata import version   # not numba.__version__: a warm co-simulation does not import numba

    return f"{spec.name}-numba{version('numba')}-llvmlite{version('llvmlite')}-{kernel_digest(spec)}"


def _aot_parts(model: str) -> list:
    """The entry points of each AOT process: two (:data:`aot.PARTS`) where this process may use two cores or more."""
    symbols = list(aot.ENTRY_POINTS[model][1])
    second = list(aot.PARTS[model]) if usable_cores() > 1 else []
    return [[symbol for symbol in symbols if symbol not in second], *([second] if second else [])]


def _compile_ir_fresh(out_dir: Path, model: str, fresh: bool) -> dict:
    """:mod:`.aot` in fresh processes (:func:`_aot_parts`; they share numba's cache), said on stderr with a
    progress bar of their compilations once they have taken ANNOUNCE_AFTER_S (as the engines' notice), its time
    left the reference's wall seconds less those gone (unknown past them).  They take the kernels numba's cache
    holds (an earlier build's: the same generic CPU) unless ``fresh`` (an empty cache)."""
    from .._compile import concurrent_builds
    from .._compile.notice import AHEAD_OF_TIME, ANNOUNCE_AFTER_S, announced_progress, cold_run   # imports numba

    parts = _aot_parts(model)
    key = next(key for key, name in AHEAD_OF_TIME.items() if name == model)
    bar = None
    counts = [0] * len(parts)

    def follow(k, stream):
        for line in stream:
            if line.strip().isdigit():
                counts[k] = int(line)

    with (tempfile.TemporaryDirectory(prefix="wearjoint_numba_") as cache, tempfile.TemporaryDirectory() as logs,
          concurrent_builds.running(key)):
        env = {**os.environ, **AOT_ENVIRONMENT, **({"NUMBA_CACHE_DIR": cache} if fresh else {})}
        processes, readers = [], []
        for k, part in enumerate(parts):
            with open(Path(logs) / f"{k}.err", "w") as errors:
                processes.append(subprocess.Popen(
                    [sys.executable, "-m", "wearjoint.fmu.aot", model, str(out_dir), ",".join(part)],
                    stdout=subprocess.PIPE, stderr=errors, text=True, env=env, cwd=PACKAGE_DIR.parent))
            readers.append(threading.Thread(target=follow, args=(k, processes[-1].stdout), daemon=True))
            readers[-1].start()
        start, reference_s = time.perf_counter(), cold_run(key)[0]
        while any(process.poll() is None for process in processes):
            elapsed = time.perf_counter() - start
            if bar is None and elapsed >= ANNOUNCE_AFTER_S:   # builds running at once share the cores
                reference_s += sum(cold_run(other)[0] for other in concurrent_builds.others(key))
                bar = announced_progress(key, seconds=reference_s)
            if bar is not None:
                if sum(counts) >= bar.total:   # more than the reference's: not 100 % while a kernel compiles
                    bar.set_total(sum(counts) + 1)
                bar.update(sum(counts), reference_s - elapsed if elapsed < reference_s else math.nan)
            time.sleep(0.1)
        for reader in readers:
            reader.join()
        if bar is not None:
            if sum(counts) > 0:
                bar.set_total(sum(counts))
            bar.close()
        for k, process in enumerate(processes):
            if process.returncode != 0:
                raise RuntimeError("compiling the kernels ahead of time failed:\n"
                                   + (Path(logs) / f"{k}.err").read_text().strip()[-3000:])
    modules = {symbol: f"{symbol}.ll" for symbol in aot.ENTRY_POINTS[model][1]}
    (out_dir / "entry_points.json").write_text(json.dumps(modules, indent=1))
    return modules


def _archive(spec) -> Path:
    return SHIPPED_DIR / f"{spec.name}.tar.xz"


def shipped_kernel_ir(out_dir: Path, spec) -> dict | None:
    """The IR the package ships for ``spec``, unpacked into ``out_dir`` ({symbol: IR file}), if it was
    compiled from these kernels by this numba and llvmlite (:func:`kernel_key`); None otherwise."""
    if shipped_key(spec).get("kernel_key") != kernel_key(spec):
        return None
    try:
        with tarfile.open(_archive(spec), "r:xz") as archive:
            modules = json.load(archive.extractfile("entry_points.json"))
            out_dir.mkdir(parents=True, exist_ok=True)
            for name in ("entry_points.json", *modules.values()):
                (out_dir / Path(name).name).write_bytes(archive.extractfile(name).read())
            return modules
    except (OSError, KeyError, ValueError, AttributeError, tarfile.TarError):
        return None


def shipped_key(spec) -> dict:
    """What the package's IR of ``spec`` was compiled from: {"kernel_key": :func:`kernel_key`,
    "digest": :func:`kernel_digest`} ({} without an archive)."""
    try:
        with tarfile.open(_archive(spec), "r:xz") as archive:
            return json.load(archive.extractfile(_KEY_MEMBER))
    except (OSError, KeyError, ValueError, AttributeError, tarfile.TarError):
        return {}


def write_shipped_ir(spec) -> Path:
    """Compile the IR of ``spec`` afresh (an empty numba cache) and write the package's archive of it."""
    with tempfile.TemporaryDirectory(prefix="wearjoint_ship_") as tmp:
        modules = _compile_ir_fresh(Path(tmp), spec.name, fresh=True)
        key = json.dumps({"kernel_key": kernel_key(spec), "digest": kernel_digest(spec)}, indent=1)
        members = {_KEY_MEMBER: key.encode(), "entry_points.json": (Path(tmp) / "entry_points.json").read_bytes(),
                   **{name: (Path(tmp) / name).read_bytes() for name in modules.values()}}
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:xz", preset=9) as archive:
        for name, data in members.items():
            info = tarfile.TarInfo(name)   # no dates or owners: the same IR gives the same archive
            info.size, info.mode = len(data), 0o644
            archive.addfile(info, io.BytesIO(data))
    SHIPPED_DIR.mkdir(exist_ok=True)
    _archive(spec).write_bytes(buffer.getvalue())
    return _archive(spec)


def compile_kernel_ir(out_dir: Path, spec, reuse: bool = True) -> dict:
    """The kernel IR of ``spec`` (a :class:`build_native.NativeModel`) in ``out_dir`` ({symbol: IR
    file}): with ``reuse``, the user cache's where an earlier build left it, else the package's
    (:func:`shipped_kernel_ir`); otherwise compiled in fresh processes (from the kernels in numba's
    cache; with an empty one unless ``reuse``) and kept in the user cache."""
    cached = user_cache_dir() / "kernels" / kernel_key(spec)
    if reuse:
        try:
            modules = json.loads((cached / "entry_points.json").read_text())
            if all((cached / name).is_file() for name in modules.values()):
                shutil.copytree(cached, out_dir, dirs_exist_ok=True)
                return modules
        except (OSError, ValueError):
            pass
        modules = shipped_kernel_ir(out_dir, spec)
        if modules is not None:
            return modules
    modules = _compile_ir_fresh(out_dir, spec.name, fresh=not reuse)
    try:   # keep it for the next build (another process may be writing the same: first one wins)
        cached.parent.mkdir(parents=True, exist_ok=True)
        partial = Path(tempfile.mkdtemp(prefix=cached.name + ".", dir=cached.parent))
        shutil.copytree(out_dir, partial, dirs_exist_ok=True)
        if cached.exists():
            shutil.rmtree(cached, ignore_errors=True)
        try:
            partial.rename(cached)
        except OSError:
            shutil.rmtree(partial, ignore_errors=True)
    except OSError:
        pass
    return modules


def _object_paths(kernel_dir: Path, modules: dict, target: platforms.Platform) -> list[str]:
    return [f"{kernel_dir.name}/{target.name}/{symbol}.o" for symbol in modules]


def cached_object(ir_path: Path, target: platforms.Platform) -> Path:
    """Where the user cache keeps the object of the IR in ``ir_path`` for ``target``: named by a hash of the IR,
    the platform's triple and CPU and llvmlite's version."""
    from importlib.metadata import version

    digest = hashlib.sha256(Path(ir_path).read_bytes())
    digest.update(f"\0{target.triple}\0{target.cpu}\0llvmlite{version('llvmlite')}".encode())
    return user_cache_dir() / "objects" / f"{digest.hexdigest()[:32]}.o"


def kernel_objects(kernel_dir: Path, modules: dict, target: platforms.Platform, reuse: bool = True) -> list[str]:
    """Objects of the kernels' IR for ``target`` in ``kernel_dir/<platform>/``, from the user cache where it has
    them (``reuse``: :func:`cached_object`) else emitted and kept there; their paths relative to ``kernel_dir``'s
    parent."""
    folder = kernel_dir / target.name
    folder.mkdir(parents=True, exist_ok=True)
    for symbol, ir_name in modules.items():
        cached = cached_object(kernel_dir / ir_name, target)
        data = cached.read_bytes() if reuse and cached.is_file() else None
        if data is None:
            data = aot.emit_object(kernel_dir / ir_name, target.triple, target.cpu)
            keep_in_cache(cached, data)
        (folder / f"{symbol}.o").write_bytes(data)
    return _object_paths(kernel_dir, modules, target)


def emit_objects(kernel_dir: Path, modules: dict, targets, reuse: bool = True):
    """Yield (platform, :func:`kernel_objects`) for each of ``targets`` as its objects are written: where
    two cores are usable and the cache lacks some of the last platform's objects, that platform's in a second
    process (``python -m wearjoint.fmu.kernel_ir``) while this one writes the others (LLVM's code generation takes
    ~0.5 s a platform)."""
    *own, last = targets
    second = None
    if own and usable_cores() > 1 and not (reuse and all(cached_object(kernel_dir / ir_name, last).is_file()
                                                           for ir_name in modules.values())):
        second = subprocess.Popen([sys.executable, "-m", __name__, str(kernel_dir), last.name,
                                   *([] if reuse else ["--fresh"])],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=PACKAGE_DIR.parent)
        targets = own
    try:
        for target in targets:
            yield target, kernel_objects(kernel_dir, modules, target, reuse)
    finally:
        if second is not None:
            errors = second.communicate()[1]
    if second is not None:
        if second.returncode != 0:
            raise RuntimeError(f"the kernels' objects for {last.name} failed:\n{errors.strip()[-3000:]}")
        yield last, _object_paths(kernel_dir, modules, last)


if __name__ == "__main__":   # KERNEL_DIR PLATFORM [--fresh]: that platform's objects of the IR in KERNEL_DIR
    kernel_dir = Path(sys.argv[1])
    kernel_objects(kernel_dir, json.loads((kernel_dir / "entry_points.json").read_text()),
                   platforms.PLATFORMS[sys.argv[2]], reuse="--fresh" not in sys.argv[3:])
