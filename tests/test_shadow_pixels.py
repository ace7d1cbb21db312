"""The frame's drawn pixels (points, normals, light facing) and the shade blend: the compiled
kernels against their numpy references, and a derivable case (no GL)."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit import settings, tol
from morphkit.camera import look_at, orthographic, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.composite import shade
from morphkit.scene import AreaLight, DirectionalLight, PointLight
from morphkit.shadow import pixels as px
from morphkit.warp import PARALLEL_MIN_PIXELS

needs_kernels = pytest.mark.skipif(not settings.COMPILED,
                                   reason="compiled kernels off (numba missing or MORPHKIT_WARP_NUMPY=1)")


def _cameras():
    persp = perspective(np.deg2rad(50), (40, 56), look_at([0.4, -0.3, 3.0], [0, 0, 0]),
                        znear=0.5, zfar=8.0)
    ortho = orthographic(1.4, 1.0, (40, 56), look_at([0.2, 0.1, 3.0], [0.1, 0.0, 0]),
                         znear=0.5, zfar=8.0)
    return [persp, ortho]


def _lights():
    return [PointLight([0.5, 0.2, 2.0]), DirectionalLight([0.3, -0.4, -1.0]),
            AreaLight([-0.4, 0.3, 2.5], [0.2, 0.0, 0.0], [0.0, 0.2, 0.0])]


def _plane_depth(cam, normal):
    """Depth image of the plane ``normal . x = 0`` (each pixel's ray meets it)."""
    o, d = cam.rays()
    t = -(o @ normal) / (d @ normal)
    world = o + t[..., None] * d
    return cam.project(world.reshape(-1, 3))[1].reshape(cam.shape)


def _both(cam, depth, light, monkeypatch):
    """drawn_pixels by the kernel, then by the numpy reference (the one gate switched)."""
    got = px.drawn_pixels(cam, depth, light)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref = px.drawn_pixels(cam, depth, light)
    monkeypatch.setattr(settings, "NUMPY_ONLY", False)
    return got, ref


def _assert_same(got, ref):
    np.testing.assert_array_equal(got.index, ref.index)
    np.testing.assert_allclose(got.points, ref.points, rtol=0, atol=tol.DRAWN_POINTS_ABS)
    np.testing.assert_allclose(got.normals, ref.normals, rtol=0, atol=tol.DRAWN_NORMALS_ABS)
    np.testing.assert_array_equal(got.facing, ref.facing)
    assert got.points.dtype == np.float64 and got.normals.dtype == np.float32


@needs_kernels
@pytest.mark.parametrize("cam", _cameras(), ids=["perspective", "orthographic"])
@pytest.mark.parametrize("light", _lights(), ids=["point", "directional", "area"])
def test_a_tilted_plane_gets_its_normal_and_facing(cam, light, monkeypatch):
    """The plane ``n . x = 0`` seen whole: every inner pixel's normal is ``n`` (it faces the
    camera), border pixels' are zero, every pixel is drawn at its ray's point, and a pixel faces
    the light where ``n`` points to it; kernel and numpy reference agree."""
    n = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    depth = _plane_depth(cam, n).astype(np.float32)
    got, ref = _both(cam, depth, light, monkeypatch)
    _assert_same(got, ref)
    h, w = cam.shape
    assert len(got.index) == h * w
    inner = np.zeros(cam.shape, bool)
    inner[1:-1, 1:-1] = True
    nrm = got.normals.reshape(h, w, 3)
    np.testing.assert_allclose(nrm[inner], np.broadcast_to(n, (inner.sum(), 3)), atol=1e-4)
    assert not nrm[~inner].any()
    np.testing.assert_allclose(got.points @ n, 0.0, atol=1e-5)  # on the plane (float32 depth)
    if isinstance(light, DirectionalLight):
        want = np.full(cam.shape, n @ -light.direction > 0)
    else:
        where = light.center if isinstance(light, AreaLight) else light.position
        want = ((where - got.points) @ n > 0).reshape(cam.shape)
    np.testing.assert_array_equal(got.facing[inner], want[inner])
    assert not got.facing[~inner].any()


@needs_kernels
@pytest.mark.parametrize("cam", _cameras(), ids=["perspective", "orthographic"])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_kernel_equals_the_numpy_reference_on_a_depth_image_with_holes(cam, dtype, rng,
                                                                          monkeypatch):
    """Random depths with background holes (+inf, NaN, 0, negative) of all sizes: the same
    pixels, points within float64 rounding, normals within float32 rounding, the same facing."""
    depth = rng.uniform(2.0, 4.0, cam.shape)
    depth[rng.random(cam.shape) < 0.15] = np.inf
    depth[5:12, 8:30] = np.inf
    depth[0, :] = np.nan
    depth[20, 3:9] = 0.0
    depth[30, 40:50] = -1.0
    for light in _lights():
        got, ref = _both(cam, depth.astype(dtype), light, monkeypatch)
        _assert_same(got, ref)
        assert 0 < len(got.index) < depth.size
        assert 0 < got.facing.sum() < len(got.index)  # both sides of the light among them


@needs_kernels
def test_bands_of_rows_give_the_one_band_result(rng, monkeypatch):
    """A frame large enough for bands (three, whatever the CPUs): every band's pixels land after
    those above it, so the result is the one band's, byte for byte, and the reference's."""
    cam = perspective(np.deg2rad(50), (270, 250), look_at([0.4, -0.3, 3.0], [0, 0, 0]),
                      znear=0.5, zfar=8.0)
    assert cam.shape[0] * cam.shape[1] >= PARALLEL_MIN_PIXELS
    depth = rng.uniform(2.0, 4.0, cam.shape).astype(np.float32)
    depth[rng.random(cam.shape) < 0.2] = np.inf
    depth[85:95] = np.inf  # a band boundary (rows 90, 180) among holes
    light = PointLight([0.5, 0.2, 2.0])
    monkeypatch.setattr(px, "WARP_THREADS", 1)
    one = px.drawn_pixels(cam, depth, light)
    monkeypatch.setattr(px, "WARP_THREADS", 3)
    got, ref = _both(cam, depth, light, monkeypatch)
    for a, b in zip(got, one, strict=True):
        np.testing.assert_array_equal(a, b)
    _assert_same(got, ref)


def test_drawn_pixels_refuses_a_depth_of_another_shape():
    cam = _cameras()[0]
    with pytest.raises(ValidationError, match="depth"):
        px.drawn_pixels(cam, np.ones((3, 3)), PointLight([0.0, 0.0, 2.0]))


@needs_kernels
@pytest.mark.parametrize("shape", [(24, 32), (260, 256)], ids=["small", "bands"])
def test_the_shade_kernel_equals_the_numpy_blend(shape, rng, monkeypatch):
    """uint8 frames blended by visibility 0, 1 and in between: the kernel's bytes are numpy's
    (in one band, and in three bands of rows where the frame is large enough)."""
    from morphkit.imaging import composite

    monkeypatch.setattr(composite, "WARP_THREADS", 3)
    assert (shape[0] * shape[1] >= PARALLEL_MIN_PIXELS) == (shape[0] > 100)
    lit = rng.integers(0, 256, (*shape, 3), dtype=np.uint8)
    unlit = rng.integers(0, 256, (*shape, 3), dtype=np.uint8)
    vis = rng.random(shape).astype(np.float32)
    vis[rng.random(vis.shape) < 0.3] = 0.0
    vis[rng.random(vis.shape) < 0.3] = 1.0
    vis[0, :4] = [0.5, 0.25, 0.75, np.float32(1 / 3)]  # rounding ties and near-ties
    got = shade(lit, unlit, vis)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref = shade(lit, unlit, vis)
    np.testing.assert_array_equal(got, ref)
    np.testing.assert_array_equal(got[vis == 1], lit[vis == 1])
    np.testing.assert_array_equal(got[vis == 0], unlit[vis == 0])
