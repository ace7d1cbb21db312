"""Soft shadows of area lights by warping: sampling, range, refusals (no GL), and
the accumulated visibility against the ray-cast ground truth (GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.errors import OutOfRangeError, ValidationError
from morphkit.imaging.groundtruth import hard_visibility, receiver_grid
from morphkit.scene import AreaLight, DirectionalLight, PointLight, SceneObject
from morphkit.shadow import (
    DirectShadow,
    MotionRange,
    RangeClampWarning,
    SoftShadow,
    bake_atlas,
    bake_soft_atlas,
    light_offsets,
    soft_motion_range,
)
from morphkit.shadow.soft import FIVE_SAMPLES

MOTION = MotionRange([-0.4, -0.3], [0.4, 0.3])
AREA = AreaLight([0.2, -0.1, 2.4], [0.3, 0.0, 0.0], [0.0, 0.2, 0.0])


# ------------------------------------------------------------------ no GL
def test_offsets_are_the_light_samples_minus_the_centre():
    off = light_offsets(AREA, (3, 2))
    assert off.shape == (6, 2)
    np.testing.assert_allclose(off, (AREA.samples(3, 2) - AREA.center)[:, :2])
    np.testing.assert_allclose(off.mean(0), 0, atol=1e-15)  # cell centres are symmetric
    five = light_offsets(AREA, FIVE_SAMPLES)
    np.testing.assert_allclose(five, [[0, 0], [-0.3, -0.2], [0.3, -0.2], [-0.3, 0.2], [0.3, 0.2]])


def test_jittered_offsets_follow_the_rng():
    a = light_offsets(AREA, 4, np.random.default_rng(3))
    b = light_offsets(AREA, 4, np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)
    assert np.all(np.abs(a) <= [0.3, 0.2])
    assert not np.allclose(a, light_offsets(AREA, 4))


def test_soft_range_grows_by_the_light_extent():
    tilted_u = AreaLight([0, 0, 3], [0.3, 0.0, 0.0], [0.0, 0.1, 0.1])
    r = soft_motion_range(MOTION, AreaLight([0, 0, 3], [0.3, 0.1, 0.0], [0.0, 0.2, 0.0]))
    np.testing.assert_allclose(r.lo, [-0.7, -0.6])
    np.testing.assert_allclose(r.hi, [0.7, 0.6])
    with pytest.raises(ValidationError, match=r"parallel to the motion plane.*v=\[0.0, 0.1, 0.1\]"):
        soft_motion_range(MOTION, tilted_u)


@pytest.mark.parametrize("samples, match", [
    ((0, 3), "n_u, n_v >= 1"),
    (np.array([[0.0, 0.0], [1.5, 0.0]]), r"each in \[-1, 1\]\^2.*1.5"),
    (np.zeros((0, 2)), "at least one"),
    (2.5, "an int k"),
    ((10**4, 10**4), r"at most 4096 \(morphkit.tol.MAX_LIGHT_SAMPLES\), got 10000 x 10000"),
    (np.zeros((5000, 2)), r"at most 4096 \(morphkit.tol.MAX_LIGHT_SAMPLES\), got 5000"),
])
def test_bad_sample_specs_are_refused(samples, match):
    with pytest.raises(ValidationError, match=match):
        light_offsets(AREA, samples)


def test_light_must_be_an_area_light():
    with pytest.raises(ValidationError, match="an AreaLight.*PointLight"):
        light_offsets(PointLight([0, 0, 2]))


# --------------------------------------------------------------------- GL
@pytest.fixture(scope="module")
def plate():
    """A thin square plate 0.5 above the ground: from a light parallel to it, its
    hard shadows are squares (its sides barely show), so the warp is near exact."""
    m = trimesh.creation.box((0.4, 0.4, 0.02))
    m.apply_translation([0.0, 0.0, 0.5])
    return m


@pytest.fixture(scope="module")
def plate_atlas(renderer, plate):
    return bake_soft_atlas(plate, np.eye(4), MOTION, AREA, (128, 128), renderer=renderer,
                           progress=False)


def _band(mask: np.ndarray, radius: int) -> np.ndarray:
    """Pixels within ``radius`` of the mask's outline (dilation minus erosion)."""
    import cv2

    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    m = mask.astype(np.uint8)
    return (cv2.dilate(m, k) - cv2.erode(m, k)).astype(bool)


@pytest.mark.gl
@pytest.mark.parametrize("warps", ["composed", "reproject"])
@pytest.mark.parametrize("samples, rng_seed", [((3, 3), 5), (np.array([[1.0, -1.0]]), None)],
                         ids=["jittered-3x3", "one-corner"])
def test_soft_shadow_equals_raycast_away_from_every_samples_outline(plate, plate_atlas, samples,
                                                                     rng_seed, warps):
    """Pointwise bound, derived: each sample's hard shadow may be wrong only within
    a few texels of its outline (nearest-texel lookup, bias, warp), so
    ``|soft - truth| <= (1/N) * #(samples whose outline band holds the point)``;
    everywhere else the accumulated visibility is exact. The band is 3 light
    texels wide at the ground (texel size ``Z / fx``, Z ~ 2.4 here). The samples
    are asymmetric (jittered; one corner), so a wrong sign of the light offsets
    would fail (the shadow would move by ~10 grid pixels for the corner)."""
    n_grid, half = 120, 0.9
    g = receiver_grid(half, (n_grid, n_grid)).reshape(-1, 3)
    rng = None if rng_seed is None else np.random.default_rng(rng_seed)
    soft = SoftShadow(plate_atlas.method(warps=warps), AREA, samples, rng=rng)
    xy = np.array([0.17, -0.11])
    pose = np.eye(4)
    pose[:2, 3] = xy
    obj = SceneObject(plate, pose)
    est = soft.visibility(xy, g).reshape(n_grid, n_grid)
    texel_px = 2.4 / plate_atlas.rig.fx / (2 * half / n_grid)
    radius = int(np.ceil(3 * texel_px))
    truth = np.zeros((n_grid, n_grid))
    allowed = np.zeros((n_grid, n_grid))
    for pl in soft.point_lights():
        lit = hard_visibility(g, pl, obj).reshape(n_grid, n_grid)
        truth += lit / soft.n_samples
        allowed += _band(lit < 0.5, radius) / soft.n_samples
    err = np.abs(est - truth)
    assert np.all(err <= allowed + 1e-6)
    assert (allowed == 0).mean() > 0.8  # the bound is exactness on most of the grid
    assert np.any(est == 0)  # an umbra: seen by no sample
    if soft.n_samples > 1:  # a real penumbra: intermediate values
        assert np.any((est > 0.3) & (est < 0.7))


@pytest.mark.gl
def test_values_are_multiples_of_one_over_n(plate_atlas):
    soft = SoftShadow(plate_atlas, AREA, FIVE_SAMPLES)
    v = soft.visibility(np.array([0.0, 0.1]), receiver_grid(0.9, (64, 64)).reshape(-1, 3))
    k = v * 5
    np.testing.assert_allclose(k, np.rint(k), atol=1e-5)
    assert set(np.rint(k).astype(int)) >= {0, 5} and len(set(np.rint(k).astype(int))) >= 4


@pytest.mark.gl
def test_one_centre_sample_is_the_ray_cast_hard_shadow_of_the_centre(plate, plate_atlas):
    """``samples = [[0, 0]]`` is the point light at the centre: the ray-cast hard
    shadow of that light (independent of the atlas: embree against the mesh),
    exactly, except within the outline band of each sample's shadow where a shadow
    map may differ (nearest texel, bias, warp: 3 light texels at the ground, as
    derived in the pointwise test above)."""
    from morphkit.imaging.groundtruth import sampled_visibility

    n_grid, half = 96, 0.9
    g = receiver_grid(half, (n_grid, n_grid)).reshape(-1, 3)
    xy = np.array([-0.2, 0.05])
    pose = np.eye(4)
    pose[:2, 3] = xy
    soft = SoftShadow(plate_atlas, AREA, np.zeros((1, 2)))
    lights = soft.point_lights()
    np.testing.assert_array_equal(lights[0].position, AREA.center)
    truth = sampled_visibility(g, lights, SceneObject(plate, pose)).reshape(n_grid, n_grid)
    est = soft.visibility(xy, g).reshape(n_grid, n_grid)
    texel_px = 2.4 / plate_atlas.rig.fx / (2 * half / n_grid)
    band = _band(truth < 0.5, int(np.ceil(3 * texel_px)))
    assert (truth == 0).sum() > 200  # the plate's shadow is on the grid
    assert np.all(est[~band] == truth[~band])  # exact off the outline
    assert band.mean() < 0.1  # measured 0.023: the bound is exactness on most of the grid
    # and on the band mostly right (measured 0.98; the corner sample's map used
    # instead: 0.51 there, and 230 wrong points off the band)
    assert np.mean(est[band] == truth[band]) > 0.8


@pytest.mark.gl
def test_warp_agrees_with_direct_rendering_per_sample(renderer, plate, plate_atlas):
    """The same light samples, re-rendered instead of warped: the two soft
    shadows differ only on outline bands (mean abs difference < 0.01 over a grid
    where the penumbra covers ~15% of the points)."""
    g = receiver_grid(0.9, (96, 96)).reshape(-1, 3)
    xy = np.array([0.3, 0.2])
    warp = SoftShadow(plate_atlas, AREA, (3, 3)).visibility(xy, g)
    direct = SoftShadow(DirectShadow(plate_atlas.rig, plate, renderer), AREA, (3, 3)).visibility(xy, g)
    assert ((direct > 0) & (direct < 1)).mean() > 0.05
    assert np.abs(warp - direct).mean() < 0.01


@pytest.mark.gl
def test_atlas_without_the_grown_range_refuses_edge_positions(renderer, plate):
    """An atlas baked for the object's range alone cannot serve light samples at
    the range's edge (their equivalent positions lie outside): a clear error, or
    a clamp with a warning; the soft atlas serves them."""
    narrow = bake_atlas(plate, np.eye(4), MOTION, PointLight(AREA.center), (64, 64),
                        renderer=renderer, progress=False)
    soft = SoftShadow(narrow, AREA, (2, 2))
    g = receiver_grid(0.9, (16, 16)).reshape(-1, 3)
    edge = MOTION.hi.copy()
    with pytest.raises(OutOfRangeError, match="inside the baked range"):
        soft.visibility(edge, g)
    with pytest.warns(RangeClampWarning, match="outside the baked range"):
        soft.visibility(edge, g, clamp=True)
    wide = bake_soft_atlas(plate, np.eye(4), MOTION, AREA, (64, 64), renderer=renderer,
                           progress=False)
    assert np.isfinite(SoftShadow(wide, AREA, (2, 2)).visibility(edge, g)).all()


@pytest.mark.gl
def test_methods_for_another_light_are_refused(renderer, plate):
    sun = bake_atlas(plate, np.eye(4), MOTION, DirectionalLight([0, 0.2, -1]), (32, 32),
                     renderer=renderer, progress=False)
    with pytest.raises(ValidationError, match="PointLight at the area light's centre.*Directional"):
        SoftShadow(sun, AREA)
    off = bake_atlas(plate, np.eye(4), MOTION, PointLight([0.0, 0.0, 2.4]), (32, 32),
                     renderer=renderer, progress=False)
    with pytest.raises(ValidationError, match=r"centre \[0.2, -0.1, 2.4\].*at \[0.0, 0.0, 2.4\]"):
        SoftShadow(off, AREA)
    with pytest.raises(ValidationError, match="method: expected a ShadowMethod .*got dict"):
        SoftShadow({"rig": off.rig}, AREA)
