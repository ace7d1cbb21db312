"""Property-based tests of the command line with inputs at the edges: images a few pixels wide for
``viewmorph``, and inputs that are not regular files (a FIFO, a folder, a symbolic link to a folder)
wherever a command reads a file (images, ``--points``, atlases, ``--path`` and ``--mesh`` files,
``--asset`` files and the textures and material libraries they name, bake inputs).

``morphkit.cli.main`` runs in-process. The property: exit 0, or exit 1 or 2 with exactly one line on
stderr (``morphkit: error: ...``; a bake's failed asset is its own line, ``morphkit bake: failed:
NAME: ...``); never a traceback, never a hang (a FIFO opened for reading waits for a writer that
never comes: :func:`props.hang_limit` fails such a case), and no temporary file left in the output.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import cv2
import numpy as np
import pytest
import trimesh
from hypothesis import event, given, settings
from hypothesis import strategies as st
from props import hang_limit

from morphkit.cli import main
from morphkit.files.outfolder import MARKER_NAME, TEMPORARY

ONE_LINE = re.compile(r"^morphkit: error: \S.*$")
ARGPARSE = re.compile(r"^morphkit( \w+)?: error: \S.*$")
BAKE_FAILED = re.compile(r"^morphkit bake: failed: \S+: \S.*$")
#: Few examples, each a whole command (the file stays a few seconds): a quarter of the profile's
#: (tests/conftest.py: 25 in "ci", 250 in "long").
FEW = settings(max_examples=settings.default.max_examples // 4, deadline=None)


def check(capsys, argv: list[object], out: Path) -> int:
    """Run the command line; assert the property (module notes); its exit code."""
    argv = [str(a) for a in argv]
    by_argparse = False
    with hang_limit():
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse: its usage, then one line
            code, by_argparse = exc.code, True
    err = capsys.readouterr().err
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    event(f"{argv[0]}: exit {code}")
    assert code in (0, 1, 2), (code, err)
    if by_argparse:
        assert code == 2 and lines and ARGPARSE.match(lines[-1]), err
    elif code == 1 and argv[0] == "bake" and lines and BAKE_FAILED.match(lines[0]):
        assert len(lines) == 1, err  # the one asset, failed
    elif code != 0:
        assert len(lines) == 1 and ONE_LINE.match(lines[0]), err
        event(f"{argv[0]}: " + lines[0].split(":")[2].strip()[:40])
    if out.exists():
        left = [p.name for p in out.rglob("*") if TEMPORARY.match(p.name)]
        assert not left, left
    return code


# =================================================================== viewmorph: images a few pixels wide
@st.composite
def tiny_image(draw: st.DrawFn, shape: tuple[int, int] | None = None) -> np.ndarray:
    """A grey, BGR or BGRA uint8 image of 1 to 16 pixels a side: noise, one colour or a ramp."""
    h, w = shape if shape is not None else (draw(st.integers(1, 16)), draw(st.integers(1, 16)))
    channels = draw(st.sampled_from([0, 3, 4]))
    full = (h, w) if channels == 0 else (h, w, channels)
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    kind = draw(st.sampled_from(["noise", "flat", "ramp"]))
    if kind == "noise":
        return rng.integers(0, 256, full, dtype=np.uint8)
    if kind == "flat":
        return np.full(full, rng.integers(0, 256), np.uint8)
    ramp = np.linspace(0, 255, w, dtype=np.float32)[None, :].repeat(h, axis=0)
    return np.broadcast_to(ramp.reshape(h, w, *([1] * (len(full) - 2))), full).astype(np.uint8)


@FEW
@given(data=st.data())
def test_viewmorph_of_images_a_few_pixels_wide(tmp_path_factory, capsys, data):
    tmp = tmp_path_factory.mktemp("tiny")
    left = data.draw(tiny_image(), label="left")
    right = data.draw(st.one_of(st.just(None), tiny_image()), label="right")
    if right is None:  # the same scene, moved one pixel
        right = np.roll(left, 1, axis=1)
    for name, img in (("l.png", left), ("r.png", right)):
        assert cv2.imwrite(str(tmp / name), img)
    argv: list[object] = ["viewmorph", tmp / "l.png", tmp / "r.png",
                          "--prewarp", data.draw(st.sampled_from(["none", "auto", "opencv", "seitz-dyer"])),
                          "--fallback", data.draw(st.sampled_from(["raise", "morph"]))]
    if data.draw(st.booleans(), label="--points"):
        coord = st.floats(-2, 18, allow_nan=False, width=32)
        rows = data.draw(st.lists(st.tuples(coord, coord, coord, coord), max_size=12), label="rows")
        (tmp / "p.csv").write_text("x0,y0,x1,y1\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
        argv += ["--points", tmp / "p.csv"]
    frames = data.draw(st.sampled_from([None, 2, 3]), label="--frames")
    out = tmp / "out"
    argv += ["-o", out / "mid.png"] if frames is None else ["--frames", frames, "-o", out]
    if check(capsys, argv, out) == 0:
        if frames is None:
            assert cv2.imread(str(out / "mid.png")) is not None
        else:
            assert sorted(p.name for p in (out / "frames").iterdir()) == [f"frame_{i:04d}.png"
                                                                        for i in range(frames)]


# =================================================================== inputs that are not regular files
KINDS = ("FIFO", "folder", "link to a folder")


def not_a_file(path: Path, kind: str) -> None:
    """Put a FIFO, a folder (holding a file) or a symbolic link to a folder at ``path``."""
    if path.is_symlink() or path.is_file():
        path.unlink()
    if kind == "FIFO":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
        (path / "inside.png").write_bytes(b"not an image")
    else:
        target = path.with_name(path.name + ".target")
        target.mkdir()
        path.symlink_to(target, target_is_directory=True)


def textured_obj(folder: Path) -> Path:
    """``box.obj`` with its material library ``box.mtl`` naming the texture ``tex.png``."""
    folder.mkdir(parents=True, exist_ok=True)
    box = trimesh.creation.box([0.4, 0.4, 0.6])
    box.apply_translation([0, 0, 0.3])
    uv = np.random.default_rng(0).random((len(box.vertices), 2))
    assert cv2.imwrite(str(folder / "tex.png"), np.full((8, 8, 3), 120, np.uint8))
    lines = ([f"v {x} {y} {z}" for x, y, z in box.vertices] + [f"vt {u} {v}" for u, v in uv]
             + [f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in box.faces])
    (folder / "box.obj").write_text("mtllib box.mtl\nusemtl m\n" + "\n".join(lines) + "\n")
    (folder / "box.mtl").write_text("newmtl m\nKd 1 1 1\nmap_Kd tex.png\n")
    return folder / "box.obj"


@pytest.fixture(scope="module")
def atlas_file_bytes(tmp_path_factory) -> bytes:
    from test_prop_files import atlas_bytes as make

    return make.__wrapped__(tmp_path_factory)


#: Each place a file is read, without a GL context: the command line (the input names are files
#: of ``_inputs``) and the input made not a regular file.
SLOTS = {
    "viewmorph LEFT": (["viewmorph", "l.png", "r.png", "--points", "p.csv", "--prewarp", "none"], "l.png"),
    "viewmorph RIGHT": (["viewmorph", "l.png", "r.png", "--points", "p.csv", "--prewarp", "none"], "r.png"),
    "viewmorph --points csv": (["viewmorph", "l.png", "r.png", "--points", "p.csv"], "p.csv"),
    "viewmorph --points json": (["viewmorph", "l.png", "r.png", "--points", "p.json"], "p.json"),
    "shadows ATLAS": (["shadows", "a.atlas.npz", "-q"], "a.atlas.npz"),
    "shadows --path": (["shadows", "a.atlas.npz", "--path", "path.csv", "-q"], "path.csv"),
    "shadows --mesh": (["shadows", "a.atlas.npz", "--mesh", "box.ply", "-q"], "box.ply"),
    "billboards --asset npz": (["billboards", "--asset", "asset.npz", "--frames", "2"], "asset.npz"),
    "billboards --asset obj": (["billboards", "--asset", "box.obj", "--frames", "2"], "box.obj"),
    "billboards --asset glb": (["billboards", "--asset", "box.glb", "--frames", "2"], "box.glb"),
    "render SCENE json": (["render", "scene.json"], "scene.json"),
    "render SCENE glb": (["render", "scene.glb"], "scene.glb"),
    "bake MESH": (["bake", "box.ply", "--workers", "1", "-q"], "box.ply"),
    "bake FOLDER holding it": (["bake", "lib", "--workers", "1", "-q"], "lib/box.ply"),
}
INPUTS = ("l.png", "r.png", "p.csv", "p.json", "a.atlas.npz", "path.csv", "box.ply", "box.glb", "box.obj",
          "asset.npz", "lib", "scene.json", "scene.glb")


def _inputs(tmp: Path, atlas: bytes) -> None:
    """Valid inputs for every slot, in ``tmp``."""
    rng = np.random.default_rng(5)
    tex = cv2.resize(rng.uniform(0, 255, (6, 6, 3)), (24, 24), interpolation=cv2.INTER_CUBIC)
    tex = np.clip(tex, 0, 255).astype(np.uint8)
    cv2.imwrite(str(tmp / "l.png"), tex)
    cv2.imwrite(str(tmp / "r.png"), np.roll(tex, 2, axis=1))
    g = np.linspace(3, 20, 4)
    p0 = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    (tmp / "p.csv").write_text("".join(f"{a},{b},{a + 2},{b}\n" for a, b in p0))
    (tmp / "p.json").write_text(json.dumps({"pts0": p0.tolist(), "pts1": (p0 + [2, 0]).tolist()}))
    (tmp / "a.atlas.npz").write_bytes(atlas)
    (tmp / "path.csv").write_text("0,0\n0.1,0.1\n")
    box = trimesh.creation.box([0.4, 0.3, 0.5])
    box.export(tmp / "box.ply")
    box.export(tmp / "box.glb")
    box.export(tmp / "box.obj")
    (tmp / "asset.npz").write_bytes(b"")
    (tmp / "lib").mkdir()
    box.export(tmp / "lib" / "box.ply")
    box.export(tmp / "scene.glb")
    scene = {"morphkit_scene": 1, "assets": [{"name": "box", "source": "box.ply"}],
             "instances": {"scatter": {"count": 2}}, "frames": 1}
    (tmp / "scene.json").write_text(json.dumps(scene))


@FEW
@given(slot=st.sampled_from(sorted(SLOTS)), kind=st.sampled_from(KINDS), overwrite=st.booleans())
def test_an_input_that_is_not_a_regular_file_is_one_line(tmp_path_factory, capsys, atlas_file_bytes, slot,
                                                          kind, overwrite):
    tmp = tmp_path_factory.mktemp("special")
    _inputs(tmp, atlas_file_bytes)
    argv, special = SLOTS[slot]
    not_a_file(tmp / special, kind)
    out = tmp / "out"
    argv = [tmp / a if a in INPUTS else a for a in argv]
    argv += ["-o", out / "mid.png" if argv[0] == "viewmorph" else out]
    argv += ["--overwrite"] if overwrite and argv[0] != "bake" else []  # a bake resumes
    code = check(capsys, argv, out)
    assert code in (1, 2), code  # never taken for an input
    event(f"{slot}, {kind}: exit {code}")


@pytest.mark.gl
@settings(max_examples=settings.default.max_examples // 10, deadline=None)  # a GL context each
@given(part=st.sampled_from(["box.mtl", "tex.png", "scene.bin", "scene_tex.png"]),
       kind=st.sampled_from(KINDS))
def test_a_texture_or_material_that_is_not_a_regular_file_is_one_line(tmp_path_factory, capsys, part, kind):
    tmp = tmp_path_factory.mktemp("look")
    if part.startswith("scene"):  # a glTF, its buffers and its texture (a file it names)
        box = trimesh.creation.box([0.4, 0.4, 0.6])
        box.visual = trimesh.visual.TextureVisuals(
            uv=np.random.default_rng(1).random((len(box.vertices), 2)),
            material=trimesh.visual.material.PBRMaterial(baseColorTexture=_pil(np.full((8, 8, 3), 90))))
        for name, data in box.export(file_type="gltf").items():
            (tmp / name).write_bytes(data)
        doc = json.loads((tmp / "model.gltf").read_text())
        doc["images"] = [{"uri": "scene_tex.png"}]  # trimesh embeds it in a buffer: named instead
        (tmp / "model.gltf").write_text(json.dumps(doc))
        assert cv2.imwrite(str(tmp / "scene_tex.png"), np.full((8, 8, 3), 90, np.uint8))
        not_a_file(tmp / ("scene_tex.png" if part == "scene_tex.png" else doc["buffers"][0]["uri"]), kind)
        asset = tmp / "model.gltf"
    else:
        asset = textured_obj(tmp)
        not_a_file(tmp / part, kind)
    out = tmp / "out"
    argv = ["billboards", "--asset", asset, "--n", "2", "--frames", "1", "--size", "32x24",
            "--asset-size", "16", "-o", out]
    assert check(capsys, argv, out) in (0, 1)


def _pil(rgb: np.ndarray):  # noqa: ANN202 - a PIL image for trimesh's material
    from PIL import Image

    return Image.fromarray(rgb.astype(np.uint8))


def test_an_index_that_is_a_fifo_is_refused_as_not_ours_and_never_waited_on(tmp_path):
    from morphkit.errors import OutputExistsError
    from morphkit.files.outfolder import DEMO_OUTPUT, claim_output

    out = tmp_path / "demo"
    out.mkdir()
    marker = {"morphkit_output": 1, "command": "demo", "status": "complete"}
    (out / MARKER_NAME).write_text(json.dumps(marker))  # a record without its file list: the index next
    os.mkfifo(out / "index.json")
    with hang_limit(), pytest.raises(OutputExistsError, match="'index.json' of another program"):
        claim_output(out, DEMO_OUTPUT, overwrite=True)  # not a demo's index: refused, never read
    assert sorted(p.name for p in out.iterdir()) == sorted([MARKER_NAME, "index.json"])
    assert json.loads((out / MARKER_NAME).read_text()) == marker
