"""The code's shape (docs/reference/code_layout.md §4, the code's layers): no import cycle among the
package's modules at import time, the kernels in ``wearjoint/core`` import nothing of the package outside it (but
numba's cache location), exudyn is imported only by ``wearjoint/exudyn.py``, ``validation/`` and the examples,
``import wearjoint`` loads none of exudyn, fmpy, pythonfmu, dask, numba, matplotlib, and no source file is over 500
lines.  Reads the sources (``ast``) and starts one interpreter."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ((REPO / "wearjoint", "wearjoint"), (REPO / "validation", "wearjoint.validation"))
MAX_LINES = 500
SOURCE_ROOTS = ("wearjoint", "validation", "fmu_src", "tests", "benchmarks")


def package_modules() -> dict[str, tuple[Path, bool]]:
    """{dotted module name: (file, whether it is a package's __init__)} of the installed package's sources."""
    modules = {}
    for root, package in PACKAGES:
        for path in sorted(root.rglob("*.py")):
            parts = [p for p in path.relative_to(root).with_suffix("").parts if p != "__init__"]
            modules[".".join([package, *parts])] = (path, path.name == "__init__.py")
    return modules


MODULES = package_modules()


def imported_names(name: str, path: Path, is_package: bool, top_level: bool) -> set[str]:
    """The dotted names module ``name`` imports (only its module-level statements if ``top_level``: an import inside
    a function runs when called, after every module has loaded), relative imports resolved."""
    tree = ast.parse(path.read_text())
    nodes = tree.body if top_level else ast.walk(tree)
    names = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                package = name.split(".") if is_package else name.split(".")[:-1]
                base = ".".join(package[:len(package) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return names


def own_module(dotted: str) -> str | None:
    """The package module ``dotted`` names (a name imported from a module: that module), None if outside it."""
    while dotted and dotted not in MODULES:
        dotted = dotted.rpartition(".")[0]
    return dotted or None


def import_graph() -> dict[str, set[str]]:
    """{module: the package modules it imports at import time}."""
    graph = {}
    for name, (path, is_package) in MODULES.items():
        targets = {own_module(t) for t in imported_names(name, path, is_package, top_level=True)}
        graph[name] = {t for t in targets if t is not None and t != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index, low, on_stack, stack, found, counter = {}, {}, set(), [], [], 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, successors = work[-1]
            w = next(successors, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_the_cycle_finder_finds_a_cycle_and_passes_a_chain():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_the_package_has_modules_and_imports_between_them():
    """The graph is read, not empty: the check below could not pass by reading nothing."""
    graph = import_graph()
    assert len(graph) > 100 and "wearjoint.core.layout" in graph["wearjoint.core.contact"]


def test_no_import_cycle_at_import_time():
    assert cycles(import_graph()) == []


def test_the_kernels_import_nothing_of_the_package_outside_core():
    """But numba's cache location (wearjoint._compile, which imports nothing of the package's)."""
    outside = {name: sorted(t for t in targets if not t.startswith(("wearjoint.core", "wearjoint._compile")))
               for name, targets in import_graph().items() if name.startswith("wearjoint.core")}
    assert {name: targets for name, targets in outside.items() if targets} == {}


def test_exudyn_is_imported_only_by_the_helper_validation_and_the_examples_built_on_it():
    importers = sorted(name for name, (path, is_package) in MODULES.items()
                       if any(t == "exudyn" or t.startswith("exudyn.")
                              for t in imported_names(name, path, is_package, top_level=False)))
    assert "wearjoint.exudyn" in importers and all(
        name == "wearjoint.exudyn" or name.startswith(("wearjoint.validation", "wearjoint.examples"))
        for name in importers), importers


def test_importing_wearjoint_loads_no_host_or_cluster_package():
    code = ("import sys, wearjoint; print(sorted(m for m in ('exudyn', 'fmpy', 'pythonfmu', 'dask', 'numba', "
            "'matplotlib') if m in sys.modules))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert loaded == "[]"


@pytest.mark.parametrize("root", SOURCE_ROOTS)
def test_no_source_file_is_over_500_lines(root):
    files = [p for p in (REPO / root).rglob("*") if p.suffix in (".py", ".c", ".h") and p.is_file()]
    assert files
    long = {str(p.relative_to(REPO)): n for p in files if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert long == {}
