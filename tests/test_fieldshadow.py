"""The field's shadow from many instances' sun atlases (issue 26): one light view, placed views,
the receiver's cull, the cache, the horizon, bad arguments.

The analytic sphere (:mod:`morphkit.billboard.analytic`: radius 0.6 about ``(0, 0, 1)``) gives
atlases without GL and shadows known exactly (as in ``tests/test_sunatlas.py``); an atlas of
the sphere moved off its axis gives a caster whose shadow turns with the instance's yaw.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.billboard.analytic import SPHERE_PIVOT, SPHERE_RADIUS, sphere_view
from morphkit.billboard.frames.instances import Instances
from morphkit.errors import ValidationError
from morphkit.imaging.metrics import shadow_iou
from morphkit.sunlit.fieldshadow import FieldShadow
from morphkit.sunlit.fieldsplat import SplatDrawer, splat_points
from morphkit.sunlit.sunatlas import SunAtlas, sun_direction
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras

DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
N = 64
TPU = 40.0
OFFSET = np.array([0.3, 0.0, 0.0])  # the off-axis sphere's centre, relative to the pivot


def _atlas(offset: np.ndarray) -> SunAtlas:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (N, N))
    depths = []
    for a, e in zip(DOME.azimuths_deg(), DOME.elevations_deg(), strict=True):
        cam = cams.ortho_camera(a, e, (N, N))
        pose = np.array(cam.cam2world)
        pose[:3, 3] -= offset  # the sphere seen from here sits at pivot + offset
        depths.append(sphere_view(cam.with_pose(pose))[2])
    return SunAtlas.from_depths(DOME, cams, np.stack(depths))


@pytest.fixture(scope="module")
def atlases() -> dict[str, SunAtlas]:
    return {"ball": _atlas(np.zeros(3)), "off": _atlas(OFFSET)}


def _grid(x0: float, y0: float, x1: float, y1: float, n: int = 200) -> np.ndarray:
    X, Y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def _truth(points: np.ndarray, spheres: list[tuple[np.ndarray, float]], sun: np.ndarray) -> np.ndarray:
    """True where the ray from a point towards the sun passes through one of the spheres."""
    out = np.zeros(len(points), bool)
    for centre, radius in spheres:
        v = centre - points
        along = v @ sun
        out |= (np.linalg.norm(v - along[:, None] * sun, axis=1) < radius) & (along > 0)
    return out


def _on_ground(centre: np.ndarray, sun: np.ndarray) -> np.ndarray:
    return centre - centre[2] / sun[2] * sun


def test_two_spheres_cast_their_two_ellipses(atlases):
    sun = sun_direction(17.0, 52.0)
    inst = Instances.from_records([("ball", 0.0, 0.0, 30.0), ("ball", 3.0, 1.0, 200.0, 1.5)])
    fm = FieldShadow(atlases).build(inst, sun, TPU)
    assert list(fm.kept) == [0, 1] and fm.skipped == 0
    spheres = [(SPHERE_PIVOT.copy(), SPHERE_RADIUS), (np.array([3.0, 1.0, 0.0]) + 1.5 * SPHERE_PIVOT,
                                                      1.5 * SPHERE_RADIUS)]
    pts = _grid(-3.0, -3.0, 4.0, 3.0, 280)
    shadow = fm.visibility(pts) < 0.5
    assert shadow_iou(shadow, _truth(pts, spheres, sun)) > 0.93
    for centre, radius in spheres:  # each ellipse about its own centre
        c = _on_ground(centre, sun)
        mine = shadow & (np.linalg.norm(pts[:, :2] - c[:2], axis=1) < 1.2 * radius / sun[2])
        assert np.linalg.norm(pts[mine, :2].mean(axis=0) - c[:2]) < 2.0 / TPU


def test_an_instance_whose_shadow_misses_the_receiver_is_skipped(atlases):
    sun = sun_direction(0.0, 45.0)  # shadows fall towards -x
    rect = (-2.0, -1.5, 1.0, 1.5)
    near = Instances.from_records([("ball", 0.0, 0.0)])
    both = Instances.from_records([("ball", 0.0, 0.0), ("ball", 0.0, 6.0), ("ball", 2.5, 0.0)])
    fs = FieldShadow(atlases)
    fm = fs.build(both, sun, TPU, rect)
    # (0, 6) is far aside; (2.5, 0)'s shadow reaches x = 2.5 - 1.6 - 0.6 / sin 45 > -2: it stays
    assert fm.skipped == 1 and list(fm.kept) == [0, 2]
    pts = _grid(*rect, 120)
    alone = fs.build(Instances.from_records([("ball", 0.0, 0.0), ("ball", 2.5, 0.0)]), sun, TPU, rect)
    assert np.array_equal(fm.visibility(pts), alone.visibility(pts))
    assert (fs.build(near, sun, TPU, rect).visibility(pts) < 0.5).sum() > 100
    gone = fs.build(Instances.from_records([("ball", 0.0, 9.0)]), sun, TPU, rect)
    assert gone.camera is None and gone.skipped == 1 and (gone.visibility(pts) == 1.0).all()


def test_no_instance_lights_everything(atlases):
    none = Instances.from_records([])
    fm = FieldShadow(atlases).build(none, sun_direction(10.0, 40.0), TPU, (-1, -1, 1, 1))
    assert fm.camera is None and len(fm.kept) == 0
    vis = fm.visibility(_grid(-1, -1, 1, 1, 10))
    assert vis.dtype == np.float32 and (vis == 1.0).all()


def test_two_instances_at_one_spot_are_one(atlases):
    sun = sun_direction(-70.0, 33.0)
    fs = FieldShadow(atlases, SplatDrawer())
    one = fs.build(Instances.from_records([("off", 1.0, 2.0, 40.0)]), sun, TPU)
    two = fs.build(Instances.from_records([("off", 1.0, 2.0, 40.0), ("off", 1.0, 2.0, 40.0)]), sun, TPU)
    assert np.isfinite(one.depth).sum() > 500
    assert np.array_equal(one.depth, two.depth)


@pytest.mark.parametrize("elevation", [0.0, -10.0, -90.0])
def test_a_sun_at_or_below_the_horizon_casts_nothing(atlases, elevation):
    inst = Instances.from_records([("ball", 0.0, 0.0), ("off", 1.0, 1.0, 50.0)])
    fm = FieldShadow(atlases).build(inst, sun_direction(30.0, elevation), TPU, (-3, -3, 3, 3))
    assert fm.camera is None
    assert (fm.visibility(_grid(-3, -3, 3, 3, 40)) == 1.0).all()


def test_a_yawed_instance_casts_the_shadow_of_the_sun_turned_back(atlases):
    yaw, sun = 90.0, sun_direction(-63.0, 41.0)
    fs = FieldShadow(atlases)
    fm = fs.build(Instances.from_records([("off", 0.0, 0.0, yaw)]), sun, TPU)
    centre = SPHERE_PIVOT + np.array([0.0, 0.3, 0.0])  # the offset turned by 90 degrees
    c = _on_ground(centre, sun)
    pts = _grid(c[0] - 1.5, c[1] - 1.5, c[0] + 1.5, c[1] + 1.5)
    seen = fm.visibility(pts)
    assert shadow_iou(seen < 0.5, _truth(pts, [(centre, SPHERE_RADIUS)], sun)) > 0.93
    # the unturned instance under the sun turned by -yaw, looked up at the points turned back
    turned = sun_direction(-63.0 - yaw, 41.0)
    back = fs.build(Instances.from_records([("off", 0.0, 0.0, 0.0)]), turned, TPU)
    rot = pts @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # Rz(-90) p, as rows
    assert (seen != back.visibility(rot)).mean() < 0.005
    assert (seen < 0.5).sum() > 1000


def test_an_unchanged_field_reuses_its_map_and_a_moved_one_does_not(atlases):
    inst = Instances.from_records([("off", 0.0, 0.0, 10.0), ("ball", 2.0, 0.0)])
    fs = FieldShadow(atlases)
    sun = sun_direction(5.0, 50.0)
    first = fs.build(inst, sun, TPU)
    assert fs.build(inst, sun.copy(), TPU) is first and fs.reused == 1
    moved = Instances(inst.names, inst.asset, inst.xy + [[0.0, 0.1], [0.0, 0.0]], inst.yaw_deg, inst.scale)
    assert fs.build(moved, sun, TPU) is not first
    assert fs.build(moved, sun, TPU, (-3.0, -3.0, 3.0, 3.0)) is not first  # another receiver
    assert fs.reused == 1


@pytest.mark.parametrize("half", [0.3, 0.5, 1.2])
def test_the_compiled_splat_equals_its_numpy_reference(monkeypatch, half):
    from morphkit.sunlit import fieldsplat

    rng = np.random.default_rng(7)
    points = rng.uniform(-1.0, 1.0, (500, 3)).astype(np.float32)
    normals = rng.normal(size=(500, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals[::7] = 0.0  # unknown normals: full squares
    normals = normals.astype(np.float32)
    seg_start, seg_len = np.array([0, 200, 350]), np.array([200, 150, 150])
    seg_dir = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, -0.6, 0.8]])
    T = np.zeros((2, 3, 4))
    T[0, :, :3], T[0, :, 3] = 9.0 * np.eye(3), [10.0, 12.0, 5.0]
    T[1, :, :3], T[1, :, 3] = 7.5 * np.eye(3)[[1, 0, 2]], [14.0, 9.5, 6.0]
    seg = np.array([[0, 2, -1], [1, -1, -1]])
    halves = np.array([half, 0.7 * half])
    suns = np.array([[0.0, 0.6, 0.8], [0.36, 0.48, 0.8]])
    out = []
    for compiled in (True, False):
        monkeypatch.setattr(fieldsplat, "use_compiled", lambda _k, c=compiled: c)
        d = np.full((24, 26), np.inf, np.float32)
        splat_points(d, points, normals, seg_start, seg_len, seg_dir, T, seg, halves, suns)
        out.append(d)
    assert np.isfinite(out[0]).sum() > 50
    np.testing.assert_array_equal(out[0], out[1])


@pytest.mark.parametrize("bands", [2, 3, 5])
def test_the_splat_and_the_closing_in_bands_of_rows_equal_one_band(monkeypatch, bands):
    """Each band draws the instances whose rows it can reach and writes its own rows: the map
    equals the numpy reference bit for bit (an instance's row bound too tight would lose the
    points of the rows beyond it)."""
    from morphkit.sunlit import fieldsplat

    rng = np.random.default_rng(11)
    points = rng.uniform(-1.0, 1.0, (600, 3)).astype(np.float32)
    normals = rng.normal(size=(600, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals = normals.astype(np.float32)
    seg_start, seg_len = np.array([0, 300]), np.array([300, 300])
    seg_dir = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    T = np.zeros((3, 3, 4))
    poses = [(9.0, [10.0, 12.0, 5.0]), (6.0, [20.0, 30.0, 6.0]), (11.0, [30.0, 41.0, 4.0])]
    for i, (k, t) in enumerate(poses):
        T[i, :, :3], T[i, :, 3] = k * np.eye(3), t
    seg = np.array([[0, 1], [1, -1], [0, -1]])
    halves, suns = np.array([0.6, 0.9, 0.4]), np.array([[0.0, 0.6, 0.8]] * 3)
    sizes = rng.choice(np.array([1.0, 2.0, 4.0], np.float32), 600)
    got = {}
    for name, compiled, n in (("numpy", False, 1), ("bands", True, bands)):
        monkeypatch.setattr(fieldsplat, "use_compiled", lambda _k, c=compiled: c)
        monkeypatch.setattr(fieldsplat, "WARP_THREADS", n)
        monkeypatch.setattr(fieldsplat, "PARALLEL_MIN_PIXELS", 0)
        d = np.full((52, 44), np.inf, np.float32)
        splat_points(d, points, normals, seg_start, seg_len, seg_dir, T, seg, halves, suns, sizes)
        got[name] = (d, fieldsplat.close_holes(d))
    assert np.isfinite(got["numpy"][0]).sum() > 300
    np.testing.assert_array_equal(got["bands"][0], got["numpy"][0])
    np.testing.assert_array_equal(got["bands"][1], got["numpy"][1])


def _one_point(xyz, normal, sun, half, view=(0.0, 0.0, 1.0)) -> np.ndarray:
    d = np.full((6, 6), np.inf, np.float32)
    T = np.zeros((1, 3, 4))
    T[0, :, :3] = np.eye(3)
    splat_points(d, np.array([xyz], np.float32), np.array([normal], np.float32), np.array([0]),
                 np.array([1]), np.array([view], float), T, np.array([[0]]), np.array([half]),
                 np.array([sun], float))
    return d


def test_a_point_fills_the_texels_whose_centres_its_square_covers():
    # facing its view and the sun alike: the square [1.2, 3.2) x [2, 4): columns 2, 3; rows 2, 3
    d = _one_point([2.2, 3.0, 1.5], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 1.0)
    assert sorted(zip(*np.nonzero(np.isfinite(d)), strict=True)) == [(2, 2), (2, 3), (3, 2), (3, 3)]
    assert (d[np.isfinite(d)] == np.float32(1.5)).all()
    assert not np.isfinite(_one_point([2.5, 3.5, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 0.2)).any()
    # an unknown normal keeps the full square
    unknown = _one_point([2.2, 3.0, 1.5], [0.0, 0.0, 0.0], [0.6, 0.0, 0.8], 1.0)
    assert np.array_equal(np.isfinite(unknown), np.isfinite(d))


def test_a_patch_the_sun_grazes_shrinks_and_one_it_faces_does_not_grow():
    # the sun at 0.25 of the view's cosine: the square's side halves, [1.7, 2.7) x [2.5, 3.5): one texel
    grazed = _one_point([2.2, 3.0, 1.5], [0.0, 0.0, 1.0], [np.sqrt(1 - 0.0625), 0.0, 0.25], 1.0)
    assert sorted(zip(*np.nonzero(np.isfinite(grazed)), strict=True)) == [(3, 2)]
    # seen at a grazing angle from its view, squarely from the sun: not more than the full square
    faced = _one_point([2.2, 3.0, 1.5], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, view=(0.0, 0.0, 1.0))
    assert np.isfinite(faced).sum() == 4


def test_bad_arguments_raise(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    up = np.array([0.0, 0.0, 1.0])
    with pytest.raises(ValidationError, match="non-empty mapping"):
        FieldShadow({})
    with pytest.raises(ValidationError, match="a SunAtlas"):
        FieldShadow({"ball": "atlas"})
    with pytest.raises(ValidationError, match="a FieldDrawer"):
        FieldShadow(atlases, "splat")  # type: ignore[arg-type]
    fs = FieldShadow(atlases)
    with pytest.raises(ValidationError, match="names with an atlas"):
        fs.build(Instances.from_records([("tree", 0.0, 0.0)]), up, TPU)
    with pytest.raises(ValidationError, match="an Instances"):
        fs.build([("ball", 0.0, 0.0)], up, TPU)
    with pytest.raises(ValidationError, match="texels_per_unit"):
        fs.build(inst, up, 0.0)
    with pytest.raises(ValidationError, match="min < max"):
        fs.build(inst, up, TPU, (1.0, 0.0, -1.0, 2.0))
    with pytest.raises(ValidationError, match="non-zero direction"):
        fs.build(inst, np.zeros(3), TPU)
    with pytest.raises(ValidationError, match="texels a side"):
        fs.build(Instances.from_records([("ball", 0.0, 0.0), ("ball", 500.0, 0.0)]), up, TPU)
    with pytest.raises(ValidationError, match="points"):
        fs.build(inst, up, TPU).visibility(np.zeros((3, 2)))


@pytest.mark.gl
def test_the_field_matches_its_direct_render_and_the_ray_cast(renderer):
    from morphkit.meshes import normalize
    from morphkit.sunlit.fieldbaselines import direct_field_map, ray_cast_field
    from morphkit.sunlit.sunatlas import bake_sun_atlas

    meshes = {"box": trimesh.creation.box(extents=(0.3, 0.6, 1.0)), "ball": trimesh.creation.icosphere()}
    atl = {nm: bake_sun_atlas(m, renderer, dome=DOME, size=48) for nm, m in meshes.items()}
    inst = Instances.from_records([("box", 0.0, 0.0, 25.0), ("ball", 2.0, 1.0, 0.0, 0.7),
                                   ("box", -1.5, 2.0, 120.0, 1.3), ("box", 30.0, 30.0)])
    sun, rect = sun_direction(-140.0, 38.0), (-4.0, -3.0, 4.0, 4.0)
    fs = FieldShadow(atl)
    tpu = 48 / (2.0 * atl["box"].cameras.half_extent[0])
    fm = fs.build(inst, sun, tpu, rect)
    dm = direct_field_map(fs, {nm: normalize(m) for nm, m in meshes.items()}, renderer, inst, sun, tpu, rect)
    assert fm.skipped == dm.skipped == 1
    np.testing.assert_array_equal(fm.camera.cam2world, dm.camera.cam2world)
    pts = _grid(*rect, 160)
    truth = ray_cast_field(meshes, inst, sun, pts) < 0.5
    assert truth.sum() > 1000
    assert shadow_iou(fm.visibility(pts) < 0.5, truth) > 0.88
    assert shadow_iou(dm.visibility(pts) < 0.5, truth) > 0.9
    assert (ray_cast_field(meshes, inst, sun_direction(0.0, -5.0), pts) == 1.0).all()


def test_holes_close_between_two_drawn_neighbours_only(monkeypatch):
    from morphkit.sunlit import fieldsplat

    rng = np.random.default_rng(3)
    d = np.where(rng.random((40, 50)) < 0.6, rng.uniform(1.0, 2.0, (40, 50)), np.inf).astype(np.float32)
    got = []
    for compiled in (True, False):
        monkeypatch.setattr(fieldsplat, "use_compiled", lambda _k, c=compiled: c)
        got.append(fieldsplat.close_holes(d))
    np.testing.assert_array_equal(got[0], got[1])
    filled = np.isfinite(got[0]) & ~np.isfinite(d)
    assert filled.sum() > 50
    r, c = np.nonzero(filled)
    p = np.pad(d, 1, constant_values=np.inf)  # texels outside are empty
    r, c = r + 1, c + 1
    want = np.minimum(np.minimum(p[r, c - 1], p[r, c + 1]), np.minimum(p[r - 1, c], p[r + 1, c]))
    assert np.array_equal(got[0][filled], want)
    # a staircase outline keeps its steps: no texel with drawn neighbours on two adjacent sides only
    stairs = np.where(np.add.outer(np.arange(8), np.arange(8)) < 8, 1.0, np.inf).astype(np.float32)
    assert np.array_equal(fieldsplat.close_holes(stairs), stairs)


def test_a_map_with_nan_depths_is_refused_at_its_first_lookup(atlases):
    from morphkit.sunlit.fieldshadow import FieldMap

    one = Instances.from_records([("ball", 0.0, 0.0)])
    fm = FieldShadow(atlases).build(one, sun_direction(0.0, 50.0), TPU)
    bad = fm.depth.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValidationError, match="NaN/-inf texels"):
        FieldMap(fm.camera, bad, fm.kept).visibility(np.zeros((2, 3)))
    pts = _grid(-2, -2, 2, 2, 30)
    assert np.array_equal(fm.visibility(pts), fm.visibility(pts))  # checked once, then trusted


def test_objects2world_is_translation_yaw_scale_of_each():
    """The splat poses its instances in one batch: translation(x, y, 0) @ Rz(yaw) @ scale each,
    as :meth:`Instances.object2world` documents."""
    import trimesh

    xy, yaw, scale = np.array([[0.5, -1.0], [2.0, 3.0], [-4.0, 0.25]]), np.array([0.0, 37.0, -120.0]), \
        np.array([1.0, 0.5, 2.5])
    inst = Instances(["a", "b"], np.array([0, 1, 0]), xy, yaw, scale)
    order = [2, 0, 1]
    many = inst.objects2world(np.array(order))
    for row, k in enumerate(order):
        want = (trimesh.transformations.translation_matrix([*xy[k], 0.0])
                @ trimesh.transformations.rotation_matrix(np.radians(yaw[k]), [0.0, 0.0, 1.0])
                @ trimesh.transformations.scale_matrix(scale[k]))
        np.testing.assert_allclose(many[row], want, atol=1e-12)
        np.testing.assert_array_equal(inst.object2world(k), many[row])
