"""Property tests (hypothesis) at the boundary users touch: random valid parameters and finite
kinematics in, for the in-process ClearanceJoint and for the native FMU.

Properties: finite outputs; pin force = -bushing force (Eq. 22); torques consistent with the
lever arms (Eqs. 21, 23: recomputed here from the contact angle, and the moment balance
T_i + T_j - (r_j - r_i) x F_i = delta F_t for the deepest point, whose two contact points are delta n
apart, 0 for the foundation, whose forces act at one point);
evaluate changes no state; serialise -> deserialise gives the same outputs; the FMU gives the
joint's numbers; invalid parameters give an error, never a crash.
"""
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wearjoint import ClearanceJoint, JointParameters, ParameterError
from wearjoint.fmu import variables as fv
from fmpy_instance import enter_initialisation
from wearjoint.parameters import CONTACT_MODELS, RHO_MODES, SLIDING_DISTANCES, WEAR_PLACEMENTS

PROPERTY_SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
N_POINTS = 64   # the FMU's N_d is fixed at build time: a small native build for these tests


def _finite(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def joint_parameters(draw) -> JointParameters:
    pin_radius = draw(_finite(1e-3, 5e-2))
    v0 = draw(_finite(0.0, 1e-2))
    model = draw(st.sampled_from(CONTACT_MODELS))
    return JointParameters(contact_model=model,
        pin_radius_m=pin_radius, bushing_radius_m=pin_radius + draw(_finite(1e-6, 1e-3)),
        pin_offset_m=(draw(_finite(-0.2, 0.2)), draw(_finite(-0.2, 0.2))),
        bushing_offset_m=(draw(_finite(-0.2, 0.2)), draw(_finite(-0.2, 0.2))),
        contact_length_m=draw(_finite(1e-3, 5e-2)), pin_youngs_modulus_Pa=draw(_finite(1e9, 1e12)),
        pin_poisson_ratio=draw(_finite(0.01, 0.49)), bushing_youngs_modulus_Pa=draw(_finite(1e9, 1e12)),
        bushing_poisson_ratio=draw(_finite(0.01, 0.49)), contact_stiffness_N_m1_5=draw(_finite(1e8, 1e12)),
        contact_exponent=draw(_finite(1.0, 2.0)) if model == "deepest" else 1.5, restitution=draw(_finite(0.05, 1.0)),
        friction_coefficient=draw(_finite(0.0, 0.5)), friction_v0_m_s=v0,
        friction_v1_m_s=v0 + draw(_finite(1e-4, 0.1)), wear_coefficient_m2_N=draw(_finite(0.0, 1e-8)),
        wear_factor=draw(_finite(0.0, 100.0)), n_points=N_POINTS, rho_mode=draw(st.sampled_from(RHO_MODES)),
        wear_placement=draw(st.sampled_from(WEAR_PLACEMENTS)),
        sliding_distance=draw(st.sampled_from(SLIDING_DISTANCES)),
        impact_velocity_floor_m_s=draw(_finite(1e-5, 1e-2)))


def _rotate(angle, x, y):
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


@st.composite
def kinematics(draw, p: JointParameters):
    """(pin body, bushing body) kinematics with the pin centre from the bushing centre at up to the
    clearance + 2 % of it (free flight and contact; half of the draws in contact, so histories have
    consecutive contacts), any direction, any velocities."""
    bushing_angle, pin_angle = draw(_finite(-10.0, 10.0)), draw(_finite(-10.0, 10.0))
    bx, by = draw(_finite(-1.0, 1.0)), draw(_finite(-1.0, 1.0))
    ox, oy = _rotate(bushing_angle, *p.bushing_offset_m)
    e = p.clearance_m * draw(st.one_of(_finite(0.0, 1.02), _finite(1.0, 1.02)))   # half of them in contact
    direction = draw(_finite(0.0, 2 * math.pi))
    px, py = _rotate(pin_angle, *p.pin_offset_m)
    pin_body = (bx + ox + e * math.cos(direction) - px, by + oy + e * math.sin(direction) - py)
    velocities = [draw(_finite(-10.0, 10.0)) for _ in range(6)]
    pin = np.array([*pin_body, pin_angle, *velocities[:3]])
    bushing = np.array([bx, by, bushing_angle, *velocities[3:]])
    return pin, bushing


@st.composite
def joint_and_kinematics(draw):
    p = draw(joint_parameters())
    return p, draw(kinematics(p)), draw(st.lists(kinematics(p), min_size=0, max_size=5))


def accept_history(joint: ClearanceJoint, history, dt: float = 1e-4, held: bool = False) -> list:
    """Some wear and contact memory first: each (pin, bushing) kinematics accepted over dt (``held``:
    as a co-simulation step, the kinematics held over it).  A step the joint refuses (its wear beyond the bushing
    radius, or the pin deeper in the wall than any contact, for the drawn parameters) leaves it unchanged; returns
    which were refused."""
    refused = []
    for h_pin, h_bushing in history:
        try:
            with warnings.catch_warnings():     # dt over the wear-step limit on purpose: much wear in few steps
                warnings.filterwarnings("ignore", "a wearing step", RuntimeWarning)
                joint.advance(h_pin, h_bushing, dt, held=held)
            refused.append(False)
        except ParameterError as exc:
            assert ("would wear the bushing by more than its radius" in str(exc)
                    or "deeper into the bushing wall" in str(exc))
            refused.append(True)
    return refused


def _result_vector(r) -> np.ndarray:
    return np.array([*r.pin_force, *r.bushing_force, r.normal_force_N, r.friction_force_N, r.penetration_m,
                     float(r.in_contact), r.contact_angle_rad, *r.eccentricity_m])


def _lever_arm_torque(p: JointParameters, joint: ClearanceJoint, pin, bushing, r) -> float:
    """Eq. 21 recomputed from the outputs: the pin's contact point is R_i along the normal n from the
    pin centre, n recovered from the force F = -F_N n + F_T t (t = n turned +90 deg, Eqs. 20-22) with
    the reported F_N and F_T; whichever contact point the joint chose, the torque must be its arm's."""
    fx, fy = r.pin_force[0], r.pin_force[1]
    f_n, f_t = r.normal_force_N, r.friction_force_N
    det = f_n * f_n + f_t * f_t                 # F = M n with M = [[-F_N, -F_T], [F_T, -F_N]]
    if det == 0.0:
        return 0.0                              # touching with no force: no torque
    n = ((-f_n * fx + f_t * fy) / det, (-f_t * fx - f_n * fy) / det)
    ax, ay = _rotate(pin[2], *p.pin_offset_m)
    centre = (pin[0] + ax, pin[1] + ay)
    arm = (centre[0] + p.pin_radius_m * n[0] - pin[0], centre[1] + p.pin_radius_m * n[1] - pin[1])
    return arm[0] * r.pin_force[1] - arm[1] * r.pin_force[0]


@PROPERTY_SETTINGS
@given(joint_and_kinematics())
def test_forces_are_finite_opposite_and_balanced(case):
    p, (pin, bushing), history = case
    joint = ClearanceJoint(p)
    accept_history(joint, history)
    before = joint.state_to_bytes()
    r = joint.evaluate(pin, bushing)
    assert np.all(np.isfinite(_result_vector(r)))
    assert joint.state_to_bytes() == before                           # evaluate changes no state
    assert np.array_equal(_result_vector(joint.evaluate(pin, bushing)), _result_vector(r))
    assert r.bushing_force[:2] == (-r.pin_force[0], -r.pin_force[1])  # Eq. 22
    assert r.in_contact == (r.penetration_m >= 0.0)
    scale = max(1.0, abs(r.normal_force_N) + abs(r.friction_force_N))
    if r.in_contact:
        assert r.pin_force[2] == pytest.approx(_lever_arm_torque(p, joint, pin, bushing, r), abs=1e-9 * scale)
        ri, rj = pin[:2], bushing[:2]
        transfer = (rj[0] - ri[0]) * r.pin_force[1] - (rj[1] - ri[1]) * r.pin_force[0]
        balance = r.pin_force[2] + r.bushing_force[2] - transfer
        # the deepest point's two contact points are delta n apart; the foundation's forces share one point
        offset = r.penetration_m if p.contact_model == "deepest" else 0.0
        assert balance == pytest.approx(offset * r.friction_force_N, abs=1e-9 * scale)
    else:
        assert r.pin_force == (0.0, 0.0, 0.0) and r.bushing_force == (0.0, 0.0, 0.0)


@PROPERTY_SETTINGS
@given(joint_and_kinematics())
def test_state_round_trip_gives_the_same_outputs(case):
    p, (pin, bushing), history = case
    joint = ClearanceJoint(p)
    accept_history(joint, history)
    copy = ClearanceJoint(p)
    copy.state_from_bytes(joint.state_to_bytes())
    assert np.array_equal(_result_vector(copy.evaluate(pin, bushing)), _result_vector(joint.evaluate(pin, bushing)))
    assert copy.state_to_bytes() == joint.state_to_bytes()


INVALID = st.one_of(
    st.tuples(st.just("restitution"), st.one_of(_finite(-1.0, 0.0), _finite(1.0 + 1e-9, 10.0))),
    st.tuples(st.just("pin_poisson_ratio"), st.one_of(_finite(-1.0, 0.0), _finite(0.5, 2.0))),
    st.tuples(st.just("contact_stiffness_N_m1_5"), st.one_of(_finite(-1e12, -1e-9), st.just(math.inf))),  # FMU 0: derived
    st.tuples(st.just("friction_coefficient"), _finite(-10.0, -1e-12)),
    st.tuples(st.just("wear_factor"), st.one_of(_finite(-1e3, -1e-12), st.just(math.nan))),
    st.tuples(st.just("bushing_radius_m"), _finite(0.0, 0.0100)),
    st.tuples(st.just("contact_length_m"), _finite(-1.0, 0.0)),
)


@PROPERTY_SETTINGS
@given(INVALID)
def test_invalid_parameters_raise_naming_them(bad):
    name, value = bad
    with pytest.raises(ParameterError, match=name):
        JointParameters(**{name: value})


# ------------------------------------------------------------- the native FMU, same properties
FIELD_TO_VARIABLE = {p.field if p.component is None else (p.field, p.component): p for p in fv.PARAMETERS}


@pytest.fixture(scope="module")
def small_native(shared_build, tmp_path_factory):
    fmpy = pytest.importorskip("fmpy")
    path = shared_build(n_points=N_POINTS, backend="native")
    md = fmpy.read_model_description(str(path))
    return {"md": md, "dir": fmpy.extract(str(path), unzipdir=str(tmp_path_factory.mktemp("small_native"))),
            "vr": fv.value_references(md)}


def _instance(small_native, p: JointParameters | None, invalid: tuple | None = None):
    from fmpy.fmi2 import FMU2Slave

    fmu = FMU2Slave(guid=small_native["md"].guid, unzipDirectory=small_native["dir"],
                    modelIdentifier=fv.MODEL_NAME, instanceName="property")
    fmu.instantiate(loggingOn=False)
    vr = small_native["vr"]
    enter_initialisation(fmu, vr, p)
    if invalid is not None:
        name, value = invalid
        fmu.setReal([vr[name]], [value])
    return fmu


FMU_OUTPUTS = ["pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque",
               "normal_force", "friction_force", "penetration", "contact", "contact_angle", "eccentricity_x",
               "eccentricity_y"]


@PROPERTY_SETTINGS
@given(case=joint_and_kinematics())
def test_native_fmu_gives_the_joints_numbers_and_round_trips_its_state(small_native, case):
    from fmpy.fmi1 import FMICallException

    p, (pin, bushing), history = case
    vr = small_native["vr"]
    inputs = [vr[v.name] for v in fv.INPUTS]
    outputs = [vr[n] for n in FMU_OUTPUTS]
    wear = [vr[fv.wear_depth_name(z)] for z in range(1, N_POINTS + 1)]
    joint = ClearanceJoint(p)
    fmu = _instance(small_native, p)
    try:
        fmu.exitInitializationMode()
        t = 0.0
        for h_pin, h_bushing in history:
            fmu.setReal(inputs, [*h_pin, *h_bushing])
            refused = accept_history(joint, [(h_pin, h_bushing)], held=True)[0]   # a CS step holds its inputs
            try:
                fmu.doStep(t, 1e-4)
                assert not refused
                t += 1e-4
            except FMICallException as failure:       # the FMU refuses the same absurd wear, with Discard: the
                assert refused and failure.status == 2    # master goes on from the FMU's time
        fmu.setReal(inputs, [*pin, *bushing])
        first = fmu.getReal(outputs)
        assert fmu.getReal(outputs) == first                   # evaluation changes nothing
        assert np.all(np.isfinite(first))
        assert first[3:5] == [-first[0], -first[1]]
        assert first == _result_vector(joint.evaluate(pin, bushing)).tolist()
        assert fmu.getReal(wear) == joint.wear_depth.tolist()
        restored = _instance(small_native, None)
        try:
            restored.exitInitializationMode()
            restored.setFMUstate(restored.deSerializeFMUstate(fmu.serializeFMUstate(fmu.getFMUstate())))
            assert restored.getReal(outputs) == first
            assert restored.getReal(wear) == joint.wear_depth.tolist()
        finally:
            restored.freeInstance()
    finally:
        fmu.freeInstance()


@PROPERTY_SETTINGS
@given(bad=INVALID)
def test_native_fmu_refuses_invalid_parameters_with_an_error(small_native, bad):
    from fmpy.fmi1 import FMICallException

    name, value = bad
    variable = FIELD_TO_VARIABLE[name].variable.name
    fmu = _instance(small_native, None, (variable, value))
    try:
        with pytest.raises(FMICallException) as failure:
            fmu.exitInitializationMode()
        assert failure.value.status == 3
    finally:
        fmu.freeInstance()
