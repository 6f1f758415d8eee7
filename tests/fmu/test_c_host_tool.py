"""The C FMI 2.0 Co-Simulation importer ``tests/c_host/fmi2_host.c``, tested on its own.

The host proves an FMU works from C with no Python on the host: it is compiled with gcc and run
with a clean environment (PATH only).  Here it drives a tiny hand-written FMU,
``tests/c_host/test_fmu/dahlquist.c`` (x' = -k x + u, advanced exactly over each step), so the
results have closed forms.  The command interface is documented at the top of ``fmi2_host.c`` and
in ``tests/c_host/README.md``.

The helpers (the test FMU's build and its start script among them) are in ``tests/fmi_host.py``, the
``c_host``, ``dahlquist_fmu`` and ``run`` fixtures in ``tests/conftest.py``; valgrind: test_c_host_valgrind.py.
"""
from __future__ import annotations

import math
import re
import shutil
import subprocess

import pytest
from fmi_host import (
    CLEAN_ENV, DAHLQUIST_GUID, DAHLQUIST_ID, VR_K, VR_NSTEPS, VR_U, VR_X, build_c_host,
    build_dahlquist_fmu, gcc_or_skip, init, needed_libraries, run_c_host, stderr_value, trace_rows,
    write_trace_file,
)

# --------------------------------------------------------------------------------------------
# building

def test_host_and_test_fmu_build_without_warnings(tmp_path):
    gcc_or_skip()
    build_c_host(tmp_path / "host", extra_flags=["-Werror", "-Wshadow"])
    build_dahlquist_fmu(tmp_path / "fmu", extra_flags=["-Werror"])


def test_host_and_test_fmu_need_only_libc_libdl_libm(c_host, dahlquist_fmu):
    assert needed_libraries(c_host) <= {"libc.so.6", "libdl.so.2"}
    assert needed_libraries(dahlquist_fmu / "binaries" / "linux64" / "dahlquist.so") <= {
        "libc.so.6", "libm.so.6"}


def test_test_fmu_model_description_is_valid(dahlquist_fmu):
    fmpy = pytest.importorskip("fmpy")
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(dahlquist_fmu)) == []
    md = fmpy.read_model_description(str(dahlquist_fmu))
    assert md.guid == DAHLQUIST_GUID
    assert md.coSimulation.modelIdentifier == DAHLQUIST_ID


# --------------------------------------------------------------------------------------------
# trace: the hot loop

def test_trace_reproduces_the_closed_form(run, tmp_path):
    k, x0, h, n = 2.0, 1.5, 0.01, 400
    trace = write_trace_file(tmp_path / "zero.txt", [(i * h, h, 0.0) for i in range(n)])
    rc, out, err = run(init(k, x0) + f"trace {trace} 1 {VR_U} {VR_X}\nget_integer {VR_NSTEPS}\n")
    assert rc == 0, err
    assert f"trace ok rows={n}" in out
    assert f"integer {VR_NSTEPS} {n}" in out
    rows = trace_rows(out)
    assert len(rows) == n
    for i, (t, x) in enumerate(rows):
        assert float(t) == i * h                      # %.17g round-trips the input time
        exact = x0 * math.exp(-k * float(t))
        assert abs(float(x) - exact) <= 1e-12 * exact, (i, x, exact)
    assert 0.0 <= stderr_value(err, "trace_seconds") < 5.0


def test_trace_sets_the_inputs_row_by_row(run, tmp_path):
    """u = 0.5 for t < 1, u = -1 from t = 1: piecewise closed form u/k + (x(t1) - u/k) e^{-k(t-t1)}."""
    k, x0, h, n, switch = 2.0, 1.5, 0.01, 200, 100
    u = [0.5 if i < switch else -1.0 for i in range(n)]
    trace = write_trace_file(tmp_path / "u.txt", [(i * h, h, u[i]) for i in range(n)])
    rc, out, err = run(init(k, x0) + f"trace {trace} 1 {VR_U} {VR_X},{VR_U}\n")
    assert rc == 0, err
    rows = trace_rows(out)
    assert len(rows) == n
    t1 = switch * h
    x1 = 0.25 + (x0 - 0.25) * math.exp(-k * t1)
    for i, (t, x, u_out) in enumerate(rows):
        t = float(t)
        assert float(u_out) == u[i]
        if i <= switch:   # the output at row `switch` is x(t1), before the step with the new u
            exact = 0.25 + (x0 - 0.25) * math.exp(-k * t)
        else:
            exact = -0.5 + (x1 + 0.5) * math.exp(-k * (t - t1))
        assert abs(float(x) - exact) <= 1e-12 * max(1.0, abs(exact)), (i, x, exact)


def test_trace_without_inputs_and_with_comments(run, tmp_path):
    trace = tmp_path / "plain.txt"
    trace.write_text("# comment\n\n0 0.5\n  0.5\t0.5  \n# another\n1 0.5\n")
    rc, out, err = run(init(1.0, 1.0) + f"trace {trace} 0 - {VR_X}\n")
    assert rc == 0, err
    rows = trace_rows(out)
    assert [r[0] for r in rows] == ["0", "0.5", "1"]
    assert [float(r[1]) for r in rows] == pytest.approx([1.0, math.exp(-0.5), math.exp(-1.0)],
                                                        rel=1e-15)


def test_trace_stops_at_a_failing_step(run, tmp_path):
    """The test FMU discards steps h > 10: rows up to the failing one are printed, then the status."""
    trace = write_trace_file(tmp_path / "big.txt", [(0.0, 1.0), (1.0, 1.0), (2.0, 11.0), (13.0, 1.0)])
    script = init() + f"trace {trace} 0 - {VR_X},{VR_K}\n"
    rc, out, err = run(script + "expect discard\nget_integer 4\n")
    assert rc == 0, err
    assert len(trace_rows(out)) == 3
    assert "trace discard row=2 call=fmi2DoStep" in out
    assert "integer 4 2" in out                      # the discarded step changed nothing
    assert "LOG discard logStatusDiscard: fmi2DoStep: step 11 > 10 refused" in err
    rc, out, err = run(script)                       # not acknowledged: FMI failure
    assert rc == 1
    assert "fmi2DoStep returned discard" in err


def test_stdout_is_deterministic(run, tmp_path):
    trace = write_trace_file(tmp_path / "t.txt", [(i * 0.1, 0.1, 0.3) for i in range(50)])
    script = init() + f"trace {trace} 1 3 0\nget_state 0\ncycle 3\n"
    first, second = run(script), run(script)
    assert first[0] == second[0] == 0
    assert first[1] == second[1]


def test_fmpy_agrees_with_the_host(run, tmp_path, dahlquist_fmu):
    """Cross-check with a reference importer: fmpy's simulate_fmu on the same FMU folder."""
    fmpy = pytest.importorskip("fmpy")
    k, x0, h, n = 2.0, 1.5, 0.01, 100
    result = fmpy.simulate_fmu(str(dahlquist_fmu), start_time=0.0, stop_time=n * h,
                               output_interval=h, fmi_type="CoSimulation",
                               start_values={"k": k, "x0": x0}, output=["x", "n_steps"])
    trace = write_trace_file(tmp_path / "t.txt", [(i * h, h) for i in range(n)])
    rc, out, err = run(init(k, x0) + f"trace {trace} 0 - {VR_X}\n")
    assert rc == 0, err
    rows = trace_rows(out)
    assert len(rows) == n
    assert list(result["n_steps"][:n]) == list(range(n))
    for row, (t, x, _) in zip(rows, result[:n]):
        assert float(row[0]) == pytest.approx(t, abs=1e-12)
        assert float(row[1]) == pytest.approx(x, rel=1e-14)


# --------------------------------------------------------------------------------------------
# FMU state

STEPS = "".join(f"do_step {i * 0.125!r} 0.125\n" for i in range(8, 13))


def test_state_get_set_round_trip_is_bit_identical(run):
    script = (init() + "".join(f"do_step {i * 0.125!r} 0.125\n" for i in range(8))
              + "set_real 3=0.75\n"
              + "get_state 0\necho A\nget_real 0 3\nget_integer 4\n"
              + STEPS + "echo B\nget_real 0 3\nget_integer 4\n"
              + "set_state 0\necho A2\nget_real 0 3\nget_integer 4\n"
              + STEPS + "echo B2\nget_real 0 3\nget_integer 4\n"
              # an occupied slot is handed to the FMU for reuse
              + "get_state 0\nset_state 0\necho B3\nget_real 0 3\nget_integer 4\n")
    rc, out, err = run(script)
    assert rc == 0, err
    blocks = {}
    for block in out.split("\n")[:-1]:
        if block in ("A", "B", "A2", "B2", "B3"):
            name = block
            blocks[name] = []
        elif block.split(" ", 1)[0] in ("real", "integer") and blocks:
            blocks[name].append(block)
    assert blocks["A"] == blocks["A2"]
    assert blocks["B"] == blocks["B2"] == blocks["B3"]
    assert blocks["A"] != blocks["B"]
    assert "integer 4 8" in blocks["A"] and "integer 4 13" in blocks["B"]
    assert "get_state 0 ok" in out and "set_state 0 ok" in out


def test_serialize_round_trip_is_bit_identical(run, tmp_path):
    f1, f2 = tmp_path / "s1.bin", tmp_path / "s2.bin"
    script = (init() + "".join(f"do_step {i * 0.125!r} 0.125\n" for i in range(8))
              + f"get_state 0\nserialize 0 {f1}\necho A\nget_real 0 1 2 3\nget_integer 4\n"
              + STEPS + "echo B\nget_real 0\n"
              + f"free_state 0\ndeserialize 1 {f1}\nserialize 1 {f2}\nset_state 1\n"
              + "echo A2\nget_real 0 1 2 3\nget_integer 4\n"
              + STEPS + "echo B2\nget_real 0\n"
              # deserializing into an occupied slot frees the old state first
              + f"deserialize 1 {f2}\nfree_state 1\n")
    rc, out, err = run(script)
    assert rc == 0, err
    assert "serialize 0 ok bytes=56" in out and "serialize 1 ok bytes=56" in out
    assert "deserialize 1 ok bytes=56" in out
    assert "free_state 0 ok pointer_null=1" in out and "free_state 1 ok pointer_null=1" in out
    assert f1.read_bytes() == f2.read_bytes()
    assert len(f1.read_bytes()) == 56
    lines = out.splitlines()

    def block(name):
        i = lines.index(name)
        return [line for line in lines[i + 1:i + 8] if line.split(" ", 1)[0] in ("real", "integer")]

    assert block("A") == block("A2")
    assert block("B") == block("B2")


def test_free_state_sets_the_pointer_to_null(run):
    rc, out, err = run(init() + "get_state 2\nfree_state 2\nfree_state 2\n"
                       "set_state 2\nexpect error\nserialize 2 /nonexistent/never_written\n"
                       "expect error\n")
    assert rc == 0, err
    assert out.count("free_state 2 ok pointer_null=1") == 2   # freeing a NULL state is a no-op
    assert "set_state 2 error" in out
    assert "serialize 2 error bytes=0" in out


def test_states_left_in_slots_are_freed(run):
    rc, out, err = run(init() + "get_state 0\nget_state 63\nfree\n")
    assert rc == 0, err
    assert "freeing the FMU state in slot 0" in err and "slot 63" in err
    assert out.splitlines()[-1] == "free ok"


# --------------------------------------------------------------------------------------------
# status checking

def test_expect_accepts_the_matching_status(run):
    rc, out, err = run("instantiate a\ndo_step 0 0.1\nexpect error\nsetup 0\nexpect ok\n"
                       "enter_init\nexit_init\ndo_step 0 11\nexpect discard\nfree\n")
    assert rc == 0, err
    assert "do_step error" in out and "do_step discard" in out
    assert "LOG error logStatusError: fmi2DoStep: not allowed in phase 1" in err


@pytest.mark.parametrize("script, message", [
    ("instantiate a\ndo_step 0 0.1\nexpect ok\n", "expect ok failed at script line 3: the previous command returned error"),
    ("instantiate a\nsetup 0\nexpect error\n", "expect error failed at script line 3: the previous command returned ok"),
    ("instantiate a\ndo_step 0 0.1\nsetup 0\n", "fmi2DoStep returned error at script line 2 and the next line is not an 'expect'"),
    ("instantiate a\nenter_init\nenter_init\n", "fmi2EnterInitializationMode returned error at script line 3 and the script ended"),
    ("instantiate a wrong-guid\nfree\n", "fmi2Instantiate returned error at script line 1"),
])
def test_a_status_mismatch_fails_the_run(run, script, message):
    rc, out, err = run(script)
    assert rc == 1, (out, err)
    assert message in err


def test_warnings_need_no_expect(run):
    rc, out, err = run("instantiate a\nset_real 1=-0.5\nexpect warning\nset_real 1=-0.25\nfree\n")
    assert rc == 0, err
    assert out.count("set_real warning") == 2
    assert "LOG warning logStatusWarning: fmi2SetReal: k = -0.25 < 0 makes x grow" in err


def test_instantiate_with_a_wrong_guid_prints_null(run):
    rc, out, err = run("instantiate a {00000000-0000-0000-0000-000000000000}\nexpect error\n"
                       "instantiate b\nfree\n")
    assert rc == 0, err
    assert out.splitlines()[:2] == ["instantiate null", "instantiate ok"]


# --------------------------------------------------------------------------------------------
# NULL arguments

COMPONENT_FUNCTIONS = [
    "fmi2SetDebugLogging", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2DoStep", "fmi2CancelStep",
    "fmi2GetReal", "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal",
    "fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate",
    "fmi2FreeFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus",
]
VALUE_FUNCTIONS = [
    "fmi2GetReal", "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal",
    "fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus", "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
]
VR_FUNCTIONS = VALUE_FUNCTIONS[:8]
STATE_FUNCTIONS = ["fmi2SetFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate"]


def test_call_null_reaches_every_function(run):
    lines = ["call_null fmi2FreeInstance"]
    lines += [f"call_null {f}" for f in COMPONENT_FUNCTIONS]
    lines += [f"call_null fmi2Instantiate {w}" for w in ("name", "guid", "callbacks", "logger", "alloc")]
    lines += init().splitlines() + ["get_state 0"]
    lines += [f"call_null {f} values" for f in VALUE_FUNCTIONS]
    lines += [f"call_null {f} vr" for f in VR_FUNCTIONS]
    lines += [f"call_null {f} state\nexpect error" for f in STATE_FUNCTIONS]
    lines += ["get_real 0", "free_state 0"]
    rc, out, err = run(lines)
    assert rc == 0, err
    assert "call_null fmi2FreeInstance component ok" in out
    for f in COMPONENT_FUNCTIONS:
        assert f"call_null {f} component error" in out
    for w in ("name", "guid", "callbacks", "alloc"):
        assert f"call_null fmi2Instantiate {w} null" in out
    # a NULL logger is allowed by this FMU (the host frees the instance it got)
    assert "call_null fmi2Instantiate logger nonnull" in out
    for f in VALUE_FUNCTIONS:
        assert f"call_null {f} values error" in out
    for f in VR_FUNCTIONS:
        assert f"call_null {f} vr error" in out
    for f in STATE_FUNCTIONS:
        assert f"call_null {f} state error" in out
    assert "get_real ok" in out                     # the instance is still usable


def test_call_null_needs_an_instance_for_non_component_arguments(run):
    rc, out, err = run("call_null fmi2GetReal values\n")
    assert rc == 2
    assert "needs an instance" in err


# --------------------------------------------------------------------------------------------
# logger, resources, start-up, cycles

def test_logger_formats_the_messages_with_their_arguments(run):
    long_name = "n" * 3000                       # longer than the logger's 1024-byte buffer
    rc, out, err = run(f"instantiate {long_name}\nsetup 0\nenter_init\nexit_init\n"
                       "do_step 0.7 0.1\nexpect error\nfree\n")
    assert rc == 0, err
    assert f"LOG ok logAll: fmi2Instantiate: '{long_name}', resources at file://" in err
    assert ("LOG error logStatusError: fmi2DoStep: currentCommunicationPoint 0.69999999999999996 "
            "does not match the FMU time 0") in err
    assert "LOG" not in out                          # the log goes to stderr only


def test_resource_uri_is_the_absolute_resources_folder(run, dahlquist_fmu):
    rc, out, err = run(init() + "get_string 5\n")
    assert rc == 0, err
    assert f"string 5 file://{dahlquist_fmu.resolve()}/resources" in out.splitlines()


def test_relative_fmu_dir_gives_an_absolute_resource_uri(c_host, dahlquist_fmu, tmp_path):
    script = tmp_path / "s.txt"
    script.write_text(init() + "get_string 5\n")
    proc = subprocess.run([str(c_host), dahlquist_fmu.name, DAHLQUIST_ID, DAHLQUIST_GUID, str(script)],
                          cwd=dahlquist_fmu.parent, capture_output=True, text=True, env=CLEAN_ENV)
    assert proc.returncode == 0, proc.stderr
    assert f"string 5 file://{dahlquist_fmu.resolve()}/resources" in proc.stdout


def test_time_load(run):
    rc, out, err = run("time_load\nget_real 0\nfree\n")
    assert rc == 0, err
    assert out.splitlines()[:3] == ["time_load ok", "get_real ok", "real 0 1"]
    assert 0.0 < stderr_value(err, "startup_seconds") < 5.0
    assert 0.0 <= stderr_value(err, "startup_seconds_since_exec") < 5.0


def test_cycle_reports_resident_set_size(run):
    rc, out, err = run("cycle 1\ncycle 500\n")
    assert rc == 0, err
    assert out.splitlines() == ["cycle ok iterations=1", "cycle ok iterations=500"]
    before = re.findall(r"^rss_kb_before (\d+)$", err, flags=re.M)
    after = re.findall(r"^rss_kb_after (\d+)$", err, flags=re.M)
    assert len(before) == len(after) == 2
    assert int(after[1]) - int(before[1]) < 256      # 500 leak-free cycles


def test_script_from_stdin_and_version(c_host, dahlquist_fmu):
    proc = subprocess.run([str(c_host), str(dahlquist_fmu), DAHLQUIST_ID, DAHLQUIST_GUID, "-"],
                          input="version\necho hello  world\n", capture_output=True, text=True,
                          env=CLEAN_ENV)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "version 2.0 default\nhello world\n"


# --------------------------------------------------------------------------------------------
# bad input to the host itself: a clear message and exit code 2, never a crash

def test_missing_binary_is_a_clear_error(c_host, tmp_path):
    empty = tmp_path / "empty_fmu"
    empty.mkdir()
    rc, out, err = run_c_host(c_host, empty, "ClearanceWearJoint", "{guid}", "instantiate a\n")
    assert rc == 2
    assert out == ""
    assert (f"fmi2_host: error: cannot load the FMU binary "
            f"{empty.resolve()}/binaries/linux64/ClearanceWearJoint.so") in err
    rc, out, err = run_c_host(c_host, tmp_path / "no_such_dir", "x", "{guid}", "")
    assert rc == 2
    assert "no_such_dir" in err and "No such file or directory" in err


def test_binary_without_fmi2_symbols(c_host, dahlquist_fmu, tmp_path):
    fmu = tmp_path / "fake"
    (fmu / "binaries" / "linux64").mkdir(parents=True)
    shutil.copyfile(dahlquist_fmu / "binaries" / "linux64" / "dahlquist.so",
                    fmu / "binaries" / "linux64" / "dahlquist.so")
    rc, out, err = run_c_host(c_host, fmu, DAHLQUIST_ID, DAHLQUIST_GUID, init() + "get_real 0\n")
    assert rc == 0, err                              # a copied binary works from any folder
    src = tmp_path / "notanfmu.c"
    src.write_text("int not_an_fmu(void) { return 42; }\n")
    subprocess.run(["gcc", "-shared", "-fPIC", str(src), "-o",
                    str(fmu / "binaries" / "linux64" / "notanfmu.so")], check=True, env=CLEAN_ENV)
    rc, out, err = run_c_host(c_host, fmu, "notanfmu", "{g}", "version\n")
    assert rc == 2
    assert "the FMU binary does not export fmi2GetVersion (script line 1)" in err
    rc, out, err = run_c_host(c_host, fmu, "notanfmu", "{g}", "instantiate a\n")
    assert rc == 2
    assert "the FMU binary does not export fmi2Instantiate" in err


def test_usage(c_host):
    proc = subprocess.run([str(c_host), "only", "three", "args"], capture_output=True, text=True,
                          env=CLEAN_ENV)
    assert proc.returncode == 2
    assert proc.stderr.startswith("usage: ")


@pytest.mark.parametrize("script, message", [
    ("frobnicate\n", "unknown command 'frobnicate' (script line 1)"),
    ("instantiate a\nset_real 0=abc\n", "set_real value: not a number: 'abc' (script line 2)"),
    ("instantiate a\nset_real 0\n", "expected <vr>=<value>, got '0'"),
    ("instantiate a\nset_integer 4=2.5\n", "not an integer"),
    ("instantiate a\nset_boolean 4=maybe\n", "not a boolean"),
    ("instantiate a\nget_real\n", "usage: get_real <vr>"),
    ("instantiate a\nget_real -1\n", "not a value reference: '-1'"),
    ("instantiate a\nget_state 64\n", "slot: not an integer in [0, 63]: '64'"),
    ("instantiate a\ndo_step 0\n", "usage: do_step"),
    ("get_real 0\n", "'get_real' needs an instance"),
    ("instantiate a\ninstantiate b\n", "an instance exists already"),
    ("instantiate a\nexpect maybe\n", "expect: unknown status 'maybe'"),
    ("instantiate a\ntrace /no/such/file 0 - 0\n", "trace: cannot open '/no/such/file'"),
    ("instantiate a\ntrace {bad} 0 - 0\n", "line 2: expected 2 numbers (t h u1..u0)"),
    ("instantiate a\ntrace {bad} 1 3,2 0\n", "n_inputs is 1 but 2 input value references"),
    ("instantiate a\ndeserialize 0 /no/such/file\n", "deserialize: cannot open"),
    ("instantiate a\ncall_null fmi2Frobnicate\n", "call_null: unsupported function 'fmi2Frobnicate'"),
    ("instantiate a\ncall_null fmi2DoStep values\n", "'values' does not apply to fmi2DoStep"),
    ("cycle -1\n", "cycle n: not an integer"),
    ("instantiate a\ntime_load\n", "time_load: an instance exists already"),
])
def test_bad_script_lines_exit_with_code_2(run, tmp_path, script, message):
    bad = tmp_path / "bad.txt"
    bad.write_text("0 0.1\n0 0.1 7\n")
    rc, out, err = run(script.format(bad=bad))
    assert rc == 2, (out, err)
    assert "fmi2_host: error: " in err
    assert message in err


def test_missing_script_file(c_host, dahlquist_fmu, tmp_path):
    rc, out, err = run_c_host(c_host, dahlquist_fmu, DAHLQUIST_ID, DAHLQUIST_GUID,
                              tmp_path / "no_script.txt")
    assert rc == 2
    assert "cannot open the script" in err
