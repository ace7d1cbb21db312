"""The morph mesh in the rectified frame: frame points, Delaunay at s = 1/2, fold-overs, and the
rectified canvas the mesh covers (:func:`mesh_canvas`).

The morph mesh
--------------
Vertices are the (inlier, de-duplicated) correspondences plus *frame points*: a
``frame_grid x frame_grid`` lattice over the rectified canvas (the bounding box
of both rectified images, grown by a margin), whose outer ring always stays and
whose inner points are dropped near the correspondences. Frame points move by
the median disparity of the correspondences (the background behaves like a
fronto-parallel plane at the object's median depth). Triangles: Delaunay of the
vertices at ``s = 1/2``. **Fold-overs**: a triangle whose signed area reaches
:data:`tol.VM_MIN_TRIANGLE_AREA_PX2` for some ``s`` in ``[0, 1]`` (checked
exactly: the area is quadratic in ``s``) loses a vertex -- an inner frame point
if it has one, else the correspondence whose disparity deviates most from its
neighbours' median -- and the mesh is re-triangulated, until none folds (the
number dropped is reported in ``MorphReport.n_dropped_foldover``).
"""

from __future__ import annotations

import numpy as np

from .. import tol
from ..errors import DegenerateViewError, FoldOverError, expected_got
from ..warp import delaunay_triangles
from .images import image_corners
from .rectify import apply_h

__all__ = ["build_morph_mesh", "min_area_over_s", "mesh_canvas"]


def min_area_over_s(r0: np.ndarray, r1: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Minimum over s in [0, 1] of the signed area of each triangle of ``(1 - s) r0 + s r1``,
    signed so that positive means "oriented as at s = 1/2".

    The area is quadratic in ``s``: its minimum is exact (the ends and the
    vertex of the parabola when it lies inside).

    Parameters
    ----------
    r0, r1 : (V, 2) float
        Vertex positions at ``s = 0`` and ``s = 1`` (one frame, e.g. rectified).
    tris : (M, 3) int
        Triangles indexing the vertices.

    Returns
    -------
    numpy.ndarray
        ``(M,)`` float64 minimum signed areas (square pixels of that frame);
        ``<= 0`` means the triangle folds over for some ``s``.
    """
    a = r0[tris]
    b = r1[tris] - r0[tris]
    u0, w0 = a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]
    u1, w1 = b[:, 1] - b[:, 0], b[:, 2] - b[:, 0]

    def cr(p: np.ndarray, q: np.ndarray) -> np.ndarray:
        return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]

    c0 = cr(u0, w0)
    c1 = cr(u0, w1) + cr(u1, w0)
    c2 = cr(u1, w1)
    sign = np.sign(c0 + 0.5 * c1 + 0.25 * c2)
    sign[sign == 0] = 1.0
    c0, c1, c2 = c0 * sign, c1 * sign, c2 * sign
    vals = [c0, c0 + c1 + c2]
    with np.errstate(divide="ignore", invalid="ignore"):
        sv = np.where(c2 > 0, -c1 / (2 * c2), -1.0)
    inside = (sv > 0) & (sv < 1)
    vals.append(np.where(inside, c0 + c1 * sv + c2 * sv * sv, np.inf))
    return 0.5 * np.min(np.stack(vals), axis=0)


def build_morph_mesh(r0c: np.ndarray, r1c: np.ndarray, bbox: tuple[np.ndarray, np.ndarray], grid: int,
                depth: np.ndarray | None = None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """Frame points + correspondences, Delaunay at s = 1/2, fold-over cleanup (module docstring).

    Parameters
    ----------
    r0c, r1c : (N, 2) float
        The correspondences' rectified positions from image 0 and image 1.
    bbox : (lo, hi), each (2,) float
        The rectified canvas the frame points span (corners ``lo``, ``hi``).
    grid : int
        Side of the frame-point lattice (at least 2 used).
    depth : (N,) float, optional
        The pairs' depths: a folding triangle then drops its farthest pair
        (else the one whose disparity deviates most from its neighbours').

    Returns
    -------
    r0, r1 : numpy.ndarray
        ``(V, 2)`` float64 rectified vertex positions at ``s = 0`` and ``s = 1``
        (frame points first, then the kept pairs in order).
    tris : numpy.ndarray
        ``(M, 3)`` int32 triangles (Delaunay at ``s = 1/2``), none folding for
        ``s`` in ``[0, 1]``.
    corr_index : numpy.ndarray
        ``(V,)`` int64: each vertex's correspondence index, ``-1`` for frame points.
    n_dropped : int
        Correspondences dropped to fold-overs.

    Raises
    ------
    FoldOverError
        Fold-overs left after dropping vertices.
    """
    lo, hi = bbox
    disp = r1c - r0c
    dmed = np.median(disp, axis=0)
    n = max(int(grid), 2)
    xs = np.linspace(lo[0], hi[0], n)
    ys = np.linspace(lo[1], hi[1], n)
    gx, gy = np.meshgrid(xs, ys)
    g = np.stack([gx.ravel(), gy.ravel()], axis=1)
    ring = (gx == xs[0]) | (gx == xs[-1]) | (gy == ys[0]) | (gy == ys[-1])
    ring = ring.ravel()
    cell = float(max(xs[1] - xs[0], ys[1] - ys[0]))
    dev = float(np.max(np.linalg.norm(disp - dmed, axis=1))) if len(disp) else 0.0
    radius = 0.75 * cell + dev
    if len(r0c):
        from scipy.spatial import cKDTree

        tree = cKDTree(np.r_[r0c, r1c])
        dist, _ = tree.query(g)
        keep_g = ring | (dist > radius)
    else:
        keep_g = np.ones(len(g), bool)
    g, ring = g[keep_g], ring[keep_g]
    r0 = np.r_[g, r0c]
    r1 = np.r_[g + dmed, r1c]
    idx = np.r_[np.full(len(g), -1), np.arange(len(r0c))]
    is_ring = np.r_[ring, np.zeros(len(r0c), bool)]
    dropped = 0
    for _ in range(200):
        mid = 0.5 * (r0 + r1)
        tris = delaunay_triangles(mid)
        amin = min_area_over_s(r0, r1, tris)
        bad = np.flatnonzero(amin < tol.VM_MIN_TRIANGLE_AREA_PX2)
        if bad.size == 0:
            return r0, r1, tris, idx, dropped
        d = r1 - r0
        # neighbours' median disparity, per vertex
        nb: list[list[int]] = [[] for _ in range(len(r0))]
        for t in tris:
            for a in range(3):
                nb[t[a]].extend((int(t[(a + 1) % 3]), int(t[(a + 2) % 3])))
        drop: set[int] = set()
        for t in tris[bad]:
            inner = [v for v in t if idx[v] < 0 and not is_ring[v]]
            if inner:
                drop.add(int(inner[0]))
                continue
            cands = [v for v in t if idx[v] >= 0]
            if not cands:
                continue
            if depth is not None:
                # the farthest point: the occluder's outline stays, the occluded side gives way
                drop.add(int(cands[int(np.argmax(depth[idx[cands]]))]))
                continue
            devs = [np.linalg.norm(d[v] - np.median(d[nb[v]], axis=0)) if nb[v] else 0.0 for v in cands]
            drop.add(int(cands[int(np.argmax(devs))]))
        if not drop:
            break
        keep = np.ones(len(r0), bool)
        keep[list(drop)] = False
        dropped += int(np.count_nonzero(idx[~keep] >= 0))
        r0, r1, idx, is_ring = r0[keep], r1[keep], idx[keep], is_ring[keep]
        if np.count_nonzero(idx >= 0) < 3:
            break
    raise FoldOverError(expected_got("morph mesh", "no triangle folding over for s in [0, 1]",
                                     "fold-overs left after dropping vertices"))


def mesh_canvas(H_rect_0: np.ndarray, H_rect_1: np.ndarray, pts0: np.ndarray, pts1: np.ndarray,
                shape0: tuple[int, int], shape1: tuple[int, int], box0: np.ndarray | None = None,
                box1: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The rectified region a morph mesh must cover (the frame points' ``bbox``).

    The bounding box of the pairs and of the given image-space quadrilaterals,
    all pre-warped, capped at :data:`tol.VM_MAX_CANVAS_FACTOR` times the larger
    image side about the pairs' centre, grown by a margin, then shrunk until
    both inverse pre-warps keep its corners in front.

    Parameters
    ----------
    H_rect_0, H_rect_1 : (3, 3) float
        The pre-warps (image-``i`` pixels to the rectified frame).
    pts0, pts1 : (N, 2) float
        The pairs in image 0 and image 1 pixels.
    shape0, shape1 : (H, W)
        The image shapes.
    box0, box1 : (k, 2) float, optional
        Image-``i`` pixel outlines to cover as well; None: the whole image
        (its corners), ``k = 0``: nothing more.

    Returns
    -------
    lo, hi : numpy.ndarray
        ``(2,)`` float64 corners of the canvas in the rectified frame.

    Raises
    ------
    DegenerateViewError
        No region around the pairs stays in front of both views.
    """
    r0c, r1c = apply_h(H_rect_0, pts0), apply_h(H_rect_1, pts1)
    parts = [r0c, r1c]
    for box, shape, H_rect_i in ((box0, shape0, H_rect_0), (box1, shape1, H_rect_1)):
        if box is None:
            box = image_corners(shape)
        if len(box):
            parts.append(apply_h(H_rect_i, box))
    allp = np.concatenate(parts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    size = float(max(max(shape0), max(shape1)))
    centre = 0.5 * (r0c.mean(axis=0) + r1c.mean(axis=0))
    lim = 0.5 * tol.VM_MAX_CANVAS_FACTOR * size
    lo, hi = np.maximum(lo, centre - lim), np.minimum(hi, centre + lim)
    margin = 0.05 * float(np.max(hi - lo)) + 4.0
    return _in_front(lo - margin, hi + margin, centre, (np.linalg.inv(H_rect_0), np.linalg.inv(H_rect_1)))


def _in_front(lo: np.ndarray, hi: np.ndarray, centre: np.ndarray, H_img_rect: tuple[np.ndarray, np.ndarray]
              ) -> tuple[np.ndarray, np.ndarray]:
    """Shrink the rectified canvas ``lo, hi`` about ``centre`` until both inverse pre-warps
    (``H_img_rect``: rectified frame to image ``i``) keep its corners in front."""
    for _ in range(40):
        c = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        ok = True
        for H_i_rect in H_img_rect:
            w = np.c_[c, np.ones(4)] @ H_i_rect[2]
            wc = np.r_[centre, 1.0] @ H_i_rect[2]
            if np.any(w * np.sign(wc) <= 0.05 * abs(wc)):
                ok = False
        if ok:
            return lo, hi
        lo = centre + 0.85 * (lo - centre)
        hi = centre + 0.85 * (hi - centre)
    raise DegenerateViewError(expected_got("rectified canvas", "a region in front of both views",
                                           "none found"))
