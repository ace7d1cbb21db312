"""The view morph of three reference views with depth: any in-between view, per pixel.

Seitz and Dyer's morph [1]_ of two views interpolates matched image positions (after
the pre-warp) and colours linearly; for views whose correspondences come from
geometry, the interpolated position of a surface point is its projection into the
in-between camera. With the references' depth maps this holds for any camera
near them, not only those on the chord between two centres, and for three views
around the viewing direction at once (:class:`~.dome.ViewDome`): every pixel of the
in-between view takes the surface point its ray meets, found in each reference's
depth, and its colour is the references' colours there blended by the
direction's barycentric weights -- the morph's linear colour interpolation, with
the positions exact instead of interpolated (warping images with depth, as McMillan's
3-D image warping [2]_).

Per reference ``k`` and target pixel (:func:`march_view`): the pixel's ray through
the bounding sphere is sampled at ``steps`` points; each is projected into view
``k`` and compared with ``k``'s depth there. The first sample at or behind ``k``'s
surface ends the march:

* **hit** -- the ray crossed ``k``'s surface between this sample and the one before: the
  sample lies at most :data:`THICKNESS_STEPS` steps behind the surface there (a ray that
  passes behind a part's outline is farther behind it); the crossing is refined (secant
  where the sample before saw a surface too, :data:`REFINE_STEPS` bisections, and a last
  secant between the bracket's ends);
* **occluded** -- the ray passed behind a nearer part's outline as ``k`` sees it: ``k``
  does not see the point (the other references fill it in);
* **free** -- no sample behind ``k``'s surface: ``k`` sees the ray's whole path as empty.

A ray passing from in front of a far surface to behind a nearer one (a gap between two
parts that ``k`` sees overlapping) lands far behind the nearer one: occluded, not hit,
so gaps another view sees through stay open (light views of
:mod:`morphkit.sunlit.sunatlas` rely on it).

The views' answers are combined (:func:`combine`): alpha is the weighted mean of the
hit views' coverage and the free views' zero (occluded views abstain); colour,
normal and depth come from the hit views whose point lies within
:data:`DEPTH_AGREE_STEPS` steps of the nearest hit, weighted. Pixels no view
answers are empty.

References
----------
.. [1] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.
.. [2] L. McMillan, "An Image-Based Approach to Three-Dimensional Computer Graphics",
   PhD thesis, UNC Chapel Hill, 1997 (warping images with depth).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from .gbuffer import ViewSurface

__all__ = ["ViewHits", "march_view", "combine", "morph_views", "plane_warp", "remap_points",
           "THICKNESS_STEPS",
           "DEPTH_AGREE_STEPS", "REFINE_STEPS", "steps_for"]

#: A first sample behind a reference's surface by more than this many march steps
#: (while the sample before it saw no surface there) is behind an outline: occluded.
THICKNESS_STEPS = 2.0
#: Hit views whose points lie within this many march steps of the nearest hit agree.
DEPTH_AGREE_STEPS = 3.0
#: Bisections after the secant estimate of a crossing.
REFINE_STEPS = 2

_FAR = np.float32(3.0e38)

#: Hit statuses.
FREE, HIT, OCCLUDED = 0, 1, 2


def steps_for(shape: tuple[int, int]) -> int:
    """March samples through the bounding sphere for an image of ``shape``: about one per
    three pixels across it, between 16 and 96. Fewer steps are a thicker surface (a crossing
    lies within :data:`THICKNESS_STEPS` of them): one per three pixels keeps thin parts'
    outlines, the last secant of the refinement keeping the depth close, for fewer samples
    than one per two; one per four loses outlines seen from low (measured:
    docs/results/billboards.md, "Billboards from any height").

    Parameters
    ----------
    shape : tuple of 2 int
        ``(h, w)`` of the target image.

    Returns
    -------
    int
        The number of samples.
    """
    return int(min(96, max(16, max(shape) // 3)))


@dataclass(frozen=True, eq=False)
class ViewHits:
    """What one reference says about each target ray.

    Parameters
    ----------
    status : (P,) int8
        ``FREE`` (0), ``HIT`` (1) or ``OCCLUDED`` (2).
    t : (P,) float32
        Ray parameter of the hit (scene units from the ray origin); ``inf`` where not hit.
    u, v : (P,) float32
        The hit's pixel in the reference (valid where hit).
    """

    status: np.ndarray
    t: np.ndarray
    u: np.ndarray
    v: np.ndarray


def _project(A: np.ndarray, B: np.ndarray, t: np.ndarray, cam: CameraModel
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    c = A + t[:, None] * B
    z = c[:, 2]
    if cam.projection == "orthographic":
        return ((cam.fx * c[:, 0] + cam.cx).astype(np.float32),
                (cam.fy * c[:, 1] + cam.cy).astype(np.float32), z)
    zs = np.where(z > 0, z, np.float32(1.0))
    return ((cam.fx * c[:, 0] / zs + cam.cx).astype(np.float32),
            (cam.fy * c[:, 1] / zs + cam.cy).astype(np.float32), z)


#: Columns of the 2-D maps point lists are laid out in for ``cv2.remap`` (whose images and
#: maps must stay under ``SHRT_MAX`` on a side).
_MAP_COLS = 4096


def remap_points(img: np.ndarray, u: np.ndarray, v: np.ndarray, flag: int, border: float) -> np.ndarray:
    """``img`` read at the points ``(u, v)`` by ``cv2.remap`` (the points laid out in rows of
    4096, since its maps must stay under ``SHRT_MAX`` a side).

    Parameters
    ----------
    img : (h, w) or (h, w, C) float32
        The image.
    u, v : (P,) float32
        Column and row of each point (pixel centres at integers).
    flag : int
        ``cv2.INTER_NEAREST`` or ``cv2.INTER_LINEAR``.
    border : float
        The value outside the image (``cv2.BORDER_CONSTANT``).

    Returns
    -------
    (P, C) float32
        ``C = 1`` for a one-channel image.
    """
    p = len(u)
    rows = max(1, -(-p // _MAP_COLS))
    cols = min(p, _MAP_COLS) if p else 1
    mu = np.full(rows * cols, -1.0e6, np.float32)
    mv = np.full(rows * cols, -1.0e6, np.float32)
    mu[:p], mv[:p] = u, v
    out = cv2.remap(img, mu.reshape(rows, cols), mv.reshape(rows, cols), flag,
                    borderMode=cv2.BORDER_CONSTANT, borderValue=border)
    return out.reshape(rows * cols, -1)[:p]


def _lookup(depth: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return remap_points(depth, u, v, cv2.INTER_NEAREST, float(_FAR)).reshape(-1)


def march_view(origins: np.ndarray, dirs: np.ndarray, t0: np.ndarray, t1: np.ndarray,
               camera: CameraModel, depth: np.ndarray, steps: int) -> ViewHits:
    """March rays through one reference's depth map (module docstring).

    Parameters
    ----------
    origins, dirs : (P, 3) float32
        Ray origins and unit directions, in the reference camera's world (object) frame.
    t0, t1 : (P,) float32
        The ray's span inside the bounding sphere (``t0 < t1``).
    camera : CameraModel
        The reference's camera (perspective or orthographic).
    depth : (h, w) float32
        Its linear depth, ``+inf`` where nothing is drawn.
    steps : int
        Samples per ray (:func:`steps_for`).

    Returns
    -------
    ViewHits
        Per ray.
    """
    R = camera.cam2world[:3, :3].astype(np.float32)
    C = camera.cam2world[:3, 3].astype(np.float32)
    A = (origins - C) @ R  # camera-frame origin
    B = dirs @ R
    dmap = np.where(np.isfinite(depth), depth, _FAR).astype(np.float32)
    p = len(t0)
    dt = (t1 - t0) / np.float32(steps - 1)
    status = np.zeros(p, np.int8)
    t_hit = np.full(p, np.inf, np.float32)
    done = np.zeros(p, bool)
    prev_f = np.full(p, -np.inf, np.float32)  # sample depth minus surface depth (negative: in front)
    prev_t = t0.copy()
    thick = np.float32(THICKNESS_STEPS) * dt
    for i in range(steps):
        t = t0 + np.float32(i) * dt
        u, v, z = _project(A, B, t, camera)
        d = _lookup(dmap, u, v)
        f = np.where(d < _FAR, z - d, np.float32(-np.inf)).astype(np.float32)
        behind = (f >= 0) & ~done
        if behind.any():
            crossed = behind & (f <= thick)
            status[behind] = np.where(crossed[behind], HIT, OCCLUDED)
            # secant between the previous sample and this one where both saw a surface
            both = crossed & np.isfinite(prev_f)
            with np.errstate(invalid="ignore"):  # -inf - -inf where not both: masked out
                frac = np.where(both, -prev_f / np.where(both, f - prev_f, np.float32(1.0)), np.float32(1.0))
            t_hit[crossed] = (prev_t + np.clip(frac, 0.0, 1.0) * (t - prev_t))[crossed]
            done |= behind
            if done.all():
                break
        prev_f = np.where(done, prev_f, f)
        prev_t = t
    hit = status == HIT
    idx = np.flatnonzero(hit)
    if len(idx):
        lo = np.maximum(t_hit[idx] - dt[idx], t0[idx])
        hi = t_hit[idx] + np.float32(0.5) * dt[idx]
        f_lo = np.full(len(idx), np.nan, np.float32)  # sample minus surface depth at lo, hi
        f_hi = np.full(len(idx), np.nan, np.float32)
        for _ in range(REFINE_STEPS):
            mid = np.float32(0.5) * (lo + hi)
            u, v, z = _project(A[idx], B[idx], mid, camera)
            d = _lookup(dmap, u, v)
            behind = (d < _FAR) & (z >= d)
            f = np.where(d < _FAR, z - d, np.float32(np.nan)).astype(np.float32)
            hi, f_hi = np.where(behind, mid, hi), np.where(behind, f, f_hi)
            lo, f_lo = np.where(behind, lo, mid), np.where(behind, f_lo, f)
        # last, the secant between the bracket's ends where both saw the surface
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = -f_lo / (f_hi - f_lo)
        ok = np.isfinite(frac) & (frac >= 0) & (frac <= 1)
        t_hit[idx] = np.where(ok, lo + np.where(ok, frac, 1.0) * (hi - lo), hi)
    u, v, _ = _project(A, B, np.where(hit, t_hit, t0), camera)
    return ViewHits(status, t_hit, u, v)


def _sample(img: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return remap_points(img, u, v, cv2.INTER_LINEAR, 0.0)


def combine(hits: Sequence[ViewHits], surfaces: Sequence[ViewSurface], weights: Sequence[float],
            dt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The views' answers per ray, put together (module docstring).

    Parameters
    ----------
    hits : sequence of ViewHits
        :func:`march_view` of each reference.
    surfaces : sequence of ViewSurface
        The references' surfaces (same order).
    weights : sequence of float
        Their barycentric weights (same order, positive).
    dt : (P,) float32
        March step per ray.

    Returns
    -------
    albedo : (P, 4) float32
        Premultiplied linear albedo and alpha.
    normal : (P, 3) float32
        Unit normals (0 where empty).
    t : (P,) float32
        Ray parameter of the surface shown (``inf`` where empty).
    covered : (P,) bool
        Rays some view hit.
    """
    p = len(dt)
    t_all = np.stack([h.t for h in hits])  # (V, P)
    t_min = t_all.min(axis=0)
    w = np.asarray(weights, np.float32)[:, None]
    agree = np.isfinite(t_all) & (t_all <= t_min + np.float32(DEPTH_AGREE_STEPS) * dt)
    col = np.zeros((p, 3), np.float32)
    nrm = np.zeros((p, 3), np.float32)
    a_num = np.zeros(p, np.float32)
    a_den = np.zeros(p, np.float32)
    c_den = np.zeros(p, np.float32)
    for k, (h, s) in enumerate(zip(hits, surfaces, strict=True)):
        hit = h.status == HIT
        free = h.status == FREE
        idx = np.flatnonzero(hit)
        wk = w[k, 0]
        a_den += np.where(hit | free, wk, np.float32(0.0))
        if len(idx) == 0:
            continue
        alb = _sample(s.albedo, h.u[idx], h.v[idx])
        a = alb[:, 3]
        a_num[idx] += wk * a
        use = agree[k, idx] & (a > tol.ALPHA_FLOOR)
        j = idx[use]
        straight = alb[use, :3] / a[use, None]
        col[j] += wk * straight
        nrm[j] += wk * _sample(s.normal, h.u[j], h.v[j])
        c_den[j] += wk
    covered = c_den > 0
    alpha = np.where(covered & (a_den > 0), a_num / np.maximum(a_den, np.float32(tol.ALPHA_FLOOR)),
                     np.float32(0.0))
    col = np.where(covered[:, None], col / np.maximum(c_den, np.float32(tol.ALPHA_FLOOR))[:, None], 0.0)
    norm = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.where(norm > 0, nrm / np.maximum(norm, np.float32(tol.ALPHA_FLOOR)), 0.0)
    albedo = np.concatenate([col * alpha[:, None], alpha[:, None]], axis=1).astype(np.float32)
    return albedo, nrm.astype(np.float32), np.where(covered, t_min, np.float32(np.inf)), covered


def morph_views(target: CameraModel, pivot: np.ndarray, radius: float,
                views: Sequence[tuple[CameraModel, ViewSurface, float]], *, steps: int | None = None
                ) -> ViewSurface:
    """The surface ``target`` sees, morphed from the weighted references ``views``.

    Parameters
    ----------
    target : CameraModel
        The in-between view (object frame), perspective or orthographic.
    pivot : (3,) float
        Bounding sphere centre, object frame.
    radius : float
        Bounding sphere radius.
    views : sequence of (CameraModel, ViewSurface, float)
        Each reference's camera (same image shape as its surface), surface and weight
        (weights > 0; they need not sum to 1).
    steps : int, optional
        March samples per ray (default :func:`steps_for` the target's shape; a target larger than
        the object's image, e.g. a whole screen, passes the object's own on-screen size's).

    Returns
    -------
    ViewSurface
        Of ``target.shape``; depth along ``target``'s axis.
    """
    h, w = target.shape
    o, d = target.rays()
    o = o.reshape(-1, 3)
    d = d.reshape(-1, 3)
    oc = o - pivot
    b = np.einsum("ij,ij->i", d, oc)
    c = np.einsum("ij,ij->i", oc, oc) - radius * radius
    disc = b * b - c
    inside = np.flatnonzero(disc > 0)
    albedo = np.zeros((h * w, 4), np.float32)
    normal = np.zeros((h * w, 3), np.float32)
    depth = np.full(h * w, np.inf, np.float32)
    if len(inside) and views:
        sq = np.sqrt(disc[inside])
        t0 = np.maximum(-b[inside] - sq, 0.0).astype(np.float32)
        t1 = (-b[inside] + sq).astype(np.float32)
        oi, di = o[inside].astype(np.float32), d[inside].astype(np.float32)
        steps = steps_for(target.shape) if steps is None else int(max(2, steps))
        hits = [march_view(oi, di, t0, t1, cam, s.depth, steps) for cam, s, _ in views]
        dt = (t1 - t0) / np.float32(steps - 1)
        alb, nrm, t, covered = combine(hits, [s for _, s, _ in views], [wt for _, _, wt in views], dt)
        albedo[inside] = alb
        normal[inside] = nrm
        axis = target.cam2world[:3, 2]
        pts_depth = (oi - target.cam2world[:3, 3]) @ axis + t * (di @ axis)
        depth[inside] = np.where(covered, pts_depth, np.inf)
    return ViewSurface(albedo.reshape(h, w, 4), normal.reshape(h, w, 3), depth.reshape(h, w))


def plane_warp(target: CameraModel, view: CameraModel, pivot: np.ndarray,
               surface: ViewSurface) -> ViewSurface:
    """``surface`` (seen by ``view``) moved into ``target``'s frame through the plane through
    ``pivot`` facing ``view``: the card of an impostor without parallax (the baselines).

    Parameters
    ----------
    target : CameraModel
        The in-between view, object frame.
    view : CameraModel
        The reference's camera (its image shape is the surface's).
    pivot : (3,) float
        A point of the card's plane, object frame.
    surface : ViewSurface
        The reference's surface.

    Returns
    -------
    ViewSurface
        Of ``target.shape`` (depth: the reference's, as drawn on the card).
    """
    h, w = target.shape
    corners = np.array([[0.0, 0.0], [w - 1.0, 0.0], [w - 1.0, h - 1.0], [0.0, h - 1.0]])
    o, d = target.rays()
    idx = corners.astype(int)
    ro, rd = o[idx[:, 1], idx[:, 0]], d[idx[:, 1], idx[:, 0]]
    n = view.cam2world[:3, 2]
    t = ((np.asarray(pivot) - ro) @ n) / np.where(np.abs(rd @ n) > tol.PARALLEL_DOT, rd @ n, tol.PARALLEL_DOT)
    px, _ = view.project(ro + t[:, None] * rd)
    H = cv2.getPerspectiveTransform(corners.astype(np.float32), px.astype(np.float32))
    flags = cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP
    alb = cv2.warpPerspective(surface.albedo, H, (w, h), flags=flags, borderMode=cv2.BORDER_CONSTANT)
    nrm = cv2.warpPerspective(surface.normal, H, (w, h), flags=flags, borderMode=cv2.BORDER_CONSTANT)
    big = np.where(np.isfinite(surface.depth), surface.depth, _FAR).astype(np.float32)
    dep = cv2.warpPerspective(big, H, (w, h), flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_CONSTANT, borderValue=float(_FAR))
    norm = np.linalg.norm(nrm, axis=-1, keepdims=True)
    nrm = np.where(norm > 0, nrm / np.maximum(norm, np.float32(tol.ALPHA_FLOOR)), 0.0).astype(np.float32)
    return ViewSurface(alb.astype(np.float32), nrm, np.where(dep >= _FAR, np.inf, dep).astype(np.float32))
