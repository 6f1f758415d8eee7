"""``modelDescription.xml`` of the ``ClearanceWearJoint`` FMU (FMI 2.0), generated from the
variable table :mod:`wearjoint.fmu.variables` for every backend.

The backends differ only in the GUID, the generation tool and a few
``<CoSimulation>`` capability flags (the native FMU provides directional derivatives);
variables, value references (= position in :func:`~wearjoint.fmu.variables.fmu_variables`),
units, descriptions, start values and the ModelStructure (direct feed-through of the joint
outputs on the inputs each depends on) are the same.
"""
from __future__ import annotations

import datetime
from xml.etree import ElementTree as ET

from .. import __version__
from ..parameters import N_POINTS_MAX, N_POINTS_MIN   # FMI 3.0: the structural parameter n_points' range
from . import variables as fv

DESCRIPTION = ("Planar revolute clearance joint with a wearing bushing (Archard wear, elastic-foundation "
               "contact, Hunt-Crossley damping, Ambrosio friction). Inputs: kinematics of the pin and bushing "
               "bodies; outputs: forces (direct feed-through) and the wear profile.")
LOG_CATEGORIES = {"logStatusError": "errors (always reported)", "logStatusWarning": "warnings",
                  "logAll": "every other message"}
# causality -> (variability, initial) of the ScalarVariable
_KIND = {fv.INPUT: ("continuous", None), fv.OUTPUT: ("continuous", "calculated"),
         fv.PARAMETER: ("fixed", "exact"), fv.LOCAL: ("constant", "exact")}


def _number(value) -> str:
    return repr(float(value)) if isinstance(value, float) else str(value)


# the native FMUs whose C model computes directional derivatives (fmu_model.h model_directional_derivative)
DIRECTIONAL_DERIVATIVES = frozenset({fv.MODEL_NAME})


def allowed_bounds(allowed) -> dict[str, str]:
    """``min`` and ``max`` of a real parameter whose rule is ``allowed`` (a :class:`wearjoint.checks.Allowed`, or
    None) in a modelDescription: the rule's bounds, an open one as the limit itself (FMI's are inclusive: a host's
    check admits the limit, which the FMU then refuses naming its rule), none where the rule has none (the FMU checks
    the rest at fmi2ExitInitializationMode)."""
    if allowed is None:
        return {}
    return {key: _number(value) for key, value in (("min", allowed.low), ("max", allowed.high)) if value is not None}


def _bounds(p) -> dict[str, str]:
    """:func:`allowed_bounds` of a joint parameter ``p`` (fv.PARAMETERS); an enumeration's (an FMI 2.0 Integer) its
    codes' range."""
    return {"min": "0", "max": str(len(p.choices) - 1)} if p.choices is not None else allowed_bounds(p.allowed)


def interfaces(fmi_version: int, model_identifier: str, completed_integrator_step: bool) -> tuple[dict, dict]:
    """The ``<CoSimulation>`` and ``<ModelExchange>`` attributes of a native FMU (FMI ``fmi_version``):
    FMU state get/set/serialise, variable communication steps, no early return or intermediate
    update, directional derivatives if the model is one of :data:`DIRECTIONAL_DERIVATIVES`;
    ``completed_integrator_step``: Model Exchange needs completedIntegratorStep."""
    derivatives = str(model_identifier in DIRECTIONAL_DERIVATIVES).lower()
    common = {"modelIdentifier": model_identifier, "needsExecutionTool": "false",
              "canBeInstantiatedOnlyOncePerProcess": "false"}
    if fmi_version == 2:
        common.update({"canNotUseMemoryManagementFunctions": "false", "canGetAndSetFMUstate": "true",
                       "canSerializeFMUstate": "true", "providesDirectionalDerivative": derivatives})
        cosimulation = {**common, "canHandleVariableCommunicationStepSize": "true", "canInterpolateInputs": "false"}
        model_exchange = {**common, "completedIntegratorStepNotNeeded": str(not completed_integrator_step).lower()}
        return cosimulation, model_exchange
    common.update({"canGetAndSetFMUState": "true", "canSerializeFMUState": "true",
                   "providesDirectionalDerivatives": derivatives, "providesAdjointDerivatives": "false",
                   "providesPerElementDependencies": "false"})
    model_exchange = {**common, "needsCompletedIntegratorStep": str(completed_integrator_step).lower(),
                      "providesEvaluateDiscreteStates": "false"}
    cosimulation = {**common, "canHandleVariableCommunicationStepSize": "true", "maxOutputDerivativeOrder": "0",
                    "providesIntermediateUpdate": "false", "mightReturnEarlyFromDoStep": "false",
                    "canReturnEarlyAfterIntermediateUpdate": "false", "hasEventMode": "false",
                    "providesEvaluateDiscreteStates": "false"}
    return cosimulation, model_exchange


def root_with_interfaces_and_units(attributes: dict, cosimulation: dict, model_exchange: dict | None,
                                   units: dict, model_name: str = fv.MODEL_NAME,
                                   description: str = DESCRIPTION) -> ET.Element:
    """<fmiModelDescription> with the common attributes, <ModelExchange> (if given), <CoSimulation>
    and <UnitDefinitions> (unit name -> SI base-unit exponents, and ``factor`` where given)."""
    root = ET.Element("fmiModelDescription", {
        "modelName": model_name, "description": description, "author": "wearjoint", "version": __version__,
        "generationDateAndTime": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "variableNamingConvention": "structured", **attributes})
    if model_exchange is not None:
        ET.SubElement(root, "ModelExchange", model_exchange)
    ET.SubElement(root, "CoSimulation", cosimulation)
    definitions = ET.SubElement(root, "UnitDefinitions")
    for name, exponents in units.items():
        unit = ET.SubElement(definitions, "Unit", name=name)
        if exponents:
            ET.SubElement(unit, "BaseUnit", {k: str(e) for k, e in exponents.items()})
    return root


def _dependencies(output: str, reference: dict[str, int], parameters: tuple[str, ...] = ()) -> str:
    """The ``dependencies`` of ``output`` (ModelStructure, indices or value references from ``reference``): the
    inputs it depends on (:data:`~wearjoint.fmu.variables.OUTPUT_DEPENDENCIES`) and, for a feed-through output's
    initial value, ``parameters``; none for the wear, which the inputs change only over a step."""
    if output not in fv.OUTPUT_DEPENDENCIES:
        return ""
    return " ".join(str(reference[name]) for name in (*fv.OUTPUT_DEPENDENCIES[output], *parameters))


def model_description_xml(n_points: int, guid: str, generation_tool: str, cosimulation: dict[str, str],
                          model_exchange: dict[str, str] | None = None, event_indicators: int = 0,
                          starts: dict | None = None, profile_stride: int = 1, note: str = "") -> bytes:
    """The complete modelDescription.xml; ``cosimulation`` / ``model_exchange`` are the
    ``<CoSimulation>`` / ``<ModelExchange>`` attributes (``modelIdentifier`` and the capability
    flags; no ``<ModelExchange>`` if None); ``event_indicators``: Model Exchange's number of
    event indicators; ``starts``: parameter start values other than the defaults
    (:func:`~wearjoint.fmu.variables.parameter_starts`); ``profile_stride``: the profile points exposed
    as outputs (:func:`~wearjoint.fmu.variables.profile_points`)."""
    root = root_with_interfaces_and_units(
        {"fmiVersion": "2.0", "guid": guid, "generationTool": generation_tool,
         "numberOfEventIndicators": str(event_indicators)}, cosimulation, model_exchange, fv.UNIT_DEFINITIONS,
        description=" ".join(filter(None, (DESCRIPTION, note))))
    categories = ET.SubElement(root, "LogCategories")
    for name, text in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=text)
    variables = fv.fmu_variables(n_points, starts, profile_stride)
    bounds = {p.variable.name: _bounds(p) for p in fv.PARAMETERS}
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
        typed.update(bounds.get(v.name, {}))
        ET.SubElement(sv, v.type, typed)
    index = {v.name: i + 1 for i, v in enumerate(variables)}   # ModelStructure indices are 1-based
    parameters = tuple(p.variable.name for p in fv.PARAMETERS)
    structure = ET.SubElement(root, "ModelStructure")
    outputs = ET.SubElement(structure, "Outputs")   # no continuous states: no <Derivatives>
    initial_unknowns = ET.SubElement(structure, "InitialUnknowns")
    for v in variables:
        if v.causality != fv.OUTPUT:
            continue
        ET.SubElement(outputs, "Unknown", index=str(index[v.name]), dependencies=_dependencies(v.name, index))
        ET.SubElement(initial_unknowns, "Unknown", index=str(index[v.name]),
                      dependencies=_dependencies(v.name, index, parameters))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


# ------------------------------------------------------------------ FMI 3.0
WEAR_DEPTH_NAME = "wear_depth"  # FMI 3.0: the wear profile, one Float64 array of n_points values
TIME_NAME = "time"
# FMI 3.0 type of a FMI 2.0 variable type
_FMI3_TYPE = {fv.REAL: "Float64", fv.INTEGER: "Int32"}


def enumeration_type_name(parameter_name: str) -> str:
    """The FMI 3.0 ``<EnumerationType>`` of an enumeration parameter, e.g. ``rho_mode`` -> ``RhoMode``."""
    return "".join(part.capitalize() for part in parameter_name.split("_"))


def fmi3_value_references() -> dict[str, int]:
    """FMI 3.0 value references by name: every scalar keeps its FMI 2.0 value reference (inputs,
    parameters, ``n_points``, scalar outputs), then the ``wear_depth`` array, then ``time``.
    Independent of N_d (the array's size is the structural parameter ``n_points``)."""
    scalars = fv.fmu_variables(0)   # no wear_depth[z] scalars
    vr = {v.name: i for i, v in enumerate(scalars)}
    vr[WEAR_DEPTH_NAME] = len(scalars)
    vr[TIME_NAME] = len(scalars) + 1
    return vr


def model_description_fmi3_xml(n_points: int, instantiation_token: str, generation_tool: str,
                               cosimulation: dict[str, str], model_exchange: dict[str, str] | None = None,
                               event_indicators: tuple[str, ...] = ("penetration",),
                               starts: dict | None = None, note: str = "") -> bytes:
    """modelDescription.xml of the FMI 3.0 FMU: the variables of :mod:`wearjoint.fmu.variables`
    as ``Float64`` / ``Enumeration`` (the three option parameters, with their
    ``<EnumerationType>``), the structural parameter ``n_points`` (``UInt64``, start
    ``n_points``, settable in Configuration Mode) and the wear profile as one ``Float64`` array
    ``wear_depth`` whose ``<Dimension>`` is ``n_points``; value references from
    :func:`fmi3_value_references`; ``event_indicators`` names the outputs that are Model
    Exchange's event indicators; ``starts`` as :func:`model_description_xml`'s."""
    vr = fmi3_value_references()
    root = root_with_interfaces_and_units(
        {"fmiVersion": "3.0", "instantiationToken": instantiation_token, "generationTool": generation_tool},
        cosimulation, model_exchange, {**fv.UNIT_DEFINITIONS, "s": {"s": 1}},   # FMI 3's time needs "s"
        description=" ".join(filter(None, (DESCRIPTION, note))))
    types = ET.SubElement(root, "TypeDefinitions")
    for p in fv.PARAMETERS:
        if p.choices is not None:
            enumeration = ET.SubElement(types, "EnumerationType", name=enumeration_type_name(p.variable.name),
                                        description=p.variable.description)
            for item, value in p.choices:
                ET.SubElement(enumeration, "Item", name=item, value=str(value))
    categories = ET.SubElement(root, "LogCategories")
    for name, text in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", name=name, description=text)

    model_variables = ET.SubElement(root, "ModelVariables")

    def variable(tag: str, name: str, description: str, causality: str, variability: str | None = None,
                 initial: str | None = None, **typed) -> ET.Element:
        attributes = {"name": name, "valueReference": str(vr[name]), "description": description,
                      "causality": causality}
        if variability:
            attributes["variability"] = variability
        if initial:
            attributes["initial"] = initial
        attributes.update({k: v for k, v in typed.items() if v is not None})
        return ET.SubElement(model_variables, tag, attributes)

    variable("Float64", TIME_NAME, "simulation time", "independent", "continuous", unit="s")
    for v in fv.INPUTS:
        variable("Float64", v.name, v.description, fv.INPUT, "continuous", unit=v.unit, start=_number(v.start))
    for p in fv.PARAMETERS:
        v = fv.parameter_variable(p, starts)
        if p.choices is not None:
            variable("Enumeration", v.name, v.description, fv.PARAMETER, "fixed", "exact",
                     declaredType=enumeration_type_name(v.name), start=str(v.start))
        else:
            variable(_FMI3_TYPE[v.type], v.name, v.description, fv.PARAMETER, "fixed", "exact", unit=v.unit,
                     start=_number(v.start), **_bounds(p))
    variable("UInt64", fv.N_POINTS_NAME,
             f"number of bushing points N_d (the size of {WEAR_DEPTH_NAME}): a structural parameter, set it in "
             f"Configuration Mode (fmi3EnterConfigurationMode), {N_POINTS_MIN} .. {N_POINTS_MAX}",
             "structuralParameter", "fixed", "exact", start=str(n_points), min=str(N_POINTS_MIN),
             max=str(N_POINTS_MAX))
    for v in (*fv.SCALAR_OUTPUTS, *fv.LINEARISATION_OUTPUTS):
        variable("Float64", v.name, v.description, fv.OUTPUT, "continuous", "calculated", unit=v.unit)
    wear = variable("Float64", WEAR_DEPTH_NAME,
                    "wear depth of the bushing points: element z (1-based) at bushing-frame angle z*2*pi/n_points rad",
                    fv.OUTPUT, "continuous", "calculated", unit="m")
    ET.SubElement(wear, "Dimension", valueReference=str(vr[fv.N_POINTS_NAME]))

    parameters = (*(p.variable.name for p in fv.PARAMETERS), fv.N_POINTS_NAME)
    structure = ET.SubElement(root, "ModelStructure")   # no continuous states
    outputs = [*(v.name for v in (*fv.SCALAR_OUTPUTS, *fv.LINEARISATION_OUTPUTS)), WEAR_DEPTH_NAME]
    for name in outputs:
        ET.SubElement(structure, "Output", valueReference=str(vr[name]), dependencies=_dependencies(name, vr))
    for name in outputs:
        ET.SubElement(structure, "InitialUnknown", valueReference=str(vr[name]),
                      dependencies=_dependencies(name, vr, parameters))
    if model_exchange is not None:
        for name in event_indicators:
            ET.SubElement(structure, "EventIndicator", valueReference=str(vr[name]),
                          dependencies=_dependencies(name, vr))
    ET.indent(root)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)
