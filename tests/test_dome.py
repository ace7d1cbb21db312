"""Dome assets (#25): the view set, the camera rule, the per-pixel depth morph, the file.

The morph is checked on an analytic sphere (its albedo, normals and depth from any
camera are known exactly), so no GL is needed; one render-marked test bakes a mesh.
"""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_dome_asset, sphere_view
from morphkit.billboard.domeasset import DomeAsset
from morphkit.billboard.formats.domefile import DOME_VERSION, read_dome
from morphkit.errors import FileFormatError, ValidationError
from morphkit.views.dome import DEFAULT_RINGS, ViewDome
from morphkit.views.domecameras import DomeCameras, direction, quad_axes
from morphkit.views.gbuffer import linear_to_srgb, srgb_to_linear

PIVOT = SPHERE_PIVOT
R_BOUND = 1.0  # bounding radius of the analytic asset's rule
D = 12.0


def _sphere_view(cam):
    return sphere_view(cam)


def _sphere_asset(dome: ViewDome | None = None, size: int = 48) -> DomeAsset:
    return sphere_dome_asset(dome, size)


# ---------------------------------------------------------------- the view set

def test_weights_are_one_view_at_a_view_and_sum_to_one_between():
    dome = ViewDome()
    az, el = dome.azimuths_deg(), dome.elevations_deg()
    for k in range(dome.views):
        views, w = dome.weights(az[k], el[k])
        assert w[list(views).index(k)] == pytest.approx(1.0)
    rng = np.random.default_rng(3)
    for a, e in zip(rng.uniform(-180, 180, 50), rng.uniform(0, 90, 50), strict=True):
        views, w = dome.weights(a, e)
        assert np.all(w >= 0) and w.sum() == pytest.approx(1.0)
        # the weighted directions point the way asked (barycentric on the triangle)
        d = (w[:, None] * direction(az[views], el[views])).sum(axis=0)
        assert np.allclose(d / np.linalg.norm(d), direction(a, e), atol=1e-9)


def test_weights_change_continuously_across_a_triangle_edge():
    dome = ViewDome()
    az, el = dome.azimuths_deg(), dome.elevations_deg()
    full = np.zeros(dome.views)
    prev = None
    for a in np.linspace(0.0, 40.0, 401):  # crosses several triangle edges at 15 degrees up
        views, w = dome.weights(a, 15.0)
        full[:] = 0.0
        full[views] = w
        if prev is not None:
            assert np.abs(full - prev).max() < 0.05  # 0.1 degree steps: no jump
        prev = full.copy()
    assert az.shape == el.shape


def test_below_the_horizon_is_clamped_to_the_lowest_ring_and_top_is_the_top_view():
    dome = ViewDome()
    assert dome.clamp(-20.0) == 0.0 and dome.clamp(95.0) == 90.0
    assert [list(x) for x in dome.weights(10.0, -20.0)] == [list(x) for x in dome.weights(10.0, 0.0)]
    views, w = dome.weights(123.0, 90.0)
    top = dome.views - 1
    assert dome.elevations_deg()[top] == 90.0 and w[list(views).index(top)] == pytest.approx(1.0)
    assert ViewDome(((10.0, 8),), top=False).clamp(70.0) == 10.0


@pytest.mark.parametrize(("rings", "match"), [
    ((), "rings"), (((10.0, 8), (5.0, 8)), "increasing"), (((95.0, 8),), r"\[0, 90\)"),
    (((0.0, 2), (30.0, 8)), "views"), (((0.0, "x"),), "views")])
def test_bad_rings_are_refused(rings, match):
    with pytest.raises(ValidationError, match=match):
        ViewDome(rings)


# ---------------------------------------------------------------- the camera rule

@pytest.mark.parametrize(("a", "e"), [(0.0, 0.0), (37.0, 20.0), (-120.0, 65.0), (80.0, 90.0)])
def test_rule_axes_are_orthonormal_and_the_image_covers_the_quad(a, e):
    right, up = quad_axes(a, e)
    d = direction(a, e)
    m = np.stack([right, up, d])
    assert np.allclose(m @ m.T, np.eye(3), atol=1e-12)
    assert np.allclose(np.cross(up, d), right, atol=1e-12)
    rule = DomeCameras(PIVOT, D, R_BOUND, (40, 40))
    h = rule.half_extent[0]
    cam = rule.camera(a, e)
    px, _ = cam.project(np.array([PIVOT - h * right + h * up, PIVOT + h * right - h * up, PIVOT]))
    assert np.allclose(px, [[-0.5, -0.5], [39.5, 39.5], [19.5, 19.5]], atol=1e-9)


def test_rule_at_the_horizon_is_the_rings_vertical_quad():
    right, up = quad_axes(30.0, 0.0)
    assert np.allclose(up, [0, 0, 1]) and np.allclose(right, [-np.sin(np.pi / 6), np.cos(np.pi / 6), 0])


def test_quad_holds_the_bounding_sphere_from_every_direction():
    rule = DomeCameras(PIVOT, D, R_BOUND, (64, 64))
    for a, e in [(0, 0), (45, 45), (170, 89)]:
        cam = rule.camera(a, e)
        right, up = quad_axes(a, e)
        rim = PIVOT + R_BOUND * (np.cos(np.linspace(0, 6.3, 64))[:, None] * right
                                 + np.sin(np.linspace(0, 6.3, 64))[:, None] * up)
        px, _ = cam.project(rim)
        assert px.min() > -0.5 and px.max() < 63.5


# ---------------------------------------------------------------- the depth morph

def test_at_a_views_direction_the_surface_is_that_view_exactly():
    asset = _sphere_asset()
    k = 12
    a, e = asset.dome.azimuths_deg()[k], asset.dome.elevations_deg()[k]
    s = asset.surface(a, e)
    ref = asset.reference_surface(k)
    assert np.array_equal(s.albedo, ref.albedo) and np.array_equal(s.depth, ref.depth)


@pytest.mark.parametrize(("a", "e"), [(17.0, 11.0), (-101.0, 44.0), (66.0, 77.0), (140.0, 90.0), (5.0, -8.0)])
def test_sphere_morphed_between_views_matches_the_sphere_seen_there(a, e):
    """Ground truth: the sphere ray-cast from the direction's own camera. Alpha IoU and
    normals within the 1-pixel outline the march's sampling and the int8 normals allow."""
    asset = _sphere_asset()
    s = asset.surface(a, e)
    rgba, n_true, depth_true, hit = _sphere_view(asset.camera(a, e))
    alpha = s.alpha
    iou = np.minimum(alpha, hit).sum() / np.maximum(alpha, hit).sum()
    assert iou > 0.95
    inner = hit & (alpha > 0.99)
    inner[[0, -1], :] = False
    cos = np.einsum("ijk,ijk->ij", s.normal, n_true)[inner]
    assert np.median(cos) > 0.999 and cos.min() > 0.95
    assert np.median(np.abs(s.depth[inner] - depth_true[inner])) < 0.01
    # colour: albedo within a few levels of the truth's over the inner disc (median)
    truth = srgb_to_linear(rgba[..., :3])
    shown = s.albedo[..., :3] / np.maximum(alpha[..., None], 1e-6)
    assert np.median(np.abs(linear_to_srgb(shown) - linear_to_srgb(truth))[inner]) * 255 < 4


def test_morph_beats_its_baselines_on_the_sphere_between_views():
    asset = _sphere_asset()
    a, e = 20.0, 47.0
    rgba, _, _, hit = _sphere_view(asset.camera(a, e))
    truth = srgb_to_linear(rgba[..., :3]) * hit[..., None]

    def err(s):
        return np.mean((s.albedo[..., :3] - truth) ** 2)

    m, x = err(asset.surface(a, e)), err(asset.crossfade_surface(a, e))
    assert m < x


def test_levels_are_smaller_and_bad_levels_refused():
    asset = _sphere_asset()
    assert asset.surface(10.0, 20.0, 1).shape == asset.level_shape(1) == (24, 24)
    with pytest.raises(ValidationError, match="level"):
        asset.surface(10.0, 20.0, 2)


# ---------------------------------------------------------------- the file

def test_file_round_trip(tmp_path):
    asset = _sphere_asset()
    p = asset.save(tmp_path / "ball.npz")
    back = DomeAsset.load(p)
    assert back.memory_bytes == asset.memory_bytes == 27 * (48 * 48 + 24 * 24) * 9  # two levels
    assert np.array_equal(back.surface(33.0, 21.0).albedo, asset.surface(33.0, 21.0).albedo)


def _rewrite(path, out, edit_meta=None, edit_arrays=None):
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays.pop("meta")).decode())
    if edit_meta:
        edit_meta(meta)
    if edit_arrays:
        edit_arrays(arrays)
    np.savez(out, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
    return out


def test_a_ring_asset_from_before_is_refused_with_rebake(tmp_path):
    p = _sphere_asset().save(tmp_path / "ball.npz")

    def v2(meta):
        meta["version"] = 2
        meta.pop("kind")
    with pytest.raises(FileFormatError, match="re-bake"):
        read_dome(_rewrite(p, tmp_path / "old.npz", edit_meta=v2))
    assert DOME_VERSION == 3


def test_corrupt_and_bad_files_are_refused(tmp_path):
    p = _sphere_asset().save(tmp_path / "ball.npz")

    def flip(arrays):
        arrays["rgba"] = arrays["rgba"].copy()
        arrays["rgba"].flat[7] ^= 1
    with pytest.raises(FileFormatError, match="checksum"):
        read_dome(_rewrite(p, tmp_path / "c.npz", edit_arrays=flip))
    raw = p.read_bytes()
    (tmp_path / "t.npz").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(FileFormatError, match="unreadable|complete"):
        read_dome(tmp_path / "t.npz")
    with pytest.raises(FileFormatError, match="existing file"):
        read_dome(tmp_path / "missing.npz")
    assert zipfile.is_zipfile(p)


# ---------------------------------------------------------------- the bake (GL)

@pytest.mark.gl
def test_bake_dome_of_a_mesh_matches_its_render_between_views():
    from morphkit.billboard.baking.bakelook import BAKE_AMBIENT, bake_lights
    from morphkit.billboard.domeasset import DOME_SUPERSAMPLE, bake_dome
    from morphkit.meshes import sample_mesh
    from morphkit.render import Renderer

    mesh = sample_mesh("cow")
    with Renderer() as r:
        asset = bake_dome(mesh, r, name="cow", size=64, levels=2)
        items = asset.items(mesh)
        for a, e in [(25.0, 15.0), (-70.0, 52.0), (150.0, 80.0)]:
            p = r.source_passes(asset.camera(a, e), items, bake_lights(), ambient=BAKE_AMBIENT,
                                supersample=DOME_SUPERSAMPLE)
            s = asset.surface(a, e)
            iou = np.minimum(s.alpha, p.alpha).sum() / np.maximum(s.alpha, p.alpha).sum()
            assert iou > 0.85, (a, e, iou)


@pytest.mark.gl
def test_a_view_that_sees_nothing_is_refused_naming_it():
    import trimesh

    from morphkit.billboard.domeasset import bake_dome
    from morphkit.errors import DegenerateViewError
    from morphkit.render import Renderer

    card = trimesh.Trimesh(vertices=[[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]],
                           faces=[[0, 1, 2], [0, 2, 3]], process=False)  # flat: edge-on from the horizon
    with Renderer() as r, pytest.raises(DegenerateViewError, match=r"dome view 0 \(azimuth 0, elevation 0"):
        bake_dome(card, r, name="card", size=32, levels=1)


def test_exactly_between_three_views_the_weights_are_a_third_and_the_sphere_holds():
    """Hard case: the direction through a triangle's centroid (equal weights, no view dominant)."""
    asset = _sphere_asset()
    dome = asset.dome
    tri = dome.triangles()[7]
    d = direction(dome.azimuths_deg()[tri], dome.elevations_deg()[tri]).sum(axis=0)
    d /= np.linalg.norm(d)
    a, e = np.degrees(np.arctan2(d[1], d[0])), np.degrees(np.arcsin(d[2]))
    views, w = dome.weights(a, e)
    assert sorted(views.tolist()) == sorted(tri.tolist())
    # equal barycentric coordinates of the centroid's direction (up to the sphere's curvature: none
    # for the normalised sum of three unit vectors, which is equidistant from all three)
    np.testing.assert_allclose(w, 1.0 / 3.0, atol=1e-9)
    s = asset.surface(a, e)
    _, _, _, hit = _sphere_view(asset.camera(a, e))
    assert np.minimum(s.alpha, hit).sum() / np.maximum(s.alpha, hit).sum() > 0.95


def test_orthographic_views_morph_the_sphere_too():
    """The march projects through either projection: orthographic references and target (light
    views) morph the sphere as the perspective ones do."""
    from morphkit.views.depthmorph import morph_views

    rule = DomeCameras(PIVOT, D, R_BOUND, (48, 48))
    dome = ViewDome()
    views, w = dome.weights(23.0, 41.0)
    refs = []
    for k, wk in zip(views, w, strict=True):
        cam = rule.ortho_camera(dome.azimuths_deg()[k], dome.elevations_deg()[k], (48, 48))
        rgba, n, depth, _ = sphere_view(cam)
        from morphkit.views.gbuffer import decode_surface, encode_surface
        refs.append((cam, decode_surface(encode_surface(rgba, n, depth)), float(wk)))
    target = rule.ortho_camera(23.0, 41.0, (48, 48))
    s = morph_views(target, PIVOT, R_BOUND, refs)
    _, _, depth_true, hit = sphere_view(target)
    assert np.minimum(s.alpha, hit).sum() / np.maximum(s.alpha, hit).sum() > 0.95
    inner = hit & (s.alpha > 0.99)
    assert np.median(np.abs(s.depth[inner] - depth_true[inner])) < 0.01


def test_a_file_whose_ring_list_would_build_a_huge_dome_is_refused_at_once(tmp_path):
    """Generated input found it (the 10x profile): a file's ring list built the triangulation of
    millions of views before the arrays were checked against it -- a hang, now a capped count."""
    p = _sphere_asset(size=16).save(tmp_path / "ball.npz")

    def huge(meta):
        meta["rings"] = [[0.0, 10**7]]
    with pytest.raises(FileFormatError, match=r"views: expected an integer in \[3, 64\]"):
        DomeAsset.load(_rewrite(p, tmp_path / "huge.npz", edit_meta=huge))
    with pytest.raises(ValidationError, match="1 to 16"):
        ViewDome(tuple((float(e), 8) for e in range(17)))
    for bad in (float("inf"), float("nan")):  # found by the 10x profile: int() of them was a raw error
        def rings(meta, bad=bad):
            meta["rings"] = [[0.0, bad]]
        with pytest.raises(FileFormatError, match="finite numbers"):
            DomeAsset.load(_rewrite(p, tmp_path / "bad.npz", edit_meta=rings))


def test_weights_many_equals_weights_one_by_one():
    dome = ViewDome(DEFAULT_RINGS, top=True)
    az = np.array([-170.0, -36.0, 0.0, 17.5, 90.0, 359.0, 720.0 + 12.0])
    for el in (-10.0, 0.0, 14.0, 45.0, 60.0, 89.0):
        views, weights = dome.weights_many(az, el)
        for k, a in enumerate(az):
            v1, w1 = dome.weights(float(a), el)
            assert list(views[k]) == list(v1)
            np.testing.assert_allclose(weights[k], w1, atol=1e-12)
    ring = ViewDome(((0.0, 8),), top=False)
    views, weights = ring.weights_many(az[:3], 30.0)
    assert views.shape == weights.shape == (3, 3)
    with pytest.raises(ValidationError, match="finite angles"):
        dome.weights_many(np.array([0.0, np.nan]), 30.0)
