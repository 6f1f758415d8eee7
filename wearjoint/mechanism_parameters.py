"""The slider-crank's parameters: one table (:data:`MECHANISM_FIELDS`) and the parameter set built on it.

Each row of the table is one value the kernels read (a slot of the parameter vector, ``core.layout.MP_*``): its
:class:`SliderCrankParameters` field (and component, for gravity's two and the load table's rows), the
``SliderCrank`` FMU's parameter name, unit, description and allowed rule, and the scale from the user's unit
(rpm, degrees) to the kernels'.  The dataclass checks, the packed vector (:func:`field_vector`), the FMU's
parameters (:mod:`wearjoint.fmu.slider_crank`) and the command line's help come from it.
"""
from __future__ import annotations

import csv
import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .checks import ANY, Allowed, ParameterError, finite, finite_pair, is_real, of_type, require
from .core import layout as L

# allowed rules of a row (the FMU's checks are built from the same rules: fmu/slider_crank.py)
FINITE, LENGTH, ABOVE_CRANK, MASS, INERTIA, SPEED, ACCELERATION, FORCE, RATE, TABLE_ROWS, TABLE_ANGLE, CHOICE = (
    "finite", "length", "above-crank", "mass", "inertia", "speed", "acceleration", "force", "rate", "table-rows",
    "table-angle", "choice")
CLEARANCE_JOINTS = L.CLEARANCE_JOINTS     # the values of clearance_joint; the FMU's: their code (L.CHOICES)
# bounds no machine passes, so that no value the rules admit overflows the mechanism's arithmetic (a 1e300 kg crank
# left the ideal joint's force NaN; 1e300 m/s^2 of gravity made the joint FMU's inputs NaN): the SI values of the
# user's units (the crank speed in rpm); ABOVE_CRANK's ``above`` is the FMU's name of the crank length
RULES = {FINITE: ANY, LENGTH: Allowed(1e-6, False, 100.0, note="m"),
         ABOVE_CRANK: Allowed(1e-6, False, 100.0, above="crank_length", note="m"),
         MASS: Allowed(1e-6, False, 1e6, note="kg"), INERTIA: Allowed(1e-12, False, 1e6, note="kg.m2"),
         SPEED: Allowed(1e-3, False, 1e5, note="rpm"), ACCELERATION: Allowed(-1e4, False, 1e4),
         FORCE: Allowed(-1e9, False, 1e9), RATE: Allowed(0.0, False, 1e6, note="1/s"),
         TABLE_ROWS: Allowed(0.0, high=float(L.MAX_LOAD_ROWS)), TABLE_ANGLE: Allowed(0.0, high=360.0),
         CHOICE: Allowed(0.0, high=float(len(L.CLEARANCE_JOINTS) - 1))}
RULE_TEXT = {**{rule: allowed.text() for rule, allowed in RULES.items()},
             ABOVE_CRANK: f"{RULES[LENGTH].text()} and > crank_length_m (the crank must turn fully)",
             TABLE_ROWS: f"0 (no table) or an integer from 2 to {L.MAX_LOAD_ROWS}", TABLE_ANGLE: "in [0, 360] deg",
             CHOICE: ", ".join(f"{code} ({name})" for name, code in L.CHOICES["clearance_joint"])}


@dataclass(frozen=True)
class MechanismField:
    """One slot of the kernels' mechanism parameters: where its value comes from and how it is named."""

    field: str                  # the SliderCrankParameters field
    fmu_name: str               # the SliderCrank FMU's parameter
    unit: str                   # the FMU's unit (the user's: rpm, deg)
    text: str                   # what it is (FMU description, CLI help)
    rule: str                   # RULE_TEXT key
    slot: int                   # core.layout.MP_*
    scale: float = 1.0          # user unit -> the kernels' SI unit: times scale, then over divisor
    divisor: float = 1.0
    component: int | None = None  # the element of a pair (gravity) or of the load table
    choices: tuple[str, ...] | None = None  # CHOICE: the field's values, the FMU's value their index


_DEG = math.pi / 180.0
_SCALARS = (
    MechanismField("crank_length_m", "crank_length", "m", "crank length l1 (Table 1)", LENGTH, L.MP_CRANK_LENGTH),
    MechanismField("crank_mass_kg", "crank_mass", "kg", "crank mass m1", MASS, L.MP_CRANK_MASS),
    MechanismField("crank_inertia_kg_m2", "crank_inertia", "kg.m2",
                   "crank moment of inertia I1 about its centre of mass", INERTIA, L.MP_CRANK_INERTIA),
    MechanismField("rod_length_m", "rod_length", "m", "connecting rod length l2 (> crank_length)", ABOVE_CRANK,
                   L.MP_ROD_LENGTH),
    MechanismField("rod_mass_kg", "rod_mass", "kg", "rod mass m2", MASS, L.MP_ROD_MASS),
    MechanismField("rod_inertia_kg_m2", "rod_inertia", "kg.m2", "rod moment of inertia I2 about its centre of mass",
                   INERTIA, L.MP_ROD_INERTIA),
    MechanismField("slider_mass_kg", "slider_mass", "kg", "slider mass m3", MASS, L.MP_SLIDER_MASS),
    MechanismField("slider_inertia_kg_m2", "slider_inertia", "kg.m2", "slider moment of inertia I3", INERTIA,
                   L.MP_SLIDER_INERTIA),
    MechanismField("crank_speed_rpm", "crank_speed", "rpm", "crank speed (clockwise)", SPEED, L.MP_OMEGA,
                   2.0 * math.pi, 60.0),
    MechanismField("initial_crank_angle_deg", "initial_crank_angle", "deg",
                   "crank angle theta0 at t = 0 (theta1 = theta0 - omega t, Eq. 39)", FINITE, L.MP_THETA0, _DEG),
    MechanismField("gravity_m_s2", "gravity_x", "m/s2", "gravity along the slider's axis x (towards the slider: "
                   "> 0)", ACCELERATION, L.MP_GRAVITY_X, component=0),
    MechanismField("gravity_m_s2", "gravity_y", "m/s2", "gravity across the slide (the paper's: -9.81)", ACCELERATION,
                   L.MP_GRAVITY_Y, component=1),
    MechanismField("baumgarte_alpha", "baumgarte_alpha", "1/s", "Baumgarte alpha (Eq. 44 stabilisation)",
                   RATE, L.MP_ALPHA),
    MechanismField("baumgarte_beta", "baumgarte_beta", "1/s", "Baumgarte beta (Eq. 44 stabilisation)",
                   RATE, L.MP_BETA),
    MechanismField("slider_force_N", "slider_force_constant", "N", "constant load on the slider along its axis, "
                   "positive towards the crank's pivot (compressing the rod)", FORCE, L.MP_SLIDER_FORCE),
    MechanismField("slider_force_table", "slider_force_table_rows", "1", "rows of the slider-load table (0: none)",
                   TABLE_ROWS, L.MP_LOAD_ROWS),
    MechanismField("clearance_joint", "clearance_joint", "1", "the joint with the clearance: "
                   f"{RULE_TEXT[CHOICE]}; the other two are ideal", CHOICE, L.MP_CLEARANCE_JOINT,
                   choices=CLEARANCE_JOINTS),
)
_TABLE = tuple(
    MechanismField("slider_force_table", f"slider_force_table_angle_{k + 1}", "deg",
                   f"slider-load table, row {k + 1}: crank angle theta1 mod 360", TABLE_ANGLE, L.MP_LOAD_ANGLES + k,
                   _DEG, component=k) for k in range(L.MAX_LOAD_ROWS)) + tuple(
    MechanismField("slider_force_table", f"slider_force_table_force_{k + 1}", "N",
                   f"slider-load table, row {k + 1}: load, positive towards the crank's pivot", FORCE,
                   L.MP_LOAD_FORCES + k, component=k) for k in range(L.MAX_LOAD_ROWS))
# every slot the fields fill, in slot order (the FMU's parameter order)
MECHANISM_FIELDS: tuple[MechanismField, ...] = tuple(sorted(_SCALARS + _TABLE, key=lambda f: f.slot))
if [f.slot for f in MECHANISM_FIELDS] != list(range(L.N_MECHANISM_FIELDS)):
    raise RuntimeError("MECHANISM_FIELDS does not fill core.layout's mechanism slots once each")
# user unit -> kernel unit of each slot, value * scale / divisor (core.slider_load.mechanism_parameter_vector): rpm as
# n 2 pi / 60, degrees as math.radians (the arithmetic the parameter set's own properties use, to the last bit)
FIELD_SCALES = np.array([[f.scale for f in MECHANISM_FIELDS], [f.divisor for f in MECHANISM_FIELDS]])
PAPER_GRAVITY_M_S2 = 9.81
# what is wrong with a slider-load table, by core.slider_load.load_table_problem's kind (the FMU logs the same words)
LOAD_TABLE_PROBLEMS = {
    L.LOAD_TABLE_ROWS: f"allowed a whole number of rows from 2 to {L.MAX_LOAD_ROWS} (0: no table)",
    L.LOAD_TABLE_START: "the first row is not at 0 deg: the table covers the revolution from 0 to 360 deg",
    L.LOAD_TABLE_END: "the last row is not at 360 deg: the table covers the revolution from 0 to 360 deg",
    L.LOAD_TABLE_RISE: "the crank angle does not rise above the row before's: the angles rise strictly from 0 to "
                       "360 deg",
    L.LOAD_TABLE_PERIODIC: "the load at 360 deg differs from the load at 0 deg: the table is periodic",
}


@dataclass(frozen=True)
class SliderForceTable:
    """A load on the slider over one crank revolution [N], positive towards the crank's pivot, linearly
    interpolated in the crank angle theta1 mod 360 (the mechanism's angle: 0 with the crank pointing at the
    slider, the slider farthest out; theta1 falls as the crank turns clockwise).  The angles rise strictly from
    0 to 360 and the 360 row repeats the 0 row's load (the table is periodic); at most ``MAX_LOAD_ROWS`` rows.
    ``source`` names where it came from (a file) in messages."""

    crank_angle_deg: tuple[float, ...]
    force_N: tuple[float, ...]
    source: str = dataclasses.field(default="slider_force_table", compare=False)   # the file, not the load

    def __post_init__(self):
        angles = tuple(self.crank_angle_deg)
        forces = tuple(self.force_N)
        where = self.source
        if len(angles) != len(forces):
            raise ParameterError(f"{where}: {len(angles)} angles for {len(forces)} loads")
        if not 2 <= len(angles) <= L.MAX_LOAD_ROWS:
            raise ParameterError(f"{where}: {len(angles)} row{'' if len(angles) == 1 else 's'}: "
                                 f"{LOAD_TABLE_PROBLEMS[L.LOAD_TABLE_ROWS]}")
        for row, (angle, force) in enumerate(zip(angles, forces), start=1):
            for name, value in (("crank_angle_deg", angle), ("force_N", force)):
                if not (is_real(value) and math.isfinite(value)):
                    raise ParameterError(f"{where}, row {row}: {name}={value!r} is not a finite number")
            if not RULES[FORCE].admits(force, {}):
                raise ParameterError(f"{where}, row {row}: force_N={force!r} is invalid: allowed {RULES[FORCE].text()}")
        fields = np.zeros(L.N_MECHANISM_FIELDS)
        fields[L.MP_LOAD_ROWS] = len(angles)
        fields[L.MP_LOAD_ANGLES:L.MP_LOAD_ANGLES + len(angles)] = angles
        fields[L.MP_LOAD_FORCES:L.MP_LOAD_FORCES + len(forces)] = forces
        from .core.slider_load import load_table_problem    # the kernels only where a table is given

        problem = load_table_problem(fields)
        if problem:
            kind, row = divmod(problem, L.LOAD_TABLE_ROW_BASE)
            value = (f"force_N={forces[row - 1]!r}" if kind == L.LOAD_TABLE_PERIODIC
                     else f"crank_angle_deg={angles[row - 1]!r}")
            raise ParameterError(f"{where}, row {row}: {value}: {LOAD_TABLE_PROBLEMS[kind]}")
        object.__setattr__(self, "crank_angle_deg", tuple(float(a) for a in angles))
        object.__setattr__(self, "force_N", tuple(float(f) for f in forces))

    @classmethod
    def from_csv(cls, path) -> "SliderForceTable":
        """The table in CSV file ``path``: a header ``crank_angle_deg,force_N`` and one row per angle."""
        path = Path(path)
        invalid = f"parameter slider_force_table={str(path)!r} is invalid"     # the CLI names its option there
        refused = f"{invalid}: allowed a text CSV file"
        try:
            with open(path, newline="", encoding="utf-8-sig") as f:     # a spreadsheet's byte-order mark dropped
                rows = list(csv.reader(f))
        except OSError as error:
            raise ParameterError(f"{refused}; cannot read it ({error.strerror})") from None
        except UnicodeDecodeError as error:
            raise ParameterError(f"{refused} (UTF-8); byte {error.start + 1} is not UTF-8 text") from None
        except csv.Error as error:
            raise ParameterError(f"{refused}; it is not one ({error})") from None
        header = [c.strip() for c in rows[0]] if rows else []
        if header != ["crank_angle_deg", "force_N"]:
            raise ParameterError(f"{invalid}: line 1: header {','.join(header)!r}: allowed "
                                 "'crank_angle_deg,force_N'")
        angles, forces = [], []
        for line, row in enumerate(rows[1:], start=2):
            if not row or all(not c.strip() for c in row):
                continue
            if len(row) != 2:
                raise ParameterError(f"{invalid}: line {line}: {len(row)} columns: allowed 2 "
                                     "(crank_angle_deg,force_N)")
            values = []
            for name, text in zip(("crank_angle_deg", "force_N"), row):
                try:
                    values.append(float(text))
                except ValueError:
                    raise ParameterError(f"{invalid}: line {line}: {name}={text.strip()!r} is not a number") \
                        from None
            angles.append(values[0])
            forces.append(values[1])
        if not angles:
            raise ParameterError(f"{invalid}: no rows after the header: allowed 2 to "
                                 f"{L.MAX_LOAD_ROWS} rows, crank angles rising from 0 to 360 deg")
        source = f"slider force table {path}"
        try:
            return cls(tuple(angles), tuple(forces), source=source)
        except ParameterError as error:     # rows of the table as lines of the file (the header is line 1)
            problem = _rows_as_lines(str(error), rows).removeprefix(source).lstrip(",: ")
            raise ParameterError(f"{invalid}: {problem}") from None

    def to_dict(self) -> dict:
        return {"crank_angle_deg": list(self.crank_angle_deg), "force_N": list(self.force_N), "source": self.source}


def same_setting(name: str, a, b) -> bool:
    """Are two mechanism dicts' values of field ``name`` (``to_dict``'s, as JSON reads them back) the same
    setting: a load table's rows, whichever file they were read from (its ``source``)?"""
    if name == "slider_force_table" and isinstance(a, dict) and isinstance(b, dict):
        a, b = ({k: v for k, v in table.items() if k != "source"} for table in (a, b))
    return a == b


def _rows_as_lines(message: str, rows: list) -> str:
    """``..., row R: ...`` of a table read from a file as ``..., line L: ...`` (L counts the header and blank lines)."""
    head, sep, tail = message.partition(", row ")
    if not sep:
        return message
    number, _, rest = tail.partition(":")
    data_lines = [i for i, row in enumerate(rows[1:], start=2) if row and any(c.strip() for c in row)]
    return f"{head}, line {data_lines[int(number) - 1]}:{rest}"


def _gravity_pair(value) -> tuple[float, float]:
    """Gravity [m/s^2] as (g_x, g_y) in the mechanism's frame: a pair as given, a single value g as (0, -g)
    (its magnitude across the slide, the paper's convention: a negative one, which would point gravity up, is
    refused; the pair says that)."""
    bound = RULES[ACCELERATION].high
    allowed = (f"one finite value g in [0, {bound:g}] (its magnitude, pointing along -y) or a pair (g_x, g_y) of "
               f"finite values in [-{bound:g}, {bound:g}] (pointing up: 0,G)")
    if is_real(value):
        require("gravity_m_s2", value, math.isfinite(value) and 0.0 <= value <= bound, allowed)
        return 0.0, 0.0 - float(value)        # (0 - g: g = 0 is +0, not -0)
    pair = finite_pair("gravity_m_s2", value, allowed)
    require("gravity_m_s2", value, max(abs(pair[0]), abs(pair[1])) <= bound, allowed)
    return pair


@dataclass(frozen=True)
class SliderCrankParameters:
    """The paper's slider-crank (Table 1, Eqs. 38-44), crank driven clockwise, with the user's loads.

    ``theta1(t) = initial_crank_angle - omega t`` with omega from ``crank_speed_rpm``.  The clearance
    joint is ``clearance_joint``: ``crank-rod`` (the crank's tip in the rod's big end, the paper's),
    ``rod-slider`` (the slider's pin in the rod's small end) or ``crank-ground`` (the crank's journal in a
    bushing fixed at the pivot); the other two joints are ideal; its body-frame offsets follow from the
    lengths (:meth:`joint_offsets`).  ``gravity_m_s2``: a pair (g_x, g_y) in the mechanism's frame (x along the slider's
    axis, from the crank's pivot towards the slider), or one value g for (0, -g).  The slider carries
    ``slider_force_N`` plus ``slider_force_table`` (a :class:`SliderForceTable`), positive towards the
    crank's pivot.
    """

    crank_length_m: float = 0.050
    crank_mass_kg: float = 3.0
    crank_inertia_kg_m2: float = 7.36e-3
    rod_length_m: float = 0.220
    rod_mass_kg: float = 0.19
    rod_inertia_kg_m2: float = 8.8e-4
    slider_mass_kg: float = 0.70
    slider_inertia_kg_m2: float = 3.6e-4
    crank_speed_rpm: float = 150.0
    initial_crank_angle_deg: float = 0.0
    gravity_m_s2: tuple[float, float] = (0.0, -PAPER_GRAVITY_M_S2)
    baumgarte_alpha: float = 5.0
    baumgarte_beta: float = 5.0
    slider_force_N: float = 0.0
    slider_force_table: SliderForceTable | None = None
    clearance_joint: str = "crank-rod"

    def __post_init__(self):
        """The rules of :data:`MECHANISM_FIELDS` (the FMU's too): a real value an int, a float or a numpy real scalar
        (kept as a float)."""
        object.__setattr__(self, "gravity_m_s2", _gravity_pair(self.gravity_m_s2))
        for f in _SCALARS:
            if f.component is not None or f.field == "slider_force_table":
                continue
            value = getattr(self, f.field)
            if f.rule == CHOICE:
                require(f.field, value, value in f.choices, " or ".join(repr(c) for c in f.choices))
                continue
            allowed = RULES[LENGTH if f.rule == ABOVE_CRANK else f.rule]    # the crank's below
            x = finite(f.field, value, "" if allowed.low is None else allowed.text())
            require(f.field, value, allowed.admits(x, {}), allowed.text())
            object.__setattr__(self, f.field, x)
        require("rod_length_m", self.rod_length_m, self.rod_length_m > self.crank_length_m,
                f"> crank_length_m = {self.crank_length_m!r} (the crank must turn fully)")
        of_type("slider_force_table", self.slider_force_table, SliderForceTable,
                "no table; SliderForceTable.from_csv(path) reads a file")

    @property
    def omega_rad_s(self) -> float:
        """Crank speed magnitude [rad/s]; the crank turns clockwise."""
        return self.crank_speed_rpm * 2.0 * math.pi / 60.0

    @property
    def loaded(self) -> bool:
        """True where the slider carries a load (constant or table)."""
        return self.slider_force_N != 0.0 or self.slider_force_table is not None

    @property
    def clearance_location(self) -> int:
        """The clearance joint's location code (core.layout.CLEARANCE_*)."""
        return L.choice_code("clearance_joint", self.clearance_joint)

    def sliding_speed_bound_m_s(self, joint) -> float:
        """Bound on the sliding speed in the clearance joint [m/s]: R_j |omega_pin - omega_bushing| with the
        rod's rate at most omega l1 / (l2 - l1) (the slider and the ground do not turn)."""
        rod_rate = self.crank_length_m / (self.rod_length_m - self.crank_length_m)
        relative = {L.CLEARANCE_CRANK_ROD: 1.0 + rod_rate, L.CLEARANCE_ROD_SLIDER: rod_rate,
                    L.CLEARANCE_CRANK_GROUND: 1.0}[self.clearance_location]
        return joint.bushing_radius_m * self.omega_rad_s * relative

    @property
    def period_s(self) -> float:
        """Duration of one crank revolution [s]."""
        return 2.0 * math.pi / self.omega_rad_s

    @property
    def contact_effective_mass_kg(self) -> float:
        """The mass [kg] the clearance joint decelerates along the rod at the dead centres (the crank's rotation
        is driven): rod and slider at the crank-rod joint, the slider at the rod-slider joint (the rod's end
        follows the crank), all three bodies at the crank-ground joint; the Tsuji damping's effective mass for
        this mechanism (docs/reference/model.md §3.5)."""
        return {L.CLEARANCE_CRANK_ROD: self.rod_mass_kg + self.slider_mass_kg,
                L.CLEARANCE_ROD_SLIDER: self.slider_mass_kg,
                L.CLEARANCE_CRANK_GROUND: self.crank_mass_kg + self.rod_mass_kg + self.slider_mass_kg,
                }[self.clearance_location]

    @property
    def rod_across_mass_kg(self) -> float:
        """The mass [kg] the clearance joint decelerates across the rod: the rod's end turning about its other
        end, (I2 + m2 l2^2 / 4) / l2^2, plus the crank's mass at the crank-ground joint (the slider cannot move
        across the slide; the smallest effective mass at the joint for the paper's proportions)."""
        length = self.rod_length_m
        rod = (self.rod_inertia_kg_m2 + 0.25 * self.rod_mass_kg * length * length) / (length * length)
        return rod + (self.crank_mass_kg if self.clearance_location == L.CLEARANCE_CRANK_GROUND else 0.0)

    def joint_defaults(self) -> dict:
        """The joint's values this mechanism sets unless given: the centres (:meth:`joint_offsets`) and the
        contact's effective mass."""
        return {**self.joint_offsets(), "effective_mass_kg": self.contact_effective_mass_kg}

    def joint_offsets(self) -> dict:
        """Pin and bushing centres in their bodies' frames (docs/reference/model.md §1): the crank's tip and the rod's big
        end (crank-rod), the slider's centre and the rod's small end (rod-slider), the crank's pivot end and the
        frame's origin (crank-ground)."""
        l1 = self.crank_length_m
        l2 = self.rod_length_m
        return {L.CLEARANCE_CRANK_ROD: {"pin_offset_m": (0.5 * l1, 0.0), "bushing_offset_m": (-0.5 * l2, 0.0)},
                L.CLEARANCE_ROD_SLIDER: {"pin_offset_m": (0.0, 0.0), "bushing_offset_m": (0.5 * l2, 0.0)},
                L.CLEARANCE_CRANK_GROUND: {"pin_offset_m": (-0.5 * l1, 0.0), "bushing_offset_m": (0.0, 0.0)},
                }[self.clearance_location]

    def replace(self, **changes) -> "SliderCrankParameters":
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        d["gravity_m_s2"] = list(self.gravity_m_s2)
        table = self.slider_force_table
        d["slider_force_table"] = table.to_dict() if table is not None else None
        return d

    @classmethod
    def from_dict(cls, values: dict) -> "SliderCrankParameters":
        """The inverse of :meth:`to_dict` (a results folder's ``mechanism``)."""
        values = dict(values)
        table = values.get("slider_force_table")
        if isinstance(table, dict):
            values["slider_force_table"] = SliderForceTable(table["crank_angle_deg"], table["force_N"],
                                                            table.get("source", "slider_force_table"))
        return cls(**values)


def mechanism_from_options(options: dict) -> SliderCrankParameters:
    """The parameter set of a command's options by field name (None: not given); ``slider_force_table`` a CSV
    file's path (:meth:`SliderForceTable.from_csv`) or a table."""
    values = {f.name: options[f.name] for f in dataclasses.fields(SliderCrankParameters)
              if options.get(f.name) is not None}
    table = values.get("slider_force_table")
    if table is not None and not isinstance(table, SliderForceTable):
        values["slider_force_table"] = SliderForceTable.from_csv(table)
    return SliderCrankParameters(**values)


def field_vector(p: SliderCrankParameters) -> np.ndarray:
    """The values of :data:`MECHANISM_FIELDS` for ``p`` in the user's units (the SliderCrank FMU's parameters,
    in its order); :func:`wearjoint.core.slider_load.mechanism_parameter_vector` scales them into the kernels'."""
    out = np.zeros(L.N_MECHANISM_FIELDS)
    table = p.slider_force_table
    for k, f in enumerate(MECHANISM_FIELDS):
        if f.field == "slider_force_table":
            if table is None:
                continue
            if f.slot == L.MP_LOAD_ROWS:
                out[k] = len(table.crank_angle_deg)
            elif f.component < len(table.crank_angle_deg):
                out[k] = (table.crank_angle_deg if f.slot < L.MP_LOAD_FORCES else table.force_N)[f.component]
        elif f.choices is not None:
            out[k] = L.choice_code(f.field, getattr(p, f.field))
        elif f.component is not None:
            out[k] = getattr(p, f.field)[f.component]
        else:
            out[k] = getattr(p, f.field)
    return out


__all__ = ["SliderCrankParameters", "SliderForceTable", "LOAD_TABLE_PROBLEMS", "MechanismField", "MECHANISM_FIELDS",
           "FIELD_SCALES", "field_vector", "mechanism_from_options", "RULE_TEXT", "PAPER_GRAVITY_M_S2", "CLEARANCE_JOINTS",
           "same_setting"]
