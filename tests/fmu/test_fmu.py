"""The ClearanceWearJoint FMU (docs/reference/fmu.md §5) of both backends driven through fmpy: its
modelDescription, its outputs and the wear of its steps.

Each FMU is built once per session (fixtures ``native_fmu``, ``built_fmu`` for pythonfmu);
the behaviour tests run on both backends (conftest.py's fixture ``fmu``; ``slave``, an initialised
instance); every test gets fresh instances (:class:`Slave` of fmpy_instance.py).  The FMU's other
features, its states, its errors and its build, have a test_fmu_* file each.
"""
import gc
import math

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402
from fmpy_instance import FORCE_NAMES, INPUT_NAMES, P, SCALAR_NAMES, Slave, contact_inputs  # noqa: E402

from wearjoint import ClearanceJoint, JointParameters  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402


# ------------------------------------------------------------- modelDescription
def test_validate_fmu_reports_no_problem(fmu):
    assert validate_fmu(str(fmu["path"])) == []


def test_model_description_matches_the_variable_table(fmu):
    md = fmu["md"]
    table = fv.fmu_variables(P.n_points)
    assert [v.name for v in md.modelVariables] == [v.name for v in table]
    for v, row in zip(md.modelVariables, table):
        assert v.description, v.name
        assert v.causality == row.causality
        if v.type == "Real":
            assert v.unit == row.unit, v.name
    n_points = next(v for v in md.modelVariables if v.name == "n_points")
    assert (n_points.variability, int(n_points.start)) == ("constant", P.n_points)
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert md.coSimulation.providesDirectionalDerivative == (fmu["backend"] == "native")   # pythonfmu: none


def test_the_native_model_description_states_the_parameters_ranges(fmu):
    """A tool shows and checks min/max (there were none): the rules' bounds, an open one as its limit (FMI's are
    inclusive); beyond max the FMU refuses the value at initialisation, naming its range."""
    if fmu["backend"] != "native":
        pytest.skip("the pythonfmu backend's modelDescription is pythonfmu's")
    variables = {v.name: v for v in fmu["md"].modelVariables}
    bounds = {name: (float(variables[name].min), float(variables[name].max))
              for name in ("pin_radius", "restitution", "pin_offset_x", "wear_interval")}
    assert bounds == {"pin_radius": (1e-6, 100.0), "restitution": (0.001, 1.0), "pin_offset_x": (-1e3, 1e3),
                      "wear_interval": (0.0, 3e-5)}
    assert variables["friction_coefficient"].min == "0.0"
    # an enumeration: its codes (contact_damping 0..3: Hunt-Crossley, Lankarani-Nikravesh, Tsuji, L-N exact)
    assert (variables["contact_damping"].min, variables["contact_damping"].max) == ("0", "3")
    assert (variables["rho_mode"].min, variables["rho_mode"].max) == ("0", "1")
    from fmpy.fmi1 import FMICallException
    from fmpy_instance import Slave

    s = Slave(fmu, "beyond_max", parameters={"pin_offset_x": 1e3 * (1 + 1e-12)})
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, "pin_offset_x", "[-1000, 1000]")
    s.free()


def test_parameter_defaults_are_the_papers(fmu):
    starts = {}
    for v in fmu["md"].modelVariables:
        if v.causality == "parameter":
            starts[v.name] = int(v.start) if v.type == "Integer" else float(v.start)
    assert fv.joint_parameters_from_fmi(starts, P.n_points) == JointParameters()


def test_every_joint_parameter_is_an_fmu_parameter():
    from dataclasses import fields

    covered = {p.field for p in fv.PARAMETERS} | {"n_points"}
    assert covered == {f.name for f in fields(JointParameters)}
    assert fv.joint_parameters_from_fmi(fv.fmi_parameter_values(P.replace(rho_mode="paper")), P.n_points) \
        == P.replace(rho_mode="paper")


def test_model_structure_declares_direct_feed_through(fmu):
    md = fmu["md"]
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    for unknown in md.outputs:
        depends_on = {v.name for v in unknown.dependencies}
        if unknown.variable.name in fv.FEED_THROUGH_OUTPUTS:   # the geometry: positions; the forces: all inputs
            assert depends_on == set(fv.OUTPUT_DEPENDENCIES[unknown.variable.name]) <= inputs, unknown.variable.name
        else:
            assert depends_on == set(), unknown.variable.name


# ------------------------------------------------------------- forces
def test_forces_are_the_joints_and_point_back_to_the_bushing_centre(slave):
    direction = 1.0
    x = contact_inputs(direction=direction)
    slave.set_inputs(x)
    out = dict(zip(SCALAR_NAMES, slave.get(SCALAR_NAMES)))

    expected = ClearanceJoint(JointParameters()).evaluate(x[:6], x[6:])
    got = [out[n] for n in FORCE_NAMES]
    np.testing.assert_allclose(got, [*expected.pin_force, *expected.bushing_force], rtol=1e-12, atol=0)
    assert out["contact"] == 1.0
    assert out["penetration"] == pytest.approx(5e-6, rel=1e-3)
    assert out["normal_force"] == pytest.approx(expected.normal_force_N, rel=1e-12)
    # the foundation's K delta^1.5 (3 % under it at 5 um: docs/reference/model.md §3.10)
    assert out["normal_force"] == pytest.approx(P.stiffness_N_m1_5 * 5e-6 ** 1.5, rel=4e-2)

    pin_force = np.array([out["pin_force_x"], out["pin_force_y"]])
    outward = np.array([math.cos(direction), math.sin(direction)])
    cos_to_centre = -pin_force @ outward / np.linalg.norm(pin_force)
    assert cos_to_centre >= math.cos(math.atan(P.friction_coefficient)) - 1e-9
    assert out["pin_force_x"] == -out["bushing_force_x"] and out["pin_force_y"] == -out["bushing_force_y"]
    # contact angle and eccentricity in the bushing frame (bushing body angle 0.3 rad)
    assert out["contact_angle"] == pytest.approx(direction - 0.3, abs=2 * math.pi / P.n_points)
    np.testing.assert_allclose([out["eccentricity_x"], out["eccentricity_y"]],
                               (P.clearance_m + 5e-6) * np.array([math.cos(0.7), math.sin(0.7)]), rtol=1e-6)


@pytest.mark.parametrize("law", range(4))
def test_every_damping_law_gives_the_joints_force(fmu, law):
    """The damping coefficient is solved inside the FMU from its own parameters (core.damping): the normal
    force of a pin approaching the wall at 0.05 m/s (and leaving at 0.02 m/s) is the in-process joint's, for
    each law at a restitution of 0.3, a restitution speed of 30 mm/s and an effective mass of 0.4 kg."""
    from wearjoint.parameters import CONTACT_DAMPINGS

    params = P.replace(contact_damping=CONTACT_DAMPINGS[law], restitution=0.3, restitution_speed_m_s=0.03,
                       effective_mass_kg=0.4)
    s = Slave(fmu, f"law{law}", parameters={"restitution": 0.3, "restitution_speed": 0.03, "effective_mass": 0.4},
              integers={"contact_damping": law}).initialise()
    for speed in (0.05, -0.02):
        x = contact_inputs(depth=3e-6)
        x[3] += speed * math.cos(1.0)           # the pin body moving along the contact direction (global 1 rad)
        x[4] += speed * math.sin(1.0)
        s.set_inputs(x)
        expected = ClearanceJoint(params).evaluate(x[:6], x[6:]).normal_force_N
        elastic = ClearanceJoint(params).evaluate(contact_inputs(depth=3e-6)[:3] + [0.0] * 3,
                                                  contact_inputs(depth=3e-6)[6:9] + [0.0] * 3).normal_force_N
        assert s.get(["normal_force"])[0] == pytest.approx(expected, rel=1e-12)
        assert abs(expected - elastic) > 0.01 * elastic        # the damping acts
    s.free()


def test_the_materials_set_the_stiffness_unless_it_is_given(fmu):
    """contact_stiffness = 0 (the start value): K of the FMU's own radii and materials, so a bushing
    10x softer carries the force of 4 E* sqrt(R)/3 (by hand here); a given K overrides them."""
    x = contact_inputs(depth=4e-6)
    forces = {}
    for label, parameters in (("paper", {}), ("soft", {"bushing_youngs_modulus": 7.17e9}),
                              ("given", {"bushing_youngs_modulus": 7.17e9, "contact_stiffness": 2e10})):
        s = Slave(fmu, label, parameters=parameters).initialise()
        s.set_inputs(x)
        forces[label] = s.get(["normal_force"])[0]
        s.free()
    def k_by_hand(e_bushing):
        e_star = 1.0 / ((1 - 0.29 ** 2) / 207e9 + (1 - 0.33 ** 2) / e_bushing)
        return 4.0 / 3.0 * e_star * math.sqrt(0.01 * 0.0101 / 0.0001)
    # the foundation's force at a fixed overlap is proportional to K (k_f = 3 K sqrt(c) / (4 sqrt(2) L sqrt(R_i R_j)))
    assert forces["soft"] / forces["paper"] == pytest.approx(k_by_hand(7.17e9) / k_by_hand(71.7e9), rel=1e-9)
    assert forces["given"] / forces["paper"] == pytest.approx(2e10 / k_by_hand(71.7e9), rel=1e-9)
    s = Slave(fmu, "exponent", parameters={"contact_exponent": 2.0}, integers={"contact_model": 1})
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, "contact_exponent")
    s.free()


def test_outputs_follow_inputs_without_a_step(slave):
    slave.set_inputs(contact_inputs(depth=2e-6))
    shallow = slave.get(["normal_force"])[0]
    slave.set_inputs(contact_inputs(depth=4e-6))
    deep = slave.get(["normal_force"])[0]
    assert deep / shallow == pytest.approx(2.0 ** 1.5, rel=2e-2)
    slave.set_inputs(contact_inputs(depth=-5e-5))
    assert list(slave.get(["contact", "normal_force", "pin_force_x"])) == [0.0, 0.0, 0.0]


def test_get_real_of_any_list_matches_one_value_at_a_time(slave, fmu):
    slave.set_inputs(contact_inputs(depth=4e-6))
    for k in range(20):
        slave.fmu.doStep(k * 1e-5, 1e-5)
    worn = int(np.argmax(slave.get(fmu["wear"]))) + 1
    names = [fv.wear_depth_name(worn), "pin_force_x", "pin_x", "max_wear_depth", "restitution", "pin_force_x",
             "worn_volume", "normal_force", fv.wear_depth_name(1), "bushing_omega"]
    together = slave.get(names)
    one_by_one = [slave.get([name])[0] for name in names]
    assert together.tolist() == one_by_one
    assert together[0] > 0.0 and together[3] == together[0] and together[4] == P.restitution
    assert slave.fmu.getReal([]) == []


def test_set_real_in_any_order_or_subset_equals_the_full_write(slave):
    x = contact_inputs(depth=3e-6)
    slave.set_inputs(x)
    expected = slave.get(SCALAR_NAMES)
    slave.set_inputs(contact_inputs(depth=-5e-5))
    order = list(reversed(INPUT_NAMES))
    slave.fmu.setReal([slave.vr[n] for n in order], [x[INPUT_NAMES.index(n)] for n in order])
    assert slave.get(SCALAR_NAMES).tolist() == expected.tolist()
    slave.set_inputs(contact_inputs(depth=-5e-5))
    for name, value in zip(INPUT_NAMES, x):
        slave.fmu.setReal([slave.vr[name]], [value])
    assert slave.get(SCALAR_NAMES).tolist() == expected.tolist()


def test_non_finite_input_is_forgotten_once_set_finite(slave):
    x = contact_inputs()
    x[3] = math.inf
    slave.set_inputs(x)
    with pytest.raises(FMICallException) as failure:
        slave.get(["pin_force_x"])
    slave.assert_failed_with_error(failure, "pin_force_x", "pin_vx=inf")
    slave.fmu.setReal([slave.vr["pin_vx"]], [0.0])   # a subset write clears it
    assert slave.get(["contact"])[0] == 1.0
    huge = contact_inputs(depth=-5e-5)
    huge[0] += 1e308   # finite values whose sum overflows: both bodies far out, no contact
    huge[6] += 1e308
    slave.set_inputs(huge)
    assert slave.get(["contact", "normal_force"]).tolist() == [0.0, 0.0]
    gc.collect()


def test_calls_on_the_wrong_variables_fail_with_fmi2_error_naming_them(slave):
    """Outputs and Integers are not settable as Reals, Reals not as Integers, and the FMU has no
    Booleans or Strings: each call fails with fmi2Error and the instance goes on."""
    vr = slave.vr
    for call, words in ((lambda: slave.fmu.setReal([vr["pin_force_x"]], [1.0]), ("pin_force_x", "cannot be set")),
                        (lambda: slave.fmu.setReal([vr["rho_mode"]], [1.0]), ("rho_mode", "cannot be set")),
                        (lambda: slave.fmu.setInteger([vr["restitution"]], [1]), ("restitution", "cannot be set")),
                        (lambda: slave.fmu.getReal([vr["rho_mode"]]), ("rho_mode", "Real")),
                        (lambda: slave.fmu.getInteger([vr["pin_x"]]), ("pin_x", "Integer")),
                        (lambda: slave.fmu.getBoolean([0]), ("Boolean",))):
        with pytest.raises(FMICallException) as failure:
            call()
        slave.assert_failed_with_error(failure, *words)
    assert slave.fmu.getInteger([vr["rho_mode"], vr["n_points"]]) == [0, P.n_points]
    slave.set_inputs(contact_inputs())
    assert slave.get(["contact"])[0] == 1.0
    gc.collect()


# ------------------------------------------------------------- wear
def test_do_step_wears_where_the_pin_presses(slave, fmu):
    x = contact_inputs(direction=2.0, pin_omega=10.0)
    slave.set_inputs(x)
    dt, steps, archard = 1e-5, 40, 0.0
    for k in range(steps):
        normal_force = slave.get(["normal_force"])[0]
        archard += P.wear_coefficient_m2_N * normal_force * P.bushing_radius_m * 10.0 * dt
        slave.fmu.doStep(k * dt, dt)
    h = slave.get(fmu["wear"])
    contact_angle, max_wear, volume = slave.get(["contact_angle", "max_wear_depth", "worn_volume"])

    phi = np.arange(1, P.n_points + 1) * 2 * math.pi / P.n_points
    assert h.min() >= 0.0 and h.max() > 0.0
    offset = np.abs(np.remainder(phi - contact_angle + math.pi, 2 * math.pi) - math.pi)
    assert h[np.argmin(offset)] > 0.0
    worn = h > 0.0
    centre = math.atan2(np.sin(phi[worn]).mean(), np.cos(phi[worn]).mean())
    assert abs(math.remainder(centre - contact_angle, 2 * math.pi)) < 2 * 2 * math.pi / P.n_points
    assert np.all(h[offset > 0.5] == 0.0)
    assert max_wear == h.max()
    # polar area between the worn and the unworn circle, times the contact length
    area = 0.5 * np.sum((P.bushing_radius_m + h) ** 2 - P.bushing_radius_m ** 2) * 2 * math.pi / P.n_points
    assert volume == pytest.approx(P.contact_length_m * area, rel=1e-12)
    # Archard: removed volume = k_w * F_N * sliding distance (rotation: R_j |omega_rel| dt)
    assert volume == pytest.approx(archard, rel=2e-2)


def test_two_instances_keep_independent_state(fmu):
    a = Slave(fmu, "a").initialise()
    b = Slave(fmu, "b").initialise()
    try:
        a.set_inputs(contact_inputs(depth=5e-6))
        b.set_inputs(contact_inputs(depth=-2e-5))
        for k in range(20):
            a.fmu.doStep(k * 1e-5, 1e-5)
            b.fmu.doStep(k * 1e-5, 1e-5)
        assert a.get(["max_wear_depth"])[0] > 0.0
        assert b.get(["max_wear_depth", "worn_volume", "normal_force"]).tolist() == [0.0, 0.0, 0.0]
        assert a.get(["contact"])[0] == 1.0
    finally:
        a.free()
        b.free()
