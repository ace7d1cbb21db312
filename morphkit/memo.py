"""One small cache: a bounded mapping from a key to a value made on first use.

Every place in morphkit that remembers a computed value (meshes made once per
parameter set, contexts per image shape, ground truth per pose, baked assets per
bench configuration) uses :class:`Memo`, so eviction, counting and clearing are
written once. Keys must be hashable; values are returned as stored (callers that
hand out arrays they must not share copy or freeze them themselves).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterator
from typing import Generic, TypeVar

from .validate import as_int

__all__ = ["Memo"]

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")


class Memo(Generic[K, V]):
    """A least-recently-used cache of at most ``maxsize`` values (None: unbounded).

    Parameters
    ----------
    maxsize : int or None
        Most values kept; the least recently used is dropped first.
    on_evict : callable, optional
        Called with each value dropped by :meth:`get` (not by :meth:`clear`), e.g.
        to release a GL context.

    Examples
    --------
    >>> squares = Memo(maxsize=2)
    >>> squares.get(3, lambda: 9)
    9
    >>> squares.get(3, lambda: -1)   # made once: the second maker is not called
    9
    >>> _ = squares.get(4, lambda: 16); _ = squares.get(5, lambda: 25)
    >>> 3 in squares, len(squares), (squares.hits, squares.misses)
    (False, 2, (1, 3))
    """

    def __init__(self, maxsize: int | None = None, *, on_evict: Callable[[V], object] | None = None):
        self.maxsize = None if maxsize is None else as_int(maxsize, "maxsize", lo=1)
        self.on_evict = on_evict
        self.hits = 0
        self.misses = 0
        self._items: OrderedDict[K, V] = OrderedDict()

    def get(self, key: K, make: Callable[[], V]) -> V:
        """The value stored for ``key``, made by ``make()`` and stored on a miss.

        Parameters
        ----------
        key : hashable
            The key.
        make : callable
            Makes the value; called only on a miss.

        Returns
        -------
        object
            The stored (or newly made) value.
        """
        if key in self._items:
            self._items.move_to_end(key)
            self.hits += 1
            return self._items[key]
        self.misses += 1
        value = make()
        self._items[key] = value
        if self.maxsize is not None:
            while len(self._items) > self.maxsize:
                _, old = self._items.popitem(last=False)
                if self.on_evict is not None:
                    self.on_evict(old)
        return value

    def __contains__(self, key: object) -> bool:
        return key in self._items

    def __len__(self) -> int:
        return len(self._items)

    def values(self) -> Iterator[V]:
        """The stored values, least recently used first.

        Returns
        -------
        iterator
            The values.
        """
        return iter(list(self._items.values()))

    def clear(self) -> None:
        """Forget every value and reset the counts (``on_evict`` is not called)."""
        self._items.clear()
        self.hits = self.misses = 0
