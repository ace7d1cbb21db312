"""The field's ray-cast truth keeps each asset's look: a cut-out asset casts through its holes."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard.frames.instances import Instances
from morphkit.errors import ValidationError
from morphkit.imaging.cutout import mesh_cutout
from morphkit.imaging.groundtruth import hard_visibility
from morphkit.meshes import load_mesh, normalize
from morphkit.programs.fixtures import write_leaf_plant
from morphkit.scene import DirectionalLight, SceneObject
from morphkit.sunlit.fieldbaselines import posed_asset_meshes, posed_field_mesh, ray_cast_field
from morphkit.sunlit.sunatlas import sun_direction


@pytest.fixture(scope="module")
def plant(tmp_path_factory):
    return load_mesh(write_leaf_plant(tmp_path_factory.mktemp("plant")))


def _field():
    return Instances.from_records([("plant", 0.0, 0.0, 10.0), ("box", 1.5, 0.2, 0.0, 0.8),
                                   ("plant", -1.2, 0.9, 200.0, 1.2)])


def _grid(n: int = 96) -> np.ndarray:
    X, Y = np.meshgrid(np.linspace(-3.0, 3.0, n), np.linspace(-3.0, 3.0, n))
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def test_posed_asset_meshes_keep_the_cutout_that_concatenation_drops(plant):
    import trimesh

    meshes = {"plant": plant, "box": trimesh.creation.box((0.3, 0.3, 0.6))}
    posed = posed_asset_meshes(meshes, _field())
    assert len(posed) == 2 and mesh_cutout(posed[0]) is not None
    assert len(posed[0].faces) == 2 * len(plant.faces)
    assert mesh_cutout(posed_field_mesh(meshes, _field())) is None


def test_the_truth_is_the_product_of_the_instances_own_ray_casts(plant):
    import trimesh

    meshes = {"plant": plant, "box": trimesh.creation.box((0.3, 0.3, 0.6))}
    field, pts = _field(), _grid()
    sun = sun_direction(-30.0, 40.0)
    got = ray_cast_field(meshes, field, sun, pts)
    want = np.ones(len(pts), np.float32)
    light = DirectionalLight(-sun)
    for k in range(len(field)):
        name = field.names[int(field.asset[k])]
        body = normalize(meshes[name]).copy()
        body.apply_transform(field.object2world(k))  # scaled: not a rigid SceneObject pose
        want *= hard_visibility(pts, light, SceneObject(body))
    np.testing.assert_array_equal(got, want)
    opaque = ray_cast_field(meshes, field, sun, pts, posed=posed_field_mesh(meshes, field))
    assert (opaque < got).sum() > 20  # the leaves' holes: lit in the truth, shadowed when opaque
    assert not (opaque > got).any()


def test_an_asset_without_a_mesh_raises(plant):
    with pytest.raises(ValidationError, match="none for"):
        posed_asset_meshes({"plant": plant}, _field())
