"""numba's cache of the kernels (wearjoint/_compile/cache.py): which edits start a new cache, where it
lives, and that importing the package writes nothing under it."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import wearjoint
from wearjoint._compile import cache
from wearjoint._compile.user_cache import prune_least_recently_used

PACKAGE = Path(wearjoint.__file__).parent


def _copy(tmp_path: Path) -> Path:
    """The package's sources (no caches) in tmp_path/wearjoint."""
    copy = tmp_path / "wearjoint"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "shipped_ir"))
    return copy


def _append(path: Path, text: str = "\n# an edit\n") -> None:
    path.write_text(path.read_text() + text)


def test_an_edit_outside_the_kernels_keeps_the_cache(tmp_path):
    copy = _copy(tmp_path)
    before = cache.kernel_digest(copy)
    for name in ("plots.py", "results.py", "simulate.py", "cli/cosim.py", "studies/wear_study.py"):
        _append(copy / name)
    assert cache.kernel_digest(copy) == before


def test_an_edit_to_a_kernel_or_a_layout_constant_starts_a_new_cache(tmp_path):
    copy = _copy(tmp_path)
    digests = [cache.kernel_digest(copy)]
    for name, text in (("core/layout.py", None),           # constants the kernels compile in
                       ("joint.py", "\n@kernel\ndef _added(x):\n    return x\n"),   # a top-level module gains one
                       ("joint.py", None),                 # and its edits count from then on
                       ("fmu/slider_crank_entry_points.py", None),     # a kernel in another subpackage
                       ("cosim/cosimulation.py", None)):   # any module of cosim/
        _append(copy / name, *(() if text is None else (text,)))
        digests.append(cache.kernel_digest(copy))
    assert len(set(digests)) == len(digests)


def test_kernels_are_cached_by_digest_outside_the_package(tmp_path):
    from wearjoint.core.geometry import bushing_point_angles, bushing_points

    bushing_point_angles(8)          # bushing_points compiled or loaded through the locator
    locator = bushing_points._cache._impl._locator
    path = Path(locator.get_cache_path())
    assert isinstance(locator, cache.KernelCacheLocator)
    assert path == cache.cache_root() / cache.kernel_digest() / "core"
    assert not path.resolve().is_relative_to(PACKAGE.resolve())


def _tree(folder: Path) -> dict:
    return {p: p.stat().st_mtime_ns for p in folder.rglob("*") if p.is_file()}


def test_a_run_writes_nothing_under_the_package_and_fills_its_digest_folder(tmp_path):
    before = _tree(PACKAGE)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "PYTHONDONTWRITEBYTECODE": "1"}
    code = "from wearjoint.core.geometry import bushing_point_angles\nbushing_point_angles(8)"
    subprocess.run([sys.executable, "-c", code], env=env, check=True, cwd=tmp_path)
    assert _tree(PACKAGE) == before
    folder = tmp_path / "numba" / "wearjoint" / cache.kernel_digest() / "core"
    assert any(folder.glob("geometry.bushing_points-*.nbi")), sorted(p.name for p in folder.iterdir())


def test_old_digest_folders_are_pruned_to_the_most_recent(tmp_path):
    root = tmp_path / "numba"
    for i in range(cache.KEEP + 2):
        (root / f"old{i}").mkdir(parents=True)
        os.utime(root / f"old{i}", (1000 + i, 1000 + i))
    prune_least_recently_used(root, "current", cache.KEEP)
    kept = sorted(p.name for p in root.iterdir())
    assert kept == [f"old{i}" for i in range(3, cache.KEEP + 2)]      # KEEP - 1 newest, and "current" to come


def test_a_module_that_only_mentions_the_decorator_is_not_a_kernel_source(tmp_path):
    copy = _copy(tmp_path)
    before = cache.kernel_digest(copy)
    _append(copy / "plots.py", '\n"""``@kernel`` is the decorator of :mod:`wearjoint.core.jit`."""\n')
    assert cache.kernel_digest(copy) == before
    _append(copy / "plots.py", "\n@kernel\ndef f():\n    pass\n")
    assert cache.kernel_digest(copy) != before
