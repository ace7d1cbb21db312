"""The mesh mode (ground truth) of a billboard scene: GL renders, tiny sizes."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from billboard_fakes import FakeAsset

from morphkit.billboard import Backdrop, BillboardScene, Ground, Instances, MeshMode, MorphMode, Sky
from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.metrics import shadow_iou
from morphkit.scene import DirectionalLight, Item

pytestmark = pytest.mark.gl

FLAT = Backdrop(Ground(cell=None), Sky((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))


def _panel():
    """A thin 0.6 x 0.8 panel standing on the ground facing +x: from the front (azimuth 0)
    it covers exactly the fake asset's quad (half extent 0.3 x 0.4, pivot at height 0.4)."""
    m = trimesh.creation.box((0.002, 0.6, 0.8))
    m.apply_translation([0, 0, 0.4])
    return m


def test_mesh_mode_and_billboards_register_in_the_same_place(renderer):
    """Seen from the front, the panel mesh and the opaque billboard quad of the same size
    cover the same pixels (both through the same camera and instance poses)."""
    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1)
    inst = Instances.from_records([("solid", 0.0, 0.0), ("solid", 0.0, 1.5, 0.0, 0.7)])
    scene = BillboardScene({"solid": asset}, inst, backdrop=FLAT)
    cam = perspective(np.radians(40), (90, 120), look_at([3.5, 0.75, 0.4], [0, 0.75, 0.4]), znear=0.1)
    mesh = MeshMode(renderer, {"solid": [Item(_panel(), color=(0.2, 0.4, 0.8))]},
                    [DirectionalLight([0, 0, -1])])
    truth = scene.render(cam, mesh)
    bb = scene.render(cam, MorphMode())
    assert truth.stats.mode == "mesh" and truth.stats.n_drawn == 2
    a_mesh, a_bb = truth.layer[..., 3] > 0.5, bb.layer[..., 3] > 0.5
    assert a_mesh.sum() > 300
    # a panel seen near azimuth 0 (the eye is off-axis by up to 12 deg: cos = 0.978, a 0.002 thick panel) is
    # the quad up to the edge pixels: IoU > 0.9 (measured 0.969; edge pixels are ~7% of the area)
    assert shadow_iou(a_mesh, a_bb) > 0.9
    empty = (truth.layer[..., 3] == 0) & (bb.layer[..., 3] == 0)
    np.testing.assert_array_equal(truth.rgb[empty], bb.rgb[empty])  # the same backdrop


def test_mesh_mode_draws_every_instance_of_one_mesh(renderer):
    asset = FakeAsset("box", levels=1)
    recs = [("box", x, 0.0) for x in (-1.0, 0.0, 1.0)]
    scene = BillboardScene({"box": asset}, Instances.from_records(recs), backdrop=FLAT)
    cam = perspective(np.radians(50), (40, 96), look_at([0, -4, 0.3], [0, 0, 0.3]), znear=0.1)
    box = trimesh.creation.box((0.3, 0.3, 0.6))
    box.apply_translation([0, 0, 0.3])
    f = scene.render(cam, MeshMode(renderer, {"box": [Item(box)]}, [DirectionalLight([0, 0, -1])],
                                   supersample=2))
    px, _ = cam.project(np.array([[x, 0.0, 0.3] for x in (-1.0, 0.0, 1.0)]))
    for x, y in np.rint(px).astype(int):
        assert f.layer[y, x, 3] > 0.99
    assert f.layer[20, 4, 3] == 0.0
    with pytest.raises(ValidationError, match="mesh mode meshes: expected items for every asset"):
        scene.render(cam, MeshMode(renderer, {"other": [Item(box)]}))
