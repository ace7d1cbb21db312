"""A glTF file read as a scene (:mod:`morphkit.scenes.gltfscene`), no GL.

Expected values come from what the files were written with (the village's layout in
:mod:`morphkit.programs.village`, the nodes of the small files built here), turned ``+z`` up
independently of the reader: ``world = T @ file`` with ``T`` the +90 degree turn about ``x``.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.errors import MeshError
from morphkit.meshes import load_mesh, sample_file
from morphkit.programs import village
from morphkit.scenes.gltfdata import pack_glb, split_glb
from morphkit.scenes.gltfscene import EXT_INSTANCING, KHR_LIGHTS, read_gltf_scene
from morphkit.sunpath import SUN_INTENSITY

VILLAGE = Path(__file__).resolve().parent.parent / "samples" / "scenes" / "village.glb"

#: +y up (file) -> +z up (world), written out here rather than taken from the reader.
T = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])


def _doc(path: Path) -> dict:
    return split_glb(path.read_bytes(), str(path))[0]


def _quat(q_xyzw) -> np.ndarray:
    x, y, z, w = q_xyzw
    return trimesh.transformations.quaternion_matrix([w, x, y, z])[:3, :3]


def _node2file(node: dict) -> np.ndarray:
    """A root node's 4x4 transform from its JSON (matrix, or T R S)."""
    if "matrix" in node:
        return np.array(node["matrix"], dtype=float).reshape(4, 4).T
    m = np.eye(4)
    m[:3, :3] = _quat(node.get("rotation", [0, 0, 0, 1])) * np.array(node.get("scale", [1, 1, 1]))
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m


def _wrap(deg):
    return (np.asarray(deg) + 180.0) % 360.0 - 180.0


# --------------------------------------------------------------------------
# The village
# --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def scene():
    return read_gltf_scene(VILLAGE)


def test_village_has_its_three_meshes_and_a_node_each_instance(scene):
    keys = list(dict.fromkeys(k for k, *_ in village.VILLAGE_NODES))
    assert sorted(a.name for a in scene.assets) == sorted(keys)
    assert scene.instances.names == tuple(a.name for a in scene.assets)
    for k, asset in enumerate(scene.assets):
        written = sum(1 for n in village.VILLAGE_NODES if n[0] == asset.name)
        assert int(np.sum(scene.instances.asset == k)) == written
        lo, hi = asset.mesh.bounds  # normalised as morphkit.meshes.normalize does
        assert np.max(hi - lo) == pytest.approx(1.0) and lo[2] == pytest.approx(0.0, abs=1e-12)
        assert (lo[:2] + hi[:2]) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert scene.notes == ()  # a sun and a camera, every node upright, uniform and on the ground


def test_village_instances_keep_the_nodes_sizes_positions_and_yaws(scene):
    meshes = village.village_meshes()
    by_place = {(round(x, 6), round(y, 6)): (key, yaw, s) for key, _, x, y, yaw, s in village.VILLAGE_NODES}
    inst = scene.instances
    assert len(inst) == len(village.VILLAGE_NODES)
    for k in range(len(inst)):
        key, yaw, s = by_place[tuple(np.round(inst.xy[k], 6))]
        asset = scene.assets[int(inst.asset[k])]
        assert asset.name == key
        # the instance's size in the file's units is the node's: its scale times the mesh's extents
        assert inst.scale[k] * asset.mesh.extents == pytest.approx(s * meshes[key].extents, rel=1e-6)
        assert _wrap(inst.yaw_deg[k] - yaw) == pytest.approx(0.0, abs=1e-4)


def test_village_sun_is_the_light_nodes_minus_z_turned_z_up(scene):
    doc = _doc(VILLAGE)
    (i, node), = [(i, n) for i, n in enumerate(doc["nodes"]) if KHR_LIGHTS in n.get("extensions", {})]
    light = doc["extensions"][KHR_LIGHTS]["lights"][node["extensions"][KHR_LIGHTS]["light"]]
    assert light["type"] == "directional" and KHR_LIGHTS in doc["extensionsUsed"]
    expected = T @ _node2file(node)[:3, :3] @ [0.0, 0.0, -1.0]
    assert scene.sun.direction == pytest.approx(expected / np.linalg.norm(expected), abs=1e-9)
    el, az = np.radians(village.SUN_ELEVATION_DEG), np.radians(village.SUN_AZIMUTH_DEG)
    assert scene.sun.direction == pytest.approx(-np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az),
                                                           np.sin(el)]), abs=1e-6)
    assert scene.sun.intensity == SUN_INTENSITY


def test_village_camera_projects_points_where_the_gltf_camera_would(scene):
    doc = _doc(VILLAGE)
    node = next(n for n in doc["nodes"] if "camera" in n)
    persp = doc["cameras"][node["camera"]]["perspective"]
    h, w = 360, 640
    points = np.vstack([village.CAMERA_TARGET, [[x, y, 1.0] for _, _, x, y, _, _ in village.VILLAGE_NODES]])
    # the glTF way: file point -> camera (looks down -Z, +Y up) -> NDC -> pixels (centres at +0.5)
    file2cam = np.linalg.inv(_node2file(node))
    p_gl = (file2cam @ np.c_[points @ T, np.ones(len(points))].T).T[:, :3]  # world -> file is T^-1 = T^T
    t = np.tan(persp["yfov"] / 2)
    ndc = np.c_[p_gl[:, 0] / (-p_gl[:, 2] * t * w / h), p_gl[:, 1] / (-p_gl[:, 2] * t)]
    expected = np.c_[(ndc[:, 0] + 1) / 2 * w - 0.5, (1 - ndc[:, 1]) / 2 * h - 0.5]
    px, depth = scene.camera.model((h, w)).project(points)
    assert px == pytest.approx(expected, abs=1e-6)
    assert depth == pytest.approx(-p_gl[:, 2])
    assert px[0] == pytest.approx([(w - 1) / 2, (h - 1) / 2], abs=1e-6)  # it looks at the target
    assert (scene.camera.yfov, scene.camera.znear, scene.camera.zfar, scene.camera.aspect) == pytest.approx(
        (persp["yfov"], persp["znear"], persp["zfar"], persp["aspectRatio"]))


def test_write_village_reproduces_the_committed_file(tmp_path):
    written = village.write_village(tmp_path / "village.glb")
    assert VILLAGE.stat().st_size < 1_000_000
    new, old = _doc(written), _doc(VILLAGE)
    assert len(new["meshes"]) == len(old["meshes"]) == 3
    assert [m["name"] for m in new["meshes"]] == [m["name"] for m in old["meshes"]]
    assert [n.get("name") for n in new["nodes"]] == [n.get("name") for n in old["nodes"]]
    for a, b in zip(new["nodes"], old["nodes"], strict=True):
        assert _node2file(a) == pytest.approx(_node2file(b), abs=1e-9)
        assert (a.get("mesh"), a.get("camera"), a.get("extensions")) == (b.get("mesh"), b.get("camera"),
                                                                         b.get("extensions"))
    assert new["cameras"] == old["cameras"]
    assert new["extensions"] == old["extensions"] and new["extensionsUsed"] == old["extensionsUsed"]
    assert [a["count"] for a in new["accessors"]] == [a["count"] for a in old["accessors"]]


def test_the_village_is_valid_gltf():
    pytest.importorskip("jsonschema")
    from trimesh.exchange.gltf import validate

    doc = _doc(VILLAGE)
    validate(doc)  # the glTF 2.0 JSON schema trimesh ships (raises when invalid)
    assert doc["asset"]["version"] == "2.0" and KHR_LIGHTS in doc["extensionsUsed"]
    data = VILLAGE.read_bytes()
    json_length = struct.unpack("<I", data[12:16])[0]
    assert json_length % 4 == 0 and data[20 + json_length - 1:20 + json_length] in (b" ", b"}")


# --------------------------------------------------------------------------
# Small files written here
# --------------------------------------------------------------------------

#: The test mesh in the file's frame (+y up): a 2 x 1 x 1 box (x, y, z) standing on y = 0.
_BOX = trimesh.creation.box(extents=(2.0, 1.0, 1.0))
_BOX.apply_translation([0.0, 0.5, 0.0])


def _write(path: Path, nodes: list[dict], *, roots: list[int] | None = None, extra: bytes = b"",
           views: list[dict] = (), accessors: list[dict] = (), box_mesh: bool = True, **top) -> Path:
    """A .glb of the box mesh (accessors 0, 1), ``nodes``, and extra data after the mesh's bytes."""
    pos = np.asarray(_BOX.vertices, dtype=np.float32).tobytes()
    idx = np.asarray(_BOX.faces, dtype=np.uint32).tobytes()
    binary = pos + idx + extra
    doc = {"asset": {"version": "2.0"}, "nodes": nodes,
           "scenes": [{"nodes": roots if roots is not None else list(range(len(nodes)))}], "scene": 0,
           "buffers": [{"byteLength": len(binary)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                           {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}, *views],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(_BOX.vertices), "type": "VEC3",
                          "min": _BOX.bounds[0].tolist(), "max": _BOX.bounds[1].tolist()},
                         {"bufferView": 1, "componentType": 5125, "count": _BOX.faces.size, "type": "SCALAR"},
                         *accessors],
           **top}
    if box_mesh and "meshes" not in doc:
        doc["meshes"] = [{"name": "box", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}]
    if path.suffix == ".gltf":  # the buffer in a file beside it
        path.with_suffix(".bin").write_bytes(binary)
        doc["buffers"][0]["uri"] = path.with_suffix(".bin").name
        path.write_text(json.dumps(doc))
    else:
        path.write_bytes(pack_glb(doc, binary))
    return path


def _yaw_q(deg: float) -> list[float]:
    """glTF (x, y, z, w) quaternion of a turn about the file's +y (the world's +z)."""
    a = np.radians(deg) / 2
    return [0.0, float(np.sin(a)), 0.0, float(np.cos(a))]


def _expected(node2file: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Position, yaw (degrees) and scale an upright, uniformly scaled node gives the box."""
    a = T @ node2file[:3, :3] @ T.T
    s = np.cbrt(np.linalg.det(a))
    base = T @ node2file[:3, 3]  # the box's base centre is the file origin
    return base[:2], float(np.degrees(np.arctan2(a[1, 0], a[0, 0]))), s * 2.0  # the box's largest side: 2


def test_gpu_instancing_gives_one_instance_per_entry(tmp_path):
    n = 5
    rng = np.random.default_rng(3)
    t = np.c_[rng.uniform(-5, 5, n), np.zeros(n), rng.uniform(-5, 5, n)].astype(np.float32)
    yaws = rng.uniform(-170, 170, n)
    r = np.array([_yaw_q(y) for y in yaws], dtype=np.float32)
    s = np.repeat(rng.uniform(0.5, 2.0, (n, 1)), 3, axis=1).astype(np.float32)
    base = len(_BOX.vertices) * 12 + _BOX.faces.size * 4
    data = [t.tobytes(), r.tobytes(), s.tobytes()]
    offsets = np.cumsum([0, *map(len, data)])
    node = {"name": "crowd", "mesh": 0, "translation": [1.0, 0.0, -2.0], "rotation": _yaw_q(30.0),
            "extensions": {EXT_INSTANCING: {"attributes": {"TRANSLATION": 2, "ROTATION": 3, "SCALE": 4}}}}
    path = _write(tmp_path / "inst.glb", [node], extra=b"".join(data),
                  views=[{"buffer": 0, "byteOffset": int(base + o), "byteLength": len(d)}
                         for o, d in zip(offsets, data, strict=False)],
                  accessors=[{"bufferView": 2 + j, "componentType": 5126, "count": n, "type": kind}
                             for j, kind in enumerate(("VEC3", "VEC4", "VEC3"))],
                  extensionsUsed=[EXT_INSTANCING])
    got = read_gltf_scene(path)
    assert len(got.assets) == 1 and len(got.instances) == n
    node2file = _node2file(node)
    for j in range(n):
        trs = {"translation": t[j].tolist(), "rotation": r[j].tolist(), "scale": s[j].tolist()}
        inst2node = _node2file(trs)
        xy, yaw, scale = _expected(node2file @ inst2node)
        assert got.instances.xy[j] == pytest.approx(xy, abs=1e-5)
        assert _wrap(got.instances.yaw_deg[j] - yaw) == pytest.approx(0.0, abs=1e-4)
        assert got.instances.scale[j] == pytest.approx(scale, rel=1e-6)


def test_gpu_instancing_reads_strided_and_offset_accessors(tmp_path):
    # two translations interleaved with 4 bytes of padding, the accessor 4 bytes into its view
    t = np.array([[3.0, 0.0, 1.0], [-2.0, 0.0, 4.0]], dtype=np.float32)
    rows = b"".join(b"\xff" * 4 + row.tobytes() + b"\xff" * 4 for row in t)[:-4]
    node = {"mesh": 0, "extensions": {EXT_INSTANCING: {"attributes": {"TRANSLATION": 2}}}}
    path = _write(tmp_path / "strided.glb", [node], extra=rows,
                  views=[{"buffer": 0, "byteOffset": len(_BOX.vertices) * 12 + _BOX.faces.size * 4,
                          "byteLength": len(rows), "byteStride": 20}],
                  accessors=[{"bufferView": 2, "byteOffset": 4, "componentType": 5126, "count": 2,
                              "type": "VEC3"}])
    got = read_gltf_scene(path)
    assert got.instances.xy == pytest.approx((t @ T.T)[:, :2])


def test_a_mesh_of_two_primitives_is_one_asset_keeping_both_looks(tmp_path):
    prims = [{"attributes": {"POSITION": 0}, "indices": 1, "material": m} for m in (0, 1)]
    materials = [{"pbrMetallicRoughness": {"baseColorFactor": c}} for c in ([1, 0, 0, 1], [0, 0, 1, 1])]
    got = read_gltf_scene(_write(tmp_path / "two.glb", [{"mesh": 0}], meshes=[{"primitives": prims}],
                                 materials=materials))
    (asset,) = got.assets
    assert asset.name == "mesh0" and len(asset.mesh.faces) == 2 * len(_BOX.faces)
    texels = np.asarray(asset.mesh.visual.material.baseColorTexture.convert("RGB")).reshape(-1, 3)
    assert {(255, 0, 0), (0, 0, 255)} <= set(map(tuple, texels.tolist()))  # an atlas of both colours


def test_a_one_mesh_file_gives_the_mesh_load_mesh_gives():
    path = sample_file("photo_crate.glb")
    got, mesh = read_gltf_scene(path), load_mesh(path)
    (asset,) = got.assets
    assert np.sort(asset.mesh.vertices, axis=0) == pytest.approx(np.sort(mesh.vertices, axis=0))
    assert np.array_equal(np.asarray(asset.mesh.visual.material.baseColorTexture),
                          np.asarray(mesh.visual.material.baseColorTexture))  # the photo kept
    assert len(got.instances) == 1


def test_a_gltf_with_its_buffer_beside_it_reads_as_the_glb(tmp_path):
    nodes = [{"name": "a", "mesh": 0, "translation": [1.0, 0.0, -2.0], "rotation": _yaw_q(25.0)},
             {"name": "b", "mesh": 0, "translation": [-3.0, 0.0, 1.0], "scale": [2.0, 2.0, 2.0]}]
    glb, gltf = (read_gltf_scene(_write(tmp_path / f"s.{ext}", nodes)) for ext in ("glb", "gltf"))
    for name in ("xy", "yaw_deg", "scale"):
        assert getattr(gltf.instances, name) == pytest.approx(getattr(glb.instances, name))
    assert np.array_equal(gltf.assets[0].mesh.vertices, glb.assets[0].mesh.vertices)
    for k, node in enumerate(nodes):
        xy, yaw, scale = _expected(_node2file(node))
        got = [*gltf.instances.xy[k], gltf.instances.yaw_deg[k], gltf.instances.scale[k]]
        assert got == pytest.approx([*xy, yaw, scale])


def test_gpu_instancing_accessor_out_of_range_is_refused(tmp_path):
    node = {"mesh": 0, "extensions": {EXT_INSTANCING: {"attributes": {"TRANSLATION": 2}}}}
    path = _write(tmp_path / "bad.glb", [node], extra=bytes(24),
                  views=[{"buffer": 0, "byteOffset": len(_BOX.vertices) * 12 + _BOX.faces.size * 4,
                          "byteLength": 24}],
                  accessors=[{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3"}])
    with pytest.raises(MeshError, match=r"accessor 2 .*expected 3 elements within its buffer view"):
        read_gltf_scene(path)


def test_gpu_instancing_with_a_zero_scale_is_refused(tmp_path):
    scales = np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]], dtype=np.float32).tobytes()
    node = {"mesh": 0, "extensions": {EXT_INSTANCING: {"attributes": {"SCALE": 2}}}}
    path = _write(tmp_path / "zero.glb", [node], extra=scales,
                  views=[{"buffer": 0, "byteOffset": len(_BOX.vertices) * 12 + _BOX.faces.size * 4,
                          "byteLength": len(scales)}],
                  accessors=[{"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"}])
    with pytest.raises(MeshError, match=r"transform of instance 1 of node 0 .*expected an invertible matrix"):
        read_gltf_scene(path)


def test_a_file_without_light_or_camera_says_so(tmp_path):
    got = read_gltf_scene(_write(tmp_path / "plain.glb", [{"mesh": 0}]))
    assert got.sun is None and got.camera is None
    assert sum("no directional light" in n for n in got.notes) == 1
    assert sum("no perspective camera" in n for n in got.notes) == 1
    assert len(got.notes) == 2


def test_skins_and_animations_are_ignored_and_noted(tmp_path):
    nodes = [{"mesh": 0, "skin": 0, "children": [1]}, {"name": "bone"}]
    got = read_gltf_scene(_write(tmp_path / "skin.glb", nodes, roots=[0], skins=[{"joints": [1]}],
                                 animations=[{"channels": [], "samplers": []}]))
    assert len(got.instances) == 1
    assert any("skin" in n and "rest pose" in n for n in got.notes)
    assert any("1 animations ignored" in n for n in got.notes)


def test_nodes_without_meshes_are_transforms(tmp_path):
    nodes = [{"name": "group", "translation": [2.0, 0.0, -3.0], "rotation": _yaw_q(90.0), "children": [1, 2]},
             {"name": "empty"}, {"mesh": 0, "translation": [1.0, 0.0, 0.0]}]
    got = read_gltf_scene(_write(tmp_path / "group.glb", nodes, roots=[0]))
    xy, yaw, scale = _expected(_node2file(nodes[0]) @ _node2file(nodes[2]))
    assert got.instances.xy[0] == pytest.approx(xy) and got.instances.yaw_deg[0] == pytest.approx(yaw)
    assert len(got.notes) == 2  # only the missing light and camera


def test_tilt_non_uniform_scale_and_a_node_under_the_ground_are_noted(tmp_path):
    tilt = trimesh.transformations.quaternion_multiply(  # yaw 40 about file +y, then 30 about local x
        trimesh.transformations.quaternion_about_axis(np.radians(40), [0, 1, 0]),
        trimesh.transformations.quaternion_about_axis(np.radians(30), [1, 0, 0]))
    nodes = [{"name": "leaning", "rotation": [*tilt[1:], tilt[0]], "mesh": 0},
             {"name": "stretched", "scale": [1.0, 2.0, 1.0], "translation": [5.0, 0.0, 0.0], "mesh": 0},
             {"name": "buried", "translation": [-5.0, -0.5, 0.0], "mesh": 0}]
    got = read_gltf_scene(_write(tmp_path / "odd.glb", nodes))
    notes = "\n".join(got.notes)
    assert "1 nodes tilt their asset off the ground: yaw kept, tilt dropped ('leaning')" in notes
    assert "1 nodes scale non-uniformly: the mean scale kept ('stretched')" in notes
    assert "do not stand on the ground: set on the ground ('buried'" in notes
    assert got.instances.yaw_deg[0] == pytest.approx(40.0)
    assert got.instances.scale[1] == pytest.approx(np.mean([1.0, 2.0, 1.0]) * 2.0)
    assert got.instances.xy[2] == pytest.approx([-5.0, 0.0])  # set on the ground where it stood


def test_a_mirroring_node_keeps_its_asset_upright_unmirrored(tmp_path):
    node = {"name": "m", "mesh": 0, "scale": [-1.0, 1.0, 1.0]}
    got = read_gltf_scene(_write(tmp_path / "mirror.glb", [node]))
    notes = "\n".join(got.notes)
    assert "1 nodes mirror their asset: the mirror dropped ('m')" in notes and "tilt" not in notes
    # x -> -x is the unmirrored box turned half a turn (the box is symmetric in its frame's y)
    assert abs(got.instances.yaw_deg[0]) == pytest.approx(180.0)
    assert got.instances.scale[0] == pytest.approx(2.0)


def test_point_lights_orthographic_cameras_and_an_infinite_far_plane(tmp_path):
    lights = {KHR_LIGHTS: {"lights": [{"type": "point"}, {"type": "directional"}]}}
    cameras = [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}},
               {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.5}}]
    nodes = [{"mesh": 0, "translation": [0.0, 0.0, -10.0]},
             {"extensions": {KHR_LIGHTS: {"light": 0}}}, {"extensions": {KHR_LIGHTS: {"light": 1}}},
             {"camera": 0}, {"camera": 1, "translation": [0.0, 1.0, 5.0]}]
    got = read_gltf_scene(_write(tmp_path / "lights.glb", nodes, extensions=lights, cameras=cameras))
    assert any("point lights ignored" in n for n in got.notes)
    assert any("orthographic cameras ignored" in n for n in got.notes)
    assert got.sun.direction == pytest.approx(T @ [0.0, 0.0, -1.0])  # an unturned light: file -Z
    lo, hi = got.assets[0].mesh.bounds
    corners = np.array(np.meshgrid(*zip(lo, hi, strict=True), indexing="ij")).reshape(3, -1).T
    pts = (got.instances.object2world(0) @ np.c_[corners, np.ones(8)].T).T[:, :3]
    far = np.linalg.norm(pts - got.camera.cam2world[:3, 3], axis=1).max()
    assert np.isfinite(got.camera.zfar) and got.camera.zfar > far
    assert got.camera.model((10, 10)).zfar == got.camera.zfar


def test_up_z_takes_the_file_as_it_is(tmp_path):
    path = _write(tmp_path / "zup.glb", [{"mesh": 0, "translation": [1.0, 2.0, 0.0]}])
    got = read_gltf_scene(path, up="z")
    # not turned: the box's base is its face z = -0.5, centred at (0, 0.5) in x, y
    assert got.assets[0].mesh.extents == pytest.approx([1.0, 0.5, 0.5])
    assert got.instances.xy[0] == pytest.approx([1.0, 2.5])
    assert any("do not stand on the ground" in n for n in got.notes)


def test_a_file_with_no_meshes_is_an_empty_scene(tmp_path):
    got = read_gltf_scene(_write(tmp_path / "none.glb", [{"name": "empty"}], box_mesh=False))
    assert got.assets == () and len(got.instances) == 0
    assert any("no meshes" in n for n in got.notes)


def test_files_of_another_kind_or_broken_are_refused(tmp_path):
    png = tmp_path / "image.glb"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(40))
    with pytest.raises(MeshError, match=r"expected a binary glTF 2.0 file .*got first bytes b'\\x89PNG'"):
        read_gltf_scene(png)
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "nodes": [')
    with pytest.raises(MeshError, match=r"expected a glTF 2.0 file .*JSON that does not parse"):
        read_gltf_scene(broken)
    other = tmp_path / "mesh.obj"
    other.write_text("v 0 0 0\n")
    with pytest.raises(MeshError, match=r"expected a \.glb or \.gltf file"):
        read_gltf_scene(other)
    old = tmp_path / "old.gltf"
    old.write_text(json.dumps({"asset": {"version": "1.0"}}))
    with pytest.raises(MeshError, match=r"asset.version .*expected '2.0'"):
        read_gltf_scene(old)


def test_a_node_cycle_is_refused_as_check_node_graph_does(tmp_path):
    nodes = [{"mesh": 0, "children": [1]}, {"children": [0]}]
    with pytest.raises(MeshError, match=r"a cycle of children 0 -> 1 -> 0"):
        read_gltf_scene(_write(tmp_path / "cycle.glb", nodes, roots=[]))


@pytest.mark.parametrize(("node", "match"), [
    ({"mesh": 0, "scale": [1.0, 0.0, 1.0]}, r"expected an invertible matrix"),
    ({"mesh": 0, "matrix": [1.0] * 15 + [float("nan")]}, r"expected finite numbers"),
    ({"mesh": 0, "translation": [1.0, 2.0]}, r"translation of node 0 .*expected 3 numbers"),
    ({"mesh": 3}, r"mesh of node 0 .*expected an integer in \[0, 1\)"),
])
def test_bad_node_transforms_and_indices_are_refused(tmp_path, node, match):
    with pytest.raises(MeshError, match=match):
        read_gltf_scene(_write(tmp_path / "bad.glb", [node]))


@pytest.mark.parametrize(("scale", "match"), [(1e200, r"expected finite numbers, got an overflow"),
                                              (1e-200, r"expected an invertible matrix")])
def test_world_transforms_that_overflow_or_vanish_are_refused(tmp_path, scale, match):
    nodes = [{"scale": [scale] * 3, "children": [1]}, {"name": "deep", "scale": [scale] * 3, "mesh": 0}]
    with pytest.raises(MeshError, match=rf"world transform of .*'deep' .*{match}"):
        read_gltf_scene(_write(tmp_path / "far.glb", nodes, roots=[0]))


def test_glb_container_round_trip():
    doc = {"asset": {"version": "2.0"}, "nodes": [{"name": "a"}]}
    data = pack_glb(doc, b"12345")
    assert len(data) % 4 == 0 and struct.unpack("<4sII", data[:12]) == (b"glTF", 2, len(data))
    assert split_glb(data, "x") == (doc, b"12345\0\0\0")
    assert tol.GLTF_GROUND_REL < 1e-2  # a visible float is noted
