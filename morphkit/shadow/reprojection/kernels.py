"""The compiled (numba) rasterising kernels of the per-pixel reprojection, and
:func:`reproject_numpy`, their independent vectorised reference (conventions:
:mod:`morphkit.shadow.reprojection`).
"""

from __future__ import annotations

import math

import numpy as np

from ... import tol
from ...settings import NUMBA_AVAILABLE, compile_kernel
from .motion import STRETCH_PX, Reprojection, orphans

# The reference is this module's public API; the compiled entry points
# ``reproject_kernel``, ``runs_kernel``, ``hull_kernel`` and ``work_kernel`` are
# the package's own (called by :func:`~morphkit.shadow.reprojection.reproject_maps`
# only; their arguments are the loops' below).
__all__ = ["reproject_numpy"]

#: Barycentric tolerance (~ pixels, triangles being ~1 px): centres on a shared
#: edge count for both triangles (the z-buffer keeps the nearer), so none falls
#: between them, and centres on the mesh's boundary stay covered under a
#: vanishing motion (the boundary runs through the border pixels' centres), as
#: :data:`morphkit.tol.MESH_BOUNDARY_PX` does for the mesh warp.
_EDGE_EPS = tol.MESH_BOUNDARY_PX

#: Stretched quads: the margin around their drawn triangles, and the slivers that
#: keep the whole box (:func:`_drawn_box`).
_DRAWN_BOX_PX = tol.REPROJECT_DRAWN_BOX_PX
_DRAWN_BOX_MIN_AREA2 = tol.REPROJECT_SLIVER_AREA2_PX2


# ----------------------------------------------------------------- compiled kernel
def _tri(px: float, py: float, x0: float, y0: float, z0: float, x1: float, y1: float, z1: float,
         x2: float, y2: float, z2: float) -> float:
    """Depth at centre ``(px, py)`` of the triangle, or ``+inf`` outside it (edges count)."""
    ax = x1 - x0
    ay = y1 - y0
    bx = x2 - x0
    by = y2 - y0
    den = ax * by - bx * ay
    qx = px - x0
    qy = py - y0
    w1 = qx * by - bx * qy  # l1 * den
    w2 = ax * qy - qx * ay  # l2 * den
    if den < 0.0:
        den = -den
        w1 = -w1
        w2 = -w2
    eps = _EDGE_EPS * den
    if den > 0.0 and w1 >= -eps and w2 >= -eps and w1 + w2 <= den + eps:
        return z0 + (w1 * (z1 - z0) + w2 * (z2 - z0)) / den
    return np.inf


def _grow(xmin: float, xmax: float, ymin: float, ymax: float, x: float, y: float, valid: bool
          ) -> tuple[float, float, float, float]:
    """The box ``(xmin, xmax, ymin, ymax)`` grown by ``(x, y)`` if ``valid``."""
    if valid:
        return min(xmin, x), max(xmax, x), min(ymin, y), max(ymax, y)
    return xmin, xmax, ymin, ymax


def _fits(x0: float, y0: float, x1: float, y1: float, x2: float, y2: float, lim: float) -> bool:
    """Whether the triangle's bounding box is at most ``lim`` wide and tall."""
    return (max(x0, x1, x2) - min(x0, x1, x2) <= lim
            and max(y0, y1, y2) - min(y0, y1, y2) <= lim)


def _area2(x0: float, y0: float, x1: float, y1: float, x2: float, y2: float) -> float:
    """Twice the triangle's area (unsigned)."""
    return abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0))


def _drawn_box(xa: float, ya: float, xb: float, yb: float, xc: float, yc: float, xd: float, yd: float,
               t0: bool, t1: bool, t2: bool, t3: bool, ia: int, ib: int, ja: int, jb: int
               ) -> tuple[int, int, int, int]:
    """The centres ``[ia, ib] x [ja, jb]`` of a quad's box that its drawn triangles
    (``t0 .. t3`` as in :func:`_draw_quads`: abc, bdc, abd, adc) can cover: their
    vertices' box widened by :data:`_DRAWN_BOX_PX`, within the given one. A centre
    that :func:`_tri` takes lies within ``2 _EDGE_EPS`` times a triangle's extent
    (at most the stretch limit) of its vertices' box, plus its rounding, which is
    far below that margin unless the triangle is a sliver: with one under
    :data:`_DRAWN_BOX_MIN_AREA2`, the box is left as it is."""
    lim = _DRAWN_BOX_MIN_AREA2
    if ((t0 and _area2(xa, ya, xb, yb, xc, yc) < lim) or (t1 and _area2(xb, yb, xd, yd, xc, yc) < lim)
            or (t2 and _area2(xa, ya, xb, yb, xd, yd) < lim)
            or (t3 and _area2(xa, ya, xd, yd, xc, yc) < lim)):
        return ia, ib, ja, jb
    xmin, xmax, ymin, ymax = np.inf, -np.inf, np.inf, -np.inf
    xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xa, ya, t0 or t2 or t3)
    xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xb, yb, t0 or t1 or t2)
    xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xc, yc, t0 or t1 or t3)
    xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xd, yd, t1 or t2 or t3)
    return (max(ia, math.ceil(xmin - _DRAWN_BOX_PX)), min(ib, math.floor(xmax + _DRAWN_BOX_PX)),
            max(ja, math.ceil(ymin - _DRAWN_BOX_PX)), min(jb, math.floor(ymax + _DRAWN_BOX_PX)))


def _motion(p: np.ndarray) -> tuple[float, float, float, float, float, float, float, float, float]:
    """A :class:`Reprojection`'s nine parameters as scalars: ``fx, fy, cx_s, cy_s, cx_d, cy_d,
    ex, ey, ez``."""
    return p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]


def _project_px(row: np.ndarray, c: int, yr: float, persp: bool, fx: float, fy: float, cxs: float,
                cxd: float, cyd: float, ex: float, ey: float, ez: float, X: np.ndarray, Y: np.ndarray,
                Z: np.ndarray, k: int) -> None:
    """Destination ``X[k], Y[k]`` and depth ``Z[k]`` of pixel ``c`` of a source row
    ``row`` (``yr = (r - cy_s) / fy``; the parameters: :class:`Reprojection`);
    ``Z[k] = +inf`` (background) leaves ``X, Y``."""
    z = np.float64(row[c])
    if z < np.inf:
        zd = z + ez
        xr = (c - cxs) / fx
        if persp:
            t = 1.0 / zd
            X[k] = fx * (z * xr + ex) * t + cxd
            Y[k] = fy * (z * yr + ey) * t + cyd
        else:
            X[k] = fx * (xr + ex) + cxd
            Y[k] = fy * (yr + ey) + cyd
        Z[k] = zd
    else:
        Z[k] = np.inf


def _project_row(src: np.ndarray, r: int, c0: int, c1: int, persp: bool, p: np.ndarray,
                 X: np.ndarray, Y: np.ndarray, Z: np.ndarray, lo: int, hi: int) -> None:
    """Destination ``X, Y`` and depth ``Z`` (``+inf``: background) of
    ``src[r, c0:c1]`` (:func:`_project_px`); only columns in ``[lo, hi)`` can hold the object."""
    Z[:] = np.inf
    lo = max(lo, c0)
    fx, fy, cxs, cys, cxd, cyd, ex, ey, ez = _motion(p)
    row = src[r]
    yr = (r - cys) / fy
    for c in range(lo, min(hi, c1)):
        _project_px(row, c, yr, persp, fx, fy, cxs, cxd, cyd, ex, ey, ez, X, Y, Z, c - c0)


def _draw_quads(Xa: np.ndarray, Ya: np.ndarray, Za: np.ndarray, Xb: np.ndarray, Yb: np.ndarray,
                Zb: np.ndarray, k0: int, k1: int, stretch: float, early_z: float, persp: bool,
                zbuf: np.ndarray, jlo: int, jhi: int, ilo: int, ihi: int, jmin: int, jmax: int
                ) -> tuple[int, int, int, int]:
    """Draw quads ``k0 .. k1 - 1`` between two projected rows (``Xa, Ya, Za`` the
    upper, ``Xb, Yb, Zb`` the lower; quad ``k`` joins their entries ``k, k + 1``)
    into rows ``[jmin, jmax)`` of ``zbuf``; returns the written-pixel bounds
    ``(jlo, jhi, ilo, ihi)`` grown. ``early_z``: skip a quad at a centre already
    holding a depth no farther than the quad's nearest vertex plus ``early_z``
    (relative to that depth for perspective, absolute for orthographic): it
    could lower that depth by at most that much, and cannot change coverage."""
    h, w = zbuf.shape
    for k in range(k0, k1):
        za = Za[k]
        zb = Za[k + 1]
        zc = Zb[k]
        zd = Zb[k + 1]
        va = za < np.inf
        vb = zb < np.inf
        vc = zc < np.inf
        vd = zd < np.inf
        if va + vb + vc + vd < 3:
            continue
        xa = Xa[k]
        ya = Ya[k]
        xb = Xa[k + 1]
        yb = Ya[k + 1]
        xc = Xb[k]
        yc = Yb[k]
        xd = Xb[k + 1]
        yd = Yb[k + 1]
        # the quad's bounding box over its object vertices (3 or 4)
        xmin, xmax, ymin, ymax = np.inf, -np.inf, np.inf, -np.inf
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xa, ya, va)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xb, yb, vb)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xc, yc, vc)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xd, yd, vd)
        ia = max(math.ceil(xmin - _EDGE_EPS), 0)
        ib = min(math.floor(xmax + _EDGE_EPS), w - 1)
        ja = max(math.ceil(ymin - _EDGE_EPS), 0, jmin)
        jb = min(math.floor(ymax + _EDGE_EPS), h - 1, jmax - 1)
        if ib < ia or jb < ja:
            continue
        # which triangles: split along b-c; with 3 object pixels, their triangle.
        # A triangle wider or taller than `stretch` spans a depth jump: not drawn.
        t0 = va and vb and vc
        t1 = vb and vc and vd
        t2 = (not (vb and vc)) and va and vb and vd
        t3 = (not (vb and vc)) and va and vc and vd
        stretched = xmax - xmin > stretch or ymax - ymin > stretch
        if stretched:
            t0 = t0 and _fits(xa, ya, xb, yb, xc, yc, stretch)
            t1 = t1 and _fits(xb, yb, xd, yd, xc, yc, stretch)
            t2 = t2 and _fits(xa, ya, xb, yb, xd, yd, stretch)
            t3 = t3 and _fits(xa, ya, xd, yd, xc, yc, stretch)
            if not (t0 or t1 or t2 or t3):
                continue
        jlo = min(jlo, ja)
        jhi = max(jhi, jb + 1)
        ilo = min(ilo, ia)
        ihi = max(ihi, ib + 1)
        if stretched:  # its box can be far larger than its drawn triangles': test only the
            # centres those can reach (the same writes; the box above keeps the quad's)
            ia, ib, ja, jb = _drawn_box(xa, ya, xb, yb, xc, yc, xd, yd, t0, t1, t2, t3, ia, ib, ja, jb)
        znear = min(za, zb, zc, zd)
        zskip = znear + early_z * (znear if persp else 1.0)
        for j in range(ja, jb + 1):
            for i in range(ia, ib + 1):
                if zbuf[j, i] <= zskip:
                    continue
                # t0/t1 share only their diagonal unless the quad folds (then
                # the first that holds the centre gives its depth); t2, t3
                # exclude each other and t0, t1
                z = np.inf
                if t0:
                    z = _tri(i, j, xa, ya, za, xb, yb, zb, xc, yc, zc)
                if t1 and z == np.inf:
                    z = _tri(i, j, xb, yb, zb, xd, yd, zd, xc, yc, zc)
                if t2:
                    z = _tri(i, j, xa, ya, za, xb, yb, zb, xd, yd, zd)
                elif t3:
                    z = _tri(i, j, xa, ya, za, xd, yd, zd, xc, yc, zc)
                if z < zbuf[j, i]:
                    zbuf[j, i] = z
    return jlo, jhi, ilo, ihi


def _reproject_loop(src: np.ndarray, spans: np.ndarray, q0: int, q1: int, c0: int, c1: int,
                    persp: bool, p: np.ndarray, orph: np.ndarray, stretch: float,
                    early_z: float, zbuf: np.ndarray, box: np.ndarray, jmin: int, jmax: int) -> None:
    """Draw the quads with top row in ``[q0, q1)`` and columns ``[c0, c1)`` of
    ``src`` (rows ``q0 .. q1`` are read; ``spans[r]`` holds row ``r``'s first and
    last + 1 object columns), and the points ``orph``, into rows ``[jmin, jmax)``
    of ``zbuf``; ``box`` grows to hold every pixel that may have been written
    (``early_z``: :func:`_draw_quads`; 0 skips only what cannot change the result)."""
    n = c1 - c0
    rows = np.empty((6, n))  # two projected rows: X, Y, Z of each
    Xa, Ya, Za, Xb, Yb, Zb = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    h, w = zbuf.shape
    jlo, jhi, ilo, ihi = box[0], box[1], box[2], box[3]
    if q1 > q0:
        _project_row(src, q0, c0, c1, persp, p, Xa, Ya, Za, spans[q0, 0], spans[q0, 1])
    for r in range(q0, q1):
        if r + 1 >= src.shape[0]:
            break
        _project_row(src, r + 1, c0, c1, persp, p, Xb, Yb, Zb, spans[r + 1, 0], spans[r + 1, 1])
        lo = min(spans[r, 0], spans[r + 1, 0])
        hi = max(spans[r, 1], spans[r + 1, 1])
        if hi > lo:
            jlo, jhi, ilo, ihi = _draw_quads(Xa, Ya, Za, Xb, Yb, Zb, max(lo - c0 - 1, 0),
                                             min(hi - c0, n - 1), stretch, early_z, persp, zbuf,
                                             jlo, jhi, ilo, ihi, jmin, jmax)
        Xa, Xb = Xb, Xa
        Ya, Yb = Yb, Ya
        Za, Zb = Zb, Za
    one_x = np.empty(1)
    one_y = np.empty(1)
    one_z = np.empty(1)
    for k in range(orph.shape[0]):
        r = orph[k, 0]
        c = orph[k, 1]
        _project_row(src, r, c, c + 1, persp, p, one_x, one_y, one_z, c, c + 1)
        if one_z[0] < np.inf:
            i = math.floor(one_x[0] + 0.5)
            j = math.floor(one_y[0] + 0.5)
            if 0 <= i < w and max(jmin, 0) <= j < min(jmax, h) and one_z[0] < zbuf[j, i]:
                zbuf[j, i] = one_z[0]
                jlo = min(jlo, j)
                jhi = max(jhi, j + 1)
                ilo = min(ilo, i)
                ihi = max(ihi, i + 1)
    box[0] = jlo
    box[1] = jhi
    box[2] = ilo
    box[3] = ihi


def _runs_loop(src: np.ndarray, runs: np.ndarray, t0: int, t1: int, persp: bool, p: np.ndarray,
               stretch: float, early_z: float, zbuf: np.ndarray, box: np.ndarray, jmin: int,
               jmax: int) -> None:
    """Draw the quads of ``src`` listed by ``runs[t0:t1]`` (rows ``(r, a, b)``: the
    quads with top row ``r`` and left columns ``a .. b - 1``) into rows
    ``[jmin, jmax)`` of ``zbuf``, as :func:`_reproject_loop` draws them; ``box``
    grows likewise."""
    w = src.shape[1]
    # projected pixels by row parity, full width (a run's rows r, r + 1 take both
    # slots), kept across runs: the runs of the next row reuse their lower row
    proj = np.empty((2, 3, w))
    held = np.full((2, w), -1, np.int64)  # the row each slot's column holds (-1: none)
    jlo, jhi, ilo, ihi = box[0], box[1], box[2], box[3]
    fx, fy, cxs, cys, cxd, cyd, ex, ey, ez = _motion(p)
    for t in range(t0, t1):
        r = runs[t, 0]
        a = runs[t, 1]
        b = runs[t, 2] + 1
        for q in range(r, r + 2):
            s = q & 1
            row = src[q]
            yr = (q - cys) / fy
            P = proj[s]
            for c in range(a, b):
                if held[s, c] != q:
                    _project_px(row, c, yr, persp, fx, fy, cxs, cxd, cyd, ex, ey, ez, P[0], P[1], P[2], c)
                    held[s, c] = q
        A = proj[r & 1]
        B = proj[(r + 1) & 1]
        jlo, jhi, ilo, ihi = _draw_quads(A[0], A[1], A[2], B[0], B[1], B[2], a, b - 1, stretch, early_z,
                                         persp, zbuf, jlo, jhi, ilo, ihi, jmin, jmax)
    box[0] = jlo
    box[1] = jhi
    box[2] = ilo
    box[3] = ihi


def _quad_hull(zrange: np.ndarray, persp: bool, p: np.ndarray, q0: int, q1: int, jmin: int, jmax: int
               ) -> tuple[int, int]:
    """The first and last + 1 quad rows in ``[q0, q1)`` whose quads (or points) can
    write a destination row in ``[jmin, jmax)`` (``(0, 0)``: none). A quad row's
    destination ``y`` lies within the bounds of its two source rows' (exact, as
    :meth:`Reprojection.row_y_range`), widened by a pixel for the rounding."""
    fy = p[1]
    cys = p[3]
    cyd = p[5]
    ey = p[7]
    ez = p[8]
    h = zrange.shape[0]
    first = -1
    last = -1
    for q in range(q0, q1):
        lo = np.inf
        hi = -np.inf
        for r in range(q, min(q + 2, h)):
            za = zrange[r, 0]
            zb = zrange[r, 1]
            if za > zb:
                continue
            yr = (r - cys) / fy
            if persp:
                ya = fy * (za * yr + ey) / (za + ez) + cyd
                yb = fy * (zb * yr + ey) / (zb + ez) + cyd
            else:
                ya = fy * (yr + ey) + cyd
                yb = ya
            lo = min(lo, ya, yb)
            hi = max(hi, ya, yb)
        if hi + 1.0 >= jmin and lo - 1.0 < jmax:
            if first < 0:
                first = q
            last = q
    if first < 0:
        return 0, 0
    return first, last + 1


def _work_rows(zrange: np.ndarray, work: np.ndarray, persp: bool, p: np.ndarray, hist: np.ndarray) -> None:
    """Add each source row's ``work`` to ``hist`` at the middle of its destination rows."""
    fy = p[1]
    cys = p[3]
    cyd = p[5]
    ey = p[7]
    ez = p[8]
    n = hist.shape[0]
    for r in range(zrange.shape[0]):
        za = zrange[r, 0]
        zb = zrange[r, 1]
        if work[r] <= 0 or za > zb:
            continue
        yr = (r - cys) / fy
        if persp:
            y = 0.5 * (fy * (za * yr + ey) / (za + ez) + fy * (zb * yr + ey) / (zb + ez)) + cyd
        else:
            y = fy * (yr + ey) + cyd
        j = min(max(int(math.floor(y)), 0), n - 1)
        hist[j] += work[r]


if NUMBA_AVAILABLE:  # inlined helpers first: the kernels resolve them when they compile
    _tri = compile_kernel(_tri, inline="always")
    _grow = compile_kernel(_grow, inline="always")
    _fits = compile_kernel(_fits, inline="always")
    _area2 = compile_kernel(_area2, inline="always")
    _drawn_box = compile_kernel(_drawn_box, inline="always")
    _motion = compile_kernel(_motion, inline="always")
    _project_px = compile_kernel(_project_px, inline="always")
    _project_row = compile_kernel(_project_row, inline="always")
    _draw_quads = compile_kernel(_draw_quads, inline="always")
reproject_kernel = compile_kernel(_reproject_loop)
runs_kernel = compile_kernel(_runs_loop)
hull_kernel = compile_kernel(_quad_hull)
work_kernel = compile_kernel(_work_rows)


# ----------------------------------------------------------------- numpy reference
def reproject_numpy(src: np.ndarray, rp: Reprojection, zbuf: np.ndarray, *,
                    stretch: float = STRETCH_PX, quads: np.ndarray | None = None) -> None:
    """The same drawing as the compiled kernel, vectorised over triangles: every
    triangle's candidate centres in its bounding box are tested at once, and the
    z-buffer minimum is taken with ``np.minimum.at``. An independent reference
    (tests compare the two) and the fallback without numba. ``quads``
    (``(H - 1, W - 1)`` bool): draw only those quads, and no orphan points (a
    :class:`Layer`).

    Parameters
    ----------
    src : (h, w) float32
        Source map, linear depth, ``+inf`` background.
    rp : Reprojection
        How its pixels move.
    zbuf : (H, W) float32
        Destination z-buffer, lowered in place (min).
    stretch : float
        Longest triangle edge drawn, in destination pixels (longer ones span a
        depth discontinuity and are dropped).
    quads : (h - 1, w - 1) bool, optional
        The quads to draw (None: all, and the orphan points).
    """
    h, w = src.shape
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float64)
    X, Y, Z = rp.move(xs, ys, src.astype(np.float64))
    fin = np.isfinite(src)
    a = (slice(None, -1), slice(None, -1))
    b = (slice(None, -1), slice(1, None))
    c = (slice(1, None), slice(None, -1))
    d = (slice(1, None), slice(1, None))
    va, vb, vc, vd = fin[a], fin[b], fin[c], fin[d]
    tris = [(a, b, c, vb & vc & va), (b, d, c, vb & vc & vd),
            (a, b, d, ~(vb & vc) & va & vd & vb), (a, d, c, ~(vb & vc) & va & vd & vc)]
    for p0, p1, p2, ok in tris:
        if quads is not None:
            ok = ok & quads
        P = [np.stack([M[s][ok] for M in (X, Y, Z)]) for s in (p0, p1, p2)]
        _raster_numpy(P[0], P[1], P[2], zbuf, stretch)
    orph = orphans(src) if quads is None else np.empty((0, 2), np.int64)
    h, w = zbuf.shape
    if len(orph):
        r, cc = orph[:, 0], orph[:, 1]
        i = np.floor(X[r, cc] + 0.5).astype(np.int64)
        j = np.floor(Y[r, cc] + 0.5).astype(np.int64)
        ok = (i >= 0) & (i < w) & (j >= 0) & (j < h)
        np.minimum.at(zbuf, (j[ok], i[ok]), Z[r, cc][ok].astype(zbuf.dtype))


def _raster_numpy(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray, zbuf: np.ndarray,
                  stretch: float) -> None:
    h, w = zbuf.shape
    xs = np.stack([p0[0], p1[0], p2[0]])
    ys = np.stack([p0[1], p1[1], p2[1]])
    keep = (xs.max(0) - xs.min(0) <= stretch) & (ys.max(0) - ys.min(0) <= stretch)
    p0, p1, p2, xs, ys = p0[:, keep], p1[:, keep], p2[:, keep], xs[:, keep], ys[:, keep]
    ax, ay = p1[0] - p0[0], p1[1] - p0[1]
    bx, by = p2[0] - p0[0], p2[1] - p0[1]
    den = ax * by - bx * ay
    ia = np.ceil(xs.min(0) - _EDGE_EPS).astype(np.int64)
    ja = np.ceil(ys.min(0) - _EDGE_EPS).astype(np.int64)
    span = int(math.floor(stretch)) + 1
    for dj in range(span + 1):
        for di in range(span + 1):
            i, j = ia + di, ja + dj
            px, py = i - p0[0], j - p0[1]
            with np.errstate(divide="ignore", invalid="ignore"):
                l1 = (px * by - bx * py) / den
                l2 = (ax * py - px * ay) / den
            z = p0[2] + l1 * (p1[2] - p0[2]) + l2 * (p2[2] - p0[2])
            ok = ((den != 0) & (l1 >= -_EDGE_EPS) & (l2 >= -_EDGE_EPS) & (l1 + l2 <= 1 + _EDGE_EPS)
                  & (i >= 0) & (i < w) & (j >= 0) & (j < h))
            np.minimum.at(zbuf, (j[ok], i[ok]), z[ok].astype(zbuf.dtype))

