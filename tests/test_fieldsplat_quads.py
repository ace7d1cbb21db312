"""Atlas views drawn as meshes into the field's light view (issue 26: the instances' own surfaces).

:func:`~morphkit.sunlit.pointlevels.grid_quads` joins four drawn texels that meet at a corner
into a quad when their depths are within a gap; :class:`~morphkit.sunlit.fieldsplat.SplatDrawer`
rasterises the quads' triangles and squares only the other points. The analytic sphere
(:mod:`morphkit.billboard.analytic`) gives the expected depth: a triangle through three points of
a convex surface lies inside it, so seen along a view's own direction the quads are never nearer
than the sphere, where flat squares are (their depth does not follow the slope).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_view
from morphkit.billboard.frames.instances import Instances
from morphkit.errors import ValidationError
from morphkit.sunlit.fieldshadow import FieldShadow
from morphkit.sunlit.fieldsplat import SplatDrawer, splat_points
from morphkit.sunlit.pointlevels import grid_quads
from morphkit.sunlit.sunatlas import AtlasQuads, SunAtlas
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras, direction

DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
N = 64
TPU = 40.0
#: The atlas stores depth as float16 offsets from the camera distance, within the sphere's radius
#: (0.6) of it: each point is off by at most half a unit in the last place, 0.6 * 2**-11.
F16_DEPTH = 0.6 * 2.0**-11


@pytest.fixture(scope="module")
def ball() -> SunAtlas:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (N, N))
    depths = [sphere_view(cams.ortho_camera(a, e, (N, N)))[2]
              for a, e in zip(DOME.azimuths_deg(), DOME.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(DOME, cams, np.stack(depths))


def test_four_texels_at_one_depth_are_a_quad_and_a_step_cuts_them():
    drawn = np.ones((3, 4), bool)
    depth = np.zeros((3, 4))
    quads, inner = grid_quads(drawn, depth, 0.5)
    assert len(quads) == 6 and inner.tolist() == [False] * 5 + [True, True] + [False] * 5
    # a step of 1 between columns 1 and 2: the middle column of quads is dropped, no texel is inner
    depth[:, 2:] = 1.0
    quads, inner = grid_quads(drawn, depth, 0.5)
    assert len(quads) == 4 and not inner.any()
    assert all(len({q % 4 >= 2 for q in quad}) == 1 for quad in quads)  # none spans the step
    # an empty texel drops the four quads it is a corner of; indices follow the drawn texels
    drawn[1, 1] = False
    quads, inner = grid_quads(drawn, np.zeros((3, 4)), 0.5)
    assert len(quads) == 2 and quads.max() == drawn.sum() - 1 and not inner.any()


def test_a_quad_is_split_along_its_deeper_diagonal():
    # texels a b / e c; a valley along b-e (b and e deeper): kept, triangles (b, c, e), (b, e, a)
    quads, _ = grid_quads(np.ones((2, 2), bool), np.array([[0.0, 1.0], [1.0, 0.0]]), 5.0)
    assert quads.tolist() == [[1, 3, 2, 0]]
    # a ridge along b-e (b and e nearer): cut under along a-c, triangles (a, b, c), (a, c, e)
    quads, _ = grid_quads(np.ones((2, 2), bool), np.array([[1.0, 0.0], [0.0, 1.0]]), 5.0)
    assert quads.tolist() == [[0, 1, 3, 2]]


@pytest.mark.parametrize(("drawn", "depth", "gap", "match"), [
    (np.ones((3, 3), bool), np.zeros((3, 4)), 1.0, "drawn, depth"),
    (np.ones(3, bool), np.zeros(3), 1.0, "drawn, depth"),
    (np.ones((3, 3), bool), np.zeros((3, 3)), -1.0, "depth_gap"),
    (np.ones((3, 3), bool), np.zeros((3, 3)), np.nan, "depth_gap"),
])
def test_bad_quad_arguments_raise(drawn, depth, gap, match):
    with pytest.raises(ValidationError, match=match):
        grid_quads(drawn, depth, gap)


def test_the_atlas_packs_each_views_quads_into_its_points(ball):
    pk, aq = ball.packed_points(0), ball.packed_quads()
    assert aq is ball.packed_quads()  # made once
    assert len(aq.starts) == len(aq.lengths) == DOME.views and len(aq.inner) == len(pk.points)
    for k in range(DOME.views):
        q = aq.quads[aq.starts[k]:aq.starts[k] + aq.lengths[k]]
        assert len(q) > 100
        assert q.min() >= pk.starts[k] and q.max() < pk.starts[k] + pk.lengths[k]
    # a view of the whole sphere: all but its outline ring is inner
    assert 0.8 < aq.inner.mean() < 0.98


@pytest.mark.parametrize("k", [9, 16, 20])
def test_quads_seen_from_their_view_are_never_in_front_of_the_sphere(ball, k):
    """The sun along view ``k``: the one view drawn. Where the sphere covers a field texel's centre
    with three texels to spare (the view's outline ring keeps its squares, 1.25 field texels an
    atlas texel), the quads' depth is the sphere's or behind it (a chord), within the atlas's
    float16 storage; the squares' flat depth is in front across their slopes."""
    az, el = float(DOME.azimuths_deg()[k]), float(DOME.elevations_deg()[k])
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    maps = {}
    for quads in (True, False):
        fm = FieldShadow({"ball": ball}, SplatDrawer(max_level=0, quads=quads)).build(inst, direction(az, el),
                                                                                   TPU)
        maps[quads] = fm.depth
    truth = sphere_view(fm.camera)[2]
    inside = np.isfinite(truth)
    inner = cv2.erode(inside.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    assert inner.sum() > 1000
    assert np.isfinite(maps[True][inner]).all()
    ahead = truth[inner] - maps[True][inner]
    assert ahead.max() <= F16_DEPTH + 1e-5, ahead.max()
    texel = 1.0 / TPU
    assert (truth[inner] - maps[False][inner] > 0.1 * texel).sum() > 0.05 * inner.sum()


def _random_quads(rng: np.random.Generator, seg_start: np.ndarray, seg_len: np.ndarray, count: int
                  ) -> AtlasQuads:
    qs, starts, lens = [], [], []
    for a, n in zip(seg_start, seg_len, strict=True):
        starts.append(sum(len(q) for q in qs))
        q = a + rng.integers(0, n, (count, 4))
        qs.append(q)
        lens.append(count)
    inner = rng.random(int(seg_start[-1] + seg_len[-1])) < 0.5
    return AtlasQuads(np.concatenate(qs).astype(np.int64), np.array(starts, np.int64),
                      np.array(lens, np.int64), inner)


@pytest.mark.parametrize("bands", [1, 3])
def test_triangles_compiled_in_bands_equal_their_numpy_reference(monkeypatch, bands):
    """Random triangles and squares over two posed instances: the compiled kernel, one band or
    three, writes the numpy reference's map bit for bit (the same sums in the same order)."""
    from morphkit.sunlit import fieldsplat

    rng = np.random.default_rng(5)
    points = rng.uniform(-1.0, 1.0, (400, 3)).astype(np.float32)
    normals = rng.normal(size=(400, 3))
    normals = (normals / np.linalg.norm(normals, axis=1, keepdims=True)).astype(np.float32)
    seg_start, seg_len = np.array([0, 250]), np.array([250, 150])
    seg_dir = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    quads = _random_quads(rng, seg_start, seg_len, 60)
    T = np.zeros((2, 3, 4))
    T[0, :, :3], T[0, :, 3] = 6.0 * np.eye(3), [10.0, 12.0, 5.0]
    T[1, :, :3], T[1, :, 3] = 4.5 * np.eye(3)[[1, 0, 2]], [14.0, 19.5, 6.0]
    seg = np.array([[0, 1], [1, -1]])
    halves, suns = np.array([0.5, 0.4]), np.array([[0.0, 0.6, 0.8], [0.36, 0.48, 0.8]])
    got = []
    for compiled, n in ((False, 1), (True, bands)):
        monkeypatch.setattr(fieldsplat, "use_compiled", lambda _k, c=compiled: c)
        monkeypatch.setattr(fieldsplat, "WARP_THREADS", n)
        monkeypatch.setattr(fieldsplat, "PARALLEL_MIN_PIXELS", 0)
        d = np.full((30, 28), np.inf, np.float32)
        splat_points(d, points, normals, seg_start, seg_len, seg_dir, T, seg, halves, suns, quads=quads)
        got.append(d)
    squares = np.full((30, 28), np.inf, np.float32)
    splat_points(squares, points, normals, seg_start, seg_len, seg_dir, T, seg, halves, suns)
    assert np.isfinite(got[0]).sum() > np.isfinite(squares).sum()  # the triangles draw more
    np.testing.assert_array_equal(got[0], got[1])


def test_without_quads_the_drawer_is_the_squares_drawer(ball):
    """``quads=False`` and a field coarser than the atlas (levels above 0) draw squares only: the
    same map as the points splatted without quads."""
    inst = Instances.from_records([("ball", 0.0, 0.0, 30.0), ("ball", 1.5, 0.5, 200.0, 0.8)])
    sun = direction(-120.0, 35.0)
    fs = FieldShadow({"ball": ball}, SplatDrawer(quads=False))
    plain = fs.build(inst, sun, TPU).depth
    with_quads = FieldShadow({"ball": ball}, SplatDrawer()).build(inst, sun, TPU).depth
    assert not np.array_equal(plain, with_quads)
    coarse = FieldShadow({"ball": ball}, SplatDrawer()).build(inst, sun, TPU / 4.0).depth
    coarse_plain = FieldShadow({"ball": ball}, SplatDrawer(quads=False)).build(inst, sun, TPU / 4.0).depth
    np.testing.assert_array_equal(coarse, coarse_plain)


def test_the_drawers_quads_flag_is_a_bool():
    with pytest.raises(ValidationError, match="quads"):
        SplatDrawer(quads="yes")  # type: ignore[arg-type]
