"""The native FMU relinked with AddressSanitizer and UndefinedBehaviorSanitizer (slow): the C hosts
(built with the same sanitizers) run a worn trace, state rollback, serialisation, a corrupted state,
non-finite inputs and instance cycles; the FMI state machines run on it in a child process.  Zero
reports.  The kernel objects come from llvmlite, not gcc: they are linked in but not instrumented;
the C layer's memory and every call into it are."""
import math

import numpy as np
import pytest
from fmi_host import (SANITIZER_FLAGS, SANITIZER_REPORTS, build_c_host, build_fmi3_host, gcc_or_skip,
                      needed_libraries, run_c_host, sanitized_fmu, sanitizer_runtime_environment, start_script,
                      trace_command, write_trace_file)
from test_fmi_fuzz import MACHINES, check_counts, run_machine

from wearjoint import paper_joint
from wearjoint.fmu import variables as fv

pytestmark = pytest.mark.slow
N_POINTS = 64


@pytest.fixture(scope="module")
def sanitized(tmp_path_factory):
    """{FMI version: (unzipped sanitized FMU, C host built with the sanitizers, GUID, value references)}."""
    from fmpy import read_model_description

    from wearjoint.fmu.build_native import build_fmu

    gcc_or_skip(fmi_version=3)
    built = {}
    for version, build_host in ((2, build_c_host), (3, build_fmi3_host)):
        path = build_fmu(tmp_path_factory.mktemp(f"asan{version}"), n_points=N_POINTS, fmi_version=version,
                         platform_names=["linux64"])
        folder = sanitized_fmu(path, tmp_path_factory.mktemp(f"asan{version}_unzipped"), version)
        host = build_host(tmp_path_factory.mktemp(f"asan_host{version}"), extra_flags=SANITIZER_FLAGS)
        binaries = list(folder.glob("binaries/*/*.so"))
        assert binaries and all({"libasan", "libubsan"} <= {n.split(".")[0] for n in needed_libraries(b)}
                                for b in binaries)
        md = read_model_description(str(folder))
        built[version] = (folder, host, md.guid, {v.name: v.valueReference for v in md.modelVariables})
    return built


def _trace(path, joint, rows=400):
    """The pin pressed 3 um into the bushing of ``joint`` along a slowly turning direction (wear every step): the
    pin body at the origin, the bushing body placed so that its bushing centre sits that far from the pin centre."""
    t = np.arange(rows) * 1e-5
    angle = 2 * math.pi * t / (rows * 1e-5)
    e = joint.clearance_m + 3e-6
    inputs = np.zeros((rows, 12))
    inputs[:, 3], inputs[:, 5], inputs[:, 11] = 0.1, -15.0, 3.0
    inputs[:, 6] = joint.pin_offset_m[0] - joint.bushing_offset_m[0] - e * np.cos(angle)
    inputs[:, 7] = joint.pin_offset_m[1] - joint.bushing_offset_m[1] - e * np.sin(angle)
    return write_trace_file(path, np.column_stack([t, np.full(rows, 1e-5), inputs]))


@pytest.mark.parametrize("version", [2, 3])
def test_c_host_on_the_sanitized_fmu_reports_nothing(sanitized, version, tmp_path):
    folder, host, guid, vr = sanitized[version]
    joint = paper_joint(wear_factor=1e4)
    trace = _trace(tmp_path / "trace.txt", joint)
    state = tmp_path / "state.bin"
    corrupted = tmp_path / "corrupted.bin"
    set_real = "set_real" if version == 2 else "set_float64"
    get_real = "get_real" if version == 2 else "get_float64"
    script = (start_script(version, vr, joint, n_points=N_POINTS if version == 3 else None)
              + trace_command(vr, trace)
              + f"get_state 0\nserialize 0 {state}\n")
    code, stdout, stderr = run_c_host(host, folder, fv.MODEL_NAME, guid, script + "free\n", timeout=1200)
    assert code == 0 and not any(r in stderr for r in SANITIZER_REPORTS), stdout[-2000:] + stderr[-4000:]
    data = bytearray(state.read_bytes())
    data[40] ^= 0x08
    corrupted.write_bytes(bytes(data))
    script += (f"deserialize 1 {state}\nset_state 1\ndo_step 0.004 1e-05\nset_state 0\nfree_state 0\nfree_state 1\n"
               f"deserialize 2 {corrupted}\nexpect error\n"
               f"{set_real} {vr['pin_x']}=nan\ndo_step 0.004 1e-05\nexpect discard\n"
               f"{get_real} {vr['pin_force_x']}\nexpect error\n{set_real} {vr['pin_x']}=1e300\n"
               f"{get_real} {vr['penetration']}\nexpect error\nterminate\nfree\ncycle 20\n")
    code, stdout, stderr = run_c_host(host, folder, fv.MODEL_NAME, guid, script, timeout=1200)
    assert code == 0, stdout[-2000:] + stderr[-4000:]
    assert not any(r in stderr for r in SANITIZER_REPORTS), stderr[-4000:]


@pytest.mark.parametrize("machine", MACHINES)
def test_state_machines_on_the_sanitized_fmu_report_nothing(sanitized, machine):
    dirs = {version: str(folder) for version, (folder, *_) in sanitized.items()}
    check_counts(machine, run_machine(dirs, machine, examples=60, steps=40, env=sanitizer_runtime_environment()))
