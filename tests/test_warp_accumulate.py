"""Tests of the fused warp-and-accumulate pass (morphkit.warp.accumulate_warps,
morphkit.warp.scanline.accumulate): exact bilinear values of a known affine warp,
agreement with the maps + cv2.remap path, skipping triangles that read only
zeros, independence of the thread split, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from morphkit import settings
from morphkit.errors import ValidationError
from morphkit.warp import Accumulation, MeshWarper, accumulate_warps
from morphkit.warp import accumulate as W

needs_numba = pytest.mark.skipif(not settings.COMPILED,
                                 reason="the fused pass needs numba (and not MORPHKIT_WARP_NUMPY=1)")


def two_planes(h: int, w: int, rng: np.random.Generator) -> np.ndarray:
    """A premultiplied-like source: coverage 0/1 on a blob, value = coverage * smooth field."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    cov = (((xx - 0.45 * w) / (0.3 * w)) ** 2 + ((yy - 0.55 * h) / (0.25 * h)) ** 2 < 1.0)
    val = 2.0 + np.sin(xx / 7.0) + 0.5 * np.cos(yy / 5.0) + rng.normal(0, 0.01, (h, w))
    return np.stack([cov, cov * val]).astype(np.float32)


def lattice(rows: int, cols: int, x0: float, x1: float, y0: float, y1: float) -> np.ndarray:
    gx, gy = np.meshgrid(np.linspace(x0, x1, cols), np.linspace(y0, y1, rows))
    return np.c_[gx.ravel(), gy.ravel()]


def bilinear(plane: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Exact bilinear samples, 0 beyond the border and blended across it (what
    cv2.remap's BORDER_CONSTANT does, without its 1/32 px quantisation)."""
    return ndimage.map_coordinates(plane.astype(np.float64), [y, x], order=1, mode="grid-constant",
                                   cval=0.0)


@needs_numba
@pytest.mark.parametrize("margin, offset", [(0.0, (3.3, -2.7)), (12.0, (-30.25, 11.5))])
def test_affine_warp_gives_exact_bilinear_values(margin, offset):
    """One global affine warp (every triangle has the same affine): each covered
    pixel gets ``weight * bilinear(src, A^-1 p)`` to float32 precision, also where
    the footprint leaves the source (triangles at the image edge; with ``margin``
    the source mesh reaches 12 px beyond the image, whose border reads 0)."""
    rng = np.random.default_rng(4)
    h, w = 90, 120
    src = two_planes(h, w, rng)
    src[:, :, :4] = src[:, :, -4:] = 1.0  # something to blend at the left and right borders
    src_pts = lattice(6, 8, -margin, w - 1 + margin, -margin, h - 1 + margin)
    A = np.array([[1.07, 0.06], [-0.04, 0.95]])
    dst_pts = src_pts @ A.T + np.asarray(offset)
    warper = MeshWarper(src_pts)
    acc = np.zeros((2, h, w), np.float32)
    plan = warper.accumulation(dst_pts, (h, w))
    assert isinstance(plan, Accumulation)
    everything = np.ones(len(warper.triangles), bool)
    roi = accumulate_warps([(plan, src, everything, 0.75)], acc)
    mask = warper.maps(dst_pts, (h, w)).mask  # the covered pixel centres (tested in test_warp)
    r0, r1, c0, c1 = roi
    assert mask.any() and not mask[:r0].any() and not mask[r1:].any()
    assert not mask[:, :c0].any() and not mask[:, c1:].any()
    yy, xx = np.nonzero(mask)
    p = np.linalg.solve(A, (np.c_[xx, yy] - np.asarray(offset)).T)  # source positions
    for k in range(2):
        expected = 0.75 * bilinear(src[k], p[0], p[1])
        # float32 weights and sums: 1e-5 relative to values of at most ~3.5
        np.testing.assert_allclose(acc[k][yy, xx], expected, atol=5e-5)
        assert np.all(acc[k][~mask] == 0.0)


@needs_numba
def test_fused_pass_agrees_with_maps_and_remap(monkeypatch):
    """The same jittered warp through the fused pass and through maps + cv2.remap
    (the numpy reference mode): equal up to OpenCV's 1/32 px quantisation of source
    positions, i.e. at most 1/32 of the largest step between neighbouring source
    pixels (coverage steps by 1, the value plane by ~3.5)."""
    rng = np.random.default_rng(7)
    h, w = 128, 160
    src = two_planes(h, w, rng)
    src_pts = lattice(9, 11, 0, w - 1, 0, h - 1)
    dst_pts = src_pts + rng.normal(0, 2.5, src_pts.shape)
    warper = MeshWarper(src_pts)
    everything = np.ones(len(warper.triangles), bool)
    fused = np.zeros((2, h, w), np.float32)
    accumulate_warps([(warper.accumulation(dst_pts, (h, w)), src, everything, 1.0)], fused)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    plan = warper.accumulation(dst_pts, (h, w))
    assert not isinstance(plan, Accumulation)
    ref = np.zeros((2, h, w), np.float32)
    accumulate_warps([(plan, src, everything, 1.0)], ref)
    steps = [max(np.abs(np.diff(s, axis=a)).max() for a in (0, 1)) for s in src]
    for k in range(2):
        assert np.abs(fused[k] - ref[k]).max() <= steps[k] / 32 + 1e-5


@needs_numba
def test_skipped_triangles_only_read_zeros():
    """Visiting only the triangles ``triangles_touching`` the source's support
    gives bit for bit the result of visiting them all; the skipped ones are
    most of a mesh over a small blob."""
    rng = np.random.default_rng(11)
    h, w = 120, 120
    src = np.zeros((2, h, w), np.float32)
    src[:, 50:62, 40:58] = two_planes(12, 18, rng) + np.float32(0.5)  # a small object
    src_pts = lattice(12, 12, 0, w - 1, 0, h - 1)
    dst_pts = src_pts + rng.normal(0, 1.5, src_pts.shape)
    warper = MeshWarper(src_pts)
    active = warper.triangles_touching(src[0])
    assert 0 < active.sum() < 0.2 * len(active)
    plan = warper.accumulation(dst_pts, (h, w))
    some = np.zeros((2, h, w), np.float32)
    all_ = np.zeros((2, h, w), np.float32)
    accumulate_warps([(plan, src, active, 0.5)], some)
    accumulate_warps([(plan, src, np.ones_like(active), 0.5)], all_)
    np.testing.assert_array_equal(some, all_)
    assert some[0].max() > 0.4


def test_triangles_touching_uses_a_two_pixel_margin():
    """A triangle counts when its source bounding box grown by 2 px holds a
    nonzero pixel; one farther away does not."""
    warper = MeshWarper(np.array([[10.0, 10], [20, 10], [10, 20], [40, 40], [50, 40], [40, 50]]),
                        [[0, 1, 2], [3, 4, 5]])
    support = np.zeros((64, 64), bool)
    support[22, 15] = True  # 2 rows below the first triangle's box (y <= 20)
    assert warper.triangles_touching(support).tolist() == [True, False]
    support[:] = False
    support[23, 15] = True  # 3 rows below: out of reach of bilinear taps
    assert warper.triangles_touching(support).tolist() == [False, False]
    with pytest.raises(ValidationError, match=r"support.*non-empty \(h, w\) array.*\(64,\)"):
        warper.triangles_touching(np.zeros(64))


@needs_numba
@pytest.mark.parametrize("threads", [2, 3, 5])
def test_thread_bands_change_no_value(monkeypatch, threads):
    """Several warps accumulated into one buffer, split into bands of rows over
    threads: bit-identical to one thread (bands never share a row)."""
    rng = np.random.default_rng(threads)
    h, w = 140, 170
    jobs = []
    for k in range(4):
        src = two_planes(h, w, rng)
        src_pts = lattice(7, 9, 0, w - 1, 0, h - 1)
        dst_pts = src_pts + rng.normal(0, 2.0, src_pts.shape) + [k * 3.0, -k * 2.0]
        warper = MeshWarper(src_pts)
        jobs.append((warper.accumulation(dst_pts, (h, w)), src,
                    warper.triangles_touching(src[0]), 0.25))
    monkeypatch.setattr(W, "PARALLEL_MIN_PIXELS", 0)
    monkeypatch.setattr(W, "WARP_THREADS", 1)
    one = np.zeros((2, h, w), np.float32)
    box1 = accumulate_warps(jobs, one)
    monkeypatch.setattr(W, "WARP_THREADS", threads)
    many = np.zeros((2, h, w), np.float32)
    box_n = accumulate_warps(jobs, many)
    np.testing.assert_array_equal(many, one)
    assert box_n == box1


def test_accumulate_refuses_bad_buffers():
    warper = MeshWarper(lattice(3, 3, 0, 31, 0, 31))
    pts = warper.src_pts + 0.5
    plan = warper.accumulation(pts, (32, 32))
    src = np.zeros((2, 32, 32), np.float32)
    act = np.ones(len(warper.triangles), bool)
    with pytest.raises(ValidationError, match=r"acc.*C-contiguous float32 \(2, H, W\).*float64"):
        accumulate_warps([(plan, src, act, 1.0)], np.zeros((2, 32, 32)))
    with pytest.raises(ValidationError, match=r"src.*float32 \(2, h, w\).*\(3, 32, 32\)"):
        accumulate_warps([(plan, np.zeros((3, 32, 32), np.float32), act, 1.0)],
                          np.zeros((2, 32, 32), np.float32))
