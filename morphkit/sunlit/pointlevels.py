"""Coarser levels of an atlas view's surface points: one point per ``b x b`` block of texels.

A sun atlas view (:class:`~morphkit.sunlit.sunatlas.SunAtlas`) holds one surface point per drawn
texel (:meth:`~morphkit.sunlit.sunatlas.SunAtlas.view_points`); splatted into a field light
view whose texel is several atlas texels wide (:mod:`.fieldsplat`), most of them land on a texel
another point already holds. **Level** ``l`` of a view keeps one point per block of
``b = 2**l`` texels a side (level 0: the texels themselves), made by :func:`block_points`:

* its **place**: the centroid of the block's drawn surface points (on the surface where the
  surface is flat across the block: a point moved to the block's nearest depth instead, a
  min-depth mip, would shift a slanted surface's shadow towards the view, and the union with
  the other views' points would grow it);
* its **size**: the side of a square of the drawn texels' area, ``sqrt(k)`` atlas texels for
  ``k`` drawn texels of the block (``b`` for a full block), so a splat of that side covers
  about the texels the block's texels would (an edge block, part drawn, a smaller square
  about its drawn part's centroid: the outline moves by under a block);
* its **normal**: the sum of its drawn texels' known unit normals, normalised (zero where none
  is known).

**The outline.** A block only part drawn (on the view's outline) is given at the next finer
level instead, its ``b / 2`` sub-blocks each a point as above: a square of a thin drawn strip's
area about its centroid reaches past the strip, and the outline's shadow grows (on the suite's
field, ``morphkit bench scene --sections levels``: more ground points wrongly shadowed than at
level 0, fewer missed); at the next level the reach is halved, for a few more points (each
partial block's texels at level 0 would be many more).

**Front and back.** A block whose drawn texels lie at two depths (a leaf before a stem, a card
before the ground behind it) would put its centroid in the air between them: its texels are
split into the **front** (within ``depth_gap`` of the block's nearest depth) and the **back**
(the rest), one point each. A surface slanted so steeply that the gap cuts it gets two
points, both on it.
"""

from __future__ import annotations

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_int

__all__ = ["block_points", "grid_quads"]


def _blocks(a: np.ndarray, b: int) -> np.ndarray:
    """``(n0, n1, ...)`` padded with zeros to multiples of ``b``, as ``(R, C, b * b, ...)``."""
    n0, n1 = a.shape[:2]
    R, C = -(-n0 // b), -(-n1 // b)
    pad = [(0, R * b - n0), (0, C * b - n1)] + [(0, 0)] * (a.ndim - 2)
    p = np.pad(a, pad)
    p = p.reshape(R, b, C, b, *a.shape[2:]).swapaxes(1, 2)
    return p.reshape(R, C, b * b, *a.shape[2:])


def _cluster(m: np.ndarray, p: np.ndarray, n: np.ndarray, b: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centroid, summed normal direction and ``sqrt`` of the count of each block's ``m`` texels
    (the blocks with at least one)."""
    k = _blocks(m.astype(np.float64), b).sum(axis=2)
    keep = k > 0
    kk = k[keep]
    mean_p = _blocks(np.where(m[..., None], p, 0.0), b)[keep].sum(axis=1) / kk[:, None]
    nb = _blocks(np.where(m[..., None], n, 0.0), b)[keep].sum(axis=1)
    norm = np.linalg.norm(nb, axis=1)
    ok = norm > tol.MIN_EXTENT
    out_n = np.where(ok[:, None], nb / np.where(ok, norm, 1.0)[:, None], 0.0)
    return mean_p, out_n, np.sqrt(kk)


def block_points(points: np.ndarray, drawn: np.ndarray, normals: np.ndarray, depth: np.ndarray,
                 block: int, depth_gap: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Up to two points per ``block x block`` texels of a view, its front and its back; a block
    only part drawn at half the side (module docstring).

    Parameters
    ----------
    points : (n0, n1, 3) float
        Each texel's surface point (object frame; any value where not drawn).
    drawn : (n0, n1) bool
        The texels that hold a point.
    normals : (n0, n1, 3) float
        Unit normals, or zeros where unknown.
    depth : (n0, n1) float
        Depth along the view's axis (any value where not drawn).
    block : int
        The block's side, texels (``>= 1``; 1 gives the drawn texels' own points).
    depth_gap : float
        A block's front: its drawn texels within this depth of its nearest (object units,
        ``>= 0``); the others are its back.

    Returns
    -------
    points : (M, 3) float32
        One per full block's front and back (those that have one), then those of the other
        blocks' ``block / 2`` sub-blocks.
    normals : (M, 3) float32
        Unit, or zero where none of the part's normals is known.
    sizes : (M,) float32
        The side of a square of the part's area, atlas texels (``sqrt`` of its texels).

    Raises
    ------
    ValidationError
        Arrays that do not fit ``drawn``'s shape, a block under 1, a negative gap.
    """
    b = as_int(block, "block", lo=1)
    gap = float(depth_gap)
    if not gap >= 0.0 or not np.isfinite(gap):
        raise ValidationError(expected_got("depth_gap", "a finite depth >= 0", depth_gap))
    m = np.asarray(drawn, bool)
    if m.ndim != 2:
        raise ValidationError(expected_got("drawn", "an (n0, n1) mask", m.shape))
    p, n, d = (np.asarray(x, np.float64) for x in (points, normals, depth))
    if p.shape != (*m.shape, 3) or n.shape != p.shape or d.shape != m.shape:
        raise ValidationError(expected_got("points, normals, depth", f"{(*m.shape, 3)} and {m.shape}",
                                           f"{p.shape}, {n.shape}, {d.shape}"))
    if b == 1:
        parts = _fronts(m, p, n, d, 1, gap)
    else:
        full = _spread(_blocks(m, b).all(axis=2), b, m.shape)
        parts = _fronts(m & full, p, n, d, b, gap) + _fronts(m & ~full, p, n, d, b // 2, gap / 2.0)
    pts, nrm, size = (np.ascontiguousarray(np.concatenate([q[j] for q in parts]), np.float32)
                      for j in range(3))
    return pts, nrm, size


def _spread(per_block: np.ndarray, b: int, shape: tuple[int, ...]) -> np.ndarray:
    """A per-block ``(R, C)`` array given to each of its texels, ``shape[:2]``."""
    return np.repeat(np.repeat(per_block, b, axis=0), b, axis=1)[: shape[0], : shape[1]]


def _fronts(m: np.ndarray, p: np.ndarray, n: np.ndarray, d: np.ndarray, b: int, gap: float) -> list:
    """The ``_cluster`` of each ``b``-block's front and of its back (module docstring)."""
    near = _spread(_blocks(np.where(m, d, np.inf), b).min(axis=2), b, m.shape)
    front = m & (d <= near + gap)
    return [_cluster(front, p, n, b), _cluster(m & ~front, p, n, b)]


def grid_quads(drawn: np.ndarray, depth: np.ndarray, depth_gap: float) -> tuple[np.ndarray, np.ndarray]:
    """A view's quads of drawn texels and the texels they cover alone (module docstring, "Quads").

    Parameters
    ----------
    drawn : (n0, n1) bool
        The texels that hold a point.
    depth : (n0, n1) float
        Depth along the view's axis (any value where not drawn).
    depth_gap : float
        A quad's four depths lie within this of each other (the depth's units, ``>= 0``).

    Returns
    -------
    quads : (Q, 4) int64
        Each quad's texels as indices into the drawn texels in row-major order (the order of
        ``points[drawn]``), going round the quad; its triangles are ``(q0, q1, q2)`` and
        ``(q0, q2, q3)``.
    inner : (M,) bool
        Per drawn texel (row-major): all four quads it is a corner of are kept.

    Raises
    ------
    ValidationError
        Shapes that differ or are not 2-D; a negative or non-finite gap.

    Examples
    --------
    >>> import numpy as np
    >>> from morphkit.sunlit.pointlevels import grid_quads
    >>> quads, inner = grid_quads(np.ones((3, 3), bool), np.zeros((3, 3)), 0.5)
    >>> len(quads), int(inner.sum())  # four quads; only the centre texel is inside all four
    (4, 1)
    """
    gap = float(depth_gap)
    if not gap >= 0.0 or not np.isfinite(gap):
        raise ValidationError(expected_got("depth_gap", "a finite depth >= 0", depth_gap))
    m = np.asarray(drawn, bool)
    d = np.asarray(depth, np.float64)
    if m.ndim != 2 or d.shape != m.shape:
        raise ValidationError(expected_got("drawn, depth", "two (n0, n1) arrays of one shape",
                                           f"{m.shape}, {d.shape}"))
    idx = np.full(m.shape, -1, np.int64)
    idx[m] = np.arange(int(m.sum()))
    d = np.where(m, d, 0.0)
    # corners a (top left), b (top right), c (bottom right), e (bottom left) of each quad
    a, b, c, e = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    da, db, dc, de = d[:-1, :-1], d[:-1, 1:], d[1:, 1:], d[1:, :-1]
    four = np.stack([da, db, dc, de])
    kept = (a >= 0) & (b >= 0) & (c >= 0) & (e >= 0) & (four.max(axis=0) - four.min(axis=0) <= gap)
    main = da + dc >= db + de  # split along the deeper diagonal: a-c, else b-e
    k = kept.ravel()
    ring_ac = np.stack([a, b, c, e], -1).reshape(-1, 4)
    ring_be = np.stack([b, c, e, a], -1).reshape(-1, 4)
    quads = np.where(main.ravel()[:, None], ring_ac, ring_be)[k]
    around = np.zeros((m.shape[0] + 1, m.shape[1] + 1), bool)
    around[1:-1, 1:-1] = kept
    inner = around[:-1, :-1] & around[:-1, 1:] & around[1:, :-1] & around[1:, 1:]
    return np.ascontiguousarray(quads, np.int64), inner[m]
