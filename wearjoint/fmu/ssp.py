"""``SliderCrankWithClearance.ssp``: the paper's slider-crank as a system of two FMUs that any SSP
master runs (SSP 1.0: System Structure and Parameterization).

The package holds ``SystemStructure.ssd`` (the system: the ``mechanism`` component, a
``SliderCrank.fmu``, and the ``joint`` component, a ``ClearanceWearJoint.fmu``; every input and
output as a connector with its unit; the 12 kinematic connections mechanism -> joint, the 6
load connections joint -> mechanism and, with the mechanism linearising the loads over a step (``load_coupling``,
the default), the 73 of the joint's normal force and published linearisation; a default experiment of one crank
revolution; the communication step (:data:`DEFAULT_STEP_S`: 5 us linearised, 0.5 us held) in OMSimulator's and
OSP's vendor annotations, with OMSimulator's result file,
logging interval and signal filter ``resources/signalFilter.xml``: docs/how-to/run_in_omsimulator.md), the two FMUs
(native, FMI 2.0, every installed platform) and one parameter set per component
(``resources/<component>.ssv``): the paper's values, the joint's body-frame offsets those of the
slider-crank (:meth:`SliderCrankParameters.joint_offsets`).  The SSD and the parameter sets are
checked against the SSP 1.0 schemas fmpy ships before the package is written.
"""
from __future__ import annotations

import math
import tempfile
import uuid
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

from ..parameters import (
    JointParameters, SliderCrankParameters, finite, require, check_joint_fits_mechanism, paper_joint,
)
from . import slider_crank as sc
from ..simulation_options import check_wear_step, wear_step_limit_s
from .build_common import replaced_whole
from . import variables as fv

SSP_NAME = "SliderCrankWithClearance"
SSP_FILE_NAME = f"{SSP_NAME}.ssp"
SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
FMU_TYPE = "application/x-fmu-sharedlibrary"
MECHANISM, JOINT = "mechanism", "joint"
PARAMETER_SET = "parameters"


def connections(load_coupling: str) -> list[tuple[str, str, str, str]]:
    """The package's connections (start element, start connector, end element, end connector): the kinematics to
    the joint, its loads to the mechanism and, ``load_coupling`` linearised, its normal force and published
    linearisation (the mechanism's slider_force input stays open: the parameters' load, or a load FMU the user
    connects)."""
    inputs = sc.INPUTS if load_coupling == "linearised" else sc.LOAD_INPUTS
    return ([(MECHANISM, name, JOINT, name) for name in sc.KINEMATIC_OUTPUTS]
            + [(JOINT, v.name, MECHANISM, v.name) for v in inputs if v.name != sc.SLIDER_FORCE_NAME])

# vendor annotations: OpenModelica's OMSimulator (its own prefix "oms", matched literally), OSP's libcosim
OMS = "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"
OSP = "http://opensimulationplatform.com/SSP/OSPAnnotations"
OMS_TYPE, OSP_TYPE = "org.openmodelica", "com.opensimulationplatform"
LOAD_COUPLINGS = sc.LOAD_COUPLINGS     # how the mechanism takes the joint's loads over a communication step
# s: the step the package asks for by coupling: inside the monolithic scatter in every master here, on time or one
# step late (8 starts, docs/explanation/cosim_study.md)
DEFAULT_STEP_S = {"hold": 0.5e-6, "linearised": 5e-6}
# s: the step the package asks OMSimulator for, which moves the kinematics before it reads the loads ("on time"):
# with the loads linearised the container, on time too, stays within 1 standard error at 10 us (8 starts)
ON_TIME_STEP_S = {"hold": 0.5e-6, "linearised": 1e-5}
# s: the shortest communication step a package or container takes: 1/500 of the held loads' 0.5 us (a revolution of the
# paper's mechanism in 4e8 steps); 1e-300 was taken, a step no master's time advances by
MIN_STEP_S = 1e-9
MIN_STEP_WHY = "a master's step: 1/500 of the held loads' 0.5 us"
# s: the longest default experiment: 16 revolutions of the slowest crank a mechanism admits (1e-3 rpm), 2.5 million of
# the paper's; the FMUs' time then still resolves a nanosecond step (1e300 was taken)
MAX_STOP_TIME_S = 1e6
STOP_TIME_WHY = "11.6 days of the machine: 2.5 million revolutions of the paper's mechanism"
RESULT_INTERVAL_S = 1e-5    # s: OMSimulator's logging interval: 100 kHz, every 20th step at 0.5 us
RESULT_FILE = f"{SSP_NAME}_res.mat"
SIGNAL_FILTER = "resources/signalFilter.xml"
# what OMSimulator records by default: the mechanism's crank and slider, the joint's scalar results
RECORDED = tuple((MECHANISM, n) for n in ("crank_angle", "slider_x", "slider_v", "slider_a")) + tuple(
    (JOINT, n) for n in ("pin_force_x", "pin_force_y", "normal_force", "friction_force", "penetration", "contact",
                         "eccentricity_x", "eccentricity_y", "tangential_velocity", "max_wear_depth",
                         "worn_volume"))

for _prefix, _uri in (("ssd", SSD), ("ssc", SSC), ("ssv", SSV), ("oms", OMS), ("osp", OSP)):
    ET.register_namespace(_prefix, _uri)


def _q(namespace: str, tag: str) -> str:
    return f"{{{namespace}}}{tag}"


def _is_profile(name: str) -> bool:
    """Whether ``name`` is one of the joint's ``wear_depth[k]`` outputs."""
    return name.startswith(fv.wear_depth_name(1).removesuffix("1]"))


def _connectors(component: ET.Element, fmu_path: Path, wired: list) -> set[str]:
    """A connector per input, output and parameter of the FMU (its unit where it has one), but the
    joint's N_d ``wear_depth[k]`` outputs: nothing connects to them, every master still reads them
    from the FMU, and a master that moves every connector at every step (fmpy's SSP simulator) runs
    ten times faster without them; nor its linearisation outputs where ``wired`` (the connections) does not
    connect them; nor an input no connection feeds (the mechanism's ``slider_force``: a master that connects a
    load FMU declares it).  Returns the units used."""
    from fmpy import read_model_description

    connectors = ET.SubElement(component, _q(SSD, "Connectors"))
    units = set()
    fed = {(end, name) for _, _, end, name in wired}
    feeding = {(start, name) for start, name, _, _ in wired}
    linearisation = {v.name for v in fv.LINEARISATION_OUTPUTS}
    for v in read_model_description(str(fmu_path)).modelVariables:
        if v.causality not in ("input", "output", "parameter") or _is_profile(v.name):
            continue
        if v.name in linearisation and v.causality == "output" and (component.get("name"), v.name) not in feeding:
            continue
        if v.causality == "input" and (component.get("name"), v.name) not in fed:
            continue          # an open input (slider_force): fmpy 0.3.32's SSP simulator wires it to the previous one's source
        connector = ET.SubElement(connectors, _q(SSD, "Connector"), name=v.name, kind=v.causality)
        if v.type == "Real":
            unit = v.unit if v.unit in _UNITS else None
            ET.SubElement(connector, _q(SSC, "Real"), **({"unit": unit} if unit else {}))
            units.add(unit)
        else:
            ET.SubElement(connector, _q(SSC, "Integer"))
    return units - {None}


# unit -> SI base-unit exponents (SSP 1.0 exponents are integers: N/m1.5 is declared without a unit)
_UNITS = {**{k: v for k, v in fv.UNIT_DEFINITIONS.items() if k != "N/m1.5"}, **sc.UNIT_DEFINITIONS}


def _parameter_set(values: dict) -> bytes:
    """An SSV parameter set: Reals and Integers (the joint's options) in the FMU's units.  Both
    components' sets have one name, :data:`PARAMETER_SET` (ecos applies sets by name)."""
    root = ET.Element(_q(SSV, "ParameterSet"), version="1.0", name=PARAMETER_SET)
    parameters = ET.SubElement(root, _q(SSV, "Parameters"))
    for key, value in values.items():
        parameter = ET.SubElement(parameters, _q(SSV, "Parameter"), name=key)
        ET.SubElement(parameter, _q(SSV, "Integer" if isinstance(value, int) else "Real"), value=repr(value))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def _annotation(parent: ET.Element, kind: str) -> ET.Element:
    """A vendor ``ssc:Annotation`` of type ``kind`` in ``parent``'s ``ssd:Annotations`` (made if absent)."""
    annotations = parent.find(_q(SSD, "Annotations"))
    if annotations is None:
        annotations = ET.SubElement(parent, _q(SSD, "Annotations"))
    return ET.SubElement(annotations, _q(SSC, "Annotation"), type=kind)


def _master_annotations(system: ET.Element, experiment: ET.Element, step_s: float, on_time_step_s: float) -> None:
    """The fixed communication step where masters read one (``on_time_step_s`` for OMSimulator, which moves the
    kinematics before it reads the loads, ``step_s`` for OSP's libcosim, which reads them one step late), and
    OMSimulator's result settings.

    OMSimulator (read first, so its annotations come first): the system's ``oms:SimulationInformation``
    with an ``oms:FixedStepMaster`` (its ``oms-ma``: a weakly coupled system at the fixed step; without it
    ``OMSimulator file.ssp`` cannot load the package), and in the default experiment its result file,
    logging interval and signal filter (:data:`SIGNAL_FILTER`).  OSP libcosim: the default experiment's
    ``osp:FixedStepAlgorithm``.  fmpy and ecos read no step from an SSP: their callers pass it."""
    information = ET.SubElement(ET.SubElement(_annotation(system, OMS_TYPE), _q(OMS, "Annotations")),
                                _q(OMS, "SimulationInformation"))
    ET.SubElement(information, _q(OMS, "FixedStepMaster"), description="oms-ma", stepSize=repr(on_time_step_s),
                  relativeTolerance="0.0001")
    oms = ET.SubElement(_annotation(experiment, OMS_TYPE), _q(OMS, "Annotations"))
    ET.SubElement(oms, _q(OMS, "SimulationInformation"), resultFile=RESULT_FILE,
                  loggingInterval=repr(max(RESULT_INTERVAL_S, on_time_step_s)), bufferSize="10",
                  signalFilter=SIGNAL_FILTER)
    algorithm = ET.SubElement(_annotation(experiment, OSP_TYPE), _q(OSP, "Algorithm"))
    ET.SubElement(algorithm, _q(OSP, "FixedStepAlgorithm"), baseStepSize=repr(step_s))


def signal_filter(recorded=RECORDED) -> bytes:
    """OMSimulator's signal filter (``oms:SignalFilter``): the variables it writes to its result file,
    ``<model>.<system>.<component>.<name>`` (the package's model and system are both :data:`SSP_NAME`)."""
    root = ET.Element(_q(OMS, "SignalFilter"), version="2.0")
    for component, name in recorded:
        kind = "input" if component == MECHANISM and name in {v.name for v in sc.INPUTS} else "output"
        ET.SubElement(root, _q(OMS, "Variable"), name=f"{SSP_NAME}.{SSP_NAME}.{component}.{name}", type="Real",
                      kind=kind)
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def system_structure(fmus: dict, stop_time: float, step_s: float, load_coupling: str = "linearised",
                     on_time_step_s: float | None = None) -> bytes:
    """``SystemStructure.ssd`` for the FMUs {component: path}, at the communication step ``step_s`` [s]
    (``on_time_step_s`` for OMSimulator, default ``step_s``), wired for ``load_coupling`` (:func:`connections`)."""
    wired = connections(load_coupling)
    root = ET.Element(_q(SSD, "SystemStructureDescription"), version="1.0", name=SSP_NAME)
    system = ET.SubElement(root, _q(SSD, "System"), name=SSP_NAME,
                           description="The paper's slider-crank (Sec. 6.1) with a wearing clearance joint between "
                                       "crank and rod: the joint's loads drive the mechanism, the mechanism's "
                                       "kinematics the joint.")
    elements = ET.SubElement(system, _q(SSD, "Elements"))
    units = set()
    for name, path in fmus.items():
        component = ET.SubElement(elements, _q(SSD, "Component"), name=name, type=FMU_TYPE,
                                  source=f"resources/{path.name}")
        units |= _connectors(component, path, wired)
        bindings = ET.SubElement(component, _q(SSD, "ParameterBindings"))
        ET.SubElement(bindings, _q(SSD, "ParameterBinding"), source=f"resources/{name}.ssv")
    wires = ET.SubElement(system, _q(SSD, "Connections"))
    for start, start_connector, end, end_connector in wired:
        ET.SubElement(wires, _q(SSD, "Connection"), startElement=start, startConnector=start_connector,
                      endElement=end, endConnector=end_connector)
    unit_definitions = ET.SubElement(root, _q(SSD, "Units"))
    for name in sorted(units):
        unit = ET.SubElement(unit_definitions, _q(SSC, "Unit"), name=name)
        ET.SubElement(unit, _q(SSC, "BaseUnit"), {k: str(v) for k, v in _UNITS[name].items()})
    experiment = ET.SubElement(root, _q(SSD, "DefaultExperiment"), startTime="0.0", stopTime=repr(float(stop_time)))
    _master_annotations(system, experiment, float(step_s),   # the system's: after its connections (schema)
                        float(step_s if on_time_step_s is None else on_time_step_s))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def _validate(xml: bytes, schema: str, what: str) -> None:
    """RuntimeError with the schema's messages if ``xml`` does not validate against fmpy's SSP ``schema``."""
    from fmpy.ssp import ssd as fmpy_ssd
    from lxml import etree

    schema_path = Path(fmpy_ssd.__file__).parent / "schema" / schema
    checker = etree.XMLSchema(file=str(schema_path))
    if not checker.validate(etree.fromstring(xml)):
        raise RuntimeError(f"{what} does not validate against {schema}: "
                           + "; ".join(f"line {e.line}: {e.message}" for e in checker.error_log))


def package_step_s(load_coupling: str, step_scale: float, limit_s: float, period_s: float,
                   on_time: bool = False) -> float:
    """The communication step the package asks for [s]: :data:`DEFAULT_STEP_S` (``on_time``: :data:`ON_TIME_STEP_S`,
    OMSimulator's) of ``load_coupling`` times ``step_scale`` (the step rule's), within ``limit_s`` (the wear-step
    limit), shortened to a whole number of steps per crank revolution of ``period_s`` [s] (3.2751 us had ended a
    revolution's run 3.5e-6 revolutions late, a sliver revolution of its own in revolutions.csv)."""
    step = min((ON_TIME_STEP_S if on_time else DEFAULT_STEP_S)[load_coupling] * step_scale, limit_s)
    return period_s / math.ceil(period_s / step * (1.0 - 1e-12))


def export_ssp(out_dir, mechanism: SliderCrankParameters | None = None, joint: JointParameters | None = None,
               stop_time: float | None = None, platforms=None, step_s: float | None = None,
               load_coupling: str = "linearised", step_scale: float = 1.0) -> Path:
    """Write ``out_dir/SliderCrankWithClearance.ssp`` and return its path.

    ``mechanism`` (default: the paper's) and ``joint`` (default: the paper's with the mechanism's
    offsets; ParameterError if its offsets do not fit the mechanism) become the parameter sets and
    the two FMUs' start values;
    ``stop_time`` the default experiment's stop time (default one crank revolution [s]);
    ``platforms`` those the FMUs carry binaries for (default: every installed one);
    ``step_s`` the communication step the package asks its masters for [s] (OMSimulator's and OSP's
    annotations; default :data:`DEFAULT_STEP_S` of the coupling for OSP, :data:`ON_TIME_STEP_S` for OMSimulator,
    both times ``step_scale``: docs/how-to/run_in_omsimulator.md);
    ``load_coupling`` how the mechanism takes the joint's loads over a step (:data:`LOAD_COUPLINGS`: "linearised",
    F0 + J (u - u0) from the joint's published linearisation, wired; "hold", the loads held).
    """
    from .build import build_fmu

    mechanism = mechanism or SliderCrankParameters()
    joint = joint or paper_joint(mechanism)
    check_joint_fits_mechanism(joint, mechanism)
    stop_time = mechanism.period_s if stop_time is None else stop_time
    stop_time = check_stop_time(stop_time, most=math.inf)      # a master's run is bounded by its trace's memory
    require("load_coupling", load_coupling, load_coupling in LOAD_COUPLINGS, f"one of {', '.join(LOAD_COUPLINGS)}")
    limit = wear_step_limit_s(joint, mechanism)          # a default within the wear-step limit, a given step checked
    on_time_step_s = (package_step_s(load_coupling, step_scale, limit, mechanism.period_s, on_time=True)
                      if step_s is None else step_s)
    if step_s is None:      # the package's own step: a stop time before it ends is the stop time's fault
        step_s = package_step_s(load_coupling, step_scale, limit, mechanism.period_s)
        require("stop_time", stop_time, stop_time >= step_s, f">= the package's communication step {step_s:g} s")
    require("step_s", step_s, 0.0 < finite("step_s", step_s) <= stop_time, f"> 0 and <= stop_time = {stop_time:g} s")
    require("step_s", step_s, step_s >= MIN_STEP_S, f">= {MIN_STEP_S:g} s ({MIN_STEP_WHY})")
    check_wear_step("step_s", max(step_s, on_time_step_s), joint, mechanism)   # every master's step wears
    on_time_step_s = min(on_time_step_s, stop_time)
    out_dir = Path(out_dir)
    with tempfile.TemporaryDirectory(prefix="wearjoint_ssp_") as tmp:
        fmus = {MECHANISM: build_fmu(Path(tmp) / MECHANISM, model="slider-crank", platforms=platforms,
                                     starts={**sc.parameter_starts(mechanism), **coupling_start(load_coupling)}),
                JOINT: build_fmu(Path(tmp) / JOINT, n_points=joint.n_points, platforms=platforms,
                                 starts=fv.parameter_starts(joint))}
        ssd = system_structure(fmus, stop_time, step_s, load_coupling, on_time_step_s)
        _validate(ssd, "SystemStructureDescription.xsd", "SystemStructure.ssd")
        parameter_sets = {MECHANISM: _parameter_set({**sc.parameter_values(mechanism),
                                                     sc.LOAD_COUPLING_NAME: float(sc.LOAD_COUPLINGS.index(load_coupling))}),
                          JOINT: _parameter_set(fv.fmi_parameter_values(joint))}
        for name, xml in parameter_sets.items():
            _validate(xml, "SystemStructureParameterValues.xsd", f"resources/{name}.ssv")
        out_dir.mkdir(parents=True, exist_ok=True)
        target = out_dir / SSP_FILE_NAME
        with replaced_whole(target) as partial, zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as ssp:
            ssp.writestr("SystemStructure.ssd", ssd)
            ssp.writestr(SIGNAL_FILTER, signal_filter())
            for name, path in fmus.items():
                ssp.write(path, f"resources/{path.name}")
                ssp.writestr(f"resources/{name}.ssv", parameter_sets[name])
    return target


def check_stop_time(stop_time, most: float = MAX_STOP_TIME_S) -> float:
    """``stop_time`` [s] as a float where it is finite, > 0 and at most ``most`` (MAX_STOP_TIME_S: export-ssp's
    default experiment; :func:`export_ssp` takes any, a master run through it bounded by the memory its trace takes,
    wearjoint.cosim.masters), else the ParameterError naming it."""
    require("stop_time", stop_time, finite("stop_time", stop_time) > 0.0, "> 0")
    require("stop_time", stop_time, stop_time <= most, f"at most {most:g} s ({STOP_TIME_WHY})")
    return float(stop_time)


def coupling_start(load_coupling: str) -> dict[str, float]:
    """SliderCrank.fmu's start value of ``load_coupling`` in a package of that coupling where it is not the FMU's
    own (hold): a master that applies no parameter set (fmpy's SSP simulator) runs the package's coupling too."""
    index = sc.LOAD_COUPLINGS.index(load_coupling)
    return {} if index == sc.LOAD_COUPLING_HOLD else {sc.LOAD_COUPLING_NAME: float(index)}


CONTAINER_FILE_NAME = f"{SSP_NAME}.fmu"
CONTAINER_STEP_S = 1e-6     # s: a step at which a zero-order hold is stable here (docs/explanation/cosim_study.md)


def bound_parameters(ssd) -> dict:
    """The parameter values the package's SSD binds, as fmpy reads it (``fmpy.ssp.ssd.read_ssd``):
    {(component, parameter name): value}."""
    return {(element.name, p.name): p.value for element in ssd.system.elements
            for binding in element.parameterBindings for s in binding.parameterValues for p in s.parameters}


def container_variable(component: str, name: str) -> str:
    """The container FMU's name of ``component``'s variable ``name``."""
    return f"{component}.{name}"


def container_fmu(ssp_path, out_path, step_s: float = CONTAINER_STEP_S) -> Path:
    """Write ``out_path``: the package's system as one FMI 2.0 Co-Simulation FMU, an fmpy container
    (``fmpy.container_fmu``: fmpy's own container library runs the nested FMUs; it ships
    x86_64-linux, x86_64-windows and x86_64/aarch64-darwin binaries, so the container runs where
    both it and the nested FMUs have a binary).  The container steps both FMUs at the fixed step
    ``step_s`` [s] (a communication step must be a multiple of it), then moves the connections in
    the SSD's order (the kinematics to the joint, then the joint's loads, evaluated at them); it
    exposes every output of both FMUs and, with the package's values as start values, every
    parameter, as ``<component>.<name>``.  Returns ``out_path``."""
    import attrs
    from fmpy import read_model_description
    from fmpy.container_fmu import Configuration
    from fmpy.container_fmu.cli import create_container_fmu
    from fmpy.container_fmu.config import Component, Connection
    from fmpy.model_description import CoSimulation, DefaultExperiment, ModelDescription, ModelVariable, Unknown
    from fmpy.ssp.ssd import read_ssd

    require("step_s", step_s, finite("step_s", step_s) > 0.0, "> 0")
    require("step_s", step_s, step_s >= MIN_STEP_S, f">= {MIN_STEP_S:g} s ({MIN_STEP_WHY})")
    ssd = read_ssd(str(ssp_path))
    out_path = Path(out_path)
    with tempfile.TemporaryDirectory(prefix="wearjoint_container_") as tmp:
        with zipfile.ZipFile(ssp_path) as package:
            package.extractall(Path(tmp) / "ssp")
        components, variables = {}, {}
        for element in ssd.system.elements:
            path = Path(tmp) / "ssp" / element.source
            md = read_model_description(str(path))
            components[element.name] = Component(name=element.name, filename=path, modelDescription=md)
            variables[element.name] = {v.name: v for v in md.modelVariables}
        token = str(uuid.uuid5(uuid.NAMESPACE_URL, f"{ssp_path}:{step_s!r}:{ssd.system.name}"))
        md = ModelDescription(fmiVersion="2.0", modelName=SSP_NAME, instantiationToken=token,
                              description=f"{SSP_NAME}.ssp as one FMU (fmpy container, fixed step {step_s:g} s)",
                              generationTool="wearjoint export-ssp --container-fmu")
        md.coSimulation = CoSimulation(modelIdentifier="container_fmu", fixedInternalStepSize=step_s)
        experiment = ET.parse(Path(tmp) / "ssp" / "SystemStructure.ssd").getroot().find(_q(SSD, "DefaultExperiment"))
        md.defaultExperiment = DefaultExperiment(startTime="0.0", stopTime=experiment.get("stopTime"),
                                                 stepSize=repr(step_s))
        md.modelVariables.append(ModelVariable(name="time", causality="independent", variability="continuous",
                                               type="Real"))
        mappings = {}
        starts = bound_parameters(ssd)
        for name, component in components.items():
            for v in component.modelDescription.modelVariables:
                if v.causality not in ("output", "parameter"):
                    continue
                exposed = ModelVariable(name=container_variable(name, v.name), causality=v.causality, type=v.type,
                                        variability=v.variability, initial=v.initial, description=v.description)
                exposed.start = starts.get((name, v.name), v.start) if v.causality == "parameter" else None
                md.modelVariables.append(exposed)
                mappings[exposed] = [(component, v)]
                if v.causality == "output":
                    md.outputs.append(Unknown(variable=exposed))
                    md.initialUnknowns.append(Unknown(variable=exposed))

        def float64(component, name):   # fmpy 0.3.32 writes an FMI 2.0 connection's type as "Real",
            return [attrs.evolve(variables[component][name], type="Float64")]   # its container reads Float64

        connections = [Connection(startElement=components[c.startElement],
                                  startConnectors=float64(c.startElement, c.startConnector),
                                  endElement=components[c.endElement],
                                  endConnectors=float64(c.endElement, c.endConnector))
                       for c in ssd.system.connections]
        configuration = Configuration(parallelDoStep=False, modelDescription=md, components=list(components.values()),
                                      connections=connections, variableMappings=mappings)
        (Path(tmp) / "container").mkdir()
        out_path.parent.mkdir(parents=True, exist_ok=True)
        with replaced_whole(out_path) as partial:
            create_container_fmu(configuration, Path(tmp) / "container", partial)
    return out_path
