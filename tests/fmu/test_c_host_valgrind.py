"""The C FMI 2.0 host under valgrind (slow): a full script and every error exit free what they
allocate, and the check is not vacuous (an FMU built to leak fails it).  The host and its test FMU:
tests/fmu/test_c_host_tool.py."""
from __future__ import annotations

import shutil

import pytest
from fmi_host import (
    CLEAN_ENV, DAHLQUIST_GUID, DAHLQUIST_ID, assert_valgrind_clean, build_dahlquist_fmu, gcc_or_skip, init,
    run_c_host, write_trace_file,
)


def _valgrind_or_skip():
    if shutil.which("valgrind", path=CLEAN_ENV["PATH"]) is None:
        pytest.skip("valgrind is not installed")


FULL_SCRIPT = """\
version
call_null fmi2FreeInstance
call_null fmi2GetReal
call_null fmi2Instantiate guid
call_null fmi2Instantiate logger
instantiate {long_name}
set_real 1=2 2=1.5
setup 0 10 1e-6
enter_init
get_real 0 1 2 3
exit_init
set_debug_logging 1 logAll
get_string 5
trace {trace} 1 3 0,3
get_integer 4
get_state 0
serialize 0 {state}
do_step 5 0.5
do_step 5.5 11
expect discard
do_step 99 0.1
expect error
set_state 0
deserialize 1 {state}
deserialize 1 {state}
set_state 1
get_real 0
call_null fmi2GetReal values
call_null fmi2SerializeFMUstate state
call_null fmi2GetFMUstate values
get_state 2
free_state 0
cycle 1
cycle 20
terminate
reset
get_state 3
free
time_load
get_real 0
get_state 4
"""


@pytest.mark.slow
def test_valgrind_full_script(c_host, dahlquist_fmu, tmp_path):
    _valgrind_or_skip()
    trace = write_trace_file(tmp_path / "t.txt", [(i * 0.01, 0.01, 0.1 * (i % 7)) for i in range(500)])
    script = FULL_SCRIPT.format(long_name="v" * 2000, trace=trace, state=tmp_path / "state.bin")
    rc, out, err = run_c_host(c_host, dahlquist_fmu, DAHLQUIST_ID, DAHLQUIST_GUID, script,
                              valgrind=True)
    assert rc == 0, err[-3000:]
    assert "trace ok rows=500" in out and "cycle ok iterations=20" in out
    assert_valgrind_clean(err)


@pytest.mark.slow
@pytest.mark.parametrize("case, expected_rc", [
    ("expect_mismatch", 1), ("unacknowledged", 1), ("syntax_error", 2), ("bad_trace_row", 2),
    ("missing_binary", 2),
])
def test_valgrind_error_exits_are_clean(c_host, dahlquist_fmu, tmp_path, case, expected_rc):
    """Every exit path frees the host's memory, the FMU states held in slots and the instance."""
    _valgrind_or_skip()
    trace = tmp_path / "t.txt"
    trace.write_text("0 0.1\n0.1 0.1\n0.2 oops\n")
    held = init() + "get_state 0\nget_state 1\n"
    scripts = {
        "expect_mismatch": held + "do_step 0 0.1\nexpect error\n",
        "unacknowledged": held + "do_step 3 0.1\nget_real 0\n",
        "syntax_error": held + "get_real 0 x\n",
        "bad_trace_row": held + f"trace {trace} 0 - 0\n",
        "missing_binary": "instantiate a\n",
    }
    fmu = tmp_path if case == "missing_binary" else dahlquist_fmu
    rc, out, err = run_c_host(c_host, fmu, DAHLQUIST_ID, DAHLQUIST_GUID, scripts[case],
                              valgrind=True)
    assert rc == expected_rc, err[-3000:]
    assert_valgrind_clean(err)


@pytest.mark.slow
def test_valgrind_check_detects_a_leaking_fmu(c_host, tmp_path):
    """The assertion is not vacuous: an FMU built to leak its instance name fails it."""
    _valgrind_or_skip()
    gcc_or_skip()
    leaky = build_dahlquist_fmu(tmp_path, extra_flags=["-DDAHLQUIST_LEAK"])
    rc, out, err = run_c_host(c_host, leaky, DAHLQUIST_ID, DAHLQUIST_GUID,
                              "instantiate leaky\nfree\n", valgrind=True)
    assert rc == 3, err[-3000:]                       # --error-exitcode=3
    assert "definitely lost: 6 bytes in 1 blocks" in err   # "leaky" and its NUL
    with pytest.raises(AssertionError):
        assert_valgrind_clean(err)
