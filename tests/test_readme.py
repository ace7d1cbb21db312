"""The README's Python examples run, in order, as a reader would paste them (the quick start's
blocks: tests/test_quickstart.py)."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).resolve().parent.parent / "README.md"


def _blocks() -> list[str]:
    """The python blocks outside ``## Quick start`` (whose blocks run one by one, each on its own:
    tests/test_quickstart.py)."""
    text = re.sub(r"^## Quick start\n.*?(?=^## )", "", README.read_text(), count=1, flags=re.M | re.S)
    return [textwrap.dedent(m.group(2)) for m in re.finditer(r"^( *)```python\n(.*?)^\1```", text,
                                                              flags=re.M | re.S)]


def test_readme_has_examples():
    assert len(_blocks()) >= 4


@pytest.mark.gl
def test_readme_examples_run(tmp_path, monkeypatch):
    from morphkit.meshes import sample_mesh

    monkeypatch.chdir(tmp_path)
    (tmp_path / "props").mkdir()  # the bake example's input folder: one small mesh
    sample_mesh("teapot").export(tmp_path / "props" / "teapot.ply")
    # the mesh-warp example names its inputs: a small image and a 2x2 grid moved by a known shift
    src = np.array([[2.0, 2.0], [20.0, 2.0], [2.0, 20.0], [20.0, 20.0]])
    ns: dict = {"image": np.zeros((24, 24), np.float32), "src_pts": src, "dst_pts": src + 0.5,
                "H": 24, "W": 24, "__name__": "readme"}
    for block in _blocks():
        exec(compile(block, str(README), "exec"), ns)  # noqa: S102 - the README is ours
    assert (tmp_path / "teapot.atlas.npz").is_file()
    assert ns["vis"].shape == (256 * 256,) and 0.0 <= ns["vis"].min() <= ns["vis"].max() <= 1.0
    assert ns["maps"].mask.any()
    assert (tmp_path / "baked" / "teapot.atlas.npz").is_file() and not ns["manifest"].failed()
