"""Mesh topology and its checks: triangulations, the grid lattice, triangle
validation, boundary edges and the disk test of :mod:`morphkit.warp`."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_int, as_points

__all__ = ["grid_triangles", "delaunay_triangles", "grid_shape", "signed_area", "list_indices",
           "as_mesh_points", "as_triangles", "default_triangles", "boundary_edges", "disk_boundary"]

# --------------------------------------------------------------------------- topology


def grid_triangles(rows: int, cols: int) -> np.ndarray:
    """Triangles of a regular ``rows x cols`` grid of points in row-major order.

    Point ``(r, c)`` has index ``r * cols + c``. Each cell is split along its
    top-left to bottom-right diagonal into two triangles, listed cell by cell in
    row-major order.

    Parameters
    ----------
    rows, cols : int
        Number of point rows and columns, integers ``>= 2`` (see :func:`morphkit.validate.as_int`).

    Returns
    -------
    numpy.ndarray
        ``(2 * (rows - 1) * (cols - 1), 3)`` int32 vertex indices.

    Examples
    --------
    >>> from morphkit.warp import grid_triangles
    >>> grid_triangles(2, 3)  # points 0 1 2 over 3 4 5: two cells, two triangles each
    array([[0, 1, 4],
           [0, 4, 3],
           [1, 2, 5],
           [1, 5, 4]], dtype=int32)
    """
    rows, cols = as_int(rows, "grid_triangles rows", lo=2), as_int(cols, "grid_triangles cols", lo=2)
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(cols - 1), indexing="ij")
    a = (r * cols + c).ravel()
    b, d = a + 1, a + cols
    e = d + 1
    tris = np.empty((a.size, 2, 3), dtype=np.int32)
    tris[:, 0] = np.stack([a, b, e], axis=1)
    tris[:, 1] = np.stack([a, e, d], axis=1)
    return tris.reshape(-1, 3)


def delaunay_triangles(points: Any) -> np.ndarray:
    """Delaunay triangulation of ``points`` (``(N, 2)``, ``N >= 3``, not collinear).

    Returns ``(M, 3)`` int32 vertex indices, every triangle with positive signed
    area in the pixel frame (``x`` right, ``y`` down).

    Parameters
    ----------
    points : (N, 2) float
        Pixel positions ``(x, y)``.

    Returns
    -------
    (M, 3) int32
        Vertex indices per triangle.
    """
    from scipy.spatial import Delaunay, QhullError

    pts = as_points(points, "points", min_count=3)
    try:
        tris = Delaunay(pts).simplices.astype(np.int32)
    except QhullError as exc:
        raise ValidationError(
            expected_got("points", "points spanning a 2-D area", "degenerate (e.g. collinear) points")
        ) from exc
    neg = signed_area(pts[tris]) < 0
    tris[neg] = tris[neg][:, [0, 2, 1]]
    return tris


def grid_shape(points: Any) -> tuple[int, int] | None:
    """Return ``(rows, cols)`` if ``points`` is a row-major axis-aligned lattice, else None.

    A lattice here has ``rows, cols >= 2``, every row sharing one ``y`` and the
    same strictly monotonic ``x`` sequence, and rows strictly monotonic in ``y``
    (the spacing need not be uniform).

    Parameters
    ----------
    points : (N, 2) float
        Pixel positions ``(x, y)``.

    Returns
    -------
    tuple of int or None
        ``(rows, cols)`` with ``rows * cols == N``, or None.
    """
    pts = np.asarray(points, dtype=np.float64)
    n = pts.shape[0]
    if pts.ndim != 2 or pts.shape[1] != 2 or n < 4:
        return None
    scale = max(1.0, float(np.max(np.abs(pts))))
    eps = tol.REL_EQUAL * scale
    same_y = np.abs(pts[:, 1] - pts[0, 1]) <= eps
    cols = int(np.argmin(same_y)) if not same_y.all() else n
    if cols < 2 or n % cols:
        return None
    rows = n // cols
    if rows < 2:
        return None
    g = pts.reshape(rows, cols, 2)
    if np.max(np.abs(g[:, :, 1] - g[:, :1, 1])) > eps or np.max(np.abs(g[:, :, 0] - g[:1, :, 0])) > eps:
        return None
    dx, dy = np.diff(g[0, :, 0]), np.diff(g[:, 0, 1])
    if not ((dx > eps).all() or (dx < -eps).all()) or not ((dy > eps).all() or (dy < -eps).all()):
        return None
    return rows, cols


def signed_area(v: np.ndarray) -> np.ndarray:
    """Signed areas of triangles in the pixel frame.

    Parameters
    ----------
    v : numpy.ndarray
        ``(M, 3, 2)`` float vertices ``(x, y)`` of each triangle, pixels.

    Returns
    -------
    numpy.ndarray
        ``(M,)`` float64 signed areas in px^2; positive = clockwise on screen
        (``x`` right, ``y`` down).
    """
    d1 = v[:, 1] - v[:, 0]
    d2 = v[:, 2] - v[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def list_indices(idx: np.ndarray, limit: int = 10) -> str:
    """Triangle indices for an error message: ``"[3, 7, ...] (12 in all)"``.

    Parameters
    ----------
    idx : numpy.ndarray
        ``(K,)`` integer indices.
    limit : int
        How many to list before ``...``.

    Returns
    -------
    str
    """
    head = ", ".join(str(int(i)) for i in idx[:limit])
    return f"[{head}{', ...' if idx.size > limit else ''}] ({idx.size} in all)"


def as_mesh_points(points: Any, name: str, *, min_count: int = 0) -> np.ndarray:
    """Control points of a mesh warp: finite, ``(N, 2)``, within :data:`tol.MAX_COORD_PX`.

    Parameters
    ----------
    points : array_like
        ``(N, 2)`` pixel positions ``(x, y)``.
    name : str
        What they are, for the message.
    min_count : int
        Fewest points accepted.

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` float64.

    Raises
    ------
    ValidationError
        Not ``(N, 2)``, NaN/inf, fewer than ``min_count`` points, or a
        coordinate whose magnitude exceeds :data:`tol.MAX_COORD_PX`.
    """
    pts = as_points(points, name, min_count=min_count)
    far = np.abs(pts) > tol.MAX_COORD_PX
    if far.any():
        raise ValidationError(expected_got(
            name, f"coordinates within +-{tol.MAX_COORD_PX:g} px (tol.MAX_COORD_PX)",
            f"{int(far.any(axis=1).sum())} points beyond it (largest |coordinate| {np.abs(pts).max():.3g})"))
    return pts


def as_triangles(triangles: Any, n_points: int) -> np.ndarray:
    """Validate triangle vertex indices into a mesh of ``n_points`` points.

    Parameters
    ----------
    triangles : array_like
        ``(M, 3)`` integer (or integral float) vertex indices, ``M >= 1``.
    n_points : int
        Number of mesh points ``N``.

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` int32, C-contiguous.

    Raises
    ------
    ValidationError
        Wrong shape or dtype, indices outside ``[0, N)``, a repeated vertex.
    """
    try:
        arr = np.asarray(triangles)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got("triangles", "an (M, 3) integer array", repr(triangles))) from exc
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] < 1:
        raise ValidationError(expected_got("triangles", "shape (M, 3) with M >= 1", f"shape {arr.shape}"))
    if arr.dtype.kind not in "iu":
        if arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr)):
            arr = arr.astype(np.int64)
        else:
            raise ValidationError(expected_got("triangles", "integer vertex indices", f"dtype {arr.dtype}"))
    bad = np.flatnonzero(((arr < 0) | (arr >= n_points)).any(axis=1))
    if bad.size:
        raise ValidationError(
            expected_got("triangles", f"indices in [0, {n_points})",
                         f"out-of-range indices in triangles {list_indices(bad)}")
        )
    rep = np.flatnonzero((arr[:, 0] == arr[:, 1]) | (arr[:, 1] == arr[:, 2]) | (arr[:, 0] == arr[:, 2]))
    if rep.size:
        raise ValidationError(
            expected_got("triangles", "three distinct vertices each",
                         f"repeated vertices in triangles {list_indices(rep)}")
        )
    return np.ascontiguousarray(arr, dtype=np.int32)


def default_triangles(src: np.ndarray) -> np.ndarray:
    """The default topology of a source mesh: :func:`grid_triangles` when
    ``src`` is a lattice (:func:`grid_shape`), else :func:`delaunay_triangles`.

    Parameters
    ----------
    src : numpy.ndarray
        ``(N, 2)`` float64 source points ``(x, y)``.

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` int32 vertex indices.
    """
    shape = grid_shape(src)
    if shape is not None:
        return grid_triangles(*shape)
    return delaunay_triangles(src)


def boundary_edges(tris: np.ndarray, n_points: int) -> np.ndarray:
    """The mesh-boundary edges (those in one triangle only).

    Parameters
    ----------
    tris : numpy.ndarray
        ``(M, 3)`` integer vertex indices.
    n_points : int
        Number of mesh points ``N``.

    Returns
    -------
    numpy.ndarray
        ``(B, 3)`` integer ``(a, b, c)`` for each boundary edge ``ab`` of triangle ``abc``.

    Raises
    ------
    ValidationError
        An edge shared by more than two triangles (not a manifold).
    """
    a = tris.ravel()
    b = tris[:, [1, 2, 0]].ravel()
    c = tris[:, [2, 0, 1]].ravel()
    key = np.minimum(a, b).astype(np.int64) * n_points + np.maximum(a, b)
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    per_edge = counts[inverse]
    if per_edge.max() > 2:
        raise ValidationError(
            expected_got("triangles", "a manifold mesh (each edge in at most 2 triangles)",
                         f"an edge shared by {int(per_edge.max())} triangles")
        )
    once = per_edge == 1
    return np.stack([a[once], b[once], c[once]], axis=1)


def disk_boundary(tris: np.ndarray, sign: np.ndarray) -> np.ndarray | None:
    """The boundary vertices of a mesh in cycle order, if the mesh is a
    consistently oriented topological disk; else None.

    Parameters
    ----------
    tris : numpy.ndarray
        ``(M, 3)`` integer vertex indices.
    sign : numpy.ndarray
        ``(M,)`` float, each triangle's orientation in the source
        (``np.sign`` of :func:`signed_area`).

    Returns
    -------
    numpy.ndarray or None
        ``(B,)`` int64 boundary vertex indices in cycle order, or None.

    Notes
    -----
    With ``sign`` each triangle is
    oriented ``(a, b, c)`` or ``(a, c, b)``; the mesh is a disk when no directed
    edge repeats (consistent orientation, a manifold), the directed edges without
    a reverse form one cycle through distinct vertices, the triangles are
    connected, and ``V - E + F == 1``. A disk whose warp keeps every triangle's
    orientation and maps the boundary to a simple polygon cannot overlap itself
    (:func:`morphkit.warp.scanline.mesh_injective`): the compiled fill then skips
    counting coverage per pixel.
    """
    if len(tris) == 0:
        return None
    t = tris.astype(np.int64)
    flip = sign < 0
    t[flip] = t[flip][:, [0, 2, 1]]
    a = t.ravel()
    b = t[:, [1, 2, 0]].ravel()
    n = int(t.max()) + 1
    key = a * n + b
    if np.unique(key).size != key.size:
        return None
    bnd = ~np.isin(b * n + a, key)
    ba, bb = a[bnd], b[bnd]
    if ba.size < 3 or np.unique(ba).size != ba.size:
        return None
    nxt = dict(zip(ba.tolist(), bb.tolist(), strict=True))
    loop = [int(ba[0])]
    while True:
        v = nxt.get(loop[-1])
        if v is None:
            return None
        if v == loop[0]:
            break
        loop.append(v)
        if len(loop) > ba.size:
            return None
    if len(loop) != ba.size:
        return None  # several boundary loops (holes, several pieces)
    used = np.unique(t)
    n_edges = (key.size + ba.size) // 2
    if used.size - n_edges + len(t) != 1:
        return None
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    tri_id = np.repeat(np.arange(len(t)), 3)
    adj = coo_matrix((np.ones(key.size), (tri_id, a)), shape=(len(t), n)).tocsr()
    n_comp, _ = connected_components(adj @ adj.T, directed=False)
    if n_comp != 1:
        return None
    return np.asarray(loop, dtype=np.int64)
