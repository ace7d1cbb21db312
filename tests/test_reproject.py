"""Per-pixel 3-D reprojection of depth maps (morphkit.shadow.reprojection), no GL.

Expected values are derived analytically: a planar patch seen by a pinhole
camera, moved by ``e`` in the camera frame, has the depth map of the plane
``n . P = d + n . e`` at the moved patch.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from morphkit import settings
from morphkit.errors import ValidationError
from morphkit.shadow import reprojection as rp

FX = FY = 180.0
H, W = 64, 80
C = ((W - 1) / 2, (H - 1) / 2)


def _rays() -> tuple[np.ndarray, np.ndarray]:
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    return (x - C[0]) / FX, (y - C[1]) / FY


def _patch(n, d, lo, hi, e=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Depth map (float32, +inf outside) of the plane ``n . P = d`` restricted to the
    camera-frame box ``lo <= (X, Y) <= hi``, moved by ``e``."""
    n = np.asarray(n, float)
    e = np.asarray(e, float)
    rx, ry = _rays()
    z = (d + n @ e) / (n[0] * rx + n[1] * ry + n[2])
    X, Y = rx * z - e[0], ry * z - e[1]  # back in the patch's own frame
    inside = (X >= lo[0]) & (X <= hi[0]) & (Y >= lo[1]) & (Y <= hi[1]) & (z > 0)
    return np.where(inside, z, np.inf).astype(np.float32)


def _job(m, e, c_dst=C):
    """``(Source, Reprojection)`` of a map (or a Layer) moved by e."""
    src = m if isinstance(m, rp.Layer) else rp.Source(m)
    return src, rp.Reprojection(True, FX, FY, C, c_dst, e)


def _run(maps_es, *, threads=1, early_z=rp.EARLY_Z_TEXELS, c_dst=C):
    jobs = [_job(m, e, c_dst) for m, e in maps_es]
    out = np.full((H, W), np.inf, np.float32)
    box = rp.reproject_maps(jobs, out, threads=threads, early_z=early_z)
    return out, box


TILTED = dict(n=(0.2, -0.3, 1.0), d=2.0, lo=(-0.35, -0.25), hi=(0.3, 0.28))


def test_tilted_plane_moves_to_its_analytic_depth_map():
    """A tilted planar patch moved by e: the reprojected map covers what the
    analytic map covers (up to one pixel at the patch's border, where the quads
    between pixel centres stop) and has its depths."""
    e = (0.043, -0.031, 0.12)
    src = _patch(**TILTED)
    want = _patch(**TILTED, e=e)
    got, box = _run([(src, e)])
    inner = ndimage.binary_erosion(np.isfinite(want), iterations=1)
    outer = ndimage.binary_dilation(np.isfinite(want), iterations=1)
    assert inner.sum() > 1000
    assert np.all(np.isfinite(got[inner]))
    assert not np.any(np.isfinite(got[~outer]))
    # depth interpolated linearly over ~1 px triangles: exact for the plane's
    # vertices, second order in between ((dz/z)^2 ~ 1e-6 here); float32 maps
    np.testing.assert_allclose(got[inner], want[inner], rtol=2e-5)
    r0, r1, c0, c1 = box
    assert np.all(np.isinf(got[:r0])) and np.all(np.isinf(got[r1:]))
    assert np.all(np.isinf(got[:, :c0])) and np.all(np.isinf(got[:, c1:]))


def test_identity_reproduces_the_map_exactly_even_thin_features():
    src = _patch(**TILTED)
    src[5, 3:40] = 1.5  # a one-pixel line: in no triangle, drawn as points
    src[50, 70] = 1.7  # an isolated pixel
    got, _ = _run([(src, (0.0, 0.0, 0.0))])
    np.testing.assert_array_equal(got, src)
    # the kernel itself (not the identity shortcut) at a vanishing motion
    got2, _ = _run([(src, (0.0, 0.0, 1e-12))])
    np.testing.assert_array_equal(np.isfinite(got2), np.isfinite(src))
    np.testing.assert_allclose(got2[np.isfinite(src)], src[np.isfinite(src)], rtol=1e-7)


def test_principal_point_shift_is_a_pure_translation():
    """No motion, destination principal point moved by (3, -2) px: the image moves."""
    src = _patch(**TILTED)
    got, _ = _run([(src, (0.0, 0.0, 0.0))], c_dst=(C[0] + 3, C[1] - 2))
    want = np.full_like(src, np.inf)
    want[:-2, 3:] = src[2:, :-3]
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))
    np.testing.assert_allclose(got[np.isfinite(want)], want[np.isfinite(want)], rtol=1e-7)


def _occluded_scene(e):
    """A near strip in front of a far plane (a depth jump), moved by e."""
    far = _patch(n=(0, 0, 1.0), d=3.0, lo=(-0.9, -0.6), hi=(0.9, 0.6), e=e)
    near = _patch(n=(0, 0, 1.0), d=1.5, lo=(-0.08, -0.5), hi=(0.08, 0.5), e=e)
    return np.minimum(far, near)


def test_depth_jump_is_not_bridged_and_another_map_fills_the_disocclusion():
    """Moving sideways, the far plane behind the near strip is disoccluded: one map
    leaves it open (its triangles across the jump are stretched past
    STRETCH_PX and dropped), a second map that saw it fills it."""
    a, b = (0.0, 0.0, 0.0), (0.16, 0.0, 0.0)
    target = (0.08, 0.0, 0.0)
    want = _occluded_scene(target)
    one, _ = _run([(_occluded_scene(a), tuple(np.subtract(target, a)))])
    two, _ = _run([(_occluded_scene(a), tuple(np.subtract(target, a))),
                   (_occluded_scene(b), tuple(np.subtract(target, b)))])
    inner = ndimage.binary_erosion(np.isfinite(want), iterations=2)
    hole_one = inner & ~np.isfinite(one)
    assert hole_one.sum() > 40, "the disocclusion must open a hole in one map's reprojection"
    assert not np.any(inner & ~np.isfinite(two))
    both = inner & np.isfinite(two)
    np.testing.assert_allclose(two[both], want[both], rtol=1e-4)


def test_thread_split_changes_nothing_bit_for_bit():
    """Bands own disjoint output rows and draw in the one-thread order: the same bits for any
    thread count, with early z (whose skips depend on what a pixel already holds) too."""
    e1, e2 = (0.05, -0.02, 0.1), (-0.03, 0.04, -0.05)
    maps = [(_occluded_scene((0, 0, 0)), e1), (_patch(**TILTED), e2)]
    for early_z in (0.0, rp.EARLY_Z_TEXELS, 50.0):  # 50 texels: early z skips much more
        ref, box = _run(maps, threads=1, early_z=early_z)
        assert np.isfinite(ref).sum() > 1500
        for t in (2, 3, 4, 5):
            got, b = _run(maps, threads=t, early_z=early_z)
            np.testing.assert_array_equal(got, ref)
            assert b == box


def test_compiled_kernel_agrees_with_the_numpy_reference(monkeypatch):
    e = (0.037, -0.029, 0.08)
    maps = [(_occluded_scene((0, 0, 0)), e), (_patch(**TILTED), (-0.02, 0.01, 0.03))]
    got, _ = _run(maps, early_z=0.0)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref, _ = _run(maps, early_z=0.0)
    # same triangles and coverage rule; barycentrics by division (numpy) or by
    # edge functions (kernel), and where a quad folds the kernel keeps its first
    # triangle's depth: measured identical on this scene, float rounding allowed
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(ref))
    both = np.isfinite(ref)
    np.testing.assert_allclose(got[both], ref[both], rtol=1e-6)


def test_layer_kernel_agrees_with_the_numpy_reference(monkeypatch):
    """A hidden layer drawn from its run list (compiled) and from its quad mask (numpy)."""
    a, b = (0.0, 0.0, 0.0), (0.16, 0.0, 0.0)
    layer = _layer_at(_occluded_scene(a), a, _occluded_scene(b), b)
    maps = [(layer, (-0.08, 0.01, 0.02))]
    got, _ = _run(maps, early_z=0.0)
    assert np.isfinite(got).sum() > 1000
    for t in (2, 3):  # bands split the runs: the same minimum
        np.testing.assert_array_equal(_run(maps, threads=t, early_z=0.0)[0], got)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref, _ = _run(maps, early_z=0.0)
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(ref))
    both = np.isfinite(ref)
    np.testing.assert_allclose(got[both], ref[both], rtol=1e-6)


def test_stretched_quads_cover_what_the_numpy_reference_covers(monkeypatch):
    """Across a slanted depth jump moved far, quads with one corner across it are
    stretched and draw one triangle of two: the kernel tests only the centres of the
    triangles it draws, the reference every centre of every kept triangle; the same
    coverage and depths."""
    y, x = np.mgrid[0:H, 0:W]
    band = np.abs(x + 0.8 * y - 50) < 9  # slanted edges: quads with one corner (a or d) across
    depth = np.where(band, np.float32(1.5), _patch(n=(0, 0, 1.0), d=3.0, lo=(-0.9, -0.6), hi=(0.9, 0.6)))
    e = (0.25, -0.12, 0.3)  # ~11 px of parallax between the band and the plane
    maps = [(depth, e)]
    got, _ = _run(maps, early_z=0.0, c_dst=(C[0] + 3.5, C[1] - 2.25))
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref, _ = _run(maps, early_z=0.0, c_dst=(C[0] + 3.5, C[1] - 2.25))
    assert np.isfinite(ref).sum() > 2000
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(ref))
    both = np.isfinite(ref)
    np.testing.assert_allclose(got[both], ref[both], rtol=1e-6)


def test_a_layer_draws_its_runs_as_one_run_at_a_time_would(rng):
    """The layer kernel keeps each projected row for the next row's runs: a layer of
    random quads draws, bit for bit, what its runs drawn as one layer each draw."""
    depth = _occluded_scene((0.0, 0.0, 0.0))
    fin = np.isfinite(depth).astype(np.int8)
    solid = (fin[:-1, :-1] + fin[:-1, 1:] + fin[1:, :-1] + fin[1:, 1:]) >= 3
    quads = solid & (rng.random(solid.shape) < 0.6)
    layer = rp.Layer(depth, quads)
    assert len(layer.runs) > 500
    e = (0.09, -0.04, 0.05)
    got, box = _run([(layer, e)], early_z=0.0)
    one = [rp.Layer(depth, np.isin(np.arange(solid.shape[0]), [r])[:, None] & quads & _cols(solid, a, b))
           for r, a, b in layer.runs]
    ref, ref_box = _run([(lay, e) for lay in one], early_z=0.0)  # z-buffer min: any order
    assert np.isfinite(got).sum() > 1500
    np.testing.assert_array_equal(got, ref)
    assert box == ref_box


def _cols(solid, a, b):
    """The quads of columns ``a .. b - 1``."""
    m = np.zeros(solid.shape, bool)
    m[:, a:b] = True
    return m


def _layer_at(primary, e_primary, secondary, e_secondary):
    """The hidden layer of a map baked with the object at ``e_secondary`` against
    one baked at ``e_primary`` (the motion between them: their difference)."""
    move = _job(secondary, tuple(np.subtract(e_primary, e_secondary)))[1]
    return rp.hidden_layer(primary, secondary, move)


def _corners(layer):
    """The pixels at the corners of a layer's quads."""
    q = layer.quads()
    px = np.zeros((H, W), bool)
    px[:-1, :-1] |= q
    px[:-1, 1:] |= q
    px[1:, :-1] |= q
    px[1:, 1:] |= q
    return px


def test_hidden_layer_of_a_plane_is_at_most_its_rim():
    """Two maps of one planar patch: the primary's surface, interpolated
    bilinearly, explains every pixel of the other map away from the patch's
    border (perspective depth is not bilinear in the image, but within a pixel
    it differs by far less than a texel), so the layer keeps at most a rim."""
    b = (0.05, -0.03, 0.02)
    sec = _patch(**TILTED, e=b)
    layer = _layer_at(_patch(**TILTED), (0, 0, 0), sec, b)
    assert layer.depth is sec  # shared, not copied
    fin = np.isfinite(sec)
    kept = _corners(layer) & fin  # (a quad of 3 object pixels has a background corner)
    assert 0 < kept.sum() < 0.2 * fin.sum()
    # the rim: landing next to the primary's border (a neighbour background),
    # and the other corners of the quads there
    assert not np.any(kept & ndimage.binary_erosion(fin, iterations=3))


def test_layered_reprojection_equals_the_whole_maps_and_holds_the_disocclusion():
    """The far plane behind the near strip, hidden from the primary's position,
    is in the neighbour's layer; reprojecting the primary with that layer gives
    the coverage of the two whole maps (and their depths within early z)."""
    a, b, target = (0.0, 0.0, 0.0), (0.16, 0.0, 0.0), (0.08, 0.0, 0.0)
    prim, sec = _occluded_scene(a), _occluded_scene(b)
    layer = _layer_at(prim, a, sec, b)
    assert layer.cum[-1] < 0.35 * np.isfinite(sec).sum()
    # the neighbour's pixels that land, at a, where the primary holds the near
    # strip in front of them (z 1.5 against 3): hidden from a, so in the layer
    ys, xs = np.mgrid[0:H, 0:W].astype(np.float64)
    x, y, z = _job(sec, tuple(np.subtract(a, b)))[1].move(xs, ys, sec.astype(np.float64))
    i = np.clip(np.floor(x + 0.5), 0, W - 1).astype(int)
    j = np.clip(np.floor(y + 0.5), 0, H - 1).astype(int)
    behind = np.isfinite(sec) & (prim[j, i] < z - 1.0)
    assert behind.sum() > 40 and np.all(_corners(layer)[behind])
    whole, _ = _run([(prim, tuple(np.subtract(target, a))), (sec, tuple(np.subtract(target, b)))])
    got, _ = _run([(prim, tuple(np.subtract(target, a))), (layer, tuple(np.subtract(target, b)))])
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(whole))
    fin = np.isfinite(whole)
    assert np.all(np.abs(got[fin] - whole[fin]) <= rp.EARLY_Z_TEXELS * whole[fin] / FX * 1.001)


def test_orthographic_motion_is_a_translation():
    src = _patch(**TILTED)
    rp_o = rp.Reprojection(False, 100.0, 100.0, C, C, (0.03, -0.02, 0.5))  # 3 px right, 2 up
    out = np.full((H, W), np.inf, np.float32)
    rp.reproject_maps([(rp.Source(src), rp_o)], out)
    want = np.full_like(src, np.inf)
    want[:-2, 3:] = src[2:, :-3] + np.float32(0.5)
    np.testing.assert_array_equal(np.isfinite(out), np.isfinite(want))
    np.testing.assert_allclose(out[np.isfinite(want)], want[np.isfinite(want)], rtol=1e-6)


def test_an_unchecked_reprojection_is_the_checked_one():
    e = (0.05, -0.02, 0.1)
    ref = rp.Reprojection(True, FX, FY, C, (C[0] + 1.25, C[1] - 0.5), e)
    got = rp.Reprojection.unchecked(True, [FX, FY, C[0], C[1], C[0] + 1.25, C[1] - 0.5, *e])
    assert got.perspective and got.params.dtype == np.float64
    np.testing.assert_array_equal(got.params, ref.params)
    assert not got.identity


def test_bad_input_is_refused():
    with pytest.raises(ValidationError, match="finite parameters"):
        rp.Reprojection(True, FX, FY, C, C, (np.nan, 0, 0))
    with pytest.raises(ValidationError, match="fx, fy > 0"):
        rp.Reprojection(True, 0.0, FY, C, C, (0, 0, 0))
    with pytest.raises(ValidationError, match=r"float32 \(H, W\).*float64"):
        rp.Source(np.zeros((4, 4)))
    with pytest.raises(ValidationError, match="z-buffer"):
        rp.reproject_maps([], np.zeros((4, 4)))
    with pytest.raises(ValidationError, match=r"quads: expected a \(3, 3\) mask, got \(4, 4\)"):
        rp.Layer(np.zeros((4, 4), np.float32), np.zeros((4, 4), bool))
    with pytest.raises(ValidationError, match=r"secondary map: expected the primary's shape \(4, 4\)"):
        rp.hidden_layer(np.zeros((4, 4), np.float32), np.zeros((4, 5), np.float32),
                        rp.Reprojection(True, FX, FY, C, C, (0, 0, 0)))


def test_orphans_are_pixels_in_no_triangle():
    d = np.full((6, 7), np.inf, np.float32)
    d[1:4, 1:4] = 1.0  # a block: every pixel in a triangle
    d[5, 6] = 2.0  # isolated
    d[0, 6] = d[1, 6] = 2.0  # a vertical pair: no triangle
    got = {tuple(p) for p in rp.orphans(d)}
    assert got == {(5, 6), (0, 6), (1, 6)}
