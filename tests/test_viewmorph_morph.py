"""ViewMorpher: end points, identity, layouts, sizes, blending, fall-backs and refusals.

Numpy-only: the images are random textures (the s = 0/1 and identity
expectations hold whatever the pixels are), the correspondences come from
synthetic cameras. The GL test at the end checks the morph against a render.
"""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.camera import look_at, perspective
from morphkit.errors import DegenerateViewError, GeometryError, ValidationError
from morphkit.viewmorph import Correspondences, ViewMorpher, crossfade, from_geometry, nearest
from morphkit.viewmorph.mesh import min_area_over_s
from morphkit.viewmorph.postwarp import PostWarpPoints
from morphkit.viewmorph.rectify import apply_h

TARGET = np.array([0.0, 0.0, 0.25])


def circle_cam(angle_deg, *, size=(96, 96), r=2.6, h=1.0):
    a = np.radians(angle_deg)
    eye = np.array([r * np.cos(a), r * np.sin(a), h])
    return perspective(np.radians(30), size, look_at(eye, TARGET))


def texture(rng, shape, channels):
    """A smooth random texture (so bilinear resampling differences stay small)."""
    import cv2

    h, w = shape
    small = rng.uniform(0, 255, (h // 6 + 2, w // 6 + 2, max(channels, 1)))
    img = cv2.resize(small, (w, h), interpolation=cv2.INTER_CUBIC)
    img = np.clip(img, 0, 255).astype(np.uint8)
    if channels == 1:
        return img if img.ndim == 2 else img[..., 0]
    if channels == 4:
        img[..., 3] = 255
    return img


def setup(rng, base=30.0, channels=4, size0=(96, 96), size1=(96, 96), n=150):
    c0, c1 = circle_cam(60 - base / 2, size=size0), circle_cam(60 + base / 2, size=size1)
    pts = rng.uniform(-0.35, 0.35, (n, 3)) + TARGET
    corr = from_geometry(pts, c0, c1, max_points=n)
    return c0, c1, corr, texture(rng, size0, channels), texture(rng, size1, channels)


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_s0_and_s1_reproduce_the_inputs(rng, channels):
    _, _, corr, i0, i1 = setup(rng, channels=channels)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    assert vm.mode == "viewmorph"
    for s, ref in ((0.0, i0), (1.0, i1)):
        out = vm.morph(s)
        assert out.shape == ref.shape and out.dtype == ref.dtype
        diff = np.abs(out.astype(int) - ref.astype(int))
        # the mesh maps each pixel centre onto itself up to float32 rounding (~1e-4 px):
        # bilinear sampling at 1/32-px steps then returns the pixel itself
        assert diff.max() <= 1, (s, diff.max())
        assert np.mean(diff > 0) < 0.01


def test_identical_images_give_the_input_at_every_s(rng):
    img = texture(rng, (80, 100), 3)
    p = rng.uniform(0, 99, (40, 2)) * [1.0, 0.8]
    vm = ViewMorpher.from_estimate(img, img.copy(), (p, p.copy()))
    assert vm.mode == "homography"
    for s in (0.0, 0.3, 0.5, 1.0):
        assert np.abs(vm.morph(s).astype(int) - img.astype(int)).max() <= 1


def test_rectified_vertices_interpolate_linearly(rng):
    _, _, corr, i0, i1 = setup(rng)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    r0 = apply_h(vm.H_rect_0, vm.correspondences.pts0)
    r1 = apply_h(vm.H_rect_1, vm.correspondences.pts1)
    assert np.abs(r0[:, 1] - r1[:, 1]).max() < 1e-4  # F from the 8-point fit: ~1e-6 px
    q = vm.vertices(0.3)[vm.is_correspondence]
    assert np.allclose(q, 0.7 * r0 + 0.3 * r1)


def test_post_warp_to_a_camera_puts_points_where_that_camera_sees_them(rng):
    c0, c1, corr, i0, i1 = setup(rng, base=20)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    mid = circle_cam(60, size=(96, 96))
    H_out_rect, shape = vm.post_homography(0.5, mid)
    assert shape == (96, 96)
    got = apply_h(H_out_rect, vm.vertices(0.5)[vm.is_correspondence])
    want, _ = mid.project(vm.correspondences.points3d)
    # the morph's camera sits on the chord between the two centres, the target on the
    # circle: the residual is that parallax, < 1 px at 20 degrees and this size
    assert np.sqrt(np.mean(np.sum((got - want) ** 2, axis=1))) < 1.0
    H_out_rect_4, _ = vm.post_homography(0.5, PostWarpPoints(np.arange(4), want[:4]))
    assert np.abs(apply_h(H_out_rect_4, vm.vertices(0.5)[vm.is_correspondence][:4]) - want[:4]).max() < 1e-4


def test_direct_and_rectified_paths_agree(rng):
    _, _, corr, i0, i1 = setup(rng, base=20)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    a = vm.morph(0.5).astype(float)
    b = vm.morph(0.5, path="rectified").astype(float)
    both = (a[..., 3] > 250) & (b[..., 3] > 250)
    # the rectified path resamples three times (blur) and interpolates affinely in the
    # rectified frame rather than in the output: a few grey levels on a smooth texture
    assert both.mean() > 0.8
    assert np.mean(np.abs(a - b)[both][:, :3]) < 6.0


def test_images_of_different_sizes(rng):
    _, _, corr, i0, i1 = setup(rng, size0=(96, 96), size1=(80, 120))
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    assert vm.morph(0.0).shape[:2] == (96, 96)
    assert vm.morph(1.0).shape[:2] == (80, 120)
    assert vm.morph(0.5).shape[:2] == (88, 108)
    assert vm.morph(0.5, out_shape=(50, 60)).shape[:2] == (50, 60)


def test_mixed_layouts_are_promoted(rng):
    _, _, corr, i0, i1 = setup(rng)
    vm = ViewMorpher.from_estimate(i0[..., 0], i1[..., :3], corr)
    out = vm.morph(0.5)
    assert out.shape == (96, 96, 3)
    vm = ViewMorpher.from_estimate(i0[..., :3], i1, corr)
    assert vm.morph(0.5).shape == (96, 96, 4)
    with pytest.raises(ValidationError, match="dtype"):
        ViewMorpher.from_estimate(i0, i1.astype(np.float32) / 255, corr)


def test_float_images(rng):
    _, _, corr, i0, i1 = setup(rng, channels=3)
    f0, f1 = i0.astype(np.float32) / 255, i1.astype(np.float32) / 255
    out = ViewMorpher.from_estimate(f0, f1, corr).morph(0.0)
    assert out.dtype == np.float32 and np.abs(out - f0).max() < 1e-2


def test_s_outside_unit_interval_refused(rng):
    _, _, corr, i0, i1 = setup(rng)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    for s in (-0.1, 1.5, np.nan):
        with pytest.raises(ValidationError, match=r"\[0, 1\]"):
            vm.morph(s)
    with pytest.raises(ValidationError, match=r"\[0, 1\]"):
        crossfade(i0, i1, 2.0)


def test_fewer_than_8_pairs_and_bad_points_refused(rng):
    _, _, corr, i0, i1 = setup(rng)
    with pytest.raises(ValidationError, match="at least 8"):
        ViewMorpher.from_estimate(i0, i1, (corr.pts0[:7], corr.pts1[:7]))
    dup = Correspondences(np.repeat(corr.pts0[:4], 3, axis=0), np.repeat(corr.pts1[:4], 3, axis=0))
    with pytest.raises(ValidationError, match="at least 8 distinct"):
        ViewMorpher.from_estimate(i0, i1, dup)
    p = corr.pts0.copy()
    p[0] = np.inf
    with pytest.raises(ValidationError, match="finite"):
        ViewMorpher.from_estimate(i0, i1, (p, corr.pts1))
    t = np.linspace(0, 90, 20)
    with pytest.raises(GeometryError, match="collinear"):
        ViewMorpher.from_estimate(i0, i1, (np.c_[t, t], np.c_[t + 3, t]))


def test_duplicates_are_dropped_and_counted(rng):
    _, _, corr, i0, i1 = setup(rng)
    p0 = np.r_[corr.pts0, corr.pts0[:10]]
    p1 = np.r_[corr.pts1, corr.pts1[:10]]
    vm = ViewMorpher.from_estimate(i0, i1, (p0, p1))
    assert vm.report.n_duplicates == 10


def test_outliers_are_removed(rng):
    _, _, corr, i0, i1 = setup(rng, n=200)
    p1 = corr.pts1.copy()
    bad = rng.choice(len(p1), int(0.3 * len(p1)), replace=False)
    p1[bad] = rng.uniform(0, 95, (bad.size, 2))
    vm = ViewMorpher.from_estimate(i0, i1, (corr.pts0, p1))
    assert vm.mode == "viewmorph"
    assert vm.report.n_outliers >= 0.9 * bad.size
    assert vm.fit is not None and vm.fit.method == "magsac"
    # with the outliers gone the morph is as good as a clean one: s = 0 reproduces image 0
    diff = np.abs(vm.morph(0.0).astype(int) - i0.astype(int))
    assert diff.max() <= 1 and np.mean(diff > 0) < 0.01


def test_planar_scene_uses_the_homography_fallback(rng):
    c0, c1 = circle_cam(45), circle_cam(75)
    plane = np.c_[rng.uniform(-0.4, 0.4, (60, 2)), np.full(60, 0.1)]
    corr = from_geometry(plane, c0, c1)
    i0, i1 = texture(rng, (96, 96), 3), texture(rng, (96, 96), 3)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    assert vm.mode == "homography" and vm.fit is None
    assert np.abs(vm.morph(0.0).astype(int) - i0.astype(int)).max() <= 1


def test_pure_rotation_uses_the_homography_fallback(rng):
    c0 = circle_cam(60)
    c1 = c0.with_pose(look_at(c0.position, TARGET + np.array([0.2, -0.1, 0.0])))
    corr = from_geometry(rng.uniform(-0.3, 0.3, (80, 3)) + TARGET, c0, c1)
    i0, i1 = texture(rng, (96, 96), 4), texture(rng, (96, 96), 4)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    assert vm.mode == "homography"
    # the morph at s is image 0 warped by the interpolated homography: at s = 1, image 1's frame
    assert np.abs(vm.morph(1.0).astype(int) - i1.astype(int)).max() <= 1


def test_epipole_inside_image_refused_or_plain_morph(rng):
    c0 = circle_cam(60, size=(256, 256))  # large enough that the parallax beats the 1 px threshold
    fwd = c0.cam2world.copy()
    fwd[:3, 3] += 0.6 * c0.axis + 0.02 * c0.cam2world[:3, 0]
    c1 = c0.with_pose(fwd)
    corr = from_geometry(rng.uniform(-0.3, 0.3, (120, 3)) + TARGET, c0, c1)
    i0, i1 = texture(rng, (256, 256), 3), texture(rng, (256, 256), 3)
    # exact pairs fit the general F to ~1e-9 px: its epipole in the image is real, not noise, so the
    # affine F (over 1000x worse on the pairs both explain) does not replace it
    with pytest.raises(DegenerateViewError, match="epipole.*affine F.*the general F is determined"):
        ViewMorpher.from_estimate(i0, i1, corr)
    vm = ViewMorpher.from_estimate(i0, i1, corr, fallback="morph")
    assert vm.mode == "morph" and "epipole" in vm.report.fallback
    assert not vm.report.affine.used and vm.report.affine.affine_rms_px > 1e3 * \
        vm.report.affine.f_rms_px
    assert np.array_equal(vm.H_rect_0, np.eye(3))
    # the plain morph (no pre-warp, identity post-warp) still has exact end points
    for s_end, ref in ((0.0, i0), (1.0, i1)):
        out = vm.morph(s_end)
        assert out.shape == ref.shape
        covered = np.any(out > 0, axis=2)  # the mesh covers the correspondences' hull only
        diff = np.abs(out.astype(int) - ref.astype(int))[covered]
        assert covered.mean() > 0.2 and diff.max() <= 1 and np.mean(diff > 0) < 0.01, s_end


def test_fold_overs_are_resolved_by_dropping_vertices(rng):
    _, _, corr, i0, i1 = setup(rng, n=120)
    p1 = corr.pts1.copy()
    # swap the image-1 positions of two distant pairs: a crossing that folds the mesh
    far = np.argsort(np.linalg.norm(corr.pts0 - corr.pts0.mean(0), axis=1))[-2:]
    p1[far] = p1[far[::-1]]
    vm = ViewMorpher.from_estimate(i0, i1, (corr.pts0, p1), prewarp="none")
    assert vm.report.n_dropped_foldover >= 1
    amin = min_area_over_s(vm.vertices(0.0), vm.vertices(1.0), vm.triangles)
    assert amin.min() > 0
    # the resolved mesh still morphs: the end points reproduce the inputs (dropping a vertex
    # re-triangulates, it does not move the remaining ones), the middle is opaque where both are
    for s_end, ref in ((0.0, i0), (1.0, i1)):
        diff = np.abs(vm.morph(s_end).astype(int) - ref.astype(int))
        assert diff.max() <= 1 and np.mean(diff > 0) < 0.01, (s_end, diff.max())
    mid = vm.morph(0.5)
    assert mid.shape == i0.shape and np.mean(mid[..., 3] == 255) > 0.9


@pytest.mark.parametrize("s", [0.25, 0.5, 0.8])
def test_colour_is_kept_under_partial_coverage(rng, s):
    """Premultiplied blending: two views of one flat colour with different, partial
    alpha morph to exactly that colour wherever anything is drawn (straight-alpha
    blending would darken the edges towards the transparent background's black)."""
    _, _, corr, _, _ = setup(rng, channels=4)
    colour = np.array([200, 60, 20], np.uint8)
    imgs = []
    for _ in range(2):
        img = np.zeros((96, 96, 4), np.uint8)
        img[..., :3] = colour
        img[..., 3] = texture(rng, (96, 96), 1)  # alpha varies smoothly over 0..255
        imgs.append(img)
    out = ViewMorpher.from_estimate(imgs[0], imgs[1], corr).morph(s)
    drawn = out[..., 3] >= 8  # below 8/255 alpha, 8-bit rounding of colour / alpha dominates
    assert drawn.mean() > 0.5
    err = np.abs(out[..., :3][drawn].astype(int) - colour.astype(int))
    assert err.max() <= 2  # colour / alpha rounded to uint8 at alpha >= 8/255


def test_min_area_over_s_is_exact():
    r0 = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])
    r1 = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, -10.0]])  # flips through zero at s = 1/2
    a = min_area_over_s(r0, r1, np.array([[0, 1, 2]]))
    assert a[0] <= 0
    r1 = r0 + [3.0, 1.0]  # translation: area constant 50
    assert np.isclose(min_area_over_s(r0, r1, np.array([[0, 1, 2]]))[0], 50.0)


def test_premultiplied_crossfade_keeps_colour_under_transparency():
    a = np.zeros((4, 4, 4), np.uint8)
    a[..., 0], a[..., 3] = 200, 255
    b = np.zeros((4, 4, 4), np.uint8)  # fully transparent (black, alpha 0)
    out = crossfade(a, b, 0.5)
    assert np.all(out[..., 0] == 200) and np.all(out[..., 3] == 128)
    assert np.array_equal(nearest(a, b, 0.5), a) and np.array_equal(nearest(a, b, 0.51), b)


def test_frame_policy_keeps_the_object_in_frame(rng):
    _, _, corr, i0, i1 = setup(rng, base=20)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    H_shift = np.array([[1.0, 0, 60], [0, 1, 0], [0, 0, 1]])
    H_out_rect, shape = vm.post_homography(0.5)
    for frame in ("contain", "fit"):
        H_framed = vm.apply_frame(H_shift @ H_out_rect, 0.5, shape, frame)
        obj = apply_h(H_framed, vm.vertices(0.5)[vm.is_correspondence])
        assert obj.min() >= -0.5 - 1e-6 and obj.max(axis=0)[0] <= shape[1] - 0.5 + 1e-6
    assert np.array_equal(vm.apply_frame(H_shift @ H_out_rect, 0.5, shape, "fixed"), H_shift @ H_out_rect)
    with pytest.raises(ValidationError, match="frame"):
        vm.morph(0.5, frame="crop")


@pytest.mark.gl
def test_morph_of_rendered_teapot_matches_the_intermediate_render(renderer):
    from morphkit.meshes import sample_mesh
    from morphkit.scene import DirectionalLight, Item

    mesh = sample_mesh("teapot")
    items = [Item(mesh)]
    light = [DirectionalLight(np.array([-1.0, -0.5, -1.0]))]
    size = (128, 128)
    c0, c1, cm = circle_cam(50, size=size), circle_cam(70, size=size), circle_cam(60, size=size)
    i0, i1, gt = (renderer.source_view(c, items, light) for c in (c0, c1, cm))
    d0, d1 = renderer.depth(c0, items), renderer.depth(c1, items)
    corr = from_geometry(mesh, c0, c1, depth0=d0, depth1=d1, max_points=400)
    # every kept pair is visible in both views: its depth matches both depth maps
    for cam, d, px in ((c0, d0, corr.pts0), (c1, d1, corr.pts1)):
        z = (np.c_[corr.points3d, np.ones(len(corr))] @ cam.world2cam[2])
        r, c = np.clip(np.rint(px[:, 1]).astype(int), 0, 127), np.clip(np.rint(px[:, 0]).astype(int), 0, 127)
        near = np.isfinite(d[r, c])
        assert np.median(np.abs(z[near] - d[r, c][near]) / z[near]) < 0.01
    vm = ViewMorpher.from_estimate(i0, i1, corr, intrinsics=(c0.K, c1.K))
    out = vm.morph(0.5, post=cm, frame="fixed")
    m_out, m_gt = out[..., 3] > 127, gt[..., 3] > 127
    iou = (m_out & m_gt).sum() / (m_out | m_gt).sum()
    assert iou >= 0.95  # the target at 20 degrees (measured 0.97-0.98 at 256^2)


# --------------------------------------------------------------------------- plan apart from application


def test_a_plan_is_estimated_once_and_applied_by_any_number_of_morphers(rng):
    import dataclasses

    from morphkit.viewmorph import MorphPlan, MorphReport, plan_view_morph

    _, _, corr, i0, i1 = setup(rng)
    plan = plan_view_morph(i0, i1, corr)
    assert isinstance(plan, MorphPlan) and isinstance(plan.report, MorphReport)
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign"):
        plan.mode = "morph"
    a, b = ViewMorpher(plan), ViewMorpher(plan)
    assert a.plan is plan and a.report is plan.report and a.mode == plan.mode == "viewmorph"
    # same plan, same views: and the same as planning and applying in one call
    one_line = ViewMorpher.from_estimate(i0, i1, corr)
    for s in (0.3, 0.7):
        np.testing.assert_array_equal(a.morph(s), b.morph(s))
        np.testing.assert_array_equal(a.morph(s), one_line.morph(s))
    np.testing.assert_array_equal(a.morph(0.5, path="rectified"), one_line.morph(0.5, path="rectified"))


def test_the_report_is_typed(rng):
    _, _, corr, i0, i1 = setup(rng)
    rep = ViewMorpher.from_estimate(i0, i1, corr).report
    assert rep.mode == "viewmorph" and rep.n_input == len(corr) and rep.fallback is None
    assert rep.affine is None and rep.layers == 1 and rep.layer_edges == () and not rep.fill_occluded
    assert rep.n_used + rep.n_dropped_foldover + rep.n_outliers + rep.n_duplicates == rep.n_input
    assert 0.0 <= rep.homography_inlier_fraction < 1.0
    with pytest.raises(TypeError, match="not subscriptable"):
        rep["mode"]  # the string-keyed dict of earlier versions is gone


def test_a_morpher_needs_a_plan(rng):
    _, _, corr, i0, i1 = setup(rng)
    with pytest.raises(ValidationError, match=r"plan: expected a MorphPlan .*from_estimate.*got ndarray"):
        ViewMorpher(i0)
    with pytest.raises(TypeError, match="positional argument"):  # the images-and-pairs constructor is gone
        ViewMorpher(i0, i1, corr)


@pytest.mark.parametrize(("option", "bad", "match"), [
    ("frame_grid", 1, r"frame_grid: expected an integer >= 2, got 1"),
    ("frame_grid", 2.5, r"frame_grid: expected an integer >= 2, got 2.5"),
    ("seed", -1, r"seed: expected an integer >= 0, got -1"),
    ("fill_occluded", 1, r"fill_occluded: expected a bool"),
])
def test_plan_options_are_checked(rng, option, bad, match):
    _, _, corr, i0, i1 = setup(rng)
    with pytest.raises(ValidationError, match=match):
        ViewMorpher.from_estimate(i0, i1, corr, **{option: bad})


def test_a_given_f_whose_prewarps_are_refused_is_not_replaced(rng):
    from morphkit.viewmorph import fundamental_from_cameras, plan_view_morph

    c0 = circle_cam(60, size=(256, 256))
    fwd = c0.cam2world.copy()
    fwd[:3, 3] += 0.6 * c0.axis + 0.02 * c0.cam2world[:3, 0]
    c1 = c0.with_pose(fwd)
    corr = from_geometry(rng.uniform(-0.3, 0.3, (120, 3)) + TARGET, c0, c1)
    i0, i1 = texture(rng, (256, 256), 3), texture(rng, (256, 256), 3)
    F = fundamental_from_cameras(c0, c1)
    with pytest.raises(DegenerateViewError, match="epipole"):
        plan_view_morph(i0, i1, corr, fundamental=F)
    plan = plan_view_morph(i0, i1, corr, fundamental=F, fallback="morph")
    assert plan.mode == "morph" and "epipole" in plan.report.fallback and plan.report.affine is None
