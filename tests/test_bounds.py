"""Inputs that hung, ran out of memory or drew nothing: each is refused (or ignored) up front.

Counts of ``morphkit bench`` against their caps, hostile glTF node graphs, dome files of
negative depths, lights that cannot reach the ground, and files of other programs that
carry morphkit's names. The CLI cases run the real entry point in a subprocess under a
timeout and an address-space limit, so that code which would work on the input instead of
refusing it fails the test rather than the machine.
"""

from __future__ import annotations

import base64
import json
import os
import re
import resource
import struct
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from morphkit import tol

ROOT = Path(__file__).resolve().parents[1]
ENV = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "OMP_NUM_THREADS": "1",
       "OPENBLAS_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1", "HOME": os.environ.get("HOME", "/tmp")}
#: Address space a refused command runs in: the imports take well under it; a command that
#: allocates for a count of 10^9 does not.
MEMORY_LIMIT = 4 * 2**30


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def morphkit_cli(*argv: str | Path, timeout: float = 120) -> tuple[int, str]:
    """Run ``python -m morphkit ARGV``; return its exit code and its one stderr line."""
    r = subprocess.run([sys.executable, "-m", "morphkit", *map(str, argv)], capture_output=True, text=True,
                       env=ENV, timeout=timeout, preexec_fn=_limit_memory, cwd=ROOT)
    lines = r.stderr.strip().splitlines()
    assert "Traceback" not in r.stderr, r.stderr[-2000:]
    assert len(lines) == 1 and lines[0].startswith("morphkit: error: "), lines[-5:]
    return r.returncode, lines[0]


# ------------------------------------------------------------ bench counts


def _want(what: str, cap: int, got: int) -> str:
    return rf"{what}: expected an integer in \[1, {cap}\], got {got}"


@pytest.mark.parametrize("argv, match", [
    (("scene", "--instances", "1000000000"), _want("--instances", tol.MAX_BENCH_INSTANCES, 1000000000)),
    (("scene", "--instances", "10", "0"), _want("--instances", tol.MAX_BENCH_INSTANCES, 0)),
    (("bake", "--workers", "1", "100000"), _want("--workers", tol.MAX_LOCAL_WORKERS, 100000)),
    (("bake", "--workers", "-2"), _want("--workers", tol.MAX_LOCAL_WORKERS, -2)),
    (("bake", "--assets", "1000000000"), _want("--assets", tol.MAX_BENCH_ASSETS, 1000000000)),
], ids=["instances-1e9", "instances-0", "workers-1e5", "workers-negative", "assets-1e9"])
def test_bench_counts_are_capped_before_any_work(argv, match):
    rc, line = morphkit_cli("bench", *argv)
    assert rc == 2  # a bad option value: a usage mistake
    assert re.search(match, line), line


@pytest.mark.parametrize("call, match", [
    ("scene_suite.run(instances=[10**9])", _want("instances", tol.MAX_BENCH_INSTANCES, 1000000000)),
    ("bake_suite.run(workers=[10**6])", _want("workers", tol.MAX_LOCAL_WORKERS, 1000000)),
    ("bake_suite.run(assets=10**9)", _want("library assets", tol.MAX_BENCH_ASSETS, 1000000000)),
], ids=["scene-instances", "bake-workers", "bake-assets"])
def test_bench_suites_check_their_counts_too(call, match):
    """The API refuses the same counts (in a subprocess: code that took them would run the suite)."""
    r = subprocess.run([sys.executable, "-c", f"from morphkit.bench import bake_suite, scene_suite; {call}"],
                       capture_output=True, text=True, env=ENV, timeout=120, preexec_fn=_limit_memory,
                       cwd=ROOT)
    assert r.returncode == 1
    assert re.search("ValidationError: " + match, r.stderr.strip().splitlines()[-1]), r.stderr[-2000:]


# ------------------------------------------------------------ glTF node graphs


def _gltf_doc(nodes: list[dict[str, Any]], roots: list[int]) -> tuple[dict[str, Any], bytes]:
    """A glTF document of one triangle drawn by ``nodes`` (scene roots ``roots``), and its buffer."""
    buf = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32).tobytes()
    buf += np.array([0, 1, 2, 0], np.uint16).tobytes()
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(buf)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                           {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "nodes": nodes, "scenes": [{"nodes": roots}], "scene": 0}
    return doc, buf


def _write_gltf(path: Path, nodes: list[dict[str, Any]], roots: list[int]) -> Path:
    """``nodes`` as a ``.gltf`` (buffer as a data URI) or a ``.glb`` (JSON and BIN chunks)."""
    doc, buf = _gltf_doc(nodes, roots)
    if path.suffix == ".gltf":
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
        path.write_text(json.dumps(doc))
        return path
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    buf += b"\0" * (-len(buf) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(buf), 0x004E4942) + buf
    path.write_bytes(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)
    return path


def _chain(n: int) -> list[dict[str, Any]]:
    """``n`` nodes, each drawing the triangle, node ``i``'s child ``i + 1``."""
    return [{"mesh": 0, "translation": [0.01, 0, 0], **({"children": [i + 1]} if i + 1 < n else {})}
            for i in range(n)]


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_gltf_trees_load(tmp_path, suffix):
    """The check passes what glTF allows: a tree of nodes, and a flat list of roots."""
    from morphkit.meshes import load_mesh

    assert len(load_mesh(_write_gltf(tmp_path / f"chain{suffix}", _chain(4), [0])).faces) == 4
    flat = [{"mesh": 0, "translation": [i, 0, 0]} for i in range(3)]
    assert len(load_mesh(_write_gltf(tmp_path / f"flat{suffix}", flat, [0, 1, 2])).faces) == 3


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
@pytest.mark.parametrize("nodes, roots, match", [
    ([{"mesh": 0, "children": [1]}, {"mesh": 0, "children": [0]}], [0], r"a cycle of children 0 -> 1 -> 0"),
    ([{"mesh": 0}, {"mesh": 0, "children": [2]}, {"mesh": 0, "children": [3]}, {"children": [1, 4]},
      {"mesh": 0}], [0], r"a cycle of children 1 -> 2 -> 3 -> 1"),
    ([{"mesh": 0, "children": [0]}], [0], r"got node 0 a child of itself"),
    ([{"mesh": 0, "children": [2]}, {"mesh": 0, "children": [2]}, {"mesh": 0}], [0, 1],
     r"got node 2 a child of node 0 and node 1"),
    ([{"mesh": 0, "children": [7]}], [0],
     r"node 0 of .*: expected children that are node indices in \[0, 1\), got 7"),
], ids=["cycle", "cycle-below-a-root", "own-child", "two-parents", "no-such-child"])
def test_gltf_nodes_that_are_not_trees_are_refused(tmp_path, suffix, nodes, roots, match):
    from morphkit.errors import MeshError
    from morphkit.meshes import load_mesh

    with pytest.raises(MeshError, match=match):
        load_mesh(_write_gltf(tmp_path / f"bad{suffix}", nodes, roots))


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_gltf_of_more_nodes_than_the_cap_is_refused(tmp_path, suffix):
    from morphkit.errors import MeshError
    from morphkit.meshes import load_mesh

    n = tol.MAX_GLTF_NODES + 1
    path = _write_gltf(tmp_path / f"many{suffix}", [{"mesh": 0}] * n, list(range(n)))
    with pytest.raises(MeshError, match=rf"nodes of mesh file .*: expected at most {tol.MAX_GLTF_NODES} "
                       rf"\(tol.MAX_GLTF_NODES\), got {n} nodes"):
        load_mesh(path)


def test_glb_node_check_reads_the_json_chunk_only(tmp_path, monkeypatch):
    """A GLB's binary chunk is not read for the check: one cut off after its header is refused by
    the node count (trimesh, which reads it, would fail on the missing bytes instead)."""
    from morphkit.errors import MeshError
    from morphkit.meshes import load_mesh

    monkeypatch.setattr(tol, "MAX_GLTF_NODES", 3)
    path = _write_gltf(tmp_path / "many.glb", [{"mesh": 0}] * 4, [0, 1, 2, 3])
    data = path.read_bytes()
    path.write_bytes(data[:-44])  # the BIN chunk's data (44 bytes) gone
    with pytest.raises(MeshError, match=r"expected at most 3 \(tol.MAX_GLTF_NODES\), got 4 nodes"):
        load_mesh(path)


def test_cli_on_a_cyclic_gltf_is_one_line(tmp_path):
    """``billboards --asset FILE`` loads the mesh first: one line, exit 1, nothing rendered."""
    cycle = [{"mesh": 0, "children": [1]}, {"mesh": 0, "children": [0]}]
    path = _write_gltf(tmp_path / "cycle.gltf", cycle, [0])
    rc, line = morphkit_cli("billboards", "--asset", path, "--views", "8", "--frames", "1",
                            "-o", tmp_path / "out")  # --views given: no line saying which was chosen
    assert rc == 1
    assert re.search(r"nodes of mesh file .*cycle.gltf.*: expected nodes forming trees .*, got a cycle of "
                     r"children 0 -> 1 -> 0$", line), line


# ------------------------------------------------------------ dome files


def _redepth(path: Path, out: Path, edit: Any) -> Path:
    """``path``'s dome file with its depth array edited and its checksums recomputed."""
    from morphkit.files.fileio import array_digest

    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays.pop("meta")).decode())
    arrays["depth"] = edit(arrays["depth"].copy(), meta)
    meta["sha256"] = {k: array_digest(np.ascontiguousarray(a)) for k, a in arrays.items()}
    np.savez(out, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
    return out


def _negative(d: np.ndarray, meta: dict[str, Any]) -> np.ndarray:
    drawn = np.isfinite(d)
    d[drawn] = np.float16(-meta["distance"] - 1.0)  # linear depth -1: behind every view's camera
    return d


def _beyond_far(d: np.ndarray, meta: dict[str, Any]) -> np.ndarray:
    d[np.isfinite(d)] = np.float16(2.0 * meta["radius"])  # past D + 1.5 r
    return d


_DEPTH = (r"dome billboard asset file: depth: expected drawn depths \(depth \+ distance .*\) within "
          r"the views' ")


@pytest.mark.parametrize("edit, match", [
    (_negative, _DEPTH + r"near and far planes \[.*\], or \+inf \(nothing drawn\), got -1 to -1 "
                         r"\(behind the camera\)"),
    (_beyond_far, _DEPTH + r"near and far planes"),
], ids=["negative", "beyond-far"])
def test_dome_file_of_depths_no_view_draws_is_refused(tmp_path, edit, match):
    from morphkit.billboard.analytic import sphere_dome_asset
    from morphkit.billboard.domeasset import DomeAsset
    from morphkit.billboard.formats.domefile import read_dome
    from morphkit.errors import FileFormatError

    p = sphere_dome_asset(None, 32).save(tmp_path / "ball.npz")
    read_dome(p)  # the baked file passes (its depths within the planes)
    same = _redepth(p, tmp_path / "same.npz", lambda d, meta: d)
    assert np.array_equal(read_dome(same).depth, read_dome(p).depth, equal_nan=True)
    bad = _redepth(p, tmp_path / "bad.npz", edit)
    with pytest.raises(FileFormatError, match=match):
        read_dome(bad)
    with pytest.raises(FileFormatError, match=match):
        DomeAsset.load(bad)


# ------------------------------------------------------------ bake lights


@pytest.mark.parametrize("light, directional, match", [
    ((0.3, 0.0, 1.0), True, r"light with directional: expected a direction travelling down \(z < 0\) to "
                            r"reach the ground, got \(0.3, 0.0, 1.0\) \(z >= 0: away from it\)"),
    ((1.0, 0.0, 0.0), True, r"light with directional: expected a direction travelling down"),
    ((0.2, -0.1, -2.0), False, r"light: expected a point light above the ground \(z > 0\), got "
                               r"\(0.2, -0.1, -2.0\) \(at or under the ground\)"),
    ((0.2, -0.1, 0.0), False, r"light: expected a point light above the ground"),
], ids=["directional-up", "directional-level", "point-under", "point-on"])
def test_a_light_that_cannot_reach_the_ground_is_refused(light, directional, match):
    from morphkit.bake import ShadowAtlasKind
    from morphkit.errors import ValidationError

    with pytest.raises(ValidationError, match=match):
        ShadowAtlasKind(light=light, directional=directional)
    ShadowAtlasKind(light=(0.3, 0.0, -1.0), directional=True)  # what reaches it is taken
    ShadowAtlasKind(light=(0.2, -0.1, 0.5))


@pytest.mark.parametrize("argv, match", [
    (("--light", "0", "0", "1", "--directional"), r"light with directional: expected a direction travelling "
                                                  r"down"),
    (("--light", "0.2", "0", "-1"), r"light: expected a point light above the ground \(z > 0\)"),
], ids=["directional-up", "point-under"])
def test_bake_refuses_such_a_light_in_one_line(tmp_path, argv, match):
    import trimesh

    trimesh.creation.box().export(tmp_path / "box.ply")
    rc, line = morphkit_cli("bake", tmp_path / "box.ply", "-o", tmp_path / "out", *argv, timeout=300)
    assert rc == 2 and re.search(match, line), line  # a bad option value: a usage mistake
    assert not (tmp_path / "out").exists()


def test_directional_alone_takes_the_default_light_s_direction_down():
    """``--directional`` without ``--light`` just works: the default point light's way to the origin."""
    from morphkit.bake import ShadowAtlasKind
    from morphkit.bake.kinds import WARP_LIGHT

    assert ShadowAtlasKind().light == WARP_LIGHT
    kind = ShadowAtlasKind(directional=True)
    assert kind.light == tuple(-v for v in WARP_LIGHT) and kind.light[2] < 0
    assert kind.options()["light"] == [-v for v in WARP_LIGHT]


# ------------------------------------------------------------ files of other programs


def test_another_program_s_manifest_json_above_an_atlas_is_passed_by(tmp_path):
    import trimesh

    from morphkit.bake.manifest import MANIFEST_FORMAT, is_bake_manifest
    from morphkit.errors import FileFormatError, ValidationError
    from morphkit.programs.playback import baked_mesh

    trimesh.creation.box().export(tmp_path / "box.ply")
    (tmp_path / "site").mkdir()
    web = tmp_path / "site" / "manifest.json"
    web.write_text(json.dumps({"name": "My App", "start_url": "/", "icons": []}))
    atlas = tmp_path / "site" / "baked" / "box.atlas.npz"
    atlas.parent.mkdir()
    assert not is_bake_manifest(web)
    assert len(baked_mesh(atlas, tmp_path / "box.ply").faces) == 12  # the web app's file is not read as ours
    with pytest.raises(ValidationError, match=r"mesh of box.atlas.npz: expected a bake manifest listing the "
                       r"atlas \(its folder or a parent\), or --mesh, got neither"):
        baked_mesh(atlas)
    (tmp_path / "site" / "manifest.json").write_text("[1, 2")  # not JSON, not naming morphkit's format
    assert len(baked_mesh(atlas, tmp_path / "box.ply").faces) == 12
    damaged = json.dumps({"format": MANIFEST_FORMAT, "version": 1, "assets": {}})[:-9]  # ours, cut short
    (atlas.parent / "manifest.json").write_text(damaged)
    assert is_bake_manifest(atlas.parent / "manifest.json")
    with pytest.raises(FileFormatError, match=rf"manifest .*manifest.json: expected a {MANIFEST_FORMAT} "
                       r"JSON file"):
        baked_mesh(atlas, tmp_path / "box.ply")
