"""The linearised coupling (scheme ``linearised``): the loads in contact F0 + J (u - u0) through the master's step,
F0 and J the joint FMU's at the step's start; the FMU takes forces and derivatives in one pass for a host that reads
both, with the same forces."""
import ctypes

import numpy as np

from wearjoint import analysis
from wearjoint.core import layout as L
from wearjoint.core.jit import kernel
from wearjoint.core.linearisation import linearised_loads
from wearjoint.core.joint_location import joint_kinematics
from wearjoint.cosim import CoSimulation, CoSimulationOptions, run_cosimulation
from wearjoint.cosim.master_layout import B_OUTPUT, O_CONTACT
from wearjoint.parameters import SliderCrankParameters, paper_joint
from wearjoint.simulate import SimulationOptions, run_simulation
from wearjoint.slider_crank import SliderCrank

NO_WEAR = paper_joint(wear_factor=0.0)
WINDOW_S = 0.015
PERIOD_S = SliderCrankParameters().period_s


@kernel
def _loads(linearisation, y, mp, body_forces):
    linearised_loads(linearisation, y, mp, body_forces)


def _linearisation(rng, u0, normal0):
    lin = np.zeros(L.N_LINEARISATION)
    lin[L.LIN_INPUTS:L.LIN_INPUTS + 12] = u0
    lin[L.LIN_LOADS:L.LIN_LOADS + 6] = rng.normal(0.0, 100.0, 6)
    lin[L.LIN_LOADS + 6] = normal0
    lin[L.LIN_JACOBIAN:L.LIN_SCRATCH] = rng.normal(0.0, 1e5, 7 * 12)
    return lin


def test_the_loads_are_f0_plus_j_times_the_change_of_the_joints_kinematics():
    rng = np.random.default_rng(3)
    mechanism = SliderCrank()
    mp = mechanism.parameter_vector
    y0 = mechanism.initial_state()
    y = y0 + rng.normal(0.0, 1e-6, y0.size)
    u0, u = np.zeros(12), np.zeros(12)
    joint_kinematics(y0, mp, u0)
    joint_kinematics(y, mp, u)
    lin = _linearisation(rng, u0, normal0=500.0)
    jacobian = lin[L.LIN_JACOBIAN:L.LIN_SCRATCH].reshape(7, 12)
    expected = lin[L.LIN_LOADS:L.LIN_LOADS + 7] + jacobian @ (u - u0)
    assert expected[6] > 0.0
    forces = np.full(6, np.nan)
    _loads(lin, y, mp, forces)
    np.testing.assert_allclose(forces, expected[:6], rtol=1e-12, atol=1e-9)
    _loads(lin, y0, mp, forces)                        # at u0: F0 exactly
    assert np.array_equal(forces, lin[L.LIN_LOADS:L.LIN_LOADS + 6])


def test_no_loads_where_the_linear_normal_force_has_reached_zero():
    """The contact ends within the step: the linearisation does not pull the pin back."""
    rng = np.random.default_rng(4)
    mechanism = SliderCrank()
    mp = mechanism.parameter_vector
    y = mechanism.initial_state()
    u = np.zeros(12)
    joint_kinematics(y, mp, u)
    lin = _linearisation(rng, u + 1e-6, normal0=0.0)
    row = lin[L.LIN_JACOBIAN + 6 * 12:L.LIN_SCRATCH]
    normal = lin[L.LIN_LOADS + 6] + row @ (-1e-6 * np.ones(12))
    lin[L.LIN_LOADS + 6] -= normal + 1.0             # the linear normal force at y: -1 N
    forces = np.full(6, np.nan)
    _loads(lin, y, mp, forces)
    assert np.array_equal(forces, np.zeros(6))


def test_the_linearised_scheme_reproduces_the_monolithic_run_over_the_first_15_ms(native_fmu):
    """As the other schemes (test_cosim.py: the scatter of valid monolithic runs plus the co-simulation's own step
    refinement), at twice their steps (fixed contact steps: the coupling itself, not its step control)."""
    rev = WINDOW_S / PERIOD_S
    rk4 = run_simulation(NO_WEAR, None, SimulationOptions(revolutions=rev, integrator="rk4", step_s=1e-6),
                         progress=False)
    others = [run_simulation(NO_WEAR, None, SimulationOptions(revolutions=rev, **options), progress=False)
              for options in ({"integrator": "dopri", "max_step_s": 1e-5}, {"integrator": "rk4", "step_s": 2e-6})]
    assert rk4.samples[:, L.T_CONTACT].any(), "the window must contain impacts"
    records = [run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=rev, scheme="linearised", step_s=step,
                                                                   coupling_tolerance=0.0),
                                fmu_path=native_fmu, progress=False) for step in (2e-6, 4e-6)]
    assert records[0].extra["coupling_controlled_steps"] > 0

    def deviation(record, reference):
        def path(r):
            return r.samples[:, L.T_TIME], r.samples[:, [L.T_ECC_X, L.T_ECC_Y, L.T_SLIDER_X]]
        t_ref, ref = path(reference)
        t, values = path(record)
        return np.max(np.abs(np.column_stack([np.interp(t_ref, t, values[:, k]) for k in range(3)]) - ref), axis=0)

    tolerance = np.max([deviation(other, rk4) for other in others], axis=0) + deviation(records[1], records[0])
    assert np.all(deviation(records[0], rk4) <= tolerance), (deviation(records[0], rk4), tolerance)


def test_reading_the_derivatives_leaves_the_fmus_forces_bit_identical(native_fmu):
    """The FMU evaluates forces and derivatives in one pass once a host reads derivatives: the same forces."""
    options = CoSimulationOptions(revolutions=0.05)
    plain, reading = CoSimulation(NO_WEAR, None, options, fmu_path=native_fmu), \
        CoSimulation(NO_WEAR, None, options, fmu_path=native_fmu)
    try:
        samples = np.zeros((20000, L.N_SAMPLE_COLUMNS))
        reached_contact = False
        for k in range(1, 200):
            t = k * 1e-4
            plain.advance_to(t, samples)
            reading.advance_to(t, samples)
            assert np.array_equal(plain.buf, reading.buf)
            # the reading instance's host reads the published derivatives at its current inputs, then the forces
            instance = reading._live_instance()
            vrs, values = reading._published
            assert instance.get_real(instance.component, vrs.ctypes.data_as(ctypes.POINTER(ctypes.c_uint)), vrs.size,
                                     values.ctypes.data_as(ctypes.POINTER(ctypes.c_double))) == 0
            reached_contact |= reading.buf[B_OUTPUT + O_CONTACT] > 0.5
        assert reached_contact
    finally:
        plain.close()
        reading.close()


def test_the_masters_40_derivatives_give_the_linearisation_of_all_60(native_fmu):
    """The master reads the published rows' columns layout.RELATIVE_COLUMNS; the linearisation it builds equals, bit
    for bit, the one from all 60 published derivatives (those along the bushing body's translation are minus the
    pin body's), at a point in contact."""
    from wearjoint.core.linearisation import linearisation_from_published
    from wearjoint.cosim.master_layout import B_INPUT, MASTER_DERIVATIVE_OUTPUTS, O_NORMAL_FORCE
    from wearjoint.fmu.variables import JACOBIAN_SLOTS

    assert len(MASTER_DERIVATIVE_OUTPUTS) == 40
    with CoSimulation(NO_WEAR, None, CoSimulationOptions(revolutions=0.05), fmu_path=native_fmu) as sim:
        samples = np.zeros((20000, L.N_SAMPLE_COLUMNS))
        t = 0.0
        while sim.buf[B_OUTPUT + O_CONTACT] < 0.5:
            t += 1e-5
            sim.advance_to(t, samples)
        instance = sim._live_instance()

        def read(names):
            vrs = np.array([instance.vr[name] for name in names], dtype=np.uint32)
            values = np.zeros(vrs.size)
            assert instance.get_real(instance.component, vrs.ctypes.data_as(ctypes.POINTER(ctypes.c_uint)), vrs.size,
                                     values.ctypes.data_as(ctypes.POINTER(ctypes.c_double))) == 0
            return values

        loads, normal, inputs = sim.buf[B_OUTPUT:B_OUTPUT + 6], sim.buf[B_OUTPUT + O_NORMAL_FORCE], \
            sim.buf[B_INPUT:B_INPUT + 12]
        every, relative = np.zeros(L.N_LINEARISATION), np.zeros(L.N_LINEARISATION)
        linearisation_from_published(loads, normal, read(tuple(JACOBIAN_SLOTS)), L.ALL_KINEMATIC_COLUMNS, inputs,
                                     every)
        linearisation_from_published(loads, normal, read(MASTER_DERIVATIVE_OUTPUTS), L.RELATIVE_COLUMNS, inputs,
                                     relative)
        assert np.any(every[L.LIN_JACOBIAN:L.LIN_SCRATCH] != 0.0)
        assert np.array_equal(every, relative)


def test_the_linearised_scheme_runs_on_either_backend_alike(native_fmu, built_fmu):
    """The pythonfmu backend publishes the same linearisation as the native one: through the first impacts the two
    runs of the linearised scheme agree to round-off."""
    options = CoSimulationOptions(revolutions=0.012, scheme="linearised", step_s=1e-5)
    runs = [run_cosimulation(NO_WEAR, None, options, fmu_path=path, progress=False) for path in (native_fmu, built_fmu)]
    assert runs[0].revolution_stats[0, L.S_IMPACTS] >= 1
    np.testing.assert_allclose(runs[1].samples, runs[0].samples, rtol=1e-9, atol=1e-12)


def test_an_fmu_that_publishes_no_derivatives_is_refused_for_the_linearised_scheme(native_fmu, monkeypatch):
    """An FMU without one of the published derivatives (one built before them) cannot run the linearised scheme:
    the error names the scheme and the missing output; the other schemes do not read them and still run."""
    import pytest

    from wearjoint.cosim import cosimulation
    from wearjoint.parameters import ParameterError

    monkeypatch.setattr(cosimulation, "MASTER_DERIVATIVE_OUTPUTS", ("d_pin_force_x_d_pin_x", "d_not_published"))
    with pytest.raises(ParameterError, match="scheme='linearised'.*d_not_published"):
        CoSimulation(paper_joint(wear_factor=0.0), None, CoSimulationOptions(revolutions=0.01), fmu_path=native_fmu)
    with CoSimulation(paper_joint(wear_factor=0.0), None, CoSimulationOptions(revolutions=0.01, scheme="adaptive"),
                      fmu_path=native_fmu) as adaptive:
        assert adaptive.options.step_s == 5e-6 and adaptive.options.coupling_tolerance == 0.0


def test_the_default_stays_closer_to_the_monolithic_path_over_the_first_impacts(native_fmu):
    """The paper's first 15 ms (its first five impacts, before the runs part) against RK4 at 1 us: the default (each
    contact from a quarter of its 10 us cap, tolerance 0.003) ends closer than the adaptive scheme at 5 us (4.6e-7
    against 1.4e-6 m); the looser tolerance 0.01 leaves the path (4.9e-6)."""
    rev = 0.015 / PERIOD_S
    rk4 = run_simulation(NO_WEAR, None, SimulationOptions(revolutions=rev, integrator="rk4", step_s=1e-6,
                                                          sample_dt_s=2.5e-7), progress=False)   # every step

    def distance(**options):
        r = run_cosimulation(NO_WEAR, None, CoSimulationOptions(revolutions=rev, **options), fmu_path=native_fmu,
                             progress=False)
        d = analysis.window_differences(r.samples, rk4.samples, 0.015, (L.T_ECC_X, L.T_ECC_Y))
        return np.max(np.hypot(d[:, 0], d[:, 1]))

    default, adaptive = distance(), distance(scheme="adaptive")
    assert default < 0.5 * adaptive and default < 1e-6
    assert distance(coupling_tolerance=0.01) > 4 * default
