"""``modelDescription.xml`` of the ``ClearanceWearJoint`` FMU (FMI 2.0), generated from the
variable table :mod:`wearjoint.fmu.variables` for every backend.

The backends differ only in the GUID, the generation tool and a few
``<CoSimulation>`` capability flags; variables, value references (= position in
:func:`~wearjoint.fmu.variables.fmu_variables`), units, descriptions, start
values and the ModelStructure (direct feed-through of the joint outputs on the
12 inputs) are the same.
"""
from __future__ import annotations

import datetime
from xml.etree import ElementTree as ET

from .. import __version__
from . import variables as fv

DESCRIPTION = ("Planar revolute clearance joint with a wearing bushing (Archard wear, "
               "Lankarani-Nikravesh contact, Ambrosio friction). Inputs: kinematics of the pin "
               "and bushing bodies; outputs: forces (direct feed-through) and the wear profile.")
LOG_CATEGORIES = {"logStatusError": "errors (always reported)", "logStatusWarning": "warnings",
                  "logAll": "every other message"}
# causality -> (variability, initial) of the ScalarVariable
_KIND = {fv.INPUT: ("continuous", None), fv.OUTPUT: ("continuous", "calculated"),
         fv.PARAMETER: ("fixed", "exact"), fv.LOCAL: ("constant", "exact")}


def _number(value) -> str:
    return repr(float(value)) if isinstance(value, float) else str(value)


def model_description_xml(n_points: int, guid: str, generation_tool: str, cosimulation: dict[str, str],
                          model_exchange: dict[str, str] | None = None, event_indicators: int = 0) -> bytes:
    """The complete modelDescription.xml; ``cosimulation`` / ``model_exchange`` are the
    ``<CoSimulation>`` / ``<ModelExchange>`` attributes (``modelIdentifier`` and the capability
    flags; no ``<ModelExchange>`` if None); ``event_indicators``: Model Exchange's number of
    event indicators."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "2.0", "modelName": fv.MODEL_NAME, "guid": guid, "description": DESCRIPTION,
        "author": "wearjoint", "version": __version__, "generationTool": generation_tool,
        "generationDateAndTime": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "structured", "numberOfEventIndicators": str(event_indicators)})
    if model_exchange is not None:
        ET.SubElement(root, "ModelExchange", model_exchange)
    ET.SubElement(root, "CoSimulation", cosimulation)
    units = ET.SubElement(root, "UnitDefinitions")
    for name, exponents in fv.UNIT_DEFINITIONS.items():
        unit = ET.SubElement(units, "Unit", name=name)
        if exponents:
            ET.SubElement(unit, "BaseUnit", {k: str(e) for k, e in exponents.items()})
    categories = ET.SubElement(root, "LogCategories")
    for name, text in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=text)
    variables = fv.fmu_variables(n_points)
    model_variables = ET.SubElement(root, "ModelVariables")
    for vr, v in enumerate(variables):
        variability, initial = _KIND[v.causality]
        attributes = {"name": v.name, "valueReference": str(vr), "description": v.description,
                      "causality": v.causality, "variability": variability}
        if initial:
            attributes["initial"] = initial
        sv = ET.SubElement(model_variables, "ScalarVariable", attributes)
        typed = {"unit": v.unit} if v.type == fv.REAL else {}
        if v.start is not None:
            typed["start"] = _number(v.start)
        ET.SubElement(sv, v.type, typed)
    index = {v.name: i + 1 for i, v in enumerate(variables)}   # ModelStructure indices are 1-based
    inputs = " ".join(str(index[v.name]) for v in fv.INPUTS)
    inputs_and_parameters = " ".join(str(index[v.name]) for v in (*fv.INPUTS, *(p.variable for p in fv.PARAMETERS)))
    structure = ET.SubElement(root, "ModelStructure")
    outputs = ET.SubElement(structure, "Outputs")   # no continuous states: no <Derivatives>
    initial_unknowns = ET.SubElement(structure, "InitialUnknowns")
    for v in variables:
        if v.causality != fv.OUTPUT:
            continue
        feed_through = v.name in fv.FEED_THROUGH_OUTPUTS
        ET.SubElement(outputs, "Unknown", index=str(index[v.name]), dependencies=inputs if feed_through else "")
        ET.SubElement(initial_unknowns, "Unknown", index=str(index[v.name]),
                      dependencies=inputs_and_parameters if feed_through else "")
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)
