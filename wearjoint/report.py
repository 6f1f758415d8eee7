"""``report.html``: one self-contained page of a results folder a designer can forward (docs/reference/results.md §6).

The folder's summary (``summary.json``, or a sweep's ``sweep_summary.json``) as tables, every number as written
there (units in the key names; an entry that is a table, a validation's metrics, as a table of its own); the joint's
and the mechanism's parameters with where each came from (the default, or given; the wear coefficient's source as the
summary states it); a study's answer tables (:data:`ANSWER_TABLES`: a sweep's ensemble, a sensitivity study's
indices); every PNG of the folder embedded; the command line and the version that made it.  :func:`write_report` writes it; ``wearjoint report DIR``
(re)writes it for any results folder, and every command that writes a results folder writes it last.
"""
from __future__ import annotations

import base64
import csv
import dataclasses
import html
import json
import math
from pathlib import Path

from . import __version__
from .mechanism_parameters import SliderCrankParameters
from .parameters import JointParameters, paper_joint

REPORT_NAME = "report.html"
SUMMARY_FILES = ("summary.json", "sweep_summary.json")     # a run's or a study's, a sweep's
_STYLE = ("body{font-family:sans-serif;max-width:60em;margin:1em auto;color:#222}"
          "table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #ccc;padding:2px 8px;"
          "text-align:left;font-size:90%}td.number{text-align:right;font-family:monospace}"
          "img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}code{background:#f4f4f4;padding:1px 4px}")


def summary_path(out_dir) -> Path | None:
    """The folder's summary file (:data:`SUMMARY_FILES`), or None."""
    return next((Path(out_dir) / name for name in SUMMARY_FILES if (Path(out_dir) / name).is_file()), None)


def cell_text(value) -> str:
    """A summary value as the report's table writes it: numbers as ``repr`` (they read back exactly), None as
    an empty cell, lists and tables as JSON."""
    if value is None:
        return ""
    if isinstance(value, bool) or isinstance(value, str):
        return str(value)
    if isinstance(value, (int, float)):
        return repr(value) if not (isinstance(value, float) and math.isnan(value)) else "nan"
    return json.dumps(value)


def _table(rows, header, table_id) -> str:
    body = "".join(
        "<tr>" + "".join(f'<td class="{"number" if isinstance(v, (int, float)) and not isinstance(v, bool) else ""}">'
                         f"{html.escape(cell_text(v))}</td>" for v in row) + "</tr>" for row in rows)
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    return f'<table id="{table_id}"><tr>{head}</tr>{body}</table>'


# the summary's entries the page shows in sections of their own (or not: the figures are embedded)
_OWN_SECTIONS = ("parameters", "case_parameters", "parameter_spread", "command_line", "figures")


def _is_cell(value) -> bool:
    """A value one table cell holds (a list of values as JSON)."""
    if isinstance(value, list):
        return all(_is_cell(v) and not isinstance(v, list) for v in value)
    return value is None or isinstance(value, (bool, int, float, str))


def _entry_section(key: str, value) -> str:
    """A summary entry that is not one value (a validation's metrics, a study's per-revolution table): a list of
    records as a table with a column per key, a dict of values as (quantity, value) rows, a dict of such dicts as a
    table with a row per entry, a list of values as one line; anything else as its JSON, folded."""
    title, table_id = f"<h3>{html.escape(key)}</h3>", f"summary-{key}"
    if not value:
        return title + "<p>none</p>"
    if isinstance(value, list) and all(isinstance(row, dict) for row in value):
        columns = list(dict.fromkeys(name for row in value for name in row))
        return title + _table([[row.get(c) for c in columns] for row in value], columns, table_id)
    if isinstance(value, dict) and all(_is_cell(v) for v in value.values()):
        return title + _table(list(value.items()), ("quantity", "value"), table_id)
    if isinstance(value, dict) and all(isinstance(row, dict) and all(_is_cell(v) for v in row.values())
                                       for row in value.values()):
        columns = list(dict.fromkeys(name for row in value.values() for name in row))
        return title + _table([[name, *(row.get(c) for c in columns)] for name, row in value.items()],
                              ("", *columns), table_id)
    if isinstance(value, list) and _is_cell(value):
        return title + f"<p>{html.escape(', '.join(cell_text(v) for v in value))}</p>"
    return (title + f"<details><summary>as in the summary (JSON)</summary><pre>"
                    f"{html.escape(json.dumps(value, indent=1))}</pre></details>")


def _parameter_rows(given: dict, defaults, sources: dict | None = None, derived=(), written=frozenset(),
                    resolved: dict | None = None) -> list:
    """(name, value, where it came from) of a parameter set's dict against the dataclass ``defaults`` (``sources``:
    name -> where a value that is not the default came from, where that is not the user's option; ``derived``: the
    names whose default follows the mechanism: "from the mechanism"; ``written``: the options the command line
    wrote, "given" even at the default; ``resolved``: name -> (the value a run derived for an unset one, whence))."""
    reference = defaults.to_dict() if hasattr(defaults, "to_dict") else dataclasses.asdict(defaults)

    def row(name, value):
        if value is None and name in (resolved or {}):
            return (name, *resolved[name])
        if f"--{name.replace('_', '-')}" in written:
            return name, value, "given"
        if json.loads(json.dumps(reference.get(name))) == value:
            return name, value, "from the mechanism" if name in derived else "default"
        return name, value, (sources or {}).get(name, "given")
    return [row(name, value) for name, value in given.items()]


def _joint_defaults(parameters: dict):
    """(the joint's defaults in the summary's mechanism, the names among them its mechanism sets): the paper's joint
    with that mechanism's offsets and effective mass (:func:`paper_joint`; a run's joint takes them from its
    mechanism unless given)."""
    try:
        mechanism = SliderCrankParameters.from_dict(parameters["mechanism"])
        return paper_joint(mechanism), tuple(mechanism.joint_defaults())
    except (KeyError, TypeError, ValueError):
        return JointParameters(), ()


# a study's answer that its summary leaves to a table file: a sweep's mean, spread and bias per grid point, a
# sensitivity study's indices with their intervals (a new user's reports held counts and timings alone)
ANSWER_TABLES = ("ensemble.csv", "indices.csv")
MAX_TABLE_ROWS = 500


def _answer_table(name: str, rows: list[list[str]]) -> str:
    """A table file's rows (the first its header) as a section of the page, at most MAX_TABLE_ROWS of them."""
    header, body = rows[0], rows[1:]
    shown = body[:MAX_TABLE_ROWS]
    more = (f"<p>{len(body) - len(shown)} more rows in {html.escape(name)}</p>" if len(body) > len(shown) else "")
    return f"<h2>{html.escape(name)}</h2>" + _table(shown, header, f"table-{name}") + more


def report_html(summary: dict, figures: list[tuple[str, bytes]], title: str,
                tables: list[tuple[str, list]] = ()) -> str:
    """The page: ``summary`` (a summary.json's content), ``figures`` (name, PNG bytes), ``title``; ``tables``: (file
    name, its rows as text, the header first) of :data:`ANSWER_TABLES`."""
    scalars = [(k, v) for k, v in summary.items() if not isinstance(v, (dict, list)) and k != "command_line"]
    # a run's joint and mechanism; a sweep's or a sensitivity study's (whose "parameters" are its sampled ones): their
    # cases' (``case_parameters`` with ``parameter_spread``, :func:`wearjoint.sweep.report.parameter_spread`)
    parameters = next((p for p in (summary.get("parameters"), summary.get("case_parameters")) if isinstance(p, dict)),
                      {})
    parts = [f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
             f"<style>{_STYLE}</style></head><body><h1>{html.escape(title)}</h1>"]
    command = summary.get("command_line")
    parts.append(f"<p>Made by <code>{html.escape(command)}</code>" if command else "<p>Made through the API")
    parts.append(f" with wearjoint {html.escape(str(summary.get('wearjoint_version', __version__)))}.</p>")
    if summary.get("completed") is False or summary.get("failure"):
        parts.append(f"<p><strong>The run did not complete:</strong> {html.escape(str(summary.get('failure') or 'stopped'))}</p>")
    parts.append("<h2>Summary</h2><p>Units are in the names (docs/reference/results.md §6).</p>")
    parts.append(_table(scalars, ("quantity", "value"), "summary"))
    parts += [_entry_section(k, v) for k, v in summary.items()
              if isinstance(v, (dict, list))
              and (k not in _OWN_SECTIONS or k == "parameters" and not isinstance(v, dict))]
    parts += [_answer_table(name, rows) for name, rows in tables if rows]
    source = str(summary.get("wear_coefficient_source", ""))
    sources = {"wear_coefficient_m2_N": source} if source.startswith("calibration") else {}
    spread = summary.get("parameter_spread")          # {name: [its values over the cases, whence]}
    spread = ({k: v for k, v in spread.items() if isinstance(v, list) and len(v) == 2} if isinstance(spread, dict)
              else {})
    sources.update({name: whence for name, (_, whence) in spread.items()})
    joint_defaults, derived = _joint_defaults(parameters)
    written = {token.split("=", 1)[0] for token in str(command or "").split() if token.startswith("--")}
    stiffness = summary.get("contact_stiffness_N_m1_5")
    resolved = {"contact_stiffness_N_m1_5": (stiffness, "from the radii and materials")} if stiffness else {}
    for label, key, defaults in (("Joint", "joint", joint_defaults),
                                 ("Mechanism", "mechanism", SliderCrankParameters())):
        if isinstance(parameters.get(key), dict):
            parts.append(f"<h2>{label} parameters</h2>")
            if key == "joint" and "wear_coefficient_source" in summary:
                parts.append(f"<p>The wear coefficient: {html.escape(source)}"
                             f"{'. ' + html.escape(str(summary['wear_coefficient_note'])) if summary.get('wear_coefficient_note') else ''}</p>")
            joint = key == "joint"
            given = {name: spread[name][0] if name in spread else value for name, value in parameters[key].items()}
            parts.append(_table(_parameter_rows(given, defaults, sources,
                                                derived if joint else (), written, resolved if joint else None),
                                ("parameter", "value", "from"), key))
    for name, data in figures:
        encoded = base64.b64encode(data).decode("ascii")
        parts.append(f'<h3>{html.escape(name)}</h3><img alt="{html.escape(name)}" src="data:image/png;base64,{encoded}">')
    parts.append("</body></html>")
    return "".join(parts)


def json_values(obj):
    """``obj`` with only values JSON holds: numpy's as Python's, paths as text, a number that is not finite (NaN, inf:
    JSON has none) as None; TypeError naming any other type."""
    if isinstance(obj, dict):
        return {key: json_values(value) for key, value in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_values(value) for value in obj]
    if hasattr(obj, "tolist") and hasattr(obj, "dtype"):       # a numpy scalar or array
        return json_values(obj.tolist())
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if obj is None or isinstance(obj, (str, int, float)):
        return obj
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def write_report(out_dir, command_line: str | None = None, facts: dict | None = None) -> Path:
    """Write ``report.html`` into the results folder ``out_dir`` (its summary and PNGs); ``command_line``: the
    command that made it, recorded into the summary too (with the version and ``facts``, entries the command
    knows of the run: where k_w came from).  Returns the page's path; FileNotFoundError without a summary,
    ValueError where it is not a JSON object."""
    out = Path(out_dir)
    path = summary_path(out)
    if path is None:
        raise FileNotFoundError(f"{out}: no {' or '.join(SUMMARY_FILES)}: not a results folder")
    try:
        summary = json.loads(path.read_text())
        why = None if isinstance(summary, dict) else "not a JSON object"
    except ValueError as exc:     # not JSON (a run killed while writing it, another file under its name)
        why = f"not JSON ({exc})"
    if why is not None:
        raise ValueError(f"{path} is invalid: {why}; rerun the command that wrote it")
    if command_line is not None:
        summary.update(command_line=command_line, wearjoint_version=__version__, **(facts or {}))
        tmp = path.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(json_values(summary), indent=2, allow_nan=False))
        tmp.replace(path)
    figures = [(png.name, png.read_bytes()) for png in sorted(out.glob("*.png"))]
    page = out / REPORT_NAME
    tmp = page.with_suffix(".html.tmp")
    tables = []
    for name in ANSWER_TABLES:
        try:
            with open(out / name, newline="") as file:
                tables.append((name, list(csv.reader(file))))
        except OSError:          # none in this folder
            pass
    tmp.write_text(report_html(summary, figures, f"wearjoint results: {out.name}", tables), encoding="utf-8")
    tmp.replace(page)
    return page


__all__ = ["REPORT_NAME", "SUMMARY_FILES", "ANSWER_TABLES", "cell_text", "json_values", "report_html", "summary_path",
           "write_report"]
