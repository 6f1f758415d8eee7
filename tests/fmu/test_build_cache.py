"""Native builds through the user cache (wearjoint/fmu/build_native.py): each build leaves a copy under its build
key; the next build of the same key, into any folder, copies it and compiles nothing; other start values, or
``force``, build."""
import sys

import pytest

from wearjoint.fmu import build_common, build_native
from wearjoint.fmu.build_common import existing_build_key

pytest.importorskip("fmpy")


@pytest.fixture
def compilations(tmp_path, monkeypatch):
    """An empty user cache, and the list of builds that reached the compilers."""
    if sys.platform in ("win32", "darwin"):
        pytest.skip("the user cache is moved by XDG_CACHE_HOME on Linux only")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    calls = []
    emit = build_native.emit_objects
    monkeypatch.setattr(build_native, "emit_objects", lambda *args, **kw: calls.append(args) or emit(*args, **kw))
    # ``force`` recompiles the kernels with numba (half a minute); the shipped IR stands in for them here
    kernel_ir = build_native.compile_kernel_ir
    monkeypatch.setattr(build_native, "compile_kernel_ir", lambda out_dir, spec, reuse=True: kernel_ir(out_dir, spec))
    return calls


def test_the_same_build_elsewhere_is_copied_and_other_starts_or_force_build(tmp_path, compilations):
    build = dict(platform_names="linux64", model="slider-crank")
    first = build_native.build_fmu(tmp_path / "a", **build)
    assert len(compilations) == 1
    kept = build_native.default_fmu_path(platform_names=["linux64"], model="slider-crank")
    assert kept.is_file() and kept.read_bytes() == first.read_bytes()
    second = build_native.build_fmu(tmp_path / "b", **build)
    assert len(compilations) == 1 and second.read_bytes() == first.read_bytes()
    assert second.stat().st_mode & 0o777 == first.stat().st_mode & 0o777    # a copy as readable as a build
    other = build_native.build_fmu(tmp_path / "c", starts={"slider_mass": 2.5}, **build)
    assert len(compilations) == 2 and existing_build_key(other) != existing_build_key(first)
    build_native.build_fmu(tmp_path / "d", force=True, **build)
    assert len(compilations) == 3


def test_the_cache_keeps_the_most_recently_used_builds(tmp_path, compilations, monkeypatch):
    """Past FMU_BUILDS_KEPT builds the least recently used go: a build copied from the cache counts as used."""
    monkeypatch.setattr(build_common, "FMU_BUILDS_KEPT", 3)
    build = dict(platform_names="linux64", model="slider-crank")
    masses = (1.5, 2.5, 3.5, 4.5)
    keys = [existing_build_key(build_native.build_fmu(tmp_path / str(mass), starts={"slider_mass": mass}, **build))
            for mass in masses[:3]]
    build_native.build_fmu(tmp_path / "again", starts={"slider_mass": masses[0]}, **build)     # a copy: used now
    assert len(compilations) == 3
    keys.append(existing_build_key(build_native.build_fmu(tmp_path / "last", starts={"slider_mass": masses[3]},
                                                          **build)))
    kept = build_native.default_fmu_path(platform_names=["linux64"], model="slider-crank").parent.parent
    assert {folder.name for folder in kept.iterdir()} == {keys[0], keys[2], keys[3]}


def test_a_file_written_whole_is_the_users_and_an_interrupted_one_leaves_nothing(tmp_path):
    """write_whole gives the umask's permissions (not a temporary file's private 0600); replaced_whole writes a
    file whole or leaves the earlier one and no partial file (Ctrl-C inside the block)."""
    import os

    umask = os.umask(0o022)
    try:
        build_common.write_whole(tmp_path / "f.fmu", b"fmu")
        assert (tmp_path / "f.fmu").stat().st_mode & 0o777 == 0o644
    finally:
        os.umask(umask)
    target = tmp_path / "p.ssp"
    target.write_bytes(b"earlier")
    with pytest.raises(KeyboardInterrupt):
        with build_common.replaced_whole(target) as partial:
            partial.write_bytes(b"half")
            raise KeyboardInterrupt
    assert target.read_bytes() == b"earlier" and sorted(p.name for p in tmp_path.iterdir()) == ["f.fmu", "p.ssp"]
    with build_common.replaced_whole(target) as partial:
        partial.write_bytes(b"whole")
    assert target.read_bytes() == b"whole" and not partial.exists()


@pytest.mark.parametrize("model", ["joint", "slider-crank"])
@pytest.mark.parametrize("module", ["joint_fields.py", "mechanism_parameters.py", "checks.py", "core/damping.py",
                                    "core/layout.py"])
def test_the_build_key_follows_the_parameters_rules_and_every_kernel(tmp_path, monkeypatch, model, module):
    """A change of a parameter's allowed range (the FMU's generated checks) or of any kernel module (its IR) is a new
    build: the cache served an FMU of the old restitution range after JOINT_FIELDS changed."""
    tree = tmp_path / "tree"
    for source in build_native.shipped_sources(2, model):
        copy = tree / source.relative_to(build_native.PACKAGE_DIR.parent)
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_bytes(source.read_bytes())
    c_sources = tree / build_native.FMU_SOURCE_DIR.relative_to(build_native.PACKAGE_DIR.parent)
    monkeypatch.setattr(build_native, "PACKAGE_DIR", tree / "wearjoint")
    monkeypatch.setattr(build_native, "FMU_SOURCE_DIR", c_sources)
    key = build_native.model_key(1257, 2, model)
    path = tree / "wearjoint" / module
    path.write_bytes(path.read_bytes() + b"\n# edited\n")
    assert build_native.model_key(1257, 2, model) != key
