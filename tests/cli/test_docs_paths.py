"""Every module, file and documented name the repository's prose mentions exists.

The prose: the Markdown files (README.md, docs/, tests/c_host/README.md; not CHANGELOG.md, whose
dated entries name what existed then), the docstrings and ``#`` comments of every tracked Python
file and the comments of every tracked C file.  A name there is checked when it is

* a dotted path starting ``wearjoint.``: the longest prefix must be an importable module and
  the rest attributes of it (``wearjoint.simulate.run_simulation``);
* a repository path: its first component is a top-level folder of the repository
  (``wearjoint/fmu/build.py``, ``fmu_src/pythonfmu/status_shim.c``, ``docs/model.md``,
  ``benchmarks/bench_cosim.py``, ``tests/c_host/``) and it must be a tracked file or folder; a
  wearjoint subpackage path ending ``.py`` (``core/contact.py``) must be a file of the package;
* a bare Python file name (``joint.py``): some tracked Python file has that name;
* in Markdown, a relative link target (to the linking file's folder) and its ``#anchor``
  (a heading of the target, GitHub's slug);
* in a Python file, the target of a Sphinx role (``:func:`prose```, and e.g. ``.design`` or
  ``core.slider_crank.NoJoint`` in a wearjoint module): names the file defines or imports, or a
  dotted path relative to the file's module or an enclosing package.

Paths whose first component is not a repository folder (``results/...`` outputs, the FMU's
``binaries/`` and ``resources/``, ``~/.cache/...``) and bare ``.c``/``.h``/``.md`` names
(generated headers, output reports) are not checked: they need not exist in the source tree.
"""
import ast
import importlib
import io
import re
import subprocess
import tokenize
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
FILES = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
PROSE = [f for f in FILES if f.endswith((".md", ".py", ".c", ".h")) and f != "CHANGELOG.md"]
TOP_FOLDERS = sorted({f.split("/")[0] for f in FILES if "/" in f})
SUBPACKAGES = sorted({Path(f).parent.name for f in FILES if f.startswith("wearjoint/") and f.count("/") == 2})
# setuptools' package-dir of pyproject.toml: folders installed under another package name
PACKAGE_FOLDERS = {"wearjoint.validation": "validation", "wearjoint.fmu_src": "fmu_src"}

_NOT_PATH_BEFORE = r"(?<![\w./~-])"
DOTTED = re.compile(_NOT_PATH_BEFORE + r"wearjoint(?:\.[A-Za-z_]\w*)+")
REPO_PATH = re.compile(_NOT_PATH_BEFORE + rf"(?:{'|'.join(map(re.escape, TOP_FOLDERS))})/[\w./-]*")
SUBPACKAGE_PATH = re.compile(_NOT_PATH_BEFORE + rf"(?:{'|'.join(SUBPACKAGES)})/[\w/]+\.py\b")
BARE_PY = re.compile(_NOT_PATH_BEFORE + r"[A-Za-z_]\w*\.py\b")
LINK = re.compile(r"\]\(([^)\s]+)\)")
ROLE = re.compile(r":(?:mod|func|class|meth|attr|data|exc):`~?(\.?[A-Za-z_][\w.]*)`")


def prose(path: str) -> list[str]:
    """The texts of ``path`` checked (see the module docstring)."""
    source = (REPO / path).read_text()
    if path.endswith(".md"):
        return [source]
    if path.endswith((".c", ".h")):
        return re.findall(r"/\*.*?\*/|//[^\n]*", source, flags=re.S)
    texts = [t.string for t in tokenize.generate_tokens(io.StringIO(source).readline) if t.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            texts.append(ast.get_docstring(node, clean=False) or "")
    return texts


def resolves(dotted: str) -> bool:
    """A ``wearjoint.`` path: the longest importable module prefix, then attributes."""
    parts = dotted.split(".")
    for n in range(len(parts), 0, -1):
        try:
            target = importlib.import_module(".".join(parts[:n]))
        except ModuleNotFoundError:
            continue
        try:
            for name in parts[n:]:
                target = getattr(target, name)
        except AttributeError:
            return False
        return True
    return False


def defined_names(path: str) -> set[str]:
    """Every name a Python file defines or imports, at any level (attributes ``self.x`` included)."""
    names = set()
    for node in ast.walk(ast.parse((REPO / path).read_text())):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
    return names


def module_of(path: str) -> str:
    """The dotted module name a tracked Python file is installed as."""
    folder, _, rest = path.partition("/")
    package = next((name for name, f in PACKAGE_FOLDERS.items() if f == folder), folder)
    parts = [package, *Path(rest).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def broken_names(path: str) -> list[str]:
    found = []
    tracked = set(FILES) | {str(Path(f).parent) for f in FILES}
    python_names = {Path(f).name for f in FILES if f.endswith(".py")}
    for text in prose(path):
        found += [f"module {m}" for m in DOTTED.findall(text) if not resolves(m)]
        found += [f"path {m}" for m in REPO_PATH.findall(text) if m.rstrip("./") not in tracked]
        found += [f"path {m}" for m in SUBPACKAGE_PATH.findall(text) if f"wearjoint/{m}" not in tracked]
        found += [f"file {m}" for m in BARE_PY.findall(text) if m not in python_names]
        if path.endswith(".md"):
            found += [f"link {m}" for m in LINK.findall(text) if not link_resolves(path, m)]
        if path.endswith(".py"):
            found += [f"role target {m}" for m in ROLE.findall(text) if not role_resolves(path, m)]
    return found


def link_resolves(path: str, target: str) -> bool:
    if re.match(r"[a-z]+:", target):
        return True   # a URL
    file, _, anchor = target.partition("#")
    linked = (REPO / path).parent / file if file else REPO / path
    if not linked.exists():
        return False
    if not anchor or linked.suffix != ".md":
        return True
    headings = re.findall(r"^#+\s+(.*)$", linked.read_text(), flags=re.M)
    return anchor in {slug(h) for h in headings}


def role_resolves(path: str, target: str) -> bool:
    """As Sphinx looks it up: a name the file defines or imports, else a module path relative to
    the file's module or to one of its enclosing packages (``core.slider_crank.NoJoint`` in
    wearjoint.core.integrators is wearjoint.core.slider_crank.NoJoint)."""
    if target.startswith("wearjoint."):
        return resolves(target)
    if not target.startswith(".") and set(target.split(".")) <= defined_names(path):
        return True
    scope = module_of(path).split(".")
    return any(resolves(".".join(scope[:n]) + ("" if target.startswith(".") else ".") + target)
               for n in range(len(scope), 0, -1) if scope[0] == "wearjoint")


@pytest.mark.parametrize("path", PROSE)
def test_names_in_the_prose_exist(path):
    assert broken_names(path) == []


@pytest.mark.parametrize("text, broken", [
    ("see wearjoint/fmu_build.py and docs/model.md", ["path wearjoint/fmu_build.py"]),
    ("``wearjoint.fmu_variables``; ``wearjoint.simulate.run_simulation``.", ["module wearjoint.fmu_variables"]),
    ("results/run/summary.json, binaries/linux64/x.so, ~/.cache/wearjoint/fmu/, fmu_src/pythonfmu/status_shim.c", []),
    ("core/contact.py and core/native.py; tests/c_host/ and tests/...", ["path core/native.py"]),
])
def test_the_rule_finds_stale_names_only(tmp_path, monkeypatch, text, broken):
    (tmp_path / "x.md").write_text(text)
    monkeypatch.setitem(globals(), "REPO", tmp_path)
    assert broken_names("x.md") == broken


def test_links_and_anchors_are_checked(tmp_path, monkeypatch):
    monkeypatch.setitem(globals(), "REPO", tmp_path)
    (tmp_path / "a.md").write_text("# The FMU contract (model `X`)\n[ok](a.md#the-fmu-contract-model-x) "
                                   "[bad anchor](a.md#nothing) [bad file](b.md)")
    assert broken_names("a.md") == ["link a.md#nothing", "link b.md"]
