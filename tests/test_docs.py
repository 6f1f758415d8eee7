"""The manual's links resolve and its pages carry no history.

Every relative link (and its #anchor, GitHub's heading slug) in README.md and docs/**/*.md resolves; no heading in
docs/ names a date; no page in docs/ but the generated performance.md (whose rows state the date they were measured)
dates its content; no page is longer than the manual's limit.  Reads files only: well under a second.
"""
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PAGES = sorted(REPO.glob("docs/**/*.md"))
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#+\s+(.*)$", re.M)
DATE = re.compile(r"\b20\d\d-\d\d(-\d\d)?\b")
GENERATED = {REPO / "docs" / "performance.md"}
MAX_LINES = 600


def slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def without_code(text: str) -> str:
    """The text with fenced code blocks removed (a comment line in a block is not a heading)."""
    return re.sub(r"^```.*?^```", "", text, flags=re.M | re.S)


def broken_links(page: Path) -> list[str]:
    broken = []
    for target in LINK.findall(without_code(page.read_text())):
        if re.match(r"[a-z]+:", target):
            continue                      # a URL
        file, _, anchor = target.partition("#")
        linked = (page.parent / file).resolve() if file else page
        if not linked.exists():
            broken.append(target)
        elif anchor and linked.suffix == ".md":
            if anchor not in {slug(h) for h in HEADING.findall(without_code(linked.read_text()))}:
                broken.append(target)
    return broken


@pytest.mark.parametrize("page", [REPO / "README.md", *PAGES], ids=lambda p: str(p.relative_to(REPO)))
def test_every_relative_link_resolves(page):
    assert broken_links(page) == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_no_dated_headings_and_no_dated_content(page):
    text = without_code(page.read_text())
    assert [h for h in HEADING.findall(text) if DATE.search(h)] == []
    if page not in GENERATED:
        assert DATE.findall(text) == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_pages_stay_focused(page):
    assert page.read_text().count("\n") <= MAX_LINES


def test_the_rules_find_what_they_should(tmp_path):
    (tmp_path / "a.md").write_text("# The FMU contract (model `X`)\n[ok](a.md#the-fmu-contract-model-x) "
                                   "[bad anchor](a.md#nothing) [bad file](b.md) [url](https://x.org/y)\n"
                                   "```\n# not a heading\n[in code](c.md)\n```\n")
    assert broken_links(tmp_path / "a.md") == ["a.md#nothing", "b.md"]
    assert DATE.search("## Measured (2026-11-27, late evening)") and not DATE.search("§3.11, 1e-5 s, 2026 runs")
