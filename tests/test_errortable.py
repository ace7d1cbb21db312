"""Error tables of a representation against its mesh (morphkit.plan.errortable) and the frame
error predicted from them (morphkit.plan.predict)."""

from __future__ import annotations

import json
import math
import zipfile

import numpy as np
import pytest
from billboard_fakes import FakeAsset

from morphkit import tol
from morphkit.billboard import BillboardScene, ClassicMode, Instances
from morphkit.billboard.compare import PSNR_CAP_DB
from morphkit.camera import look_at, perspective
from morphkit.errors import FileFormatError, ValidationError
from morphkit.plan.errortable import ErrorTable, fit_frame, frame_shape, measure_error_table, table_camera
from morphkit.plan.predict import instance_views, predict_frame_error

HASH = "ab" * 32


def _table(**kw) -> ErrorTable:
    args = dict(asset="tree", mesh_hash=HASH, representation="classic",
                heights_px=np.array([16.0, 32.0, 64.0]), elevations_deg=np.array([0.0, 20.0, 40.0]),
                psnr_db=np.array([[20.0, 21.0, 22.0], [24.0, 25.0, 26.0], [30.0, 29.0, 28.0]]),
                iou=np.array([[0.70, 0.72, 0.74], [0.80, 0.82, 0.84], [0.90, 0.86, 0.82]]),
                params={"views": 8, "size": 64})
    args.update(kw)
    return ErrorTable(**args)


# ---------------------------------------------------------------- lookup


def test_lookup_at_the_bins_returns_the_cells():
    t = _table()
    h, e = np.meshgrid(t.heights_px, t.elevations_deg, indexing="ij")
    p, q = t.lookup(h, e)
    np.testing.assert_array_equal(p, t.psnr_db)
    np.testing.assert_array_equal(q, t.iou)


def test_lookup_between_the_bins_is_bilinear_in_log_height_and_elevation():
    t = _table()
    # 32 * 2**0.25 px is a quarter of the way (in log2) from 32 to 64; 30 deg is halfway from 20 to 40:
    # psnr = 0.75 0.5 (25 + 26) + 0.25 0.5 (29 + 28) = 19.125 + 7.125 = 26.25
    # iou  = 0.75 0.5 (0.82 + 0.84) + 0.25 0.5 (0.86 + 0.82) = 0.6225 + 0.21 = 0.8325
    p, q = t.lookup(32.0 * 2 ** 0.25, 30.0)
    assert p == pytest.approx(26.25, abs=1e-12)
    assert q == pytest.approx(0.8325, abs=1e-12)
    # along one axis only: 16 -> 32 halfway in log2 (22.63 px) at a bin's elevation
    p, _ = t.lookup(16.0 * math.sqrt(2.0), 40.0)
    assert p == pytest.approx(24.0, abs=1e-12)


def test_lookup_outside_the_grid_is_clamped():
    t = _table()
    p, q = t.lookup([4.0, 1000.0, np.inf, 32.0, 32.0], [20.0, 20.0, 0.0, -30.0, 89.0])
    np.testing.assert_array_equal(p, [21.0, 29.0, 30.0, 24.0, 26.0])
    np.testing.assert_array_equal(q, [0.72, 0.86, 0.90, 0.80, 0.84])
    with pytest.raises(ValidationError, match="heights > 0"):
        t.lookup(0.0, 10.0)


def test_a_table_of_one_bin_is_constant():
    t = _table(heights_px=np.array([32.0]), elevations_deg=np.array([10.0]), psnr_db=np.array([[25.0]]),
               iou=np.array([[0.9]]))
    p, q = t.lookup([8.0, 32.0, 300.0], [0.0, 10.0, 80.0])
    np.testing.assert_array_equal(p, 25.0)
    np.testing.assert_array_equal(q, 0.9)


def test_bad_tables_are_refused():
    with pytest.raises(ValidationError, match="heights_px: expected finite values strictly increasing"):
        _table(heights_px=np.array([32.0, 16.0, 64.0]))
    with pytest.raises(ValidationError, match=r"psnr_db: expected shape \(3, 3\)"):
        _table(psnr_db=np.zeros((2, 3)))


# ---------------------------------------------------------------- files


def test_save_load_round_trip(tmp_path):
    t = _table()
    path = t.save(tmp_path / "tree.table.npz")
    back = ErrorTable.load(path, mesh_hash=HASH)
    for k in ("asset", "mesh_hash", "representation", "params"):
        assert getattr(back, k) == getattr(t, k)
    for k in ("heights_px", "elevations_deg", "psnr_db", "iou"):
        np.testing.assert_array_equal(getattr(back, k), getattr(t, k))
    assert [p.name for p in tmp_path.iterdir()] == ["tree.table.npz"]  # written atomically: no leftovers


def _rewrite_meta(path, change):
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays.pop("meta")).decode())
    change(meta)
    np.savez(path, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)


def test_another_version_is_refused(tmp_path):
    path = _table().save(tmp_path / "t.npz")
    _rewrite_meta(path, lambda m: m.update(version=99))
    with pytest.raises(FileFormatError, match="version: expected 1, got 99"):
        ErrorTable.load(path)


def test_a_damaged_file_is_refused(tmp_path):
    path = _table().save(tmp_path / "t.npz")
    data = path.read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[: len(data) // 2])
    with pytest.raises(FileFormatError, match="expected a complete morphkit-error-table .npz file, got an"):
        ErrorTable.load(tmp_path / "cut.npz")
    # an array changed behind the checksums
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["psnr_db"] = arrays["psnr_db"] + 1.0
    np.savez(tmp_path / "edited.npz", **arrays)
    with pytest.raises(FileFormatError, match="'psnr_db': expected the checksum recorded in meta"):
        ErrorTable.load(tmp_path / "edited.npz")
    with zipfile.ZipFile(tmp_path / "foreign.npz", "w") as zf:
        zf.writestr("x.npy", b"not an array")
    with pytest.raises(FileFormatError, match="error table file foreign.npz"):
        ErrorTable.load(tmp_path / "foreign.npz")
    with pytest.raises(FileFormatError, match="expected an existing file"):
        ErrorTable.load(tmp_path / "missing.npz")


def test_another_meshs_table_is_refused(tmp_path):
    path = _table().save(tmp_path / "t.npz")
    other = "cd" * 32
    with pytest.raises(FileFormatError, match=f"mesh_hash: expected {other} .*, got {HASH}"):
        ErrorTable.load(path, mesh_hash=other)
    assert ErrorTable.load(path).mesh_hash == HASH  # not asked: read as it is


# ---------------------------------------------------------------- instance views (no GL)

FY = 120.0 / math.tan(math.radians(25.0))  # a 50-degree field of view over 240 rows
SHAPE = (240, 320)


def _camera(eye, target):
    return perspective(math.radians(50.0), SHAPE, look_at(np.asarray(eye, float), np.asarray(target, float)))


def test_instance_views_height_elevation_and_culling():
    asset = FakeAsset("fake", views=8, half_extent=(0.3, 0.4), levels=1)  # quad 0.8 high, pivot at 0.4
    inst = Instances.from_records([("fake", 0.0, 8.0), ("fake", 0.0, -3.0), ("fake", 2.0, 6.0, 0.0, 2.0)])
    scene = BillboardScene({"fake": asset}, inst)
    # the eye at the first instance's mid height (its pivot), looking straight at it along +y from y = 0
    cam = _camera([0.0, 0.0, 0.4], [0.0, 8.0, 0.4])
    h, e, vis = instance_views(scene, cam)
    # straight ahead at d = 8: 2 fy h / d with half height 0.4
    assert h[0] == pytest.approx(2 * FY * 0.4 / 8.0, rel=1e-12)
    assert e[0] == pytest.approx(0.0, abs=1e-12)
    assert vis.tolist() == [True, False, True]  # the second stands behind the camera
    # the doubled third: pivot at 0.8, half height 0.8, depth 6 (the camera looks along +y)
    assert h[2] == pytest.approx(2 * FY * 0.8 / 6.0, rel=1e-12)
    assert e[2] == pytest.approx(-math.degrees(math.atan2(0.4, math.hypot(2.0, 6.0))), rel=1e-12)
    # raised 3 units: the eye 3 above the first pivot, 8 away horizontally
    cam = _camera([0.0, 0.0, 3.4], [0.0, 8.0, 0.4])
    _, e, _ = instance_views(scene, cam)
    assert e[0] == pytest.approx(math.degrees(math.atan2(3.0, 8.0)), rel=1e-12)


def test_prediction_is_the_mean_of_the_drawn_billboards_lookups():
    asset = FakeAsset("tree", views=8, half_extent=(0.3, 0.4), levels=1)
    inst = Instances.from_records([("tree", -1.0, 5.0), ("tree", 1.0, 9.0), ("tree", 0.0, -3.0)])
    scene = BillboardScene({"tree": asset}, inst)
    cam = _camera([0.0, 0.0, 1.5], [0.0, 8.0, 0.4])
    t = _table()
    h, e, vis = instance_views(scene, cam)
    p, q = t.lookup(h[vis], e[vis])
    got = predict_frame_error({"tree": t}, scene, cam)
    assert got == {"psnr": pytest.approx(np.mean(p)), "iou": pytest.approx(np.mean(q)), "n": 2.0}
    assert scene.plan(cam).placements and len(scene.plan(cam).placements) == 2
    away = _camera([0.0, 0.0, 1.5], [0.0, -8.0, 0.4])  # looking away from the two in front
    got = predict_frame_error({"tree": t}, scene, away)
    assert got["n"] == 1.0
    nothing = _camera([0.0, 30.0, 1.5], [0.0, 60.0, 0.4])
    got = predict_frame_error({"tree": t}, scene, nothing)
    assert got["n"] == 0.0 and math.isnan(got["psnr"]) and math.isnan(got["iou"])
    with pytest.raises(ValidationError, match=r"an ErrorTable for every drawn asset \['tree'\]"):
        predict_frame_error({}, scene, cam)


def test_a_cells_camera_makes_the_billboard_its_height_and_elevation():
    asset = FakeAsset("fake", views=8, half_extent=(0.3, 0.4), levels=1)
    scene = BillboardScene({"fake": asset}, Instances.from_records([("fake", 0.0, 0.0)]))
    for hp, el, az in ((16.0, 0.0, 18.0), (100.0, 35.0, 124.0), (256.0, 80.0, 276.0)):
        cam = table_camera(scene.pivots[0], 0.4, hp, el, az, frame_shape(hp, 0.75), FY)
        cam = table_camera(scene.pivots[0], 0.4, hp, el, az, fit_frame(scene, cam), FY)
        (pl,) = scene.plan(cam).placements
        assert pl.height_px == pytest.approx(hp, rel=1e-9)
        assert pl.elevation_deg == pytest.approx(el, abs=1e-9)
        r0, r1, c0, c1 = pl.roi
        assert r0 > 0 and c0 > 0 and r1 < cam.shape[0] and c1 < cam.shape[1]  # the whole box in the frame


def test_a_mode_measured_against_itself_is_exact():
    asset = FakeAsset("fake", views=8, levels=1, solid=True)
    t = measure_error_table(asset, None, None, ClassicMode(), ClassicMode(), heights_px=(16.0, 40.0),
                            elevations_deg=(0.0, 30.0), azimuths_deg=(10.0,), mesh_hash=HASH,
                            representation="classic")
    np.testing.assert_array_equal(t.psnr_db, PSNR_CAP_DB)
    np.testing.assert_array_equal(t.iou, 1.0)
    assert t.params["azimuths_deg"] == [10.0] and t.representation == "classic"
    with pytest.raises(ValidationError, match="mesh_hash: expected the asset's mesh hash"):
        measure_error_table(asset, None, None, ClassicMode(), ClassicMode())


# ---------------------------------------------------------------- against the real mesh (GL)


@pytest.fixture(scope="module")
def tree_tables(renderer):
    """A tree ring asset (8 views, 64 px) and its classic and morph tables, for the 50-degree
    cameras of :func:`_camera`."""
    from morphkit.billboard import MorphCache, MorphMode, bake_asset
    from morphkit.meshes import normalize, sample_mesh

    mesh = normalize(sample_mesh("tree"))
    asset = bake_asset(mesh, renderer, name="tree", views=8, size=64, levels=2)
    items = asset.items(mesh)
    modes = {"classic": ClassicMode(), "morph": MorphMode(MorphCache())}
    tables = {nm: measure_error_table(asset, items, renderer, m, None, heights_px=(16.0, 32.0, 64.0, 128.0),
                                      focal_px=FY, representation=f"ring-{nm}-64", params={"views": 8})
              for nm, m in modes.items()}
    return asset, items, modes, tables


@pytest.mark.gl
def test_the_morph_beats_the_card_where_its_ring_was_baked(tree_tables):
    asset, _, _, tables = tree_tables
    classic, morph = tables["classic"], tables["morph"]
    assert classic.mesh_hash == asset.mesh_hash and classic.elevations_deg.tolist() == [0, 10, 20, 40, 60, 80]
    k = classic.elevations_deg.tolist().index(asset.cameras.elevation_deg)
    # at the bake elevation the morph is the better image at every size, in colour and in outline
    assert np.all(morph.psnr_db[:, k] > classic.psnr_db[:, k] + 1.5)
    assert np.all(morph.iou[:, k] > classic.iou[:, k] + 0.05)
    # and it is the morph's best elevation: a ring of one elevation has no views above or below
    assert np.all(morph.psnr_db[:, k] > morph.psnr_db[:, k - 1] + 0.5)
    assert np.all(morph.psnr_db[:, k] > morph.psnr_db[:, k + 1] + 0.5)
    # above it, both get worse the higher the eye
    for t in (classic, morph):
        assert np.all(np.diff(t.psnr_db[:, k:], axis=1) < 0)


def _whole(frame) -> bool:
    h, w = frame.rgb.shape[:2]
    for pl in frame.placements:
        c = pl.H_screen_unit @ np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float).T
        xy = c[:2] / c[2]
        if xy.min() < 0 or xy[0].max() > w or xy[1].max() > h:
            return False
    return True


@pytest.mark.gl
def test_prediction_against_measurement(tree_tables, renderer):
    """Seven trees 4 to 13 units away (23 to 72 px high), random yaws, seen from three eye heights
    (elevations 5 to 32 degrees, between the tables' bins): the predicted mean per-billboard error
    against compare_modes'. The morph keeps within the planner's budget; the card's IoU gap is over
    it with tables of three azimuths (its IoU turns with the azimuth; twelve bring it under)."""
    from morphkit.billboard import BAKE_AMBIENT, MeshMode, bake_lights
    from morphkit.billboard.compare import compare_modes

    asset, items, modes, tables = tree_tables
    truth = MeshMode(renderer, {"tree": items}, bake_lights(), BAKE_AMBIENT)
    ang = np.radians([-24, -15, -7, 0, 8, 16, 25])
    dist = np.array([4.0, 6.5, 9.0, 5.0, 11.0, 7.5, 13.0])
    xy = np.stack([dist * np.sin(ang), dist * np.cos(ang) - 2.0], 1)
    yaw = np.random.default_rng(1).uniform(0, 360, len(xy))
    scene = BillboardScene({"tree": asset}, Instances(("tree",), np.zeros(len(xy), np.int64), xy, yaw,
                                                      np.ones(len(xy))))
    gaps: dict[str, list[tuple[float, float]]] = {nm: [] for nm in modes}
    for eye_z in (1.6, 2.2, 3.0):  # every billboard whole in the frame (a cut box is measured in part)
        cam = _camera([0.0, -2.0, eye_z], [0.0, 7.0, 0.0])
        c = compare_modes(scene, cam, modes, truth)
        for nm in modes:
            assert _whole(c.frames[nm])
            pred, meas = predict_frame_error({"tree": tables[nm]}, scene, cam), c.errors[nm]
            assert pred["n"] == meas["n"] == len(xy)
            gaps[nm].append((abs(pred["psnr"] - meas["psnr"]), abs(pred["iou"] - meas["iou"])))
    morph, card = np.median(gaps["morph"], axis=0), np.median(gaps["classic"], axis=0)
    assert morph[0] <= tol.PLAN_GAP_DB and morph[1] <= tol.PLAN_GAP_IOU
    assert card[0] <= tol.PLAN_GAP_DB and card[1] <= tol.PLAN_CARD_GAP_IOU


@pytest.mark.gl
def test_the_relit_dome_morph_holds_over_elevation_where_the_card_falls(renderer):
    from morphkit.billboard import BAKE_AMBIENT, bake_lights
    from morphkit.billboard.domeasset import bake_dome
    from morphkit.imaging.shading import Lighting
    from morphkit.meshes import normalize, sample_mesh
    from morphkit.sunlit.litmodes import ClassicSurface, LitMode, MorphSurface

    mesh = normalize(sample_mesh("tree"))
    dome = bake_dome(mesh, renderer, name="tree", size=32, levels=2)
    items = dome.items(mesh)
    base = Lighting(BAKE_AMBIENT, tuple(bake_lights()))
    tables = {nm: measure_error_table(dome, items, renderer, LitMode(choice, base), None, lighting=base,
                                      heights_px=(16.0, 32.0, 64.0), representation=f"dome-{nm}-32")
              for nm, choice in (("morph", MorphSurface()), ("card", ClassicSurface()))}
    morph, card = tables["morph"], tables["card"]
    assert morph.params["facing"] == "ViewpointFacing"
    assert morph.elevations_deg.tolist() == [0, 20, 40, 60, 80]
    # the card is one view (the front, at the horizon): it gets worse with every step up, colour and outline
    assert np.all(np.diff(card.psnr_db, axis=1) < 0) and np.all(np.diff(card.iou, axis=1) < 0)
    # the dome's morph has views over the hemisphere: well above the card from 20 degrees up
    assert np.all(morph.psnr_db[:, 1:] > card.psnr_db[:, 1:] + 2.0)
    assert np.all(morph.iou[:, 1:] > card.iou[:, 1:] + 0.05)


def test_a_cells_frame_never_outgrows_the_largest_a_table_draws():
    # an upright ring quad close under a high eye flares at its top: its frame is capped, the quad cut
    asset = FakeAsset("fake", views=8, levels=1)
    scene = BillboardScene({"fake": asset}, Instances.from_records([("fake", 0.0, 0.0)]))
    hp, el, focal = tol.PLAN_MAX_TABLE_HEIGHT_PX, 80.0, 500.0  # 1024 px, the focal of a 640 x 480 frame
    cam = table_camera(scene.pivots[0], 0.4, hp, el, 30.0, frame_shape(hp, 0.75), focal)
    side = fit_frame(scene, cam)
    assert side == (tol.PLAN_MAX_TABLE_FRAME_PX, tol.PLAN_MAX_TABLE_FRAME_PX)
    (pl,) = scene.plan(table_camera(scene.pivots[0], 0.4, hp, el, 30.0, side, focal)).placements
    assert pl.height_px == pytest.approx(hp, rel=1e-9)  # drawn at its cell's height, cut by the frame
