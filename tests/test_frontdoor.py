"""The front door: ``import morphkit`` is cheap and gives the names of the three jobs (imported on
first use), the conveniences those jobs use refuse bad input with morphkit's errors, and the
samples a user copies build their inputs from the public API (none imports the test scenes)."""

from __future__ import annotations

import ast
import importlib
import inspect
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import morphkit
from morphkit.errors import MeshError, ValidationError

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = sorted((ROOT / "samples").glob("*.py"))


HEAVY = ("pyrender", "OpenGL", "pyglet", "trimesh", "cv2", "numba")


def _loaded_after_import(code: str) -> list[str]:
    """The modules of :data:`HEAVY` a fresh interpreter holds after running ``code``."""
    probe = f"{code}\nimport sys\nprint(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT,
                         timeout=120)
    return ast.literal_eval(out.stdout.strip().splitlines()[-1])


def test_import_morphkit_loads_no_gl_and_no_heavy_library():
    assert _loaded_after_import("import morphkit") == []


def test_the_import_check_sees_a_heavy_import():
    """The check above can fail: a name of the GL boundary, used, loads pyrender."""
    assert "pyrender" in _loaded_after_import("import morphkit\nmorphkit.Renderer")


def test_every_exported_name_resolves_to_its_modules_own_object():
    assert {"bake_atlas", "ViewMorpher", "SunlitField", "Renderer", "sun"} <= set(morphkit.__all__)
    for name in morphkit.__all__:
        obj = getattr(morphkit, name)
        if inspect.isclass(obj) or inspect.isroutine(obj):
            home = importlib.import_module(obj.__module__)
            assert obj.__module__.startswith("morphkit."), (name, obj.__module__)
            assert getattr(home, name) is obj, name


def test_no_exported_name_is_also_a_submodule_name():
    """Importing ``morphkit.x`` sets the package's attribute ``x`` to the module: an exported
    function of that name (``morphkit.sun``) would turn into the module once anything imported it."""
    package = Path(morphkit.__file__).parent
    clashes = sorted(n for n in morphkit.__all__
                     if (package / f"{n}.py").exists() or (package / n / "__init__.py").exists())
    assert not clashes, f"exported names that are also submodules of morphkit: {clashes}"


def test_dir_lists_every_exported_name():
    assert set(morphkit.__all__) <= set(dir(morphkit))
    assert len(morphkit.__all__) == len(set(morphkit.__all__))


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="module 'morphkit' has no attribute 'bake_atlass'"):
        morphkit.bake_atlass  # noqa: B018 - the access is the test


# ----------------------------------------------------------------------- the conveniences

def test_sample_file_is_the_bundled_crate_and_refuses_other_names():
    path = morphkit.sample_file("photo_crate.glb")
    assert path.is_file() and path.parent.name == "data"
    with pytest.raises(ValidationError, match=r"sample file name: expected one of \['photo_crate.glb'\]"):
        morphkit.sample_file("crate.glb")


def _window_pair() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    scene = np.kron(rng.integers(0, 256, (24, 32), dtype=np.uint8), np.ones((4, 4), np.uint8))
    return scene[:, :112], scene[:, 16:]


def test_from_estimate_without_points_matches_the_images():
    left, right = _window_pair()
    default = morphkit.ViewMorpher.from_estimate(left, right).morph(0.5)
    given = morphkit.ViewMorpher.from_estimate(left, right, morphkit.from_images(left, right)).morph(0.5)
    assert np.array_equal(default, given)


def test_from_estimate_without_points_refuses_two_unrelated_images():
    left, _ = _window_pair()
    other = np.random.default_rng(1).integers(0, 256, left.shape, dtype=np.uint8)
    with pytest.raises(ValidationError, match="do not seem to show one scene"):
        morphkit.ViewMorpher.from_estimate(left, other)


@pytest.mark.parametrize("meshes, error, match", [
    ({}, ValidationError, "meshes: expected a non-empty mapping"),
    ([1], ValidationError, "meshes: expected a non-empty mapping name -> trimesh.Trimesh, got list"),
    ({"": None}, ValidationError, "asset name: expected a non-empty string"),
    ({"box": "box.glb"}, MeshError, "mesh of 'box': expected a trimesh.Trimesh, got str"),
])
def test_sunlit_field_refuses_bad_meshes_before_any_bake(meshes, error, match):
    with pytest.raises(error, match=match):
        morphkit.SunlitField.from_meshes(meshes, renderer=None)


def test_sunlit_field_refuses_what_is_not_a_scene():
    with pytest.raises(ValidationError, match="scene: expected a BillboardScene, got dict"):
        morphkit.SunlitField({}, {}, {}, renderer=None)


@pytest.mark.gl
def test_sunlit_field_small(renderer):
    import trimesh

    box, post = trimesh.creation.box((0.4, 0.4, 1.0)), trimesh.creation.cylinder(0.15, 0.8)
    field = morphkit.SunlitField.from_meshes({"box": box, "post": post}, renderer, n=3, seed=1, view_size=32,
                                             atlas_size=32)
    assert len(field.scene.instances) == 3 and set(field.atlases) == {"box", "post"}
    cam = field.camera((48, 64))
    cmp = field.compare(cam, morphkit.sun(30.0, 35.0))
    assert cmp.strip.shape == (48, 128, 3)
    assert 0.0 <= cmp.shadow_iou["ground"] <= 1.0
    assert cmp.billboards.rgb.shape == cmp.truth.rgb.shape == (48, 64, 3)
    with pytest.raises(ValidationError, match="sun: expected a DirectionalLight"):
        field.render(cam, (30.0, 35.0))
    with pytest.raises(ValidationError, match="meshes: expected one per asset of the scene"):
        morphkit.SunlitField(field.scene, {"box": box}, field.atlases, renderer)
    with pytest.raises(ValidationError, match="the mesh it was baked from"):
        morphkit.SunlitField(field.scene, {"box": post, "post": box}, field.atlases, renderer)


# ----------------------------------------------------------------------- the samples

def _fixture_imports(source: str) -> list[str]:
    """The imports of the demo/bench/test scenes (``morphkit.programs.fixtures``) in a script's source."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            bad += [f"line {node.lineno}: import {a.name}" for a in node.names
                    if a.name.startswith("morphkit.") and "fixtures" in a.name.split(".")]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [a.name for a in node.names]
            here = node.module.split(".")
            if here[0] == "morphkit" and ("fixtures" in here or "fixtures" in names):
                bad.append(f"line {node.lineno}: from {node.module} import {', '.join(names)}")
    return bad


def test_the_samples_are_found():
    assert len(SAMPLES) >= 5


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_no_sample_imports_the_test_scenes(path):
    assert _fixture_imports(path.read_text()) == []


def test_the_sample_scan_sees_a_fixture_import():
    src = ("from morphkit.programs.fixtures import demo_scene\nimport morphkit.programs.fixtures\n"
           "from morphkit import fixtures\nfrom morphkit.scene import Scene\n")
    assert _fixture_imports(src) == ["line 1: from morphkit.programs.fixtures import demo_scene",
                                     "line 2: import morphkit.programs.fixtures",
                                     "line 3: from morphkit import fixtures"]
