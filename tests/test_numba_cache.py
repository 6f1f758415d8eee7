"""The numba cache's stamp (wearjoint/_numba_cache.py): which edits drop the compiled kernels."""
from __future__ import annotations

import shutil
from pathlib import Path

import wearjoint
from wearjoint._numba_cache import kernel_digest, kernel_folders

PACKAGE = Path(wearjoint.__file__).parent


def _copy(tmp_path: Path) -> Path:
    """The package's sources (no caches) in tmp_path/wearjoint."""
    copy = tmp_path / "wearjoint"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "shipped_ir"))
    return copy


def _digest(copy: Path) -> str:
    folders = [copy, copy / "core", copy / "cosim"]
    return kernel_digest([f for f in folders if (f / "__init__.py").is_file()])


def _append(path: Path, text: str = "\n# an edit\n") -> None:
    path.write_text(path.read_text() + text)


def test_the_installed_package_stamps_its_kernel_folders():
    names = {folder.name for folder in kernel_folders()}
    assert {"wearjoint", "core", "cosim"} <= names


def test_an_edit_outside_the_kernels_keeps_the_cache(tmp_path):
    copy = _copy(tmp_path)
    before = _digest(copy)
    for name in ("plots.py", "results.py", "simulate.py", "cli/cosim.py"):
        _append(copy / name)
    assert _digest(copy) == before


def test_an_edit_to_a_kernel_or_a_layout_constant_drops_it(tmp_path):
    copy = _copy(tmp_path)
    before = _digest(copy)
    _append(copy / "core" / "layout.py")                    # constants the kernels compile in
    after_layout = _digest(copy)
    _append(copy / "exudyn.py")                             # a top-level module defining kernels
    after_exudyn = _digest(copy)
    _append(copy / "cosim" / "cosimulation.py")             # any module of cosim/
    assert len({before, after_layout, after_exudyn, _digest(copy)}) == 4
