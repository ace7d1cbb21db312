"""Compiled scanline fill of piecewise-affine warp maps (numba).

One pass over the destination triangles writes, for every output pixel centre a
triangle covers, its source position ``A_src_dst[t] @ (x, y, 1)``; pixels no
triangle covers get :data:`morphkit.warp.OUTSIDE`. The coverage rule and the edge arithmetic
are exactly those of :func:`morphkit.warp.build.build_maps`' numpy path (the
reference implementation, kept for tests and for machines without numba): rows
``[ceil(y_top), ceil(y_bottom))``, columns ``[ceil(x_left), ceil(x_right))``,
each edge crossing computed as ``s * y + q`` from the edge's own top end, so
triangles sharing an edge agree bit for bit. Each pixel counts the triangles
covering it; a count above 1 is a fold-over, reported by the caller.

Counting is skipped when the mesh provably cannot overlap itself
(:func:`mesh_injective`: a topological disk whose triangles all keep their
orientation and whose boundary stays a simple polygon); the per-call set-up
(fold test, closed boundary, ROI, affines) is compiled too
(:func:`prepare_warp`). Large ROIs are split into bands of rows filled in
parallel (one per numba thread, ``prange``); a row's values depend only on the
triangles' edges, so the bands change no value. Small ones are filled in the
calling thread (:data:`PARALLEL_MIN_PIXELS`).

:func:`accumulate` walks the same rows but, instead of writing maps, samples
two source planes bilinearly at each pixel's source position and adds them,
weighted, into an accumulator (the fused warp-and-blend of the shadow atlas).
Its per-pixel bounds test is hoisted to one test per triangle.

numba earns its place here: the numpy path needs ~10 full-image passes (runs,
sort, repeat, LUTs, products); the kernel touches each pixel once.
"""

from __future__ import annotations

import math

import numpy as np

from .. import tol
from ..settings import compile_kernel, numba

__all__ = ["accumulate", "fill_maps", "mesh_injective", "n_bands", "prepare_warp", "MIN_BAND_ROWS",
           "PARALLEL_MIN_PIXELS"]


#: Cast of a pixel offset known to be >= 0 (see ``_fill_band``).
_u = numba.uint64 if numba is not None else int


def _tri_rows(cov: np.ndarray, tris: np.ndarray, t: int, b0: int, b1: int
              ) -> tuple[int, int, int, float, float, float, float, float, float]:
    """Scanline set-up of triangle ``t`` clipped to rows ``[b0, b1)``:
    ``(ya, yb, yc, sl, ql, su, qu, sd, qd)``: the upper piece spans rows
    ``[ya, yb)`` between edges ``(sl, ql)`` (long, top to bottom vertex) and
    ``(su, qu)``, the lower piece rows ``[yb, yc)`` between ``(sl, ql)`` and
    ``(sd, qd)``; an edge ``(s, q)`` crosses row ``y`` at ``s * y + q``."""
    ia = tris[t, 0]
    ib = tris[t, 1]
    ic = tris[t, 2]
    # sort the three vertices by y (stable, as numpy's argsort on 3 elements)
    v0, v1, v2 = ia, ib, ic
    if cov[v1, 1] < cov[v0, 1]:
        v0, v1 = v1, v0
    if cov[v2, 1] < cov[v1, 1]:
        v1, v2 = v2, v1
        if cov[v1, 1] < cov[v0, 1]:
            v0, v1 = v1, v0
    x0 = cov[v0, 0]
    y0 = cov[v0, 1]
    x1 = cov[v1, 0]
    y1 = cov[v1, 1]
    x2 = cov[v2, 0]
    y2 = cov[v2, 1]
    sl = (x2 - x0) / (y2 - y0)
    ql = x0 - y0 * sl
    su = (x1 - x0) / (y1 - y0)
    qu = x0 - y0 * su
    sd = (x2 - x1) / (y2 - y1)
    qd = x1 - y1 * sd
    ya = min(max(math.ceil(y0), b0), b1)
    yb = min(max(math.ceil(y1), b0), b1)
    yc = min(max(math.ceil(y2), b0), b1)
    return ya, yb, yc, sl, ql, su, qu, sd, qd


def _row_span(sl: float, ql: float, s: float, q: float, yf: float, c0: int, c1: int
              ) -> tuple[int, int]:
    """Columns ``[xl, xr)`` of row ``yf`` between the edges ``(sl, ql)`` and
    ``(s, q)`` (each crossing the row at ``s * yf + q``), clipped to ``[c0, c1)``:
    the top-left rule of every kernel here."""
    xa = sl * yf
    xa += ql
    xb = s * yf
    xb += q
    xl = min(max(math.ceil(min(xa, xb)), c0), c1)
    xr = min(max(math.ceil(max(xa, xb)), c0), c1)
    return xl, xr


def _fill_band(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
               c1: int, b0: int, b1: int, out_outside: float, mx: np.ndarray, my: np.ndarray,
               count: np.ndarray, counting: bool) -> int:
    """Fill rows ``[b0, b1)`` (absolute, inside ``[r0, r1)``) of ``mx``, ``my``
    (``(r1 - r0, c1 - c0)`` float32). Each row is computed from the triangle's
    edges alone, so splitting the image into bands changes no value.

    ``counting``: count in ``count`` (uint8) how many triangles cover each pixel
    (more than 1 is a fold-over, which the caller checks; the maps then hold the
    last triangle's values), write :data:`out_outside` where none does, and
    return the band's largest count. Otherwise the mesh is known not to overlap
    itself (:func:`mesh_injective`): the rows are written :data:`out_outside`
    first, ``count`` is unused, and the return value is 1 if the band covers a
    pixel, else 0. Both write the same values.
    """
    w = c1 - c0
    for i in range(b0 - r0, b1 - r0):
        if counting:
            count[i, :] = 0
        else:
            mx[i, :] = out_outside
            my[i, :] = out_outside
    top = 0
    for t in range(tris.shape[0]):
        ya, yb, yc, sl, ql, su, qu, sd, qd = _tri_rows(cov, tris, t, b0, b1)
        a00 = coef[t, 0]
        a10 = coef[t, 1]
        a01 = coef[t, 2]
        a11 = coef[t, 3]
        bx = coef[t, 4]
        by = coef[t, 5]
        for piece in range(2):
            if piece == 0:
                ys, ye, s, q = ya, yb, su, qu
            else:
                ys, ye, s, q = yb, yc, sd, qd
            for y in range(ys, ye):
                yf = float(y)
                xl, xr = _row_span(sl, ql, s, q, yf, c0, c1)
                if xr <= xl:
                    continue
                ox = a01 * yf + bx
                oy = a11 * yf + by
                # Unsigned column offsets (x >= xl >= c0): a signed index makes
                # numba test for negative (wrap-around) indices per pixel, which
                # keeps the loops from vectorising (docs/RESULTS.md, mesh warp).
                mrow = mx[y - r0]
                nrow = my[y - r0]
                if counting:  # one branch per run: the pixel loops stay simple
                    crow = count[y - r0]
                    for x in range(xl, xr):
                        crow[_u(x - c0)] += 1
                else:
                    top = 1
                for x in range(xl, xr):
                    xf = float(x)
                    j = _u(x - c0)
                    mrow[j] = a00 * xf + ox
                    nrow[j] = a10 * xf + oy
    if counting:
        for i in range(b0 - r0, b1 - r0):  # pixels no triangle covers
            for j in range(w):
                c = count[i, j]
                if c == 0:
                    mx[i, j] = out_outside
                    my[i, j] = out_outside
                elif c > top:
                    top = c
    return top


def _fill_one(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
              c1: int, out_outside: float, mx: np.ndarray, my: np.ndarray, count: np.ndarray,
              n_bands: int, counting: bool, b: int) -> int:
    """Band ``b`` of ``n_bands`` (``_fill_band``)."""
    h = r1 - r0
    lo = r0 + (h * b) // n_bands
    hi = r0 + (h * (b + 1)) // n_bands
    return _fill_band(cov, tris, coef, r0, r1, c0, c1, lo, hi, out_outside, mx, my, count, counting)


def _fill_parallel(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int,
                   c0: int, c1: int, out_outside: float, mx: np.ndarray, my: np.ndarray,
                   count: np.ndarray, n_bands: int, counting: bool) -> int:
    tops = np.zeros(n_bands, np.int64)
    for b in _prange(n_bands):
        tops[b] = _fill_one(cov, tris, coef, r0, r1, c0, c1, out_outside, mx, my, count, n_bands,
                            counting, b)
    return int(tops.max())


def _fill_serial(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
                 c1: int, out_outside: float, mx: np.ndarray, my: np.ndarray, count: np.ndarray,
                 n_bands: int, counting: bool) -> int:
    top = 0
    for b in range(n_bands):
        top = max(top, _fill_one(cov, tris, coef, r0, r1, c0, c1, out_outside, mx, my, count,
                                 n_bands, counting, b))
    return top


def fill_maps(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
              c1: int, out_outside: float, mx: np.ndarray, my: np.ndarray, count: np.ndarray,
              n_bands: int, counting: bool) -> int:
    """Fill the maps of ROI rows ``[r0, r1)``, columns ``[c0, c1)`` in ``n_bands``
    bands of rows (:func:`n_bands`): in parallel (numba ``prange``, the bands
    write disjoint rows) when there are several, else in the calling thread.
    ``counting``: count coverage in ``count``; otherwise the mesh is known
    injective and ``count`` is unused (``_fill_band``). Returns the largest
    count (0: nothing covered, > 1: a fold-over).

    Parameters
    ----------
    cov : (N, 2) float64
        Coverage geometry, output pixels (``Accumulation.cov``).
    tris : (M, 3) int64
        Vertex indices per triangle.
    coef : (M, 6) float64
        Per-triangle affines ``A_src_dst`` as ``[jxx, jyx, jxy, jyy, cx, cy]``.
    r0, r1, c0, c1 : int
        The ROI, output rows and columns.
    out_outside : float
        Map value written where no triangle covers a pixel.
    mx, my : (r1 - r0, c1 - c0) float32
        The maps (source ``x`` and ``y``), filled in place.
    count : (r1 - r0, c1 - c0) uint8
        Coverage counts, filled when ``counting``.
    n_bands : int
        Bands of rows (1: the calling thread).
    counting : bool
        Count coverage per pixel (the mesh is not known injective).

    Returns
    -------
    int
        The largest coverage count.
    """
    if n_bands > 1:
        return _fill_parallel_jit(cov, tris, coef, r0, r1, c0, c1, out_outside, mx, my, count,
                                  n_bands, counting)
    return _fill_serial_jit(cov, tris, coef, r0, r1, c0, c1, out_outside, mx, my, count, 1,
                            counting)


def _sample_border(plane: np.ndarray, ix: int, iy: int, ax: float, ay: float) -> float:
    """Bilinear sample of ``plane`` at ``(ix + ax, iy + ay)`` reading 0 outside it
    (``cv2.BORDER_CONSTANT`` with value 0)."""
    h, w = plane.shape
    v = 0.0
    for dy in range(2):
        yy = iy + dy
        if yy < 0 or yy >= h:
            continue
        wy = ay if dy else 1.0 - ay
        for dx in range(2):
            xx = ix + dx
            if xx < 0 or xx >= w:
                continue
            v += wy * (ax if dx else 1.0 - ax) * plane[yy, xx]
    return v


def _accumulate(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, active: np.ndarray,
                src: np.ndarray, weight: float, acc: np.ndarray, r0: int, r1: int, c0: int,
                c1: int, box: np.ndarray) -> int:
    """``acc[p, y, x] += weight * src[p](A_t (x, y))`` for ``p = 0, 1`` (bilinear,
    0 outside ``src``) for every pixel centre ``(x, y)`` of every ``active``
    triangle ``t``, in rows ``[r0, r1)`` and columns ``[c0, c1)`` (a band of the
    ROI: rows are clipped as in ``_fill_band``): the warp maps and the remap
    of :func:`fill_maps` fused into one pass, for a mesh known not to overlap
    itself (:func:`mesh_injective`: each pixel is visited once). Same coverage
    rule and edge arithmetic as ``_fill_band``; source positions are exact
    (float64), where ``cv2.remap`` quantises them to 1/32 px. ``src`` and ``acc``
    are ``(2, H, W)`` float32 (``acc`` C-contiguous); ``src`` must be finite.
    ``box`` (int64 ``[y0, y1, x0, x1]``) is grown to hold every pixel written.
    Returns the number of pixels written.

    Parameters
    ----------
    cov : (N, 2) float64
        Coverage geometry, output pixels.
    tris : (M, 3) int64
        Vertex indices per triangle.
    coef : (M, 6) float64
        Per-triangle affines ``A_src_dst`` as ``[jxx, jyx, jxy, jyy, cx, cy]``.
    active : (M,) bool
        The triangles to draw.
    src : (2, h, w) float32
        Source planes, input pixels.
    weight : float
        Weight of this source.
    acc : (2, H, W) float32
        Accumulator, updated in place.
    r0, r1, c0, c1 : int
        The band, output rows and columns.
    box : (4,) int64
        ``[y0, y1, x0, x1]`` of the pixels written, grown in place.

    Returns
    -------
    int
        Pixels written.
    """
    h = src.shape[1]
    w = src.shape[2]
    s0 = src[0]
    s1 = src[1]
    acc0 = acc[0]
    acc1 = acc[1]
    wm1 = float(w - 1)
    hm1 = float(h - 1)
    n = 0
    for t in range(tris.shape[0]):
        if not active[t]:
            continue
        ya, yb, yc, sl, ql, su, qu, sd, qd = _tri_rows(cov, tris, t, r0, r1)
        a00 = coef[t, 0]
        a10 = coef[t, 1]
        a01 = coef[t, 2]
        a11 = coef[t, 3]
        bx = coef[t, 4]
        by = coef[t, 5]
        # Bounds are tested per triangle: the pixels it covers lie in its
        # (pushed-out) triangle ``cov``, whose image by the affine holds every
        # source position read. Inside [0.5, size - 1.5] with room to spare,
        # every footprint is in the source: no per-pixel test.
        safe = True
        for v in range(3):
            px = cov[tris[t, v], 0]
            py = cov[tris[t, v], 1]
            sx = a00 * px + a01 * py + bx
            sy = a10 * px + a11 * py + by
            if not (0.5 <= sx <= wm1 - 0.5 and 0.5 <= sy <= hm1 - 0.5):
                safe = False
        for piece in range(2):
            if piece == 0:
                ys, ye, s, q = ya, yb, su, qu
            else:
                ys, ye, s, q = yb, yc, sd, qd
            for y in range(ys, ye):
                yf = float(y)
                xl, xr = _row_span(sl, ql, s, q, yf, c0, c1)
                if xr <= xl:
                    continue
                n += xr - xl
                box[0] = min(box[0], y)
                box[1] = max(box[1], y + 1)
                box[2] = min(box[2], xl)
                box[3] = max(box[3], xr)
                ox = a01 * yf + bx
                oy = a11 * yf + by
                out0 = acc0[_u(y)]
                out1 = acc1[_u(y)]
                if safe:
                    for x in range(xl, xr):
                        xf = float(x)
                        sx = a00 * xf + ox
                        sy = a10 * xf + oy
                        ix = int(sx)  # truncation is floor here
                        iy = int(sy)
                        ax = np.float32(sx - ix)
                        ay = np.float32(sy - iy)
                        bx0 = np.float32(1.0) - ax
                        by0 = np.float32(1.0) - ay
                        u0 = _u(ix)
                        u1 = _u(ix + 1)
                        t0 = s0[_u(iy)]
                        b0 = s0[_u(iy + 1)]
                        v0 = by0 * (bx0 * t0[u0] + ax * t0[u1]) + ay * (bx0 * b0[u0] + ax * b0[u1])
                        t0 = s1[_u(iy)]
                        b0 = s1[_u(iy + 1)]
                        v1 = by0 * (bx0 * t0[u0] + ax * t0[u1]) + ay * (bx0 * b0[u0] + ax * b0[u1])
                        out0[_u(x)] += weight * v0
                        out1[_u(x)] += weight * v1
                else:
                    for x in range(xl, xr):
                        xf = float(x)
                        sx = a00 * xf + ox
                        sy = a10 * xf + oy
                        fx = math.floor(sx)
                        fy = math.floor(sy)
                        out0[x] += weight * _sample_border(s0, int(fx), int(fy), sx - fx, sy - fy)
                        out1[x] += weight * _sample_border(s1, int(fx), int(fy), sx - fx, sy - fy)
    return n


def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def _mesh_injective(cov: np.ndarray, tris: np.ndarray, sign: np.ndarray, loop: np.ndarray
                    ) -> bool:
    """Whether a mesh that is a topological disk (``loop``: its boundary
    vertices in cycle order, :func:`morphkit.warp.mesh.disk_boundary`) is mapped by
    ``cov`` without overlap: every triangle keeps the orientation ``sign`` and the
    boundary polygon is simple. Then the map has degree 1 inside the boundary's
    image and is one-to-one (each point's preimages all count +1 and sum to the
    winding number 1). Conservative: touching or collinear boundary edges count
    as crossing (the caller then counts coverage per pixel instead).

    Parameters
    ----------
    cov : (N, 2) float64
        Destination vertex positions, output pixels.
    tris : (M, 3) int64
        Vertex indices per triangle.
    sign : (M,) float64
        Orientation each triangle must keep.
    loop : (B,) int64
        Boundary vertices in cycle order.

    Returns
    -------
    bool
        True when the mesh is provably injective.
    """
    for t in range(tris.shape[0]):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        ar = _orient(cov[a, 0], cov[a, 1], cov[b, 0], cov[b, 1], cov[c, 0], cov[c, 1])
        if ar == 0.0 or (ar > 0.0) != (sign[t] > 0.0):
            return False
    n = loop.shape[0]
    for i in range(n):
        p = cov[loop[i]]
        q = cov[loop[(i + 1) % n]]
        r = cov[loop[(i + 2) % n]]
        # a spike: the boundary turns back on itself at q
        if (_orient(p[0], p[1], q[0], q[1], r[0], r[1]) == 0.0
                and (q[0] - p[0]) * (r[0] - q[0]) + (q[1] - p[1]) * (r[1] - q[1]) <= 0.0):
            return False
        lox = min(p[0], q[0])
        hix = max(p[0], q[0])
        loy = min(p[1], q[1])
        hiy = max(p[1], q[1])
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue  # adjacent through the loop's closing edge
            u = cov[loop[j]]
            v = cov[loop[(j + 1) % n]]
            if (max(u[0], v[0]) < lox or min(u[0], v[0]) > hix or max(u[1], v[1]) < loy
                    or min(u[1], v[1]) > hiy):
                continue
            d1 = _orient(u[0], u[1], v[0], v[1], p[0], p[1])
            d2 = _orient(u[0], u[1], v[0], v[1], q[0], q[1])
            d3 = _orient(p[0], p[1], q[0], q[1], u[0], u[1])
            d4 = _orient(p[0], p[1], q[0], q[1], v[0], v[1])
            if d1 * d2 <= 0.0 and d3 * d4 <= 0.0:
                return False
    return True


def _prepare_warp(dst: np.ndarray, tris: np.ndarray, src_v: np.ndarray, src_sign: np.ndarray,
                  boundary: np.ndarray, H: int, W: int, min_det: float, push: float,
                  cov: np.ndarray, coef: np.ndarray) -> tuple[int, int, int, int, int]:
    """The per-call set-up of :func:`morphkit.warp.build.prepare` in one compiled
    pass (the numpy version is the reference and writes the error messages):
    fold test, boundary pushed out by ``push`` into ``cov``, ROI, per-triangle
    affines into ``coef``. Returns ``(n_folded, r0, r1, c0, c1)``; on
    ``n_folded > 0`` nothing else is computed.

    Parameters
    ----------
    dst : (N, 2) float64
        Destination points ``(x, y)``, output pixels.
    tris : (M, 3) int64
        Vertex indices per triangle.
    src_v : (M, 3, 2) float64
        Source triangle vertices, input pixels.
    src_sign : (M,) float64
        Orientation of each source triangle.
    boundary : (B, 3) int64
        Boundary edges (:func:`morphkit.warp.mesh.boundary_edges`).
    H, W : int
        Output size.
    min_det : float
        Smallest absolute doubled triangle area that is not a fold.
    push : float
        How far the boundary is pushed out (pixels).
    cov : (N, 2) float64
        Filled with the coverage geometry.
    coef : (M, 6) float64
        Filled with the per-triangle affines.

    Returns
    -------
    tuple of int
        ``(n_folded, r0, r1, c0, c1)``.
    """
    M = tris.shape[0]
    bad = 0
    edges = np.empty((M, 5))  # d1 = v1 - v0, d2 = v2 - v0, det = d1 x d2 (2 * signed area)
    for t in range(M):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        d1x = dst[b, 0] - dst[a, 0]
        d1y = dst[b, 1] - dst[a, 1]
        d2x = dst[c, 0] - dst[a, 0]
        d2y = dst[c, 1] - dst[a, 1]
        det = d1x * d2y - d1y * d2x
        edges[t, 0] = d1x
        edges[t, 1] = d1y
        edges[t, 2] = d2x
        edges[t, 3] = d2y
        edges[t, 4] = det
        sg = 1.0 if det > 0.0 else (-1.0 if det < 0.0 else 0.0)
        if sg != src_sign[t] or abs(det) < min_det:
            bad += 1
    if bad:
        return bad, 0, 0, 0, 0
    n = dst.shape[0]
    for i in range(n):
        cov[i, 0] = 0.0
        cov[i, 1] = 0.0
    nb = boundary.shape[0]
    nrm = np.empty((nb, 2))
    for k in range(nb):
        a = boundary[k, 0]
        b = boundary[k, 1]
        c = boundary[k, 2]
        ex = dst[b, 0] - dst[a, 0]
        ey = dst[b, 1] - dst[a, 1]
        nx = ey
        ny = -ex
        ln = max(math.hypot(nx, ny), tol.ZERO)
        nx /= ln
        ny /= ln
        if nx * (dst[c, 0] - dst[a, 0]) + ny * (dst[c, 1] - dst[a, 1]) > 0.0:
            nx = -nx
            ny = -ny
        nrm[k, 0] = nx
        nrm[k, 1] = ny
    for col in range(2):  # the order of numpy's two np.add.at calls
        for k in range(nb):
            v = boundary[k, col]
            cov[v, 0] += nrm[k, 0]
            cov[v, 1] += nrm[k, 1]
    lox = hix = loy = hiy = 0.0
    for i in range(n):
        x = dst[i, 0] + push * cov[i, 0]
        y = dst[i, 1] + push * cov[i, 1]
        cov[i, 0] = x
        cov[i, 1] = y
        if i == 0 or x < lox:
            lox = x
        if i == 0 or x > hix:
            hix = x
        if i == 0 or y < loy:
            loy = y
        if i == 0 or y > hiy:
            hiy = y
    r0 = min(max(math.ceil(loy), 0), H)
    r1 = min(max(math.ceil(hiy), 0), H)
    c0 = min(max(math.ceil(lox), 0), W)
    c1 = min(max(math.ceil(hix), 0), W)
    if r1 <= r0 or c1 <= c0:
        return 0, r0, r1, c0, c1
    for t in range(M):
        a = tris[t, 0]
        d1x = edges[t, 0]
        d1y = edges[t, 1]
        d2x = edges[t, 2]
        d2y = edges[t, 3]
        inv = 1.0 / edges[t, 4]
        i00 = d2y * inv
        i01 = -d2x * inv
        i10 = -d1y * inv
        i11 = d1x * inv
        s1x = src_v[t, 1, 0] - src_v[t, 0, 0]
        s1y = src_v[t, 1, 1] - src_v[t, 0, 1]
        s2x = src_v[t, 2, 0] - src_v[t, 0, 0]
        s2y = src_v[t, 2, 1] - src_v[t, 0, 1]
        j0 = s1x * i00 + s2x * i10
        j1 = s1y * i00 + s2y * i10
        j2 = s1x * i01 + s2x * i11
        j3 = s1y * i01 + s2y * i11
        coef[t, 0] = j0
        coef[t, 1] = j1
        coef[t, 2] = j2
        coef[t, 3] = j3
        coef[t, 4] = src_v[t, 0, 0] - j0 * dst[a, 0] - j2 * dst[a, 1]
        coef[t, 5] = src_v[t, 0, 1] - j1 * dst[a, 0] - j3 * dst[a, 1]
    return 0, r0, r1, c0, c1


#: Rows per band, at least, when filling in parallel.
MIN_BAND_ROWS = 64

#: ROI pixels below which the fill runs in the calling thread: waking numba's
#: sleeping worker threads (OpenMP, passive waiting: :mod:`morphkit.settings`)
#: costs more than a whole fill of a ROI this small in one thread, while larger
#: ones gain from the bands (figures: ``docs/RESULTS.md``, mesh warp; measure
#: with ``morphkit bench warp``).
PARALLEL_MIN_PIXELS = 1 << 19


def n_bands(rows: int, cols: int) -> int:
    """How many bands to fill a ``rows x cols`` ROI in: 1 below
    :data:`PARALLEL_MIN_PIXELS`, else one per numba thread, at least
    :data:`MIN_BAND_ROWS` rows each.

    Parameters
    ----------
    rows, cols : int
        Size of the ROI.

    Returns
    -------
    int
        Number of bands (>= 1).
    """
    if numba is None or rows * cols < PARALLEL_MIN_PIXELS:
        return 1
    return max(1, min(numba.get_num_threads(), rows // MIN_BAND_ROWS))


if numba is not None:
    _prange = numba.prange
    _tri_rows = compile_kernel(_tri_rows, error_model="numpy")
    _row_span = compile_kernel(_row_span, error_model="numpy", inline="always")
    _fill_band = compile_kernel(_fill_band, error_model="numpy")
    _fill_one = compile_kernel(_fill_one, error_model="numpy")
    _orient = compile_kernel(_orient, error_model="numpy")
    mesh_injective = compile_kernel(_mesh_injective, error_model="numpy")
    prepare_warp = compile_kernel(_prepare_warp, error_model="numpy")
    _fill_serial_jit = compile_kernel(_fill_serial, error_model="numpy")
    _sample_border = compile_kernel(_sample_border, error_model="numpy")
    accumulate = compile_kernel(_accumulate, error_model="numpy",
                                fastmath={"contract", "reassoc", "nsz", "arcp", "afn"})
    _fill_parallel_jit = compile_kernel(_fill_parallel, parallel=True, error_model="numpy")
else:  # pragma: no cover - no numba: the public kernels are None, as compile_kernel returns
    # them, and callers run their numpy references (morphkit.settings.use_compiled)
    _prange = range
    fill_maps = accumulate = mesh_injective = prepare_warp = None
