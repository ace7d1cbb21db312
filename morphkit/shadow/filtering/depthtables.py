"""Per-map tables of the filtered shadow lookup: summed-area tables and a max-depth pyramid.

:mod:`morphkit.shadow.filtering.filtered` answers "what fraction of this box of the depth map is
occluder in front of the point" in a few reads whatever the box's size: the summed-area
tables of occluder coverage and depth give a box's coverage and depth sum (four bilinear
reads each), and the max-depth pyramid bounds the depths under a box (whether every
occluder texel there is in front of the receiver) and finds, block by block, those that
are not. Both cover only the window of the map that holds occluder texels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...settings import compile_kernel, use_compiled

__all__ = ["DepthTables"]


@dataclass(frozen=True)
class DepthTables:
    """Per-map tables of the filtered lookup (see the module docstring), over the
    window of the map that holds occluder texels (outside it the map is empty).

    Parameters
    ----------
    sat : (h + 1, w + 1, 2) float64
        Summed-area tables of occluder coverage (``[..., 0]``) and depth
        (``[..., 1]``) over the window (``sat[j, i]``: texels of window rows ``< j``
        and columns ``< i``).
    pyramid : (M,) float64
        Max-depth pyramid of the window, levels concatenated (``-inf``: no occluder).
    offsets : (L,) int64
        Start of each level in ``pyramid``.
    widths : (L,) int64
        Width of each level (level ``l`` has ``ceil(w / 2^l)`` columns).
    origin : (int, int)
        Map row and column of the window's first texel.
    z_min : float
        Nearest occluder depth (``+inf`` for an empty map).
    z_mean : float
        Mean occluder depth (``+inf`` for an empty map).
    """

    sat: np.ndarray
    pyramid: np.ndarray
    offsets: np.ndarray
    widths: np.ndarray
    origin: tuple[int, int]
    z_min: float
    z_mean: float

    @classmethod
    def of(cls, depth_map: np.ndarray) -> DepthTables:
        """The tables of a (checked) depth map.

        Parameters
        ----------
        depth_map : (H, W) float32 or float64
            Linear light depth, ``+inf`` where empty.

        Returns
        -------
        DepthTables
            Its summed-area tables, pyramid and depth statistics.
        """
        box = np.zeros(4, np.int64)
        (_bbox_kernel if use_compiled(_bbox_kernel) else _bbox_loop)(depth_map, box)
        r0, r1, c0, c1 = (int(v) for v in box)
        if r1 < r0:
            return cls(np.zeros((2, 2, 2)), np.full(1, -np.inf), np.zeros(1, np.int64),
                       np.ones(1, np.int64), (0, 0), np.inf, np.inf)
        sub = np.ascontiguousarray(depth_map[r0:r1 + 1, c0:c1 + 1], np.float64)
        h, w = sub.shape
        shapes = [(h, w)]
        while shapes[-1] != (1, 1):
            shapes.append(((shapes[-1][0] + 1) // 2, (shapes[-1][1] + 1) // 2))
        sizes = np.array([a * b for a, b in shapes], np.int64)
        offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        widths = np.array([b for _a, b in shapes], np.int64)
        sat = np.zeros((h + 1, w + 1, 2))
        pyramid = np.empty(int(sizes.sum()))
        stats = np.zeros(2)
        tables = _tables_kernel if use_compiled(_tables_kernel) else _tables_loop
        tables(sub, sat, pyramid, offsets, widths, stats)
        return cls(sat, pyramid, offsets, widths, (r0, c0), float(stats[0]),
                   float(stats[1] / sat[-1, -1, 0]))


def _bbox_loop(dm: np.ndarray, box: np.ndarray) -> None:
    """``box = (first row, last row, first column, last column)`` of the finite texels
    (last < first when there are none)."""
    h, w = dm.shape
    r0, r1, c0, c1 = h, -1, w, -1
    for j in range(h):
        for i in range(w):
            if dm[j, i] < np.inf:
                r0, r1 = min(r0, j), max(r1, j)
                c0, c1 = min(c0, i), max(c1, i)
    box[0], box[1], box[2], box[3] = r0, r1, c0, c1


def _tables_loop(sub: np.ndarray, sat: np.ndarray, pyr: np.ndarray, off: np.ndarray,
                 wid: np.ndarray, stats: np.ndarray) -> None:
    """Fill the summed-area tables and the pyramid; ``stats = (z_min, depth sum)``."""
    h, w = sub.shape
    z_min = np.inf
    for j in range(h):
        c_row, d_row = 0.0, 0.0
        for i in range(w):
            d = sub[j, i]
            if d < np.inf:
                c_row += 1.0
                d_row += d
                z_min = min(z_min, d)
                pyr[j * w + i] = d
            else:
                pyr[j * w + i] = -np.inf
            sat[j + 1, i + 1, 0] = sat[j, i + 1, 0] + c_row
            sat[j + 1, i + 1, 1] = sat[j, i + 1, 1] + d_row
    stats[0] = z_min
    stats[1] = sat[h, w, 1]
    ph, pw = h, w
    for lev in range(1, len(off)):
        nh, nw = (ph + 1) // 2, (pw + 1) // 2
        po, no = off[lev - 1], off[lev]
        for j in range(nh):
            a, b = po + 2 * j * pw, po + min(2 * j + 1, ph - 1) * pw  # the two rows (one at the edge)
            for i in range(nw):
                i0, i1 = 2 * i, min(2 * i + 1, pw - 1)
                pyr[no + j * nw + i] = max(max(pyr[a + i0], pyr[a + i1]), max(pyr[b + i0], pyr[b + i1]))
        ph, pw = nh, nw


_tables_kernel = compile_kernel(_tables_loop)
_bbox_kernel = compile_kernel(_bbox_loop)
