"""Per-thread buffer pools of :mod:`morphkit.warp`: coordinate planes, map
buffers recycled from dead :class:`~morphkit.warp.WarpMaps`."""

from __future__ import annotations

import sys
import threading
from functools import lru_cache

import numpy as np


@lru_cache(maxsize=16)
def _xx(c0: int, c1: int, h: int) -> np.ndarray:
    """(h * (c1 - c0), 2) float32: the pixel x coordinate, twice, for each ROI pixel."""
    x = np.arange(c0, c1, dtype=np.float32)
    out = np.repeat(np.tile(x, h), 2).reshape(-1, 2)
    out.setflags(write=False)
    return out


_local = threading.local()


def _planes(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(X, Y, scratch)`` float32 ``shape`` arrays: pixel x, pixel y, and a per-thread work buffer.

    Kept per thread for the last few output shapes: reusing the buffers avoids
    fresh page faults on every call (they cost as much as the arithmetic).
    """
    cache = getattr(_local, "planes", None)
    if cache is None:
        cache = _local.planes = {}
    hit = cache.get(shape)
    if hit is None:
        if len(cache) >= 4:
            cache.pop(next(iter(cache)))
        h, w = shape
        X = np.empty(shape, dtype=np.float32)
        X[...] = np.arange(w, dtype=np.float32)
        Y = np.empty(shape, dtype=np.float32)
        Y[...] = np.arange(h, dtype=np.float32)[:, None]
        X.setflags(write=False)
        Y.setflags(write=False)
        hit = cache[shape] = (X, Y, np.empty(shape, dtype=np.float32))
    return hit


def _pooled(shape: tuple[int, int]) -> np.ndarray:
    """A float32 ``shape`` array, recycled from dead :class:`WarpMaps` when possible."""
    pool = getattr(_local, "pool", None)
    if pool:
        free = pool.get(shape)
        if free:
            return free.pop()
    return np.empty(shape, dtype=np.float32)


def _recycle(arr: np.ndarray | None) -> None:
    """Return a map buffer to this thread's pool, unless anything else still refers to it.

    (Fresh page-faulted buffers cost as much as computing the maps; a frame loop
    that drops last frame's WarpMaps reuses its buffers.)
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
