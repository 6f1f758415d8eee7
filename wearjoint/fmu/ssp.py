"""``SliderCrankWithClearance.ssp``: the paper's slider-crank as a system of two FMUs that any SSP
master runs (SSP 1.0: System Structure and Parameterization).

The package holds ``SystemStructure.ssd`` (the system: the ``mechanism`` component, a
``SliderCrank.fmu``, and the ``joint`` component, a ``ClearanceWearJoint.fmu``; every input and
output as a connector with its unit; the 12 kinematic connections mechanism -> joint and the 6
load connections joint -> mechanism; a default experiment of one crank revolution), the two FMUs
(native, FMI 2.0, every installed platform) and one parameter set per component
(``resources/<component>.ssv``): the paper's values, the joint's body-frame offsets those of the
slider-crank (:meth:`SliderCrankParameters.joint_offsets`).  The SSD and the parameter sets are
checked against the SSP 1.0 schemas fmpy ships before the package is written.
"""
from __future__ import annotations

import tempfile
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

from ..parameters import (
    JointParameters, SliderCrankParameters, _finite, _require, check_joint_fits_mechanism, paper_joint,
)
from . import slider_crank as sc
from . import variables as fv

SSP_NAME = "SliderCrankWithClearance"
SSP_FILE_NAME = f"{SSP_NAME}.ssp"
SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
FMU_TYPE = "application/x-fmu-sharedlibrary"
MECHANISM, JOINT = "mechanism", "joint"
# connections (start element, start connector, end element, end connector)
CONNECTIONS = ([(MECHANISM, name, JOINT, name) for name in sc.KINEMATIC_OUTPUTS]
               + [(JOINT, v.name, MECHANISM, v.name) for v in sc.INPUTS])

ET.register_namespace("ssd", SSD)
ET.register_namespace("ssc", SSC)
ET.register_namespace("ssv", SSV)


def _q(namespace: str, tag: str) -> str:
    return f"{{{namespace}}}{tag}"


def _connectors(component: ET.Element, fmu_path: Path) -> set[str]:
    """A connector per input, output and parameter of the FMU (its unit where it has one); the units used."""
    from fmpy import read_model_description

    connectors = ET.SubElement(component, _q(SSD, "Connectors"))
    units = set()
    for v in read_model_description(str(fmu_path)).modelVariables:
        if v.causality not in ("input", "output", "parameter"):
            continue
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


def _parameter_set(name: str, values: dict) -> bytes:
    """An SSV parameter set: Reals and Integers (the joint's options) in the FMU's units."""
    root = ET.Element(_q(SSV, "ParameterSet"), version="1.0", name=name)
    parameters = ET.SubElement(root, _q(SSV, "Parameters"))
    for key, value in values.items():
        parameter = ET.SubElement(parameters, _q(SSV, "Parameter"), name=key)
        ET.SubElement(parameter, _q(SSV, "Integer" if isinstance(value, int) else "Real"), value=repr(value))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def system_structure(fmus: dict, stop_time: float) -> bytes:
    """``SystemStructure.ssd`` for the FMUs {component: path}."""
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
        units |= _connectors(component, path)
        bindings = ET.SubElement(component, _q(SSD, "ParameterBindings"))
        ET.SubElement(bindings, _q(SSD, "ParameterBinding"), source=f"resources/{name}.ssv")
    connections = ET.SubElement(system, _q(SSD, "Connections"))
    for start, start_connector, end, end_connector in CONNECTIONS:
        ET.SubElement(connections, _q(SSD, "Connection"), startElement=start, startConnector=start_connector,
                      endElement=end, endConnector=end_connector)
    unit_definitions = ET.SubElement(root, _q(SSD, "Units"))
    for name in sorted(units):
        unit = ET.SubElement(unit_definitions, _q(SSC, "Unit"), name=name)
        ET.SubElement(unit, _q(SSC, "BaseUnit"), {k: str(v) for k, v in _UNITS[name].items()})
    ET.SubElement(root, _q(SSD, "DefaultExperiment"), startTime="0.0", stopTime=repr(float(stop_time)))
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


def export_ssp(out_dir, mechanism: SliderCrankParameters | None = None, joint: JointParameters | None = None,
               stop_time: float | None = None, platforms=None) -> Path:
    """Write ``out_dir/SliderCrankWithClearance.ssp`` and return its path.

    ``mechanism`` (default: the paper's) and ``joint`` (default: the paper's with the mechanism's
    offsets; ParameterError if its offsets do not fit the mechanism) become the parameter sets;
    ``stop_time`` the default experiment's stop time (default one crank revolution [s]);
    ``platforms`` those the FMUs carry binaries for (default: every installed one).
    """
    from .build import build_fmu

    mechanism = mechanism or SliderCrankParameters()
    joint = joint or paper_joint(mechanism)
    check_joint_fits_mechanism(joint, mechanism)
    stop_time = mechanism.period_s if stop_time is None else stop_time
    _require("stop_time", stop_time, _finite("stop_time", stop_time) > 0.0, "> 0")
    out_dir = Path(out_dir)
    with tempfile.TemporaryDirectory(prefix="wearjoint_ssp_") as tmp:
        fmus = {MECHANISM: build_fmu(Path(tmp) / MECHANISM, model="slider-crank", platforms=platforms),
                JOINT: build_fmu(Path(tmp) / JOINT, n_points=joint.n_points, platforms=platforms)}
        ssd = system_structure(fmus, stop_time)
        _validate(ssd, "SystemStructureDescription.xsd", "SystemStructure.ssd")
        parameter_sets = {MECHANISM: _parameter_set(MECHANISM, sc.parameter_values(mechanism)),
                          JOINT: _parameter_set(JOINT, fv.fmi_parameter_values(joint))}
        for name, xml in parameter_sets.items():
            _validate(xml, "SystemStructureParameterValues.xsd", f"resources/{name}.ssv")
        out_dir.mkdir(parents=True, exist_ok=True)
        target = out_dir / SSP_FILE_NAME
        partial = target.with_name(target.name + ".partial")
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as ssp:
            ssp.writestr("SystemStructure.ssd", ssd)
            for name, path in fmus.items():
                ssp.write(path, f"resources/{path.name}")
                ssp.writestr(f"resources/{name}.ssv", parameter_sets[name])
        partial.replace(target)
    return target
