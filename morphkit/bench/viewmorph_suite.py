"""Suite ``viewmorph``: view morphing against the billboard baselines, on rendered pairs.

Scenes. Each sample mesh, split into eight colour groups by a 3-D checker
(0.05 units) of its face centres (so the object has texture for SIFT and for PSNR/SSIM; the
renderer has no texture maps), is rendered as RGBA (alpha = coverage) by
cameras on a horizontal circle of radius 2.2 at height 1.0 looking at
``(0, 0, 0.25)``, 30-degree vertical field of view. The pair is centred on
azimuth 60 degrees (a three-quarter view of the teapot: spout and handle both
visible) with baselines of 10, 20, 40 and 60 degrees. The ground truth for ``s``
is the render from the camera on the circle at azimuth ``60 - b/2 + s b``.

Methods (all from the same two reference renders):

* ``viewmorph`` -- :class:`~morphkit.viewmorph.ViewMorpher` with geometric
  correspondences (mesh vertices visible in both views by the depth test, up
  to 600, F *estimated* from them), post-warp to the target camera (the
  least-squares homography from the morph's correspondences to their
  projections in that camera: the camera a billboard renderer knows);
* ``viewmorph-layered`` -- the same, with dense correspondences from the two
  depth maps (:func:`~morphkit.viewmorph.from_depth`: every 6th object pixel and
  every 2nd silhouette pixel of each view) and two depth layers
  (``layers=2``, keys from :func:`~morphkit.viewmorph.pair_depth`): what a
  billboard baker that renders its references has at hand;
* ``viewmorph-auto`` -- the same dense pairs with ``layers="auto"`` (two layers
  only when one mesh drops more than ``tol.VM_AUTO_LAYER_DROP`` of the pairs to
  fold-overs; the note says which);
* ``viewmorph-interp`` -- the same morpher with the default post-warp
  (interpolated between the two views; knows nothing of the target);
* ``viewmorph-images`` -- correspondences from the images alone
  (:func:`~morphkit.viewmorph.from_images`: SIFT and dense flow) + robust F,
  default post-warp, ``fallback="morph"`` (the build row's note says what was used);
* ``morph`` -- mesh morph of the same geometric correspondences without pre- or
  post-warp; ``crossfade`` -- premultiplied cross-dissolve;
  ``nearest`` -- the nearer reference image (a classic billboard).

Metrics: ``iou`` -- silhouette IoU (alpha > 0.5); ``psnr``/``ssim`` -- on the
premultiplied RGB (composited over black) over the union of both object masks
(data range 255); ``occluded`` -- fraction of the ground truth's object pixels
whose surface point is *not* visible in both references (what no
correspondence can carry); ``mae_occl``/``mae_vis`` -- mean absolute error
(grey levels, premultiplied RGB) over those pixels and over the others.
``err_iou = 1 - iou`` is plotted against time.

Timing: ``ms_*`` is one :meth:`ViewMorpher.morph` call (correspondences given,
the morpher built once per pair) or one baseline call, median of repeats at
256^2; rows with ``size`` 512 time the teapot at 20 degrees, ``s = 0.5``.
``viewmorph-build`` rows time the construction (``ViewMorpher.from_estimate``: the plan --
cleaning, F, pre-warps, mesh -- and the morpher applying it);
``viewmorph-layered-build`` rows that of the layered morpher (from the pairs and keys).
``--quick``: teapot only, baselines 20 and 40, ``s = 0.5``, sizes 256 and 512.

Image-only success rate (rows ``images``, ``images-sift``, ``images-depth``):
many pairs at 192^2 -- the three meshes, baselines 10, 20 and 40 degrees,
pairs centred on azimuths 0, 45, ..., 315 (8 per mesh and baseline; the views
of each pair at ``azimuth -/+ baseline/2``), ``s = 0.5``, ground truth the
render from the middle camera, default (interpolated) post-warp. Each row
aggregates the 8 pairs of one mesh and baseline:

* ``images`` -- the image-only path as a user runs it:
  ``ViewMorpher.from_estimate(i0, i1, from_images(i0, i1))`` (SIFT and dense flow, robust F,
  the affine F in place of a refused one), ``fallback="raise"``;
* ``images-sift`` -- the same with SIFT matches only, the matcher of before dense
  matching (``SiftMatcher(ratio=0.75, contrast_threshold=0.02, upscale=1)``),
  with the affine-F replacement;
* ``images-depth`` -- the same morpher on dense pairs from the two depth maps
  (:func:`~morphkit.viewmorph.from_depth`): what the image-only path is compared with.

Metrics: ``success`` -- fraction of the pairs morphed (not refused);
``iou``/``iou_min`` -- mean/min silhouette IoU of the successful ones against
the rendered middle view; ``iou_depth`` (``images`` rows) -- mean IoU of the
``images-depth`` morph on the same pairs; ``iou_crossfade`` -- mean IoU of the
cross-dissolve of the same (successful) pairs; ``affine`` -- pairs whose refused F
was replaced by the affine F; ``matches`` -- median pairs matched. Time: one
pair's matching, construction and morph (median over the pairs).
``--quick``: teapot, 20 degrees, azimuths 0, 90, 180, 270.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..camera import CameraModel
from ..errors import MorphkitError
from ..imaging.metrics import mean_abs_error, psnr, shadow_iou, ssim
from ..programs.fixtures import CENTRE_AZIMUTH, circle_camera, render_pair, textured_items
from ..protocols import SceneRenderer
from .harness import Timing, make_row, time_call

__all__ = ["run", "FLOOR_METHOD", "PLOT_OPTIONS"]

SUITE = "viewmorph"
#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "crossfade"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS: dict[str, Any] = {
    "error_key": "err_iou", "panel_keys": ("mesh",), "scene_keys": ("mesh", "baseline"),
    "defaults": ({"method": "viewmorph-auto", "s": 0.5, "size": 256},),
    "default_label": "default: viewmorph-auto (s = 0.5, 256²)"}

BASELINES = (10, 20, 40, 60)
SS = (0.25, 0.5, 0.75)
MESHES = ("teapot", "chair", "cow")
IMAGE_ONLY_BASELINES = (10, 20, 40)
IMAGE_ONLY_AZIMUTHS = tuple(float(a) for a in range(0, 360, 45))
IMAGE_ONLY_SIZE = 192
def _premul(img: np.ndarray) -> np.ndarray:
    return img[..., :3].astype(np.float64) * (img[..., 3:4] / 255.0)


def _quality(pred: np.ndarray, gt: np.ndarray, occl: np.ndarray) -> dict[str, float]:
    mp, mg = pred[..., 3] > 127, gt[..., 3] > 127
    union = mp | mg
    a, b = _premul(pred), _premul(gt)
    iou = shadow_iou(mp, mg)
    out = {"iou": iou, "err_iou": 1.0 - iou,
           "psnr": psnr(a, b, data_range=255.0, mask=union),
           "ssim": ssim(a, b, data_range=255.0, mask=union)}
    vis = mg & ~occl
    if occl.any():
        out["mae_occl"] = mean_abs_error(a, b, mask=occl)
    if vis.any():
        out["mae_vis"] = mean_abs_error(a, b, mask=vis)
    return out


def _finite(m: dict[str, float]) -> dict[str, float]:
    """Drop non-finite metrics (e.g. PSNR of identical images) so the JSON stays valid."""
    return {k: float(v) for k, v in m.items() if np.isfinite(v)}


def _occluded(cam: CameraModel, depth: np.ndarray, gt: np.ndarray, refs: list[tuple[CameraModel, np.ndarray]]
              ) -> np.ndarray:
    """Ground-truth object pixels whose surface point is not visible in every reference."""
    from ..viewmorph.correspondences import visible_in

    pts, valid = cam.unproject(depth)
    obj = valid & (gt[..., 3] > 127)
    idx = np.flatnonzero(obj)
    both = np.ones(idx.size, bool)
    for c, d in refs:
        _, vis = visible_in(c, pts.reshape(-1, 3)[idx], d)
        both &= vis
    occl = np.zeros(obj.size, bool)
    occl[idx[~both]] = True
    return occl.reshape(obj.shape)


def _case(renderer: SceneRenderer, name: str, mesh: Any, items: list[Any], base: float, ss: tuple[float, ...],
          size: int, repeats: int, rows: list[dict[str, Any]]) -> None:
    from ..viewmorph import (
        ViewMorpher,
        crossfade,
        from_depth,
        from_geometry,
        from_images,
        nearest,
        pair_depth,
    )

    a0, a1 = CENTRE_AZIMUTH - base / 2, CENTRE_AZIMUTH + base / 2
    c0, c1 = circle_camera(a0, size), circle_camera(a1, size)
    (i0, d0), (i1, d1) = render_pair(renderer, items, [c0, c1])
    corr = from_geometry(mesh, c0, c1, depth0=d0, depth1=d1, max_points=600,
                         rng=np.random.default_rng(0))
    morphers: dict[str, Any] = {}
    notes: dict[str, str] = {}
    build = time_call(lambda: ViewMorpher.from_estimate(i0, i1, corr), repeats=max(1, repeats // 2), warmup=0)
    vm = ViewMorpher.from_estimate(i0, i1, corr)
    morphers["viewmorph"] = morphers["viewmorph-interp"] = vm
    notes["viewmorph"] = notes["viewmorph-interp"] = (
        f"{vm.mode}/{vm.rectification.method}, {vm.report.n_used}/{len(corr)} pairs")
    dense = from_depth(c0, c1, d0, d1)
    keys = pair_depth(c0, c1, d0, d1)
    build_l = time_call(lambda: ViewMorpher.from_estimate(i0, i1, dense, layers=2, layer_depth=keys),
                        repeats=max(1, repeats // 2), warmup=0)
    vl = ViewMorpher.from_estimate(i0, i1, dense, layers=2, layer_depth=keys)
    morphers["viewmorph-layered"] = vl
    notes["viewmorph-layered"] = (f"{vl.mode}/{vl.rectification.method}, {vl.report.layers} layers, "
                                  f"{vl.report.n_used} mesh pairs from {len(dense)}")
    va = ViewMorpher.from_estimate(i0, i1, dense, layers="auto", layer_depth=keys)
    notes["viewmorph-auto"] = (f"{va.report.layers} layer(s): one mesh dropped "
                               f"{100 * va.report.auto_dropped_fraction:.2f}% of the pairs")
    morphers["morph"] = ViewMorpher.from_estimate(i0, i1, corr, prewarp="none")
    try:
        matched = from_images(i0, i1)
        vs = ViewMorpher.from_estimate(i0, i1, matched, fallback="morph")
        morphers["viewmorph-images"] = vs
        notes["viewmorph-images"] = (f"{vs.mode}/{vs.rectification.method}"
                                     f"{'' if vs.fit is None else ' F ' + vs.fit.method}, "
                                     f"{vs.report.n_used}/{len(matched)} matches used")
    except MorphkitError as exc:  # too few matches etc.: reported, not hidden
        notes["viewmorph-images"] = f"failed: {type(exc).__name__}: {str(exc)[:80]}"
    params0 = {"mesh": name, "baseline": base, "size": size}
    bm = {"y_rms_px": vm.rectification.y_rms, "anisotropy": vm.rectification.anisotropy}
    if vm.fit is not None:
        bm["sampson_rms_px"] = vm.fit.sampson_rms
    rows.append(make_row(SUITE, "viewmorph-build", dict(params0, s=-1.0), build, metrics=_finite(bm),
                         note=notes["viewmorph"] + "; images: " + notes["viewmorph-images"]))
    rows.append(make_row(SUITE, "viewmorph-layered-build", dict(params0, s=-1.0), build_l,
                         note=notes["viewmorph-layered"]))
    for s in ss:
        ct = circle_camera(a0 + s * base, size)
        ((gt, dg),) = render_pair(renderer, items, [ct])
        occl = _occluded(ct, dg, gt, [(c0, d0), (c1, d1)])
        calls = {
            "viewmorph": lambda s=s, ct=ct: vm.morph(s, post=ct, frame="fixed"),
            "viewmorph-layered": lambda s=s, ct=ct: vl.morph(s, post=ct, frame="fixed"),
            "viewmorph-auto": lambda s=s, ct=ct: va.morph(s, post=ct, frame="fixed"),
            "viewmorph-interp": lambda s=s: vm.morph(s),
            "morph": lambda s=s: morphers["morph"].morph(s),
            "crossfade": lambda s=s: crossfade(i0, i1, s),
            "nearest": lambda s=s: nearest(i0, i1, s),
        }
        if "viewmorph-images" in morphers:
            calls["viewmorph-images"] = lambda s=s: morphers["viewmorph-images"].morph(s)
        params = dict(params0, s=s)
        base_m = {"occluded": float(occl.sum() / max((gt[..., 3] > 127).sum(), 1))}
        for method in ("viewmorph", "viewmorph-layered", "viewmorph-auto", "viewmorph-interp",
                       "viewmorph-images", "morph", "crossfade", "nearest"):
            if method not in calls:
                continue  # (viewmorph-images failed: the build row's note says why)
            t = time_call(calls[method], repeats=repeats, warmup=1)
            m = _finite(dict(base_m, **_quality(calls[method](), gt, occl)))
            rows.append(make_row(SUITE, method, params, t, metrics=m, note=notes.get(method, "")))


def _image_only(renderer: SceneRenderer, name: str, items: list[Any], base: float,
                azimuths: tuple[float, ...], size: int, rows: list[dict[str, Any]]) -> None:
    """The ``images``/``images-sift``/``images-depth`` rows of one mesh and baseline."""
    import time

    from ..viewmorph import SiftMatcher, ViewMorpher, crossfade, from_depth, from_images

    sift = SiftMatcher(ratio=0.75, contrast_threshold=0.02, upscale=1)
    got: dict[str, list[dict[str, Any]]] = {"images": [], "images-sift": [], "images-depth": []}
    fade: dict[float, float] = {}
    for az in azimuths:
        c0, c1, ct = (circle_camera(a, size) for a in (az - base / 2, az + base / 2, az))
        (i0, d0), (i1, d1), (gt, _) = render_pair(renderer, items, [c0, c1, ct])
        fade[az] = shadow_iou(crossfade(i0, i1, 0.5)[..., 3] > 127, gt[..., 3] > 127)
        pairs = {"images": lambda i0=i0, i1=i1: from_images(i0, i1),
                 "images-sift": lambda i0=i0, i1=i1: from_images(i0, i1, matcher=sift),
                 "images-depth": lambda c0=c0, c1=c1, d0=d0, d1=d1: from_depth(c0, c1, d0, d1)}
        for method, make in pairs.items():
            t0 = time.perf_counter()
            corr = None
            try:
                corr = make()  # from_images refuses images with too few distinctive matches: a failure
                vm = ViewMorpher.from_estimate(i0, i1, corr)
                out = vm.morph(0.5)
            except MorphkitError as exc:
                got[method].append({"ok": False, "s": time.perf_counter() - t0, "az": az,
                                    "n": 0 if corr is None else len(corr), "why": type(exc).__name__})
                continue
            dt = time.perf_counter() - t0
            iou = shadow_iou(out[..., 3] > 127, gt[..., 3] > 127)
            got[method].append({"ok": True, "s": dt, "n": len(corr), "az": az, "iou": iou,
                                "affine": vm.report.affine is not None and vm.report.affine.used})
    params = {"mesh": name, "baseline": base, "size": size, "s": 0.5, "pairs": len(azimuths)}
    for method, res in got.items():
        ok = [r for r in res if r["ok"]]
        m: dict[str, float] = {"success": len(ok) / len(res), "affine": float(sum(r["affine"] for r in ok)),
                               "matches": float(np.median([r["n"] for r in res]))}
        if ok:
            m.update(iou=float(np.mean([r["iou"] for r in ok])), iou_min=float(min(r["iou"] for r in ok)))
            m["err_iou"] = 1.0 - m["iou"]
        if ok:
            m["iou_crossfade"] = float(np.mean([fade[r["az"]] for r in ok]))
        if method == "images" and ok:
            depth = {r["az"]: r for r in got["images-depth"] if r["ok"]}
            both = [depth[r["az"]]["iou"] for r in ok if r["az"] in depth]
            if both:
                m["iou_depth"] = float(np.mean(both))
        failed = [f"az {r['az']:g}: {r['why']}" for r in res if not r["ok"]]
        rows.append(make_row(SUITE, method, params, Timing.from_seconds([r["s"] for r in res]), metrics=m,
                             note="; ".join(failed)))


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """Run the suite; see the module docstring.

    Parameters
    ----------
    quick : bool
        Fewer and smaller cases (a smoke run).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    rows: list[dict[str, Any]] = []
    meshes = ("teapot",) if quick else MESHES
    bases = (20, 40) if quick else BASELINES
    ss = (0.5,) if quick else SS
    with Renderer() as r:
        for name in meshes:
            mesh, items = textured_items(name)
            for base in bases:
                _case(r, name, mesh, items, float(base), ss, 256, 5 if quick else 7, rows)
        mesh, items = textured_items("teapot")
        _case(r, "teapot", mesh, items, 20.0, (0.5,), 512, 5 if quick else 7, rows)
        for name in meshes:
            _, items = textured_items(name)
            for base in (20,) if quick else IMAGE_ONLY_BASELINES:
                azimuths = IMAGE_ONLY_AZIMUTHS[::2] if quick else IMAGE_ONLY_AZIMUTHS
                _image_only(r, name, items, float(base), azimuths, IMAGE_ONLY_SIZE, rows)
    return rows
