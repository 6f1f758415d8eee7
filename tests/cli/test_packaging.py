"""What a wheel installs: every package of the source tree (pyproject.toml's explicit list) and the FMUs' sources."""
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib")
REPO = Path(__file__).resolve().parents[2]
CONFIG = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]


def test_every_package_folder_is_installed():
    remapped = {folder: name for name, folder in CONFIG["package-dir"].items()}
    folders = [init.parent for init in (REPO / "wearjoint").rglob("__init__.py")]
    folders += [REPO / folder for folder in remapped if (REPO / folder / "__init__.py").is_file()]
    names = {remapped.get(f.relative_to(REPO).as_posix(), f.relative_to(REPO).as_posix().replace("/", "."))
             for f in folders}
    assert names == set(CONFIG["packages"]), (names ^ set(CONFIG["packages"]))


def test_every_fmu_source_is_package_data():
    sources = REPO / "fmu_src"
    patterns = CONFIG["package-data"]["wearjoint.fmu_src"]
    files = {p for p in sources.rglob("*") if p.is_file() and "__pycache__" not in p.parts and p.name != "__init__.py"}
    covered = {p for pattern in patterns for p in sources.glob(pattern) if p.is_file()}
    assert files and files <= covered, sorted(str(p.relative_to(sources)) for p in files - covered)
