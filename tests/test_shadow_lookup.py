"""The projective shadow lookup without GL: analytic occluders, and the compiled
kernel against the numpy reference path."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.camera import look_at, orthographic, perspective
from morphkit.errors import ValidationError
from morphkit.shadow import ShadowBias, shadow_visibility
from morphkit.shadow import lookup as lk


def _cameras():
    persp = perspective(np.deg2rad(50), (48, 64), look_at([0.3, -0.2, 3.0], [0, 0, 0]),
                        znear=0.5, zfar=6.0)
    ortho = orthographic(1.2, 0.9, (48, 64), look_at([0.0, 0.0, 3.0], [0.2, 0.1, 0]),
                         znear=0.5, zfar=6.0)
    return [persp, ortho]


@pytest.mark.parametrize("cam", _cameras(), ids=["perspective", "orthographic"])
def test_plane_occluder_shadows_exactly_the_points_behind_it(cam):
    """A depth map holding a constant depth ``Z = d`` everywhere: points of the
    light frustum with ``Z > d + bias`` are shadowed, points with ``Z < d`` lit
    (the bias is at most a few texels, far smaller than the 0.3 margin used)."""
    d = 2.0
    dm = np.full(cam.shape, d, np.float32)
    h, w = cam.shape
    xs, ys = np.meshgrid(np.arange(2, w - 2, 3.0), np.arange(2, h - 2, 3.0))
    pix = np.c_[xs.ravel(), ys.ravel()]
    near = cam.unproject(np.full(cam.shape, d - 0.3, np.float32))[0][pix[:, 1].astype(int),
                                                                     pix[:, 0].astype(int)]
    far = cam.unproject(np.full(cam.shape, d + 0.3, np.float32))[0][pix[:, 1].astype(int),
                                                                   pix[:, 0].astype(int)]
    assert np.all(shadow_visibility(near, dm, cam) == 1.0)
    assert np.all(shadow_visibility(far, dm, cam) == 0.0)
    # empty texels (+inf) occlude nothing
    assert np.all(shadow_visibility(far, np.full(cam.shape, np.inf, np.float32), cam) == 1.0)


@pytest.mark.parametrize("cam", _cameras(), ids=["perspective", "orthographic"])
@pytest.mark.parametrize("with_normals", [False, True])
def test_compiled_kernel_matches_the_numpy_reference(cam, with_normals, rng):
    """Same arithmetic, one pass: the kernel's visibility equals the numpy path's
    on random points (inside and outside the window, behind the light) against a
    random depth map with empty texels."""
    if lk._lookup_kernel is None:
        pytest.skip("numba not installed")
    dm = rng.uniform(1.0, 5.0, cam.shape).astype(np.float32)
    dm[rng.random(cam.shape) < 0.2] = np.inf
    pts = rng.uniform([-3, -3, -2], [3, 3, 4], (20000, 3))
    normals = None
    if with_normals:
        normals = rng.normal(size=(len(pts), 3)).astype(np.float32)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        normals[::7] = 0.0  # rows without slope information
    bias = ShadowBias(0.7, 1.3, 5.0)
    ref = np.ones(len(pts), np.float32)
    lk._lookup_numpy(ref, pts, dm, cam, normals, bias)
    got = shadow_visibility(pts, dm, cam, normals=normals, bias=bias)
    assert (ref == 0).sum() > 200 and (ref == 1).sum() > 200  # the test decides both ways
    np.testing.assert_array_equal(got, ref)


def test_lookup_refuses_a_map_of_another_shape():
    cam = _cameras()[0]
    with pytest.raises(ValidationError, match=r"shape \(48, 64\) of the light camera.*\(10, 10\)"):
        shadow_visibility(np.zeros((1, 3)), np.ones((10, 10), np.float32), cam)


def test_lookup_refuses_nan_points():
    cam = _cameras()[0]
    with pytest.raises(ValidationError, match="points"):
        shadow_visibility(np.array([[0.0, np.nan, 0.0]]), np.ones(cam.shape, np.float32), cam)


def _map_with(value, dtype=np.float32):
    dm = np.full(_cameras()[0].shape, 2.0, dtype)
    dm[10, 20] = value
    return dm


@pytest.mark.parametrize("depth_map, match", [
    (_map_with(np.nan), r"depth_map: expected finite or \+inf depths, got 1 NaN/-inf texels"),
    (_map_with(-np.inf), r"depth_map: expected finite or \+inf depths, got 1 NaN/-inf texels"),
    (np.full((48, 64), 2, np.int32), r"depth_map: expected a float32/float64 depth map, got int32"),
    (np.full((48, 64), True), r"depth_map: expected a float32/float64 depth map, got bool"),
    ([[2.0] * 64] * 48, r"depth_map: expected a numpy array, got list"),
    (np.full((48, 64, 1), 2.0, np.float32), r"depth_map: expected shape \(48, 64\)"),
], ids=["nan", "-inf", "int", "bool", "list", "3-d"])
def test_lookup_refuses_depth_maps_it_cannot_compare(depth_map, match):
    """NaN compares false with every depth (a NaN texel lit everything behind it)
    and an integer map held truncated depths: both used to pass silently."""
    cam = _cameras()[0]
    with pytest.raises(ValidationError, match=match):
        shadow_visibility(np.zeros((1, 3)), depth_map, cam)


def test_lookup_refuses_a_light_camera_that_is_not_one():
    with pytest.raises(ValidationError, match="light_cam: expected a CameraModel, got dict"):
        shadow_visibility(np.zeros((1, 3)), np.ones((48, 64), np.float32), {"shape": (48, 64)})


# ------------------------------------------------- fold relaxation (atlas)
def test_compiled_fold_relaxation_matches_the_numpy_reference(rng):
    """The atlas pulls the vertices of folded destination triangles towards their
    plane-anchor positions; the compiled loop takes the same rounds and gives the
    same points as the numpy reference, and the result never folds."""
    from morphkit import settings, tol
    from morphkit.shadow.baking import fold as F
    from morphkit.warp import grid_triangles

    if not settings.COMPILED:
        pytest.skip("compiled kernels off (numba missing or MORPHKIT_WARP_NUMPY=1)")
    tri = grid_triangles(9, 9)
    ys, xs = np.mgrid[0:9, 0:9] * 10.0
    plane = np.c_[xs.ravel(), ys.ravel()]
    sign = np.sign(F.signed_areas(plane, tri))
    min_area = 4 * tol.TRIANGLE_AREA_PX2
    folded_cases = 0
    for _ in range(30):
        surf = plane + rng.normal(scale=6.0, size=plane.shape)  # parallax: some triangles flip
        ref, got = np.empty_like(surf), np.empty_like(surf)
        k_ref = F.relax_folds_numpy(surf, plane, tri, sign, min_area, 16, ref)
        k_got = F.relax_folds_python(surf, plane, tri, sign, min_area, 16, got)  # pure-Python run
        k_jit = F.relax_folds(surf, plane, tri, sign, min_area, 16, got)
        assert k_ref == k_got == k_jit
        assert F.any_folded(surf, tri, sign, min_area) == F.any_folded_numpy(surf, tri, sign,
                                                                               min_area)
        if F.any_folded_numpy(surf, tri, sign, min_area):
            folded_cases += 1
            assert k_ref > 0
            np.testing.assert_array_equal(got, ref)
            assert not F.any_folded_numpy(ref, tri, sign, min_area)
    assert folded_cases > 20


def test_fold_kernels_go_through_the_one_gate(monkeypatch):
    """``MORPHKIT_WARP_NUMPY`` (settings.NUMPY_ONLY) switches the fold kernels to their
    numpy references at call time, as every compiled kernel (settings.use_compiled)."""
    from morphkit import settings, tol
    from morphkit.shadow.baking import fold as F
    from morphkit.warp import grid_triangles

    calls = []
    monkeypatch.setattr(F, "any_folded_numpy", lambda *a: calls.append("any") or False)
    monkeypatch.setattr(F, "relax_folds_numpy", lambda *a: calls.append("relax") or 0)
    tri = grid_triangles(3, 3)
    pts = np.c_[np.tile(np.arange(3.0), 3), np.repeat(np.arange(3.0), 3)]
    sign, out, a_min = np.ones(len(tri)), np.empty_like(pts), tol.TRIANGLE_AREA_PX2
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    F.any_folded(pts, tri, sign, a_min)
    F.relax_folds(pts, pts, tri, sign, a_min, 4, out)
    assert calls == ["any", "relax"]
    if settings.NUMBA_AVAILABLE:
        monkeypatch.setattr(settings, "NUMPY_ONLY", False)
        assert F.any_folded(pts, tri, sign, a_min) is False
        assert F.relax_folds(pts, pts, tri, sign, a_min, 4, out) == 1  # nothing folds: one round
        assert calls == ["any", "relax"]


@pytest.mark.parametrize("cam", _cameras(), ids=["perspective", "orthographic"])
def test_normals_of_an_unprojected_ground_face_up(cam):
    """The ground ``z = 0`` seen from above: the normals from the unprojected grid
    are ``+z`` (towards the camera), not ``-z`` -- the frame's light-facing mask
    depends on it."""
    from morphkit.shadow import normals_from_points

    o, d = cam.rays()
    t = -o[..., 2] / d[..., 2]  # ray-plane intersection with z = 0
    world = o + t[..., None] * d
    n = normals_from_points(world, np.ones(cam.shape, bool))
    inner = n[1:-1, 1:-1].reshape(-1, 3)
    np.testing.assert_allclose(inner, np.broadcast_to([0, 0, 1], inner.shape), atol=1e-5)
