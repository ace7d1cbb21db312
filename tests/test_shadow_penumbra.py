"""Smooth penumbrae from few light samples: the filtered lookup (no GL: synthetic
maps against a texel-by-texel reference and the hard lookup) and the PCF / PCSS
soft shadows against the ray cast (GL), with the issue's hard cases."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.camera import look_at, orthographic, perspective
from morphkit.errors import OutOfRangeError, ValidationError
from morphkit.imaging.groundtruth import area_visibility, receiver_grid
from morphkit.scene import AreaLight, SceneObject
from morphkit.shadow import (
    DirectShadow,
    MotionRange,
    RangeClampWarning,
    SoftShadow,
    bake_atlas,
    bake_soft_atlas,
    shadow_visibility,
)
from morphkit.shadow.filtering import filtered
from morphkit.shadow.filtering.depthtables import DepthTables
from morphkit.shadow.filtering.filtered import cell_half_widths, filtered_visibility, point_chunks
from morphkit.shadow.filtering.penumbra import (
    PcfSoftShadow,
    PcssSoftShadow,
    light_cell,
    soft_shadow_class,
)
from morphkit.shadow.lookup import ShadowBias
from morphkit.shadow.soft import FIVE_SAMPLES

MOTION = MotionRange([-0.4, -0.3], [0.4, 0.3])
AREA = AreaLight([0.2, -0.1, 2.4], [0.3, 0.0, 0.0], [0.0, 0.2, 0.0])


# ------------------------------------------------------------------ no GL
@pytest.fixture(scope="module")
def synthetic():
    """A 64^2 light map looking straight down from 2.4 with a two-depth occluder
    (a block at depth 1.6 beside one at 1.9) and ground points below it."""
    cam = perspective(np.deg2rad(40), (64, 64), look_at([0, 0, 2.4], [0, 0, 0], [0, 1, 0]),
                      znear=0.5, zfar=5)
    dm = np.full((64, 64), np.inf, np.float32)
    dm[20:44, 16:40] = 1.9
    dm[24:40, 16:26] = 1.6
    g = receiver_grid(0.5, (48, 48)).reshape(-1, 3)
    return cam, dm, g


def _reference(points, dm, cam, cell, mode):
    """The filtered lookup's definition, texel by texel over the whole map (no tables)."""
    bias = ShadowBias()
    kx, ky = cell_half_widths(cell, cam)
    T = cam.texture_matrix()
    q = points @ T[:, :3].T + T[:, 3]
    z = q[:, 2]
    px, py = q[:, 0] / q[:, 3], q[:, 1] / q[:, 3]
    occ = np.isfinite(dm)
    z_min, z_mean = dm[occ].min(), dm[occ].mean()
    ii, jj = np.meshgrid(np.arange(dm.shape[1]), np.arange(dm.shape[0]))
    out = np.ones(len(points))

    def blocked(k, hx, hy, zt, centre=None):
        cx, cy = (px[k], py[k]) if centre is None else centre
        ox = np.clip(np.minimum(cx + hx, ii + 0.5) - np.maximum(cx - hx, ii - 0.5), 0, None)
        oy = np.clip(np.minimum(cy + hy, jj + 0.5) - np.maximum(cy - hy, jj - 0.5), 0, None)
        wgt = ox * oy * (occ & (dm < zt))
        return wgt.sum(), (wgt * np.where(occ, dm, 0)).sum()

    for k in range(len(points)):
        texel = z[k] / cam.fx
        zt = z[k] - texel * (bias.constant + bias.slope)  # no normals: tan = 1
        s = 1 / (z_mean if mode == "mean" else z_min) - 1 / z[k]
        hx, hy = kx * s, ky * s
        if mode == "search" and max(hx, hy) >= 0.5:
            sx, sy = max(hx, 0.5), max(hy, 0.5)
            i0, i1 = max(np.floor(px[k] - sx + 0.5), 0), min(np.floor(px[k] + sx + 0.5), dm.shape[1] - 1)
            j0, j1 = max(np.floor(py[k] - sy + 0.5), 0), min(np.floor(py[k] + sy + 0.5), dm.shape[0] - 1)
            # the search box rounded out to whole texels
            a, ds = blocked(k, (i1 - i0 + 1) / 2, (j1 - j0 + 1) / 2,
                            zt - texel * bias.slope * max(sx, sy), ((i0 + i1) / 2, (j0 + j1) / 2))
            if a <= tol.PX_EQUAL:
                continue
            s = 1 / (ds / a) - 1 / z[k]
            c, r = int(np.rint(px[k])), int(np.rint(py[k]))  # contact: blockers next to the point
            near = dm[max(r - 1, 0):r + 2, max(c - 1, 0):c + 2]
            if np.any(near < zt):
                s = min(s, 1 / near[near < zt].max() - 1 / z[k])
            hx, hy = kx * s, ky * s
        if max(hx, hy) < 0.5:
            c, r = int(np.rint(px[k])), int(np.rint(py[k]))
            if 0 <= c < dm.shape[1] and 0 <= r < dm.shape[0] and occ[r, c]:
                out[k] = 0.0 if z[k] > dm[r, c] + texel * (bias.constant + bias.slope) else 1.0
            continue
        hx, hy = max(hx, 0.5), max(hy, 0.5)
        a, _ = blocked(k, hx, hy, zt - texel * bias.slope * max(hx, hy))
        out[k] = np.clip(1 - a / (4 * hx * hy), 0, 1)
    return out


@pytest.mark.parametrize("mode", ["mean", "search"])
@pytest.mark.parametrize("height", [0.0, 0.65], ids=["ground", "between-the-blocks"])
def test_tables_give_the_texel_by_texel_definition(synthetic, mode, height):
    """Ground points: every occluder texel is in front (the summed-area tables
    answer); points at height 0.65 (depth 1.75, between the two blocks): the
    texel-by-texel scan answers. Both equal the definition."""
    cam, dm, g = synthetic
    pts = g + [0, 0, height]
    cell = np.array([[0.1, 0, 0], [0, 0.07, 0]])
    got = filtered_visibility(pts, dm, cam, cell, blocker=mode)
    want = _reference(pts, dm, cam, cell, mode)
    np.testing.assert_allclose(got, want, atol=2e-6)
    if height == 0:  # (at 0.65 the penumbra falls outside the grid)
        assert np.count_nonzero((got > 0.05) & (got < 0.95)) > 50  # a real penumbra was tested


@pytest.mark.parametrize("mode", ["mean", "search"])
def test_runs_and_threads_leave_the_lookup_unchanged(synthetic, rng, monkeypatch, mode):
    """Runs of points whose bounding box misses the map are lit without a look at their
    points: shuffled points (every run spans the map) give the same values bit for bit,
    and so does a split of the points over threads."""
    cam, dm, g = synthetic
    far = g + [5, 0, 0]  # beyond the map's reach
    pts = np.concatenate([g, g + [0, 0, 0.65], far])
    cell = np.array([[0.1, 0, 0], [0, 0.07, 0]])
    want = filtered_visibility(pts, dm, cam, cell, blocker=mode)
    assert np.all(want[2 * len(g):] == 1) and np.count_nonzero((want > 0.05) & (want < 0.95)) > 50
    order = rng.permutation(len(pts))
    np.testing.assert_array_equal(filtered_visibility(pts[order], dm, cam, cell, blocker=mode), want[order])
    monkeypatch.setattr(filtered, "PARALLEL_MIN_POINTS", 1)
    monkeypatch.setattr(filtered, "WARP_THREADS", 3)
    np.testing.assert_array_equal(filtered_visibility(pts, dm, cam, cell, blocker=mode), want)


@pytest.mark.parametrize("normals", [False, True], ids=["no-normals", "normals"])
@pytest.mark.parametrize("half", [0.1, 0.6], ids=["narrow", "wide"])
def test_shared_searches_leave_the_lookup_unchanged(synthetic, rng, normals, half):
    """Ground points on a slab at their own depth (texels behind the point under every box,
    as where an object touches its receiver) beside a nearer block: a point's texels
    behind come from a search shared with its neighbours or from its own, and runs are
    tested as a whole first; points in grid order, shuffled, and one at a time (nothing
    shared, runs of one) agree bit for bit. The wide cell's shared searches hold more
    texels than ``BEHIND_SHARE_KEEP`` (the points then search alone)."""
    cam, _dm, g = synthetic
    dm = np.full((64, 64), np.inf, np.float32)
    dm[4:60, 4:60] = 2.4  # the ground's depth under the camera at 2.4
    dm[26:38, 18:30] = 1.6
    cell = np.array([[half, 0, 0], [0, half, 0]])
    nrm = np.tile([0.0, 0.0, 1.0], (len(g), 1)) if normals else None
    grid = filtered_visibility(g, dm, cam, cell, normals=nrm)
    assert np.count_nonzero((grid > 0.05) & (grid < 0.95)) > 50  # a penumbra on the slab
    if half > 0.5:  # the shared box (widest box + margins) over the slab overflows
        sx = cell_half_widths(cell, cam)[0] * (1 / 1.6 - 1 / 2.4)
        assert (2 * sx + 1 + 2 * filtered.BEHIND_SHARE_TEXELS) ** 2 > filtered.BEHIND_SHARE_KEEP
    order = rng.permutation(len(g))
    shuffled = filtered_visibility(g[order], dm, cam, cell, normals=None if nrm is None else nrm[order])
    np.testing.assert_array_equal(shuffled, grid[order])
    some = rng.choice(len(g), 300, replace=False)
    alone = [filtered_visibility(g[k:k + 1], dm, cam, cell, normals=None if nrm is None else nrm[k:k + 1])[0]
             for k in some]
    np.testing.assert_array_equal(alone, grid[some])


def test_point_chunks_bound_their_runs(rng):
    pts = rng.normal(size=(1000, 3))
    ch = point_chunks(pts)
    n_c = -(-1000 // filtered.CHUNK_POINTS)
    assert ch.shape == (n_c + -(-n_c // filtered.CHUNK_GROUP), 6)
    run = pts[filtered.CHUNK_POINTS:2 * filtered.CHUNK_POINTS]
    np.testing.assert_array_equal(ch[1], np.r_[run.min(0), run.max(0)])
    np.testing.assert_array_equal(ch[n_c], np.r_[pts[:filtered.CHUNK_POINTS * filtered.CHUNK_GROUP].min(0),
                                                  pts[:filtered.CHUNK_POINTS * filtered.CHUNK_GROUP].max(0)])
    last = (n_c - 1) // filtered.CHUNK_GROUP * filtered.CHUNK_GROUP * filtered.CHUNK_POINTS
    np.testing.assert_array_equal(ch[-1, 3:], pts[last:].max(0))


def test_a_cell_of_zero_extent_is_the_hard_lookup_exactly(synthetic, rng):
    cam, dm, g = synthetic
    pts = g + rng.normal(0, 0.01, g.shape) + [0, 0, 0.2]
    nrm = rng.normal(size=g.shape)
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    for mode in ("mean", "search"):
        np.testing.assert_array_equal(
            filtered_visibility(pts, dm, cam, np.zeros((2, 3)), blocker=mode, normals=nrm),
            shadow_visibility(pts, dm, cam, normals=nrm))


def test_a_straight_edge_gives_a_linear_ramp(synthetic):
    """One occluder depth, axis-aligned cell: the penumbra of a straight edge is the
    exact linear ramp (the box sweeps the edge), with no steps."""
    cam, _dm, _g = synthetic
    dm = np.full((64, 64), np.inf, np.float32)
    dm[:, :32] = 1.9  # a half-plane at depth 1.9, edge between columns 31 and 32
    x = np.linspace(-0.4, 0.4, 400)
    pts = np.c_[x, np.zeros_like(x), np.zeros_like(x)]
    cell = np.array([[0.1, 0, 0], [0, 0.1, 0]])
    vis = filtered_visibility(pts, dm, cam, cell, blocker="mean")
    kx, _ = cell_half_widths(cell, cam)
    z = 2.4
    texel = z / cam.fx
    hx = kx * (1 / 1.9 - 1 / z)
    px = cam.texture_matrix()[0, :3] @ pts.T / z + cam.texture_matrix()[0, 3] / z
    ramp = np.clip((px - 31.5) / (2 * hx) + 0.5, 0, 1)
    np.testing.assert_allclose(vis, ramp, atol=1e-5)
    assert texel > 0 and hx > 0.5  # a ramp wider than a texel
    assert np.max(np.abs(np.diff(vis))) < 2.5 * np.max(np.abs(np.diff(ramp)))


@pytest.mark.parametrize("mode", ["mean", "search"])
def test_a_sloped_receiver_does_not_shadow_itself(synthetic, mode):
    """A plane steep to the light (depth rises 1.5 per unit across the image) in the
    map, points on it with their normals, a wide cell: the kernel spans many texels
    of the plane in front of the point, and the receiver's plane keeps them from
    counting; a block hovering 0.3 in front of the plane still casts its (soft)
    shadow (a bias growing with the kernel, texel x slope x width, lost it whole)."""
    cam, _dm, _g = synthetic
    g_slope, z0 = 1.5, 2.0
    ii = np.arange(64)
    depth_row = z0 / (1 - g_slope * (ii - cam.cx) / cam.fx)  # Z = z0 + g X in the camera frame
    dm = np.tile(depth_row, (64, 1)).astype(np.float32)
    uu, vv = np.meshgrid(np.linspace(8, 56, 25), np.linspace(8, 56, 25))
    zz = z0 / (1 - g_slope * (uu - cam.cx) / cam.fx)
    pc = np.stack([(uu - cam.cx) * zz / cam.fx, (vv - cam.cy) * zz / cam.fy, zz], -1).reshape(-1, 3)
    c2w = np.linalg.inv(cam.world2cam)
    pts = pc @ c2w[:3, :3].T + c2w[:3, 3]
    n = np.array([g_slope, 0.0, -1.0]) / np.hypot(g_slope, 1.0)  # faces the light
    nrm = np.tile(n @ c2w[:3, :3].T, (len(pts), 1))
    cell = np.array([[0.6, 0, 0], [0, 0.6, 0]])
    vis = filtered_visibility(pts, dm, cam, cell, blocker=mode, normals=nrm)
    assert vis.min() > 0.99
    dm2 = dm.copy()
    dm2[28:36, 28:36] -= 0.3
    vis2 = filtered_visibility(pts, dm2, cam, cell, blocker=mode, normals=nrm)
    assert vis2.min() < 0.5 and np.count_nonzero(vis2 < 0.99) < 0.25 * len(pts)
    if mode == "search":
        assert np.count_nonzero((vis2 > 0.01) & (vis2 < 0.99)) > 20  # a penumbra


def test_empty_map_and_bad_inputs(synthetic):
    cam, _dm, g = synthetic
    empty = np.full((64, 64), np.inf, np.float32)
    cell = np.array([[0.1, 0, 0], [0, 0.1, 0]])
    assert np.all(filtered_visibility(g, empty, cam, cell) == 1)
    assert DepthTables.of(empty).z_min == np.inf
    with pytest.raises(ValidationError, match="'search' or 'mean'"):
        filtered_visibility(g, empty, cam, cell, blocker="nearest")
    ortho = orthographic(1, 1, (64, 64), look_at([0, 0, 2.4], [0, 0, 0], [0, 1, 0]), znear=0.5, zfar=5)
    with pytest.raises(ValidationError, match="a perspective CameraModel"):
        filtered_visibility(g, empty, ortho, cell)
    with pytest.raises(ValidationError, match="finite or \\+inf"):
        filtered_visibility(g, np.full((64, 64), np.nan, np.float32), cam, cell)


def test_cells_share_the_light():
    np.testing.assert_allclose(light_cell(AREA, (3, 2)), [[0.1, 0, 0], [0, 0.1, 0]])
    np.testing.assert_allclose(light_cell(AREA, 1), [AREA.u, AREA.v])
    np.testing.assert_allclose(light_cell(AREA, FIVE_SAMPLES), [AREA.u / 5**0.5, AREA.v / 5**0.5])
    assert soft_shadow_class("pcss") is PcssSoftShadow
    assert soft_shadow_class("average") is SoftShadow
    with pytest.raises(ValidationError, match="one of \\['average', 'pcf', 'pcss'\\]"):
        soft_shadow_class("vsm")


# --------------------------------------------------------------------- GL
@pytest.fixture(scope="module")
def plate():
    m = trimesh.creation.box((0.4, 0.4, 0.02))
    m.apply_translation([0.0, 0.0, 0.5])
    return m


@pytest.fixture(scope="module")
def plate_atlas(renderer, plate):
    return bake_soft_atlas(plate, np.eye(4), MOTION, AREA, (128, 128), renderer=renderer,
                           progress=False)


def _truth(mesh, xy, g, light=AREA, n=16):
    pose = np.eye(4)
    pose[:2, 3] = xy
    return area_visibility(g, light, SceneObject(mesh, pose), n)


@pytest.mark.gl
@pytest.mark.parametrize("cls", [PcfSoftShadow, PcssSoftShadow])
def test_filtered_beats_averaging_on_the_same_maps(plate, plate_atlas, cls):
    g = receiver_grid(0.9, (96, 96)).reshape(-1, 3)
    xy = np.array([0.17, -0.11])
    truth = _truth(plate, xy, g)
    avg = SoftShadow(plate_atlas, AREA, (3, 3)).visibility(xy, g)
    filt = cls(plate_atlas, AREA, (3, 3)).visibility(xy, g)
    assert np.abs(filt - truth).mean() < 0.6 * np.abs(avg - truth).mean()
    assert len(np.unique(np.round(filt, 4))) > 5 * len(np.unique(avg))  # no N + 1 levels
    assert np.any(filt < 1e-6) and np.any(filt == 1)  # (summed-area tables round at 1e-16)


@pytest.mark.gl
@pytest.mark.parametrize("source", ["composed", "reproject", "direct"])
def test_pcss_works_with_every_map_source(renderer, plate, plate_atlas, source):
    method = (DirectShadow(plate_atlas.rig, plate, renderer) if source == "direct"
              else plate_atlas.method(warps=source))
    g = receiver_grid(0.9, (96, 96)).reshape(-1, 3)
    xy = np.array([-0.2, 0.1])
    err = np.abs(PcssSoftShadow(method, AREA, (3, 3)).visibility(xy, g) - _truth(plate, xy, g))
    assert err.mean() < 0.01


@pytest.mark.gl
def test_one_sample_is_a_whole_light_penumbra(plate, plate_atlas):
    """N = 1: the centre's map with the whole light as its cell -- still a penumbra."""
    g = receiver_grid(0.9, (96, 96)).reshape(-1, 3)
    xy = np.array([0.0, 0.0])
    one = PcssSoftShadow(plate_atlas, AREA, 1)
    assert one.n_samples == 1
    vis = one.visibility(xy, g)
    truth = _truth(plate, xy, g)
    hard = SoftShadow(plate_atlas, AREA, 1).visibility(xy, g)
    assert np.abs(vis - truth).mean() < 0.5 * np.abs(hard - truth).mean()
    assert np.count_nonzero((vis > 0.1) & (vis < 0.9)) > 100


@pytest.mark.gl
def test_a_tiny_light_gives_the_hard_shadows_exactly(renderer, plate):
    """A light far smaller than a texel's footprint: every lookup is the hard one, so
    PCF and PCSS equal the plain average of the same hard shadows, bit for bit (and
    with one sample, the hard shadow of the centre)."""
    tiny = AreaLight(AREA.center, [1e-4, 0, 0], [0, 1e-4, 0])
    atlas = bake_soft_atlas(plate, np.eye(4), MOTION, tiny, (128, 128), renderer=renderer,
                            progress=False)
    g = receiver_grid(0.9, (64, 64)).reshape(-1, 3)
    xy = np.array([0.1, 0.05])
    for samples in (1, (3, 3)):
        avg = SoftShadow(atlas, tiny, samples).visibility(xy, g)
        for cls in (PcfSoftShadow, PcssSoftShadow):
            np.testing.assert_array_equal(cls(atlas, tiny, samples).visibility(xy, g), avg)
    np.testing.assert_array_equal(PcssSoftShadow(atlas, tiny, 1).visibility(xy, g),
                                  shadow_visibility(g, *atlas.shadow_map(xy)))


@pytest.mark.gl
def test_contact_stays_sharp_where_the_object_touches_the_ground(renderer):
    """A cube on the ground (a receiver touching the occluder): the umbra under it
    stays exact, and PCSS is no blurrier at the base than PCF."""
    cube = trimesh.creation.box((0.3, 0.3, 0.3))
    cube.apply_translation([0, 0, 0.15])
    atlas = bake_soft_atlas(cube, np.eye(4), MOTION, AREA, (128, 128), renderer=renderer,
                            progress=False)
    xy = np.array([0.0, 0.0])
    x = np.linspace(-0.25, 0.25, 201)  # across the base edges at x = +-0.15
    line = np.c_[x, np.zeros_like(x), np.zeros_like(x)]
    truth = _truth(cube, xy, line)
    pcss = PcssSoftShadow(atlas, AREA, (3, 3)).visibility(xy, line)
    pcf = PcfSoftShadow(atlas, AREA, (3, 3)).visibility(xy, line)
    texel = 2.4 / atlas.rig.fx
    near = np.abs(np.abs(x) - 0.15) < 2 * texel  # within 2 texels of the contact line
    assert near.sum() >= 4
    centre = np.abs(x) < 0.05  # under the cube, farther than a kernel from its edges
    assert np.all(pcss[centre] < 1e-6) and np.all(truth[centre] == 0)
    # the map holds the cube's top only, so the blocker depth at the base is the top's:
    # the penumbra reaches under the base (measured in docs/results/soft_shadows.md, contact error)
    assert np.abs(pcss - truth)[near].mean() <= np.abs(pcf - truth)[near].mean() + 1e-6
    assert np.abs(pcss - truth)[near].mean() < 0.3


@pytest.mark.gl
def test_an_occluder_larger_than_the_light(renderer):
    """A 1.2 x 1.2 plate (twice the light's extent) at height 0.8: a wide umbra and a
    penumbra all round, as the ray cast has them."""
    big = trimesh.creation.box((1.2, 1.2, 0.02))
    big.apply_translation([0.0, 0.0, 0.8])
    atlas = bake_soft_atlas(big, np.eye(4), MOTION, AREA, (128, 128), renderer=renderer,
                            progress=False)
    g = receiver_grid(1.3, (96, 96)).reshape(-1, 3)
    xy = np.array([0.05, 0.0])
    truth = _truth(big, xy, g)
    vis = PcssSoftShadow(atlas, AREA, (3, 3)).visibility(xy, g)
    assert np.count_nonzero(truth == 0) > 1000  # the umbra
    assert vis[truth == 0].mean() < 0.01 and vis[truth == 0].max() < 0.1
    err = np.abs(vis - truth)
    assert err[(truth > 0) & (truth < 1)].mean() < 0.05


@pytest.mark.gl
def test_a_sample_leaving_the_baked_range_is_refused_or_clamped(renderer, plate):
    from morphkit.scene import PointLight

    atlas = bake_atlas(plate, np.eye(4), MOTION, PointLight(AREA.center), (64, 64),
                       renderer=renderer, progress=False)
    soft = PcssSoftShadow(atlas, AREA, (3, 3))
    g = receiver_grid(0.5, (8, 8)).reshape(-1, 3)
    with pytest.raises(OutOfRangeError, match="inside the baked range"):
        soft.visibility(MOTION.hi, g)
    with pytest.warns(RangeClampWarning):
        vis = soft.visibility(MOTION.hi, g, clamp=True)
    assert vis.shape == (64,) and np.all((vis >= 0) & (vis <= 1))
