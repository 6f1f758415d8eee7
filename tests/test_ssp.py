"""SliderCrankWithClearance.ssp (wearjoint export-ssp): valid SSP 1.0, wired and parameterised as the
monolithic slider-crank, and run closed-loop by a third-party master, OSP libcosim, whose slider
converges to the monolithic engine's over the first impacts as its step shrinks (first order:
libcosim holds each FMU's inputs over a step)."""
from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("libcosimpy")
from fmpy import read_model_description  # noqa: E402
from fmpy.ssp.ssd import read_ssd  # noqa: E402
from libcosimpy.CosimExecution import CosimExecution  # noqa: E402
from lxml import etree  # noqa: E402
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level  # noqa: E402
from libcosimpy.CosimObserver import CosimObserver  # noqa: E402

from wearjoint.cli import main  # noqa: E402
from wearjoint.core import layout as L  # noqa: E402
from wearjoint.fmu import ssp  # noqa: E402
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters, paper_joint  # noqa: E402
from wearjoint.simulate import Simulation, SimulationOptions  # noqa: E402

WINDOW_S, SAMPLE_S = 6e-3, 1e-4      # free flight, then the first impacts (the first near 2-3 ms)


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    """The SSP as `wearjoint export-ssp` writes it (linux64 binaries: libcosim runs here), unzipped."""
    out = tmp_path_factory.mktemp("ssp")
    assert main(["export-ssp", "--out", str(out), "--platforms", "linux64"]) == 0
    path = out / ssp.SSP_FILE_NAME
    unzipped = tmp_path_factory.mktemp("ssp_x")
    with zipfile.ZipFile(path) as zf:
        zf.extractall(unzipped)
    return path, unzipped


def test_the_ssp_validates_and_wires_every_joint_variable(package):
    """fmpy reads the SSD against the SSP 1.0 schema; every joint input comes from the mechanism output
    of the same name and unit, every mechanism input from the joint; both parameter sets are the
    paper's, the joint's offsets the mechanism's."""
    path, unzipped = package
    ssd = read_ssd(str(path), validate=True)
    components = {c.name: c for c in ssd.system.elements}
    assert set(components) == {ssp.MECHANISM, ssp.JOINT}
    mds = {name: read_model_description(str(unzipped / c.source)) for name, c in components.items()}
    inputs = {(name, v.name): v for name, md in mds.items() for v in md.modelVariables if v.causality == "input"}
    outputs = {(name, v.name): v for name, md in mds.items() for v in md.modelVariables if v.causality == "output"}
    connected = set()
    for c in ssd.system.connections:
        start, end = outputs[(c.startElement, c.startConnector)], inputs[(c.endElement, c.endConnector)]
        assert start.unit == end.unit and c.startConnector == c.endConnector
        connected.add((c.endElement, c.endConnector))
    assert connected == set(inputs)
    root = etree.parse(str(unzipped / "SystemStructure.ssd")).getroot()
    units = {u.name for u in ssd.units}
    variables = {(name, v.name): v for name, md in mds.items() for v in md.modelVariables}
    for component in root.iter("{%s}Component" % ssp.SSD):
        for connector in component.iter("{%s}Connector" % ssp.SSD):
            real = connector.find("{%s}Real" % ssp.SSC)
            variable = variables[(component.get("name"), connector.get("name"))]
            if (component.get("name"), connector.get("name")) in {*inputs, *outputs}:
                assert real.get("unit") == variable.unit and real.get("unit") in units
    schema = etree.XMLSchema(file=str(Path(fmpy.ssp.ssd.__file__).parent / "schema"
                                      / "SystemStructureParameterValues.xsd"))
    sets = {}
    for name in components:
        parameter_set = etree.parse(str(unzipped / "resources" / f"{name}.ssv")).getroot()
        assert schema.validate(parameter_set), schema.error_log
        sets[name] = {p.get("name"): float(p[0].get("value")) for p in parameter_set.iter("{%s}Parameter" % ssp.SSV)}
    mechanism, joint = SliderCrankParameters(), paper_joint()
    assert sets[ssp.MECHANISM]["rod_length"] == mechanism.rod_length_m
    assert sets[ssp.MECHANISM]["crank_speed"] == mechanism.crank_speed_rpm
    assert sets[ssp.JOINT]["pin_offset_x"] == 0.5 * mechanism.crank_length_m == joint.pin_offset_m[0]
    assert sets[ssp.JOINT]["bushing_offset_x"] == -0.5 * mechanism.rod_length_m
    assert sets[ssp.JOINT]["contact_stiffness"] == JointParameters().contact_stiffness_N_m1_5
    experiment = root.find("{%s}DefaultExperiment" % ssp.SSD)
    assert float(experiment.get("stopTime")) == mechanism.period_s


def test_a_joint_that_does_not_fit_the_mechanism_is_refused(tmp_path):
    with pytest.raises(ParameterError, match="pin_offset_m"):
        ssp.export_ssp(tmp_path, joint=JointParameters(), platforms="linux64")
    with pytest.raises(ParameterError, match="stop_time"):
        ssp.export_ssp(tmp_path, stop_time=0.0, platforms="linux64")


def _libcosim(ssd: Path, step: float):
    """Slider x every SAMPLE_S over WINDOW_S through libcosim at ``step``; whether the joint was in contact."""
    log_output_level(CosimLogLevel.ERROR)
    execution = CosimExecution.from_ssp_file(str(ssd), step_size=round(step * 1e9))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index = {s.name.decode(): s.index for s in execution.slave_infos()}
    slider = {v.name.decode(): v.reference for v in execution.slave_variables(index[ssp.MECHANISM])}["slider_x"]
    contact = {v.name.decode(): v.reference for v in execution.slave_variables(index[ssp.JOINT])}["contact"]
    xs, touched = [], False
    for _ in range(round(WINDOW_S / SAMPLE_S)):
        for _ in range(round(SAMPLE_S / step)):
            assert execution.step(1)
            touched |= observer.last_real_values(index[ssp.JOINT], [contact])[0] > 0.5
        xs.append(observer.last_real_values(index[ssp.MECHANISM], [slider])[0])
    return np.array(xs), touched


def test_libcosim_runs_the_ssp_closed_loop_and_converges_to_the_monolithic_engine(package):
    """OSP libcosim runs the package (SystemStructure.ssd, its parameter sets applied) at 2, 1 and
    0.5 us; over the first impacts its slider approaches the monolithic engine's (DOPRI, tight
    tolerances) at first order in the step."""
    _, unzipped = package
    options = SimulationOptions(rtol=1e-9, atol_position_m=1e-12, atol_velocity_m_s=1e-8, max_step_s=1e-6)
    simulation = Simulation(options=options)
    samples = np.zeros((round(SAMPLE_S / options.sample_dt_s) + 10, L.N_SAMPLE_COLUMNS))
    reference = []
    for k in range(round(WINDOW_S / SAMPLE_S)):
        simulation.advance_to((k + 1) * SAMPLE_S, samples)
        reference.append(simulation.y[L.SLIDER])
    assert simulation.revolution_stats[0, L.S_IMPACTS] >= 1
    errors = {}
    for step in (2e-6, 1e-6, 5e-7):
        xs, touched = _libcosim(unzipped / "SystemStructure.ssd", step)
        assert touched
        errors[step] = np.abs(xs - reference).max()
    assert errors[2e-6] > errors[1e-6] > errors[5e-7]
    assert errors[2e-6] / errors[1e-6] > 1.6 and errors[1e-6] / errors[5e-7] > 1.6, errors
    assert errors[5e-7] < 1e-6    # m, of a 100 mm stroke
