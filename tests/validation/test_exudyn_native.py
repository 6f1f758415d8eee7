"""exudyn's own contact as the unworn clearance joint (validation/exudyn_native.py): the
parameter mapping against the laws it stands for, and a pin in a bushing on ground against
statics, the Hertz / Lankarani-Nikravesh impact closed form and the friction angle."""
import math

import numpy as np
import pytest

from wearjoint import JointParameters, ParameterError
from wearjoint.core import layout as L
from wearjoint.core.contact import ambrosio_friction_factor

native = pytest.importorskip("wearjoint.validation.exudyn_native")
import exudyn as exu  # noqa: E402
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D,
)

PIN = JointParameters(wear_factor=0.0)      # pin centre at the body's node, bushing centre at the origin
MASS = 1.0                                  # kg


# ---------------------------------------------------------------- the mapping
@pytest.mark.parametrize("restitution", [0.3, 0.6, 0.9, 1.0])
def test_exudyns_restitution_gives_our_laws_coefficient(restitution):
    """exudyn's impactModel 1: lambda = K/delta_dot^- * 3/2 (e_x - 1), i.e. F = K delta^n (1 + 3/2 (1 - e_x)
    delta_dot/delta_dot^-): 3/2 (1 - e_x) is Hunt-Crossley's exact a(e_r), the root of -a e - ln(1 - a e) =
    a - ln(1 + a) (checked here by its residual), floored at v_r; Eq. (15)'s 3/4 (1 - e_r^2) for the paper's law."""
    args = native.native_contact_parameters(PIN.replace(restitution=restitution))
    assert args["impactModel"] == native.HUNT_CROSSLEY and args["contactDamping"] == 0.0
    a, e = 1.5 * (1.0 - args["restitutionCoefficient"]), restitution
    assert abs(a - np.log1p(a) + a * e + np.log1p(-a * e)) < 1e-12 and (a > 0.0) == (e < 1.0)
    assert args["minimumImpactVelocity"] == PIN.restitution_speed_m_s          # our default, Hunt-Crossley's v_r
    literal = native.native_contact_parameters(PIN.replace(contact_damping="lankarani-nikravesh",
                                                           restitution=restitution))
    assert 1.5 * (1.0 - literal["restitutionCoefficient"]) == pytest.approx(0.75 * (1.0 - restitution ** 2),
                                                                            abs=1e-15)
    assert literal["minimumImpactVelocity"] == PIN.impact_velocity_floor_m_s


def test_proportional_zone_is_the_closest_to_ambrosios_ramp():
    """exudyn's friction factor min(1, v/v_reg) against Ambrosio's c_d(v): v_reg has his mean deficit,
    the integral of 1 - c_d over v, and no other v_reg has a smaller largest difference."""
    v_reg = native.native_contact_parameters(PIN)["frictionProportionalZone"]
    v = np.linspace(0.0, 0.05, 200001)
    ambrosio = np.array([ambrosio_friction_factor(x, PIN.friction_v0_m_s, PIN.friction_v1_m_s) for x in v])

    def largest_difference(zone):
        return np.abs(np.minimum(1.0, v / zone) - ambrosio).max()

    assert np.trapezoid(1.0 - np.minimum(1.0, v / v_reg), v) == pytest.approx(np.trapezoid(1.0 - ambrosio, v),
                                                                              rel=1e-6)
    others = np.linspace(0.5 * v_reg, 2.0 * v_reg, 301)
    assert largest_difference(v_reg) <= min(largest_difference(z) for z in others) + 1e-9


def test_native_contact_refuses_wear_and_keeps_the_hollow_sphere_on_the_bushing():
    args = native.native_contact_parameters(PIN)
    assert args["isHollowSphere1"] and args["spheresRadii"] == [PIN.pin_radius_m, PIN.bushing_radius_m]
    system = exu.SystemContainer()
    mbs = system.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    body = mbs.AddObject(ObjectRigidBody2D(mass=1.0, inertia=1.0, nodeNumber=mbs.AddNode(NodeRigidBody2D())))
    with pytest.raises(ParameterError, match="cannot wear"):
        native.NativeContact(mbs, body, ground, PIN.replace(wear_factor=1.0))
    with pytest.raises(ParameterError, match="pin_body"):
        native.NativeContact(mbs, 99, ground, PIN)


# ---------------------------------------------------------------- a pin in a bushing on ground
def _pin_in_ground_bushing(p, position, velocity, gravity, inertia=1.0):
    """A free body of MASS [kg] (its node at the pin centre) in a bushing fixed on ground at the
    origin; exudyn's own contact between them.  Returns (system, mbs, contact)."""
    system = exu.SystemContainer()
    mbs = system.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=list(position), initialVelocities=list(velocity)))
    body = mbs.AddObject(ObjectRigidBody2D(mass=MASS, inertia=inertia, nodeNumber=node))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                     loadVector=[0.0, -gravity, 0.0]))
    contact = native.NativeContact(mbs, body, ground, p)
    mbs.Assemble()
    return system, mbs, contact


def _solve(mbs, end_s, step_s, post_step=None):
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = end_s
    settings.timeIntegration.numberOfSteps = int(round(end_s / step_s))
    settings.timeIntegration.verboseMode = 0
    settings.timeIntegration.discontinuous.useRecommendedStepSize = False   # as the slider-crank (exudyn_model)
    settings.solution.file.write = False
    settings.solution.sensors.active = False
    if post_step is not None:
        mbs.SetPostStepUserFunction(post_step)
    exu.SolveDynamic(mbs, settings)


def test_resting_pin_carries_its_weight_at_the_hertz_penetration():
    """A 1 kg pin let go at the bottom of the clearance settles where K delta^n = m g: the force on
    it is its weight, upwards, and the bushing feels the opposite.  With the Lankarani-Nikravesh mapping
    (its 1 mm/s floor damps the micro-bounce within 2 ms; Hunt-Crossley's v_r = 50 mm/s leaves damping
    ratio 0.002 there, still ringing after the 0.1 s simulated)."""
    g = 9.81
    system, mbs, contact = _pin_in_ground_bushing(PIN.replace(contact_damping="lankarani-nikravesh"),
                                                  (0.0, -PIN.clearance_m, 0.0), (0.0, 0.0, 0.0), g)
    _solve(mbs, 0.1, 1e-5)
    r = contact.read(mbs, np.zeros(L.N_RESULT))
    system.Reset()
    weight = MASS * g
    assert r[L.R_CONTACT] == 1.0 and r[L.R_NORMAL_FORCE] == pytest.approx(weight, rel=1e-6)
    np.testing.assert_allclose(r[[L.R_PIN_FX, L.R_PIN_FY]], [0.0, weight], atol=1e-6 * weight)
    np.testing.assert_allclose(r[[L.R_BUSHING_FX, L.R_BUSHING_FY]], [0.0, -weight], atol=1e-6 * weight)
    static = (weight / PIN.stiffness_N_m1_5) ** (1.0 / PIN.contact_exponent)
    assert r[L.R_PENETRATION] == pytest.approx(static, rel=1e-5)
    np.testing.assert_allclose(r[[L.R_ECCENTRICITY_X, L.R_ECCENTRICITY_Y]], [0.0, -(PIN.clearance_m + static)],
                               atol=1e-3 * static)


def _impact_peak_force(p, v0, mass):
    """Closed form: the largest normal force of a mass ``mass`` [kg] hitting the wall at v0 [m/s] with
    F = K delta^n (1 + chi u/v0), chi = 3/2 (1 - e_x) of the restitution exudyn is given, u = delta_dot.  Energy along the compression,
    m u du / (1 + chi u/v0) = -K delta^n d delta, integrates to
    K delta(u)^(n+1)/(n+1) = m v0^2 [chi (1 - u/v0) - ln((1 + chi)/(1 + chi u/v0))] / chi^2;
    undamped (chi -> 0): delta_max = ((n+1) m v0^2 / (2K))^(1/(n+1)) = (5 m v0^2/(4K))^(2/5), F_max = K delta_max^n.
    LN's damping lowers delta_max by [2 (chi - ln(1 + chi))/chi^2]^(1/(n+1)) (0.959 at e_r = 0.9) and moves the
    peak before delta_max, to the largest K delta(u)^n (1 + chi u/v0) over 0 <= u <= v0 (taken on a fine grid)."""
    k, n = p.stiffness_N_m1_5, p.contact_exponent
    chi = 1.5 * (1.0 - native.native_contact_parameters(p)["restitutionCoefficient"])
    if chi == 0.0:
        return k * ((n + 1.0) * mass * v0 ** 2 / (2.0 * k)) ** (n / (n + 1.0))
    u = np.linspace(0.0, v0, 100001)
    energy = mass * v0 ** 2 * (chi * (1.0 - u / v0) - np.log((1.0 + chi) / (1.0 + chi * u / v0))) / chi ** 2
    delta = ((n + 1.0) * energy / k) ** (1.0 / (n + 1.0))
    return float((k * delta ** n * (1.0 + chi * u / v0)).max())


@pytest.mark.parametrize("restitution", [1.0, 0.9])
def test_dropped_pin_first_impact_peaks_at_the_hertz_lankarani_nikravesh_closed_form(restitution):
    """A pin flying at v0 = 0.2 m/s (no gravity, no tangential speed, so no friction) from the bushing
    centre onto the wall: the peak force of its first impact is the closed form's (3798 N undamped, 5.1 %
    less at e_r = 0.9; measured 4e-5 off at 1 us steps over the ~190 us impact, 1e-5 at 0.5 us)."""
    p = PIN.replace(restitution=restitution)
    v0 = 0.2
    system, mbs, contact = _pin_in_ground_bushing(p, (0.0, 0.0, 0.0), (0.0, -v0, 0.0), 0.0)
    out, peak, speed = np.zeros(L.N_RESULT), [0.0], []

    def post_step(mbs_, t):
        peak[0] = max(peak[0], contact.read(mbs_, out)[L.R_NORMAL_FORCE])
        speed.append(mbs_.systemData.GetODE2Coordinates_t()[1])
        return True

    _solve(mbs, 0.8e-3, 1e-6, post_step)
    system.Reset()
    assert peak[0] == pytest.approx(_impact_peak_force(p, v0, MASS), rel=2e-4)
    assert speed[-1] > 0.0                                              # it bounced
    if restitution == 1.0:
        assert speed[-1] == pytest.approx(v0, rel=1e-4)                 # no loss but generalized-alpha's


@pytest.mark.parametrize("slip_per_zone", [10.0, 0.5])
def test_spinning_pin_rests_at_its_friction_angle(slip_per_zone):
    """A pin spinning at omega (slip omega R_i) resting in the bushing under its weight sits off the bottom
    where friction balances: tan phi = F_T/F_N, mu when sliding (slip >> v_reg), mu slip/v_reg in exudyn's
    proportional zone; started there, it stays, carrying its weight."""
    g, mu = 9.81, PIN.friction_coefficient
    v_reg = native.native_contact_parameters(PIN)["frictionProportionalZone"]
    slip = slip_per_zone * v_reg
    ratio = mu * min(1.0, slip / v_reg)
    phi = math.atan(ratio)
    delta = (MASS * g * math.cos(phi) / PIN.stiffness_N_m1_5) ** (1.0 / PIN.contact_exponent)
    e = PIN.clearance_m + delta
    omega = slip / PIN.pin_radius_m                   # counter-clockwise: the contact slides to +x, friction to -x
    position = (-e * math.sin(phi), -e * math.cos(phi), 0.0)
    system, mbs, contact = _pin_in_ground_bushing(PIN, position, (0.0, 0.0, omega), g, inertia=100.0)
    _solve(mbs, 0.02, 1e-5)
    r = contact.read(mbs, np.zeros(L.N_RESULT))
    system.Reset()
    assert r[L.R_CONTACT] == 1.0
    assert -r[L.R_FRICTION_FORCE] / r[L.R_NORMAL_FORCE] == pytest.approx(ratio, rel=1e-4)
    np.testing.assert_allclose(r[[L.R_PIN_FX, L.R_PIN_FY]], [0.0, MASS * g], atol=1e-4 * MASS * g)
    angle = math.atan2(-r[L.R_ECCENTRICITY_X], -r[L.R_ECCENTRICITY_Y])
    assert angle == pytest.approx(phi, rel=1e-3)
