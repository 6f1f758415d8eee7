"""One source for every default: each command's --help, the README, docs/reference/'s tables and the FMU's
modelDescription state the defaults of the dataclasses (JointParameters, SliderCrankParameters,
SimulationOptions, CoSimulationOptions, WearStudyConfig, ValidationPlan) or what a run resolves from them."""
import dataclasses
import math
import re
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np
import pytest

from wearjoint.cli import COMMANDS, build_parser
from wearjoint.cli.sweep import DEFAULT_SEEDS
from wearjoint.cosim import CoSimulationOptions
from wearjoint.fmu import variables as fv
from wearjoint.fmu.build import FMI_VERSIONS
from wearjoint.fmu.model_description import interfaces, model_description_fmi3_xml, model_description_xml
from wearjoint.fmu.ssp import CONTAINER_STEP_S
from wearjoint.parameters import JointParameters, SliderCrankParameters
from wearjoint.studies.calibration import DEFAULT_TOLERANCE
from wearjoint.simulate import SimulationOptions
from wearjoint.validation.compare import FULL, ValidationPlan
from wearjoint.studies.wear_study import DEFAULT_WEAR_FACTOR, WearStudyConfig

REPO = Path(__file__).resolve().parents[2]
NOTHING = object()


def _fields(cls) -> dict:
    return {f.name: f.default for f in dataclasses.fields(cls) if f.default is not dataclasses.MISSING}


# model options: the parameter sets' fields; in the slider-crank commands the joint sits at the mechanism's offsets
MODEL = {**_fields(JointParameters), **_fields(SliderCrankParameters), **SliderCrankParameters().joint_offsets()}
# a command's other options -> the dataclasses holding their defaults (field = dest, or dest + a unit suffix)
SOURCES = {"simulate": (SimulationOptions,), "cosim": (CoSimulationOptions, SimulationOptions),
           "wear-study": (WearStudyConfig,), "validate": (ValidationPlan,)}
# options left None whose run resolves a default the help states
RESOLVED = {
    ("simulate", "max_step"): SimulationOptions().for_joint(JointParameters(wear_factor=0.0)).max_step_s,
    ("simulate", "free_flight_max_step"): SimulationOptions().for_joint(JointParameters()).free_flight_max_step_s,
    ("cosim", "step"): CoSimulationOptions().step_s,
    ("cosim", "coupling_tolerance"): CoSimulationOptions().coupling_tolerance,
    ("wear-study", "wear_factor"): DEFAULT_WEAR_FACTOR,
    # the joint FMU alone: the joint's own offsets, its start values (test_model_description_start_values_are_the_
    # joint_defaults below); the help said the crank's tip, where the FMU started at 0
    ("build-fmu", "pin_offset_m"): JointParameters().pin_offset_m,
    ("build-fmu", "bushing_offset_m"): JointParameters().bushing_offset_m,
    ("wear-study", "cycle_jump_tolerance"): WearStudyConfig.__dataclass_fields__["jump_tolerance"].default,
    ("validate", "revolutions"): FULL.revolutions,
    ("validate", "wear_revolutions"): FULL.wear_revolutions,
    ("validate", "wear_factor"): FULL.wear_factor,
    ("export-ssp", "container_step"): CONTAINER_STEP_S,
    ("wear-study", "seeds"): DEFAULT_SEEDS,
    ("calibrate", "tolerance"): DEFAULT_TOLERANCE,      # without depth uncertainties (refused with them)
}


def command_parser(command: str):
    parser = build_parser(command)
    return next(a for a in parser._actions if a.dest == "command").choices[command]


def expected_default(command: str, dest: str):
    """What a run of ``command`` uses when option ``dest`` is not given (NOTHING: no dataclass says)."""
    if (command, dest) in RESOLVED:
        return RESOLVED[(command, dest)]
    if dest in MODEL:
        return MODEL[dest]
    for cls in SOURCES.get(command, ()):
        fields = _fields(cls)
        names = [n for n in fields if n == dest or n.startswith(dest + "_")]
        if names:
            return fields[min(names, key=len)]          # window -> window_s, not window_step_s
    return NOTHING


def normalized(value) -> list:
    """A default as comparable items: numbers as floats, ``0.025 0`` / ``a,b`` / tuples as lists."""
    items = value if isinstance(value, (list, tuple)) else re.split(r"[\s,]+", str(value).strip())
    out = []
    for item in items:
        try:
            out.append(float(str(item).replace("−", "-")))
        except ValueError:
            out.append(str(item))
    return out


def same(a, b) -> bool:
    a, b = normalized(a), normalized(b)
    return len(a) == len(b) and all(math.isclose(x, y, rel_tol=1e-5) if isinstance(x, float) and isinstance(y, float)
                                    else x == y for x, y in zip(a, b))


def stated_default(help_text: str):
    """The value of a help's ``(default VALUE)``, ``(default VALUE; ...)`` or ``(default VALUE, --quick ...)``."""
    match = re.search(r"\(default ([^;)]*)", help_text or "")
    return None if match is None else match[1].split(", ")[0].strip()


OPTIONS = []
for _command in COMMANDS:
    _parser = command_parser(_command)
    for _action in _parser._actions:
        if _action.option_strings and _action.dest != "help":
            OPTIONS.append(pytest.param(_command, _action.dest, id=f"{_command}:{_action.dest}"))


@pytest.mark.parametrize("command,dest", OPTIONS)
def test_help_default_is_the_dataclass_default(command, dest):
    parser = command_parser(command)
    action = next(a for a in parser._actions if a.dest == dest)
    expected = expected_default(command, dest)
    if action.default is not None and expected is not NOTHING and not isinstance(action.default, bool):
        assert same(action.default, expected), f"--{dest} default {action.default!r}, dataclass {expected!r}"
    stated = stated_default(parser._get_formatter()._expand_help(action) if action.help else "")
    if stated is not None:
        truth = action.default if expected is NOTHING else expected
        assert same(stated, truth), f"--help of {command} --{dest} says default {stated!r}, the run uses {truth!r}"


def test_build_fmu_help_names_every_fmi_version_and_both_interfaces():
    text = " ".join(command_parser("build-fmu").format_help().split())
    assert all(f"FMI {v}.0" in text or f" {v}.0" in text for v in FMI_VERSIONS)
    assert "Co-Simulation" in text and "Model Exchange" in text


def _readme_claims():
    """(command, option, value) for every ``--option ...` (default V)`` or ``(V ...)`` in the README's commands table."""
    text = (REPO / "README.md").read_text()
    table = text[text.index("## Commands"):text.index("## Library")]
    for row in (line for line in table.splitlines() if line.startswith("| `")):
        command = re.match(r"\| `([\w-]+)", row)[1]
        for option, remark in re.findall(r"`(--[\w-]+)[^`]*`\s*\(([^)]*)\)", row):
            if remark.startswith("default "):
                yield command, option, remark.split()[1]
            else:
                number = re.search(r"(?<![\w.])[-+]?\d[\d.]*(?:e[-+]?\d+)?(?!\w)", remark)
                if number:
                    yield command, option, number[0]


def test_readme_commands_table_states_the_dataclass_defaults():
    claims = list(_readme_claims())
    assert ("wear-study", "--cycle-jump-tolerance", "0.003") in claims   # the wear study's default route
    for command, option, value in claims:
        parser = command_parser(command)
        action = parser._option_string_actions[option]
        expected = expected_default(command, action.dest)
        truth = action.default if expected is NOTHING else expected
        assert same(value, truth), f"README: {command} {option} default {value}, the run uses {truth!r}"


def test_docs_state_the_wear_study_default_factor():
    study = (REPO / "docs" / "explanation" / "wear_study.md").read_text()
    assert same(re.search(r"wear factor F \(default (\S+?):", study)[1], DEFAULT_WEAR_FACTOR)
    model = (REPO / "docs" / "reference" / "model.md").read_text()
    assert same(re.search(r"the wear study uses (\S+?)\)", model)[1], DEFAULT_WEAR_FACTOR)


_UNIT = {"GPa": 1e9, "mm": 1e-3, "mm/s": 1e-3}
_VALUE = re.compile(r"(?<![\w^.])([-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?)\s*(GPa|mm/s|mm|N/m\^1\.5|m²/N|m/s²|kg m²|kg|rpm|m)?")


def _model_table():
    """(fields, values in SI) per row of docs/reference/model.md §2; a row ``--x-... …`` stands for every field
    named x_*."""
    text = (REPO / "docs" / "reference" / "model.md").read_text()
    section = text[text.index("## 2. "):text.index("## 3. ")]
    dests = {a.option_strings[0]: a.dest for a in command_parser("simulate")._actions if a.option_strings}
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) != 3 or not cells[2].startswith("`"):
            continue
        fields = [dests.get(o) for o in re.findall(r"`(--[\w-]+)", cells[2])]
        values = [float(v) * _UNIT.get(u, 1.0) for v, u in _VALUE.findall(cells[1])]
        rows.append((fields, "…" in cells[2], values))
    named = {f for fields, _, _ in rows for f in fields}
    for fields, grouped, values in rows:
        if grouped:
            prefix = fields[0].split("_")[0] + "_"
            fields = [f for f in MODEL if f.startswith(prefix) and (f == fields[0] or f not in named)]
        if all(f in MODEL for f in fields):
            yield fields, values


def test_model_md_parameter_table_states_the_dataclass_defaults():
    covered = set()
    for fields, values in _model_table():
        # a pair takes two values, a field without a default value (None: "none", "from ...") none
        widths = [len(MODEL[f]) if isinstance(MODEL[f], tuple) else int(MODEL[f] is not None) for f in fields]
        assert len(values) >= sum(widths), (fields, values)
        for field, start, width in zip(fields, np.cumsum([0, *widths]), widths):
            if width == 0:
                continue
            value = values[start:start + width] if width > 1 else values[start]
            assert same(value, MODEL[field]), f"docs/reference/model.md §2: {field} = {value}, the dataclass says {MODEL[field]}"
        covered.update(fields)
    numeric = {f for f, v in MODEL.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    assert numeric <= covered, f"docs/reference/model.md §2 lacks {sorted(numeric - covered)}"


def _fmu_starts(fmi_version: int) -> dict:
    """name -> start of every parameter and n_points in the generated modelDescription (no binary built)."""
    cosimulation, model_exchange = interfaces(fmi_version, fv.MODEL_NAME, completed_integrator_step=True)
    n = JointParameters.n_points
    xml = (model_description_xml(n, "guid", "test", cosimulation, model_exchange, 1) if fmi_version == 2 else
           model_description_fmi3_xml(n, "token", "test", cosimulation, model_exchange))
    root = ET.fromstring(xml)
    starts = {}
    for element in root.find("ModelVariables"):
        typed = element if fmi_version == 3 else next(iter(element))
        if element.get("causality") in ("parameter", "structuralParameter", "local"):
            starts[element.get("name")] = typed.get("start")
    return starts


def _joint_value(p, joint: JointParameters):
    value = getattr(joint, p.field)
    if value is None:                  # the unset contact stiffness: the FMU's 0, "from the radii and materials"
        return 0.0
    return dict(p.choices)[value] if p.choices else value if p.component is None else value[p.component]


@pytest.mark.parametrize("fmi_version", FMI_VERSIONS)
def test_model_description_start_values_are_the_joint_defaults(fmi_version):
    starts = _fmu_starts(fmi_version)
    joint = JointParameters()
    for p in fv.PARAMETERS:
        assert same(starts[p.variable.name], _joint_value(p, joint)), p.variable.name
    assert same(starts[fv.N_POINTS_NAME], joint.n_points)


def test_model_md_fmu_table_states_the_start_values():
    text = (REPO / "docs" / "reference" / "fmu.md").read_text()
    section = text[text.index("## 5. "):text.index("### The state format")]
    by_name = {p.variable.name: p for p in fv.PARAMETERS}
    joint = JointParameters()
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 7 and cells[2] == "parameter":
            for name, start in zip(re.findall(r"`(\w+)`", cells[1]), cells[5].split(", ")):
                assert name in by_name, f"docs/reference/fmu.md §5 names {name}, not an FMU parameter"
                assert same(start, _joint_value(by_name[name], joint)), f"docs/reference/fmu.md §5: {name} starts at {start}"
