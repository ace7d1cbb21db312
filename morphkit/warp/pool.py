"""Per-thread buffer pools of :mod:`morphkit.warp`: coordinate planes, map
buffers recycled from dead :class:`~morphkit.warp.WarpMaps`."""

from __future__ import annotations

import sys
import threading
from functools import lru_cache

import numpy as np

from ..memo import Memo

__all__ = ["pixel_x_pairs", "coordinate_planes", "map_buffer", "recycle"]


@lru_cache(maxsize=16)
def pixel_x_pairs(c0: int, c1: int, h: int) -> np.ndarray:
    """The pixel ``x`` of each pixel of a ROI, twice (an interleaved map's two columns).

    Parameters
    ----------
    c0, c1 : int
        The ROI's columns ``c0:c1``.
    h : int
        Its number of rows.

    Returns
    -------
    numpy.ndarray
        ``(h * (c1 - c0), 2)`` float32, read-only, cached.
    """
    x = np.arange(c0, c1, dtype=np.float32)
    out = np.repeat(np.tile(x, h), 2).reshape(-1, 2)
    out.setflags(write=False)
    return out


_local = threading.local()


def coordinate_planes(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixel coordinate planes and a work buffer of one output shape, kept per thread.

    Kept for the last four output shapes used (a per-thread :class:`~morphkit.memo.Memo`):
    reusing the buffers avoids fresh page faults on every call (they cost as much
    as the arithmetic).

    Parameters
    ----------
    shape : tuple[int, int]
        ``(H, W)``.

    Returns
    -------
    tuple[numpy.ndarray, numpy.ndarray, numpy.ndarray]
        ``(X, Y, scratch)``, each ``(H, W)`` float32: pixel ``x`` and ``y``
        (read-only) and this thread's scratch buffer.
    """
    planes: Memo[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = getattr(
        _local, "planes", None)
    if planes is None:
        planes = _local.planes = Memo(maxsize=4)
    return planes.get(shape, lambda: _make_planes(shape))


def _make_planes(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    h, w = shape
    X = np.empty(shape, dtype=np.float32)
    X[...] = np.arange(w, dtype=np.float32)
    Y = np.empty(shape, dtype=np.float32)
    Y[...] = np.arange(h, dtype=np.float32)[:, None]
    X.setflags(write=False)
    Y.setflags(write=False)
    return X, Y, np.empty(shape, dtype=np.float32)


def map_buffer(shape: tuple[int, int]) -> np.ndarray:
    """A map buffer, recycled (:func:`recycle`) from a dead
    :class:`~morphkit.warp.WarpMaps` of this thread when possible.

    Parameters
    ----------
    shape : tuple[int, int]
        ``(h, w)``.

    Returns
    -------
    numpy.ndarray
        ``(h, w)`` float32, contents undefined.
    """
    pool = getattr(_local, "pool", None)
    if pool:
        free = pool.get(shape)
        if free:
            return free.pop()
    return np.empty(shape, dtype=np.float32)


def recycle(arr: np.ndarray | None) -> None:
    """Return a map buffer to this thread's pool (:func:`map_buffer`), unless
    anything else still refers to it.

    Fresh page-faulted buffers cost as much as computing the maps; a frame loop
    that drops last frame's WarpMaps reuses its buffers.

    Parameters
    ----------
    arr : numpy.ndarray or None
        A float32 buffer from :func:`map_buffer`, held only by the caller's
        local variable (a view, or one with other references, is left alone).
    """
    # references: the caller's local, the argument, getrefcount's own argument
    if arr is None or arr.base is not None or sys.getrefcount(arr) > 3:
        return
    pool = getattr(_local, "pool", None)
    if pool is None:
        pool = _local.pool = {}
    free = pool.setdefault(arr.shape, [])
    if len(free) < 4:
        if len(pool) > 4:
            pool.clear()
            pool[arr.shape] = free
        free.append(arr)
