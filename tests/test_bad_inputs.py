"""Bad and extreme inputs, through the API and the CLI, in one table (issue 18).

Each row: (description, callable taking a temporary folder, expected exception
type, regex its message must match). A row passes when the callable raises that
type with a matching message; API rows expect a morphkit error (its message says
what was expected and what was got), CLI rows run ``morphkit.cli.main`` and
expect :class:`CliExit` carrying the exit code and the one line printed on stderr
(no traceback).

Run as a script to print the count handled / tried::

    PYTHONPATH=$PWD python tests/test_bad_inputs.py

The image-only view-morph path on rendered pairs and the thread-count
determinism of ``warps="reproject"`` are not bad inputs: they are tested in
``tests/test_viewmorph_images.py`` and ``tests/test_reproject.py``.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import re
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.bench import run_suite
from morphkit.camera import perspective
from morphkit.errors import FileFormatError, MeshError, OutOfRangeError, ValidationError
from morphkit.files.fileio import write_image
from morphkit.imaging.groundtruth import receiver_grid
from morphkit.meshes import check_mesh, load_mesh
from morphkit.scene import AreaLight, PointLight
from morphkit.shadow import LightRig, MotionRange, ShadowAtlas, SoftShadow
from morphkit.warp import warp_mesh

# ---------------------------------------------------------------- helpers


class CliExit(Exception):
    """A CLI run that ended with a non-zero exit code and one ``morphkit: error:`` line."""


def cli(*argv: Any) -> Callable[[Path], None]:
    """A row callable running ``main([...])`` (``{tmp}`` in arguments: the row's folder)."""

    def run(tmp: Path) -> None:
        from morphkit.cli import main

        args = [str(a).replace("{tmp}", str(tmp)) for a in argv]
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                rc = main(args)
            except SystemExit as exc:  # argparse
                rc = exc.code
        lines = err.getvalue().strip().splitlines()
        assert "Traceback" not in err.getvalue(), err.getvalue()
        if rc == 0:
            return
        assert len(lines) == 1 and lines[0].startswith("morphkit: error: "), lines
        raise CliExit(f"exit {rc}: {lines[0]}")

    return run


class _NoRender:
    """A renderer that must not be reached (the input is refused before any work)."""

    def depth(self, *_a: Any, **_k: Any) -> Any:
        raise AssertionError("rendered although the input is bad")

    color_depth = source_view = depth


class _FlatRenderer:
    """No GL: every pixel sees a surface at depth 2 (enough to reach ``visibility``)."""

    def depth(self, camera: Any, items: Any) -> np.ndarray:
        return np.full(camera.shape, 2.0, np.float32)

    def color_depth(self, camera: Any, items: Any, lights: Any, **_k: Any) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros((*camera.shape, 3), np.uint8), self.depth(camera, items)

    def source_view(self, camera: Any, items: Any, lights: Any, **_k: Any) -> np.ndarray:
        return np.zeros((*camera.shape, 4), np.uint8)


def _box() -> trimesh.Trimesh:
    m = trimesh.creation.box((0.4, 0.3, 0.5))
    m.apply_translation([0, 0, 0.25])
    return m


def _nan_box() -> trimesh.Trimesh:
    m = _box()
    m.vertices[0] = np.nan
    return m


def _collinear() -> trimesh.Trimesh:
    v = np.c_[np.arange(4.0), 2 * np.arange(4.0), np.zeros(4)]
    return trimesh.Trimesh(v, [[0, 1, 2], [1, 2, 3]], process=False)


MOTION_LO, MOTION_HI = [-0.5, -0.4], [0.5, 0.4]
LIGHT = (0.2, -0.1, 2.6)


def _bake(mesh: Any = None, shape: Any = (32, 32), **kw: Any) -> Any:
    from morphkit.scene import DirectionalLight
    from morphkit.shadow import bake_atlas

    return bake_atlas(_box() if mesh is None else mesh, np.eye(4), MotionRange(MOTION_LO, MOTION_HI),
                      DirectionalLight([-0.5, 0.35, -1.0]), shape, renderer=_NoRender(), progress=False, **kw)


@functools.lru_cache(maxsize=1)
def _atlas() -> Any:
    """A 3 x 3 atlas of 24 x 32 maps with made-up depths (no GL)."""
    from morphkit.shadow.rig import sample_axis

    rig = LightRig(PointLight(LIGHT), _box(), np.eye(4), MotionRange(MOTION_LO, MOTION_HI), (24, 32))
    rng = np.random.default_rng(7)
    maps = np.full((3, 3, 24, 32), np.inf, np.float32)
    maps[:, :, 6:18, 8:24] = rng.uniform(2.0, 2.5, (3, 3, 12, 16))
    plane = np.zeros((3, 3, 9, 3))
    plane[..., :2] = rng.uniform(-0.2, 0.2, (3, 3, 9, 2))
    plane[..., 2] = 0.25
    return ShadowAtlas(rig, sample_axis(-0.5, 0.5, 3), sample_axis(-0.4, 0.4, 3), maps,
                       plane + rng.uniform(-0.05, 0.05, plane.shape), plane, (3, 3), "sample")


def _atlas_file(tmp: Path, change: Callable[[dict, dict], None] | None = None) -> Path:
    """Save the synthetic atlas and rewrite it with ``change(meta, arrays)`` applied."""
    from morphkit.shadow.formats.atlasfile import save_atlas

    path = save_atlas(_atlas().baked, tmp / "a.npz")
    if change is None:
        return path
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays["meta"]).decode())
    change(meta, arrays)
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), np.uint8)
    np.savez(tmp / "bad.npz", **arrays)
    return tmp / "bad.npz"


def _load(change: Callable[[dict, dict], None] | None = None, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        return ShadowAtlas.load(_atlas_file(tmp, change), **kw)

    return run


def _nan_in_map(meta: dict, a: dict) -> None:
    a["maps"] = a["maps"].copy()
    a["maps"][1, 1, 10, 12] = np.nan


def _rehashed(change: Callable[[dict, dict], None], *names: str) -> Callable[[dict, dict], None]:
    """``change``, then the named arrays' checksums recomputed (a writer's bug, not damage)."""

    def both(meta: dict, a: dict) -> None:
        from morphkit.files.fileio import array_digest

        change(meta, a)
        for k in names:
            meta["arrays"][k]["sha256"] = array_digest(a[k])

    return both


def _inf_anchor(meta: dict, a: dict) -> None:
    a["anchors"] = a["anchors"].copy()
    a["anchors"][0, 1, 2, 0] = np.inf


def _rows_swapped(meta: dict, a: dict) -> None:
    a["maps"] = a["maps"].copy()
    a["maps"][1, 1, [8, 9]] = a["maps"][1, 1, [9, 8]]


def _anchors_swapped(meta: dict, a: dict) -> None:
    a["anchors"], a["plane_anchors"] = a["plane_anchors"], a["anchors"]


def _pickled(meta: dict, a: dict) -> None:
    a["xs"] = np.array([{"x": 1}, None, "a"], dtype=object)


def _set(path: str, value: Any) -> Callable[[dict, dict], None]:
    def change(meta: dict, a: dict) -> None:
        d = meta
        *head, last = path.split(".")
        for k in head:
            d = d[k]
        if value is _DELETE:
            del d[last]
        else:
            d[last] = value

    return change


_DELETE = object()


def _truncated(tmp: Path) -> Any:
    good = _atlas_file(tmp).read_bytes()
    (tmp / "t.npz").write_bytes(good[: len(good) // 2])
    return ShadowAtlas.load(tmp / "t.npz")


def _mesh_file(tmp: Path, content: str, name: str = "m.obj") -> Any:
    (tmp / name).write_text(content)
    return load_mesh(tmp / name)


def _frame(visibility: Any, *, scene: Any = None, renderer: Any = None) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from morphkit.camera import look_at
        from morphkit.scene import DirectionalLight, Scene, SceneObject
        from morphkit.shadow.frame import render_frame

        cam = perspective(np.deg2rad(40), (16, 16), look_at([1.6, -1.8, 1.2], [0, 0, 0.2]), znear=0.1,
                          zfar=10)
        sc = Scene(SceneObject(_box()), DirectionalLight([0.4, 0.2, -1.0]), cam) if scene is None else scene
        return render_frame(_FlatRenderer() if renderer is None else renderer, sc, visibility)

    return run


def _lookup(depth_map: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from morphkit.camera import look_at
        from morphkit.shadow import shadow_visibility

        cam = perspective(np.deg2rad(50), (48, 64), look_at([0.3, -0.2, 3.0], [0, 0, 0]), znear=0.5, zfar=6)
        return shadow_visibility(np.zeros((4, 3)), depth_map, cam)

    return run


def _nan_map() -> np.ndarray:
    m = np.full((48, 64), 2.0, np.float32)
    m[3, 4] = np.nan
    return m


def _vm_files(tmp: Path) -> None:
    img = (np.random.default_rng(0).random((40, 48, 3)) * 255).astype(np.uint8)
    cv2.imwrite(str(tmp / "l.png"), img)
    cv2.imwrite(str(tmp / "r.png"), img)
    (tmp / "p.json").write_text(json.dumps([[x, y, x + 1, y] for x in (2, 20, 45) for y in (2, 20, 37)]))
    (tmp / "syntax.json").write_text("{not json")
    (tmp / "layout.json").write_text('{"pts0": [[1, 2, 3]], "pts1": [[1, 2]]}')
    (tmp / "afile").write_text("x")


def vm(out: str, points: str = "p.json") -> Callable[[Path], None]:
    run = cli("viewmorph", "{tmp}/l.png", "{tmp}/r.png", "--points", "{tmp}/" + points, "--prewarp", "none",
              "-o", out)

    def with_files(tmp: Path) -> None:
        _vm_files(tmp)
        run(tmp)

    return with_files


def _with(prepare: Callable[[Path], Any], run: Callable[[Path], Any]) -> Callable[[Path], Any]:
    def both(tmp: Path) -> Any:
        prepare(tmp)
        return run(tmp)

    return both


def _previous_demo(tmp: Path) -> None:
    (tmp / "demo").mkdir()
    (tmp / "demo" / "index.json").write_text('{"morphkit_demo": 1, "files": []}')


#: A square warp mesh (4 control points, pixels).
_SQUARE = np.array([[0.0, 0.0], [30.0, 0.0], [0.0, 30.0], [30.0, 30.0]])


def _nan_image() -> np.ndarray:
    img = np.zeros((32, 32), np.float32)
    img[3, 3] = np.nan
    return img


def _billboard() -> Any:
    import morphkit.billboard as bb

    return bb


def _bake_pkg() -> Any:
    import morphkit.bake as bk

    return bk


def _api(fn: Callable[[], Any]) -> Callable[[Path], Any]:
    return lambda _tmp: fn()


def _run_demo_into_a_file(tmp: Path) -> Any:
    from morphkit.programs.demo import run_demo  # imports the GL module (no context is made)

    (tmp / "f").write_text("x")
    return run_demo(tmp / "f", quick=True)


# ---------------------------------------------------------------- the table
FFE, ME, VE = FileFormatError, MeshError, ValidationError
BIG = int(np.sqrt(tol.MAX_IMAGE_PIXELS)) + 1
AREA = AreaLight([0, 0, 2], [0.3, 0, 0], [0, 0.2, 0])
SQUARE = [[0, 0], [7, 0], [0, 7], [7, 7]]

ROWS: list[tuple[str, Callable[[Path], Any], type[BaseException], str]] = [
    # -- corrupt atlas files
    ("atlas: NaN written into a map", _load(_nan_in_map), FFE, r"atlas array 'maps': expected sha256"),
    ("atlas: NaN in a map with a matching checksum", _load(_rehashed(_nan_in_map, "maps")), FFE,
     r"atlas maps: expected finite or \+inf depths, got 1 NaN/-inf values"),
    ("atlas: inf anchor with a matching checksum", _load(_rehashed(_inf_anchor, "anchors")), FFE,
     r"atlas anchors: expected finite values, got 1 NaN/inf values"),
    ("atlas: two map rows swapped", _load(_rows_swapped), FFE, r"atlas array 'maps': expected sha256"),
    ("atlas: surface anchors swapped with plane anchors", _load(_anchors_swapped), FFE,
     r"atlas array 'anchors': expected sha256"),
    ("atlas: a missing metadata key", _load(_set("rig", _DELETE)), FFE,
     r"atlas metadata: expected a key 'rig'"),
    ("atlas: a missing rig key", _load(_set("rig.fx", _DELETE)), FFE, r"atlas rig: expected a key 'fx'"),
    ("atlas: a wrongly typed field (fx a string)", _load(_set("rig.fx", "abc")), FFE,
     r"atlas rig fx: expected a finite number > 0, got 'abc'"),
    ("atlas: a wrongly typed field (control_grid)", _load(_set("control_grid", "17x17")), FFE,
     r"atlas control_grid: expected \[rows, cols\]"),
    ("atlas: a pickled object array", _load(_pickled), FFE,
     r"atlas array 'xs': expected a numeric array \(pickled objects are never loaded\)"),
    ("atlas: version 1", _load(_set("version", 1)), FFE, r"atlas version: expected 3 .*re-bake.*, got 1"),
    ("atlas: another light", _load(light=PointLight([0, 0, 3])), FFE,
     r"atlas light: expected the light it is used with"),
    ("atlas: truncated file", _truncated, FFE, r"expected a complete morphkit-shadow-atlas .npz file"),
    ("atlas: missing file", lambda tmp: ShadowAtlas.load(tmp / "none.npz"), FFE,
     r"atlas file: expected an existing file"),
    # -- meshes at the door
    ("load_mesh: missing file", lambda tmp: load_mesh(tmp / "nope.obj"), ME, r"file not found"),
    ("load_mesh: empty OBJ", lambda tmp: _mesh_file(tmp, ""), ME, r"at least one face, got 0 faces"),
    ("load_mesh: NaN vertex", lambda tmp: _mesh_file(tmp, "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), ME,
     r"expected finite vertex coordinates, got 1"),
    ("load_mesh: all-collinear mesh", lambda tmp: _mesh_file(tmp, "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n"), ME,
     r"all vertices on one line"),
    ("load_mesh: zero-area faces only", lambda tmp: _mesh_file(
        tmp, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 2\nf 1 3 3\nf 1 4 4\n"), ME, r"faces of zero area"),
    ("check_mesh: not a mesh", _api(lambda: check_mesh("teapot.obj", "mesh")), ME,
     r"mesh: expected a trimesh.Trimesh, got str"),
    ("bake_atlas: empty mesh", _api(lambda: _bake(trimesh.Trimesh())), ME, r"at least one face, got 0 faces"),
    ("bake_atlas: NaN vertices", _api(lambda: _bake(_nan_box())), ME, r"finite vertex coordinates"),
    ("bake_atlas: not a mesh", _api(lambda: _bake({"vertices": []})), ME, r"a trimesh.Trimesh, got dict"),
    ("bake_atlas: all-collinear mesh", _api(lambda: _bake(_collinear())), ME, r"all vertices on one line"),
    ("LightRig: not a mesh", _api(lambda: LightRig(PointLight(LIGHT), None, np.eye(4),
                                                   MotionRange(MOTION_LO, MOTION_HI), (8, 8))),
     ME, r"a trimesh.Trimesh, got NoneType"),
    # -- sizes, before allocating
    ("bake_atlas: 20000^2 maps", _api(lambda: _bake(shape=(20000, 20000))), VE,
     rf"expected at most {tol.MAX_IMAGE_PIXELS} pixels"),
    ("bake_atlas: 100000^2 maps", _api(lambda: _bake(shape=(100000, 100000))), VE,
     rf"expected at most {tol.MAX_IMAGE_PIXELS} pixels"),
    ("bake_atlas: 9 x 9 maps of 8192^2", _api(lambda: _bake(shape=(8192, 8192), grid=9)), VE,
     r"atlas maps: expected at most 4294967296 bytes"),
    ("bake_atlas: map shape (32.5, 32)", _api(lambda: _bake(shape=(32.5, 32))), VE,
     r"expected an \(H, W\) pair of integers, got \(32.5, 32\)"),
    ("bake_atlas: grid 2.5", _api(lambda: _bake(grid=2.5)), VE, r"grid: expected k >= 2 samples per axis"),
    ("bake_atlas: control_grid (5.5, 5)", _api(lambda: _bake(control_grid=(5.5, 5))), VE,
     r"control_grid: expected \(rows, cols\) >= \(2, 2\)"),
    ("SoftShadow: 10^4 x 10^4 samples", _api(lambda: SoftShadow(_atlas(), AREA, (10**4, 10**4))), VE,
     r"light samples: expected at most 4096"),
    ("AreaLight.samples: 2.5 x 2", _api(lambda: AREA.samples(2.5, 2)), VE,
     r"n_u: expected an integer, got 2.5"),
    ("render size: a 100000^2 camera", _api(lambda: perspective(0.7, (100000, 100000), np.eye(4))), VE,
     r"shape: expected at most \d+ pixels"),
    ("warp output shape: 20000^2", _api(lambda: warp_mesh(np.zeros((8, 8), np.float32), SQUARE, SQUARE,
                                                          (20000, 20000))), VE,
     r"out_shape: expected at most \d+ pixels"),
    ("warp output shape: (32.5, 32)", _api(lambda: warp_mesh(np.zeros((8, 8), np.float32), SQUARE, SQUARE,
                                                             (32.5, 32))), VE,
     r"out_shape: expected an \(H, W\) pair of integers"),
    ("receiver_grid: over the pixel limit", _api(lambda: receiver_grid(1.0, (BIG, BIG))), VE,
     r"at most \d+ pixels"),
    # -- unchecked values
    ("shadow_visibility: NaN depth map", _lookup(_nan_map()), VE,
     r"depth_map: expected finite or \+inf depths"),
    ("shadow_visibility: integer depth map", _lookup(np.full((48, 64), 2, np.int32)), VE,
     r"depth_map: expected a float32/float64 depth map, got int32"),
    ("render_frame: visibility of the wrong length", _frame(lambda p, n: np.ones(len(p) - 1, np.float32)), VE,
     r"visibility\(points, normals\): expected \(\d+,\) values in \[0, 1\], got shape"),
    ("render_frame: NaN visibility", _frame(lambda p, n: np.full(len(p), np.nan, np.float32)), VE,
     r"values outside \[0, 1\] or NaN"),
    ("render_frame: not a scene", _frame(lambda p, n: np.ones(len(p)), scene={"camera": None}), VE,
     r"scene: expected a morphkit.scene.Scene, got dict"),
    ("render_frame: not a renderer", _frame(lambda p, n: np.ones(len(p)), renderer="gl"), VE,
     r"renderer: expected a SceneRenderer"),
    ("shadow_map: outside the baked range", _api(lambda: _atlas().shadow_map(np.array([0.9, 0.0]))),
     OutOfRangeError, r"object position: expected inside the baked range"),
    ("bench: unknown suite (API)", _api(lambda: run_suite("nope")), VE, r"bench suite: expected one of"),
    ("write_image: unknown extension", lambda tmp: write_image(tmp / "x.xyz", np.zeros((4, 4), np.uint8)), VE,
     r"image for .xyz"),
    ("run_demo: into a file", _run_demo_into_a_file, VE,
     r"demo output folder: expected a folder, got the file"),
    # -- the CLI: one line, exit 1 (a failed run) or 2 (usage: bad option values included)
    ("cli viewmorph: output whose parent is a file", vm("{tmp}/afile/o.png"), CliExit,
     r"exit 2: .*expected a path whose parents are folders, got .*afile.* is a file"),
    ("cli viewmorph: output under a system path", vm("/proc/morphkit-bad-input.png"), CliExit,
     r"exit 1: .*cannot write /proc/morphkit-bad-input.png"),
    ("cli viewmorph: unknown image extension", vm("{tmp}/o.xyz"), CliExit, r"exit 2: .*image for .xyz"),
    ("cli viewmorph: output that is a folder", vm("{tmp}"), CliExit,
     r"exit 2: .*expected an image file path .*, got the folder"),
    ("cli viewmorph: malformed --points JSON", vm("{tmp}/o.png", "syntax.json"), CliExit,
     r"exit 1: .*points file: expected valid JSON"),
    ("cli viewmorph: --points of the wrong layout", vm("{tmp}/o.png", "layout.json"), CliExit,
     r"exit 1: .*points file pts0: expected a list of \[x, y\] numbers, got shape \(1, 3\)"),
    ("cli viewmorph: missing input image",
     cli("viewmorph", "{tmp}/no.png", "{tmp}/no.png", "-o", "{tmp}/o.png"), CliExit,
     r"exit 1: .*image .*no.png.*: expected an existing file, got nothing there"),
    ("cli demo: -o pointing at a file", _with(lambda tmp: (tmp / "f").write_text("x"),
                                            cli("demo", "--quick", "-o", "{tmp}/f")), CliExit,
     r"exit 2: .*demo output folder: expected a folder"),
    ("cli demo: folder with a previous demo, no --overwrite", _with(_previous_demo, cli(
        "demo", "--quick", "-o", "{tmp}/demo")), CliExit, r"exit 2: .*already holds a demo.*--overwrite"),
    ("cli bench: unknown suite", cli("bench", "nope"), CliExit, r"exit 2: .*unknown suite 'nope'"),
    ("cli bench: --json is a folder", cli("bench", "warp", "--json", "{tmp}"), CliExit,
     r"exit 2: .*--json: expected a file path, got the folder"),
    # -- the mesh warp (issue 18's second list)
    ("warp_mesh: NaN pixels", _api(lambda: warp_mesh(_nan_image(), _SQUARE, _SQUARE, (32, 32))), VE,
     r"image: expected no NaN pixels .*, got 1 NaN values"),
    ("warp_mesh: coordinates of 1e20", _api(lambda: warp_mesh(np.zeros((32, 32), np.float32), _SQUARE,
                                                             _SQUARE * 1e20, (32, 32))), VE,
     r"dst_pts: expected coordinates within \+-1e\+07 px \(tol.MAX_COORD_PX\)"),
    # -- billboards (issue 16) and the bake (issue 17)
    ("billboard: a ring of one view", _api(lambda: _billboard().ViewRing(1)), VE,
     r"views: expected K >= 2 reference views .*got 1"),
    ("billboard: bake cameras 2 radii away", _api(lambda: _billboard().QuadCameras.fit(
        trimesh.creation.box(), (64, 64), 10.0, distance_factor=2.0)), VE,
     r"distance_factor: expected a number in \[3, 100\] \(radii\), got 2.0"),
    ("billboard: coverage splat on a 0x grid", _api(lambda: _billboard().splat_coverage(
        np.zeros((1, 3)), _billboard().QuadCameras.fit(trimesh.creation.box(), (64, 64), 10.0).camera(0.0),
        supersample=0)), VE, r"supersample: expected an int >= 1, got 0"),
    ("billboard: asset file that is not one", _with(lambda tmp: (tmp / "bad.npz").write_bytes(b"garbage"),
                                                   lambda tmp: _billboard().BillboardAsset.load(
                                                       tmp / "bad.npz")), FileFormatError,
     r"billboard asset file: .*expected a complete morphkit-billboard .npz file"),
    ("billboard: missing asset file", lambda tmp: _billboard().BillboardAsset.load(tmp / "none.npz"),
     FileFormatError, r"billboard asset file: .*expected an existing file"),
    ("bake: a billboard kind of one view", _api(lambda: _bake_pkg().BillboardKind(views=1)), VE,
     r"billboard views: expected an integer in \[2, 64\], got 1"),
    ("cli billboards: a size that is not WxH", cli("billboards", "--size", "640by480", "-o", "{tmp}/o"),
     CliExit, r"exit 2: .*--size: expected WIDTHxHEIGHT"),
    ("cli billboards: unknown asset", cli("billboards", "--asset", "unicorn", "-o", "{tmp}/o"), CliExit,
     r"exit 2: .*--asset: expected a sample mesh name \(teapot, chair, cow, tree, person\).*got 'unicorn'"),
    ("cli billboards: negative count", cli("billboards", "--n", "-1", "-o", "{tmp}/o"), CliExit,
     r"exit 2: .*--n: expected an integer in \[0, 100000\], got -1"),
    ("cli bake: missing input", cli("bake", "{tmp}/missing.obj", "-o", "{tmp}/out"), CliExit,
     r"exit 1: .*input: expected an existing mesh file or folder"),
    ("cli bake: --views without --billboard", _with(lambda tmp: trimesh.creation.box().export(tmp / "b.ply"),
                                                    cli("bake", "{tmp}/b.ply", "-o", "{tmp}/out", "--views",
                                                        "3")), CliExit,
     r"exit 2: .*--views: expected together with --billboard"),
]


#: rows that import the GL module (morphkit.programs.demo imports morphkit.render; no context is made)
_GL = ("run_demo", "cli demo")


@pytest.mark.parametrize("description, fn, exc, match", [
    pytest.param(*r, marks=pytest.mark.gl) if r[0].startswith(_GL) else r for r in ROWS],
    ids=[r[0] for r in ROWS])
def test_bad_input_is_handled(tmp_path, description, fn, exc, match):
    if "/proc/" in description + match and not Path("/proc/self").exists():
        pytest.skip("needs Linux /proc")
    with pytest.raises(exc, match=match):
        fn(tmp_path)


def test_the_table_covers_the_issue():
    assert len(ROWS) >= 50 and len({r[0] for r in ROWS}) == len(ROWS)


def count() -> tuple[int, int, list[str]]:
    """Run every row; return (handled, tried, descriptions of the rows not handled)."""
    bad = []
    for description, fn, exc, match in ROWS:
        with tempfile.TemporaryDirectory() as d:
            try:
                fn(Path(d))
            except exc as e:
                if re.search(match, str(e)):
                    continue
                bad.append(f"{description}: {type(e).__name__}: {e}")
            except BaseException as e:  # noqa: BLE001 - counted, reported
                bad.append(f"{description}: {type(e).__name__}: {e}")
            else:
                bad.append(f"{description}: no error")
    return len(ROWS) - len(bad), len(ROWS), bad


if __name__ == "__main__":
    handled, tried, failures = count()
    for f in failures:
        print("NOT HANDLED:", f[:300])
    print(f"handled {handled}/{tried}")
    sys.exit(0 if handled == tried else 1)
