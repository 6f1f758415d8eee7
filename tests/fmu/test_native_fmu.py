"""The native FMU backend (docs/reference/fmu.md §5): one shared library that needs libc and libm
only, the same numbers as the in-process joint, usable from C without Python.

The behaviour both backends share (variables, forces, wear, FMU state, errors) is tested on both
in the test_fmu*.py files; this file holds what is particular to the native binary.
"""
import ctypes
import math
import shutil
import subprocess
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmi_host import (  # noqa: E402
    assert_valgrind_clean, needed_libraries, run_c_host, stderr_value, trace_rows, value_lines, write_trace_file,
)

from fmpy_instance import enter_initialisation  # noqa: E402
from kinematic_trace import slider_crank_trace as record_trace  # noqa: E402

from wearjoint import ClearanceJoint, SliderCrankParameters, paper_joint  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402

SCALAR_NAMES = [v.name for v in fv.SCALAR_OUTPUTS]
N_POINTS = paper_joint().n_points
WEAR_FACTOR = 1.0     # the paper's k_w: tens of um of wear per revolution, and impacts go on
TRACE_STEP = 1e-5     # [s]
TRACE_REVOLUTIONS = 4


@pytest.fixture(scope="module")
def native(native_fmu, tmp_path_factory):
    """The native FMU unzipped: its folder, model description and value references."""
    directory = Path(extract(str(native_fmu), unzipdir=str(tmp_path_factory.mktemp("native_unzipped"))))
    md = read_model_description(str(native_fmu))
    return {"path": native_fmu, "dir": directory, "md": md, "vr": fv.value_references(md),
            "binary": directory / "binaries" / "linux64" / f"{fv.MODEL_NAME}.so"}


# ------------------------------------------------------------- a self-contained binary
def test_binary_needs_libc_and_libm_only(native):
    assert needed_libraries(native["binary"]) <= {"libc.so.6", "libm.so.6"}
    undefined = subprocess.run(["nm", "-D", "--undefined-only", str(native["binary"])], capture_output=True,
                               text=True, check=True).stdout.split()
    symbols = {s.split("@")[0] for s in undefined if s not in ("U", "w")}
    libc, libm = ctypes.CDLL("libc.so.6"), ctypes.CDLL("libm.so.6")
    weak_runtime = {"_ITM_deregisterTMCloneTable", "_ITM_registerTMCloneTable", "__cxa_finalize", "__gmon_start__"}
    assert not {s for s in symbols - weak_runtime if not (hasattr(libc, s) or hasattr(libm, s))}
    assert not any(s.startswith(("Py", "_Py", "NRT_", "numba_")) for s in symbols)
    ldd = subprocess.run(["ldd", str(native["binary"])], capture_output=True, text=True).stdout
    assert "python" not in ldd


def test_binary_exports_the_fmi_functions_only(native):
    defined = subprocess.run(["nm", "-D", "--defined-only", str(native["binary"])], capture_output=True,
                             text=True, check=True).stdout.split()[2::3]
    assert defined and all(name.startswith("fmi2") for name in defined), defined
    assert {"fmi2Instantiate", "fmi2DoStep", "fmi2GetFMUstate", "fmi2DeSerializeFMUstate"} <= set(defined)


def _variables(xml: bytes) -> list[tuple]:
    root = ET.fromstring(xml)
    rows = []
    for sv in root.find("ModelVariables"):
        typed = sv[0]
        rows.append((sv.get("name"), sv.get("valueReference"), sv.get("causality"), sv.get("variability"),
                     sv.get("initial"), sv.get("description"), typed.tag, typed.get("unit"), typed.get("start")))
    structure = [(u.get("index"), u.get("dependencies")) for u in root.find("ModelStructure").iter("Unknown")]
    return rows + structure


def test_variables_are_the_pythonfmu_backends(native, built_fmu):
    with zipfile.ZipFile(native["path"]) as a, zipfile.ZipFile(built_fmu) as b:
        assert _variables(a.read("modelDescription.xml")) == _variables(b.read("modelDescription.xml"))
    penetration = next(v for v in native["md"].modelVariables if v.name == "penetration")
    assert "negative" in penetration.description and "gap" in penetration.description


def test_sources_relink_into_a_working_binary(native, tmp_path, c_host):
    sources = native["dir"] / "sources"
    for name in ("fmi2Functions.c", "joint_kernels.h", "model_variables.h", "build.sh", "kernels/wearjoint_evaluate.ll",
                 "kernels/linux64/wearjoint_evaluate.o", "kernels/linux64/wearjoint_advance.o"):
        assert (sources / name).is_file(), name
    done = subprocess.run(["sh", str(sources / "build.sh"), "linux64"], capture_output=True, text=True,
                          env={"PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr
    relinked = sources / f"{fv.MODEL_NAME}.so"
    assert relinked.is_file() and needed_libraries(relinked) <= {"libc.so.6", "libm.so.6"}
    # the relinked binary answers like the shipped one
    copy = tmp_path / "relinked"
    (copy / "binaries" / "linux64").mkdir(parents=True)
    relinked.rename(copy / "binaries" / "linux64" / f"{fv.MODEL_NAME}.so")
    script = _init_script(native) + f"set_real {_inputs_assignment(native, _touching_inputs())}\n" + \
        f"get_real {' '.join(str(native['vr'][n]) for n in SCALAR_NAMES)}\n"
    answers = [run_c_host(c_host, d, fv.MODEL_NAME, native["md"].guid, script) for d in (native["dir"], copy)]
    assert answers[0][0] == 0, answers[0][2]
    assert value_lines(answers[0][1]) == value_lines(answers[1][1])


# ------------------------------------------------------------- the same numbers as the joint in process
def test_the_sources_relink_under_the_fmi3_platform_name(fmus, tmp_path):
    """``sh sources/build.sh x86_64-linux``, the name of the FMI 3.0 FMU's binaries/ folder, relinks the shipped
    binary (it had said "unknown platform 'x86_64-linux' (this FMU carries: linux64)")."""
    shutil.copytree(fmus[3]["dir"], tmp_path / "fmu")
    sources = tmp_path / "fmu" / "sources"
    done = subprocess.run(["sh", str(sources / "build.sh"), "x86_64-linux"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    relinked = sources / f"{fv.MODEL_NAME}.so"
    assert relinked.read_bytes() == (tmp_path / "fmu" / "binaries" / "x86_64-linux" / relinked.name).read_bytes()
    done = subprocess.run(["sh", str(sources / "build.sh"), "sparc"], capture_output=True, text=True)
    assert done.returncode == 2 and "this FMU carries: linux64 (x86_64-linux)" in done.stderr


@pytest.fixture(scope="module")
def slider_crank_trace():
    """TRACE_REVOLUTIONS of the slider-crank with wear, every TRACE_STEP."""
    period = SliderCrankParameters().period_s
    return record_trace(TRACE_JOINT, int(round(TRACE_REVOLUTIONS * period / TRACE_STEP)), TRACE_STEP)


@pytest.fixture(scope="module")
def joint_on_trace(slider_crank_trace):
    """The in-process ClearanceJoint driven through the trace: scalar outputs before every step,
    wear profiles every 1000 steps and at the end."""
    joint = ClearanceJoint(TRACE_JOINT)
    outputs = np.empty((len(slider_crank_trace), len(SCALAR_NAMES)))
    profiles = {}
    for i, row in enumerate(slider_crank_trace):
        k = row[2:]
        result = joint.evaluate_array(k[0:3], k[3:6], k[6:9], k[9:12])
        outputs[i] = [result[fv.RESULT_SLOTS[name]] if name in fv.RESULT_SLOTS
                      else joint.max_wear_depth_m if name == "max_wear_depth" else joint.worn_volume_m3
                      for name in SCALAR_NAMES]
        if i % 1000 == 0:
            profiles[i] = joint.wear_depth.copy()
        joint.advance_array(k[0:3], k[3:6], k[6:9], k[9:12], row[1], True)   # doStep: the inputs held
    return outputs, profiles, joint


def test_trace_has_hundreds_of_onsets_and_visible_wear(joint_on_trace):
    outputs, _, joint = joint_on_trace
    contact = outputs[:, SCALAR_NAMES.index("contact")]
    assert np.count_nonzero((contact[1:] > 0.5) & (contact[:-1] < 0.5)) >= 150
    assert joint.max_wear_depth_m > 1e-5   # a tenth of the clearance


TRACE_JOINT = paper_joint(wear_factor=WEAR_FACTOR)   # the slider-crank's joint: its body-frame offsets


def test_native_fmu_in_fmpy_equals_the_joint_bit_for_bit(native, slider_crank_trace, joint_on_trace):
    outputs, profiles, joint = joint_on_trace
    vr = native["vr"]
    fmu = FMU2Slave(guid=native["md"].guid, unzipDirectory=str(native["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName="trace")
    fmu.instantiate()
    try:
        enter_initialisation(fmu, vr, TRACE_JOINT)
        fmu.exitInitializationMode()
        inputs = [vr[v.name] for v in fv.INPUTS]
        scalars = [vr[n] for n in SCALAR_NAMES]
        wear = [vr[fv.wear_depth_name(z)] for z in range(1, N_POINTS + 1)]
        for i, row in enumerate(slider_crank_trace):
            fmu.setReal(inputs, list(row[2:]))
            assert np.array_equal(fmu.getReal(scalars), outputs[i]), i
            if i in profiles:
                assert np.array_equal(fmu.getReal(wear), profiles[i]), i
            fmu.doStep(row[0], row[1])
        assert np.array_equal(fmu.getReal(wear), joint.wear_depth)
    finally:
        fmu.terminate()
        fmu.freeInstance()


def _init_script(native, params=None) -> str:
    """Instantiate and initialise with the parameters of ``params`` (default: the paper's slider-crank joint)."""
    reals, integers = fv.fmi_parameter_values_by_type(params or paper_joint())
    vr = native["vr"]
    return ("instantiate joint\nsetup 0\nenter_init\n"
            f"set_real {' '.join(f'{vr[k]}={v!r}' for k, v in reals.items())}\n"
            f"set_integer {' '.join(f'{vr[k]}={v!r}' for k, v in integers.items())}\nexit_init\n")


def test_native_fmu_from_c_without_python_equals_the_joint(native, c_host, slider_crank_trace, joint_on_trace,
                                                           tmp_path):
    outputs, _, joint = joint_on_trace
    vr = native["vr"]
    trace = write_trace_file(tmp_path / "trace.txt", slider_crank_trace)
    wear = " ".join(str(vr[fv.wear_depth_name(z)]) for z in range(1, N_POINTS + 1))
    script = (_init_script(native, TRACE_JOINT)
              + f"trace {trace} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
                f"{','.join(str(vr[n]) for n in SCALAR_NAMES)}\n"
              + f"get_real {wear}\nterminate\nfree\n")
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid, script)
    assert code == 0, stderr[-2000:]
    rows = np.array(trace_rows(stdout), dtype=float)
    assert rows.shape == (len(slider_crank_trace), 1 + len(SCALAR_NAMES))
    assert np.array_equal(rows[:, 1:], outputs)
    profile = [float(line.split()[2]) for line in value_lines(stdout)]
    assert np.array_equal(profile, joint.wear_depth)
    assert stderr_value(stderr, "trace_seconds") > 0.0


# ------------------------------------------------------------- from C: state, cycles, errors, memory
def _touching_inputs():
    """FMU inputs with the pin pressed 5 um into the bushing of the paper's slider-crank at rest."""
    p = paper_joint()
    bushing_angle, pin_angle, direction = 0.3, 0.7, 1.0
    bx = math.cos(bushing_angle) * p.bushing_offset_m[0]
    by = math.sin(bushing_angle) * p.bushing_offset_m[0]
    centre = (0.2 + bx, 0.05 + by)
    e = p.clearance_m + 5e-6
    pin = (centre[0] + e * math.cos(direction), centre[1] + e * math.sin(direction))
    px, py = math.cos(pin_angle) * p.pin_offset_m[0], math.sin(pin_angle) * p.pin_offset_m[0]
    return [pin[0] - px, pin[1] - py, pin_angle, 10.0 * py, -10.0 * px, 10.0, 0.2, 0.05, bushing_angle, 0.0, 0.0, 0.0]


def _inputs_assignment(native, values) -> str:
    return " ".join(f"{native['vr'][v.name]}={x!r}" for v, x in zip(fv.INPUTS, values))


def test_a_rolled_back_repeat_from_c_is_bit_identical(native, c_host):
    steps = "".join(f"do_step {k * 1e-5!r} 1e-05\nget_real {native['vr']['pin_force_x']} "
                    f"{native['vr']['max_wear_depth']}\n" for k in range(20))
    script = (_init_script(native) + f"set_real {_inputs_assignment(native, _touching_inputs())}\n"
              + "get_state 0\n" + steps + "set_state 0\n" + steps + "free_state 0\nfree\n")
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid, script)
    assert code == 0, stderr
    values = value_lines(stdout)
    assert len(values) == 80 and values[:40] == values[40:]
    assert float(values[39].split()[2]) > 0.0   # the repeat did wear the bushing
    assert "free_state 0 ok pointer_null=1" in stdout


def test_thousand_instances_leave_resident_memory_unchanged(native, c_host):
    """After 10 cycles have touched the pages an instance uses (code, libm, heap), 1000 more
    instantiate/initialise/free cycles leave the resident set as it was (two pages of slack)."""
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid,
                                      "cycle 10\ncycle 1000\n")
    assert code == 0, stderr
    assert "iterations=1000" in stdout
    growth = stderr_value(stderr, "rss_kb_after") - stderr_value(stderr, "rss_kb_before")   # the last cycle's
    assert growth <= 8, f"resident memory grew by {growth} kB over 1000 instantiate/free cycles"


def test_startup_and_resident_memory_of_a_c_host(native, c_host):
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid,
                                      "time_load\nfree\n")
    assert code == 0, stderr
    # generous bounds for a loaded CI machine; the benchmark reports the figures
    assert stderr_value(stderr, "startup_seconds") < 0.5


def test_wrong_guid_unknown_references_null_pointers_and_call_order_from_c(native, c_host):
    vr = native["vr"]
    n_variables = len(native["md"].modelVariables)
    script = f"""\
instantiate bad {{00000000-0000-0000-0000-000000000000}}
expect error
instantiate joint
do_step 0 1e-5
expect error
get_real {vr['pin_force_x']}
expect error
setup 0
enter_init
exit_init
get_real {n_variables}
expect error
set_real {vr['pin_force_x']}=1.0
expect error
set_real {vr['restitution']}=0.5
expect error
call_null fmi2GetReal values
expect error
call_null fmi2DoStep component
expect error
call_null fmi2GetFMUstate values
expect error
do_step 0 -1e-5
expect discard
do_step 0 1e-5
free
"""
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid, script)
    assert code == 0, stdout + stderr
    assert "instantiate null" in stdout
    assert "GUID" in stderr and "not allowed in state" in stderr
    assert f"<no variable with valueReference {n_variables}>" in stderr
    assert "pin_force_x cannot be set" in stderr and "parameter restitution is fixed" in stderr


BAD_PARAMETERS = [   # FMU variable, value, words of the allowed range
    ("bushing_radius", 0.0099, "pin_radius"), ("bushing_radius", 0.0100, "pin_radius"),
    ("pin_youngs_modulus", 0.0, "> 0"), ("bushing_youngs_modulus", -1.0, "> 0"),
    ("pin_poisson_ratio", 0.5, "(0, 0.5)"), ("bushing_poisson_ratio", 0.0, "(0, 0.5)"),
    ("restitution", 0.0, "[0.001, 1]"), ("restitution", 1.2, "[0.001, 1]"), ("friction_coefficient", -0.1, "in [0, 10]"),
    ("friction_v1", 1e-3, "friction_v0"), ("wear_coefficient", -1e-10, ">= 0"), ("wear_factor", -2.0, ">= 0"),
    ("pin_radius", math.nan, "finite"), ("contact_stiffness", math.inf, "finite"), ("contact_length", 0.0, "> 0"),
    ("impact_velocity_floor", 0.0, "in (0, 100]"), ("contact_exponent", -1.5, "> 0"), ("pin_offset_y", math.nan, "finite"),
    ("rho_mode", 2, "conformal"), ("wear_placement", 5, "patch"), ("sliding_distance", -1, "rotation"),
]


@pytest.mark.parametrize("name, value, allowed", BAD_PARAMETERS)
def test_bad_parameter_fails_initialisation_naming_the_fmu_variable(native, c_host, name, value, allowed):
    """fmi2Error at exitInitializationMode, logged (even with logging off) naming the FMU variable,
    its value and its allowed range; the instance is then freed normally."""
    kind = "set_integer" if isinstance(value, int) else "set_real"
    script = (f"instantiate bad\nset_debug_logging 0\nsetup 0\nenter_init\n{kind} {native['vr'][name]}={value!r}\n"
              "exit_init\nexpect error\nfree\n")
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid, script)
    assert code == 0, stdout + stderr
    errors = [line for line in stderr.splitlines() if line.startswith("LOG error")]
    shown = "nan" if value != value else repr(value)
    assert any(f"parameter {name}={shown} is invalid: allowed" in m and allowed in m for m in errors), errors


@pytest.mark.slow
def test_the_c_host_runs_the_native_fmu_under_valgrind_without_errors_or_leaks(native, c_host, slider_crank_trace,
                                                                                  tmp_path):
    """A trace with wear, a state rollback and serialisation, error paths and instance cycles
    under valgrind: zero errors, no definite leak."""
    vr = native["vr"]
    trace = write_trace_file(tmp_path / "trace.txt", slider_crank_trace[:3000])
    end = float(slider_crank_trace[2999][0] + slider_crank_trace[2999][1])      # the FMU's time after the trace
    script = (_init_script(native, TRACE_JOINT)
              + f"trace {trace} 12 {','.join(str(vr[v.name]) for v in fv.INPUTS)} "
                f"{','.join(str(vr[n]) for n in SCALAR_NAMES)}\n"
              + f"get_state 0\nserialize 0 {tmp_path / 'state.bin'}\ndeserialize 1 {tmp_path / 'state.bin'}\n"
              + f"set_state 1\ndo_step {end!r} 1e-05\nfree_state 0\nfree_state 1\n"
              + f"set_real {vr['pin_x']}=nan\ndo_step {end + 1e-5!r} 1e-05\nexpect discard\n"
              + f"get_real {vr['pin_force_x']}\nexpect error\nterminate\nfree\n"
              + "instantiate bad {00000000-0000-0000-0000-000000000000}\nexpect error\n"
              + f"instantiate again\nsetup 0\nenter_init\nset_real {vr['restitution']}=2.0\nexit_init\n"
              + "expect error\nfree\ncycle 50\n")
    code, stdout, stderr = run_c_host(c_host, native["dir"], fv.MODEL_NAME, native["md"].guid, script,
                                      valgrind=True, timeout=1200)
    assert code == 0, stdout[-2000:] + stderr[-3000:]
    assert_valgrind_clean(stderr)


def test_the_fmu_writes_nothing_to_stdout(native, capfd):
    """Errors and every call sequence go to the host's logger; the FMU itself prints nothing."""
    from fmpy.fmi2 import fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, defaultCallbacks

    messages = []
    logger = fmi2CallbackLoggerTYPE(lambda env, name, status, category, message: messages.append(message))
    callbacks = fmi2CallbackFunctions(logger=logger, allocateMemory=defaultCallbacks.allocateMemory,
                                      freeMemory=defaultCallbacks.freeMemory)
    vr = native["vr"]
    capfd.readouterr()
    fmu = FMU2Slave(guid=native["md"].guid, unzipDirectory=str(native["dir"]), modelIdentifier=fv.MODEL_NAME,
                    instanceName="quiet")
    fmu.instantiate(callbacks=callbacks, loggingOn=True)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["friction_v1"]], [0.0])
    with pytest.raises(FMICallException):
        fmu.exitInitializationMode()
    fmu.setReal([vr["friction_v1"]], [0.01])
    fmu.exitInitializationMode()
    fmu.setReal([vr[v.name] for v in fv.INPUTS], [math.inf] * 12)
    with pytest.raises(FMICallException):
        fmu.getReal([vr["normal_force"]])
    with pytest.raises(FMICallException):
        fmu.doStep(0.0, 1e-5)
    fmu.terminate()
    fmu.freeInstance()
    assert len(messages) >= 3
    assert capfd.readouterr().out == ""
