"""Building the ClearanceWearJoint FMU: what the pythonfmu FMU imports at run time and ships (exactly
its slave's import closure), its build key, and the build command (``wearjoint build-fmu``) of both
backends."""
import dataclasses
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402
from fmpy_instance import P  # noqa: E402

from wearjoint.cli.build_fmu import add_arguments, run  # noqa: E402
from wearjoint.fmu.build_pythonfmu import build_fmu, build_key, default_fmu_path  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]


# ------------------------------------------------------------- run-time imports
HOST_SCRIPT = textwrap.dedent("""
    import json, sys
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    fmu, unzipped = sys.argv[1:3]
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    before = set(sys.modules)
    s = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu, unzipdir=unzipped), modelIdentifier="ClearanceWearJoint",
                  instanceName="imports")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.setReal([vr["pin_x"]], [-0.135])
    s.doStep(0.0, 1e-5)
    force = s.getReal([vr["pin_force_x"], vr["worn_volume"]])
    s.terminate()
    s.freeInstance()
    loaded = sorted(set(sys.modules) - before)
    wearjoint_file = sys.modules["wearjoint"].__file__
    try:
        import scipy  # the host may still import it itself
        host_scipy = True
    except ImportError:
        host_scipy = False
    print(json.dumps({"loaded": loaded, "wearjoint": wearjoint_file, "host_scipy": host_scipy}))
""")


@pytest.mark.slow   # 12 s (a fresh interpreter imports the pythonfmu slave); the default suite stays under 5 min
def test_fmu_runtime_imports_only_numpy_numba_and_wearjoint(built_fmu, tmp_path):
    done = subprocess.run([sys.executable, "-c", HOST_SCRIPT, str(built_fmu), str(tmp_path / "unzipped")],
                          capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    heavy = [m for m in report["loaded"] if m.split(".")[0] in ("scipy", "matplotlib", "exudyn", "fmpy_gui")]
    assert heavy == []
    assert "numba" in report["loaded"] and "wearjoint.joint" in report["loaded"]
    assert "resources" in report["wearjoint"]  # the FMU's own copy of the package
    try:
        import scipy  # noqa: F401
    except ImportError:
        return
    assert report["host_scipy"], "the FMU left scipy blocked in sys.modules"


def test_library_modules_stay_light(tmp_path):
    code = ("import sys, wearjoint.fmu.variables, wearjoint.fmu.build_pythonfmu; "
            "print(sorted(m for m in ('pythonfmu', 'fmpy', 'exudyn', 'matplotlib') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                          cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(REPO_ROOT)})
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


CLOSURE_SCRIPT = textwrap.dedent("""
    import json, sys
    resources = sys.argv[1]
    sys.path.insert(0, resources)
    import ClearanceWearJoint  # noqa: F401
    print(json.dumps({name: module.__file__ for name, module in sys.modules.items()
                      if name == "wearjoint" or name.startswith("wearjoint.")}))
""")


def test_fmu_ships_exactly_the_slaves_import_closure(fmu, tmp_path):
    if fmu["backend"] != "pythonfmu":
        pytest.skip("the native FMU ships no Python")
    resources = Path(fmu["dir"]) / "resources"
    done = subprocess.run([sys.executable, "-c", CLOSURE_SCRIPT, str(resources)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    loaded = {Path(f).resolve() for f in json.loads(done.stdout.strip().splitlines()[-1]).values()}
    package = (resources / "wearjoint").resolve()
    assert all(package in f.parents for f in loaded), loaded   # nothing from the source tree
    assert loaded == {f.resolve() for f in package.rglob("*.py")}


def test_build_key_follows_the_shipped_files_only(tmp_path, monkeypatch):
    from wearjoint.fmu import build_pythonfmu as fmu_build

    tree = tmp_path / "tree"
    for source in (*fmu_build.shipped_sources(), fmu_build.PACKAGE_DIR / "runner.py"):
        copy = tree / source.relative_to(fmu_build.PACKAGE_DIR.parent)
        copy.parent.mkdir(parents=True, exist_ok=True)
        copy.write_bytes(source.read_bytes())
    monkeypatch.setattr(fmu_build, "PACKAGE_DIR", tree / "wearjoint")
    monkeypatch.setattr(fmu_build, "SLAVE_SOURCE", tree / fmu_build.SLAVE_SOURCE.relative_to(REPO_ROOT))
    monkeypatch.setattr(fmu_build, "SHIM_SOURCE", tree / fmu_build.SHIM_SOURCE.relative_to(REPO_ROOT))
    key = fmu_build.build_key(P.n_points)
    assert key == build_key(P.n_points)

    def edited(relative):
        path = tree / relative
        original = path.read_bytes()
        path.write_bytes(original + b"\n# edited\n")
        try:
            return fmu_build.build_key(P.n_points)
        finally:
            path.write_bytes(original)

    assert edited("wearjoint/runner.py") == key
    for shipped in ("wearjoint/joint.py", "wearjoint/core/contact.py", "fmu_src/pythonfmu/status_shim.c",
                    "fmu_src/pythonfmu/ClearanceWearJoint.py"):
        assert edited(shipped) != key, shipped


# ------------------------------------------------------------- build command
def test_build_is_skipped_when_identical_and_n_points_is_built_in(tmp_path):
    small = build_fmu(tmp_path, n_points=64)
    stamp = small.stat().st_mtime_ns
    assert build_fmu(tmp_path, n_points=64) == small
    assert small.stat().st_mtime_ns == stamp
    build_fmu(tmp_path, n_points=64, force=True)
    assert small.stat().st_mtime_ns != stamp

    md = read_model_description(str(small))
    assert sum(v.name.startswith("wear_depth[") for v in md.modelVariables) == 64
    assert next(int(v.start) for v in md.modelVariables if v.name == "n_points") == 64
    assert validate_fmu(str(small)) == []
    assert default_fmu_path(64) != default_fmu_path(P.n_points)


@pytest.mark.parametrize("backend", ["native", "pythonfmu"])
def test_build_fails_clearly_without_a_c_compiler(tmp_path, monkeypatch, capsys, backend):
    import argparse

    from wearjoint.fmu.build import build_fmu as build_with

    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    with pytest.raises(RuntimeError, match="C compiler"):
        build_with(tmp_path, n_points=64, force=True, backend=backend)
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    assert run(parser.parse_args(["--out", str(tmp_path / "out"), "--n-points", "64", "--backend", backend])) == 2
    assert "no-such-cc" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("backend", ["native", "pythonfmu"])
def test_cli_reports_a_bad_n_points(capsys, tmp_path, backend):
    from wearjoint.cli import main

    assert main(["build-fmu", "--out", str(tmp_path), "--n-points", "3", "--backend", backend]) == 2
    assert "--n-points=3 (n_points) is invalid" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


def test_a_profile_stride_exposes_every_sth_point_and_none(tmp_path):
    """--profile-stride S: wear_depth[1], [1 + S], ... are outputs with the worn depths of those points (the
    full FMU's values), 0: none; the profile stays whole in the state; refused for FMI 3.0 and pythonfmu."""
    import fmpy
    from fmpy_instance import Slave, contact_inputs

    from wearjoint.fmu import variables as fv
    from wearjoint.fmu.build import build_fmu
    from wearjoint.parameters import ParameterError

    def worn(path):
        md = fmpy.read_model_description(str(path))
        fmu = {"md": md, "dir": fmpy.extract(str(path), unzipdir=str(tmp_path / path.parent.name / "x")),
               "vr": fv.value_references(md)}
        s = Slave(fmu, path.parent.name, parameters={"wear_factor": 1000.0}).initialise()
        s.set_inputs(contact_inputs(depth=4e-6))
        for k in range(20):
            s.fmu.doStep(k * 1e-5, 1e-5)
        names = [v.name for v in md.modelVariables if v.name.startswith("wear_depth[")]
        values = dict(zip(names, s.get(names))) if names else {}
        state = s.fmu.serializeFMUstate(s.fmu.getFMUstate())
        s.free()
        return values, len(state)

    full, full_state = worn(build_fmu(tmp_path / "full", platforms="linux64"))
    strided, strided_state = worn(build_fmu(tmp_path / "strided", platforms="linux64", profile_stride=10))
    none, none_state = worn(build_fmu(tmp_path / "none", platforms="linux64", profile_stride=0))
    assert len(full) == 1257 and sorted(strided, key=lambda n: int(n[11:-1])) == [fv.wear_depth_name(z)
                                                                                   for z in range(1, 1258, 10)]
    assert max(full.values()) > 0.0 and strided == {name: full[name] for name in strided} and none == {}
    assert full_state == strided_state == none_state            # the whole profile in each FMU's state
    from wearjoint import JointParameters
    from wearjoint.fmu.instance import FmuInstance

    with pytest.raises(ParameterError, match="every profile point as an output"):   # our master reads them all
        FmuInstance(tmp_path / "none" / "ClearanceWearJoint.fmu", JointParameters(), np.zeros(12), np.zeros(1),
                    ("normal_force",))
    for bad in ({"profile_stride": 2, "fmi_version": 3}, {"profile_stride": 2, "backend": "pythonfmu"},
                {"profile_stride": -1}):
        with pytest.raises(ParameterError, match="profile_stride"):
            build_fmu(tmp_path / "bad", platforms="linux64", **bad)


def test_a_pythonfmu_fmu_loaded_in_the_process_does_not_break_the_next_build(built_fmu, tmp_path):
    """Loading the pythonfmu FMU in process puts its resources (the slave, a copy of pythonfmu's modules
    without its binaries) on sys.path; a build in the same process must still use the installed pythonfmu."""
    code = textwrap.dedent(f"""
        import sys, zipfile
        from fmpy import extract, instantiate_fmu, read_model_description
        from wearjoint.fmu.build_pythonfmu import build_fmu
        md = read_model_description({str(built_fmu)!r})
        fmu = instantiate_fmu(extract({str(built_fmu)!r}, unzipdir={str(tmp_path / "unzipped")!r}), md,
                              "CoSimulation")
        fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode(); fmu.exitInitializationMode()
        assert "pythonfmu" in sys.modules and "resources" in sys.modules["pythonfmu"].__file__
        built = build_fmu({str(tmp_path)!r}, n_points=64, force=True)
        assert "binaries/linux64/ClearanceWearJoint.so" in zipfile.ZipFile(built).namelist()
        fmu.terminate(); fmu.freeInstance()
        print("ok")""")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stderr[-3000:]


def test_a_scalar_output_without_a_source_is_a_build_error(monkeypatch):
    """Each scalar output of the joint FMU names where its value comes from (a result slot, the max wear depth or
    the worn volume): one with none is refused when the C tables are generated, not wired to some other value."""
    from wearjoint.fmu import build_native
    from wearjoint.fmu import variables as fv

    stray = dataclasses.replace(fv.SCALAR_OUTPUTS[-1], name="stray_output")
    monkeypatch.setattr(fv, "SCALAR_OUTPUTS", (*fv.SCALAR_OUTPUTS, stray))
    with pytest.raises(RuntimeError, match="scalar output 'stray_output' has no source"):
        build_native.model_variables_header(16, "guid")
