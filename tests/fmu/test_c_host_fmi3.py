"""The native FMU as FMI 3.0, Co-Simulation and Model Exchange, driven from C with no Python on the
host: ``tests/c_host/fmi3_host.c`` (on ``host_common.c``, the script machinery it shares with the
FMI 2.0 host; commands in tests/c_host/README.md).

References independent of the FMI 3.0 host: the FMI 2.0 build of the same FMU driven by the FMI 2.0
C host through the same rows, and the in-process ``ClearanceJoint``.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmi_host import (  # noqa: E402
    assert_valgrind_clean, build_fmi3_host, event_lines, gcc_or_skip, needed_libraries, profile_command,
    profile_values, run_c_host, start_script, stderr_value, trace_command, trace_rows, valgrind_or_skip,
    write_trace_file,
)
from kinematic_trace import run_joint_on_trace, slider_crank_trace  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.fmu.model_description import fmi3_value_references  # noqa: E402

VR3 = fmi3_value_references()
JOINT = paper_joint(wear_factor=10.0)
N_POINTS = JOINT.n_points
ROWS, STEP = 1000, 1e-4          # 0.1 s of the slider-crank: contact onsets, separations, wear
OUTPUTS = [v.name for v in fv.SCALAR_OUTPUTS]
STATE_DOUBLES = fv.STATE_HEAD_SIZE + L.N_MEMORY   # float64 values of an FMU state besides the wear depths
STATE_FRAME = 24 + 4                             # its header and CRC-32C (docs/reference/fmu.md, the state format)


# ------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def fmi3(shared_build, tmp_path_factory):
    path = shared_build(backend="native", fmi_version=3)
    md = read_model_description(str(path))
    return {"dir": Path(extract(str(path), unzipdir=str(tmp_path_factory.mktemp("c_fmi3_unzipped")))),
            "token": md.guid}


@pytest.fixture(scope="module")
def fmi2(native_fmu, tmp_path_factory):
    md = read_model_description(str(native_fmu))
    return {"dir": Path(extract(str(native_fmu), unzipdir=str(tmp_path_factory.mktemp("c_fmi2_unzipped")))),
            "token": md.guid, "vr": fv.value_references(md)}


@pytest.fixture(scope="module")
def trace():
    return slider_crank_trace(JOINT, ROWS, STEP)


@pytest.fixture(scope="module")
def trace_file(trace, tmp_path_factory):
    return write_trace_file(tmp_path_factory.mktemp("fmi3_trace") / "trace.txt", trace)


def run3(host, fmu, script, **kw):
    code, out, err = run_c_host(host, fmu["dir"], fv.MODEL_NAME, fmu["token"], script, **kw)
    assert code == 0, out[-2000:] + err[-3000:]
    return out, err


def start3(interface="instantiate", n_points=None, params=JOINT) -> str:
    """An FMI 3.0 instance initialised with ``params`` (n_points set in Configuration Mode); a Model
    Exchange one left in Continuous-Time Mode."""
    return start_script(3, VR3, params, interface, n_points, name="joint3")


def start2(fmu, interface="instantiate") -> str:
    return start_script(2, fmu["vr"], JOINT, interface, name="joint2")


def profile3(out, n=N_POINTS) -> np.ndarray:
    """The last ``float64 <wear_depth vr> v1 .. vn`` line."""
    return profile_values(out, 3, VR3, n)


def relative(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape
    scale = np.maximum(np.maximum(np.abs(a), np.abs(b)), 1e-300)
    return float(np.max(np.abs(a - b) / scale)) if a.size else 0.0


def joint_run(rows, me=False, n_points=N_POINTS):
    return run_joint_on_trace(paper_joint(wear_factor=JOINT.wear_factor, n_points=n_points), rows, me)


# ------------------------------------------------------------------ the host itself
def test_fmi3_host_builds_without_warnings_and_needs_libc_libdl_only(fmi3_host, tmp_path):
    gcc_or_skip(fmi_version=3)
    build_fmi3_host(tmp_path, extra_flags=["-Werror", "-Wshadow"])
    assert needed_libraries(fmi3_host) <= {"libc.so.6", "libdl.so.2"}


# ------------------------------------------------------------------ the same numbers as FMI 2.0
def test_cosimulation_and_model_exchange_from_c_equal_fmi2(fmi3, fmi2, fmi3_host, c_host, trace, trace_file):
    """The same rows through FMI 3.0 (fmi3_host) and FMI 2.0 (fmi2_host), in Co-Simulation and in
    Model Exchange: outputs, events and worn profiles within 1e-12 relative (in fact equal); and
    Co-Simulation equals the in-process joint."""
    wear2 = profile_command(2, fmi2["vr"], N_POINTS)
    wear3 = f"get_float64 {VR3['wear_depth']}:{N_POINTS} {VR3['time']}\n"
    joint_outputs, joint_wear = joint_run(trace)
    for me in (False, True):
        interface = "instantiate_me" if me else "instantiate"
        out3, err3 = run3(fmi3_host, fmi3, start3(interface) + trace_command(VR3, trace_file, me) + wear3 + "free\n")
        out2, _ = run3(c_host, fmi2, start2(fmi2, interface) + trace_command(fmi2["vr"], trace_file, me) + wear2)
        rows3, rows2 = np.array(trace_rows(out3), float), np.array(trace_rows(out2), float)
        assert rows3.shape == (ROWS, 1 + len(OUTPUTS))
        assert relative(rows3, rows2) <= 1e-12, me
        wear = [float(line.split()[2]) for line in out2.splitlines() if line.startswith("real ")]
        assert relative(profile3(out3), wear) <= 1e-12 and max(wear) > 1e-6
        assert event_lines(out3) == event_lines(out2)
        times = [float(line.split()[2]) for line in out3.splitlines() if line.startswith(f"float64 {VR3['time']} ")]
        assert times == [float(trace[-1, 0] if me else trace[-1, 0] + STEP)]     # %.17g round-trips exactly
        assert stderr_value(err3, "trace_seconds") > 0.0
        if me:
            # the 0.1 ms steps wear over the wear-step limit (1e-5 s): logged once, every call fmi3OK
            assert len(event_lines(out3)) >= 10 and re.search(r"trace_me ok rows=1000 events=\d+", out3)
        else:
            assert relative(rows3[:, 1:], joint_outputs) <= 1e-12
            assert relative(profile3(out3), joint_wear) <= 1e-12


@pytest.mark.parametrize("n_points", [628, 2514])
def test_n_points_set_at_instantiation_sizes_the_worn_profile(fmi3, fmi3_host, trace, n_points, tmp_path):
    """n_points set in Configuration Mode (Co-Simulation and Model Exchange instances): the worn
    profile is an array of exactly n_points values, equal to the in-process joint's of that size;
    the FMU state holds n_points depths."""
    rows = trace[:300]
    path = write_trace_file(tmp_path / "rows.txt", rows)
    get = (f"get_uint64 {VR3['n_points']}\nget_float64 {VR3['wear_depth']}:{n_points}\n"
           f"get_float64 {VR3['wear_depth']}:{n_points + 1}\nexpect error\n"
           f"get_float64 {VR3['wear_depth']}:{n_points - 1}\nexpect error\nget_state 0\nserialize 0 {tmp_path / 's'}\n")
    for me in (False, True):
        out, err = run3(fmi3_host, fmi3, start3("instantiate_me" if me else "instantiate", n_points)
                        + trace_command(VR3, path, me, "events_first" if me else "") + get + "free\n")
        assert f"uint64 {VR3['n_points']} {n_points}" in out.splitlines()
        outputs, wear = joint_run(rows, me, n_points)
        assert relative(profile3(out, n_points), wear) <= 1e-12 and wear.max() > 0.0
        assert relative(np.array(trace_rows(out), float)[:, 1:], outputs) <= 1e-12
        assert out.count("get_float64 error") == 2
        assert f"wear_depth has n_points={n_points}" in err
        assert f"serialize 0 ok bytes={STATE_FRAME + 8 * (STATE_DOUBLES + n_points)}" in out


def test_invalid_n_points_gives_fmi3error_naming_it(fmi3, fmi3_host):
    bad_values = (0, 7, 1_000_001, 2**64 - 1)
    script = "instantiate bad_n\nenter_config\n" + "".join(
        f"set_uint64 {VR3['n_points']}={n}\nexpect error\n" for n in bad_values)
    script += (f"get_uint64 {VR3['n_points']}\nexit_config\nset_uint64 {VR3['n_points']}=628\nexpect error\n"
               f"enter_init\nset_uint64 {VR3['n_points']}=2514\nexpect error\nexit_init\n"
               f"get_uint64 {VR3['n_points']}\nget_float64 {VR3['wear_depth']}:{N_POINTS}\nfree\n")
    out, err = run3(fmi3_host, fmi3, script)
    assert out.count("set_uint64 error") == len(bad_values) + 2
    errors = [line for line in err.splitlines() if line.startswith("LOG error logStatusError: fmi3SetUInt64")]
    for n in bad_values:
        assert any(f"n_points={n} is invalid" in line for line in errors), n
    assert sum("can be changed in Configuration Mode only" in line and "n_points" in line for line in errors) == 2
    assert out.splitlines().count(f"uint64 {VR3['n_points']} {N_POINTS}") == 2     # unchanged throughout
    assert len(profile3(out)) == N_POINTS


def test_fmu_state_round_trips_are_bit_identical(fmi3, fmi2, fmi3_host, c_host, trace, tmp_path):
    """get_state / set_state and serialize / deserialize give the same continuation to the last bit,
    in Co-Simulation and in Model Exchange (events included); the serialized FMI 3.0 state is the
    FMI 2.0 build's, byte for byte."""
    # the first part ends out of contact, the continuation crosses onsets and separations and ends in
    # contact: set_state must also restore trace_me's sign at the last completed step
    first = write_trace_file(tmp_path / "first.txt", trace[:120])
    later = write_trace_file(tmp_path / "later.txt", trace[120:420])
    for me in (False, True):
        f1, f2, f_fmi2 = (tmp_path / f"{name}_{me}.bin" for name in ("one", "two", "fmi2"))
        interface = "instantiate_me" if me else "instantiate"
        tail = trace_command(VR3, later, me) + f"get_float64 {VR3['wear_depth']}:{N_POINTS}\n"
        out, _ = run3(fmi3_host, fmi3, start3(interface) + trace_command(VR3, first, me)
                      + f"get_state 0\nserialize 0 {f1}\necho A\n" + tail + "set_state 0\necho B\n" + tail
                      + f"deserialize 1 {f1}\nserialize 1 {f2}\nfree_state 0\nfree_state 1\n")
        a, b = out.split("\nA\n", 1)[1].split("\nB\n", 1)
        a = a[:a.rindex("set_state 0")]
        b = b[:b.index("deserialize")]
        assert a == b and a.count("\nout ") >= 299 and profile3(a).max() > 0.0, me
        if me:
            assert "event " in a
        assert f1.read_bytes() == f2.read_bytes()
        assert len(f1.read_bytes()) == STATE_FRAME + 8 * (STATE_DOUBLES + N_POINTS)
        assert "free_state 1 ok pointer_null=1" in out
        run3(c_host, fmi2, start2(fmi2, interface) + trace_command(fmi2["vr"], first, me)
             + f"get_state 0\nserialize 0 {f_fmi2}\n")
        assert f1.read_bytes() == f_fmi2.read_bytes(), me


# ------------------------------------------------------------------ errors and bad input
def test_wrong_instantiation_token_gives_null(fmi3, fmi3_host):
    out, err = run3(fmi3_host, fmi3, "instantiate bad {00000000-0000-0000-0000-000000000000}\nexpect error\n"
                                     "instantiate_me bad {not-this-fmu}\nexpect error\ninstantiate good\nfree\n"
                                     "version\n")
    assert out.splitlines() == ["instantiate null", "instantiate_me null", "instantiate ok", "free ok",
                                "version 3.0"]
    assert "LOG error logStatusError: fmi3InstantiateCoSimulation: the instantiationToken does not match" in err
    assert "LOG error logStatusError: fmi3InstantiateModelExchange: the instantiationToken does not match" in err
    code, out, err = run_c_host(fmi3_host, fmi3["dir"], fv.MODEL_NAME, fmi3["token"],
                                "instantiate bad {00000000-0000-0000-0000-000000000000}\nfree\n")
    assert code == 1 and "fmi3InstantiateCoSimulation returned error at script line 1" in err


@pytest.mark.parametrize("script, code, message", [
    ("setup 0\n", 2, "fmi3_host: error: unknown command 'setup' (script line 1)"),
    ("instantiate a\nget_float64 51:x\n", 2, "value count: not an integer"),
    ("instantiate a\nset_uint64 35=-1\n", 2, "not an unsigned 64-bit integer: '-1'"),
    ("instantiate a\ntrace_me /no/such/file 0 - -\n", 2, "trace_me: cannot open '/no/such/file'"),
    ("instantiate a\ntrace_me /dev/null 0 - - sideways\n", 2, "events_after or events_first, got 'sideways'"),
    ("instantiate a\ndo_step 0 1e-3\n", 1, "fmi3DoStep returned error at script line 2"),
    ("instantiate a\nenter_init\nexit_init\nget_float64 44\nexpect discard\n", 1,
     "expect discard failed at script line 5: the previous command returned ok"),
])
def test_bad_input_and_unacknowledged_failures_exit_1_or_2(fmi3, fmi3_host, script, code, message):
    got, out, err = run_c_host(fmi3_host, fmi3["dir"], fv.MODEL_NAME, fmi3["token"], script)
    assert got == code, out + err
    assert message in err


def test_missing_binary_cycles_and_start_up(fmi3, fmi2, fmi3_host):
    code, out, err = run_c_host(fmi3_host, fmi2["dir"], fv.MODEL_NAME, fmi3["token"], "instantiate a\n")
    assert code == 2 and out == ""
    assert f"cannot load the FMU binary {fmi2['dir'].resolve()}/binaries/x86_64-linux/{fv.MODEL_NAME}.so" in err
    for flags in ([], ["--model-exchange"]):
        out, err = run3(fmi3_host, fmi3, "time_load\nget_number_of_event_indicators\n"
                                         "get_number_of_continuous_states\nfree\ncycle 10\ncycle 300\n", host_args=flags)
        assert out.splitlines() == ["time_load ok", "get_number_of_event_indicators ok n=1",
                                    "get_number_of_continuous_states ok n=0", "free ok", "cycle ok iterations=10",
                                    "cycle ok iterations=300"]
        assert stderr_value(err, "startup_seconds") < 0.5
        assert stderr_value(err, "rss_kb_after") - stderr_value(err, "rss_kb_before") <= 8


# ------------------------------------------------------------------ valgrind
@pytest.mark.slow
def test_fmi3_host_runs_the_fmu_under_valgrind(fmi3, fmi3_host, trace, tmp_path):
    """Co-Simulation with n_points set in Configuration Mode, arrays, states and serialisation,
    Model Exchange with events and a rejected trial, error statuses, cycles: zero errors, no
    definite leak."""
    valgrind_or_skip()
    rows = write_trace_file(tmp_path / "rows.txt", trace[:400])
    later = write_trace_file(tmp_path / "later.txt", trace[400:600])
    state = tmp_path / "state.bin"
    script = (start3("instantiate", 628) + trace_command(VR3, rows)
              + f"get_float64 {VR3['wear_depth']}:628 {VR3['time']}\nget_int64 {VR3['rho_mode']}\n"
              + f"get_state 0\nserialize 0 {state}\ndeserialize 1 {state}\nset_state 1\n"
              + trace_command(VR3, later) + "set_state 0\nfree_state 1\n"
              + f"set_float64 {VR3['pin_x']}=nan\ndo_step 0.04 1e-4\nexpect discard\n"
              + f"get_float64 {VR3['normal_force']}\nexpect error\nget_float64 {VR3['wear_depth']}:3\nexpect error\n"
              + "get_state 2\nterminate\nreset\nfree\n"
              + "instantiate bad {0}\nexpect error\n"
              + start3("instantiate_me", 2514) + trace_command(VR3, rows, True)
              + f"set_time 0.05\nset_float64 {VR3['pin_x']}=0.001\nget_event_indicators 1\n"
              + trace_command(VR3, later, True, "events_first") + "get_state 3\n"
              + "enter_event_mode\nupdate_discrete_states\nenter_continuous_time_mode\nget_derivatives 0\n"
              + "terminate\nfree\ncycle 20\n")
    out, err = run3(fmi3_host, fmi3, script, valgrind=True, timeout=1200)
    # each instance's first trace wears over the wear-step limit (0.1 ms steps): logged, the calls fmi3OK
    assert out.count("trace warning") == 0 and out.count("trace ok") == 2 and "cycle ok iterations=20" in out
    assert out.count("trace_me warning") == 0 and out.count("trace_me ok") == 2
    assert_valgrind_clean(err)


@pytest.mark.slow
@pytest.mark.parametrize("case, expected", [("unacknowledged", 1), ("syntax_error", 2), ("bad_trace_row", 2)])
def test_fmi3_host_error_exits_are_clean_under_valgrind(fmi3, fmi3_host, tmp_path, case, expected):
    """Every exit path frees the FMU states held in slots, the instance and the host's memory."""
    valgrind_or_skip()
    bad = tmp_path / "bad.txt"
    bad.write_text("0 0.1\n0.1 oops\n")
    held = start3("instantiate", 628) + "get_state 0\nget_state 1\n"
    scripts = {"unacknowledged": held + "do_step 3 -1\nget_float64 44\n", "syntax_error": held + "get_int64 x\n",
               "bad_trace_row": held + f"trace_me {bad} 0 - -\n"}
    code, out, err = run_c_host(fmi3_host, fmi3["dir"], fv.MODEL_NAME, fmi3["token"], scripts[case], valgrind=True)
    assert code == expected, err[-3000:]
    assert_valgrind_clean(err)
