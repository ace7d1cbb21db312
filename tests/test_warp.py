"""Tests of morphkit.warp: exactness (identity, global affine vs cv2.warpAffine,
skimage reference), reuse, dtypes/channels, non-finite safety, and bad input."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from morphkit import tol
from morphkit.errors import FoldOverError, ValidationError
from morphkit.warp import (
    MeshWarper,
    WarpMaps,
    delaunay_triangles,
    grid_shape,
    grid_triangles,
    warp_mesh,
)
from morphkit.warp.build import prepare
from morphkit.warp.mesh import boundary_edges, disk_boundary, signed_area


def lattice(rows: int, cols: int, h: int, w: int) -> np.ndarray:
    xs = np.linspace(0.0, w - 1.0, cols)
    ys = np.linspace(0.0, h - 1.0, rows)
    X, Y = np.meshgrid(xs, ys)
    return np.stack([X.ravel(), Y.ravel()], axis=1)


def mesh_setup(warper: MeshWarper) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """``(src_v, src_sign, boundary, loop)`` of a warper's source mesh (what
    MeshWarper keeps), from the public helpers of morphkit.warp.mesh."""
    src_v = warper.src_pts[warper.triangles]
    sign = np.sign(signed_area(src_v))
    return (src_v, sign, boundary_edges(warper.triangles, warper.n_points),
            disk_boundary(warper.triangles, sign))


def smooth_image(h: int, w: int, channels: int | None = None) -> np.ndarray:
    """Values in [0, 1], gradient <= ~0.03 / px: OpenCV's 1/32-px interpolation steps
    (in cv2.remap and cv2.warpAffine alike) then stay below 1e-3 of the range."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    base = 0.5 + 0.2 * np.sin(xx / 13.0) + 0.15 * np.cos(yy / 9.0) + 0.1 * np.sin((xx + yy) / 17.0)
    if channels is None:
        return base.astype(np.float32)
    return np.stack([np.roll(base, 7 * k, axis=1) for k in range(channels)], axis=2).astype(np.float32)


def cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a, b = np.asarray(a), np.asarray(b)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def interior(mask: np.ndarray, r: int = 2) -> np.ndarray:
    return cv2.erode(mask.astype(np.uint8), np.ones((2 * r + 1, 2 * r + 1), np.uint8)) > 0


def jittered(rows: int, cols: int, h: int, w: int, rng: np.random.Generator, frac: float = 0.2):
    """Lattice with interior points jittered by up to ``frac`` of a cell; Delaunay(dst) triangles."""
    src = lattice(rows, cols, h, w)
    cell = min((w - 1) / (cols - 1), (h - 1) / (rows - 1))
    inner = (src[:, 0] > 0) & (src[:, 0] < w - 1) & (src[:, 1] > 0) & (src[:, 1] < h - 1)
    dst = src.copy()
    dst[inner] += rng.uniform(-frac * cell, frac * cell, (int(inner.sum()), 2))
    return src, dst, delaunay_triangles(dst)


# ----------------------------------------------------------------------------- topology


def test_grid_triangles_topology_and_orientation():
    t = grid_triangles(3, 4)
    assert t.shape == (2 * 2 * 3, 3) and t.dtype == np.int32
    assert t.min() == 0 and t.max() == 11
    pts = lattice(3, 4, 10, 10)
    v = pts[t]
    area = cross2(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]) / 2
    assert np.all(area > 0)
    assert np.isclose(area.sum(), 9.0 * 9.0)  # the cells tile the lattice's rectangle


def test_grid_triangles_sizes_follow_as_int():
    np.testing.assert_array_equal(grid_triangles(3.0, np.int64(4)), grid_triangles(3, 4))
    with pytest.raises(ValidationError, match=r"grid_triangles rows: expected an integer >= 2, got 2\.5"):
        grid_triangles(2.5, 4)  # formerly truncated to 2 without a word
    with pytest.raises(ValidationError, match="grid_triangles cols: expected an integer >= 2, got 1"):
        grid_triangles(3, 1)


def test_grid_shape_detection():
    pts = lattice(5, 15, 64, 64)
    assert grid_shape(pts) == (5, 15)
    assert grid_shape(np.stack([np.tile([0.0, 1.0, 3.0], 2), np.repeat([0.0, 2.0], 3)], axis=1)) == (2, 3)
    rng = np.random.default_rng(0)
    assert grid_shape(pts[rng.permutation(len(pts))]) is None
    assert grid_shape(rng.uniform(0, 10, (12, 2))) is None
    assert grid_shape(pts.reshape(5, 15, 2).transpose(1, 0, 2).reshape(-1, 2)) is None  # column-major


def test_default_triangles_grid_vs_delaunay():
    pts = lattice(4, 5, 32, 32)
    assert np.array_equal(MeshWarper(pts).triangles, grid_triangles(4, 5))
    rng = np.random.default_rng(1)
    scattered = np.vstack([[0, 0], [31, 0], [0, 31], [31, 31], rng.uniform(2, 29, (10, 2))])
    w = MeshWarper(scattered)
    v = scattered[w.triangles]
    assert np.all(cross2(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]) > 0)
    assert np.isclose(cross2(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]).sum() / 2, 31 * 31)


# ----------------------------------------------------------------------------- exactness


@pytest.mark.parametrize("dtype", [np.uint8, np.float32, np.uint16, np.float64])
def test_identity_is_identity(dtype):
    rng = np.random.default_rng(2)
    img = (rng.uniform(0, 200, (37, 53, 4))).astype(dtype)
    for src in (lattice(5, 15, 37, 53), lattice(2, 2, 37, 53)):
        out, mask = warp_mesh(img, src, src, (37, 53), return_mask=True)
        assert out.dtype == img.dtype and out.shape == img.shape
        assert mask.all()
        assert np.array_equal(out, img)
        near = warp_mesh(img, src, src, (37, 53), interpolation="nearest")
        assert np.array_equal(near, img)


def test_identity_nonuniform_lattice_and_delaunay():
    rng = np.random.default_rng(3)
    img = rng.uniform(0, 1, (40, 40)).astype(np.float32)
    xs = np.array([0.0, 3.0, 17.5, 30.0, 39.0])
    ys = np.array([0.0, 11.0, 39.0])
    X, Y = np.meshgrid(xs, ys)
    src = np.stack([X.ravel(), Y.ravel()], axis=1)
    assert np.array_equal(warp_mesh(img, src, src, (40, 40)), img)
    tri = delaunay_triangles(src + rng.uniform(-0.1, 0.1, src.shape) * (src % 39 != 0))
    assert np.array_equal(warp_mesh(img, src, src, (40, 40), triangles=tri), img)


@pytest.mark.parametrize("dtype", [np.float32, np.uint8])
@pytest.mark.parametrize(
    "A",
    [
        [[1.0, 0.0, 3.25], [0.0, 1.0, -2.5]],
        [[0.9, 0.15, 10.0], [-0.1, 1.1, -6.0]],
        [[np.cos(0.3) * 1.2, -np.sin(0.3) * 1.2, 40.0], [np.sin(0.3) * 1.2, np.cos(0.3) * 1.2, -20.0]],
    ],
)
def test_global_affine_matches_warpaffine(A, dtype):
    A = np.asarray(A)
    h, w = 96, 128
    img = smooth_image(h, w, 3)
    if dtype == np.uint8:
        img = np.rint(img * 255).astype(np.uint8)
    vrange = 255.0 if dtype == np.uint8 else 1.0
    src = lattice(7, 15, h, w)
    dst = src @ A[:, :2].T + A[:, 2]  # A maps source pixels to destination pixels (A_dst_src)
    out, mask = warp_mesh(img, src, dst, (h, w), return_mask=True)
    ref = cv2.warpAffine(img, A, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)
    inner = interior(mask)
    assert inner.sum() > 0.3 * h * w
    diff = np.abs(out.astype(np.float64) - ref.astype(np.float64))[inner]
    # uint8: both round to integers, so a 1-level difference from 1/32-px steps is allowed
    assert diff.max() <= (1.0 if dtype == np.uint8 else 1e-3 * vrange)
    assert diff.mean() < 1e-3 * vrange
    # the mask is the destination rectangle's image under A
    corners = np.array([[0, 0], [w - 1, 0], [w - 1, h - 1], [0, h - 1]], float) @ A[:, :2].T + A[:, 2]
    poly = np.zeros((h, w), np.uint8)
    cv2.fillConvexPoly(poly, np.round(corners * 256).astype(np.int32), 1, cv2.LINE_8, 8)
    assert np.mean(mask != poly.astype(bool)) < 0.02


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_jittered_mesh_matches_skimage(seed):
    skt = pytest.importorskip("skimage.transform")
    rng = np.random.default_rng(seed)
    h, w = 80, 112
    src, dst, tri = jittered(6, 8, h, w, rng)
    img = smooth_image(h, w)
    out, mask = warp_mesh(img, src, dst, (h, w), triangles=tri, return_mask=True)
    if hasattr(skt.PiecewiseAffineTransform, "from_estimate"):
        tf = skt.PiecewiseAffineTransform.from_estimate(dst, src)
    else:  # pragma: no cover - older skimage
        tf = skt.PiecewiseAffineTransform()
        tf.estimate(dst, src)
    ref = skt.warp(img.astype(np.float64), tf, order=1, preserve_range=True, cval=0.0)
    inner = interior(mask)
    diff = np.abs(out - ref)[inner]
    assert diff.mean() < 1e-3  # value range is ~1
    assert diff.max() < 5e-3
    # coverage: the lattice's rectangle (boundary points were not moved)
    assert mask.all()


def test_piecewise_values_are_the_per_triangle_affines():
    """Every covered pixel samples A_src_dst[t] p for the triangle t containing its centre."""
    rng = np.random.default_rng(5)
    h, w = 60, 70
    src, dst, tri = jittered(4, 5, h, w, rng, frac=0.25)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    coords = np.stack([xx, yy], axis=2)  # a linear image: sampling it returns the source position
    out, mask = warp_mesh(coords, src, dst, (h, w), triangles=tri, return_mask=True)
    p = np.stack([xx, yy], axis=2).reshape(-1, 2).astype(np.float64)
    expect = np.full((h * w, 2), np.nan)
    for t in tri:
        D = np.hstack([dst[t], np.ones((3, 1))])
        lam = np.linalg.solve(D.T, np.hstack([p, np.ones((len(p), 1))]).T).T
        inside = (lam >= -1e-9).all(axis=1)
        expect[inside] = lam[inside] @ src[t]
    inner = interior(mask, 1).ravel()
    got = out.reshape(-1, 2)[inner]
    assert np.abs(got - expect[inner]).max() < 1.0 / 32 + 1e-4  # remap's 1/32-px sub-pixel steps


# ----------------------------------------------------------------------------- reuse


def test_warper_and_maps_reuse_match_one_shot():
    rng = np.random.default_rng(6)
    h, w = 50, 64
    src = lattice(4, 6, h, w)
    warper = MeshWarper(src)
    a = rng.uniform(0, 255, (h, w, 4)).astype(np.uint8)
    b = rng.uniform(0, 1, (h, w)).astype(np.float32)
    for _ in range(3):
        dst = src + rng.uniform(-2, 2, src.shape)
        wm = warper.maps(dst, (h, w))
        assert isinstance(wm, WarpMaps) and wm.out_shape == (h, w)
        for img in (a, b):
            one, m1 = warp_mesh(img, src, dst, (h, w), return_mask=True)
            assert np.array_equal(wm.apply(img), one)
            assert np.array_equal(warper(img, dst, (h, w)), one)
            assert np.array_equal(wm.mask, m1)
        # channels warped separately equal the multi-channel warp
        chans = np.stack([wm.apply(np.ascontiguousarray(a[:, :, k])) for k in range(4)], axis=2)
        assert np.array_equal(chans, wm.apply(a))


def test_output_size_and_partial_coverage():
    h, w = 40, 40
    src = lattice(3, 3, h, w)
    img = np.full((h, w), 7.0, np.float32)
    dst = src * 0.5 + [30.0, -5.0]  # half size, partly outside a 24 x 50 output
    out, mask = warp_mesh(img, src, dst, (24, 50), fill=-1.0, return_mask=True)
    assert out.shape == (24, 50)
    assert np.all(out[mask] == 7.0) and np.all(out[~mask] == -1.0)
    ys, xs = np.nonzero(mask)
    assert xs.min() == 30 and xs.max() == 49 and ys.min() == 0 and ys.max() == 14
    out, mask = warp_mesh(img, src, src + 1000.0, (24, 50), fill=3.0, return_mask=True)
    assert not mask.any() and np.all(out == 3.0)


# ----------------------------------------------------------------------------- dtypes, fill, non-finite


@pytest.mark.parametrize("dtype", [np.bool_, np.int8, np.int32, np.int64, np.uint32, np.float16])
def test_other_dtypes_roundtrip(dtype):
    rng = np.random.default_rng(7)
    img = rng.integers(-100 if np.dtype(dtype).kind == "i" else 0, 100, (20, 30)).astype(dtype)
    src = lattice(3, 4, 20, 30)
    out = warp_mesh(img, src, src, (20, 30))
    assert out.dtype == img.dtype and np.array_equal(out, img)
    shifted = warp_mesh(img, src, src + [2.0, 0.0], (20, 30), interpolation="nearest", fill=0)
    assert np.array_equal(shifted[:, 2:], img[:, :-2])


@pytest.mark.parametrize("channels", [2, 3, 4, 5, 6])
@pytest.mark.parametrize("dtype", [np.float32, np.uint8])
def test_every_channel_count_samples_like_single_channels(channels, dtype):
    """OpenCV remaps 2-channel images on a separate path with 1/32-px fixed-point
    weights (1, 3 and 4 channels agree with each other); morphkit never hands it
    2 channels, so every channel count samples exactly like its planes do one at
    a time (bit for bit; 2 and 6 channels fail on a plain cv2.remap)."""
    rng = np.random.default_rng(18)
    h, w = 40, 48
    img = (rng.uniform(0, 255, (h, w, channels))).astype(dtype)
    src = lattice(4, 5, h, w)
    dst = src + rng.uniform(-1.7, 1.7, src.shape)  # sub-pixel positions everywhere
    wm = MeshWarper(src).maps(dst, (h, w))
    planes = np.stack([wm.apply(np.ascontiguousarray(img[:, :, k])) for k in range(channels)], axis=2)
    assert np.array_equal(wm.apply(img), planes)


def test_many_channels_and_per_channel_fill():
    rng = np.random.default_rng(8)
    img = rng.uniform(0, 1, (16, 16, 6)).astype(np.float32)
    src = lattice(2, 2, 16, 16)
    dst = src * 0.5
    fill = [1, 2, 3, 4, 5, 6]
    out, mask = warp_mesh(img, src, dst, (16, 16), fill=fill, return_mask=True)
    assert out.shape == (16, 16, 6)
    assert np.array_equal(out[~mask], np.broadcast_to(np.float32(fill), out[~mask].shape))
    rgba = rng.integers(0, 255, (16, 16, 4)).astype(np.uint8)
    out = warp_mesh(rgba, src, dst, (16, 16), fill=(255, 0, 0, 0))
    assert np.array_equal(out[15, 15], [255, 0, 0, 0])


def test_depth_map_with_inf_background_never_nan():
    h, w = 48, 48
    depth = np.full((h, w), np.inf, np.float32)
    depth[10:38, 12:30] = np.linspace(1.0, 2.0, 18, dtype=np.float32)[None, :]
    src = lattice(4, 4, h, w)
    rng = np.random.default_rng(9)
    dst = src + np.where((src > 0) & (src < 47), rng.uniform(-3.3, 3.3, src.shape), 0.0)
    for interp in ("linear", "nearest"):
        out = warp_mesh(depth, src, dst, (h, w), interpolation=interp, fill=np.inf)
        assert not np.isnan(out).any()
        assert np.isinf(out).any() and np.isfinite(out).any()
    lin = warp_mesh(depth, src, dst, (h, w), fill=np.inf)
    near = warp_mesh(depth, src, dst, (h, w), interpolation="nearest", fill=np.inf)
    # where the bilinear footprint is all-finite, linear equals the finite-only warp ...
    finite_only = warp_mesh(np.where(np.isfinite(depth), depth, 0.0).astype(np.float32), src, dst, (h, w))
    ok = np.isfinite(lin) & (near < 10)
    # footprints touching a non-finite value or the (inf) border: raw remap of an indicator
    maps = MeshWarper(src).maps(dst, (h, w))
    indicator = np.where(np.isfinite(depth), 0, np.nan).astype(np.float32)
    touched = ~np.isfinite(cv2.remap(indicator, maps.map1, maps.map2, cv2.INTER_LINEAR,
                                     borderMode=cv2.BORDER_CONSTANT, borderValue=np.nan))
    sel = ok & ~touched
    assert sel.sum() > 100
    assert np.allclose(lin[sel], finite_only[sel], atol=1e-6)
    # ... and where it touches +inf it takes the nearest value (finite or inf)
    assert np.array_equal(lin[touched], near[touched])


def test_nearest_values_come_from_the_image():
    rng = np.random.default_rng(10)
    img = rng.integers(0, 5, (30, 30)).astype(np.float32)
    src, dst, tri = jittered(4, 4, 30, 30, rng, frac=0.3)
    out = warp_mesh(img, src, dst, (30, 30), triangles=tri, interpolation="nearest", fill=-1)
    assert set(np.unique(out)) <= {-1.0, 0.0, 1.0, 2.0, 3.0, 4.0}


# ----------------------------------------------------------------------------- bad input


def test_bad_points_and_counts():
    src = lattice(3, 3, 10, 10)
    img = np.zeros((10, 10), np.float32)
    with pytest.raises(ValidationError, match="dst_pts.*9 points"):
        warp_mesh(img, src, src[:8], (10, 10))
    bad = src.copy()
    bad[4, 0] = np.nan
    with pytest.raises(ValidationError, match="src_pts.*finite"):
        warp_mesh(img, bad, src, (10, 10))
    bad[4, 0] = np.inf
    with pytest.raises(ValidationError, match="dst_pts.*finite"):
        warp_mesh(img, src, bad, (10, 10))
    with pytest.raises(ValidationError, match="src_pts.*shape"):
        MeshWarper(src[:, :1])
    with pytest.raises(ValidationError, match="out_shape"):
        warp_mesh(img, src, src, (0, 10))
    with pytest.raises(ValidationError, match="image"):
        warp_mesh(np.zeros((10, 10, 3, 2)), src, src, (10, 10))


def test_nan_pixels_refused_with_their_count():
    src = lattice(3, 3, 10, 10)
    img = np.zeros((10, 10, 2), np.float32)
    img[2, 3, 0] = img[7, 1, 1] = img[5, 5, 1] = np.nan
    with pytest.raises(ValidationError, match=r"image: expected no NaN pixels.*got 3 NaN values"):
        warp_mesh(img, src, src, (10, 10))
    with pytest.raises(ValidationError, match="got 3 NaN values"):
        MeshWarper(src).maps(src, (10, 10)).apply(img, interpolation="nearest")
    img[np.isnan(img)] = np.inf  # +inf (a depth background) stays allowed
    out = warp_mesh(img, src, src, (10, 10), interpolation="nearest")
    np.testing.assert_array_equal(out, img)  # an identity warp of a nearest sample


def test_coordinates_beyond_the_limit_refused():
    src = lattice(3, 3, 10, 10)
    img = np.ones((10, 10), np.float32)
    far = (src - 4.5) * 1e20 + 4.5  # used to give an empty mask without a word
    with pytest.raises(ValidationError, match=r"dst_pts: expected coordinates within \+-1e\+07 px.*"
                       r"8 points beyond it \(largest \|coordinate\| 4\.5e\+20\)"):
        warp_mesh(img, src, far, (10, 10))
    with pytest.raises(ValidationError, match="src_pts: expected coordinates within"):
        MeshWarper(far)
    with pytest.raises(ValidationError, match="dst_pts: expected coordinates within"):
        MeshWarper(src).accumulation(far, (10, 10))
    # at the limit the warp still holds: a mesh scaled up about the image centre covers it all
    big = (src - 4.5) * (tol.MAX_COORD_PX / 5.0) + 4.5
    out, mask = warp_mesh(img, src, big, (10, 10), return_mask=True)
    assert mask.all() and np.all(out == 1.0)


def test_bad_triangles():
    src = lattice(3, 3, 10, 10)
    with pytest.raises(ValidationError, match=r"indices in \[0, 9\).*triangles \[1\]"):
        MeshWarper(src, [[0, 1, 4], [0, 9, 4]])
    with pytest.raises(ValidationError, match="indices in"):
        MeshWarper(src, [[0, -1, 4]])
    with pytest.raises(ValidationError, match=r"shape \(M, 3\)"):
        MeshWarper(src, [[0, 1]])
    with pytest.raises(ValidationError, match="integer"):
        MeshWarper(src, [[0.5, 1, 4]])
    with pytest.raises(ValidationError, match="distinct"):
        MeshWarper(src, [[0, 1, 1]])
    with pytest.raises(ValidationError, match="manifold"):
        MeshWarper(src, [[0, 4, 1], [0, 4, 3], [0, 4, 5]])
    with pytest.raises(FoldOverError, match=r"source triangles.*\[0\]"):
        MeshWarper(src, [[0, 1, 2]])  # collinear source points


def test_bad_interpolation_and_fill():
    src = lattice(2, 2, 8, 8)
    with pytest.raises(ValidationError, match="interpolation"):
        warp_mesh(np.zeros((8, 8)), src, src, (8, 8), interpolation="cubic")
    with pytest.raises(ValidationError, match="fill"):
        warp_mesh(np.zeros((8, 8), np.uint8), src, src, (8, 8), fill=np.inf)
    with pytest.raises(ValidationError, match="fill"):
        warp_mesh(np.zeros((8, 8, 3), np.uint8), src, src, (8, 8), fill=(1, 2))


def test_flipped_triangle_raises_foldover_with_indices():
    src = lattice(3, 3, 20, 20)
    dst = src.copy()
    dst[4] = [25.0, 25.0]  # centre vertex pushed past the opposite corner: triangles flip
    with pytest.raises(FoldOverError, match=r"fold over.*triangles \[") as exc:
        warp_mesh(np.zeros((20, 20)), src, dst, (20, 20))
    flipped = [int(s) for s in str(exc.value).split("[")[1].split("]")[0].split(", ")]
    tri = grid_triangles(3, 3)
    assert all(4 in tri[i] for i in flipped)


def test_zero_area_destination_triangle_raises():
    src = lattice(2, 2, 10, 10)  # triangles (0, 1, 3) and (0, 3, 2)
    dst = src.copy()
    dst[1] = dst[0] + (dst[3] - dst[0]) * 0.5  # vertex 1 onto the diagonal: triangle 0 collapses
    assert abs(cross2(dst[1] - dst[0], dst[3] - dst[0])) / 2 < tol.TRIANGLE_AREA_PX2
    with pytest.raises(FoldOverError, match=r"triangles \[0\]"):
        warp_mesh(np.zeros((10, 10)), src, dst, (10, 10))


def test_overlapping_triangles_raise_foldover():
    # two disjoint source triangles moved on top of each other, both keeping orientation
    src = np.array([[0, 0], [10, 0], [0, 10], [20, 0], [30, 0], [20, 10]], float)
    dst = src.copy()
    dst[3:] -= [19.0, 0.0]
    with pytest.raises(FoldOverError, match="overlap"):
        warp_mesh(np.zeros((12, 32)), src, dst, (12, 32), triangles=[[0, 2, 1], [3, 5, 4]])


def test_delaunay_rejects_collinear_points():
    with pytest.raises(ValidationError, match="2-D"):
        delaunay_triangles([[0, 0], [1, 1], [2, 2], [3, 3]])


# ----------------------------------------------------------- compiled vs numpy path
@pytest.mark.parametrize("shape, grid", [((512, 512), (5, 15)), ((97, 131), (4, 6)), ((200, 300), (17, 17))])
def test_compiled_maps_equal_numpy_reference(monkeypatch, shape, grid):
    """The numba scanline (default) and the numpy reference path cover exactly the
    same pixel centres and give the same source positions (up to float32 rounding
    of the numpy path's arithmetic)."""
    from morphkit import settings

    if not settings.NUMBA_AVAILABLE:
        pytest.skip("numba not importable: only the numpy path exists")
    rng = np.random.default_rng(sum(shape))
    h, w = shape
    rows, cols = grid
    gx, gy = np.meshgrid(np.linspace(0, w - 1, cols), np.linspace(0, h - 1, rows))
    src = np.c_[gx.ravel(), gy.ravel()]
    dst = src + rng.normal(0, min(h, w) / (12 * max(rows, cols)), src.shape)
    warper = MeshWarper(src)
    monkeypatch.setattr(settings, "NUMPY_ONLY", True)
    ref = warper.maps(dst, shape)
    monkeypatch.setattr(settings, "NUMPY_ONLY", False)
    fast = warper.maps(dst, shape)
    np.testing.assert_array_equal(fast.mask, ref.mask)
    r0, r1, c0, c1 = ref.roi
    inside = ref.mask[r0:r1, c0:c1]
    np.testing.assert_allclose(fast.map_xy[inside], ref.map_xy[inside], atol=1e-3)
    assert np.all(fast.map_xy[~inside] == ref.map_xy[~inside])


def _jittered_lattice(rng: np.random.Generator, xs: tuple[float, float, int],
                      ys: tuple[float, float, int], sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """``(src, dst)``: a row-major lattice ``linspace(*xs) x linspace(*ys)`` and
    the same points moved by Gaussian noise of ``sigma`` px."""
    gx, gy = np.meshgrid(np.linspace(*xs), np.linspace(*ys))
    src = np.c_[gx.ravel(), gy.ravel()]
    return src, src + rng.normal(0, sigma, src.shape)


@pytest.mark.parametrize("bands", [2, 3, 7])
def test_parallel_bands_change_no_value(monkeypatch, bands):
    """The compiled fill splits the rows into bands filled in parallel; each row
    depends only on the triangle edges, so any band count gives bit-identical maps
    and coverage (including the fold-over count on the band seams)."""
    from morphkit import settings
    from morphkit.warp import scanline

    if not settings.NUMBA_AVAILABLE:
        pytest.skip("numba not importable")
    src, dst = _jittered_lattice(np.random.default_rng(bands), (0, 299, 9), (0, 199, 6), 3.0)
    warper = MeshWarper(src)
    monkeypatch.setattr(scanline, "n_bands", lambda rows, cols: 1)
    one = warper.maps(dst, (200, 300))
    monkeypatch.setattr(scanline, "n_bands", lambda rows, cols: bands)
    many = warper.maps(dst, (200, 300))
    assert one.roi == many.roi
    np.testing.assert_array_equal(many.mask, one.mask)
    np.testing.assert_array_equal(many.map_xy, one.map_xy)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_compiled_setup_is_bit_identical_to_numpy(monkeypatch, seed):
    """The compiled per-call set-up (closed boundary, ROI, affines) gives the
    numpy reference's values bit for bit, so both paths cover the same pixels."""
    from morphkit import settings

    if not settings.NUMBA_AVAILABLE:
        pytest.skip("numba not importable")
    src, dst = _jittered_lattice(np.random.default_rng(seed), (-20, 330, 13), (5, 190, 8), 2.5)
    for warper in (MeshWarper(src), MeshWarper(src, delaunay_triangles(src))):
        src_v, sign, boundary, _ = mesh_setup(warper)
        args = (dst, warper.triangles, src_v, sign, boundary, (200, 300))
        monkeypatch.setattr(settings, "NUMPY_ONLY", False)
        fast = prepare(*args)
        monkeypatch.setattr(settings, "NUMPY_ONLY", True)
        ref = prepare(*args)
        assert fast[2] == ref[2]
        np.testing.assert_array_equal(fast[0], ref[0])
        np.testing.assert_array_equal(fast[1], ref[1])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_injective_fill_equals_counting_fill(monkeypatch, seed):
    """A disk mesh proved not to overlap is filled without counting coverage;
    forcing the counting fill gives bit-identical maps and mask."""
    from morphkit import settings
    from morphkit.warp import scanline

    if not settings.NUMBA_AVAILABLE:
        pytest.skip("numba not importable")
    src, dst = _jittered_lattice(np.random.default_rng(seed), (3, 296, 11), (2, 197, 7), 4.0)
    for warper in (MeshWarper(src), MeshWarper(src, delaunay_triangles(src))):
        src_v, sign, boundary, loop = mesh_setup(warper)
        assert loop is not None
        cov, _, _ = prepare(dst, warper.triangles, src_v, sign, boundary, (200, 300))
        assert scanline.mesh_injective(cov, warper.triangles.astype(np.int64), sign, loop)
        fast = warper.maps(dst, (200, 300))
        monkeypatch.setattr(scanline, "mesh_injective", lambda *a: False)
        ref = warper.maps(dst, (200, 300))
        monkeypatch.undo()
        assert fast.roi == ref.roi
        np.testing.assert_array_equal(fast.map_xy, ref.map_xy)
        np.testing.assert_array_equal(fast.mask, ref.mask)


def test_disk_boundary_recognises_disks_only():
    """The no-count fill is only allowed for meshes that are topological disks."""
    def loop(pts, tris):
        return disk_boundary(np.asarray(tris), mesh_setup(MeshWarper(pts, tris))[1])

    gx, gy = np.meshgrid(np.arange(4.0), np.arange(4.0))
    pts = np.c_[gx.ravel(), gy.ravel()] * 10
    tris = grid_triangles(4, 4)
    ring = loop(pts, tris)
    assert ring is not None and sorted(ring.tolist()) == [0, 1, 2, 3, 4, 7, 8, 11, 12, 13, 14, 15]
    # a hole: drop the two triangles of the middle cell (cells are row-major, 2 each)
    assert loop(pts, np.delete(tris, [8, 9], axis=0)) is None
    # two pieces: the first and the last cell only
    assert loop(pts, tris[[0, 1, 16, 17]]) is None
    # a bow-tie: two triangles sharing one vertex (the boundary passes it twice)
    bow = np.array([[0, 0], [10, 0], [5, 5], [10, 10], [0, 10]], float)
    assert loop(bow, [[0, 1, 2], [2, 3, 4]]) is None


def test_overlap_without_flips_is_found_on_a_disk():
    """A strip wound round so that its end lies on its start: no triangle flips,
    but the boundary crosses itself, so the fill counts coverage and refuses."""
    n = 24
    t = np.linspace(0.0, 1.0, n + 1)
    src = np.r_[np.c_[t * 400 + 20, np.full(n + 1, 20.0)], np.c_[t * 400 + 20, np.full(n + 1, 40.0)]]
    tris = np.array([[i, i + 1, n + 1 + i] for i in range(n)]
                    + [[i + 1, n + 2 + i, n + 1 + i] for i in range(n)])
    ang = t * 2.4 * np.pi  # more than a full turn
    inner, outer = 60.0, 80.0
    dst = np.r_[np.c_[150 + outer * np.cos(ang), 150 + outer * np.sin(ang)],
                np.c_[150 + inner * np.cos(ang), 150 + inner * np.sin(ang)]]
    warper = MeshWarper(src, tris)
    assert mesh_setup(warper)[3] is not None
    with pytest.raises(FoldOverError, match=r"overlap"):
        warper.maps(dst, (300, 300))


def test_compiled_path_reports_overlaps(monkeypatch):
    from morphkit import settings

    if not settings.NUMBA_AVAILABLE:
        pytest.skip("numba not importable")
    # two triangles with the same orientation stacked on top of each other
    src = np.array([[0, 0], [10, 0], [0, 10], [20, 0], [30, 0], [20, 10]], float)
    tris = np.array([[0, 1, 2], [3, 4, 5]])
    dst = src.copy()
    dst[3:] -= [20, 0]  # the second triangle moves onto the first
    with pytest.raises(FoldOverError, match=r"overlap.*triangles \[0, 1\].* both cover pixel"):
        warp_mesh(np.ones((12, 32), np.float32), src, dst, (12, 32), triangles=tris)
