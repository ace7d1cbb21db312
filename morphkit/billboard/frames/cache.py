"""The morph cache: a bounded least-recently-used store of billboard images.

A scene of many instances of a few assets asks for the same few images again
and again: instances seen from nearby azimuths share a quantised ``s``, and a
camera that moves a little keeps most keys of the last frame. The cache keys an
image by ``(asset name, i, j, quantised s, level)`` (:func:`morph_key`) and
holds at most ``capacity`` entries and ``max_bytes`` bytes of images, evicting
the least recently used first, so its memory is bounded by its size, not by the
number of instances. Hits and misses are counted (:class:`CacheCounts`); a
scene reports them per frame.

Quantising ``s`` trades accuracy for reuse: :func:`quantise_s` rounds ``s`` to
steps of about ``quantum_deg`` degrees of viewing azimuth between the pair's two
references; :func:`bracket_s` gives the two steps around ``s`` and the weight
between them, so that a mode can blend two cached images and change smoothly
with the view (no jump when ``s`` crosses a step).
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Callable, Hashable
from dataclasses import dataclass

import numpy as np

from ... import tol
from ...validate import as_int, as_positive

__all__ = ["CacheCounts", "MorphCache", "morph_key", "quantise_s", "bracket_s"]


@dataclass(frozen=True)
class CacheCounts:
    """Counts of a :class:`MorphCache` since it was made (or between two snapshots).

    Parameters
    ----------
    hits, misses, evictions : int, optional
        The counts.

    Attributes
    ----------
    hits, misses, evictions : int
    """

    hits: int = 0
    misses: int = 0
    evictions: int = 0

    def __sub__(self, other: CacheCounts) -> CacheCounts:
        return CacheCounts(self.hits - other.hits, self.misses - other.misses,
                           self.evictions - other.evictions)

    @property
    def hit_rate(self) -> float:
        """``hits / (hits + misses)``; 1.0 when nothing was asked."""
        n = self.hits + self.misses
        return 1.0 if n == 0 else self.hits / n


class MorphCache:
    """A least-recently-used image cache bounded in entries and bytes.

    Parameters
    ----------
    capacity : int
        Most entries held (>= 1).
    max_bytes : int, optional
        Most bytes of images held (``ndarray.nbytes`` summed); None: no byte bound.
        An image larger than ``max_bytes`` is returned but not kept.
    """

    def __init__(self, capacity: int = 2048, max_bytes: int | None = 256 * 2**20) -> None:
        capacity = as_int(capacity, "cache capacity", lo=1)
        if max_bytes is not None:
            max_bytes = int(as_positive(max_bytes, "cache max_bytes"))
        self.capacity = int(capacity)
        self.max_bytes = max_bytes
        self._store: OrderedDict[Hashable, np.ndarray] = OrderedDict()
        self._bytes = 0
        self._hits = self._misses = self._evictions = 0

    def __len__(self) -> int:
        return len(self._store)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._store

    @property
    def nbytes(self) -> int:
        """Bytes of the images held."""
        return self._bytes

    @property
    def counts(self) -> CacheCounts:
        """Hits, misses and evictions so far (subtract two snapshots for one frame's)."""
        return CacheCounts(self._hits, self._misses, self._evictions)

    def keys(self) -> list[Hashable]:
        """The keys held, least recently used first.

        Returns
        -------
        list of Hashable
            The keys, least recently used first.
        """
        return list(self._store)

    def clear(self) -> None:
        """Drop every entry (counts are kept)."""
        self._store.clear()
        self._bytes = 0

    def get(self, key: Hashable, make: Callable[[], np.ndarray]) -> np.ndarray:
        """The image under ``key``; on a miss ``make()`` computes it and it is stored.

        The returned array is shared with the cache: read it, do not write it
        (it is marked read-only).

        Parameters
        ----------
        key : Hashable
            Cache key (see :func:`morph_key`).
        make : callable
            ``make() -> ndarray``, called on a miss.

        Returns
        -------
        numpy.ndarray
            The cached image, read-only.
        """
        img = self._store.get(key)
        if img is not None:
            self._store.move_to_end(key)
            self._hits += 1
            return img
        self._misses += 1
        img = make()
        if self.max_bytes is not None and img.nbytes > self.max_bytes:
            return img
        img.setflags(write=False)
        self._store[key] = img
        self._bytes += img.nbytes
        while len(self._store) > self.capacity or (self.max_bytes is not None
                                                   and self._bytes > self.max_bytes):
            _, old = self._store.popitem(last=False)
            self._bytes -= old.nbytes
            self._evictions += 1
        return img


def quantise_s(s: float, span_deg: float, quantum_deg: float) -> float:
    """``s`` rounded to the nearest of ``n = max(1, round(span_deg / quantum_deg))`` equal steps.

    Parameters
    ----------
    s : float
        Fraction in ``[0, 1]`` between two references.
    span_deg : float
        Azimuth between the two references, degrees.
    quantum_deg : float
        Wanted step of viewing azimuth, degrees; ``0`` keeps ``s`` as is.

    Returns
    -------
    float
        ``round(s n) / n`` (exactly 0 and 1 at the ends).
    """
    if quantum_deg <= 0:
        return float(s)
    n = max(1, int(round(abs(span_deg) / quantum_deg)))
    return math.floor(s * n + 0.5) / n


def bracket_s(s: float, span_deg: float, quantum_deg: float) -> tuple[float, float, float]:
    """The steps ``s_lo <= s <= s_hi`` of :func:`quantise_s`'s grid around ``s`` and the weight of ``s_hi``.

    Parameters
    ----------
    s, span_deg, quantum_deg
        As in :func:`quantise_s` (``quantum_deg > 0``).

    Returns
    -------
    s_lo, s_hi : float
        Neighbouring steps ``k / n`` and ``(k + 1) / n`` (``s_hi = s_lo`` when ``s``
        lies on a step, up to :data:`morphkit.tol.REL_EQUAL` of a step).
    w : float
        ``(s - s_lo) / (s_hi - s_lo)`` in ``[0, 1)`` (0 on a step).
    """
    n = max(1, int(round(abs(span_deg) / quantum_deg)))
    x = min(max(float(s), 0.0), 1.0) * n
    k = math.floor(x + tol.REL_EQUAL)
    w = x - k
    if w <= tol.REL_EQUAL or k >= n:
        return min(k, n) / n, min(k, n) / n, 0.0
    return k / n, (k + 1) / n, w


def morph_key(asset: str, i: int, j: int, s_q: float, level: int) -> tuple[str, int, int, float, int]:
    """The cache key of an image: ``(asset name, i, j, quantised s, level)``.

    Parameters
    ----------
    asset : str
        Asset name.
    i, j : int
        Reference view indices.
    s_q : float
        Quantised morph fraction.
    level : int
        Pyramid level.

    Returns
    -------
    tuple
        ``(asset, i, j, s_q, level)``.
    """
    return (asset, int(i), int(j), float(s_q), int(level))
