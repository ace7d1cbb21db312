"""The README's quick start: one python block per job, each at most 12 lines, using morphkit's
top-level names only (numpy and trimesh make the data), and each runs on its own -- in a fresh
namespace, in an empty folder -- to the figure it prints."""

from __future__ import annotations

import ast
import re
import textwrap
from pathlib import Path

import pytest

import morphkit

README = Path(__file__).resolve().parent.parent / "README.md"

#: At most this many lines a block (blank lines and comments count).
MAX_LINES = 12

#: The modules a block may import besides morphkit: the data makers.
DATA_MAKERS = {"numpy", "trimesh"}


def _section(text: str) -> str:
    m = re.search(r"^## Quick start\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S)
    assert m, "README.md has no '## Quick start' section"
    return m.group(1)


def quick_start_blocks(text: str | None = None) -> list[str]:
    """The python blocks under ``## Quick start``, in order."""
    section = _section(README.read_text() if text is None else text)
    return [textwrap.dedent(m.group(2)) for m in re.finditer(r"^( *)```python\n(.*?)^\1```", section,
                                                              flags=re.M | re.S)]


def outside_names(block: str) -> list[str]:
    """What in ``block`` is not a top-level ``morphkit`` name or a data maker: imports of other
    modules or of morphkit's sub-modules, ``morphkit.X`` for an ``X`` not in ``morphkit.__all__``
    (a sub-module such as ``morphkit.shadow`` included), ``morphkit`` itself rebound."""
    bad = []
    for node in ast.walk(ast.parse(block)):
        if isinstance(node, ast.Import):
            for a in node.names:
                top = a.name.split(".")[0]
                if a.name != "morphkit" and top not in DATA_MAKERS:
                    bad.append(f"line {node.lineno}: import {a.name}")
                elif a.name == "morphkit" and a.asname not in (None, "morphkit"):
                    bad.append(f"line {node.lineno}: import morphkit as {a.asname}")
        elif isinstance(node, ast.ImportFrom):
            if (node.module or "").split(".")[0] not in DATA_MAKERS or node.level:
                bad.append(f"line {node.lineno}: from {node.module} import ...")
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            if node.value.id == "morphkit" and node.attr not in morphkit.__all__:
                bad.append(f"line {node.lineno}: morphkit.{node.attr}")
        elif isinstance(node, ast.Name) and node.id == "morphkit" and not isinstance(node.ctx, ast.Load):
            bad.append(f"line {node.lineno}: morphkit rebound")
    return bad


BLOCKS = quick_start_blocks()
IDS = [f"block{k + 1}" for k in range(len(BLOCKS))]


def test_the_quick_start_has_a_block_per_job():
    assert len(BLOCKS) >= 3


def test_the_block_finder_reads_the_section_only():
    text = ("# x\n```python\nbefore\n```\n## Quick start\nintro\n```python\nimport morphkit\n```\n"
            "## Next\n```python\nafter\n```\n")
    assert quick_start_blocks(text) == ["import morphkit\n"]


@pytest.mark.parametrize("block", BLOCKS, ids=IDS)
def test_each_block_is_short(block):
    n = len(block.rstrip("\n").splitlines())
    assert n <= MAX_LINES, f"{n} lines, at most {MAX_LINES}"


@pytest.mark.parametrize("block", BLOCKS, ids=IDS)
def test_each_block_uses_top_level_names_only(block):
    assert "import morphkit" in block
    assert outside_names(block) == []


def test_the_name_check_finds_what_is_not_top_level():
    block = ("import os\nimport morphkit as mk\nimport numpy as np\nfrom morphkit.shadow import bake_atlas\n"
             "import morphkit\nx = morphkit.shadow.bake_atlas\ny = morphkit.Renderer\nz = morphkit.nope\n")
    assert sorted(outside_names(block)) == ["line 1: import os", "line 2: import morphkit as mk",
                                    "line 4: from morphkit.shadow import ...", "line 6: morphkit.shadow",
                                    "line 8: morphkit.nope"]


def _warped_shadow(ns: dict) -> None:
    iou = morphkit.shadow_iou(ns["warped"] < 0.5, ns["truth"] < 0.5)
    assert (ns["truth"] < 0.5).sum() > 100  # a shadow on the ground to compare
    assert iou >= 0.95, f"warped shadow IoU against the ray cast {iou:.3f}"


def _view_morph(ns: dict) -> None:
    assert ns["middle"].shape == ns["truth"].shape
    assert ns["psnr"] >= 22.0, f"PSNR against the rendered middle view {ns['psnr']:.1f} dB"


def _field(ns: dict) -> None:
    cmp = ns["cmp"]
    assert Path("field.png").is_file()
    assert morphkit.read_image("field.png").shape == cmp.strip.shape
    assert cmp.shadow_iou["ground"] >= 0.95, cmp.shadow_iou
    assert 0.0 <= cmp.shadow_iou["objects"] <= 1.0, cmp.shadow_iou


#: What each block claims, checked on its namespace after it ran (in the README's order).
CLAIMS = [_warped_shadow, _view_morph, _field]


def test_every_block_has_its_claim_checked():
    assert len(CLAIMS) == len(BLOCKS)


@pytest.mark.gl
@pytest.mark.parametrize("k", range(len(BLOCKS)), ids=IDS)
def test_each_block_runs_on_its_own(k, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    ns: dict = {"__name__": "quickstart"}
    exec(compile(BLOCKS[k], f"README.md quick start {IDS[k]}", "exec"), ns)  # noqa: S102 - the README is ours
    printed = capsys.readouterr().out
    assert re.search(r"\d\.\d", printed), f"the block prints its figure, printed {printed!r}"
    CLAIMS[k](ns)
