"""The command line stands alone on the top floor: no module of the package outside wearjoint/cli imports it (every
import, those inside functions too; the entry point wearjoint/__main__.py aside)."""
import ast
from pathlib import Path

import wearjoint

PACKAGE = Path(wearjoint.__file__).resolve().parent
CLI = "wearjoint.cli"


def _module(path: Path) -> list:
    """The module's dotted name as parts (a package's __init__: the package)."""
    parts = ["wearjoint", *path.relative_to(PACKAGE).with_suffix("").parts]
    return parts[:-1] if parts[-1] == "__init__" else parts


def _imported(path: Path, node) -> list:
    """The absolute names an import statement (or an import_module / __import__ call of a constant) refers to."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if isinstance(node, ast.ImportFrom):
        if node.level == 0:
            base = node.module or ""
        else:
            package = _module(path) if path.name == "__init__.py" else _module(path)[:-1]
            package = package[:len(package) - node.level + 1]
            base = ".".join(package + ([node.module] if node.module else []))
        return [base, *(f"{base}.{a.name}" for a in node.names)]
    if isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant) \
            and isinstance(node.args[0].value, str):
        name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
        if name in ("import_module", "__import__"):
            return [node.args[0].value]
    return []


def test_nothing_outside_the_cli_imports_it():
    sources = [p for p in PACKAGE.rglob("*.py") if "cli" not in p.relative_to(PACKAGE).parts[:1]
               and p != PACKAGE / "__main__.py"]
    assert len(sources) > 50 and PACKAGE / "sweep" / "worker.py" in sources
    found = [f"{path.relative_to(PACKAGE.parent)}:{node.lineno}: {name}"
             for path in sources for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
             for name in _imported(path, node) if name == CLI or name.startswith(CLI + ".")]
    assert found == []


def test_the_scan_sees_relative_and_function_level_imports(tmp_path):
    """The scan itself: a relative import inside a function and an import_module of a constant are found."""
    source = "def f():\n    from ..cli import main\n    importlib.import_module('wearjoint.cli.sweep')\n"
    path = PACKAGE / "sweep" / "example.py"          # never written: only its place in the package counts
    names = [n for node in ast.walk(ast.parse(source)) for n in _imported(path, node)]
    assert "wearjoint.cli" in names and "wearjoint.cli.sweep" in names
