"""The native SliderCrank FMU in the C hosts (FMI 2.0 and 3.0, no Python), its parameters' and states' errors,
its state round trip and the cross-compiled binaries (tests/fmu/test_slider_crank_fmu.py: the model).

References are independent of the FMU: the ideal slider-crank's closed form (slider
x3 = l1 cos th1 + sqrt(l2^2 - l1^2 sin^2 th1), its derivatives) and the ideal mechanism of
:mod:`wearjoint.core.slider_crank` (the crank-rod revolute as a constraint, whose Lagrange
multipliers give the joint's reaction loads fed to the FMU).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmi_host import (  # noqa: E402
    assert_valgrind_clean, build_c_host, platform_or_skip, run_c_host, trace_rows,
    valgrind_or_skip, write_trace_file,
)
from slider_crank_fmu import (  # noqa: E402
    INPUT_VRS, OUTPUT_VRS, STATE_VRS, WIN64_TOLERANCE, initialised_slave, slider_crank_fmus, smooth_loads,
    start_script, trace_command,
)

from wearjoint.core import layout as L  # noqa: E402
from wearjoint.core.state_format import CONTENTS_FMU, CONTENTS_MECHANISM  # noqa: E402
from wearjoint.fmu import slider_crank as sc  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.joint import read_state_bytes, state_bytes  # noqa: E402
from wearjoint.mechanism_parameters import MECHANISM_FIELDS  # noqa: E402
from wearjoint.parameters import ParameterError, SliderCrankParameters  # noqa: E402


@pytest.fixture(scope="module")
def fmus(shared_build, tmp_path_factory):
    return slider_crank_fmus(shared_build, tmp_path_factory)


@pytest.mark.parametrize("name, value, allowed", [
    ("crank_length", 0.0, "> 0 (from 1e-06 to 100 m)"),
    ("rod_length", 0.04, "> 0 (from 1e-06 to 100 m) and > crank_length (crank_length = 0.05)"),
    ("slider_mass", -1.0, "> 0 (from 1e-06 to 1e+06 kg)"),
    ("crank_mass", 1e300, "> 0 (from 1e-06 to 1e+06 kg)"),       # the ideal joint's force was NaN
    ("rod_inertia", 1e-300, "> 0 (from 1e-12 to 1e+06 kg.m2)"),
    ("crank_speed", math.inf, "a finite value > 0 (from 0.001 to 100000 rpm)"),
    ("initial_crank_angle", math.nan, "a finite real number"),
    ("gravity_y", 1e300, "in [-10000, 10000]"),                  # the joint's inputs became NaN
    ("slider_force_constant", -1e300, "in [-1e+09, 1e+09]"),
    ("baumgarte_beta", -0.5, ">= 0 (at most 1e+06 1/s)"),
    (sc.MAX_INTERNAL_STEP_NAME, 0.0, "> 0"),
    ("clearance_joint", 1.5, "0 (crank-rod), 1 (rod-slider), 2 (crank-ground)"),
])
def test_bad_parameter_fails_initialisation_naming_the_variable(fmus, c_host, fmi3_host, name, value, allowed):
    """The FMU refuses what SliderCrankParameters refuses, at exitInitializationMode (FMI 2.0 and
    3.0), with one message naming the variable, its value and the allowed range; nothing on stdout
    but the host's own lines."""
    field = {f.fmu_name: f.field for f in MECHANISM_FIELDS}.get(name)
    if field is not None:
        with pytest.raises(ParameterError, match=f"parameter {field}="):
            SliderCrankParameters(**{field: value})
    for version, host in ((2, c_host), (3, fmi3_host)):
        fmu = fmus[version]
        script = start_script(version, {name: value}) + "expect error\nfree\n"
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"], script)
        assert code == 0, err
        text = f"fmi{version}ExitInitializationMode: parameter {name}={value!r} is invalid: allowed {allowed}"
        assert text in err, (text, err)
        assert "exit_init error" in out and all(line.split()[0] in ("instantiate", "setup", "enter_init",
                                                                     "set_real", "set_float64", "exit_init", "free")
                                                for line in out.splitlines())


def test_c_hosts_run_it_without_python_and_equal_fmpy(fmus, c_host, fmi3_host, tmp_path):
    """The C hosts (FMI 2.0 and 3.0, no Python) step the FMU through a trace of loads: FMI 3.0 gives
    FMI 2.0's bits, and both are fmpy's run of the same calls."""
    h, n = 1e-3, 200
    rows = [[i * h, h, *smooth_loads(i * h)] for i in range(n)]
    path = write_trace_file(tmp_path / "loads.txt", rows)
    command = f"trace {path} {len(INPUT_VRS)} {','.join(map(str, INPUT_VRS))} {','.join(map(str, OUTPUT_VRS))}\n"
    results = {}
    for version, host in ((2, c_host), (3, fmi3_host)):
        fmu = fmus[version]
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"],
                                    start_script(version, {}) + command + "terminate\nfree\n")
        assert code == 0, err
        assert f"trace ok rows={n}" in out
        results[version] = np.array(trace_rows(out), dtype=float)
    assert np.array_equal(results[2], results[3])
    slave = initialised_slave(fmus[2])
    fmpy_rows = []
    for t, step, *loads in rows:
        slave.setReal(INPUT_VRS, loads)
        fmpy_rows.append([t, *slave.getReal(OUTPUT_VRS)])
        slave.doStep(t, step)
    slave.terminate()
    slave.freeInstance()
    assert np.array_equal(results[2], np.array(fmpy_rows))


def test_state_round_trip_is_exact_in_the_projects_state_format(fmus):
    """getFMUstate / serialise / deserialise / setFMUstate, then the same steps again: the same
    bits; the bytes are the project's one state format (core/state_format.py: a SliderCrank
    state whose head holds the time, the inputs, the parameters and the coordinates and
    velocities); a state with another magic is refused."""
    slave = initialised_slave(fmus[2])
    t, h = 0.0, 1e-3
    for i in range(20):
        loads = smooth_loads(t)
        slave.setReal(INPUT_VRS, list(loads))
        slave.doStep(t, h)
        t += h
    state = slave.serializeFMUstate(slave.getFMUstate())

    def continue_run(t):
        rows = []
        for _ in range(30):
            slave.setReal(INPUT_VRS, list(smooth_loads(t)))
            slave.doStep(t, h)
            t += h
            rows.append(slave.getReal(OUTPUT_VRS))
        return np.array(rows)

    y = np.array(slave.getReal(STATE_VRS))
    first = continue_run(t)
    slave.setFMUstate(slave.deSerializeFMUstate(state))
    assert np.array_equal(continue_run(t), first)
    head, memory, points = read_state_bytes(state, CONTENTS_MECHANISM, sc.STATE_HEAD_SIZE, 0)
    assert head[0] == t and head[1] == 1.0 and np.array_equal(head[-len(y):], y)
    assert np.array_equal(head[2:2 + len(INPUT_VRS)], loads) and points.size == 0
    with pytest.raises(Exception):
        slave.deSerializeFMUstate(b"WJFMU002" + state[8:])
    slave.terminate()
    slave.freeInstance()


def test_a_corrupted_state_is_refused_with_an_error_naming_the_check(fmus, c_host, fmi3_host, tmp_path):
    """Through the C hosts (FMI 2.0 and 3.0): a flipped bit in the payload (the CRC-32C), a flipped
    bit in the magic, a truncated state and a joint FMU's state are refused at deserialisation
    with fmi2Error / fmi3Error and one message naming the failed check; the host lives on and
    the instance, its intact state restored, steps on."""
    n = 20
    command = trace_command(tmp_path, n)
    for version, host in ((2, c_host), (3, fmi3_host)):
        fmu = fmus[version]
        good = tmp_path / f"good{version}.bin"
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"], start_script(version, {})
                                    + command + f"get_state 0\nserialize 0 {good}\nterminate\nfree\n")
        assert code == 0, err
        data = good.read_bytes()
        assert data.startswith(b"WJSTATE\0")
        payload_bit, magic_bit = bytearray(data), bytearray(data)
        payload_bit[len(data) // 2] ^= 0x04
        magic_bit[0] ^= 0x01
        cases = {"payload_bit": (bytes(payload_bit), "the bytes are corrupted"),
                 "magic_bit": (bytes(magic_bit), "does not begin with the magic bytes WJSTATE"),
                 "truncated": (data[:-5], f"the state has {len(data) - 5} bytes, its header declares {len(data)}"),
                 "joint_state": (state_bytes(CONTENTS_FMU, np.zeros(fv.STATE_HEAD_SIZE), np.zeros(2), np.zeros(3)),
                                 "contents are kind 2, expected kind 3")}
        script = start_script(version, {}) + command
        for name, (bad, _) in cases.items():
            (tmp_path / f"{name}{version}.bin").write_bytes(bad)
            script += f"deserialize 1 {tmp_path / f'{name}{version}.bin'}\nexpect error\n"
        resumed = trace_command(tmp_path, n, start=n * 1e-3)      # from the restored state's time
        script += f"deserialize 1 {good}\nset_state 1\n" + resumed + "terminate\nfree\n"
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"], script)
        assert code == 0, err
        for _, words in cases.values():
            assert words in err, (version, words, err)
        assert out.count(f"trace ok rows={n}") == 2


# ------------------------------------------------------------------ platforms and valgrind
@pytest.mark.parametrize("platform", ["win64", "aarch64-linux"])
def test_cross_binaries_run_the_trace_as_linux64(fmus, tmp_path, platform):
    """The FMI 2.0 trace (Co-Simulation) and FMI 3.0 Model Exchange derivatives through the C host
    built for the platform (win64 under wine, aarch64 under qemu): aarch64 gives linux64's bits,
    win64 agrees to 1e-9 of each output's range."""
    platform_or_skip(platform)
    if not (fmus[2]["dir"] / "binaries" / platform).is_dir():
        pytest.skip(f"the FMU carries no {platform} binary (its cross toolchain is not installed)")
    command = trace_command(tmp_path, 100)
    results = {}
    for where in ("linux64", platform):
        host = build_c_host(tmp_path / f"host_{where}", extra_flags=["-Werror"], platform=where)
        code, out, err = run_c_host(host, fmus[2]["dir"], sc.MODEL_IDENTIFIER, fmus[2]["token"],
                                    start_script(2, {}) + command + "terminate\nfree\n", platform=where)
        assert code == 0, err
        results[where] = np.array(trace_rows(out), dtype=float)
    if platform == "aarch64-linux":
        assert np.array_equal(results[platform], results["linux64"])
    else:
        scale = np.maximum(np.ptp(results["linux64"], axis=0), 1e-300)
        assert (np.abs(results[platform] - results["linux64"]) / scale).max() < WIN64_TOLERANCE


@pytest.mark.slow
def test_c_hosts_run_it_under_valgrind_clean(fmus, c_host, fmi3_host, tmp_path):
    """Co-Simulation trace, FMU states (get, serialise, deserialise, set; a foreign state refused), a
    refused parameter and Model Exchange calls under valgrind: no error, no leak (FMI 2.0 and 3.0)."""
    valgrind_or_skip()
    n = 20
    command = trace_command(tmp_path, n)
    foreign = tmp_path / "joint_state.bin"
    foreign.write_bytes(state_bytes(CONTENTS_FMU, np.zeros(fv.STATE_HEAD_SIZE), np.zeros(2), np.zeros(3)))
    for version, host in ((2, c_host), (3, fmi3_host)):
        fmu = fmus[version]
        state = tmp_path / f"state{version}.bin"
        script = (start_script(version, {sc.MAX_INTERNAL_STEP_NAME: 1e-4}) + command
                  + f"get_state 0\nserialize 0 {state}\ndeserialize 2 {foreign}\nexpect error\n"
                  + f"deserialize 1 {state}\nset_state 1\n" + trace_command(tmp_path, n, start=n * 1e-3)
                  + "terminate\nfree\n" + start_script(version, {"rod_length": 0.0}) + "expect error\nfree\n"
                  + start_script(version, {}, "instantiate_me") + f"get_derivatives {2 * L.N_COORDINATES}\nfree\n")
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"], script, valgrind=True)
        assert code == 0, err[-3000:]
        assert_valgrind_clean(err)
