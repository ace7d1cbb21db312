"""Property-based tests: the numpy entry points with generated arrays (issue 28).

Images of every size from 1 x 1 up, every dtype and channel count (those the
API accepts and those it should refuse), NaN/inf/huge values; point sets that
are too few, duplicated, collinear or outside the image; cameras and poses that
are singular, NaN or behind. The property (props.outcome): valid output of the
promised shape and dtype, finite where promised -- or a MorphkitError; never a
raw exception, a hang or NaN output.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from props import outcome

from morphkit.camera import CameraModel, look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.composite import over, shade, to_premultiplied
from morphkit.imaging.metrics import mean_abs_error, psnr, rmse, shadow_iou, ssim
from morphkit.scene import DirectionalLight, PointLight, light_view
from morphkit.shadow.lookup import shadow_visibility
from morphkit.viewmorph import Correspondences, plan_view_morph
from morphkit.warp import warp_mesh

DTYPES = ["uint8", "uint16", "int8", "int32", "int64", "float16", "float32", "float64", "bool",
          "complex64"]
SPECIAL = [np.nan, np.inf, -np.inf, 1e300, -1e300, 3e38, 0.0, -0.0, 1e-300]

sizes = st.integers(1, 12)


def mostly(good: st.SearchStrategy, bad: st.SearchStrategy) -> st.SearchStrategy:
    """``good`` three times in four, else ``bad``: cases that change one thing at a time."""
    return st.integers(0, 3).flatmap(lambda i: bad if i == 0 else good)
#: Numbers: mostly ordinary, sometimes special (NaN, infinities, huge, tiny, negative zero).
reals = st.floats(-10, 10) | st.floats(0.01, 5) | st.sampled_from(SPECIAL) | st.floats()


@st.composite
def images(draw: st.DrawFn, *, dtypes: list[str] = DTYPES,
           channels: tuple[int | None, ...] = (None, 1, 2, 3, 4, 5),
           shape: tuple[int, int] | None = None, special: bool = True) -> np.ndarray:
    """An image of any size (1 x 1 up), dtype and channel count, with special values sometimes."""
    h, w = shape or (draw(sizes), draw(sizes))
    c = draw(st.sampled_from(channels))
    dt = np.dtype(draw(st.sampled_from(dtypes)))
    full = (h, w) if c is None else (h, w, c)
    if dt.kind == "f" and special and draw(st.booleans()):
        img = draw(hnp.arrays(dt, full, elements=st.floats(width=dt.itemsize * 8, allow_nan=True,
                                                           allow_infinity=True)))
    elif dt.kind == "f":
        img = draw(hnp.arrays(dt, full, elements=st.floats(0, 1, width=dt.itemsize * 8)))
    elif dt.kind == "c":
        img = np.zeros(full, dt)
    else:
        img = draw(hnp.arrays(dt, full))
    return img


def _finite_if_input_finite(out: np.ndarray, *inputs: np.ndarray) -> None:
    if out.dtype.kind == "f" and all(np.isfinite(a).all() for a in inputs if a.dtype.kind == "f"):
        assert not np.isnan(out).any()


# =================================================================== warp_mesh
@st.composite
def point_sets(draw: st.DrawFn, n_max: int = 12, extent: float = 12.0) -> np.ndarray:
    """Point sets: random, too few, duplicated, collinear, outside the image, with NaN/inf."""
    how = draw(st.sampled_from(["grid", "random", "few", "grid", "duplicate", "collinear", "outside",
                                "special", "grid"]))
    n = draw(st.integers(0 if how == "few" else 3, 2 if how == "few" else n_max))
    coords = st.floats(-2.0, extent + 2.0)
    pts = np.array(draw(st.lists(st.tuples(coords, coords), min_size=n, max_size=n)), float).reshape(-1, 2)
    if how == "duplicate" and len(pts):
        pts[1:] = pts[0]
    elif how == "collinear" and len(pts):
        pts[:, 1] = 2.0 * pts[:, 0] + 1.0
    elif how == "outside" and len(pts):
        pts *= draw(st.sampled_from([100.0, -100.0, 1e9]))
    elif how == "special" and len(pts):
        pts[draw(st.integers(0, len(pts) - 1)), draw(st.integers(0, 1))] = draw(st.sampled_from(SPECIAL))
    elif how == "grid":
        g = np.linspace(0, extent - 1, 3)
        pts = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    return pts


@given(image=images(), src=point_sets(), jitter=st.floats(-3, 3), dst=st.none() | point_sets(),
       out_shape=st.tuples(st.integers(-1, 16), st.integers(-1, 16))
       | st.sampled_from([(0, 0), (1, 1), (3,)]),
       interpolation=st.sampled_from(["linear", "nearest", "cubic"]), return_mask=st.booleans())
def test_warp_mesh(image, src, jitter, dst, out_shape, interpolation, return_mask):
    dst = src + jitter if dst is None else dst
    ok, out = outcome(warp_mesh, image, src, dst, out_shape, interpolation=interpolation,
                      return_mask=return_mask)
    if ok:
        warped, mask = out if return_mask else (out, None)
        assert warped.shape[:2] == tuple(out_shape) and warped.shape[2:] == image.shape[2:]
        assert warped.dtype == image.dtype
        _finite_if_input_finite(warped, image)
        if mask is not None:
            assert mask.shape == tuple(out_shape) and mask.dtype == bool


# =================================================================== composite
@given(lit=images(channels=(3, 4, None)), unlit=images(channels=(3, 4, None)),
       vis=images(dtypes=["float32", "float64", "uint8", "bool"], channels=(None, 1)))
def test_shade(lit, unlit, vis):
    ok, out = outcome(shade, lit, unlit, vis)
    if ok:
        assert out.shape == lit.shape and out.dtype == np.uint8


@given(image=images(), channels=st.integers(-1, 6))
def test_to_premultiplied(image, channels):
    ok, out = outcome(to_premultiplied, image, channels)
    if ok:
        assert out.dtype == np.float32 and out.shape[:2] == image.shape[:2]
        assert np.isfinite(out).all()


def test_to_premultiplied_refuses_an_alpha_beyond_its_range():
    """Found by the property above: a float alpha of 2 times a colour near float32's largest
    value overflowed to inf (and an alpha of 2 was returned as is)."""
    image = np.zeros((2, 2, 4))
    image[..., 0], image[..., 3] = 3e38, 2.0
    with pytest.raises(ValidationError, match=r"image alpha: expected values in \[0, 1\], got 2 to 2"):
        to_premultiplied(image, 4)
    image[..., 3] = 1.0
    assert np.isfinite(to_premultiplied(image, 4)).all()


@given(out=st.none() | images(dtypes=["float32", "float64"], channels=(2, 4), shape=(8, 8)),
       part=images(dtypes=["float32", "float64", "uint8"], channels=(2, 4, None)),
       r0=st.integers(-2, 9), c0=st.integers(-2, 9))
def test_over(out, part, r0, c0):
    roi = (r0, r0 + part.shape[0], c0, c0 + part.shape[1])
    ok, res = outcome(over, None if out is None else out.copy(), part, roi, (8, 8))
    if ok:
        assert res.shape[:2] == (8, 8)


# =================================================================== metrics
_metric_images = images(dtypes=["float32", "float64", "uint8", "int32", "bool"], channels=(None, 3),
                        shape=(5, 6))


@given(a=_metric_images, b=_metric_images,
       mask=st.none() | hnp.arrays(bool, st.sampled_from([(5, 6), (5,), (5, 6, 3)])),
       data_range=reals, metric=st.sampled_from(["mae", "rmse", "psnr", "ssim", "iou"]))
def test_metrics(a, b, mask, data_range, metric):
    fn = {"mae": lambda: mean_abs_error(a, b, mask), "rmse": lambda: rmse(a, b, mask),
          "psnr": lambda: psnr(a, b, data_range=data_range, mask=mask),
          "ssim": lambda: ssim(a, b, data_range=data_range, mask=mask),
          "iou": lambda: shadow_iou(a, b, mask)}[metric]
    ok, v = outcome(fn)
    if ok:
        assert isinstance(v, float) and not np.isnan(v)
        if metric != "psnr":
            assert np.isfinite(v)


@given(size=st.tuples(sizes, sizes), metric=st.sampled_from([ssim, psnr]))
def test_metrics_every_size(size, metric):
    a = np.linspace(0, 1, size[0] * size[1]).reshape(size)
    ok, v = outcome(metric, a, a[::-1].copy(), data_range=1.0)
    if ok:
        assert not np.isnan(v)


# =================================================================== cameras, poses, lights
poses = st.one_of(
    st.just(np.eye(4)),
    st.builds(lambda e: look_at(np.array(e), np.zeros(3)),
              st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(1, 5))),
    hnp.arrays(np.float64, (4, 4), elements=reals),
    st.sampled_from([np.zeros((4, 4)), np.diag([1.0, 1.0, -1.0, 1.0]), np.diag([2.0, 2.0, 2.0, 1.0]),
                     np.eye(3), np.eye(4)[:3]]),
)


@given(projection=mostly(st.sampled_from(["perspective", "orthographic"]), st.just("fisheye")),
       shape=mostly(st.tuples(sizes, sizes), st.tuples(st.integers(-1, 9), st.integers(-1, 9))),
       f=st.tuples(mostly(st.floats(0.5, 50), reals), mostly(st.floats(0.5, 50), reals)),
       c=st.tuples(mostly(st.floats(-5, 15), reals), mostly(st.floats(-5, 15), reals)),
       z=mostly(st.tuples(st.floats(0.01, 1), st.floats(2, 100)), st.tuples(reals, reals)), pose=poses)
def test_camera_model(projection, shape, f, c, z, pose):
    ok, cam = outcome(CameraModel, projection, shape, f[0], f[1], c[0], c[1], z[0], z[1], pose)
    if ok:
        ok, res = outcome(cam.project, np.array([[0.0, 0.0, 1.0], [0.3, -0.2, 2.0]]))
        if ok:
            px, depth = res
            assert px.shape == (2, 2) and depth.shape == (2,)


@given(eye=hnp.arrays(np.float64, 3, elements=reals), target=hnp.arrays(np.float64, 3, elements=reals),
       up=st.none() | hnp.arrays(np.float64, 3, elements=reals), same=st.booleans())
def test_look_at(eye, target, up, same):
    ok, pose = outcome(look_at, eye, eye if same else target, up)
    if ok:
        assert pose.shape == (4, 4) and np.isfinite(pose).all()


@given(yfov=reals | st.floats(0.01, 3.1), shape=st.tuples(st.integers(-1, 9), st.integers(-1, 9)), pose=poses)
def test_perspective(yfov, shape, pose):
    ok, cam = outcome(perspective, yfov, shape, pose)
    if ok:
        assert np.isfinite(cam.K).all()


@given(kind=st.sampled_from([DirectionalLight, PointLight]),
       v=mostly(st.builds(np.array, st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(2, 5))),
                hnp.arrays(np.float64, st.sampled_from([3, 2, 4]), elements=reals)),
       points=mostly(point_sets(n_max=6),
                     hnp.arrays(np.float64, st.tuples(st.integers(0, 6), st.integers(2, 4)), elements=reals)),
       shape=mostly(st.tuples(sizes, sizes), st.tuples(st.integers(-1, 9), st.integers(-1, 9))),
       margin=mostly(st.floats(0, 0.5), reals))
def test_light_view(kind, v, points, shape, margin):
    ok, light = outcome(kind, v)
    if not ok:
        return
    if points.shape[1:] == (2,):
        points = np.concatenate([points, np.full((len(points), 1), 0.5)], axis=1)
    ok, cam = outcome(light_view, light, points, shape, margin=margin)
    if ok:
        assert cam.shape == tuple(shape) and np.isfinite(cam.cam2world).all()
        assert np.isfinite([cam.fx, cam.fy, cam.cx, cam.cy, cam.znear, cam.zfar]).all()


@given(points=hnp.arrays(np.float64, st.tuples(st.integers(0, 6), st.integers(2, 4)), elements=reals),
       depth=images(dtypes=["float32", "float64", "float16", "uint8"], channels=(None, 1)),
       normals=st.none() | hnp.arrays(np.float64, st.tuples(st.integers(0, 6), st.just(3)), elements=reals))
def test_shadow_visibility(points, depth, normals):
    cam = perspective(1.0, depth.shape[:2], look_at(np.array([0.0, 0.0, 3.0]), np.zeros(3)))
    ok, vis = outcome(shadow_visibility, points, depth, cam, normals=normals)
    if ok:
        assert vis.shape == (len(points),) and vis.dtype == np.float32
        assert np.isfinite(vis).all() and ((vis >= 0) & (vis <= 1)).all()


# =================================================================== view morph
@st.composite
def correspondences(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    p0 = draw(point_sets(n_max=14, extent=16.0))
    how = draw(st.sampled_from(["shift", "other", "same", "count"]))
    if how == "shift":
        p1 = p0 + np.array([draw(st.floats(-3, 3)), 0.0])
    elif how == "other":
        p1 = draw(point_sets(n_max=14, extent=16.0))
    elif how == "same":
        p1 = p0.copy()
    else:
        p1 = p0[: max(0, len(p0) - 1)]
    return p0, p1


@given(image0=images(dtypes=["uint8", "uint16", "float32", "float64", "int32", "bool"],
                     channels=(None, 3, 4, 2), special=False),
       same_shape=st.booleans(), corr=correspondences(),
       prewarp=st.sampled_from(["auto", "opencv", "seitz-dyer", "none", "other"]),
       fallback=st.sampled_from(["raise", "morph"]), layers=st.sampled_from([1, 2, "auto", 0]))
def test_plan_view_morph(image0, same_shape, corr, prewarp, fallback, layers):
    image1 = image0.copy() if same_shape else np.ascontiguousarray(image0[::-1])
    ok, plan = outcome(plan_view_morph, image0, image1, corr, prewarp=prewarp, fallback=fallback,
                       layers=layers)
    if ok:
        from morphkit.viewmorph import ViewMorpher

        ok, morpher = outcome(ViewMorpher, plan)
        if ok:
            ok, img = outcome(morpher.morph, 0.5)
            if ok:
                assert img.ndim in (2, 3) and not (img.dtype.kind == "f" and np.isnan(img).any())


@given(p0=hnp.arrays(np.float64, st.tuples(st.integers(0, 5), st.integers(1, 3)), elements=reals),
       p1=hnp.arrays(np.float64, st.tuples(st.integers(0, 5), st.integers(1, 3)), elements=reals))
def test_correspondences(p0, p1):
    ok, c = outcome(Correspondences, p0, p1, "user")
    if ok:
        ok, res = outcome(c.cleaned)
        if ok:
            cleaned, _ = res
            assert np.isfinite(cleaned.pts0).all() and np.isfinite(cleaned.pts1).all()
