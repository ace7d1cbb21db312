"""Property-based tests of scene files: whatever a JSON scene file or a glTF file holds, reading it
gives a scene or a morphkit error (expected vs got), never another exception.

Documents are made from a valid scene file by replacing, removing or adding values anywhere in
it; glTF files by corrupting a valid file's bytes or its JSON chunk. No GL: nothing is rendered.
"""

from __future__ import annotations

import json
from pathlib import Path

import trimesh
from hypothesis import event, given, settings
from hypothesis import strategies as st

from morphkit.errors import MorphkitError
from morphkit.scenes import SceneDescription, load_scene
from morphkit.scenes.jsonfile import scene_from_json

VALID = {
    "morphkit_scene": 1,
    "assets": [{"name": "tree", "source": "tree", "scale": 2.0}, {"name": "p", "source": "person"}],
    "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 1.0, "yaw_deg": 30.0, "scale": 1.1},
                             {"asset": "p", "x": 2.0, "y": 0.0}]},
    "camera": {"keyframes": [{"eye": [0.0, -8.0, 1.7], "target": [0.0, 0.0, 1.0]}], "yfov_deg": 45.0},
    "sun": {"day": {"max_elevation": 50.0}},
    "shadows": {"soft": "pcss", "sun_atlas_size": 64},
    "image": {"width": 64, "height": 48},
    "frames": 3,
    "views": None,
    "ground": {"cell": 2.0},
}

JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-(10**12), 10**12) | st.floats(allow_nan=True)
    | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12)


def _paths(obj, prefix=()):
    """Every path into ``obj`` (dict keys and list indices)."""
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _paths(v, (*prefix, i))


def _mutated(data) -> object:
    doc = json.loads(json.dumps(VALID))
    for _ in range(data.draw(st.integers(1, 3), label="edits")):
        paths = [p for p in _paths(doc) if p]
        if not paths:
            break
        path = data.draw(st.sampled_from(paths), label="where")
        parent = doc
        for k in path[:-1]:
            parent = parent[k]
        how = data.draw(st.sampled_from(["replace", "remove", "add"]), label="how")
        if how == "remove":
            del parent[path[-1]]
        elif how == "add" and isinstance(parent, dict):
            parent[data.draw(st.text(max_size=8), label="new key")] = data.draw(JSON_VALUES, label="new")
        else:
            parent[path[-1]] = data.draw(JSON_VALUES, label="value")
    return doc


@settings(deadline=None)
@given(data=st.data())
def test_any_scene_document_is_a_scene_or_a_morphkit_error(data):
    doc = _mutated(data)
    try:
        scene = scene_from_json(doc, where="s.json")
    except MorphkitError as exc:
        assert str(exc).startswith("scene file s.json"), str(exc)
        event(type(exc).__name__)
        return
    assert isinstance(scene, SceneDescription)
    event("read")


def _glb(tmp: Path) -> bytes:
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box([0.4, 0.3, 0.5]), node_name="a", geom_name="box")
    scene.add_geometry(trimesh.creation.box([0.4, 0.3, 0.5]), node_name="b", geom_name="box",
                       transform=trimesh.transformations.translation_matrix([2.0, 0.0, 0.0]))
    return scene.export(file_type="glb")


@settings(deadline=None)
@given(data=st.data())
def test_any_bytes_as_a_gltf_scene_are_a_scene_or_a_morphkit_error(tmp_path_factory, data):
    tmp = tmp_path_factory.mktemp("glb")
    raw = bytearray(_glb(tmp))
    how = data.draw(st.sampled_from(["flip", "truncate", "json"]), label="how")
    if how == "flip":
        for _ in range(data.draw(st.integers(1, 8), label="flips")):
            i = data.draw(st.integers(0, len(raw) - 1), label="at")
            raw[i] = data.draw(st.integers(0, 255), label="byte")
    elif how == "truncate":
        raw = raw[: data.draw(st.integers(0, len(raw) - 1), label="length")]
    else:  # a glTF JSON document of mutated nodes, meshes and scenes, as a .gltf
        doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
               "nodes": [{"mesh": 0}, {"children": [0], "translation": [1, 0, 0]}],
               "meshes": [{"primitives": []}]}
        key = data.draw(st.sampled_from(sorted(doc)), label="key")
        doc[key] = data.draw(JSON_VALUES, label="value")
        path = tmp / "s.gltf"
        path.write_text(json.dumps(doc))
        _read(path)
        return
    path = tmp / "s.glb"
    path.write_bytes(bytes(raw))
    _read(path)


def _read(path: Path) -> None:
    try:
        scene = load_scene(path)
    except MorphkitError as exc:
        event(type(exc).__name__)
        return
    assert isinstance(scene, SceneDescription)
    event("read")
