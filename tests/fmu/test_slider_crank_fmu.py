"""The native SliderCrank FMU: the paper's slider-crank with the crank-rod joint open (Eqs. 38-44),
built from the mechanism kernels of the monolithic engine (docs/reference/fmu.md §5.x).

References are independent of the FMU: the ideal slider-crank's closed form (slider
x3 = l1 cos th1 + sqrt(l2^2 - l1^2 sin^2 th1), its derivatives) and the ideal mechanism of
:mod:`wearjoint.core.slider_crank` (the crank-rod revolute as a constraint, whose Lagrange
multipliers give the joint's reaction loads fed to the FMU).
"""
from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import simulate_fmu  # noqa: E402
from fmpy.fmi2 import POINTER, FMU2Model, fmi2Real  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402
from fmi_host import run_c_host  # noqa: E402
from slider_crank_fmu import (  # noqa: E402
    INPUT_VRS, MECHANISM, OUTPUTS, STATE_VRS, initialised, initialised_slave, slider_crank_fmus, smooth_loads,
    start_script,
)

from wearjoint.core import layout as L  # noqa: E402
from wearjoint.core.slider_crank import accelerations  # noqa: E402
from wearjoint.fmu import slider_crank as sc  # noqa: E402
from wearjoint.fmu import variables as fv  # noqa: E402
from wearjoint.slider_crank import SliderCrank  # noqa: E402
from wearjoint.mechanism_parameters import SliderForceTable  # noqa: E402
from wearjoint.parameters import SliderCrankParameters  # noqa: E402


# ------------------------------------------------------------------ fixtures and helpers
@pytest.fixture(scope="module")
def fmus(shared_build, tmp_path_factory):
    return slider_crank_fmus(shared_build, tmp_path_factory)


def ideal_loads(t, y, mechanism=MECHANISM, slider_input=0.0):
    """The FMU's inputs that hold the ideal crank-rod revolute: its loads on the crank and the rod at (t, y) (-C^T
    lambda of its two rows, Eq. 44 with the joint as a constraint) and the slider's input load ``slider_input``;
    and the ideal mechanism's accelerations."""
    qdd = np.empty(L.N_COORDINATES)
    ws = mechanism.workspace
    mp = mechanism.parameter_vector.copy()
    mp[L.MP_SLIDER_FORCE_INPUT] = slider_input
    accelerations(t, y[:L.N_COORDINATES], y[L.N_COORDINATES:], mp, True, np.zeros(6), ws, qdd)
    jac, lam = ws[0], ws[3]                     # the multipliers of all nine rows, in order
    loads = np.array([-(jac[7, c] * lam[7] + jac[8, c] * lam[8])
                      for c in (*range(L.CRANK, L.CRANK + 3), *range(L.ROD, L.ROD + 3))] + [slider_input])
    return loads, qdd


def _fed_the_ideal_joint(fmu, h, stop):
    """The CS FMU over [0, stop] in steps h, fed at each step the ideal joint's loads at its own
    state (held over the step); the largest slider errors against the closed form."""
    slave = initialised_slave(fmu)
    errors = np.zeros(3)
    t = 0.0
    for i in range(int(round(stop / h))):
        y = np.array(slave.getReal(STATE_VRS))
        slave.setReal(INPUT_VRS, list(ideal_loads(t, y)[0]))
        slave.doStep(t, h)
        t = (i + 1) * h
        got = slave.getReal([sc.VALUE_REFERENCES[n] for n in ("slider_x", "slider_v", "slider_a")])
        exact = MECHANISM.closed_form(t)
        errors = np.maximum(errors, np.abs(np.array(got) - [exact["slider_x_m"], exact["slider_v_m_s"],
                                                            exact["slider_a_m_s2"]]))
    slave.terminate()
    slave.freeInstance()
    return errors


# ------------------------------------------------------------------ the model

def _continuous_time_model(fmu, parameters=None) -> "FMU2Model":
    """An initialised FMI 2.0 Model Exchange instance of the SliderCrank FMU ``fmu`` with ``parameters``, in
    Continuous-Time Mode."""
    model = initialised(FMU2Model, fmu, parameters, "me")
    model.newDiscreteStates()
    model.enterContinuousTimeMode()
    return model


def test_fmu_validates_and_declares_the_joint_fmus_counterparts(fmus):
    """Both versions validate; the inputs are the joint FMU's force outputs, the slider's load and the joint FMU's
    normal force and linearisation outputs (load_coupling 1), the outputs
    include its 12 kinematic inputs, every scalar SliderCrankParameters field is a parameter with its default
    (gravity's two components; the load table's rows 0)."""
    for version, fmu in fmus.items():
        assert validate_fmu(str(fmu["path"])) == [], version
        md = fmu["md"]
        variables = {v.name: v for v in md.modelVariables}
        assert [v.name for v in md.modelVariables if v.causality == "input"] == \
            [v.name for v in fv.SCALAR_OUTPUTS[:6]] + ["slider_force", "normal_force"] + \
            [v.name for v in fv.LINEARISATION_OUTPUTS]
        assert {v.name for v in fv.INPUTS} <= {v.name for v in md.modelVariables if v.causality == "output"}
        defaults = SliderCrankParameters()
        for field in dataclasses.fields(SliderCrankParameters):
            if field.name == "slider_force_table":
                assert float(variables["slider_force_table_rows"].start) == 0.0
                continue
            name = {"slider_force_N": "slider_force_constant"}.get(field.name,
                                                                   re.sub(r"_(m|kg|kg_m2|rpm|deg|m_s2)$", "", field.name))
            default = getattr(defaults, field.name)
            if isinstance(default, tuple):
                assert [float(variables[f"{name}_{axis}"].start) for axis in "xy"] == list(default), name
            elif field.name == "clearance_joint":            # an enumeration's index
                assert L.CLEARANCE_JOINTS[int(float(variables[name].start))] == default
            else:
                assert float(variables[name].start) == default, name
        assert md.coSimulation is not None and md.modelExchange is not None
        assert len(md.derivatives) == 2 * L.N_COORDINATES
        # the rules' bounds as min/max (an open bound as its limit), none where a rule has none
        bounds = {name: (variables[name].min, variables[name].max) for name in
                  ("crank_length", "clearance_joint", "slider_force_table_rows", "slider_force_table_angle_1",
                   "gravity_y", "initial_crank_angle")}
        assert bounds == {"crank_length": ("1e-06", "100.0"), "clearance_joint": ("0.0", "2.0"),
                          "slider_force_table_rows": ("0.0", "361.0"), "slider_force_table_angle_1": ("0.0", "360.0"),
                          "gravity_y": ("-10000.0", "10000.0"), "initial_crank_angle": (None, None)}, (version, bounds)


def test_fed_the_ideal_joint_reaction_the_derivatives_are_the_ideal_mechanisms(fmus):
    """Model Exchange at states near the ideal motion (off its constraints, where Baumgarte acts), the
    inputs the ideal joint's reaction there: the FMU's derivatives are the velocities and the ideal
    mechanism's accelerations."""
    fmu = fmus[2]
    model = _continuous_time_model(fmu)
    rng = np.random.default_rng(3)
    y0 = MECHANISM.initial_state()
    for t in np.linspace(0.0, 0.4, 9):
        y = y0.copy()
        y[:L.N_COORDINATES] += 1e-4 * rng.normal(size=L.N_COORDINATES)
        y[L.N_COORDINATES:] += 1e-2 * rng.normal(size=L.N_COORDINATES)
        loads, qdd = ideal_loads(t, y)
        model.setTime(t)
        model.setContinuousStates(y.ctypes.data_as(POINTER(fmi2Real)), y.size)
        model.setReal(INPUT_VRS, list(loads))
        dx = np.zeros(y.size)
        model.getDerivatives(dx.ctypes.data_as(POINTER(fmi2Real)), dx.size)
        assert np.array_equal(dx[:L.N_COORDINATES], y[L.N_COORDINATES:])
        np.testing.assert_allclose(dx[L.N_COORDINATES:], qdd, rtol=1e-9, atol=1e-9 * np.abs(qdd).max())
    model.terminate()
    model.freeInstance()


LOADED = SliderCrankParameters(slider_force_N=150.0, gravity_m_s2=(4.0, -9.0), slider_force_table=SliderForceTable(
    (0.0, 20.0, 40.0, 300.0, 360.0), (0.0, 1800.0, 200.0, -400.0, 0.0)))


def _loaded_parameters() -> dict:
    """The FMU parameters that make the default SliderCrank FMU :data:`LOADED`."""
    return sc.parameter_starts(LOADED)


def test_loaded_and_tilted_the_derivatives_are_the_ideal_mechanisms(fmus):
    """The slider's load (constant, table and input) and gravity in the plane reach the FMU: fed the reaction that
    the ideal revolute carries under them (and a slider input of 250 N), its Model Exchange derivatives are the
    ideal mechanism's accelerations; without the load parameters they are not."""
    loaded = SliderCrank(LOADED)
    y0 = loaded.initial_state()
    for version, parameters, matches in ((2, _loaded_parameters(), True), (2, {}, False)):
        model = FMU2Model(guid=fmus[version]["token"], unzipDirectory=str(fmus[version]["dir"]),
                          modelIdentifier=sc.MODEL_IDENTIFIER, instanceName="loaded")
        model.instantiate()
        model.setupExperiment(startTime=0.0)
        model.enterInitializationMode()
        for key, value in parameters.items():
            model.setReal([sc.VALUE_REFERENCES[key]], [value])
        model.exitInitializationMode()
        model.newDiscreteStates()
        model.enterContinuousTimeMode()
        errors = []
        for t in np.linspace(0.0, 0.4, 17):
            y = y0.copy()
            loads, qdd = ideal_loads(t, y, loaded, slider_input=250.0)
            model.setTime(t)
            model.setContinuousStates(y.ctypes.data_as(POINTER(fmi2Real)), y.size)
            model.setReal(INPUT_VRS, list(loads))
            dx = np.zeros(y.size)
            model.getDerivatives(dx.ctypes.data_as(POINTER(fmi2Real)), dx.size)
            errors.append(np.abs(dx[L.N_COORDINATES:] - qdd).max() / np.abs(qdd).max())
        model.terminate()
        model.freeInstance()
        assert (max(errors) < 1e-9) == matches, (matches, max(errors))


@pytest.mark.parametrize("changes, row, problem", [
    ({"slider_force_table_angle_3": 10.0}, 3, "the crank angle does not rise"),
    ({"slider_force_table_force_5": 5.0}, 5, "the load at 360 deg differs"),
    ({"slider_force_table_rows": 4.0}, 4, "the last row is not at 360 deg"),
    ({"slider_force_table_rows": 2.5}, None, "slider_force_table_rows=2.5 is invalid: allowed a whole number of rows "
                                             "from 2 to 361 (0: no table)"),
])
def test_a_bad_load_table_fails_initialisation_naming_the_row(fmus, c_host, fmi3_host, changes, row, problem):
    """A table SliderForceTable refuses is refused by the FMU at exitInitializationMode, in one line naming the
    row and the problem (the same words), FMI 2.0 and 3.0."""
    parameters = {**_loaded_parameters(), **changes}
    for version, host in ((2, c_host), (3, fmi3_host)):
        fmu = fmus[version]
        script = start_script(version, parameters) + "expect error\nfree\n"
        code, out, err = run_c_host(host, fmu["dir"], sc.MODEL_IDENTIFIER, fmu["token"], script)
        assert code == 0, err
        where = f", row {row}" if row else ""
        assert f"fmi{version}ExitInitializationMode: slider-load table{where}: " in err and problem in err, err
        assert "exit_init error" in out


def test_fed_the_ideal_joint_reaction_it_follows_the_ideal_slider_crank_closed_form(fmus):
    """Co-Simulation, fed at each communication step the ideal joint's reaction at its own state
    (held over the step): the slider follows x3 = l1 cos th1 + sqrt(l2^2 - l1^2 sin^2 th1), its
    velocity and acceleration, to an error first order in the step (zero-order hold)."""
    errors = {h: _fed_the_ideal_joint(fmus[2], h, 0.2) for h in (2e-4, 1e-4, 5e-5)}
    for coarse, fine in ((2e-4, 1e-4), (1e-4, 5e-5)):
        ratio = errors[coarse] / errors[fine]
        assert np.all((ratio > 1.8) & (ratio < 2.2)), (coarse, ratio)
    stroke = 2 * MECHANISM.params.crank_length_m
    assert errors[5e-5][0] < 1e-3 * stroke                     # metres
    assert errors[5e-5][1] < 1e-3 * stroke * MECHANISM.params.omega_rad_s
    assert errors[5e-5][2] < 1e-2 * stroke * MECHANISM.params.omega_rad_s ** 2


def test_co_simulation_converges_with_its_internal_rk4_step(fmus):
    """One communication step of 0.02 s with constant loads: the internal RK4 steps' error falls
    with the fourth power of max_internal_step (against 1e-6 s)."""
    def state_after(step):
        slave = initialised_slave(fmus[2], {sc.MAX_INTERNAL_STEP_NAME: step})
        slave.setReal(INPUT_VRS, list(smooth_loads(0.01)))
        slave.doStep(0.0, 0.02)
        y = np.array(slave.getReal(STATE_VRS))
        slave.terminate()
        slave.freeInstance()
        return y

    reference = state_after(1e-6)
    errors = [np.abs(state_after(step) - reference).max() for step in (4e-3, 2e-3, 1e-3)]
    assert errors[0] > errors[1] > errors[2] > 0
    assert 10 < errors[0] / errors[1] < 24 and 10 < errors[1] / errors[2] < 24, errors


def test_model_exchange_under_fmpys_cvode_equals_co_simulation(fmus):
    """fmpy.simulate_fmu with its own solver (CVode, rtol 1e-10) through Model Exchange equals the
    Co-Simulation interface (RK4, 1e-5 s) under the same constant loads, to the solver's
    tolerance, over 0.1 s."""
    loads = smooth_loads(0.02)
    signals = np.array([(0.0, *loads), (1.0, *loads)],
                       dtype=[("time", float), *((v.name, float) for v in sc.LOAD_INPUTS)])
    common = dict(stop_time=0.1, output_interval=1e-3, input=signals, output=OUTPUTS)
    for version, fmu in fmus.items():
        cs = simulate_fmu(str(fmu["path"]), fmi_type="CoSimulation", **common)
        me = simulate_fmu(str(fmu["path"]), fmi_type="ModelExchange", solver="CVode", relative_tolerance=1e-10,
                          **common)
        assert np.array_equal(cs["time"], me["time"])
        for name in OUTPUTS:
            scale = max(np.ptp(cs[name]), 1e-12)
            assert np.abs(me[name] - cs[name]).max() < 1e-6 * scale, (version, name)


def _declared_input_dependencies(md) -> dict[str, set[str]]:
    """{unknown: the inputs its ModelStructure declares it depends on} over the outputs and derivatives."""
    return {u.variable.name: {d.name for d in u.dependencies if d.causality == "input"}
            for u in (*md.outputs, *md.derivatives)}


def test_model_structure_declares_the_feed_through_finite_differences_show(fmus):
    """Every output and derivative declares its dependencies (none absent: absent means "on every known", an
    algebraic loop for a master closing the joint around it); FMI 2.0 and 3.0 declare the same ones, for any
    clearance_joint (a parameter).  Model Exchange at a generic state (30 ms into a run), with the clearance at
    each joint in turn, each input moved by 1 N (N m): an unknown declared independent of an input moves by
    round-off at most (the crank's angular acceleration follows from its drive alone, the slider's across the
    slide and in rotation from its guide), one declared dependent moves by more than 1e-3 of its unit at one
    joint at least."""
    declared = {version: _declared_input_dependencies(fmu["md"]) for version, fmu in fmus.items()}
    assert declared[2] == declared[3]
    for version, fmu in fmus.items():
        assert all(u.dependencies is not None for u in (*fmu["md"].outputs, *fmu["md"].derivatives,
                                                         *fmu["md"].initialUnknowns)), version
    state_outputs = {v.name for v in (*sc.POSITIONS, *sc.VELOCITIES, *sc.JOINT_KINEMATICS)
                     if v.causality == fv.OUTPUT}
    assert all(declared[2][name] == set() for name in state_outputs)
    assert declared[2]["slider_a"]      # the acceleration feeds through
    unknowns = sorted(declared[2])
    vrs = [sc.VALUE_REFERENCES[name] for name in unknowns]
    moved_somewhere = {name: set() for name in unknowns}
    for location in range(len(L.CLEARANCE_JOINTS)):
        slave = initialised_slave(fmus[2], {"clearance_joint": float(location)})
        for i in range(30):
            slave.doStep(i * 1e-3, 1e-3)
        y = slave.getReal(STATE_VRS)
        slave.terminate()
        slave.freeInstance()
        model = _continuous_time_model(fmus[2], {"clearance_joint": float(location)})
        model.setTime(0.03)
        model.setContinuousStates((fmi2Real * len(y))(*y), len(y))
        base = list(smooth_loads(0.03))
        model.setReal(INPUT_VRS, base)
        before = np.array(model.getReal(vrs))
        for k, v in enumerate(sc.LOAD_INPUTS):     # the linearisation's inputs act in doStep alone
            moved = list(base)
            moved[k] += 1.0
            model.setReal(INPUT_VRS, moved)
            change = np.abs(np.array(model.getReal(vrs)) - before)
            for name, delta in zip(unknowns, change):
                if v.name not in declared[2][name]:
                    assert delta < 1e-9, (location, name, v.name, delta)
                elif delta > 1e-3:
                    moved_somewhere[name].add(v.name)
        model.terminate()
        model.freeInstance()
    assert moved_somewhere == {name: declared[2][name] for name in unknowns}


def test_the_initial_state_declares_the_parameters_finite_differences_show(fmus):
    """At initialisation (InitialUnknowns) the positions, velocities and the joint's kinematics declare the
    parameters that assemble the mechanism; with a three-row slider-load table on, every other parameter (the
    masses, gravity, the loads, the table's second row, the internal step, the coupling) moved leaves them
    unchanged to the bit, and each declared one moves one of them by more than 1e-9 of its unit."""
    declared = {u.variable.name: {d.name for d in u.dependencies} for u in fmus[2]["md"].initialUnknowns}
    accelerations = {a.name for a in sc.ACCELERATIONS}
    assembled = sorted(name for name in declared if name not in accelerations)
    assert len(assembled) == 30 and {frozenset(declared[name]) for name in assembled} == {frozenset(
        declared[assembled[0]])}
    vrs = [sc.VALUE_REFERENCES[name] for name in assembled]
    table = {"slider_force_table_rows": 3.0, "slider_force_table_angle_1": 0.0, "slider_force_table_angle_2": 180.0,
             "slider_force_table_angle_3": 360.0, "slider_force_table_force_1": 100.0,
             "slider_force_table_force_2": -50.0, "slider_force_table_force_3": 100.0}

    def initial_values(changes):
        slave = initialised_slave(fmus[2], {**table, **changes})
        values = np.array(slave.getReal(vrs))
        slave.terminate()
        slave.freeInstance()
        return values

    before = initial_values({})
    moving = set()
    for p in sc.PARAMETERS:
        if (p.name.startswith("slider_force_table_") and p.name not in table) or p.name.endswith(("_1", "_3")):
            continue        # rows the table does not use; its first and last rows are fixed at 0 and 360 deg
        value = table.get(p.name, p.start)
        if p.name == "slider_force_table_rows":
            moved = 0.0
        elif p.choices:
            moved = float((int(value) + 1) % len(p.choices))
        else:
            moved = 1.1 * value + 0.1
        change = np.abs(initial_values({p.name: moved}) - before).max()
        if p.name in declared[assembled[0]]:
            assert change > 1e-9, (p.name, change)
            moving.add(p.name)
        else:
            assert change == 0.0, (p.name, change)
    assert moving == declared[assembled[0]]
