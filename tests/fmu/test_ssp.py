"""SliderCrankWithClearance.ssp (wearjoint export-ssp): valid SSP 1.0, wired and parameterised as the
monolithic slider-crank; its container FMU valid and carrying fmpy's container binaries.  The
closed-loop runs in third-party masters: tests/cosim/test_masters.py."""
from __future__ import annotations

import zipfile
from pathlib import Path

import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import read_model_description  # noqa: E402
from fmpy.ssp.ssd import read_ssd  # noqa: E402
from lxml import etree  # noqa: E402

from wearjoint.cli import main  # noqa: E402
from wearjoint.fmu import ssp  # noqa: E402
from wearjoint.parameters import JointParameters, ParameterError, SliderCrankParameters, paper_joint  # noqa: E402


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    """The SSP and its container FMU as `wearjoint export-ssp --container-fmu` writes them (linux64
    binaries), the SSP unzipped."""
    out = tmp_path_factory.mktemp("ssp")
    assert main(["export-ssp", "--out", str(out), "--platforms", "linux64", "--container-fmu"]) == 0
    path = out / ssp.SSP_FILE_NAME
    unzipped = tmp_path_factory.mktemp("ssp_x")
    with zipfile.ZipFile(path) as zf:
        zf.extractall(unzipped)
    return path, unzipped


def test_the_ssp_validates_and_wires_every_joint_variable(package):
    """fmpy reads the SSD against the SSP 1.0 schema; every joint input comes from the mechanism output
    of the same name and unit, every mechanism input but the slider's load from the joint; both parameter sets are the
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
    assert connected == set(inputs) - {(ssp.MECHANISM, "slider_force")}   # open: a user's load FMU feeds it
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
    assert sets[ssp.JOINT]["contact_stiffness"] == 0.0      # from the radii and materials
    experiment = root.find("{%s}DefaultExperiment" % ssp.SSD)
    assert float(experiment.get("stopTime")) == mechanism.period_s
    assert sets[ssp.MECHANISM]["load_coupling"] == 1.0      # the mechanism integrates the published linearisation
    assert len(ssd.system.connections) == 12 + 6 + 1 + 72


def test_the_held_package_wires_the_loads_alone(tmp_path):
    """`export-ssp --load-coupling hold`: the 12 kinematic and 6 load connections, no connector for the joint's
    linearisation or the mechanism's linearisation inputs, the mechanism's load_coupling 0, the step 0.5 us."""
    assert main(["export-ssp", "--out", str(tmp_path), "--platforms", "linux64", "--load-coupling", "hold"]) == 0
    path = tmp_path / ssp.SSP_FILE_NAME
    ssd = read_ssd(str(path), validate=True)
    assert sorted(c.endConnector for c in ssd.system.connections if c.endElement == ssp.MECHANISM) == sorted(
        ["pin_force_x", "pin_force_y", "pin_torque", "bushing_force_x", "bushing_force_y", "bushing_torque"])
    assert len(ssd.system.connections) == 18
    connectors = {(e.name, c.name) for e in ssd.system.elements for c in e.connectors}
    assert not any(name.startswith(("d_", "evaluated_")) for _, name in connectors)
    with zipfile.ZipFile(path) as zf:
        mechanism = etree.fromstring(zf.read(f"resources/{ssp.MECHANISM}.ssv"))
        root = etree.fromstring(zf.read("SystemStructure.ssd"))
    coupling = [p for p in mechanism.iter("{%s}Parameter" % ssp.SSV) if p.get("name") == "load_coupling"]
    assert float(coupling[0][0].get("value")) == 0.0
    step = next(e for e in root.iter() if e.tag.endswith("FixedStepAlgorithm")).get("baseStepSize")
    assert float(step) == ssp.DEFAULT_STEP_S["hold"] == 0.5e-6


def _master_settings(root) -> dict:
    """What the SSD tells a master: OMSimulator's fixed step, result file, logging interval and signal
    filter, OSP's base step, the stop time."""
    q = lambda ns, tag: "{%s}%s" % (ns, tag)   # noqa: E731
    system, experiment = root.find(q(ssp.SSD, "System")), root.find(q(ssp.SSD, "DefaultExperiment"))
    first = lambda element: element.find(q(ssp.SSD, "Annotations"))[0]   # noqa: E731 (OMSimulator reads the first)
    assert first(system).get("type") == first(experiment).get("type") == ssp.OMS_TYPE
    master = first(system).find(f"{q(ssp.OMS, 'Annotations')}/{q(ssp.OMS, 'SimulationInformation')}/"
                                f"{q(ssp.OMS, 'FixedStepMaster')}")
    information = first(experiment).find(f"{q(ssp.OMS, 'Annotations')}/{q(ssp.OMS, 'SimulationInformation')}")
    osp = experiment.find(f"{q(ssp.SSD, 'Annotations')}/{q(ssp.SSC, 'Annotation')}[@type='{ssp.OSP_TYPE}']/"
                          f"{q(ssp.OSP, 'Algorithm')}/{q(ssp.OSP, 'FixedStepAlgorithm')}")
    return {"oms_step": float(master.get("stepSize")), "solver": master.get("description"),
            "osp_step": float(osp.get("baseStepSize")), "stop": float(experiment.get("stopTime")),
            "result": information.get("resultFile"), "interval": float(information.get("loggingInterval")),
            "filter": information.get("signalFilter")}


def test_the_ssd_carries_the_step_stop_time_and_recorded_signals(package, tmp_path):
    """OMSimulator's vendor annotations (the system's fixed-step master, first so that OMSimulator reads
    it; the default experiment's result file, logging interval and signal filter, a file in the
    package naming the recorded signals) and OSP's fixed-step algorithm hold the default steps of the linearised
    coupling, 10 us for OMSimulator (on time), 5 us for libcosim (one step late); export_ssp's step_s and stop_time
    change them; the SSD stays valid (fmpy reads it with the schema)."""
    path, unzipped = package
    settings = _master_settings(etree.parse(str(unzipped / "SystemStructure.ssd")).getroot())
    assert settings == {"oms_step": 1e-5, "solver": "oms-ma", "osp_step": 5e-6,
                        "stop": SliderCrankParameters().period_s, "result": ssp.RESULT_FILE,
                        "interval": ssp.RESULT_INTERVAL_S, "filter": ssp.SIGNAL_FILTER}
    signals = etree.parse(str(unzipped / ssp.SIGNAL_FILTER)).getroot()
    assert [v.get("name") for v in signals] == [f"{ssp.SSP_NAME}.{ssp.SSP_NAME}.{c}.{n}" for c, n in ssp.RECORDED]
    other = ssp.export_ssp(tmp_path, stop_time=0.8, step_s=5e-7, platforms="linux64")
    read_ssd(str(other), validate=True)
    with zipfile.ZipFile(other) as zf:
        settings = _master_settings(etree.fromstring(zf.read("SystemStructure.ssd")))
    assert (settings["oms_step"], settings["osp_step"], settings["stop"]) == (5e-7, 5e-7, 0.8)
    with pytest.raises(ParameterError, match="step_s"):
        ssp.export_ssp(tmp_path, step_s=0.0, platforms="linux64")


def test_a_joint_that_does_not_fit_the_mechanism_is_refused(tmp_path):
    with pytest.raises(ParameterError, match="pin_offset_m"):
        ssp.export_ssp(tmp_path, joint=JointParameters(), platforms="linux64")
    with pytest.raises(ParameterError, match="stop_time"):
        ssp.export_ssp(tmp_path, stop_time=0.0, platforms="linux64")
    # a step given past the wear-step limit (3e-5 s on the paper's joint, 5.5e-8 s at wear factor 1e5)
    with pytest.raises(ParameterError, match=r"step_s=0.001 is invalid with wear.*at most 3e-05 s"):
        ssp.export_ssp(tmp_path, step_s=1e-3, platforms="linux64")
    with pytest.raises(ParameterError, match=r"step_s=1e-06 is invalid with wear.*at most 5.52e-08 s"):
        ssp.export_ssp(tmp_path, joint=paper_joint(wear_factor=1e5), step_s=1e-6, platforms="linux64")
    assert not any(tmp_path.iterdir())


def test_the_default_step_of_a_fast_wearing_package_is_its_wear_step_limit(tmp_path):
    """At wear factor 1e5 the limit (5.52e-8 s) is below the measured 5 us: the package asks for the limit."""
    from wearjoint.simulation_options import wear_step_limit_s

    joint = paper_joint(wear_factor=1e5)
    with zipfile.ZipFile(ssp.export_ssp(tmp_path, joint=joint, platforms="linux64")) as zf:
        settings = _master_settings(etree.fromstring(zf.read("SystemStructure.ssd")))
    assert settings["oms_step"] == settings["osp_step"] == pytest.approx(wear_step_limit_s(joint), rel=1e-12)


@pytest.mark.parametrize("coupling, start", [("linearised", 1.0), ("hold", 0.0)])
def test_the_packaged_mechanism_fmu_starts_with_the_packages_coupling(tmp_path, coupling, start):
    """A master that applies no parameter set (fmpy's SSP simulator without parameters) runs SliderCrank.fmu's
    start values: its load_coupling is the package's, as in mechanism.ssv."""
    ssp.export_ssp(tmp_path, platforms="linux64", load_coupling=coupling)
    with zipfile.ZipFile(tmp_path / ssp.SSP_FILE_NAME) as zf:
        zf.extract("resources/SliderCrank.fmu", tmp_path)
    variables = read_model_description(str(tmp_path / "resources" / "SliderCrank.fmu")).modelVariables
    assert float(next(v.start for v in variables if v.name == "load_coupling")) == start


def test_the_container_fmu_validates_and_exposes_the_system(package):
    """The container FMU validates; it carries fmpy's container library for the platforms fmpy ships
    it for (not aarch64-linux, which the joint and mechanism FMUs also carry); every output of both
    FMUs is one of its outputs, every parameter one of its parameters with the package's value."""
    from fmpy.validation import validate_fmu

    path, unzipped = package
    container = path.with_name(ssp.CONTAINER_FILE_NAME)
    assert validate_fmu(str(container)) == []
    with zipfile.ZipFile(container) as zf:
        platforms = {name.split("/")[1] for name in zf.namelist()
                     if name.startswith("binaries/") and name.count("/") > 1}
    assert platforms == {"linux64", "win64", "darwin64"}
    md = read_model_description(str(container))
    variables = {v.name: v for v in md.modelVariables}
    for component in (ssp.MECHANISM, ssp.JOINT):
        inner = read_model_description(str(next((unzipped / "resources").glob(
            "SliderCrank.fmu" if component == ssp.MECHANISM else "ClearanceWearJoint.fmu"))))
        for v in inner.modelVariables:
            if v.causality in ("output", "parameter"):
                assert variables[ssp.container_variable(component, v.name)].causality == v.causality
    assert float(variables[ssp.container_variable(ssp.JOINT, "pin_offset_x")].start) == \
        0.5 * SliderCrankParameters().crank_length_m
