"""View morphing geometry: F, epipoles, pre-warps, correspondences, and the refusals.

Synthetic pinhole cameras with known poses give the expectations: the geometric
F ``K1^-T [t]x R K0^-1``, the epipoles (the other camera's centre projected),
and rectified pairs that must share their y.
"""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from morphkit.camera import look_at, perspective
from morphkit.errors import DegenerateViewError, FileFormatError, GeometryError, ValidationError
from morphkit.viewmorph import (
    F0,
    Correspondences,
    epipoles,
    estimate_fundamental,
    from_geometry,
    fundamental_from_cameras,
    load_points,
    rectify,
    sampson_distance,
    save_points,
)
from morphkit.viewmorph.correspondences import visible_in
from morphkit.viewmorph.fundamental import epipole_pixel, homography_degeneracy
from morphkit.viewmorph.rectify import (
    apply_h,
    normalize_prewarps,
    seitz_dyer_angles,
    seitz_dyer_prewarps,
)

TARGET = np.array([0.0, 0.0, 0.25])


def circle_cam(angle_deg: float, *, r: float = 2.6, h: float = 1.0, size: int = 256):
    a = np.radians(angle_deg)
    eye = np.array([r * np.cos(a), r * np.sin(a), h])
    return perspective(np.radians(30), (size, size), look_at(eye, TARGET))


def cloud(rng: np.random.Generator, n: int = 300) -> np.ndarray:
    return rng.uniform(-0.4, 0.4, (n, 3)) + TARGET


def pair(rng, base=30.0, n=300):
    c0, c1 = circle_cam(60 - base / 2), circle_cam(60 + base / 2)
    corr = from_geometry(cloud(rng, n), c0, c1, max_points=n)
    return c0, c1, corr


def proportional(A: np.ndarray, B: np.ndarray) -> float:
    """Distance between two matrices up to scale and sign (0 = proportional)."""
    a, b = A / np.linalg.norm(A), B / np.linalg.norm(B)
    return float(min(np.abs(a - b).max(), np.abs(a + b).max()))


# --------------------------------------------------------------------------- F and epipoles


def test_geometric_f_satisfies_epipolar_constraint(rng):
    c0, c1, corr = pair(rng)
    F = fundamental_from_cameras(c0, c1)
    assert np.max(sampson_distance(F, corr.pts0, corr.pts1)) < 1e-6


def test_epipoles_are_svd_null_vectors_and_camera_centres(rng):
    c0, c1, _ = pair(rng)
    F = fundamental_from_cameras(c0, c1)
    e0, e1 = epipoles(F)
    assert np.linalg.norm(F @ e0) < 1e-12 and np.linalg.norm(e1 @ F) < 1e-12
    U, _, Vt = np.linalg.svd(F)
    assert proportional(e0[None], Vt[2][None]) < 1e-12 and proportional(e1[None], U[:, 2][None]) < 1e-12
    # epipole of image 0 = camera 1's centre seen by camera 0 (and vice versa)
    for e, cam, other in ((e0, c0, c1), (e1, c1, c0)):
        q = cam.K @ cam.world2cam[:3] @ np.r_[other.position, 1.0]
        assert proportional(e[None], q[None]) < 1e-9


def test_estimated_f_matches_geometric_f_on_exact_points(rng):
    c0, c1, corr = pair(rng)
    fit = estimate_fundamental(corr.pts0, corr.pts1)
    assert fit.method == "8point" and fit.inliers.all()
    assert fit.sampson_max < 1e-4
    assert proportional(fit.F, fundamental_from_cameras(c0, c1)) < 1e-4


def test_robust_fit_with_30_percent_outliers(rng):
    c0, c1, corr = pair(rng, n=300)
    n = len(corr)
    bad = rng.choice(n, size=int(0.3 * n), replace=False)
    p1 = corr.pts1.copy()
    p1[bad] = rng.uniform(0, 255, (bad.size, 2))
    fit = estimate_fundamental(corr.pts0, p1)
    assert fit.method == "magsac"
    Fg = fundamental_from_cameras(c0, c1)
    true_out = sampson_distance(Fg, corr.pts0, p1) > 1.0  # a few random "outliers" fit by chance
    assert np.count_nonzero(fit.inliers & true_out) <= 2
    assert np.count_nonzero(~fit.inliers & ~true_out) <= 0.02 * n
    e_true = epipole_pixel(epipoles(Fg)[0])
    e_est = epipole_pixel(epipoles(fit.F)[0])
    assert abs(np.arctan2(*e_true[::-1]) - np.arctan2(*e_est[::-1])) < np.radians(0.5)


def test_fewer_than_8_pairs_refused(rng):
    _, _, corr = pair(rng)
    with pytest.raises(ValidationError, match="at least 8"):
        estimate_fundamental(corr.pts0[:7], corr.pts1[:7])


def test_nan_and_inf_refused(rng):
    _, _, corr = pair(rng)
    p = corr.pts0.copy()
    p[3, 1] = np.nan
    with pytest.raises(ValidationError, match="finite"):
        estimate_fundamental(p, corr.pts1)
    p[3, 1] = np.inf
    with pytest.raises(ValidationError, match="finite"):
        Correspondences(p, corr.pts1)


def test_collinear_points_refused(rng):
    t = rng.uniform(0, 200, 20)
    p0 = np.c_[t, 0.5 * t + 3]
    p1 = p0 + [5.0, 0.0]
    with pytest.raises(GeometryError, match="collinear"):
        estimate_fundamental(p0, p1)


def test_planar_scene_has_no_f(rng):
    c0, c1 = circle_cam(40), circle_cam(70)
    plane = np.c_[rng.uniform(-0.5, 0.5, (60, 2)), np.full(60, 0.1)]
    corr = from_geometry(plane, c0, c1)
    H, frac = homography_degeneracy(corr.pts0, corr.pts1)
    assert H is not None and frac == 1.0
    assert np.abs(apply_h(H, corr.pts0) - corr.pts1).max() < 1e-4  # cv2 DLT + refinement: ~1e-5 px
    with pytest.raises(DegenerateViewError, match="homography"):
        estimate_fundamental(corr.pts0, corr.pts1)


def test_pure_rotation_has_no_f(rng):
    c0 = circle_cam(60)
    R = look_at(c0.position, TARGET + np.array([0.3, -0.2, 0.05]))
    c1 = c0.with_pose(R)
    corr = from_geometry(cloud(rng), c0, c1)
    with pytest.raises(DegenerateViewError, match="homography"):
        estimate_fundamental(corr.pts0, corr.pts1)
    with pytest.raises(DegenerateViewError, match="baseline"):
        fundamental_from_cameras(c0, c1)


def test_identical_points_have_no_f(rng):
    p = rng.uniform(0, 255, (40, 2))
    with pytest.raises(DegenerateViewError, match="homography"):
        estimate_fundamental(p, p.copy())


# --------------------------------------------------------------------------- pre-warps


@pytest.mark.parametrize("method", ["opencv", "seitz-dyer"])
@pytest.mark.parametrize("base", [10.0, 40.0, 60.0])
def test_rectified_pairs_share_y(rng, method, base):
    c0, c1, corr = pair(rng, base=base)
    F = fundamental_from_cameras(c0, c1)
    r = rectify(F, corr.pts0, corr.pts1, c0.shape, c1.shape, method=method)
    assert r.method == method
    r0, r1 = apply_h(r.H_rect_0, corr.pts0), apply_h(r.H_rect_1, corr.pts1)
    assert np.abs(r1[:, 1] - r0[:, 1]).max() < 1e-6
    assert proportional(np.linalg.inv(r.H_rect_1).T @ F @ np.linalg.inv(r.H_rect_0), F0) < 1e-6
    # normalised: a similarity (no mirror) at the centroid, centroids at the origin
    assert np.linalg.det(r.H_rect_0[:2, :2]) != 0
    assert np.abs(r0.mean(axis=0)).max() < 1e-6 and np.abs(r1[:, 0].mean()) < 1e-6
    assert r.anisotropy < 1.5


def test_seitz_dyer_rotations_send_epipoles_to_infinity_on_x(rng):
    c0, c1, _ = pair(rng, base=40)
    F = fundamental_from_cameras(c0, c1)
    Fh = c1.K.T @ F @ c0.K
    ang = seitz_dyer_angles(Fh)
    for i, e in enumerate(epipoles(Fh)):
        er = ang[f"R{i}"] @ e
        assert abs(er[2]) < 1e-12 and abs(er[1]) < 1e-12
        assert abs(ang[f"theta{i}"]) <= np.pi / 2 + 1e-12
    # with the true intrinsics the pre-warps are rotations: the rectified F is F0 up to T
    H_rect_0, H_rect_1 = seitz_dyer_prewarps(F, c0.shape, c1.shape, K0=c0.K, K1=c1.K)
    assert proportional(np.linalg.inv(H_rect_1).T @ F @ np.linalg.inv(H_rect_0), F0) < 1e-9


def test_opencv_and_seitz_dyer_agree_after_normalisation_on_symmetric_views(rng):
    c0, c1, corr = pair(rng, base=30)
    F = fundamental_from_cameras(c0, c1)
    a = rectify(F, corr.pts0, corr.pts1, c0.shape, c1.shape, method="opencv")
    b = rectify(F, corr.pts0, corr.pts1, c0.shape, c1.shape, method="seitz-dyer", K0=c0.K, K1=c1.K)
    assert abs(a.anisotropy - b.anisotropy) < 0.05


def test_normalize_prewarps_is_local_similarity(rng):
    c0, c1, corr = pair(rng)
    F = fundamental_from_cameras(c0, c1)
    H_rect_0, H_rect_1 = normalize_prewarps(*seitz_dyer_prewarps(F, c0.shape, c1.shape), corr.pts0, corr.pts1)
    for H, p in ((H_rect_0, corr.pts0), (H_rect_1, corr.pts1)):
        c = p.mean(axis=0)
        eps = 1e-3
        J = np.stack([(apply_h(H, [c + [eps, 0]]) - apply_h(H, [c - [eps, 0]]))[0] / (2 * eps),
                      (apply_h(H, [c + [0, eps]]) - apply_h(H, [c - [0, eps]]))[0] / (2 * eps)], axis=1)
        assert abs(J[0, 0] - J[1, 1]) < 1e-5 and abs(J[0, 1] + J[1, 0]) < 1e-5 and np.linalg.det(J) > 0


def test_parallel_views_skip_the_prewarp(rng):
    pose = look_at(np.array([0.0, -3.0, 0.3]), np.array([0.0, 0.0, 0.3]))
    c0 = perspective(np.radians(40), (200, 240), pose)
    pose1 = pose.copy()
    pose1[:3, 3] += 0.3 * pose[:3, 0]  # move along the camera's x axis
    c1 = c0.with_pose(pose1)
    corr = from_geometry(cloud(rng) + [0, 0, 0.05], c0, c1)
    F = estimate_fundamental(corr.pts0, corr.pts1).F
    r = rectify(F, corr.pts0, corr.pts1, c0.shape, c1.shape)
    assert r.method == "parallel"
    assert np.array_equal(r.H_rect_0, np.eye(3)) and np.array_equal(r.H_rect_1, np.eye(3))


def test_epipole_inside_the_image_refused(rng):
    c0 = circle_cam(60)
    fwd = c0.cam2world.copy()
    fwd[:3, 3] += 0.4 * c0.axis + 0.02 * c0.cam2world[:3, 0]  # step forward: epipole near the centre
    c1 = c0.with_pose(fwd)
    corr = from_geometry(cloud(rng), c0, c1)
    F = estimate_fundamental(corr.pts0, corr.pts1).F
    assert epipole_pixel(epipoles(F)[0]) is not None
    with pytest.raises(DegenerateViewError, match="epipole"):
        rectify(F, corr.pts0, corr.pts1, c0.shape, c1.shape)


# --------------------------------------------------------------------------- correspondences


def test_duplicates_are_dropped(rng):
    _, _, corr = pair(rng, n=50)
    p0 = np.r_[corr.pts0, corr.pts0[:5], corr.pts0[5:7]]
    p1 = np.r_[corr.pts1, corr.pts1[:5], corr.pts1[5:7] + 10.0]  # conflicting matches too
    clean, n = Correspondences(p0, p1).cleaned()
    assert n == 7 and len(clean) == len(corr)
    assert np.array_equal(clean.pts0, corr.pts0)


def test_visibility_uses_the_depth_map():
    cam = perspective(np.radians(40), (64, 64), look_at(np.array([0.0, 0, 5]), np.zeros(3),
                                                         up=np.array([0.0, 1, 0])))
    depth = np.full((64, 64), 5.0, np.float32)  # a wall at z = 0
    depth[:, :32] = 4.0  # left half: an occluder 1 unit in front
    pts = np.array([[-0.3, 0.0, 0.0], [0.3, 0.0, 0.0], [-0.3, 0.0, 1.0]])
    px, vis = visible_in(cam, pts, depth)
    left = px[:, 0] < 31
    assert left[0] and not left[1]
    assert vis.tolist() == [False, True, True]  # the wall behind the occluder is hidden


def test_points_file_roundtrip(tmp_path, rng):
    _, _, corr = pair(rng, n=30)
    for name in ("pts.json", "pts.csv"):
        p = save_points(tmp_path / name, corr)
        back = load_points(p)
        assert np.array_equal(back.pts0, corr.pts0) and np.array_equal(back.pts1, corr.pts1)
    # written through morphkit.files.fileio: a rewrite replaces the file whole, no temporary left behind
    save_points(tmp_path / "pts.csv", corr.subset(np.arange(5)))
    assert len(load_points(tmp_path / "pts.csv")) == 5
    assert sorted(q.name for q in tmp_path.iterdir()) == ["pts.csv", "pts.json"]
    with pytest.raises(ValidationError, match=r"path: expected a \.json or \.csv file name"):
        save_points(tmp_path / "new" / "pts.txt", corr)
    assert not (tmp_path / "new").exists()  # refused before creating anything
    rows = [[1, 2, 3, 4], [5, 6, 7, 8]]
    (tmp_path / "rows.json").write_text(json.dumps(rows))
    assert load_points(tmp_path / "rows.json").pts1.tolist() == [[3, 4], [7, 8]]
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(FileFormatError, match="valid JSON"):
        load_points(tmp_path / "bad.json")
    (tmp_path / "bad.csv").write_text("x0,y0,x1\n1,2,3\n")
    with pytest.raises(FileFormatError, match="4 numbers"):
        load_points(tmp_path / "bad.csv")
    (tmp_path / "nan.csv").write_text("1,2,3,nan\n" * 9)
    with pytest.raises(ValidationError, match="finite"):
        load_points(tmp_path / "nan.csv")


def test_homography_degeneracy_finds_a_dominant_plane_with_a_short_search(rng):
    """96% of the pairs on a plane (plus off-plane points): degenerate, found by the short RANSAC
    (a few dozen samples suffice for a >= 95% inlier homography); a real 3-D cloud is not."""
    c0, c1 = circle_cam(40), circle_cam(70)
    plane = np.c_[rng.uniform(-0.5, 0.5, (480, 2)), np.full(480, 0.1)]
    off = cloud(rng)[:20]
    corr = from_geometry(np.r_[plane, off], c0, c1, max_points=10_000)
    assert len(corr) == 500
    for seed in range(5):  # cv2's RANSAC draws from its global RNG
        cv2.setRNGSeed(seed)
        H, frac = homography_degeneracy(corr.pts0, corr.pts1)
        assert H is not None and 0.95 <= frac <= 0.97
    solid = from_geometry(cloud(rng), c0, c1)
    H, frac = homography_degeneracy(solid.pts0, solid.pts1)
    assert H is None and frac < 0.95
