"""Values of the wrong type, out of physical bounds or in the wrong place are refused in one line naming the
parameter, its value and what is allowed (never a numba TypingError, a TypeError later, or a silent run); the
RK4 step and the co-simulation's step keep the wear-step limit (docs/reference/model.md §7)."""
import math
from decimal import Decimal

import numpy as np
import pytest

from wearjoint import JointParameters, ParameterError, SliderCrankParameters
from wearjoint.checks import ParameterTypeError
from wearjoint.cli import main
from wearjoint.cosim.cosimulation import CoSimulation, CoSimulationOptions, run_cosimulation
from wearjoint.cosim.model_exchange import run_model_exchange
from wearjoint.joint_fields import JOINT_FIELDS, allowed_text
from wearjoint.parameters import paper_joint
from wearjoint.simulate import run_simulation
from wearjoint.simulation_options import SimulationOptions, check_wear_step

def _refused(call, name, value=None, allowed=None, error=ParameterError) -> str:
    """The one line ``call`` is refused with: naming ``name``, its ``value`` (as shown, where given) and what is
    ``allowed`` (where given)."""
    with pytest.raises(error) as refused:
        call()
    text = str(refused.value)
    assert "\n" not in text and text.startswith(f"parameter {name}=") and " is invalid" in text, text
    assert value is None or text.startswith(f"parameter {name}={value} is invalid"), text
    assert allowed is None or f"allowed {allowed}" in text, text
    return text


# ------------------------------------------------------------------ 1: the RK4 step with the default max_step_s
def test_an_rk4_step_over_the_wear_step_limit_is_refused_whatever_max_step_s():
    for max_step in (None, 1e-5):
        _refused(lambda: SimulationOptions(integrator="rk4", step_s=6e-5, max_step_s=max_step).for_joint(paper_joint()),
                 "step_s", "6e-05", "at most 3e-05 s", ParameterError)
    # the share's limit too: a 100x wear factor (a wear-study) shortens it below 3e-5 s
    worn = paper_joint(wear_factor=1000.0)
    text = _refused(lambda: SimulationOptions(integrator="rk4", step_s=1e-5).for_joint(worn), "step_s", "1e-05",
                    "at most 5.52e-06 s")
    assert "with wear" in text and "model.md §7" in text
    # no wear, or the ideal joint: any step
    assert SimulationOptions(integrator="rk4", step_s=6e-5).for_joint(paper_joint(wear_factor=0.0)).step_s == 6e-5
    assert SimulationOptions(integrator="rk4", step_s=6e-5, ideal=True).for_joint(paper_joint()).step_s == 6e-5


@pytest.mark.parametrize("argv, written", [(["simulate", "--integrator", "rk4", "--step", "6e-5"], "6e-5"),
                                           (["cosim", "--scheme", "zoh", "--step", "1e-4"], "1e-4")])
def test_the_cli_refuses_a_step_over_the_wear_step_limit_naming_step(tmp_path, capsys, argv, written):
    """The monolithic RK4 step and the co-simulation's contact step, each named as the command line writes it."""
    code = main([*argv, "--revolutions", "0.01", "--quiet", "--out", str(tmp_path / "out")])
    error = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(error) == 1, error
    assert f"error: --step={written} (step_s) is invalid with wear" in error[0]
    assert "allowed at most 3e-05 s" in error[0]
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------------------ 2: the joint's types
@pytest.mark.parametrize("name, value", [
    ("pin_radius_m", "0.01"), ("pin_radius_m", Decimal("0.01")), ("pin_radius_m", True), ("pin_radius_m", 0.01 + 0j),
    ("restitution", "0.9"), ("restitution", None), ("wear_factor", np.bool_(True)),
    ("contact_stiffness_N_m1_5", "8e10"),
])
def test_a_joint_value_that_is_no_real_number_is_refused(name, value):
    allowed = "a finite real number " + allowed_text(next(f for f in JOINT_FIELDS if f.field == name),
                                                     {f.fmu_name: f.field for f in JOINT_FIELDS})
    _refused(lambda: JointParameters(**{name: value}), name, repr(value), allowed, ParameterTypeError)
    with pytest.raises(TypeError):           # a type error is a TypeError as well as a ParameterError
        JointParameters(**{name: value})


@pytest.mark.parametrize("value", ["12", b"12", (0.0, "1"), (0.0, True), (1.0, 2.0, 3.0), 1.0])
def test_an_offset_that_is_no_pair_of_reals_is_refused(value):
    _refused(lambda: JointParameters(pin_offset_m=value), "pin_offset_m", repr(value),
             "a pair (x, y) of finite lengths in metres", ParameterTypeError)


def test_numpy_reals_are_taken_as_floats_and_numpy_integers_as_integers():
    j = JointParameters(pin_radius_m=np.float32(0.01), restitution=np.float64(0.8), wear_factor=2,
                        pin_offset_m=np.array([0.025, 0.0]), n_points=np.int64(100), contact_stiffness_N_m1_5=0)
    assert type(j.pin_radius_m) is float and type(j.restitution) is float and type(j.wear_factor) is float
    assert j.pin_offset_m == (0.025, 0.0) and type(j.pin_offset_m[0]) is float
    assert type(j.n_points) is int and j.n_points == 100 and j.contact_stiffness_N_m1_5 is None
    assert j == JointParameters(pin_radius_m=float(np.float32(0.01)), restitution=0.8, wear_factor=2.0,
                                pin_offset_m=(0.025, 0.0), n_points=100)
    for n in (True, 100.0, "100"):
        _refused(lambda: JointParameters(n_points=n), "n_points", repr(n), "an integer from 8 to 1000000",
                 ParameterTypeError)


# ------------------------------------------------------------------ 3: the options' types
@pytest.mark.parametrize("cls, changes, name, allowed", [
    (SimulationOptions, {"revolutions": "0.02"}, "revolutions", "a finite real number > 0"),
    (SimulationOptions, {"integrator": "rk4", "step_s": "1e-6"}, "step_s", "a finite real number > 0"),
    (SimulationOptions, {"max_step_s": "1e-5"}, "max_step_s", "a finite real number > 0"),
    (SimulationOptions, {"min_step_s": None}, "min_step_s", "a finite real number > 0"),   # was a TypeError
    (SimulationOptions, {"ideal": "no"}, "ideal", "True or False"),
    (SimulationOptions, {"ideal": 1}, "ideal", "True or False"),
    (CoSimulationOptions, {"revolutions": "1"}, "revolutions", "a finite real number > 0"),
    (CoSimulationOptions, {"step_s": "1e-6"}, "step_s", "a finite real number > 0"),
    (CoSimulationOptions, {"coupling_tolerance": "0.01"}, "coupling_tolerance", "a finite real number >= 0"),
])
def test_an_option_of_the_wrong_type_is_refused(cls, changes, name, allowed):
    _refused(lambda: cls(**changes), name, repr(changes[name]), allowed, ParameterTypeError)


def test_options_keep_numpy_values_as_python_ones():
    o = SimulationOptions(revolutions=np.int64(2), step_s=np.float32(1e-6), ideal=np.bool_(True))
    assert type(o.revolutions) is float and type(o.step_s) is float and o.ideal is True
    c = CoSimulationOptions(revolutions=1, step_s=np.float64(5e-6), scheme="adaptive")
    assert type(c.revolutions) is float and type(c.step_s) is float


# ------------------------------------------------------------------ 4: the mechanism's types, the load table's file
@pytest.mark.parametrize("name, value, allowed", [
    ("crank_length_m", "0.05", "a finite real number > 0"), ("crank_length_m", True, "a finite real number > 0"),
    ("crank_speed_rpm", "150", "a finite real number > 0"),
    ("initial_crank_angle_deg", "90", "a finite real number"), ("slider_force_N", "10", "a finite real number"),
    ("baumgarte_alpha", Decimal(5), "a finite real number >= 0"),
    ("gravity_m_s2", "9.81", "one finite value g"), ("gravity_m_s2", ("0", "-9.81"), "one finite value g"),
    ("slider_force_table", "load.csv", "a SliderForceTable or None"),
])
def test_a_mechanism_value_of_the_wrong_type_is_refused(name, value, allowed):
    _refused(lambda: SliderCrankParameters(**{name: value}), name, repr(value), allowed, ParameterTypeError)


def test_mechanism_values_are_kept_as_floats():
    m = SliderCrankParameters(crank_speed_rpm=np.int64(150), crank_length_m=1 / 20, gravity_m_s2=np.float32(9.81))
    assert type(m.crank_speed_rpm) is float and m.period_s == pytest.approx(0.4)
    assert all(type(g) is float for g in m.gravity_m_s2)


def test_a_load_table_that_is_not_text_is_refused_naming_the_option(tmp_path, capsys):
    table = tmp_path / "load.csv"
    table.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    code = main(["cosim", "--slider-force-table", str(table), "--revolutions", "0.01", "--quiet",
                 "--out", str(tmp_path / "out")])
    error = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(error) == 1, error
    assert f"--slider-force-table='{table}' (slider_force_table) is invalid: allowed a text CSV file" in error[0]
    assert "byte 1 is not UTF-8 text" in error[0] and not (tmp_path / "out").exists()


# ------------------------------------------------------------------ 5: bounds that keep the arithmetic finite
@pytest.mark.parametrize("changes, name, allowed", [
    ({"contact_stiffness_N_m1_5": 1e300}, "contact_stiffness_N_m1_5", ">= 0 (at most 1e+20 N/m^n"),
    ({"pin_youngs_modulus_Pa": 1e308, "bushing_youngs_modulus_Pa": 1e308}, "pin_youngs_modulus_Pa",
     "> 0 (from 100000 to 1e+13 Pa, from foam rubber's 1e5 Pa to 10x diamond's"),
    ({"bushing_youngs_modulus_Pa": 71.7}, "bushing_youngs_modulus_Pa", "> 0 (from 100000 to 1e+13 Pa"),   # GPa as Pa
    ({"pin_youngs_modulus_Pa": 2.1e4}, "pin_youngs_modulus_Pa", "> 0 (from 100000 to 1e+13 Pa"),
    ({"contact_length_m": 1e-300}, "contact_length_m", "> 0 (from 1e-06 to 100 m)"),
    ({"contact_length_m": 1e300}, "contact_length_m", "> 0 (from 1e-06 to 100 m)"),     # wore nothing: depth 0
    ({"wear_coefficient_m2_N": 1e300}, "wear_coefficient_m2_N", ">= 0 (at most 1e-06 m2/N"),
    ({"wear_factor": 1e300}, "wear_factor", ">= 0 (at most 1e+06 times"),
    ({"friction_coefficient": 1e300}, "friction_coefficient", "in [0, 10]"),
    ({"friction_v0_m_s": 1e300}, "friction_v0_m_s", "in [0, 100]"),
    ({"pin_radius_m": 1e-300, "bushing_radius_m": 2e-300}, "pin_radius_m", "> 0 (from 1e-06 to 100 m)"),
    ({"pin_radius_m": 1e200, "bushing_radius_m": 2e200}, "pin_radius_m", "> 0 (from 1e-06 to 100 m)"),
])
def test_values_that_would_overflow_the_contact_are_refused(changes, name, allowed):
    _refused(lambda: JointParameters(**changes), name, repr(changes[name]), allowed)


def test_the_joint_at_its_bounds_gives_finite_forces():
    """The stiffest, smallest and largest joints the rules admit: finite forces half the admissible depth in."""
    from wearjoint import ClearanceJoint

    for ri, length, k in ((1e-6, 1e-6, 1e20), (99.0, 1e-6, None), (1e-6, 100.0, None)):
        joint = JointParameters(pin_radius_m=ri, bushing_radius_m=ri * 1.01, contact_length_m=length,
                                pin_youngs_modulus_Pa=1e13, bushing_youngs_modulus_Pa=1e13,
                                contact_stiffness_N_m1_5=k, n_points=64)
        depth = joint.clearance_m + 0.5 * joint.admissible_penetration_m
        result = ClearanceJoint(joint).evaluate((depth, 0.0, 0.0, 0.0, 1.0, 10.0), (0.0,) * 6)
        assert result.normal_force_N > 0.0 and np.all(np.isfinite(result.pin_force))
        assert math.isfinite(joint.foundation_modulus_N_m3) and 0.0 < joint.max_wear_step_s(1.0) <= 3e-5


@pytest.mark.parametrize("name, value, allowed", [
    ("pin_youngs_modulus", 1e14, "> 0 (from 100000 to 1e+13 Pa"),
    ("bushing_youngs_modulus", 71.7, "> 0 (from 100000 to 1e+13 Pa"),
    ("contact_length", 1e-300, "> 0 (from 1e-06 to 100 m"),
    ("contact_length", 1e300, "> 0 (from 1e-06 to 100 m"), ("wear_coefficient", 1e300, ">= 0 (at most 1e-06 m2/N"),
    ("wear_factor", 1e300, ">= 0 (at most 1e+06 times"),
    ("contact_stiffness", 1e300, ">= 0 (at most 1e+20 N/m^n"),
])
def test_the_fmus_refuse_the_bounds_too(fmu, name, value, allowed):
    """Both backends (the native one from its generated table of the same rules) fail the initialisation with
    fmi2Error naming the parameter and the bound."""
    pytest.importorskip("fmpy")
    from fmpy.fmi1 import FMICallException
    from fmpy_instance import Slave

    s = Slave(fmu, f"bound_{name}", parameters={name: value})
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, f"parameter {name}", " is invalid: allowed " + allowed)   # pythonfmu: API name
    s.free()


# ------------------------------------------------------------------ 6, 7, 8: the runs' arguments
@pytest.mark.parametrize("run, options", [(run_simulation, SimulationOptions(revolutions=0.01)),
                                          (run_cosimulation, CoSimulationOptions(revolutions=0.01)),
                                          (run_model_exchange, SimulationOptions(revolutions=0.01))])
@pytest.mark.parametrize("chunks, error", [(0, ParameterError), (-1, ParameterError), (2.5, ParameterTypeError),
                                           (10 ** 9, ParameterError)])      # 1e9 chunks ran for minutes
def test_chunks_per_revolution_must_be_an_integer_from_1_to_10000(run, options, chunks, error):
    _refused(lambda: run(paper_joint(), SliderCrankParameters(), options, progress=False,
                         chunks_per_revolution=chunks), "chunks_per_revolution", repr(chunks), "an integer from 1 to 10000",
             error)


def test_an_fmu_path_that_is_not_an_fmu_is_refused(tmp_path):
    """Not a zip, missing, a folder, or a zip without a modelDescription.xml (it died in fmpy's FileNotFoundError,
    leaving a temporary folder behind)."""
    import zipfile

    text = tmp_path / "joint.fmu"
    text.write_text("not a zip archive")
    archive = tmp_path / "archive.fmu"
    with zipfile.ZipFile(archive, "w") as z:
        z.writestr("hello.txt", "no model description")
    allowed = "an existing FMU file (.fmu: a zip archive with a modelDescription.xml)"
    for path in (text, tmp_path / "missing.fmu", tmp_path, archive):
        _refused(lambda: CoSimulation(paper_joint(), SliderCrankParameters(), CoSimulationOptions(revolutions=0.01),
                                      fmu_path=path), "fmu_path", repr(str(path)), allowed)
        _refused(lambda: run_model_exchange(paper_joint(), None, SimulationOptions(revolutions=0.01), fmu_path=path),
                 "fmu_path", repr(str(path)), allowed)


@pytest.mark.parametrize("mechanism", [JointParameters(), 0, {}, "paper"])
def test_paper_joint_takes_a_mechanism_only(mechanism):
    text = _refused(lambda: paper_joint(mechanism), "mechanism", error=ParameterTypeError)
    assert "allowed a SliderCrankParameters or None" in text and len(text) < 160


@pytest.mark.parametrize("args, name, expected", [
    ((SliderCrankParameters(), paper_joint()), "joint", "a JointParameters or None"),
    ((paper_joint(), paper_joint()), "mechanism", "a SliderCrankParameters or None"),
    ((paper_joint(), None, {"revolutions": 0.02}), "options", "a SimulationOptions or None"),
])
def test_run_simulation_names_an_argument_of_the_wrong_type(args, name, expected):
    text = _refused(lambda: run_simulation(*args, progress=False), name, error=ParameterTypeError)
    assert expected in text


def test_run_cosimulation_names_options_of_the_wrong_type():
    text = _refused(lambda: run_cosimulation(paper_joint(), None, SimulationOptions(), progress=False), "options",
                    error=ParameterTypeError)
    assert "a CoSimulationOptions or None" in text


# ------------------------------------------------------------------ 9: the wear-step limit's sliding speed
@pytest.mark.parametrize("speed, allowed", [(-1.0, ">= 0"), (math.nan, "a finite real number >= 0"),
                                            ("1", "a finite real number >= 0")])
def test_max_wear_step_refuses_a_sliding_speed_that_is_not_finite_and_non_negative(speed, allowed):
    _refused(lambda: JointParameters().max_wear_step_s(speed), "sliding_speed_m_s", repr(speed), allowed)


def test_max_wear_step_of_a_joint_that_does_not_slide_is_unbounded():
    assert JointParameters().max_wear_step_s(0.0) == math.inf
    assert JointParameters().max_wear_step_s(1.0) <= 3e-5


# ------------------------------------------------------------------ 10: the co-simulation's step with wear
def test_a_cosimulation_step_over_the_wear_step_limit_is_refused_up_front():
    options = CoSimulationOptions(scheme="zoh", step_s=1.0, max_step_s=1.0)
    text = _refused(lambda: CoSimulation(paper_joint(), SliderCrankParameters(), options), "step_s", "1.0",
                    "at most 3e-05 s", ParameterError)
    assert "with wear" in text
    # the same rule as the monolithic engine's, and none without wear
    check_wear_step("step_s", 1.0, paper_joint(wear_factor=0.0))
    check_wear_step("step_s", CoSimulationOptions().step_s, paper_joint())
