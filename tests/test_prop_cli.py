"""Property-based tests of the command line with generated bad arguments and files (issue 28).

``morphkit.cli.main`` runs in-process (a subprocess per case would take a second
each). The property: exit 0 with the promised output, or exit 1 with exactly one
stderr line ``morphkit: error: ...``, or argparse's exit 2 (its usage, then one
``morphkit <command>: error: ...`` line); never a traceback, and no temporary
or partial file left in the output folder. The cases are chosen so that none
reaches the GL renderer (a damaged or missing asset, a missing mesh): this
file runs without a GL context.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import cv2
import numpy as np
import pytest
from hypothesis import event, given
from hypothesis import strategies as st
from props import damaged

from morphkit.cli import main
from morphkit.files.outfolder import LOCK_NAME, MARKER_NAME

ONE_LINE = re.compile(r"^morphkit: error: \S.*$")
ARGPARSE = re.compile(r"^morphkit \w+: error: \S.*$")

numbers = st.one_of(st.sampled_from(["nan", "inf", "-inf", "-1", "0", "1", "2", "1e999", "0.5", "abc", "",
                                     "3.7", "1e6", "-0"]),
                    st.integers(-5, 10).map(str), st.floats(allow_nan=True).map(repr))


#: True about one time in four: most cases change one thing only.
rarely = st.integers(0, 3).map(lambda v: v == 0)


def check_cli(capsys, argv: list[str], out: Path) -> None:
    by_argparse = False
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse refuses the argument list
        code, by_argparse = exc.code, True
        assert code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    if code == 0:
        event(f"{argv[0]}: valid")
    elif code == 1:
        event(f"{argv[0]}: refused (exit 1)")
        assert len(lines) == 1 and ONE_LINE.match(lines[0]), err
    elif by_argparse:
        event(f"{argv[0]}: refused by argparse (exit 2)")
        assert code == 2 and lines and ARGPARSE.match(lines[-1]), err
    else:  # a bad option value: a usage error too
        event(f"{argv[0]}: refused (exit 2)")
        assert code == 2 and len(lines) == 1 and ONE_LINE.match(lines[0]), err
    if out.exists():  # no temporary or partial file (fileio's ".<stem>.*.part<suffix>") left behind
        names = {p.name for p in out.rglob("*")}
        left = [n for n in names if ".part" in n
                or (n.startswith(".morphkit-") and n not in (MARKER_NAME, LOCK_NAME))]
        assert not left, left
        # the output folder's marker and lock (morphkit.files.outfolder) stay only beside what the run
        # wrote: a run that wrote nothing leaves no folder behind, one that finished says so
        assert names - {MARKER_NAME, LOCK_NAME} or not names, sorted(names)
        if code == 0:  # every output folder the run claimed (e.g. viewmorph --frames) says finished
            for marker in out.rglob(MARKER_NAME):
                assert json.loads(marker.read_text())["status"] == "complete", marker


# =================================================================== viewmorph
@pytest.fixture(scope="module")
def vm_files(tmp_path_factory) -> dict[str, bytes]:
    folder = tmp_path_factory.mktemp("vm")
    rng = np.random.default_rng(5)
    tex = np.clip(cv2.resize(rng.uniform(0, 255, (6, 6, 3)), (24, 24), interpolation=cv2.INTER_CUBIC),
                  0, 255).astype(np.uint8)
    moved = np.roll(tex, 2, axis=1)
    g = np.linspace(3, 20, 4)
    p0 = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    for name, img in (("left.png", tex), ("right.png", moved)):
        cv2.imwrite(str(folder / name), img)
    return {"left.png": (folder / "left.png").read_bytes(), "right.png": (folder / "right.png").read_bytes(),
            "points.json": json.dumps({"pts0": p0.tolist(), "pts1": (p0 + [2, 0]).tolist()}).encode(),
            "points.csv": ("x0,y0,x1,y1\n" + "".join(f"{a},{b},{a + 2},{b}\n" for a, b in p0)).encode()}


@given(data=st.data())
def test_cli_viewmorph(vm_files, tmp_path_factory, capsys, data):
    tmp = tmp_path_factory.mktemp("case")
    files = {}
    for name, valid in vm_files.items():
        files[name] = tmp / name
        files[name].write_bytes(data.draw(damaged(valid)) if data.draw(rarely, label=f"damage {name}")
                                else valid)
    points = data.draw(st.sampled_from(["points.json", "points.csv", None]))
    out = tmp / "out"
    argv = ["viewmorph", str(files["left.png"]), str(files["right.png"]), "--prewarp",
            data.draw(st.sampled_from(["none", "none", "auto", "opencv", "seitz-dyer", "bogus"])),
            "--fallback", "morph", "-o",
            str(out / data.draw(st.sampled_from(["mid.png", "mid.png", "mid.jpg", "mid.xyz", "mid", ""])))]
    if points is not None:
        argv += ["--points", str(files[points])]
    if data.draw(st.booleans(), label="--s"):
        argv += ["--s", data.draw(numbers | st.sampled_from(["0.25", "0.5", "1"]))]
    if data.draw(rarely, label="--frames"):
        argv += ["--frames", data.draw(numbers | st.sampled_from(["2", "3"]))]
    check_cli(capsys, argv, out)


# =================================================================== shadows
@pytest.fixture(scope="module")
def atlas_file_bytes(tmp_path_factory) -> bytes:
    from test_prop_files import atlas_bytes as make

    return make.__wrapped__(tmp_path_factory)


@given(data=st.data())
def test_cli_shadows(atlas_file_bytes, tmp_path_factory, capsys, data):
    tmp = tmp_path_factory.mktemp("case")
    atlas = tmp / "a.atlas.npz"
    atlas.write_bytes(data.draw(damaged(atlas_file_bytes)) if data.draw(st.booleans()) else atlas_file_bytes)
    out = tmp / "out"
    argv = ["shadows", str(atlas), "-o", str(out), "-q"]
    path = data.draw(st.sampled_from(["line", "circle", "csv", "missing.csv", "spiral"]))
    if path == "csv":
        rows = data.draw(st.lists(st.lists(numbers, min_size=1, max_size=3), max_size=4))
        (tmp / "p.csv").write_text("\n".join(",".join(r) for r in rows))
        path = str(tmp / "p.csv")
    argv += ["--path", path]
    for opt, n in (("--frames", 1), ("--size", 1), ("--samples", 1), ("--area-light", 2)):
        if data.draw(st.booleans(), label=opt):
            argv += [opt, *(data.draw(numbers) for _ in range(n))]
    # no --mesh and no manifest: every case ends before the renderer
    check_cli(capsys, argv, out)


# =================================================================== billboards
@given(data=st.data())
def test_cli_billboards(tmp_path_factory, capsys, data):
    tmp = tmp_path_factory.mktemp("case")
    asset = tmp / "asset.npz"
    asset.write_bytes(data.draw(st.binary(max_size=64)))
    out = tmp / "out"
    argv = ["billboards", "-o", str(out), "--asset",
            data.draw(st.sampled_from([str(asset), str(tmp / "missing.npz"), "no-such-sample", str(tmp)]))]
    for opt in ("--n", "--frames", "--views", "--asset-size", "--seed"):
        if data.draw(st.booleans(), label=opt):
            argv += [opt, data.draw(numbers)]
    if data.draw(st.booleans(), label="--size"):
        argv += ["--size", data.draw(st.sampled_from(["640x480", "0x0", "x", "64x", "1x1", "99999x2", "ax b",
                                                      "-3x4", "2x2x2"]))]
    if data.draw(st.booleans(), label="--path"):
        argv += ["--path", data.draw(st.sampled_from(["pan", "orbit", "fly", "zigzag"]))]
    check_cli(capsys, argv, out)
