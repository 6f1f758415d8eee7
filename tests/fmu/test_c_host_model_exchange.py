"""The native FMU's FMI 2.0 Model Exchange interface driven from C, with no Python on the host.

``tests/c_host/fmi2_host.c`` (``instantiate_me``, ``trace_me`` and the single Model Exchange
calls, see tests/c_host/README.md) runs a recorded kinematic trace of the slider-crank with wear
through the call sequence of ``wearjoint/core/joint_access.py`` at accepted points:
fmi2SetTime, fmi2SetReal of the 12 inputs, fmi2GetReal of the outputs (plus
fmi2GetEventIndicators), fmi2CompletedIntegratorStep, and an event iteration where the contact
begins or ends.  The references are independent of the C host: fmpy's FMU2Model making the same
calls, and the in-process ``ClearanceJoint`` (outputs evaluated before the step is accepted, wear
over t_i - t_(i-1)).
"""
from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi2 import FMU2Model  # noqa: E402
from fmi_host import (  # noqa: E402
    assert_valgrind_clean, event_lines, run_c_host, trace_rows, valgrind_or_skip, value_lines, write_trace_file,
)
from fmpy_instance import enter_initialisation  # noqa: E402
from kinematic_trace import run_joint_on_trace, slider_crank_trace  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402

ROWS, STEP = 2000, 1e-4              # 0.2 s of the slider-crank: ten contact onsets, nine separations
JOINT = paper_joint(wear_factor=10.0)   # micrometres of wear within the trace
OUTPUTS = [v.name for v in fv.SCALAR_OUTPUTS]
CONTACT = OUTPUTS.index("contact")


# ------------------------------------------------------------------ fixtures and the two references
@pytest.fixture(scope="module")
def fmu(native_fmu, tmp_path_factory):
    """The FMI 2.0 native FMU, unzipped: folder, GUID, value references."""
    md = read_model_description(str(native_fmu))
    folder = Path(extract(str(native_fmu), unzipdir=str(tmp_path_factory.mktemp("me_unzipped"))))
    return {"dir": folder, "guid": md.guid, "vr": fv.value_references(md)}


@pytest.fixture(scope="module")
def trace():
    return slider_crank_trace(JOINT, ROWS, STEP)


@pytest.fixture(scope="module")
def trace_file(trace, tmp_path_factory):
    return write_trace_file(tmp_path_factory.mktemp("me_trace") / "trace.txt", trace)


def _contact_changes(contact, times) -> list[tuple[float, str]]:
    """(t, onset|separation) wherever the contact differs from the previous row's (none before the first)."""
    previous = np.concatenate([[0.0], contact[:-1]])
    return [(float(t), "onset" if c > 0.5 else "separation") for t, c, p in zip(times, contact, previous)
            if (c > 0.5) != (p > 0.5)]


@pytest.fixture(scope="module")
def joint_reference(trace):
    """The in-process joint through the Model Exchange semantics: the outputs at every row before
    the step is accepted, the step accepted over t_i - t_(i-1) (from the start time 0)."""
    outputs, wear = run_joint_on_trace(JOINT, trace, model_exchange=True)
    return {"outputs": outputs, "events": _contact_changes(outputs[:, CONTACT], trace[:, 0]), "wear": wear}


def _parameters(vr) -> str:
    """set_real / set_integer lines for JOINT's FMU parameters."""
    reals, integers = fv.fmi_parameter_values_by_type(JOINT)
    return (f"set_real {' '.join(f'{vr[k]}={v!r}' for k, v in reals.items())}\n"
            f"set_integer {' '.join(f'{vr[k]}={v}' for k, v in integers.items())}\n")


def _me_start(fmu, instantiate="instantiate_me joint") -> str:
    """Instantiate, initialise with JOINT, leave the initial event mode: continuous-time mode."""
    return (f"{instantiate}\nsetup 0\nenter_init\n{_parameters(fmu['vr'])}exit_init\n"
            "new_discrete_states\nenter_continuous_time_mode\n")


def _trace_me(fmu, trace_file, order="events_after") -> str:
    vr = fmu["vr"]
    return (f"trace_me {trace_file} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
            f"{','.join(str(vr[n]) for n in OUTPUTS)} {order}\n")


def _wear(fmu) -> str:
    return "get_real " + " ".join(str(fmu["vr"][fv.wear_depth_name(z)]) for z in range(1, JOINT.n_points + 1)) + "\n"


def _run(fmu, c_host, script, **kw):
    code, out, err = run_c_host(c_host, fmu["dir"], fv.MODEL_NAME, fmu["guid"], script, **kw)
    assert code == 0, out[-2000:] + err[-3000:]
    return out, err


def _rows(out) -> np.ndarray:
    return np.array(trace_rows(out), dtype=float)


def _profile(out) -> np.ndarray:
    """The wear profile: the last n_points values read."""
    return np.array([float(line.split()[2]) for line in value_lines(out)[-JOINT.n_points:]])


def fmpy_model_exchange(fmu, rows, events_first=False):
    """trace_me's call sequence through fmpy's FMU2Model: (outputs per row, [(t, kind)], wear)."""
    vr = fmu["vr"]
    model = FMU2Model(guid=fmu["guid"], unzipDirectory=str(fmu["dir"]), modelIdentifier=fv.MODEL_NAME,
                      instanceName="fmpy_me")
    model.instantiate()
    try:
        enter_initialisation(model, vr, JOINT)
        model.exitInitializationMode()
        model.newDiscreteStates()
        model.enterContinuousTimeMode()
        inputs, outputs = [vr[v.name] for v in fv.INPUTS], [vr[n] for n in OUTPUTS]
        indicator = (ctypes.c_double * 1)()
        values_out, events, contact = [], [], False

        def event_iteration():
            model.enterEventMode()
            while model.newDiscreteStates()[0]:     # newDiscreteStatesNeeded
                pass
            model.enterContinuousTimeMode()

        for row in rows:
            model.setTime(row[0])
            model.setReal(inputs, list(row[2:]))
            values_out.append(model.getReal(outputs))
            model.getEventIndicators(indicator, 1)
            event = (indicator[0] >= 0.0) != contact
            if event and events_first:
                event_iteration()
            model.completedIntegratorStep()
            if event and not events_first:
                event_iteration()
            if event:
                contact = not contact
                events.append((float(row[0]), "onset" if contact else "separation"))
        wear = model.getReal([vr[fv.wear_depth_name(z)] for z in range(1, JOINT.n_points + 1)])
        model.terminate()
    finally:
        model.freeInstance()
    return np.array(values_out), events, np.array(wear)


# ------------------------------------------------------------------ the same numbers from C
def test_trace_me_from_c_equals_fmpy_making_the_same_calls(fmu, c_host, trace, trace_file):
    """joint_access.py's order (the event iteration after fmi2CompletedIntegratorStep): the C host
    and fmpy agree bit for bit, row by row, event by event; an event wherever the contact output
    changes; the trace wears the bushing."""
    out, err = _run(fmu, c_host, _me_start(fmu) + _trace_me(fmu, trace_file) + _wear(fmu) + "terminate\nfree\n")
    rows = _rows(out)
    assert rows.shape == (ROWS, 1 + len(OUTPUTS))
    assert np.array_equal(rows[:, 0], trace[:, 0])
    outputs, events, wear = fmpy_model_exchange(fmu, trace)
    assert np.array_equal(rows[:, 1:], outputs)
    assert np.array_equal(_profile(out), wear) and wear.max() > 1e-6
    assert event_lines(out) == events
    # one event iteration at every change of the contact output, counted in the summary line
    assert events == _contact_changes(rows[:, 1 + CONTACT], rows[:, 0])
    onsets = sum(kind == "onset" for _, kind in events)
    # the trace's 0.1 ms steps wear over the wear-step limit (1e-5 s): logged once as a warning, every call fmi2OK
    assert onsets >= 5 and f"trace_me ok rows={ROWS} events={len(events)} onsets={onsets} " \
                            f"separations={len(events) - onsets}" in out
    logged = [line for line in err.splitlines() if line.startswith("LOG")]
    assert len(logged) == 1 and logged[0].startswith("LOG warning") and "wear-step limit" in logged[0]


def test_trace_me_events_first_equals_the_in_process_joint_bit_for_bit(fmu, c_host, trace, trace_file,
                                                                         joint_reference):
    """With the event iteration before fmi2CompletedIntegratorStep the FMU reproduces the in-process
    joint exactly: outputs, contact onsets and separations (one event each), final wear profile."""
    out, _ = _run(fmu, c_host, _me_start(fmu) + _trace_me(fmu, trace_file, "events_first") + _wear(fmu) + "free\n")
    rows = _rows(out)
    assert np.array_equal(rows[:, 1:], joint_reference["outputs"])
    assert event_lines(out) == joint_reference["events"]
    onsets = sum(kind == "onset" for _, kind in joint_reference["events"])
    assert f"events={len(joint_reference['events'])} onsets={onsets} " in out and onsets >= 5
    assert np.array_equal(_profile(out), joint_reference["wear"])
    # fmpy, making the same calls, agrees
    outputs, events, wear = fmpy_model_exchange(fmu, trace, events_first=True)
    assert np.array_equal(outputs, joint_reference["outputs"]) and events == joint_reference["events"]


def test_the_event_order_of_joint_access_equals_the_in_process_joint(fmu, c_host, trace_file, joint_reference):
    """The FMI order (fmi2CompletedIntegratorStep, then the event iteration) gives the in-process
    joint's numbers: the event keeps the onset the completed step stored from the contact before
    its wear, even where that wear exceeds the penetration (a re-evaluation would then see no
    contact and clear it)."""
    out, _ = _run(fmu, c_host, _me_start(fmu) + _trace_me(fmu, trace_file, "events_after") + "free\n")
    assert np.array_equal(_rows(out)[:, 1:], joint_reference["outputs"])


def test_a_rejected_trial_changes_nothing(fmu, c_host, trace, tmp_path):
    """A trial stage between two accepted rows -- a later time, inputs deep in contact, outputs and the
    event indicator read, never completed -- leaves every later output, event and the wear as they were."""
    out, _ = _run(fmu, c_host, _me_start(fmu) + _trace_me(fmu, write_trace_file(tmp_path / "all.txt", trace)) + "free\n")
    contact = _rows(out)[:, 1 + CONTACT]
    split = next(i for i in range(120, ROWS) if contact[i - 1] < 0.5 and contact[i] < 0.5)   # out of contact
    deep = int(np.argmax(_rows(out)[:, 1 + OUTPUTS.index("penetration")]))                  # the deepest row
    first = write_trace_file(tmp_path / "first.txt", trace[:split])
    rest = write_trace_file(tmp_path / "rest.txt", trace[split:])
    vr = fmu["vr"]
    trial = (f"set_time {float(trace[split, 0] + 5 * STEP)!r}\n"
             f"set_real {' '.join(f'{vr[v.name]}={float(x)!r}' for v, x in zip(fv.INPUTS, trace[deep, 2:]))}\n"
             f"get_real {vr['contact']} {vr['normal_force']}\nget_event_indicators 1\n")
    runs = {}
    for name, middle in (("plain", ""), ("trial", trial)):
        script = (_me_start(fmu) + _trace_me(fmu, first) + middle + _trace_me(fmu, rest) + _wear(fmu) + "free\n")
        runs[name], _ = _run(fmu, c_host, script)
    assert f"real {vr['contact']} 1" in runs["trial"].splitlines()                 # the trial was in contact ...
    indicator = next(line for line in runs["trial"].splitlines() if line.startswith("indicator 0 "))
    assert float(indicator.split()[2]) > 0.0                           # ... with a positive indicator
    for name in runs:
        assert np.array_equal(_rows(runs[name]), _rows(out)), name     # split in two == in one go
        assert event_lines(runs[name]) == event_lines(out), name
    assert np.array_equal(_profile(runs["trial"]), _profile(runs["plain"]))
    assert _profile(runs["plain"]).max() > 0.0


# ------------------------------------------------------------------ single Model Exchange calls from C
def test_model_exchange_calls_and_their_errors_from_c(fmu, c_host):
    """nx = 0 states and derivatives; the call sequence enforced (fmi2Error, logged); a
    Co-Simulation instance refuses trace_me at its first call; --model-exchange instantiates ME."""
    vr = fmu["vr"]
    script = _me_start(fmu) + f"""\
get_continuous_states 0
get_derivatives 0
get_continuous_states 1
expect error
get_event_indicators 2
expect error
set_time nan
expect error
do_step 0 1e-4
expect error
enter_event_mode
completed_integrator_step
expect error
new_discrete_states
new_discrete_states
enter_continuous_time_mode
set_time 1e-4
completed_integrator_step 0
get_real {vr['max_wear_depth']}
get_state 3
set_state 3
free_state 3
terminate
free
instantiate cs
setup 0
enter_init
exit_init
trace_me {{trace}} 0 - -
expect error
free
"""
    rows = Path(fmu["dir"]).parent / "one_row.txt"
    rows.write_text("0 0.0001\n")
    out, err = _run(fmu, c_host, script.format(trace=rows))
    lines = out.splitlines()
    for expected in ("get_continuous_states ok", "get_derivatives ok", "get_continuous_states error",
                     "get_event_indicators error", "set_time error", "do_step error", "completed_integrator_step error",
                     "new_discrete_states ok needed=0 terminate=0 nominals_changed=0 values_changed=0 "
                     "next_event_time_defined=0 next_event_time=0",
                     "completed_integrator_step warning enter_event_mode=0 terminate=0", "set_state 3 ok",
                     "trace_me error row=0 call=fmi2SetTime events=0 onsets=0 separations=0"):
        assert expected in lines, expected
    assert "this FMU has no continuous states (nx=1 given)" in err and "(ni=2 given)" in err
    assert "inputs put the pin centre 0.135 m from the bushing centre, outside the bushing" in err   # the offsets
    assert "fmi2CompletedIntegratorStep: not allowed in state event mode" in err
    assert "fmi2SetTime: not allowed in state step complete" in err
    code, out, err = run_c_host(c_host, fmu["dir"], fv.MODEL_NAME, fmu["guid"],
                                "instantiate a\nset_time 0\nexpect error\nfree\ncycle 3\ntime_load\nenter_event_mode\n",
                                host_args=["--model-exchange"])
    assert code == 0, err
    assert out.splitlines() == ["instantiate ok", "set_time error", "free ok", "cycle ok iterations=3",
                                "time_load ok", "enter_event_mode ok"]   # initialised ME instances are in event mode


# ------------------------------------------------------------------ valgrind
@pytest.mark.slow
def test_model_exchange_from_c_under_valgrind(fmu, c_host, trace, tmp_path):
    """trace_me through onsets and separations (both event orders), a rejected trial, state
    round trips, error statuses, ME cycles under valgrind: zero errors, no definite leak."""
    valgrind_or_skip()
    vr = fmu["vr"]
    part = write_trace_file(tmp_path / "part.txt", trace[:500])
    later = write_trace_file(tmp_path / "later.txt", trace[500:700])
    state = tmp_path / "state.bin"
    script = (_me_start(fmu, "instantiate valgrind") + _trace_me(fmu, part) + "get_state 0\n"
              + f"serialize 0 {state}\nset_time 0.09\nset_real {vr['pin_x']}=0.001\nget_real {vr['normal_force']}\n"
              + "get_event_indicators 1\n" + _trace_me(fmu, later, "events_first") + "set_state 0\n"
              + _trace_me(fmu, later) + f"deserialize 1 {state}\nset_state 1\nfree_state 0\n"
              + f"set_real {vr['pin_x']}=nan\nget_real {vr['normal_force']}\nexpect error\n"
              + "get_event_indicators 1\nexpect error\nset_time 0.1\ncompleted_integrator_step\nexpect discard\n"
              + "get_continuous_states 0\nget_derivatives 0\nenter_event_mode\nnew_discrete_states\nexpect error\n"
              + "get_state 2\nterminate\nfree\ncycle 5\n")
    out, err = _run(fmu, c_host, script, host_args=["--model-exchange"], valgrind=True, timeout=1200)
    # the first trace wears over the wear-step limit (0.1 ms steps): logged, the calls fmi2OK
    assert out.count("trace_me warning") == 0 and out.count("trace_me ok") == 3 and "cycle ok iterations=5" in out
    assert_valgrind_clean(err)
