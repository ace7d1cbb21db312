"""A sun disc's soft shadow from one orthographic map (issue #26's soft sun, #27's filtering):
derived cases on a map made by hand (no GL)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from morphkit import tol
from morphkit.camera import look_at, orthographic, perspective
from morphkit.conventions import SUN_DISC_RADIUS_DEG
from morphkit.errors import ValidationError
from morphkit.shadow.lookup import ShadowBias, shadow_visibility
from morphkit.sunlit import sundisc
from morphkit.sunlit.sundisc import DISC_SQUARE, disc_visibility

N = 64  # texels a side over [-2, 2]: 16 texels a unit


def _cam():
    pose = look_at(np.array([0.0, 0.0, 10.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
    return orthographic(2.0, 2.0, (N, N), pose, znear=0.5, zfar=20.0)


def _half_plane(depth: float) -> np.ndarray:
    """Occluder texels at ``depth`` over x < 0 (image columns left of the centre)."""
    dm = np.full((N, N), np.inf, np.float32)
    dm[:, : N // 2] = depth
    return dm


def _ground(xs: np.ndarray, y: float = 0.3) -> np.ndarray:
    return np.stack([xs, np.full_like(xs, y), np.zeros_like(xs)], axis=1)


def test_a_disc_of_zero_radius_is_the_hard_lookup():
    cam, rng = _cam(), np.random.default_rng(5)
    dm = np.where(rng.random((N, N)) < 0.3, rng.uniform(2.0, 9.0, (N, N)), np.inf).astype(np.float32)
    pts = np.c_[rng.uniform(-2.2, 2.2, (500, 2)), rng.uniform(0.0, 5.0, 500)]
    hard = shadow_visibility(pts, dm, cam, bias=ShadowBias(constant=tol.SUN_GROUND_BIAS_TEXELS, slope=0.0))
    got = disc_visibility(pts, dm, cam, 0.0)
    assert 50 < (hard == 0).sum() < 450
    np.testing.assert_array_equal(got, hard)


def _spread_ramp(xs: np.ndarray, h: float, r: float, n: int = 20000) -> np.ndarray:
    """The lit fraction of the disc's square (half-width ``h``) beside a straight edge at x = 0
    (occluder over x < 0), averaged over shifts uniform in ``[-r, r]``: midpoints of ``n``
    strips (the integrand is piecewise linear: exact but for its two kinks, ~1e-9 here)."""
    s = (np.arange(n) + 0.5) / n * 2.0 * r - r
    return np.clip((xs[:, None] + s[None, :] + h) / (2.0 * h), 0.0, 1.0).mean(axis=1)


@pytest.mark.parametrize("a", [SUN_DISC_RADIUS_DEG, 2.0])
def test_a_straight_edge_gives_the_disc_square_spread_over_the_raster(a):
    cam = _cam()
    dm = _half_plane(7.0)  # the occluder 3 units above the ground (depth 10)
    k = cam.fx * math.tan(math.radians(a))
    h = DISC_SQUARE * k * 3.0 / cam.fx  # the square's half-width, world units (0.0929 at 2 degrees)
    r = tol.SUN_DISC_RASTER_HALF_TEXEL / cam.fx
    xs = np.linspace(-1.5 * (h + r), 1.5 * (h + r), 61)
    vis = disc_visibility(_ground(xs), dm, cam, a)
    # the edge lies at the texel boundary x = 0 (column 31.5): the trapezoid's covered fraction
    np.testing.assert_allclose(vis, _spread_ramp(xs, h, r), atol=1e-5)
    assert vis[0] == 0.0 and vis[-1] == 1.0 and np.all(np.diff(vis) >= 0)
    assert 0 < vis[len(xs) // 2 - 2] < 0.5 < vis[len(xs) // 2 + 2] < 1  # soft at the real sun too


def test_at_the_real_sun_an_edge_between_texel_centres_is_nearer_the_disc_than_the_hard_lookup():
    """The true edge anywhere within a texel (16 offsets), the map drawn by texel centres: against
    the disc's exact visible fraction (a circular segment), the filtered lookup's mean absolute
    and rms errors are below the hard lookup's (the edge on the texel grid)."""
    cam, a, height = _cam(), SUN_DISC_RADIUS_DEG, 3.0
    radius = height * math.tan(math.radians(a))  # the disc's shadow radius: 0.47 texel
    xs = np.linspace(-0.2, 0.2, 801)
    centres = (np.arange(N) - cam.texture_matrix()[0, 3]) / cam.texture_matrix()[0, 0]
    err = {"disc": [], "hard": []}
    for t in (np.arange(16) + 0.5) / 16 - 0.5:
        edge = t / cam.fx  # t texels right of the texel boundary x = 0
        dm = np.full((N, N), np.inf, np.float32)
        dm[:, centres < edge] = 10.0 - height
        s = np.clip((xs - edge) / radius, -1.0, 1.0)
        truth = 1.0 - (np.arccos(s) - s * np.sqrt(1.0 - s * s)) / math.pi
        for name, deg in (("disc", a), ("hard", 0.0)):
            err[name].append(disc_visibility(_ground(xs), dm, cam, deg) - truth)
    mae = {k: float(np.abs(v).mean()) for k, v in err.items()}
    rms = {k: float(np.sqrt(np.square(v).mean())) for k, v in err.items()}
    assert mae["disc"] < mae["hard"] and rms["disc"] < 0.9 * rms["hard"]


def test_the_penumbra_widens_with_the_distance_to_the_occluder():
    cam, a = _cam(), 3.0
    xs = np.linspace(-0.5, 0.5, 201)
    widths = []
    for depth in (8.0, 6.0):  # occluder 2, then 4 units above the ground
        vis = disc_visibility(_ground(xs), _half_plane(depth), cam, a)
        pen = (vis > 0.0) & (vis < 1.0)
        widths.append(xs[pen].max() - xs[pen].min())
    raster = 2.0 * tol.SUN_DISC_RASTER_HALF_TEXEL / cam.fx  # the box's own width: not the disc's
    assert widths[1] - raster == pytest.approx(2.0 * (widths[0] - raster), rel=0.1)


def test_far_from_occluders_lit_and_under_a_wide_plate_umbra():
    cam = _cam()
    dm = np.full((N, N), np.inf, np.float32)
    dm[16:48, 16:48] = 8.0  # a plate [-1, 1]^2, 2 units above the ground
    vis = disc_visibility(np.array([[0.0, 0.0, 0.0], [1.9, 1.9, 0.0], [-1.95, 0.0, 0.0]]), dm, cam, 2.0)
    assert list(vis) == [0.0, 1.0, 1.0]


def test_the_compiled_loop_equals_its_python_reference(monkeypatch):
    cam, rng = _cam(), np.random.default_rng(9)
    dm = np.where(rng.random((N, N)) < 0.4, rng.uniform(5.0, 9.5, (N, N)), np.inf).astype(np.float32)
    pts = np.c_[rng.uniform(-2.0, 2.0, (400, 2)), rng.uniform(0.0, 3.0, 400)]
    got = disc_visibility(pts, dm, cam, 4.0)
    monkeypatch.setattr(sundisc, "use_compiled", lambda _k: False)
    np.testing.assert_allclose(disc_visibility(pts, dm, cam, 4.0), got, atol=1e-6)
    assert 0 < ((got > 0) & (got < 1)).sum()


def test_bad_arguments_raise():
    cam = _cam()
    dm = _half_plane(7.0)
    persp = perspective(math.radians(60.0), (N, N), cam.cam2world)
    with pytest.raises(ValidationError, match="orthographic CameraModel"):
        disc_visibility(np.zeros((1, 3)), dm, persp, 1.0)
    with pytest.raises(ValidationError, match=r"degrees in \[0, 90\)"):
        disc_visibility(np.zeros((1, 3)), dm, cam, 95.0)
    with pytest.raises(ValidationError, match="points"):
        disc_visibility(np.zeros((1, 2)), dm, cam, 1.0)
    bad = dm.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValidationError, match="NaN/-inf"):
        disc_visibility(np.zeros((1, 3)), bad, cam, 1.0)


def test_a_prepared_map_answers_as_a_one_off_lookup():
    from morphkit.sunlit.sundisc import DiscMap

    cam, rng = _cam(), np.random.default_rng(11)
    dm = np.where(rng.random((N, N)) < 0.4, rng.uniform(5.0, 9.5, (N, N)), np.inf).astype(np.float32)
    prepared = DiscMap(dm, cam)
    for radius in (0.0, 1.5, 4.0):
        pts = np.c_[rng.uniform(-2.0, 2.0, (300, 2)), rng.uniform(0.0, 3.0, 300)]
        np.testing.assert_array_equal(prepared.visibility(pts, radius), disc_visibility(pts, dm, cam, radius))
    empty = DiscMap(np.full((N, N), np.inf, np.float32), cam)
    assert (empty.visibility(np.zeros((4, 3)), 2.0) == 1.0).all()
