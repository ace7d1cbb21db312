"""ViewRing (which references serve an azimuth) and QuadCameras (the camera rule and the quad).

Numpy only: no GL. The quad rule is checked by projecting its corners; the fitted
quad by projecting a mesh from every azimuth.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from morphkit.billboard import QuadCameras, ViewRing, wrap_deg
from morphkit.errors import ValidationError
from morphkit.meshes import sample_mesh

# --------------------------------------------------------------------------- ViewRing


def test_k1_is_refused_as_the_classic_billboard():
    with pytest.raises(ValidationError, match=r"views: expected K >= 2 .*classic billboard.*got 1"):
        ViewRing(1)
    for bad in (0, 2.5, True, "8"):
        with pytest.raises(ValidationError, match="views"):
            ViewRing(bad)
    assert ViewRing(8.0).views == 8  # validate.as_int's one rule: an integral float is an integer


def test_ring_layouts_and_their_checks():
    pair = ViewRing(2)
    assert pair.arc_deg == 60.0 and pair.elevation_deg == 10.0
    np.testing.assert_array_equal(pair.azimuths_deg(), [-30.0, 30.0])
    assert pair.pairs() == [(0, 1)] and pair.spacing_deg == 60.0
    ring = ViewRing(8)
    assert ring.arc_deg == 360.0
    np.testing.assert_array_equal(ring.azimuths_deg(), [0, 45, 90, 135, -180, -135, -90, -45])
    assert ring.pairs()[-1] == (7, 0) and ring.spacing_deg == 45.0
    with pytest.raises(ValidationError, match=r"arc_deg: expected 360 for K = 8"):
        ViewRing(8, 90.0)
    for arc in (0.0, 180.0, -10.0):
        with pytest.raises(ValidationError, match=r"arc_deg: expected an angle in \(0, 180\)"):
            ViewRing(2, arc)
    with pytest.raises(ValidationError, match=r"elevation_deg: expected an angle in \[0, 60\]"):
        ViewRing(2, elevation_deg=75.0)
    with pytest.raises(ValidationError, match="view pair: expected neighbouring references"):
        ring.check_pair(0, 2)
    with pytest.raises(ValidationError, match=r"view index j: expected an integer in \[0, 7\]"):
        ring.check_pair(0, 8)
    assert ring.check_pair(0, 7) == (0, 7)  # neighbours in either order
    with pytest.raises(ValidationError, match="azimuth: expected a finite angle"):
        ring.pair(float("nan"))


def test_pair_is_exact_at_the_references_and_half_way():
    ring = ViewRing(8)
    for k, a in enumerate(ring.azimuths_deg()):
        for turn in (0.0, 360.0, -720.0):
            assert ring.pair(a + turn) == (k, (k + 1) % 8, 0.0, 0.0)
    for k in range(8):
        i, j, s, out = ring.pair(45.0 * k + 22.5)
        assert (i, j, s, out) == (k, (k + 1) % 8, 0.5, 0.0)
    pair = ViewRing(2)
    assert pair.pair(-30.0) == (0, 1, 0.0, 0.0)
    assert pair.pair(30.0) == (0, 1, 1.0, 0.0)
    assert pair.pair(0.0) == (0, 1, 0.5, 0.0)


def test_k2_outside_the_arc_is_clamped_and_reported():
    pair = ViewRing(2)
    assert pair.pair(50.0) == (0, 1, 1.0, pytest.approx(20.0))
    assert pair.pair(-45.0) == (0, 1, 0.0, pytest.approx(15.0))
    # behind the asset: clamped to the nearer end, measured the short way round
    assert pair.pair(170.0) == (0, 1, 1.0, pytest.approx(140.0))
    assert pair.pair(-100.0) == (0, 1, 0.0, pytest.approx(70.0))


def test_s_is_the_chord_fraction_and_inverts():
    """A morph at s shows the view from (1 - s) C_i + s C_j: the direction of that point is the azimuth."""
    for ring in (ViewRing(2), ViewRing(6), ViewRing(12)):
        az = ring.azimuths_deg()
        prev = -1.0
        for a in np.linspace(az[0], az[0] + ring.spacing_deg, 41)[1:-1]:
            i, j, s, out = ring.pair(a)
            assert (i, j) == ring.pairs()[0] and out == 0.0
            assert s > prev  # monotonic
            prev = s
            u0 = np.array([math.cos(math.radians(az[i])), math.sin(math.radians(az[i]))])
            u1 = np.array([math.cos(math.radians(az[j])), math.sin(math.radians(az[j]))])
            c = (1 - s) * u0 + s * u1
            assert wrap_deg(math.degrees(math.atan2(c[1], c[0])) - a) == pytest.approx(0.0, abs=1e-9)
            assert wrap_deg(ring.pair_azimuth_deg(i, j, s) - a) == pytest.approx(0.0, abs=1e-9)
            # the reversed pair runs the other way
            assert wrap_deg(ring.pair_azimuth_deg(j, i, 1.0 - s) - a) == pytest.approx(0.0, abs=1e-9)
    with pytest.raises(ValidationError, match=r"s: expected a number in \[0, 1\]"):
        ViewRing(8).pair_azimuth_deg(0, 1, 1.5)


# --------------------------------------------------------------------------- QuadCameras

QUAD = QuadCameras(np.array([0.1, -0.2, 0.35]), 2.5, 15.0, (0.6, 0.45), (60, 80))


def _corner_pixels(h: int, w: int) -> np.ndarray:
    return np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5], [-0.5, h - 0.5]])


@pytest.mark.parametrize("level", [0, 1, 2])
def test_quad_corners_land_on_the_image_corners(level):
    h, w = QUAD.level_shape(level)
    assert (h, w) == (round(60 / 2**level), round(80 / 2**level))
    for az in (0.0, 37.0, -120.0):
        corners = QUAD.quad_corners(az)
        cams = [QUAD.camera(az, level), QUAD.chord_camera(az - 20.0, az + 20.0, 0.5, level)]
        for cam in cams:
            px, _ = cam.project(corners)
            np.testing.assert_allclose(px, _corner_pixels(h, w), atol=1e-9)
            centre, _ = cam.project(QUAD.pivot[None])
            np.testing.assert_allclose(centre[0], [(w - 1) / 2, (h - 1) / 2], atol=1e-9)
            # the image plane is vertical: the optical axis is horizontal
            assert abs(cam.axis[2]) < 1e-12


def test_reference_cameras_sit_on_the_ring_and_chord_cameras_between():
    for az in (0.0, 90.0, 200.0):
        eye = QUAD.camera(az).position
        d = eye - QUAD.pivot
        assert np.linalg.norm(d) == pytest.approx(2.5)
        assert math.degrees(math.asin(d[2] / 2.5)) == pytest.approx(15.0)
        assert math.degrees(math.atan2(d[1], d[0])) == pytest.approx(wrap_deg(az))
    e0, e1 = QUAD.eye(10.0), QUAD.eye(70.0)
    np.testing.assert_allclose(QUAD.chord_camera(10.0, 70.0, 0.25).position, 0.75 * e0 + 0.25 * e1,
                               atol=1e-12)
    np.testing.assert_array_equal(QUAD.chord_camera(10.0, 70.0, 0.0).position, QUAD.camera(10.0).position)
    with pytest.raises(ValidationError, match="eye: expected a point off the pivot's vertical line"):
        QUAD.camera_at(QUAD.pivot + np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValidationError, match=r"level: expected an integer >= 0"):
        QUAD.camera(0.0, -1)


def test_fitted_quad_holds_the_mesh_from_every_azimuth():
    mesh = sample_mesh("person")
    q = QuadCameras.fit(mesh, (64, 48), 10.0)
    hw, hh = q.half_extent
    assert hw / hh == pytest.approx(48 / 64)  # square pixels
    cam0 = q.camera(0.0)
    assert cam0.fx == pytest.approx(cam0.fy)
    np.testing.assert_allclose(q.pivot, [0.0, 0.0, 0.5], atol=1e-9)  # normalised: height 1
    inside_margin = []
    for az in np.arange(0.0, 360.0, 7.5):
        px, _ = q.camera(az).project(np.asarray(mesh.vertices))
        assert px.min() >= -0.5 and px[:, 0].max() <= 47.5 and px[:, 1].max() <= 63.5
        inside_margin.append(min(px[:, 1].min() + 0.5, 63.5 - px[:, 1].max()))
    # tall object: the height sets the quad; the margin (tol FRAME_MARGIN, 4%) stays about 1 px
    assert 0.5 < min(inside_margin) < 3.0
