"""Fold-over relaxation of a shadow atlas's destination control points (compiled, numpy reference)."""

from __future__ import annotations

import numpy as np

from ...settings import NUMBA_AVAILABLE, compile_kernel, use_compiled

__all__ = ["signed_areas", "RELAX_ROUNDS", "folded_numpy", "any_folded", "any_folded_numpy", "relax_folds",
           "relax_folds_numpy", "relax_folds_python"]


def signed_areas(pts: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Twice the signed area of each triangle (positive counter-clockwise in ``(x, y)``).

    Parameters
    ----------
    pts : ndarray, float (N, 2)
        Vertex positions ``(x, y)`` (pixels).
    tri : ndarray, int (M, 3)
        Vertex indices per triangle.

    Returns
    -------
    ndarray, float (M,)
        The cross product ``(b - a) x (c - a)`` per triangle (pixels^2).
    """
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


#: Rounds of the fold relaxation before falling back to plane anchors.
RELAX_ROUNDS = 16


def folded_numpy(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                  ) -> np.ndarray:
    """Which triangles fold: their orientation differs from ``sign``, or they are too small.

    Parameters
    ----------
    pts : ndarray, float (N, 2)
        Vertex positions ``(x, y)`` (pixels).
    tri : ndarray, int (M, 3)
        Vertex indices per triangle.
    sign : ndarray, float (M,)
        The orientation each triangle must keep (+1 or -1).
    min_area : float
        Smallest absolute value of :func:`signed_areas` that still counts as a triangle.

    Returns
    -------
    ndarray, bool (M,)
        True where the triangle folds.
    """
    area = signed_areas(pts, tri)
    return (np.sign(area) != sign) | (np.abs(area) < min_area)


def any_folded_numpy(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                      ) -> bool:
    """Whether any triangle folds (:func:`folded_numpy`; same parameters); the numpy reference.

    Parameters
    ----------
    pts : (N, 2) float
        Vertex positions (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.

    Returns
    -------
    bool
        True when some triangle folds.
    """
    return bool(folded_numpy(pts, tri, sign, min_area).any())


def relax_folds_numpy(surf: np.ndarray, plane: np.ndarray, tri: np.ndarray, sign: np.ndarray,
                 min_area: float, rounds: int, out: np.ndarray) -> int:
    """Pull the vertices of folded triangles towards their plane positions,
    ``out = plane + a (surf - plane)`` with ``a`` halved per round for every vertex
    of a folded triangle, until nothing folds. Returns the number of rounds taken,
    negated when ``rounds`` did not suffice (``out`` is then meaningless).
    This is the reference for the compiled :func:`relax_folds_python`.

    Parameters
    ----------
    surf : (N, 2) float64
        Destination positions from the surface anchors (pixels).
    plane : (N, 2) float64
        Destination positions from the plane anchors (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.
    rounds : int
        Most halvings tried.
    out : (N, 2) float64
        Filled with the relaxed positions.

    Returns
    -------
    int
        Rounds taken, or ``-rounds`` when they did not suffice.
    """
    alpha = np.ones(len(surf))
    bad = folded_numpy(surf, tri, sign, min_area)
    for k in range(rounds):
        alpha[np.unique(tri[bad])] *= 0.5
        out[...] = plane + alpha[:, None] * (surf - plane)
        bad = folded_numpy(out, tri, sign, min_area)
        if not bad.any():
            return k + 1
    return -rounds


def _tri_folded(p: np.ndarray, tri: np.ndarray, sign: np.ndarray, t: int, min_area: float
                ) -> bool:
    a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
    area = ((p[b, 0] - p[a, 0]) * (p[c, 1] - p[a, 1])
            - (p[b, 1] - p[a, 1]) * (p[c, 0] - p[a, 0]))
    s = 1.0 if area > 0 else (-1.0 if area < 0 else 0.0)
    return s != sign[t] or abs(area) < min_area


def _any_folded_loop(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                     ) -> bool:
    """Whether any triangle folds (:func:`folded_numpy`; same parameters), stopping at the first.

    Parameters
    ----------
    pts : (N, 2) float
        Vertex positions (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.

    Returns
    -------
    bool
        True when some triangle folds.
    """
    for t in range(tri.shape[0]):
        if _tri_folded(pts, tri, sign, t, min_area):
            return True
    return False


def relax_folds_python(surf: np.ndarray, plane: np.ndarray, tri: np.ndarray, sign: np.ndarray,
                min_area: float, rounds: int, out: np.ndarray) -> int:
    """:func:`relax_folds_numpy` as loops, for numba (same parameters and result).

    Parameters
    ----------
    surf, plane : (N, 2) float64
        Surface- and plane-anchor destination positions (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.
    rounds : int
        Most halvings tried.
    out : (N, 2) float64
        Filled with the relaxed positions.

    Returns
    -------
    int
        Rounds taken, or ``-rounds`` when they did not suffice.
    """
    n, m = surf.shape[0], tri.shape[0]
    alpha = np.ones(n)
    mark = np.zeros(n, np.bool_)
    for t in range(m):
        if _tri_folded(surf, tri, sign, t, min_area):
            mark[tri[t, 0]] = mark[tri[t, 1]] = mark[tri[t, 2]] = True
    for k in range(rounds):
        for v in range(n):
            if mark[v]:
                alpha[v] *= 0.5
                mark[v] = False
            out[v, 0] = plane[v, 0] + alpha[v] * (surf[v, 0] - plane[v, 0])
            out[v, 1] = plane[v, 1] + alpha[v] * (surf[v, 1] - plane[v, 1])
        bad = False
        for t in range(m):
            if _tri_folded(out, tri, sign, t, min_area):
                bad = True
                mark[tri[t, 0]] = mark[tri[t, 1]] = mark[tri[t, 2]] = True
        if not bad:
            return k + 1
    return -rounds


if NUMBA_AVAILABLE:  # the inlined helper first: the kernels resolve it when they compile
    _tri_folded = compile_kernel(_tri_folded)
_any_folded_kernel = compile_kernel(_any_folded_loop)
_relax_folds_kernel = compile_kernel(relax_folds_python)


def any_folded(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float) -> bool:
    """Whether a destination mesh folds: the compiled kernel, or the numpy reference
    :func:`any_folded_numpy` (:func:`morphkit.settings.use_compiled` decides at each call).

    Parameters
    ----------
    pts : (N, 2) float
        Vertex positions (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.

    Returns
    -------
    bool
        True when some triangle folds.
    """
    if use_compiled(_any_folded_kernel):
        return bool(_any_folded_kernel(pts, tri, sign, min_area))
    return any_folded_numpy(pts, tri, sign, min_area)


def relax_folds(surf: np.ndarray, plane: np.ndarray, tri: np.ndarray, sign: np.ndarray,
                min_area: float, rounds: int, out: np.ndarray) -> int:
    """The fold relaxation: the compiled kernel, or the numpy reference
    :func:`relax_folds_numpy` (:func:`morphkit.settings.use_compiled` decides at each call).

    Parameters
    ----------
    surf, plane : (N, 2) float64
        Surface- and plane-anchor destination positions (pixels).
    tri : (M, 3) int
        Vertex indices per triangle.
    sign : (M,) float
        Orientation each triangle must keep.
    min_area : float
        Smallest absolute doubled area that counts as a triangle.
    rounds : int
        Most halvings tried.
    out : (N, 2) float64
        Filled with the relaxed positions.

    Returns
    -------
    int
        Rounds taken, or ``-rounds`` when they did not suffice.
    """
    if use_compiled(_relax_folds_kernel):
        return int(_relax_folds_kernel(surf, plane, tri, sign, min_area, rounds, out))
    return relax_folds_numpy(surf, plane, tri, sign, min_area, rounds, out)
