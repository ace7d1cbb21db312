"""Coverage of a view from surface samples (:mod:`morphkit.billboard.coverage`), no GL: a plane
square of known extent seen by a known camera, so the expected coverage is derived."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit import tol
from morphkit.billboard import object_points, splat_coverage
from morphkit.camera import CameraModel, look_at
from morphkit.errors import ValidationError


def _camera(shape: tuple[int, int] = (40, 40)) -> CameraModel:
    """Looks down -z from (0, 0, 5) at the origin, focal 40 px: 1 world unit at z = 0 is 8 px."""
    h, w = shape
    c2w = look_at(np.array([0.0, 0.0, 5.0]), np.zeros(3), np.array([0.0, 1.0, 0.0]))
    return CameraModel("perspective", shape, 40.0, 40.0, (w - 1) / 2, (h - 1) / 2, 0.1, 10.0, c2w)


def _square_samples(half: float, step: float) -> np.ndarray:
    g = np.arange(-half + step / 2, half, step)
    x, y = np.meshgrid(g, g)
    return np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]


def test_dense_samples_of_a_square_cover_its_pixels():
    cam = _camera()
    # a 2 x 2 square at z = 0 covers 16 x 16 pixels about the centre (19.5, 19.5): pixels 12..27
    cov = splat_coverage(_square_samples(1.0, 0.05), cam)
    expected = np.zeros((40, 40), bool)
    expected[12:28, 12:28] = True
    assert cov.dtype == np.float32 and cov.shape == (40, 40)
    np.testing.assert_array_equal(cov > 0.5, expected)
    assert cov[13:27, 13:27].min() == 1.0 and cov[~np.pad(np.ones((18, 18), bool), 11)].max() == 0.0


def test_sparse_samples_are_closed_into_a_solid_square():
    cam = _camera()
    # samples 1.25 px apart leave gaps on the 2x grid; the closing fills them, the edges stay put
    sparse = splat_coverage(_square_samples(1.0, 1.25 / 8), cam)
    assert sparse[13:27, 13:27].min() == 1.0
    open_ = splat_coverage(_square_samples(1.0, 1.25 / 8), cam, close_px=1)
    assert open_[13:27, 13:27].min() < 1.0  # without the closing: holes
    # the samples span 16 - 1.25 = 14.75 px (half a spacing in from each edge), and no sample lies
    # outside the square's 16 px: between 14 and 16 pixels a side are more than half covered
    assert 14 ** 2 <= (sparse > 0.5).sum() <= 16 ** 2


def test_object_points_are_the_object_pixels_unprojected():
    cam = _camera((8, 8))
    depth = np.full((8, 8), np.inf)
    depth[2:5, 3:6] = 5.0
    pts = object_points(cam, depth)
    assert pts.shape == (9, 3) and pts.dtype == np.float32
    np.testing.assert_allclose(pts[:, 2], 0.0, atol=1e-5)  # the plane z = 0, 5 units in front
    px, _ = cam.project(pts.astype(np.float64))
    np.testing.assert_allclose(np.sort(px[:, 0]), np.repeat([3.0, 4.0, 5.0], 3), atol=1e-4)


def test_no_samples_cover_nothing():
    assert splat_coverage(np.zeros((0, 3)), _camera()).max() == 0.0


@pytest.mark.parametrize("kw, match", [({"supersample": 0}, "supersample"), ({"close_px": 0}, "close_px")])
def test_bad_parameters_are_refused(kw, match):
    with pytest.raises(ValidationError, match=match):
        splat_coverage(np.zeros((1, 3)), _camera(), **kw)


def test_bad_points_and_depth_are_refused():
    with pytest.raises(ValidationError, match="points"):
        splat_coverage(np.zeros((4, 2)), _camera())
    with pytest.raises(ValidationError, match=r"depth.*shape \(40, 40\)"):
        object_points(_camera(), np.zeros((3, 3)))


def test_defaults_are_the_tolerances():
    pts = _square_samples(1.0, 0.2)
    np.testing.assert_array_equal(
        splat_coverage(pts, _camera()),
        splat_coverage(pts, _camera(), supersample=tol.BB_COVERAGE_SUPERSAMPLE,
                       close_px=tol.BB_COVERAGE_CLOSE_PX))
