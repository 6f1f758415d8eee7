"""The kernels' IR (wearjoint/fmu/kernel_ir.py): the IR the package ships (wearjoint/fmu/shipped_ir/: the native
FMUs' and the co-simulation master's) is compiled from these kernels, a build with empty caches takes it instead of compiling, never once the
kernels or numba changed; its objects for several platforms, two cores at once, kept in the user cache."""
import dataclasses
import re
import sys

import pytest

from wearjoint.fmu import aot, kernel_ir, platforms
from wearjoint.fmu.build_native import MODELS
from wearjoint.fmu.ship_ir import SHIPPED


@pytest.mark.parametrize("model", list(SHIPPED))
def test_the_shipped_ir_is_compiled_from_these_kernels(model):
    spec = SHIPPED[model]
    assert kernel_ir.shipped_key(spec).get("digest") == kernel_ir.kernel_digest(spec), (
        f"wearjoint/fmu/shipped_ir/{model}.tar.xz was compiled from other kernels: run "
        f"python -m wearjoint.fmu.ship_ir {model}")


@pytest.mark.parametrize("model", list(SHIPPED))
def test_the_digest_covers_every_package_module_the_entry_points_import(model):
    """Every wearjoint module the model's entry points import, at any depth and inside functions too, is hashed
    into the digest, unless it cannot reach a kernel (the package's front matter: reports, plots, progress, the
    compile notice, where numba caches, the host's calls of the kernels; what it imports is not followed): an edit
    to one that the digest missed would leave a stale shipped IR looking current."""
    import ast
    from pathlib import Path
    package = Path(kernel_ir.PACKAGE_DIR)
    front_matter = {"__init__.py", "analysis.py", "against_ideal.py", "checks.py", "plots.py", "profile_metrics.py",
                    "progress.py", "report.py", "results.py", "slider_crank.py", "_compile/__init__.py", "_compile/cache.py",
                    "_compile/notice.py", "_compile/prefetch.py", "_compile/user_cache.py", "kernel_calls.py"}

    def module_file(name):
        parts = name.split(".")[1:]
        if not parts:
            return package / "__init__.py"
        relative = Path(*parts)
        for candidate in (package / relative.with_suffix(".py"), package / relative / "__init__.py"):
            if candidate.is_file():
                return candidate
        return None

    spec = SHIPPED[model]
    seen, todo = set(), [aot.ENTRY_POINTS[model][0]]
    while todo:
        path = module_file(todo.pop())
        if path is None or path in seen:
            continue
        seen.add(path)
        if path.relative_to(package).as_posix() in front_matter:
            continue
        module = ".".join(("wearjoint", *path.relative_to(package).with_suffix("").parts))
        if path.name == "__init__.py":
            module += ".__init__"
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level:
                base = ".".join(module.split(".")[:-node.level] + ([node.module] if node.module else []))
                todo += [base] + [f"{base}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("wearjoint"):
                todo.append(node.module)
    hashed = {*kernel_ir.IR_SOURCES, *spec.ir_modules}
    missing = sorted(p.relative_to(package).as_posix() for p in seen)
    missing = [name for name in missing if name not in hashed and name not in front_matter]
    assert not missing, f"the kernel digest misses {missing} (wearjoint/fmu/kernel_ir.py IR_SOURCES)"


def test_the_digest_is_the_same_where_the_package_is_installed(tmp_path, monkeypatch):
    """In the source tree fmu_src/ sits beside the package; a wheel installs it inside the package."""
    spec = MODELS["joint"]
    in_tree = kernel_ir.kernel_digest(spec)
    installed = tmp_path / "site-packages" / "wearjoint" / "fmu_src"
    header = installed / spec.folder / spec.kernel_header
    header.parent.mkdir(parents=True)
    header.write_bytes((kernel_ir.FMU_SOURCE_DIR / spec.folder / spec.kernel_header).read_bytes())
    monkeypatch.setattr(kernel_ir, "FMU_SOURCE_DIR", installed)
    assert kernel_ir.kernel_digest(spec) == in_tree
    header.write_bytes(b"/* another header */\n")
    assert kernel_ir.kernel_digest(spec) != in_tree


def _no_compiling(*args, **kwargs):
    raise AssertionError("compiled the kernels although the package ships their IR")


@pytest.mark.parametrize("model", list(SHIPPED))
def test_a_build_with_empty_caches_takes_the_shipped_ir(model, tmp_path, monkeypatch):
    spec = SHIPPED[model]
    shipped = kernel_ir.shipped_key(spec).get("kernel_key")
    if shipped != kernel_ir.kernel_key(spec):
        pytest.skip(f"the shipped IR is {shipped}, this tree needs {kernel_ir.kernel_key(spec)}")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(kernel_ir, "_compile_ir_fresh", _no_compiling)
    out = tmp_path / "kernels"
    modules = kernel_ir.compile_kernel_ir(out, spec)
    assert set(modules) == set(aot.ENTRY_POINTS[model][1])
    for symbol, name in modules.items():
        # the entry point, exported under its C name
        assert re.search(rf"^define .* @{symbol}\(", (out / name).read_text(), re.MULTILINE), symbol


def test_a_changed_kernel_or_numba_is_compiled_not_taken_from_the_package(tmp_path, monkeypatch):
    spec = MODELS["joint"]
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(kernel_ir, "kernel_key", lambda spec: f"{spec.name}-numba0.0-llvmlite0.0-0000")
    assert kernel_ir.shipped_kernel_ir(tmp_path / "shipped", spec) is None
    compiled = []
    monkeypatch.setattr(kernel_ir, "_compile_ir_fresh", lambda out, model, fresh: compiled.append((model, fresh)) or {})
    kernel_ir.compile_kernel_ir(tmp_path / "kernels", spec)
    assert compiled == [("joint", False)]


def test_ship_ir_check_names_a_stale_archive(monkeypatch, capsys):
    from wearjoint.fmu import ship_ir

    monkeypatch.setattr(ship_ir, "kernel_digest", lambda spec: "changed" if spec.name == "joint" else
                        kernel_ir.kernel_digest(spec))
    assert ship_ir.main(["--check"]) == 1
    assert capsys.readouterr().out.splitlines()[0] == "joint: stale"
    with pytest.raises(SystemExit):
        ship_ir.main(["no-such-model"])
    assert "MODEL='no-such-model' is invalid: allowed one of joint, slider-crank" in capsys.readouterr().err


def _shipped_kernels(tmp_path):
    spec = MODELS["joint"]
    if kernel_ir.shipped_key(spec).get("kernel_key") != kernel_ir.kernel_key(spec):
        pytest.skip("the shipped IR is for another numba or llvmlite")
    return tmp_path / "kernels", kernel_ir.shipped_kernel_ir(tmp_path / "kernels", spec)


# what an object file starts with: ELF, or the COFF header of an x86-64 object (machine 0x8664)
OBJECT_MAGIC = {"linux64": b"\x7fELF", "aarch64-linux": b"\x7fELF", "win64": b"\x64\x86"}


@pytest.fixture
def empty_cache(tmp_path, monkeypatch):
    """An empty user cache (this process's and its children's): every object is emitted."""
    if sys.platform in ("win32", "darwin"):
        pytest.skip("the user cache is moved by XDG_CACHE_HOME on Linux only")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    return tmp_path / "cache" / "wearjoint" / "objects"


@pytest.mark.parametrize("cores", [1, 2])
def test_every_platforms_objects_are_written_on_one_or_two_cores(tmp_path, monkeypatch, empty_cache, cores):
    monkeypatch.setattr(kernel_ir, "usable_cores", lambda: cores)
    kernel_dir, modules = _shipped_kernels(tmp_path)
    targets = [platforms.PLATFORMS[name] for name in OBJECT_MAGIC]
    emitted = {target.name: paths for target, paths in kernel_ir.emit_objects(kernel_dir, modules, targets)}
    assert sorted(emitted) == sorted(OBJECT_MAGIC)
    for name, paths in emitted.items():
        assert len(paths) == len(modules)
        for path in paths:
            assert (tmp_path / path).read_bytes().startswith(OBJECT_MAGIC[name]), path


def test_a_platform_that_fails_in_the_second_process_is_named(tmp_path, monkeypatch, empty_cache):
    monkeypatch.setattr(kernel_ir, "usable_cores", lambda: 2)
    kernel_dir, modules = _shipped_kernels(tmp_path)
    unknown = dataclasses.replace(platforms.PLATFORMS["linux64"], name="no-such-platform")
    with pytest.raises(RuntimeError, match="objects for no-such-platform failed"):
        list(kernel_ir.emit_objects(kernel_dir, modules, [platforms.PLATFORMS["linux64"], unknown]))


def test_a_second_emission_takes_every_object_from_the_cache_and_a_fresh_one_none(tmp_path, monkeypatch, empty_cache):
    """The first emission writes each object into the user cache; the next (another folder, both platforms) emits
    nothing and gives the same bytes; ``reuse=False`` (``build-fmu --force``) emits every one again.  The cache is
    keyed by the IR: an object of other IR is not taken for it."""
    monkeypatch.setattr(kernel_ir, "usable_cores", lambda: 1)
    emitted = []
    emit = aot.emit_object
    monkeypatch.setattr(aot, "emit_object", lambda *args: emitted.append(args) or emit(*args))
    targets = [platforms.PLATFORMS["linux64"], platforms.PLATFORMS["win64"]]
    objects = {}
    for run, reuse in (("first", True), ("second", True), ("fresh", False)):
        kernel_dir, modules = _shipped_kernels(tmp_path / run)
        before = len(emitted)
        objects[run] = {target.name: [(tmp_path / run / path).read_bytes() for path in paths]
                        for target, paths in kernel_ir.emit_objects(kernel_dir, modules, targets, reuse=reuse)}
        emitted_now = len(emitted) - before
        assert emitted_now == (0 if run == "second" else 2 * len(modules)), run
    assert objects["second"] == objects["first"] == objects["fresh"]
    assert len(list(empty_cache.glob("*.o"))) == 2 * len(modules)
    ir = kernel_dir / next(iter(modules.values()))
    ir.write_text(ir.read_text() + "\n; another module\n")
    assert not kernel_ir.cached_object(ir, targets[0]).is_file()
