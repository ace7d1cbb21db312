"""The measured results read as one page: ``docs/RESULTS.md`` short, its detail pages and the
changelog in the documentation, and every pointer into them valid."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
RESULTS = DOCS / "RESULTS.md"
PAGES = sorted((DOCS / "results").glob("*.md"))
MAX_RESULTS_LINES = 400


def _headings(path: Path) -> list[str]:
    return [m.group(1).strip() for m in re.finditer(r"^#{1,6} +(.+)$", path.read_text(), flags=re.M)]


def _squash(text: str) -> str:
    """Text as a reader sees it across wrapped comment lines: ``#:``/``#`` and runs of space gone."""
    return re.sub(r"\s+", " ", re.sub(r"\n\s*#:? ?", " ", text))


def test_results_is_one_page():
    n = len(RESULTS.read_text().splitlines())
    assert n <= MAX_RESULTS_LINES, f"docs/RESULTS.md has {n} lines (at most {MAX_RESULTS_LINES})"


def test_results_pages_and_changelog_are_in_the_toctree_and_linked():
    index = (DOCS / "index.md").read_text()
    summary = RESULTS.read_text()
    assert len(PAGES) >= 8
    for page in PAGES:
        assert re.search(rf"^results/{page.stem}$", index, flags=re.M), page.name
        assert f"(results/{page.name})" in summary, f"RESULTS.md does not link {page.name}"
    assert re.search(r"^CHANGELOG$", index, flags=re.M) and "(CHANGELOG.md)" in summary


def test_each_summary_section_names_its_command():
    sections = re.split(r"^## ", RESULTS.read_text(), flags=re.M)[1:]
    assert len(sections) >= 8
    for body in sections:
        title = body.splitlines()[0]
        if title.startswith("Targets not met"):
            continue
        assert re.search(r"`(morphkit |python |PYTHONPATH=|pytest |bash |bench )", body), title


def test_technique_pages_include_sections_that_exist():
    summary = RESULTS.read_text()
    keys = set()
    for page in (DOCS / "techniques").glob("*.md"):
        keys |= set(re.findall(r':start-after: "<!-- results:(\w+):start -->"', page.read_text()))
    assert {"warp", "render", "shadows", "soft", "viewmorph", "billboard", "bake"} <= keys
    for key in keys:
        start, end = f"<!-- results:{key}:start -->", f"<!-- results:{key}:end -->"
        assert summary.count(start) == 1 and summary.count(end) == 1, key
        body = summary[summary.index(start):summary.index(end)]
        assert len(body) > 200, key
        assert not re.search(r"^#", body, flags=re.M), f"{key}: a heading inside an included section"


@pytest.mark.parametrize("path", [RESULTS, DOCS / "CHANGELOG.md", *PAGES], ids=lambda p: p.name)
def test_relative_links_resolve(path):
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", path.read_text()):
        if "://" in target:
            continue
        assert (path.parent / target).exists(), f"{path.name} links {target}"


def test_pointers_into_the_results_name_what_is_there():
    """``docs/RESULTS.md``, "Heading" and ``docs/results/PAGE.md``, "Heading" in the code, the
    tests and the README: the file exists and has a heading that starts with the name."""
    sources = [ROOT / "README.md", *sorted((ROOT / "morphkit").rglob("*.py")),
               *sorted((ROOT / "tests").glob("*.py"))]
    pointer = re.compile(r"docs/(RESULTS\.md|CHANGELOG\.md|results/\w+\.md)`*,? \"([^\"]+)\"")
    checked = 0
    for src in sources:
        if src == Path(__file__).resolve():
            continue
        text = _squash(src.read_text())
        for m in re.finditer(r"docs/results/(\w+)\.md", text):
            assert (DOCS / "results" / f"{m.group(1)}.md").exists(), f"{src.name}: {m.group(0)}"
        for m in pointer.finditer(text):
            target, name = DOCS / m.group(1), m.group(2).rstrip(".")
            headings = [_squash(h) for h in _headings(target)]
            assert any(h.startswith(name) for h in headings), f"{src.name}: {m.group(0)}"
            checked += 1
    assert checked >= 3  # the README's "Any Linux machine", receivers.py's and tol.py's pointers
