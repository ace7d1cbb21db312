"""Billboard scenes with a test-double asset (no GL): cache, compositor, plan, modes, hard cases."""

from __future__ import annotations

import numpy as np
import pytest
from billboard_fakes import FakeAsset, ellipse_view

from morphkit.billboard import (
    Backdrop,
    BillboardScene,
    ClassicMode,
    CrossfadeMode,
    Fog,
    Ground,
    Instances,
    MorphCache,
    MorphMode,
    NearestMode,
    ScreenFacing,
    Sky,
    morph_key,
    place_random,
    quantise_s,
)
from morphkit.billboard.frames.compositor import draw, finish, new_depth, new_layer
from morphkit.billboard.frames.frametypes import Placement
from morphkit.billboard.frames.frustum import unit_from_image
from morphkit.billboard.protocols import BillboardSource, ViewPairing
from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.composite import over_warped

FLAT = Backdrop(Ground(cell=None), Sky((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))


def _cam(eye, target, shape=(48, 64), yfov=50.0, znear=0.1):
    return perspective(np.radians(yfov), shape, look_at(np.asarray(eye, float), np.asarray(target, float)),
                       znear=znear, zfar=200.0)


def _scene(records, asset=None, **kw):
    asset = asset or FakeAsset("fake")
    return BillboardScene({asset.name: asset}, Instances.from_records(records), **kw), asset


def test_fake_asset_implements_the_protocols():
    a = FakeAsset()
    assert isinstance(a, BillboardSource) and isinstance(a.ring, ViewPairing)
    assert not isinstance(object(), BillboardSource)


# --------------------------------------------------------------------- cache


def test_lru_eviction_order_and_counts():
    c = MorphCache(capacity=3, max_bytes=None)
    img = {k: np.full((2, 2, 4), i, np.float32) for i, k in enumerate("abcde")}
    for k in "abc":
        c.get(k, lambda k=k: img[k])
    assert c.get("a", lambda: pytest.fail("a is cached")) is img["a"]  # hit, a becomes most recent
    c.get("d", lambda: img["d"])  # evicts the least recently used: b
    assert c.keys() == ["c", "a", "d"] and "b" not in c
    assert (c.counts.hits, c.counts.misses, c.counts.evictions) == (1, 4, 1)
    assert c.counts.hit_rate == pytest.approx(0.2)
    snap = c.counts
    c.get("c", lambda: img["c"])
    c.get("b", lambda: img["b"])  # miss: evicts a (c was just used)
    assert c.keys() == ["d", "c", "b"]
    d = c.counts - snap
    assert (d.hits, d.misses, d.evictions) == (1, 1, 1)
    assert c.nbytes == 3 * img["a"].nbytes
    with pytest.raises(ValueError):
        c.get("c", lambda: img["c"])[0, 0, 0] = 5.0  # cached images are read-only


def test_cache_byte_bound():
    c = MorphCache(capacity=100, max_bytes=2 * 64)  # two 2x2x4 float32 images
    for k in range(5):
        c.get(k, lambda: np.zeros((2, 2, 4), np.float32))
    assert len(c) == 2 and c.nbytes == 128 and c.keys() == [3, 4]
    big = c.get("big", lambda: np.zeros((8, 8, 4), np.float32))  # larger than the bound: not kept
    assert big.shape == (8, 8, 4) and "big" not in c and len(c) == 2
    with pytest.raises(ValidationError, match="cache capacity: expected an integer >= 1"):
        MorphCache(capacity=0)


def test_quantise_s_and_key():
    assert quantise_s(0.26, 60.0, 6.0) == 0.3  # 10 steps
    assert quantise_s(0.24, 60.0, 0.0) == 0.24
    assert quantise_s(0.04, 60.0, 6.0) == 0.0 and quantise_s(0.97, 60.0, 6.0) == 1.0
    assert quantise_s(0.7, 45.0, 90.0) == 1.0  # at least one step
    assert morph_key("tree", 1, 2, 0.25, 1) == ("tree", 1, 2, 0.25, 1)


# ----------------------------------------------------------------- compositor


def test_over_warped_matches_a_hand_computed_pixel():
    """Premultiplied (0.2, 0.1, 0.05, a=0.5) over an opaque (0.2, 0.6, 1.0):
    (0.2, 0.1, 0.05, 0.5) + 0.5 (0.2, 0.6, 1.0, 1) = (0.3, 0.4, 0.55, 1)."""
    out = np.zeros((6, 8, 4), np.float32)
    out[:] = (0.2, 0.6, 1.0, 1.0)
    src = np.zeros((4, 4, 4), np.float32)
    src[:] = (0.2, 0.1, 0.05, 0.5)
    H = np.array([[1.0, 0, 3], [0, 1.0, 1], [0, 0, 1]])  # src pixel (u, v) -> out (u + 3, v + 1)
    over_warped(out, src, H, (1, 5, 3, 7))
    np.testing.assert_allclose(out[2, 4], [0.3, 0.4, 0.55, 1.0], atol=1e-6)
    np.testing.assert_allclose(out[0, 0], [0.2, 0.6, 1.0, 1.0])  # outside the ROI: untouched
    # fog: colour towards white by 0.5, alpha kept: 0.5 (0.2, 0.1, 0.05) + 0.5 * 0.5 * 1 = (0.35, 0.3, 0.275)
    out[:] = (0.2, 0.6, 1.0, 1.0)
    over_warped(out, src, H, (1, 5, 3, 7), fade=0.5, fade_color=(1.0, 1.0, 1.0))
    np.testing.assert_allclose(out[2, 4], [0.45, 0.6, 0.775, 1.0], atol=1e-6)
    # a mask of 0 leaves the pixel alone
    out[:] = (0.2, 0.6, 1.0, 1.0)
    mask = np.ones((4, 4), np.float32)
    mask[1, 1] = 0.0
    over_warped(out, src, H, (1, 5, 3, 7), mask=mask)
    np.testing.assert_allclose(out[2, 4], [0.2, 0.6, 1.0, 1.0])
    # finish: the layer over an opaque backdrop, to uint8
    layer = new_layer((1, 2))
    layer[0, 0] = (0.2, 0.1, 0.05, 0.5)
    rgb = finish(layer, np.full((1, 2, 3), (0.32, 0.6, 1.0), np.float32))
    assert rgb.tolist() == [[[92, 102, 140], [82, 153, 255]]]  # 255 * (0.36, 0.4, 0.55), 255 * 0.32 rounded


def _placement(shape, offset, depth):
    """A placement drawing an image of ``shape`` at pixel ``offset = (x, y)``, unscaled."""
    T = np.array([[1.0, 0, offset[0]], [0, 1.0, offset[1]], [0, 0, 1]])
    H = T @ np.linalg.inv(unit_from_image(shape))
    roi = (offset[1], offset[1] + shape[0], offset[0], offset[0] + shape[1])
    return Placement(0, "fake", 0.0, 0.0, False, depth, depth, float(shape[0]), 0, H, roi, None, 0.0)


def test_draw_by_depth_goes_over_in_front_and_under_behind():
    """Premultiplied red (0.5, 0, 0, a=0.5) at depth 5, then blue (0, 0, 0.8, a=0.8): where the
    blue is at depth 3 it goes over, (0, 0, 0.8, 0.8) + 0.2 red = (0.1, 0, 0.8, 0.9), and takes
    the depth buffer; where it is at depth 8 it goes under, red + 0.5 blue = (0.5, 0, 0.4, 0.9),
    and the buffer keeps 5."""
    layer, zbuf = new_layer((4, 6)), new_depth((4, 6))
    red = np.zeros((2, 4, 4), np.float32)
    red[:] = (0.5, 0.0, 0.0, 0.5)
    draw(layer, _placement((2, 4), (1, 1), 5.0), red, zbuf=zbuf, depth=np.full((2, 4), 5.0, np.float32))
    blue = np.zeros((2, 4, 4), np.float32)
    blue[:] = (0.0, 0.0, 0.8, 0.8)
    depth = np.array([[3.0, 3.0, 8.0, 8.0]] * 2, np.float32)
    draw(layer, _placement((2, 4), (1, 1), 4.0), blue, zbuf=zbuf, depth=depth)
    np.testing.assert_allclose(layer[1:3, 1:3], np.broadcast_to([0.1, 0.0, 0.8, 0.9], (2, 2, 4)), atol=1e-6)
    np.testing.assert_allclose(layer[1:3, 3:5], np.broadcast_to([0.5, 0.0, 0.4, 0.9], (2, 2, 4)), atol=1e-6)
    np.testing.assert_array_equal(zbuf[1:3, 1:5], depth * [1, 1, 0, 0] + 5.0 * np.array([0, 0, 1, 1]))
    assert np.isinf(zbuf[0]).all() and (layer[0] == 0).all()  # outside the boxes: untouched


def test_draw_by_depth_of_flat_quads_back_to_front_is_the_plain_over():
    """Images without depth lie at their pivots' depth: drawn back to front, the depth test
    never sends one under, and the layer is bit for bit the plain "over" of each."""
    rng = np.random.default_rng(4)
    plain, layer, zbuf = new_layer((12, 12)), new_layer((12, 12)), new_depth((12, 12))
    for k, z in enumerate([9.0, 7.0, 7.0, 2.0]):  # back to front, a tie among them
        img = rng.uniform(0, 1, (5, 5, 4)).astype(np.float32)
        img[..., :3] *= img[..., 3:]
        pl = _placement((5, 5), (k * 2, k), z)
        draw(plain, pl, img)
        draw(layer, pl, img, zbuf=zbuf)
    np.testing.assert_array_equal(layer, plain)


def test_quad_footprint_is_the_projected_rectangle():
    """An opaque asset seen straight on from distance 4: its 0.6 x 0.8 quad covers
    2 hw f / 4 by 2 hh f / 4 pixels around the pivot's projection."""
    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1)
    scene, _ = _scene([("solid", 0, 0)], asset, backdrop=FLAT)
    cam = perspective(np.radians(40), (120, 160), look_at([0, -4, 0.4], [0, 0, 0.4]), znear=0.1)
    f = scene.render(cam, MorphMode())
    a = f.layer[..., 3]
    fx = cam.fx
    half_w, half_h = 0.3 * fx / 4, 0.4 * fx / 4  # pixels
    x, y = cam.pixel_grid()
    inner = (np.abs(x - cam.cx) < half_w - 1) & (np.abs(y - cam.cy) < half_h - 1)
    outer = (np.abs(x - cam.cx) > half_w + 1) | (np.abs(y - cam.cy) > half_h + 1)
    assert np.all(a[inner] > 0.999) and np.all(a[outer] == 0)
    assert a.sum() == pytest.approx(4 * half_w * half_h, rel=0.03)
    assert f.stats.n_drawn == 1 and f.placements[0].roi[0] <= cam.cy - half_h


# -------------------------------------------------------------- hard cases


def test_zero_billboards_give_the_backdrop():
    scene = BillboardScene({"fake": FakeAsset()}, Instances.from_records([]), backdrop=FLAT)
    cam = _cam([0, -5, 1.6], [0, 0, 0.5])
    f = scene.render(cam, MorphMode())
    assert f.stats.n_instances == 0 and f.stats.n_drawn == 0 and not f.layer.any()
    np.testing.assert_array_equal(f.rgb, finish(new_layer(cam.shape), scene.backdrop.draw(cam)))
    ground = scene.backdrop.draw(cam)[-1, 0]
    np.testing.assert_allclose(ground, Ground().color_a, atol=1e-6)  # flat ground at the bottom


def test_all_behind_the_camera():
    recs = [("fake", x, -10.0) for x in np.linspace(-3, 3, 7)]
    scene, asset = _scene(recs, backdrop=FLAT)
    cam = _cam([0, 0, 1.0], [0, 10, 1.0])  # looking +y; every billboard at y = -10
    f = scene.render(cam, MorphMode())
    assert f.stats.n_frustum_culled == 7 and f.stats.n_drawn == 0 and not f.layer.any()
    assert asset.calls["morph"] == 0


def test_billboard_cut_by_the_near_plane_is_clipped_not_inverted():
    """A billboard beside the camera whose quad runs from behind the camera to in front
    of it: coverage must equal a per-pixel ray cast against the quad's front part
    (hits at camera depth >= znear), never the part behind projected through the centre."""
    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1, half_extent=(0.6, 0.4))
    scene, _ = _scene([("solid", 0.5, 0.2)], asset, backdrop=FLAT)
    cam = perspective(np.radians(90), (60, 80), look_at([0, 0, 0.4], [0, 10, 0.4]), znear=0.1, zfar=50)
    plan = scene.plan(cam)
    assert plan.n_near_clipped == 1 and len(plan.placements) == 1
    f = scene.render(cam, MorphMode())
    # ray cast: quad centre c, axes from the axial facing, half sizes 0.6 x 0.4
    c = scene.pivots[0]
    n = np.r_[cam.position[:2] - c[:2], 0.0]
    n /= np.linalg.norm(n)
    right, up = np.array([-n[1], n[0], 0.0]), np.array([0.0, 0.0, 1.0])
    o, d = cam.rays()
    t = ((c - o) @ n) / (d @ n)
    p = o + t[..., None] * d
    u, v = (p - c) @ right, (p - c) @ up
    zc = (p - cam.position) @ cam.axis
    hit = (t > 0) & (np.abs(u) < 0.6) & (np.abs(v) < 0.4) & (zc >= cam.znear)
    a = f.layer[..., 3]
    # compare away from the quad's outline (bilinear edges, 1/16-px polygon rounding)
    inner = (t > 0) & (np.abs(u) < 0.6 - 0.03) & (np.abs(v) < 0.4 - 0.03) & (zc >= cam.znear + 0.02)
    assert inner.sum() > 200 and np.all(a[inner] > 0.99)
    import cv2

    near = cv2.dilate(hit.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    assert np.all(a[~near] == 0)  # nothing drawn where the ray cast sees no front part
    # the part behind the camera would project to the left of the image: nothing there
    assert not a[:, : a.shape[1] // 3].any()


def test_camera_directly_above_a_billboard():
    """Axial facing: the quad is seen edge-on from straight above (skipped as too small,
    no NaN); the screen-aligned quad is seen face-on and drawn. Both report the fallback."""
    scene, asset = _scene([("fake", 1.0, 2.0, 35.0), ("fake", 3.0, 2.0)], backdrop=FLAT)
    cam = perspective(np.radians(60), (48, 64), look_at([1.0, 2.0, 5.0], [1.0, 2.0, 0.0]), znear=0.1)
    f = scene.render(cam, MorphMode())
    assert f.stats.n_above == 1
    assert 0 not in [p.index for p in f.placements] and np.all(np.isfinite(f.layer))
    screen = BillboardScene(scene.assets, scene.instances, backdrop=FLAT, facing=ScreenFacing())
    g = screen.render(cam, MorphMode())
    above = [p for p in g.placements if p.index == 0]
    assert g.stats.n_above == 1 and len(above) == 1
    assert above[0].above and above[0].azimuth_deg == 0.0  # the front view: s = 0.5 on the +-30 arc
    assert g.layer[24, 32, 3] > 0.99  # drawn face-on under the camera
    assert asset.calls["morph"] == 1


def test_ten_thousand_instances_memory_bounded_by_the_cache():
    asset = FakeAsset("fake", views=8, size=(32, 24), levels=2)
    inst = place_random(["fake"], 10_000, np.random.default_rng(1), half_size=60.0)
    scene = BillboardScene({"fake": asset}, inst, backdrop=FLAT, min_pixels=1.0)
    cache = MorphCache(capacity=16, max_bytes=None)
    mode = MorphMode(cache, quantum_deg=0.5)
    cams = [_cam([0, -70 + 5 * k, 3.0], [0, 0, 0.5], shape=(60, 80)) for k in range(2)]
    for cam in cams:
        f = scene.render(cam, mode)
        assert len(cache) <= 16 and f.stats.cache_entries <= 16
        assert cache.nbytes <= 16 * 32 * 24 * 4 * 4
        assert f.stats.n_drawn > 100 and f.stats.misses > 16 and f.stats.evictions > 0
    assert asset.calls["morph"] == cache.counts.misses  # every miss computed once, nothing else


# --------------------------------------------------------------------- modes


def _seen_from(azimuth_deg, yaw=0.0):
    """One instance at the origin and a camera at ``azimuth_deg`` (object frame) 5 units away."""
    a = np.radians(azimuth_deg + yaw)
    return _cam([5 * np.cos(a), 5 * np.sin(a), 0.4], [0, 0, 0.4])


def test_morph_mode_images_and_cache_keys():
    scene, asset = _scene([("fake", 0, 0, 20.0)], backdrop=FLAT)
    mode = MorphMode(MorphCache(capacity=8), quantum_deg=2.0, blend=False)  # 30 steps over the 60 deg arc
    f = scene.render(_seen_from(-10.0, 20.0), mode)
    assert f.placements[0].azimuth_deg == pytest.approx(-10.0)
    assert (f.stats.hits, f.stats.misses) == (0, 1)
    lv = f.placements[0].level
    assert mode.cache.keys() == [("fake", 0, 1, 10 / 30, lv)]  # s = 20/60 = 1/3 exactly a step
    g = scene.render(_seen_from(-10.4, 20.0), mode)  # same quantum: a hit
    assert (g.stats.hits, g.stats.misses) == (1, 0)
    np.testing.assert_array_equal(f.layer, scene.render(_seen_from(-10.0, 20.0), mode).layer)
    # at an end of the arc the reference itself is drawn, without the cache
    h = scene.render(_seen_from(30.0, 20.0), mode)
    assert (h.stats.hits, h.stats.misses) == (0, 0) and asset.calls["morph"] == 1


def test_morph_mode_blends_the_two_grid_steps_around_s():
    """Seen from -10.5 deg on a 2-degree grid over the +-30 arc: s = 19.5/60 = 9.75/30 lies
    3/4 of the way from step 9/30 (-12 deg) to 10/30 (-10 deg): 0.25 m(9/30) + 0.75 m(10/30)."""
    scene, asset = _scene([("fake", 0, 0)], backdrop=FLAT)
    mode = MorphMode(MorphCache(capacity=8), quantum_deg=2.0)
    pl = scene.plan(_seen_from(-10.5)).placements[0]
    img, _ = mode.image(asset, pl)
    shape = asset.shape(pl.level)
    expect = 0.25 * ellipse_view(-30 + 18.0, shape) + 0.75 * ellipse_view(-30 + 20.0, shape)
    np.testing.assert_allclose(img, expect, atol=1e-6)
    assert (mode.cache.counts.hits, mode.cache.counts.misses) == (0, 2)
    mode.image(asset, scene.plan(_seen_from(-11.5)).placements[0])  # same two steps: two hits
    assert (mode.cache.counts.hits, mode.cache.counts.misses) == (2, 2)
    on_step, _ = mode.image(asset, scene.plan(_seen_from(-10.0)).placements[0])  # on a step: one image
    np.testing.assert_allclose(on_step, ellipse_view(-10.0, shape), atol=1e-6)
    assert mode.cache.counts.hits == 3


def test_two_views_outside_the_arc_are_clamped_and_reported():
    scene, asset = _scene([("fake", 0, 0)], backdrop=FLAT)
    mode = MorphMode()
    f = scene.render(_seen_from(90.0), mode)
    assert f.stats.max_outside_deg == pytest.approx(60.0)
    ref = asset.reference(1, f.placements[0].level)
    img, out = mode.image(asset, f.placements[0])
    np.testing.assert_array_equal(img, ref)
    assert out == pytest.approx(60.0)
    assert scene.render(_seen_from(10.0), mode).stats.max_outside_deg == 0.0


def test_classic_nearest_crossfade_images():
    scene, asset = _scene([("fake", 0, 0)], backdrop=FLAT)
    pl = scene.plan(_seen_from(-20.0)).placements[0]
    shape = asset.shape(pl.level)
    classic = ClassicMode()
    img, out = classic.image(asset, pl)
    np.testing.assert_array_equal(img, ellipse_view(0.0, shape))  # the front view whatever the azimuth
    assert out == 0.0
    np.testing.assert_array_equal(classic.image(asset, scene.plan(_seen_from(25.0)).placements[0])[0], img)
    near, _ = NearestMode().image(asset, pl)  # -20 is nearer the -30 reference
    np.testing.assert_array_equal(near, ellipse_view(-30.0, shape))
    near2, _ = NearestMode().image(asset, scene.plan(_seen_from(5.0)).placements[0])
    np.testing.assert_array_equal(near2, ellipse_view(30.0, shape))
    cf = CrossfadeMode(quantum_deg=0.0)
    blend, _ = cf.image(asset, pl)
    s = 10.0 / 60.0
    np.testing.assert_allclose(blend, (1 - s) * ellipse_view(-30.0, shape) + s * ellipse_view(30.0, shape),
                               atol=1e-6)
    assert asset.calls["crossfade"] == 1 and len(cf.cache) == 1


def test_fog_fades_far_billboards():
    scene, _ = _scene([("fake", 0, 0)], backdrop=Backdrop(Ground(cell=None), fog=Fog((1, 1, 1), 0.2)))
    near = scene.plan(_cam([0, -2, 0.4], [0, 0, 0.4])).placements[0]
    far = scene.plan(_cam([0, -12, 0.4], [0, 0, 0.4])).placements[0]
    assert near.fog == pytest.approx(1 - np.exp(-0.4)) and far.fog == pytest.approx(1 - np.exp(-2.4))


def test_fog_blends_a_meshes_layer_by_each_pixels_distance_along_its_ray():
    cam = _cam([0, -2, 0.4], [0, 0, 0.4])
    fog = Fog((1.0, 1.0, 1.0), 0.2)
    layer = np.zeros(cam.shape + (4,), np.float32)
    layer[:, :, 3] = 1.0  # opaque black everywhere, at camera depth 3
    layer[0, 0, 3] = 0.0  # nothing drawn here
    depth = np.full(cam.shape, 3.0)
    depth[0, 0] = np.inf
    fog.blend_layer(layer, depth, cam)
    # distance = Z times the ray's length per unit Z: sqrt(((u - cx)/fx)^2 + ((v - cy)/fy)^2 + 1)
    v, u = 10, 50
    d = 3.0 * np.sqrt(((u - cam.cx) / cam.fx) ** 2 + ((v - cam.cy) / cam.fy) ** 2 + 1.0)
    np.testing.assert_allclose(layer[v, u, :3], 1.0 - np.exp(-0.2 * d), rtol=1e-6)
    assert layer[0, 0, :3].tolist() == [0.0, 0.0, 0.0] and layer[v, u, 3] == 1.0


def test_scene_validation():
    with pytest.raises(ValidationError, match="assets: expected one for every instance's asset"):
        BillboardScene({"fake": FakeAsset()}, Instances.from_records([("tree", 0, 0)]))
    with pytest.raises(ValidationError, match="asset 'fake': expected a billboard asset .*SurfaceSource"):
        BillboardScene({"fake": object()}, Instances.from_records([("fake", 0, 0)]))
    with pytest.raises(ValidationError, match="facing: expected a Facing"):
        BillboardScene({"fake": FakeAsset()}, Instances.from_records([("fake", 0, 0)]), facing="axial")
    with pytest.raises(ValidationError, match="quantum_deg: expected a finite number >= 0"):
        MorphMode(quantum_deg=-1)
