"""Frames mixing the real meshes with billboards (:mod:`morphkit.plan.mixed`), on small scenes
(32 px views, frames of 192 x 144): with no band of the mesh a mixed frame is its billboard mode's,
with every band the mesh it is the truth's, and between them a mesh hides what stands behind it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from morphkit.billboard.frames.compositor import finish, new_depth, new_layer
from morphkit.errors import ValidationError
from morphkit.plan.mixed import LitMeshBands, RingMeshBands, banded_mode, split_placements
from morphkit.plan.representations import CULL, MESH, BandChoice, BandedRing, BandedSurface, elevation_band
from morphkit.programs.scenerender import prepare_scene, scene_choices
from morphkit.scenes import load_scene
from morphkit.sunlit import LitMode
from morphkit.sunlit.litmesh import LitMeshMode

pytestmark = pytest.mark.gl

BASE = {
    "morphkit_scene": 1,
    "image": {"width": 96, "height": 72},
    "frames": 4,
    "asset_size": 32,
    "fog": False,
}
# two assets one behind the other on the camera's line of sight: the person (nearer) and the tree
ROW = {
    "assets": [{"name": "tree", "source": "tree", "scale": 2.0}, {"name": "person", "source": "person"}],
    "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 4.0}, {"asset": "person", "x": 0.0, "y": 0.0}]},
    "camera": {"keyframes": [{"eye": [0.0, -4.0, 1.0], "target": [0.0, 4.0, 1.0]}]},
    "image": {"width": 192, "height": 144},
}


def _prepared(tmp_path, renderer, **kw):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps({**BASE, **ROW, **kw}))
    scene = load_scene(path)
    sun, views, cams, _label, _chosen = scene_choices(scene, "plan")
    return prepare_scene(scene, renderer, views, head="", command="plan", sun=sun), cams


@pytest.fixture(scope="module")
def ring(renderer, tmp_path_factory):
    return _prepared(tmp_path_factory.mktemp("ring"), renderer, views=4)


@pytest.fixture(scope="module")
def relit(renderer, tmp_path_factory):
    return _prepared(
        tmp_path_factory.mktemp("relit"), renderer, sun={"azimuth_deg": 150.0, "elevation_deg": 48.0}
    )


def _draw(prep, cam, choice):
    mode = banded_mode(choice, prep.relit, prep.base, None, prep.meshes())
    return prep.scene.render(cam, mode)


@pytest.mark.parametrize("kind", ["ring", "relit"])
def test_no_band_of_the_mesh_is_the_billboard_mode_and_every_band_is_the_truth(kind, request):
    prep, cams = request.getfixturevalue(kind)
    cam = cams[0]
    assert len(prep.scene.plan(cam).placements) == 2
    none = banded_mode(BandChoice(), prep.relit, prep.base, None, prep.meshes())
    assert isinstance(none, LitMode if prep.relit else BandedRing)  # nothing of the mesh: no mixing
    mixed = LitMeshBands if prep.relit else RingMeshBands
    billboards = LitMode(BandedSurface(BandChoice()), prep.base) if prep.relit else BandedRing(BandChoice())
    through = mixed(BandChoice(), billboards, prep.meshes())
    np.testing.assert_array_equal(prep.scene.render(cam, through).rgb, prep.scene.render(cam, none).rgb)
    # every band the mesh: the truth's drawing (no shadows here, so the truth's own frame)
    every = _draw(prep, cam, BandChoice(default=MESH))
    np.testing.assert_array_equal(every.rgb, prep.scene.render(cam, prep.meshes()).rgb)


@pytest.mark.parametrize("kind", ["ring", "relit"])
def test_a_mesh_in_front_hides_the_billboard_behind_and_a_billboard_in_front_covers_the_mesh(kind, request):
    prep, cams = request.getfixturevalue(kind)
    cam = cams[0]
    meshes = prep.meshes()
    front = np.array([prep.scene.instances.names[a] for a in prep.scene.instances.asset]) == "person"
    idx_front, idx_back = np.flatnonzero(front), np.flatnonzero(~front)
    layer = meshes.shaded_layer if prep.relit else meshes.depth_layer
    person = layer(prep.scene, cam, idx_front)[0][:, :, 3] > 0
    assert person.sum() > 20
    only_mesh = prep.scene.render(cam, prep.meshes()).rgb
    # the person (in front) a mesh, the tree (behind) a billboard: the person's pixels are the truth's
    choice = BandChoice(default="morph", choices=_bands(prep, cam, "person", MESH))
    got = _draw(prep, cam, choice)
    np.testing.assert_array_equal(got.rgb[person], only_mesh[person])
    # the tree a mesh, the person a billboard: where the person's billboard is opaque over the tree's
    # mesh, the frame is the person's billboard (as drawn over the tree's billboard without meshes)
    choice = BandChoice(default="morph", choices=_bands(prep, cam, "tree", MESH))
    got = _draw(prep, cam, choice)
    alone = prep.scene.render(cam, banded_mode(BandChoice(), prep.relit, prep.base, None, None))
    (pl,) = [p for p in prep.scene.plan(cam).placements if p.asset == "person"]
    own = _alone(prep, cam, pl)
    tree = layer(prep.scene, cam, idx_back)[0][:, :, 3] > 0
    over = (own[:, :, 3] > 0.999) & tree
    assert over.sum() > 0  # the person stands in front of the tree on screen
    # at most one level apart: what of the tree shows through alpha > 0.999 is < 0.26 of a level
    np.testing.assert_allclose(got.rgb[over].astype(int), alone.rgb[over].astype(int), atol=1)
    # and the mesh is not drawn over it: the tree's mesh colour differs there
    assert not np.array_equal(got.rgb[over], only_mesh[over])


def _alone(prep, cam, pl):
    """The layer of one placement drawn alone by its billboard mode (the view morph)."""
    own = new_layer(cam.shape)
    if prep.relit:
        LitMode(BandedSurface(BandChoice()), prep.base).draw_placements(
            prep.scene, cam, [pl], own, new_depth(cam.shape)
        )
    else:
        BandedRing(BandChoice()).draw_placements(prep.scene, [pl], own)
    return own


def _bands(prep, cam, asset, rep):
    return {
        (pl.asset, pl.level, int(elevation_band(pl.elevation_deg))): rep
        for pl in prep.scene.plan(cam).placements
        if pl.asset == asset
    }


def test_a_plan_with_bands_of_the_mesh_needs_the_meshes_and_a_billboard_mode_refuses_them(ring):
    prep, cams = ring
    with pytest.raises(ValidationError, match=r"meshes: expected the scene's real meshes"):
        banded_mode(BandChoice(default=MESH), False, prep.base, None, None)
    with pytest.raises(ValidationError, match=r"expected a billboard representation .*got mesh"):
        prep.scene.render(cams[0], BandedRing(BandChoice(default=MESH)))
    with pytest.raises(ValidationError, match=r"meshes: expected a MeshMode, got LitMeshMode"):
        RingMeshBands(BandChoice(), BandedRing(BandChoice()), _lit(prep))
    meshes, billboards = split_placements(
        BandChoice(default="morph", choices=_bands(prep, cams[0], "tree", MESH)),
        prep.scene.plan(cams[0]).placements,
    )
    assert [pl.asset for pl in meshes] == ["tree"] and [pl.asset for pl in billboards] == ["person"]


def _lit(prep):
    return LitMeshMode(prep.meshes().renderer, prep.resolved.items, prep.base)


def test_a_relit_billboards_band_is_decided_where_its_mode_decides_it(ring):
    prep, cams = ring
    placements = prep.scene.plan(cams[0]).placements
    (tree,) = [pl for pl in placements if pl.asset == "tree"]
    choice = BandChoice(choices={("tree", tree.level, 1): MESH})  # the oblique band only
    assert elevation_band(tree.elevation_deg) == 0
    meshes, _ = split_placements(choice, placements)
    assert meshes == []
    # a mode rounding the elevation into the oblique band draws it there: so does the split
    meshes, billboards = split_placements(choice, placements, lambda pl: 45.0)
    assert meshes == [tree] and [pl.asset for pl in billboards] == ["person"]


@pytest.mark.parametrize("kind", ["ring", "relit"])
def test_a_culled_band_is_left_out_of_the_frame_and_its_placements_still_counted(kind, request):
    prep, cams = request.getfixturevalue(kind)
    cam = cams[0]
    placements = prep.scene.plan(cam).placements
    # every band culled: the backdrop alone (no shadows here), every placement still listed
    culled = _draw(prep, cam, BandChoice(default=CULL))
    np.testing.assert_array_equal(culled.rgb, finish(new_layer(cam.shape), prep.scene.backdrop.draw(cam)))
    assert [pl.index for pl in culled.placements] == [pl.index for pl in placements]
    assert not culled.layer[..., 3].any()
    # the tree culled, the person (in front) a billboard: the person's billboard alone over the backdrop
    person = BandChoice(default="morph", choices=_bands(prep, cam, "tree", CULL))
    got = _draw(prep, cam, person)
    (pl,) = [p for p in placements if p.asset == "person"]
    np.testing.assert_allclose(got.layer, _alone(prep, cam, pl), atol=1e-6)
    meshes, billboards = split_placements(person, placements)
    assert meshes == [] and [p.asset for p in billboards] == ["person"]
    # a culled band needs no meshes; a billboard mode refuses it
    assert isinstance(banded_mode(BandChoice(default=CULL), prep.relit, prep.base, None, None),
                      LitMeshBands if prep.relit else RingMeshBands)
    with pytest.raises(ValidationError, match=r"expected a billboard representation .*got cull"):
        prep.scene.render(cam, LitMode(BandedSurface(BandChoice(default=CULL)), prep.base)
                          if prep.relit else BandedRing(BandChoice(default=CULL)))
