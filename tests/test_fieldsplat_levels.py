"""Coarser atlas point levels for the field's splat (issue 26: small or far casters get coarser maps).

A flat square plate (side 1, at ``z = 1``) gives an atlas without GL whose shadow is known exactly:
in the field's orthographic light view it is the projection of its four corners. Its outline drawn
from a coarse level stays within one field texel of that (and of level 0's); a field finer than
the atlas keeps level 0 (the same map as the drawer without levels).
"""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard.frames.instances import Instances
from morphkit.errors import ValidationError
from morphkit.sunlit.fieldshadow import FieldShadow
from morphkit.sunlit.fieldsplat import SplatDrawer, splat_levels, splat_points
from morphkit.sunlit.pointlevels import block_points
from morphkit.sunlit.sunatlas import MAX_POINT_LEVEL, SunAtlas, sun_direction
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras

DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
N = 128
HALF = 0.5  # the plate's half side
HEIGHT = 1.0
PIVOT = np.array([0.0, 0.0, HEIGHT])


def _plate_depth(cam) -> np.ndarray:
    """Linear depth of the plate ``|x|, |y| <= HALF, z = HEIGHT`` seen by an orthographic camera."""
    p1, _ = cam.unproject(np.ones(cam.shape))
    p2, _ = cam.unproject(np.full(cam.shape, 2.0))
    ray = p2 - p1  # per unit depth
    t = 1.0 + (HEIGHT - p1[..., 2]) / ray[..., 2]
    hit = p1 + (t - 1.0)[..., None] * ray
    inside = (np.abs(hit[..., 0]) <= HALF) & (np.abs(hit[..., 1]) <= HALF) & (t > 0)
    return np.where(inside, t, np.inf)


@pytest.fixture(scope="module")
def plate() -> SunAtlas:
    cams = DomeCameras(PIVOT, 12.0, 0.75, (N, N))
    depths = [_plate_depth(cams.ortho_camera(a, e, (N, N)))
              for a, e in zip(DOME.azimuths_deg(), DOME.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(DOME, cams, np.stack(depths))


def _atlas_tpu(atlas: SunAtlas) -> float:
    return atlas.size / (2.0 * float(atlas.cameras.half_extent[0]))


def _exact(cam, inst: Instances) -> np.ndarray:
    """Field texels whose centres the plates' projections along the sun cover."""
    T = cam.texture_matrix()[:3]
    H, W = cam.shape
    cc, rr = np.meshgrid(np.arange(W), np.arange(H))
    out = np.zeros(cam.shape, bool)
    for k in range(len(inst)):
        sq = np.array([[-HALF, -HALF], [HALF, -HALF], [HALF, HALF], [-HALF, HALF]])
        corners = np.c_[sq, np.full(4, HEIGHT), np.ones(4)] @ inst.object2world(k).T
        uv = (corners @ T.T)[:, :2]
        inside = np.ones(cam.shape, bool)
        e1, e2 = uv[1] - uv[0], uv[2] - uv[0]
        sign = np.sign(e1[0] * e2[1] - e1[1] * e2[0])
        for i in range(4):
            a, b = uv[i], uv[(i + 1) % 4]
            inside &= sign * ((b[0] - a[0]) * (rr - a[1]) - (b[1] - a[1]) * (cc - a[0])) >= 0
        out |= inside
    return out


def _grow(mask: np.ndarray) -> np.ndarray:
    """``mask`` and every texel next to it (8 neighbours): within one texel."""
    p = np.pad(mask, 1)
    H, W = mask.shape
    return np.any([p[1 + dr:1 + dr + H, 1 + dc:1 + dc + W] for dr in (-1, 0, 1) for dc in (-1, 0, 1)], axis=0)


def test_a_coarse_level_keeps_the_plates_outline_within_one_field_texel(plate):
    inst = Instances.from_records([("plate", 0.0, 0.0, 30.0, 1.0), ("plate", 3.0, 1.0, -75.0, 0.8)])
    sun = sun_direction(-140.0, 38.0)
    tpu = _atlas_tpu(plate) / 4.0  # an atlas texel a quarter of a field texel
    maps = {}
    for lv in (0, MAX_POINT_LEVEL):
        drawer = SplatDrawer(max_level=lv)
        fm = FieldShadow({"plate": plate}, drawer).build(inst, sun, tpu)
        maps[lv] = (fm, drawer.last_levels)
    fine, coarse = (np.isfinite(maps[lv][0].depth) for lv in (0, MAX_POINT_LEVEL))
    assert maps[0][1].tolist() == [0, 0]
    assert maps[MAX_POINT_LEVEL][1].tolist() == [2, 2]  # 4 x 4 blocks: 0.25 * 4 = 1 field texel; 0.2 * 4
    exact = _exact(maps[0][0].camera, inst)
    assert exact.sum() > 300
    for got in (fine, coarse):
        assert not (got & ~_grow(exact)).any()
        assert not (exact & ~_grow(got)).any()
    assert not (coarse & ~_grow(fine)).any() and not (fine & ~_grow(coarse)).any()
    # both levels hold the same surface: a texel of place is 1.28 texels of depth on the plate under
    # this sun (cot 38 degrees), one more where a hole was filled from a neighbour
    both = fine & coarse
    err = np.abs(maps[MAX_POINT_LEVEL][0].depth[both] - maps[0][0].depth[both]) * tpu
    assert err.max() < 2.6 and np.median(err) < 0.5


def test_a_field_finer_than_the_atlas_keeps_level_zero(plate):
    inst = Instances.from_records([("plate", 0.0, 0.0, 30.0, 1.0), ("plate", 3.0, 1.0, -75.0, 0.6)])
    sun = sun_direction(20.0, 55.0)
    tpu = 1.7 * _atlas_tpu(plate)  # the smaller plate's texel 1.02 field texels
    depth = {}
    for lv in (0, MAX_POINT_LEVEL):
        drawer = SplatDrawer(max_level=lv)
        depth[lv] = FieldShadow({"plate": plate}, drawer).build(inst, sun, tpu).depth
        assert drawer.last_levels.tolist() == [0, 0]
    np.testing.assert_array_equal(depth[0], depth[MAX_POINT_LEVEL])


def test_the_level_is_the_coarsest_whose_texel_fits_the_field_texel():
    foot = np.array([2.0, 1.0, 0.5, 0.3, 0.25, 0.01])
    assert splat_levels(foot, MAX_POINT_LEVEL, 1.0).tolist() == [0, 0, 1, 1, 2, 6]
    assert splat_levels(foot, 1, 1.0).tolist() == [0, 0, 1, 1, 1, 1]
    assert splat_levels(foot, 0, 1.0).tolist() == [0] * 6
    assert splat_levels(foot, MAX_POINT_LEVEL, 2.0).tolist() == [0, 1, 2, 2, 3, 6]


def test_blocks_keep_a_slanted_planes_points_and_split_two_depths():
    n = 8
    r, c = np.mgrid[0:n, 0:n].astype(float)
    pts = np.stack([c, r, 0.3 * c], -1)  # a plane
    depth = 10.0 - 0.3 * c
    normals = np.tile(np.array([-0.3, 0.0, 1.0]) / np.hypot(0.3, 1.0), (n, n, 1))
    drawn = np.ones((n, n), bool)
    drawn[0, 0] = drawn[0, 1] = drawn[1, 0] = False  # a corner block of 1 of 4 texels
    p, nr, size = block_points(pts, drawn, normals, depth, 2, 4.0)
    assert len(p) == 16
    np.testing.assert_allclose(p[:, 2], 0.3 * p[:, 0], atol=1e-6)  # on the plane
    part = size == 1.0  # the corner block, 1 of its 4 texels drawn: at the next level, that texel
    np.testing.assert_allclose(p[part], [[1.0, 1.0, 0.3]])
    assert (size[~part] == 2.0).all() and part.sum() == 1
    np.testing.assert_allclose(nr, np.tile(normals[0, 0], (16, 1)), atol=1e-6)
    one = block_points(pts, drawn, normals, depth, 1, 4.0)
    np.testing.assert_array_equal(one[0], pts[drawn].astype(np.float32))
    assert (one[2] == 1.0).all()
    # a texel far behind its block's others: a second point, the front's centroid on the plane
    depth2 = depth.copy()
    depth2[7, 7] += 5.0
    pts2 = pts.copy()
    pts2[7, 7] = [7.0, 7.0, -10.0]
    p2, _, size2 = block_points(pts2, drawn, normals, depth2, 2, 1.0)
    assert len(p2) == 17
    front = np.flatnonzero(np.isclose(size2, np.sqrt(3.0)))
    back = np.flatnonzero(p2[:, 2] < -1.0)
    assert len(front) == len(back) == 1 and size2[back[0]] == 1.0
    np.testing.assert_allclose(p2[front[0]], [6 + 1 / 3, 6 + 1 / 3, 0.3 * (6 + 1 / 3)], atol=1e-5)
    np.testing.assert_allclose(p2[back[0]], [7.0, 7.0, -10.0])
    # blocks 4 a side: the corner one, 3 texels missing, as its four 2 x 2 sub-blocks (one of 1 texel)
    p4, _, size4 = block_points(pts, drawn, normals, depth, 4, 8.0)
    assert sorted(size4.tolist()) == pytest.approx([1.0] + [2.0] * 3 + [4.0] * 3)


def test_a_level_packs_fewer_points_of_the_same_area(plate):
    areas = []
    for lv in range(4):
        pk = plate.packed_points(lv)
        assert pk.points.shape == pk.normals.shape and len(pk.sizes) == len(pk.points)
        assert pk.lengths.sum() == len(pk.points)
        # each view's reach, packed once: its farthest point from the origin
        norms = np.linalg.norm(pk.points.astype(np.float64), axis=1)
        want = [norms[a:a + n].max() if n else 0.0 for a, n in zip(pk.starts, pk.lengths, strict=True)]
        np.testing.assert_allclose(pk.reach, want, rtol=1e-12)
        areas.append(float((pk.sizes.astype(np.float64) ** 2).sum()))
        if lv:
            assert len(pk.points) < len(plate.packed_points(lv - 1).points) / 2
    np.testing.assert_allclose(areas, areas[0], rtol=1e-5)
    assert plate.packed_points(2) is plate.packed_points(2)  # made once


def test_sized_points_splat_alike_compiled_and_in_numpy(monkeypatch):
    from morphkit.sunlit import fieldsplat

    rng = np.random.default_rng(11)
    points = rng.uniform(-1.0, 1.0, (300, 3)).astype(np.float32)
    normals = np.tile(np.array([[0.0, 0.0, 1.0]], np.float32), (300, 1))
    sizes = rng.choice([1.0, np.sqrt(2.0), 2.0, 4.0], 300).astype(np.float32)
    T = np.zeros((1, 3, 4))
    T[0, :, :3], T[0, :, 3] = 9.0 * np.eye(3), [12.0, 11.0, 5.0]
    out = []
    for compiled in (True, False):
        monkeypatch.setattr(fieldsplat, "use_compiled", lambda _k, c=compiled: c)
        d = np.full((24, 26), np.inf, np.float32)
        splat_points(d, points, normals, np.array([0]), np.array([300]), np.array([[0.0, 0.0, 1.0]]), T,
                     np.array([[0, -1, -1]]), np.array([0.3]), np.array([[0.0, 0.6, 0.8]]), sizes)
        out.append(d)
    np.testing.assert_array_equal(out[0], out[1])
    assert np.isfinite(out[0]).sum() > 150


def test_bad_level_parameters_raise(plate):
    with pytest.raises(ValidationError, match="max_level"):
        SplatDrawer(max_level=-1)
    with pytest.raises(ValidationError, match="max_level"):
        SplatDrawer(max_level=MAX_POINT_LEVEL + 1)
    with pytest.raises(ValidationError, match="max_texels"):
        SplatDrawer(max_texels=0.0)
    with pytest.raises(ValidationError, match="footprint"):
        splat_levels(np.array([0.5, 0.0]), 2, 1.0)
    with pytest.raises(ValidationError, match="level"):
        plate.packed_points(MAX_POINT_LEVEL + 1)
    g = np.zeros((4, 4, 3))
    m = np.ones((4, 4), bool)
    with pytest.raises(ValidationError, match="block"):
        block_points(g, m, g, np.zeros((4, 4)), 0, 1.0)
    with pytest.raises(ValidationError, match="depth_gap"):
        block_points(g, m, g, np.zeros((4, 4)), 2, -1.0)
    with pytest.raises(ValidationError, match="points, normals, depth"):
        block_points(g, m, g, np.zeros((4, 5)), 2, 1.0)
