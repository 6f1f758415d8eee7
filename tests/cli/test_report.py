"""report.html (wearjoint.report): every results folder a command writes carries one self-contained page: the
summary's numbers exactly as summary.json has them, the parameters and where each came from, the figures embedded,
the command line and version; `wearjoint report DIR` rewrites it (a sweep's folder too)."""
import json
import math
from html.parser import HTMLParser

import pytest

from wearjoint import __version__
from wearjoint.cli import main
from wearjoint.report import REPORT_NAME


class Tables(HTMLParser):
    """The page's tables by id (rows of cell texts) and its embedded images (their data URIs)."""

    def __init__(self, text):
        super().__init__()
        self.tables, self.images, self._table, self._row, self._cell = {}, [], None, None, None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "table":
            self._table = self.tables.setdefault(attrs.get("id"), [])
        elif tag == "tr":
            self._row = []
        elif tag == "td":
            self._cell = ""
        elif tag == "img":
            self.images.append(attrs["src"])

    def handle_endtag(self, tag):
        if tag == "td":
            self._row.append(self._cell)
            self._cell = None
        elif tag == "tr" and self._row:
            self._table.append(self._row)
        elif tag == "table":
            self._table = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "run"
    assert main(["simulate", "--revolutions", "0.3", "--slider-force-N", "250", "--quiet", "--out", str(out)]) == 0
    return out


def test_every_number_of_the_summary_is_in_the_report_as_written(folder):
    summary = json.loads((folder / "summary.json").read_text())
    page = Tables((folder / REPORT_NAME).read_text(encoding="utf-8"))
    rows = dict(page.tables["summary"])
    numbers = {k: v for k, v in summary.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    assert len(numbers) > 20
    for key, value in numbers.items():
        shown = float(rows[key])
        assert shown == value or (math.isnan(value) and math.isnan(shown)), key
    assert rows["completed"] == "True"
    assert summary["command_line"].startswith("wearjoint simulate --revolutions 0.3 --slider-force-N 250")
    assert summary["wearjoint_version"] == __version__
    text = (folder / REPORT_NAME).read_text(encoding="utf-8")
    assert summary["command_line"] in text


def test_the_parameters_say_where_they_came_from_and_the_figures_are_embedded(folder):
    summary = json.loads((folder / "summary.json").read_text())
    page = Tables((folder / REPORT_NAME).read_text(encoding="utf-8"))
    mechanism = {name: (value, source) for name, value, source in page.tables["mechanism"]}
    assert mechanism["slider_force_N"] == ("250.0", "given") and mechanism["crank_length_m"][1] == "default"
    joint = {name: source for name, _, source in page.tables["joint"]}
    assert joint["pin_radius_m"] == "default"
    pngs = sorted(p.name for p in folder.glob("*.png"))
    assert len(pngs) == len(summary["figures"]) >= 4
    assert len(page.images) == len(pngs) and all(src.startswith("data:image/png;base64,") for src in page.images)


def test_a_joints_values_its_mechanism_sets_are_defaults_and_a_calibrated_k_w_names_its_source(tmp_path):
    """A rod-slider joint's offsets and effective mass come from its mechanism, and say so (they were marked
    "given", then "default" though another rod length moves them); a k_w from --calibration DIR says so (it was
    "given")."""
    calibration = tmp_path / "cal"
    calibration.mkdir()
    (calibration / "calibration.json").write_text(json.dumps({"law": "archard", "wear_coefficient_m2_N": 3.5e-13}))
    out = tmp_path / "run"
    assert main(["simulate", "--revolutions", "0.01", "--clearance-joint", "rod-slider", "--calibration",
                 str(calibration), "--quiet", "--no-plots", "--out", str(out)]) == 0
    page = Tables((out / REPORT_NAME).read_text(encoding="utf-8"))
    joint = {name: source for name, _, source in page.tables["joint"]}
    assert joint["pin_offset_m"] == joint["bushing_offset_m"] == joint["effective_mass_kg"] == "from the mechanism"
    assert joint["pin_radius_m"] == "default"
    assert joint["wear_coefficient_m2_N"] == f"calibration {calibration}"
    mechanism = {name: source for name, _, source in page.tables["mechanism"]}
    assert mechanism["clearance_joint"] == "given"


def test_the_report_command_rewrites_a_folder_and_refuses_one_without_a_summary(folder, tmp_path, capsys):
    (folder / REPORT_NAME).unlink()
    assert main(["report", str(folder)]) == 0 and (folder / REPORT_NAME).is_file()
    assert main(["report", str(tmp_path)]) == 2
    assert "not a results folder" in capsys.readouterr().err


def test_a_summarys_tables_are_tables_of_the_page(tmp_path):
    """A validation's metrics (a list of records), its per-engine verdicts (a dict of records), a plan (a dict of
    values): the page showed only the summary's single numbers, so its verdict table was missing."""
    from wearjoint.report import write_report

    summary = {"passed": False, "metrics_failed": ["cosim: impacts"], "gaps": [],
               "metrics": [{"name": "impacts", "value": 12.5, "tolerance": 2.0, "passed": False},
                           {"name": "contact_fraction", "value": 0.25, "passed": True, "scatter_values": [0.2, 0.3]}],
               "engines": {"cosim": {"metrics": 2, "failed": 1}, "exudyn": {"metrics": 3, "failed": 0}},
               "plan": {"revolutions": 0.1, "engines": ["cosim", "exudyn"]},
               "odd": {"nested": {"deeper": {"x": 1}}}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    page = Tables(write_report(tmp_path).read_text(encoding="utf-8"))
    assert page.tables["summary-metrics"] == [["impacts", "12.5", "2.0", "False", ""],
                                              ["contact_fraction", "0.25", "", "True", "[0.2, 0.3]"]]
    assert page.tables["summary-engines"] == [["cosim", "2", "1"], ["exudyn", "3", "0"]]
    assert page.tables["summary-plan"] == [["revolutions", "0.1"], ["engines", '["cosim", "exudyn"]']]
    text = (tmp_path / REPORT_NAME).read_text(encoding="utf-8")
    assert "<h3>gaps</h3><p>none</p>" in text and "<h3>metrics_failed</h3><p>cosim: impacts</p>" in text
    assert "&quot;deeper&quot;: {" in text                  # what fits no table: its JSON


def test_a_studys_answer_tables_and_sampled_parameters_are_in_its_page(tmp_path):
    """A sweep's report held counts and timings but not its mean and spread (ensemble.csv), a sensitivity study's
    not its indices (indices.csv) nor its sampled parameters (a list, not the joint's and mechanism's dicts)."""
    from wearjoint.report import write_report

    sweep = tmp_path / "sweep"
    sweep.mkdir()
    (sweep / "sweep_summary.json").write_text(json.dumps({"cases": 6, "ok": 6}))
    (sweep / "ensemble.csv").write_text("friction_coefficient,n,max_wear_depth_m_mean,max_wear_depth_m_std\n"
                                        "0.05,3,5.932e-05,3.9e-07\n0.15,3,6.1e-05,4.4e-07\n")
    page = Tables(write_report(sweep).read_text(encoding="utf-8"))
    assert page.tables["table-ensemble.csv"] == [["0.05", "3", "5.932e-05", "3.9e-07"],
                                                 ["0.15", "3", "6.1e-05", "4.4e-07"]]
    study = tmp_path / "sensitivity"
    study.mkdir()
    (study / "summary.json").write_text(json.dumps({"method": "morris", "parameters": [
        {"name": "friction_coefficient", "low": 0.05, "high": 0.15, "log": False}]}))
    (study / "indices.csv").write_text("output,rank,parameter,mu_star,mu_star_low\nmax_wear_depth_m,1,mu,4.7e-06,0.0\n")
    page = Tables(write_report(study).read_text(encoding="utf-8"))
    assert page.tables["table-indices.csv"] == [["max_wear_depth_m", "1", "mu", "4.7e-06", "0.0"]]
    assert page.tables["summary-parameters"] == [["friction_coefficient", "0.05", "0.15", "False"]]


def test_a_value_written_at_its_default_is_given_and_an_unset_stiffness_is_the_materials(tmp_path):
    """--crank-length-m 0.05 is the default's value, but written on the command line: "given" (it said "default");
    the contact stiffness left unset is the one the run derived from the radii and materials, with its value (it
    said "default" beside nothing)."""
    out = tmp_path / "run"
    assert main(["simulate", "--revolutions", "0.01", "--crank-length-m", "0.05", "--quiet", "--no-plots",
                 "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    page = Tables((out / REPORT_NAME).read_text(encoding="utf-8"))
    mechanism = {name: (value, source) for name, value, source in page.tables["mechanism"]}
    assert mechanism["crank_length_m"] == ("0.05", "given") and mechanism["rod_length_m"][1] == "default"
    joint = {name: (value, source) for name, value, source in page.tables["joint"]}
    assert joint["contact_stiffness_N_m1_5"] == (repr(summary["contact_stiffness_N_m1_5"]),
                                                 "from the radii and materials")
