"""The octahedral impostor (the engines' anchor baseline): its grid map, frame weights and
runtime on frames of an analytic sphere (no GL), and one bake of the cow (GL)."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard.impostor import (
    OctahedralImpostor,
    frame_grid_uv,
    hemi_oct_decode,
    hemi_oct_encode,
    impostor_frame_size,
)
from morphkit.billboard.protocols import SurfaceSource
from morphkit.errors import ValidationError
from morphkit.views.domecameras import DomeCameras, direction, quad_axes
from morphkit.views.gbuffer import BYTES_PER_PIXEL, ViewSurface

PIVOT = np.array([0.1, -0.2, 0.5])
CENTRE = PIVOT + np.array([0.25, 0.1, 0.2])  # the sphere is off the pivot: parallax matters
RADIUS = 0.45
M = 32


def _cams(m: int = M) -> DomeCameras:
    return DomeCameras(PIVOT, 12.0, 1.0, m)


def _sphere_frame(cams: DomeCameras, d: np.ndarray, right: np.ndarray, up: np.ndarray, m: int) -> ViewSurface:
    """The analytic sphere seen orthographically along ``-d`` on the quad's pixel grid."""
    half = cams.half_extent[0]
    t = (np.arange(m) - (m - 1) / 2.0) * (2.0 * half / m)
    fu, fv = t[None, :], -t[:, None]
    c = CENTRE - cams.pivot
    du, dv = fu - c @ right, fv - c @ up
    rho2 = du**2 + dv**2
    inside = rho2 < RADIUS**2
    z = np.sqrt(np.maximum(RADIUS**2 - rho2, 0.0))
    n = (du[..., None] * right + dv[..., None] * up + z[..., None] * d) / RADIUS
    n = np.where(inside[..., None], n, 0.0)
    colour = 0.2 + 0.3 * (n + 1.0)  # linear albedo that follows the surface (same from every frame)
    albedo = np.zeros((m, m, 4))
    albedo[..., :3] = np.where(inside[..., None], colour, 0.0)
    albedo[..., 3] = inside
    depth = np.where(inside, cams.distance - (c @ d + z), np.inf)
    return ViewSurface(albedo.astype(np.float32), n.astype(np.float32), depth.astype(np.float32))


def _sphere_impostor(frames: int = 5, m: int = M, **kw) -> OctahedralImpostor:
    cams = _cams(m)
    uv = frame_grid_uv(frames).reshape(-1, 2)
    dirs = hemi_oct_decode(uv)
    horiz = np.hypot(dirs[:, 0], dirs[:, 1])
    az = np.where(horiz > 0, np.degrees(np.arctan2(dirs[:, 1], dirs[:, 0])), 0.0)
    el = np.degrees(np.arctan2(dirs[:, 2], horiz))
    right, up = quad_axes(az, el)
    surfaces = [_sphere_frame(cams, dirs[k], right[k], up[k], m) for k in range(len(dirs))]
    return OctahedralImpostor.from_surfaces("sphere", cams, frames, surfaces, **kw)


@pytest.fixture(scope="module")
def sphere9() -> OctahedralImpostor:
    return _sphere_impostor(9)


@pytest.fixture(scope="module")
def sphere9o() -> OctahedralImpostor:
    return _sphere_impostor(9, projection="orthographic")


def test_hemi_octahedral_map_round_trips_and_its_landmarks(rng):
    uv = rng.uniform(-1, 1, size=(500, 2))
    d = hemi_oct_decode(uv)
    assert np.allclose(np.linalg.norm(d, axis=-1), 1.0) and (d[:, 2] >= 0).all()
    assert np.allclose(hemi_oct_encode(d), uv, atol=1e-12)
    d2 = rng.normal(size=(500, 3))
    d2[:, 2] = np.abs(d2[:, 2])
    d2 /= np.linalg.norm(d2, axis=-1, keepdims=True)
    assert np.allclose(hemi_oct_decode(hemi_oct_encode(d2)), d2, atol=1e-12)
    corners = hemi_oct_decode(np.array([[0.0, 0.0], [1, 1], [1, -1], [-1, -1], [-1, 1]]))
    assert np.allclose(corners, [[0, 0, 1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]])


def test_weights_at_a_frame_between_frames_and_at_the_top(sphere9):
    imp = sphere9
    for k in (0, 8, 13, 40, 62, 80):
        a, e = imp.frame_angles[k]
        assert imp.weights(a, e) == [(k, 1.0)]
    assert imp.frame_angles[40, 1] == pytest.approx(90.0)  # 9 x 9: the centre frame is straight above
    for a, e in [(17.0, 33.0), (200.0, 5.0), (-45.0, 71.0), (123.0, 0.0)]:
        w = imp.weights(a, e)
        assert 1 <= len(w) <= 3 and sum(x for _, x in w) == pytest.approx(1.0)
        # barycentric: the weighted frame grid points reproduce the direction's grid point
        uv = frame_grid_uv(9).reshape(-1, 2)
        target = hemi_oct_encode(direction(a, e))
        assert np.allclose(sum(x * uv[k] for k, x in w), target, atol=1e-12)
    assert len(imp.weights(10.0, 40.0)) == 3
    assert imp.weights(30.0, -20.0) == imp.weights(30.0, 0.0)  # below the horizon: clamped
    even = _sphere_impostor(4, m=16, levels=1)
    top = even.weights(0.0, 90.0)
    # the centre of an even grid: on a cell's diagonal, two frames
    assert len(top) == 2 and sum(x for _, x in top) == pytest.approx(1.0)


def test_at_a_frame_the_orthographic_surface_is_that_frame(sphere9o):
    imp = sphere9o
    assert isinstance(imp, SurfaceSource)
    for k in (10, 31, 57):  # not straight above (the frame's own roll is azimuth 0 there)
        a, e = imp.frame_angles[k]
        s, f = imp.surface(a, e), imp.frame_surface(k)
        assert s.shape == imp.level_shape(0) == (M, M)
        assert np.allclose(s.albedo, f.albedo, atol=1e-4)
        drawn = f.alpha > 0
        assert np.allclose(s.normal[drawn], f.normal[drawn], atol=1e-4)
        assert np.allclose(s.depth[drawn], f.depth[drawn], rtol=1e-5)
        assert np.isinf(s.depth[~drawn]).all()


def _expected_disc(imp: OctahedralImpostor, a: float, e: float, side: int) -> tuple[np.ndarray, float]:
    """Centre (x, y) and radius (px) of the sphere's orthographic image on the quad."""
    right, up = quad_axes(a, max(e, 0.0))
    c = CENTRE - imp.pivot
    px = imp.half_extent[0] * 2.0 / side
    centre = np.array([c @ right / px + (side - 1) / 2.0, -(c @ up) / px + (side - 1) / 2.0])
    return centre, RADIUS / px


def _ray_traced(imp: OctahedralImpostor, a: float, e: float, side: int, projection: str
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sphere ray-traced through the quad's pixel centres: hit mask, normals, depth from the eye plane."""
    e = max(e, 0.0)
    d, (right, up) = direction(a, e), quad_axes(a, e)
    t = (np.arange(side) - (side - 1) / 2.0) * (2.0 * imp.half_extent[0] / side)
    p = imp.pivot + t[None, :, None] * right - t[:, None, None] * up
    if projection == "perspective":
        o = np.broadcast_to(imp.pivot + imp.distance * d, p.shape)
        v = (p - o) / np.linalg.norm(p - o, axis=-1, keepdims=True)
    else:
        o, v = p + imp.distance * d, np.broadcast_to(-d, p.shape)
    oc = CENTRE - o
    along = np.einsum("ijk,ijk->ij", oc, v)
    miss2 = np.einsum("ijk,ijk->ij", oc, oc) - along**2
    hit = miss2 < RADIUS**2
    x = o + (along - np.sqrt(np.maximum(RADIUS**2 - miss2, 0.0)))[..., None] * v
    return hit, (x - CENTRE) / RADIUS, np.where(hit, imp.distance - (x - imp.pivot) @ d, np.inf)


DIRECTIONS = [(17.0, 33.0), (200.0, 5.0), (-45.0, 71.0), (123.0, 0.0), (30.0, -10.0), (10.0, 90.0),
              (250.0, 90.0), (61.0, 83.0)]


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
@pytest.mark.parametrize("a, e", DIRECTIONS)
def test_the_sphere_from_any_direction_matches_the_ray_traced_sphere(sphere9, sphere9o, a, e, projection):
    imp = sphere9 if projection == "perspective" else sphere9o
    s = imp.surface(a, e)
    hit, n, depth = _ray_traced(imp, a, e, M, projection)
    if projection == "orthographic":  # the ray tracer agrees with the disc of the frames' rule
        centre, r = _expected_disc(imp, a, e, M)
        assert abs(np.sqrt(hit.sum() / np.pi) - r) < 0.5
    y, x = np.mgrid[:M, :M]
    area, true_area = float(s.alpha.sum()), float(hit.sum())
    assert abs(np.sqrt(area / np.pi) - np.sqrt(true_area / np.pi)) < 1.0
    got = np.array([(s.alpha * x).sum(), (s.alpha * y).sum()]) / area
    want = np.array([x[hit].mean(), y[hit].mean()])
    assert np.linalg.norm(got - want) < 1.0
    ci, cj = np.rint(want).astype(int)
    assert s.normal[cj, ci] @ n[cj, ci] > 0.98
    assert s.depth[cj, ci] == pytest.approx(depth[cj, ci], abs=0.05)
    assert np.isinf(s.depth[s.alpha == 0]).all() and (s.normal[s.alpha == 0] == 0).all()


def test_straight_above_the_azimuth_sets_the_roll(sphere9):
    s0, s90 = sphere9.surface(0.0, 90.0), sphere9.surface(90.0, 90.0)
    # turning the azimuth by 90 degrees turns the image by 90 degrees about its centre
    assert np.allclose(np.rot90(s0.alpha, 1), s90.alpha, atol=0.05) or \
        np.allclose(np.rot90(s0.alpha, -1), s90.alpha, atol=0.05)
    assert not np.allclose(s0.alpha, s90.alpha, atol=0.05)


def test_a_coarse_grid_needs_the_parallax_search():
    """5 x 5 frames (cells of 22 to 45 degrees): one parallax step (the engines') loses the
    silhouette where the frames disagree by several pixels; the ray march keeps it."""
    imp = _sphere_impostor(5, levels=1, projection="orthographic")
    s1 = imp.surface(17.0, 33.0)
    imp.parallax_samples = 32
    s3 = imp.surface(17.0, 33.0)
    _, r = _expected_disc(imp, 17.0, 33.0, M)
    assert abs(np.sqrt(s3.alpha.sum() / np.pi) - r) < 0.5 < abs(np.sqrt(s1.alpha.sum() / np.pi) - r)


def test_levels_out_size_memory_and_the_ray_march():
    imp = _sphere_impostor(9, m=32, levels=3, out_size=40, parallax_samples=16, projection="orthographic")
    assert imp.levels == 3 and imp.level_shape(1) == (20, 20) and imp.level_shape(2) == (10, 10)
    assert imp.memory_bytes == 81 * BYTES_PER_PIXEL * (32**2 + 16**2 + 8**2)
    s = imp.surface(40.0, 20.0, level=1)
    centre, r = _expected_disc(imp, 40.0, 20.0, 20)
    assert s.shape == (20, 20) and abs(np.sqrt(s.alpha.sum() / np.pi) - r) < 1.0


def test_frame_size_for_a_budget():
    m = impostor_frame_size(12 * 12 * 9 * (64**2 + 32**2 + 16**2), 12, 3)
    assert m == 64
    m = impostor_frame_size(12 * 12 * 9 * (64**2 + 32**2 + 16**2) - 1, 12, 3)
    assert m == 63
    with pytest.raises(ValidationError, match="budget_bytes"):
        impostor_frame_size(1000, 12, 3)
    with pytest.raises(ValidationError, match="frames"):
        impostor_frame_size(10**7, 2, 3)


def test_bad_arguments(sphere9):
    with pytest.raises(ValidationError, match="elevation"):
        sphere9.surface(0.0, 91.0)
    with pytest.raises(ValidationError, match="azimuth"):
        sphere9.surface(float("nan"), 10.0)
    with pytest.raises(ValidationError, match="level"):
        sphere9.surface(0.0, 10.0, level=3)
    with pytest.raises(ValidationError, match="frames"):
        _sphere_impostor(2, m=16, levels=1)
    with pytest.raises(ValidationError, match="levels"):
        _sphere_impostor(3, m=16, levels=4)
    nine = [sphere9.frame_surface(0)] * 9
    with pytest.raises(ValidationError, match="surfaces"):
        OctahedralImpostor.from_surfaces("x", _cams(), 3, [sphere9.frame_surface(0)] * 8)
    with pytest.raises(ValidationError, match="parallax_samples"):
        OctahedralImpostor.from_surfaces("x", _cams(), 3, nine, parallax_samples=0)
    with pytest.raises(ValidationError, match="projection"):
        OctahedralImpostor.from_surfaces("x", _cams(), 3, nine, projection="fisheye")
    with pytest.raises(ValidationError, match="name"):
        OctahedralImpostor.from_surfaces("", _cams(), 3, nine)


@pytest.mark.gl
def test_bake_the_cow_matches_a_direct_render(renderer):
    from morphkit.billboard.baking.bakelook import bake_items
    from morphkit.billboard.impostor import bake_impostor
    from morphkit.meshes import normalize, sample_mesh

    cow = sample_mesh("cow")
    imp = bake_impostor(cow, renderer, name="cow", frames=4, frame_size=32)
    assert imp.memory_bytes == 16 * BYTES_PER_PIXEL * (32**2 + 16**2 + 8**2)
    norm = normalize(cow)
    cams = DomeCameras.fit(norm, 32)
    assert np.allclose(imp.pivot, cams.pivot) and imp.half_extent == cams.half_extent
    for k in (5, 9):
        a, e = imp.frame_angles[k]
        s = imp.surface(a, e)
        truth = renderer.source_passes(cams.camera(a, e), bake_items(norm), []).alpha
        inter = np.minimum(s.alpha, truth).sum()
        union = np.maximum(s.alpha, truth).sum()
        assert inter / union > 0.9
    with pytest.raises(ValidationError, match="renderer"):
        bake_impostor(cow, object(), frames=3, frame_size=16, levels=1)


@pytest.mark.gl
def test_orthographic_frame_depth_lands_on_the_mesh(renderer):
    """The frames' depth (pyrender's orthographic depth, corrected in morphkit.render) unprojects
    onto the mesh: what the parallax offset reads is the surface's height."""
    import trimesh

    from morphkit.billboard.baking.bakelook import bake_items
    from morphkit.meshes import normalize, sample_mesh

    norm = normalize(sample_mesh("cow"))
    cams = DomeCameras.fit(norm, 48)
    for a, e in [(30.0, 20.0), (0.0, 90.0)]:
        cam = cams.ortho_camera(a, e, (48, 48))
        p = renderer.source_passes(cam, bake_items(norm), [], supersample=1)
        pts, valid = cam.unproject(p.depth)
        assert valid.sum() > 300
        _, dist, _ = trimesh.proximity.closest_point(norm, pts[valid])
        assert dist.max() < 1e-4


def test_stored_frames_are_checked():
    frames = [[object()] * 9]
    with pytest.raises(ValidationError, match="stored level 0"):
        OctahedralImpostor("x", _cams(), 3, frames)
    with pytest.raises(ValidationError, match="stored"):
        OctahedralImpostor("x", _cams(), 3, [[None] * 8])
