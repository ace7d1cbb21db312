"""Maps prepared for reprojection (:class:`Source`), their hidden layers
(:class:`Layer`, :func:`hidden_layer`) and the z-buffered reprojection of a
frame's maps over bands of output rows (:func:`reproject_maps`; conventions and
the determinism across threads: :mod:`morphkit.shadow.reprojection`).
"""

from __future__ import annotations

import numpy as np

from ...errors import ValidationError, expected_got
from ...settings import use_compiled
from ...warp import band_pool
from .kernels import hull_kernel, reproject_kernel, reproject_numpy, runs_kernel, work_kernel
from .motion import (
    EARLY_Z_TEXELS,
    LAYER_TEXELS,
    STRETCH_PX,
    Reprojection,
    orphans,
    row_depth_range,
    row_spans,
    support_box,
)

__all__ = ["Layer", "Source", "hidden_layer", "reproject_maps"]


def _check_depth(depth: np.ndarray) -> np.ndarray:
    if depth.dtype != np.float32 or depth.ndim != 2:
        raise ValidationError(expected_got("depth map", "float32 (H, W)",
                                           f"{depth.dtype} {depth.shape}"))
    return depth


class Source:
    """A map prepared for reprojection (what does not change per frame): its
    :func:`support_box`, :func:`row_spans`, :func:`orphans` and
    :func:`row_depth_range`.

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.
    """

    __slots__ = ("depth", "box", "spans", "cum", "orphans", "zrange", "row_work")

    def __init__(self, depth: np.ndarray) -> None:
        self.depth = _check_depth(depth)
        self.box = support_box(depth)
        self.spans, self.cum = row_spans(depth)
        self.orphans = orphans(depth)
        self.zrange = row_depth_range(depth)
        self.row_work = np.diff(self.cum).astype(np.float64)  # object pixels per row


class Layer:
    """The quads of a map that a frame draws, not the whole map (a
    :func:`hidden_layer`): ``runs (K, 3)`` int64 rows ``(r, a, b)``, the quads with
    top row ``r`` and left columns ``a`` to ``b - 1``, in row-major order; ``cum
    (K + 1,)`` the quads before each run (band splits). The map is shared, not
    copied: a layer costs only its runs (:attr:`nbytes`).

    Parameters
    ----------
    depth : (H, W) float32
        The map, linear depth, ``+inf`` background (shared, not copied).
    quads : (H - 1, W - 1) bool
        The quads of the layer.
    """

    __slots__ = ("depth", "runs", "cum", "zrange", "row_work")

    def __init__(self, depth: np.ndarray, quads: np.ndarray) -> None:
        self.depth = _check_depth(depth)
        h, w = depth.shape
        if quads.shape != (max(h - 1, 0), max(w - 1, 0)):
            raise ValidationError(expected_got("quads", f"a ({h - 1}, {w - 1}) mask", str(quads.shape)))
        pad = np.zeros((quads.shape[0], quads.shape[1] + 2), np.int8)
        pad[:, 1:-1] = quads
        step = np.diff(pad, axis=1)
        r, a = np.nonzero(step == 1)
        _r, b = np.nonzero(step == -1)  # row-major, so starts and ends pair up
        self.runs = np.stack([r, a, b], 1).astype(np.int64).reshape(-1, 3)
        self.cum = np.zeros(len(self.runs) + 1, np.int64)
        np.cumsum(b - a, out=self.cum[1:])
        self.zrange = row_depth_range(depth)
        self.row_work = np.bincount(r, weights=b - a, minlength=h).astype(np.float64)  # quads per row

    @property
    def nbytes(self) -> int:
        """Bytes the layer keeps (its runs and their cumulative quad counts; the map is shared)."""
        return int(self.runs.nbytes + self.cum.nbytes)

    def quads(self) -> np.ndarray:
        """The ``(H - 1, W - 1)`` bool mask of the quads drawn.

        Returns
        -------
        (H - 1, W - 1) bool
            True for each quad of the layer.
        """
        h, w = self.depth.shape
        q = np.zeros((max(h - 1, 0), max(w - 1, 0)), bool)
        for r, a, b in self.runs:
            q[r, a:b] = True
        return q



def hidden_layer(primary: np.ndarray, secondary: np.ndarray, rp: Reprojection, *,
                 texels: float = LAYER_TEXELS) -> Layer:
    """What ``secondary`` holds that ``primary`` does not: one layer of a layered
    depth image (Shade et al. 1998), so that a frame reprojects the primary map
    whole and only this part of its neighbour.

    ``rp`` moves ``secondary``'s pixels to ``primary``'s sample position (exact:
    both are baked maps). A secondary pixel is *explained* when it lands inside
    the map and the primary's depth interpolated bilinearly there (its 4
    neighbouring pixels all object) is within ``texels`` texels' world size
    (``z / fx``; orthographic ``1 / fx``) of the pixel's moved depth: the
    primary saw that surface there (bilinear: exact on a plane). The others
    (hidden from the primary's position, or at or past its silhouette, where
    the union of maps draws a finer outline than any one) are *new*. The layer
    is every quad of ``secondary`` with a new pixel among its corners (and 3 or
    more object pixels), drawn as in the whole map.

    Parameters
    ----------
    primary, secondary : (H, W) float32
        The two maps, linear depth, ``+inf`` background.
    rp : Reprojection
        Moves ``secondary``'s pixels to ``primary``'s sample position.
    texels : float
        Depth tolerance, in texel world sizes.

    Returns
    -------
    Layer
        ``secondary``'s new quads.
    """
    primary = _check_depth(primary)
    if primary.shape != _check_depth(secondary).shape:
        raise ValidationError(expected_got("secondary map", f"the primary's shape {primary.shape}",
                                           str(secondary.shape)))
    h, w = secondary.shape
    fin = np.isfinite(secondary)
    r, c = np.nonzero(fin)
    x, y, z = rp.move(c.astype(np.float64), r.astype(np.float64), secondary[r, c].astype(np.float64))
    i0 = np.floor(x)
    j0 = np.floor(y)
    inside = (i0 >= 0) & (i0 < w - 1) & (j0 >= 0) & (j0 < h - 1)
    ax = np.where(inside, x - i0, 0.0)
    ay = np.where(inside, y - j0, 0.0)
    i0 = np.where(inside, i0, 0).astype(np.int64)
    j0 = np.where(inside, j0, 0).astype(np.int64)
    p = primary.astype(np.float64)
    with np.errstate(invalid="ignore"):  # inf * 0 where a neighbour is background: nan
        zi = ((p[j0, i0] * (1 - ax) + p[j0, i0 + 1] * ax) * (1 - ay)
              + (p[j0 + 1, i0] * (1 - ax) + p[j0 + 1, i0 + 1] * ax) * ay)
        tau = texels * (z if rp.perspective else 1.0) / rp.params[0]
        explained = inside & (np.abs(z - zi) <= tau)  # nan, inf: not explained
    new = np.zeros((h, w), bool)
    new[r[~explained], c[~explained]] = True
    f = fin.astype(np.int8)
    solid = (f[:-1, :-1] + f[:-1, 1:] + f[1:, :-1] + f[1:, 1:]) >= 3
    touched = new[:-1, :-1] | new[:-1, 1:] | new[1:, :-1] | new[1:, 1:]
    return Layer(secondary, touched & solid)


Job = tuple[Source | Layer, Reprojection]


def _output_bands(plan: list[tuple[int, Source | Layer, Reprojection]], h: int, n: int) -> np.ndarray:
    """``n + 1`` output-row edges (``0 .. h``) splitting the frame's work (object
    pixels, quads) about evenly: each source row's work counted at the middle of
    its destination rows. Only the balance depends on this, never the result."""
    hist = np.zeros(h)
    for _k, src, rp in plan:
        work_kernel(src.zrange, src.row_work, rp.perspective, rp.params, hist)
    cum = np.cumsum(hist)
    if cum[-1] <= 0:
        return np.linspace(0, h, n + 1).astype(np.int64)
    edges = np.searchsorted(cum, cum[-1] * np.arange(1, n) / n, side="left") + 1
    return np.r_[0, np.clip(edges, 0, h), h].astype(np.int64)


def reproject_maps(jobs: list[Job], out: np.ndarray, *, threads: int = 1, stretch: float = STRETCH_PX,
                   early_z: float = EARLY_Z_TEXELS) -> tuple[int, int, int, int]:
    """Reproject every ``(source, rp)`` of ``jobs`` into the z-buffer ``out``
    (``(H, W)`` float32, min), the first job with its orphan points, the others
    (they mostly fill what the first one leaves open; whole maps or
    :func:`hidden_layer` s) with ``early_z``. Returns the ROI
    ``(r0, r1, c0, c1)`` holding every pixel written.

    With ``threads > 1`` the output rows are split into that many bands of
    about equal work; each band draws, in the order one thread would, every
    quad and point whose destination can reach its rows
    (:meth:`Reprojection.row_y_range`) and writes only its rows. Each output
    pixel so sees the same writes and early-z tests as with one thread: the
    result is bit-identical for any ``threads``. Compiled (numba) unless
    ``MORPHKIT_WARP_NUMPY=1``: then :func:`reproject_numpy` per map, in one
    thread, with every map's orphans and no early z (the exact union).

    Parameters
    ----------
    jobs : list of (Source or Layer, Reprojection)
        The maps (or layers) and their motions, first job first.
    out : (H, W) float32
        Z-buffer, lowered in place (min); ``+inf`` where empty.
    threads : int
        Bands drawn in parallel.
    stretch : float
        Longest triangle edge drawn, in destination pixels.
    early_z : float
        Early-z margin for the jobs after the first, in texels.

    Returns
    -------
    tuple of int
        ``(r0, r1, c0, c1)``.
    """
    if out.dtype != np.float32 or out.ndim != 2:
        raise ValidationError(expected_got("out", "a float32 (H, W) z-buffer", f"{out.dtype} {out.shape}"))
    box = np.array([out.shape[0], 0, out.shape[1], 0], np.int64)
    if not use_compiled(reproject_kernel):
        for src, rp in jobs:
            before = out.copy()
            reproject_numpy(src.depth, rp, out, stretch=stretch,
                            quads=src.quads() if isinstance(src, Layer) else None)
            changed = np.argwhere(out != before)
            if len(changed):
                box[:] = (min(box[0], changed[:, 0].min()), max(box[1], changed[:, 0].max() + 1),
                          min(box[2], changed[:, 1].min()), max(box[3], changed[:, 1].max() + 1))
        return _box(box)
    no_points = np.empty((0, 2), np.int64)
    h = out.shape[0]
    n = max(1, min(int(threads), h))
    plan = [(k, src, rp) for k, (src, rp) in enumerate(jobs) if src.cum[-1] > 0]
    rows = np.array([0, h], np.int64) if n == 1 else _output_bands(plan, h, n)

    def band(b: int) -> np.ndarray:
        jmin, jmax = int(rows[b]), int(rows[b + 1])
        bx = np.array([h, 0, out.shape[1], 0], np.int64)
        if jmax <= jmin:
            return bx
        for k, src, rp in plan:
            ez = early_z / rp.params[0] if k > 0 else 0.0
            if isinstance(src, Layer):
                t0, t1 = 0, len(src.runs)
                if n > 1:  # the runs whose quad rows can reach this band's rows
                    qa, qb = hull_kernel(src.zrange, rp.perspective, rp.params, int(src.runs[0, 0]),
                                          int(src.runs[-1, 0]) + 1, jmin, jmax)
                    t0 = int(np.searchsorted(src.runs[:, 0], qa, side="left"))
                    t1 = int(np.searchsorted(src.runs[:, 0], qb, side="left"))
                if t1 > t0:
                    runs_kernel(src.depth, src.runs, t0, t1, rp.perspective, rp.params, float(stretch), ez,
                                 out, bx, jmin, jmax)
                continue
            r0, r1, c0, c1 = src.box
            if rp.identity:  # a sample position: the map itself
                a, z = max(r0, jmin), min(r1, jmax)
                if z > a:
                    o, m = out[a:z, c0:c1], src.depth[a:z, c0:c1]
                    np.minimum(o, m, out=o)
                    bx[:] = (min(bx[0], a), max(bx[1], z), min(bx[2], c0), max(bx[3], c1))
                continue
            q0, q1 = r0, max(r1 - 1, r0)
            if n > 1:  # the quad rows that can reach this band's rows (points: checked one by one)
                q0, q1 = hull_kernel(src.zrange, rp.perspective, rp.params, q0, q1, jmin, jmax)
            reproject_kernel(src.depth, src.spans, q0, q1, c0, c1, rp.perspective, rp.params,
                              src.orphans if k == 0 else no_points, float(stretch), ez, out, bx, jmin, jmax)
        return bx

    if n == 1:
        return _box(band(0))
    futures = [band_pool().submit(band, b) for b in range(1, n)]
    boxes = [band(0)] + [f.result() for f in futures]
    for bx in boxes:
        if bx[1] > bx[0] and bx[3] > bx[2]:
            box[:] = (min(box[0], bx[0]), max(box[1], bx[1]), min(box[2], bx[2]), max(box[3], bx[3]))
    return _box(box)


def _box(b: np.ndarray) -> tuple[int, int, int, int]:
    return (0, 0, 0, 0) if b[1] <= b[0] or b[3] <= b[2] else (int(b[0]), int(b[1]), int(b[2]), int(b[3]))
