"""An asset's views tiled into one image (an engine's texture atlas).

View ``k`` of ``V`` square views of ``n`` pixels sits in cell ``(k mod C, k div C)`` of a grid of
``C = ceil(sqrt(V))`` columns and ``ceil(V / C)`` rows; each cell is the view with ``pad`` pixels
on every side, filled by repeating the view's edge pixels (OpenCV's ``BORDER_REPLICATE``), so a
texture's mip level ``l`` of the atlas averages no pixel of a neighbouring view while
``2^l <= pad`` (:data:`TILE_PAD`: 8 pixels, three levels). Cells left over at the end of the last
row are zero. The view's own pixels are copied unchanged: :func:`untile_views` gives them back bit
for bit.

Convention: rows top to bottom, columns left to right (image order, :mod:`morphkit.conventions`);
``origin(k)`` is the ``(x, y)`` pixel of view ``k``'s first pixel in the atlas.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from ..errors import FileFormatError, ValidationError, expected_got
from ..validate import as_int

__all__ = ["TILE_PAD", "TileLayout", "tile_views", "untile_views"]

#: Pixels of each view's own edge repeated around it in an atlas (module notes).
TILE_PAD = 8


@dataclass(frozen=True)
class TileLayout:
    """Where each view sits in an atlas (module notes).

    Parameters
    ----------
    views : int
        How many views (>= 1).
    side : int
        Each view's side, pixels (>= 1).
    pad : int, optional
        Pixels of padding around each view (>= 0).

    Examples
    --------
    >>> from morphkit.export.tiles import TileLayout
    >>> t = TileLayout(27, 128)
    >>> t.columns, t.rows, t.shape, t.origin(7)
    (6, 5, (720, 864), (152, 152))
    """

    views: int
    side: int
    pad: int = TILE_PAD

    def __post_init__(self) -> None:
        object.__setattr__(self, "views", as_int(self.views, "views", lo=1))
        object.__setattr__(self, "side", as_int(self.side, "side", lo=1))
        object.__setattr__(self, "pad", as_int(self.pad, "pad", lo=0))

    @property
    def columns(self) -> int:
        """Cells a row."""
        return math.ceil(math.sqrt(self.views))

    @property
    def rows(self) -> int:
        """Rows of cells."""
        return math.ceil(self.views / self.columns)

    @property
    def cell(self) -> int:
        """A cell's side: the view and its padding."""
        return self.side + 2 * self.pad

    @property
    def shape(self) -> tuple[int, int]:
        """The atlas's ``(height, width)``, pixels."""
        return self.rows * self.cell, self.columns * self.cell

    def origin(self, k: int) -> tuple[int, int]:
        """The ``(x, y)`` pixel of view ``k``'s first pixel.

        Parameters
        ----------
        k : int
            The view, ``0 <= k < views``.

        Returns
        -------
        (int, int)
        """
        k = as_int(k, "view", lo=0, hi=self.views - 1)
        return (k % self.columns) * self.cell + self.pad, (k // self.columns) * self.cell + self.pad

    def to_json(self) -> dict[str, Any]:
        """The layout as a file holds it: ``views``, ``side``, ``pad``, ``columns``, ``rows``.

        Returns
        -------
        dict
        """
        return {"views": self.views, "side": self.side, "pad": self.pad, "columns": self.columns,
                "rows": self.rows}

    @classmethod
    def from_json(cls, obj: Any) -> TileLayout:
        """The layout :meth:`to_json` wrote.

        Parameters
        ----------
        obj : dict
            ``views``, ``side``, ``pad`` (``columns`` and ``rows``, if given, must follow from them).

        Returns
        -------
        TileLayout

        Raises
        ------
        FileFormatError
            Another object, missing or bad values.
        """
        try:
            out = cls(obj["views"], obj["side"], obj["pad"])
        except (KeyError, TypeError, ValidationError) as exc:
            raise FileFormatError(
                expected_got("tile layout", "views, side and pad (ints)", repr(obj)[:120])
            ) from exc
        for key in ("columns", "rows"):
            if key in obj and obj[key] != getattr(out, key):
                raise FileFormatError(expected_got(f"tile layout {key}", getattr(out, key), repr(obj[key])))
        return out


def tile_views(views: np.ndarray) -> tuple[np.ndarray, TileLayout]:
    """``(V, n, n[, C])`` views tiled into one atlas (module notes).

    Parameters
    ----------
    views : (V, n, n) or (V, n, n, C) array
        Square views of any dtype OpenCV pads (uint8, uint16, ...).

    Returns
    -------
    atlas : (H, W[, C]) array
        Of the views' dtype.
    layout : TileLayout

    Raises
    ------
    ValidationError
        Views that are not square images.
    """
    v = np.asarray(views)
    if v.ndim not in (3, 4) or v.shape[1] != v.shape[2] or v.shape[0] < 1:
        raise ValidationError(expected_got("views", "(V, n, n) or (V, n, n, C) square views", v.shape))
    layout = TileLayout(v.shape[0], v.shape[1])
    atlas = np.zeros((*layout.shape, *v.shape[3:]), v.dtype)
    p, c = layout.pad, layout.cell
    for k in range(layout.views):
        x, y = layout.origin(k)
        img = v[k]
        if img.ndim == 3 and img.shape[2] > 4:
            raise ValidationError(expected_got("views", "at most 4 channels", img.shape[2]))
        padded = cv2.copyMakeBorder(img, p, p, p, p, cv2.BORDER_REPLICATE)
        atlas[y - p : y - p + c, x - p : x - p + c] = padded.reshape(c, c, *v.shape[3:])
    return atlas, layout


def untile_views(atlas: np.ndarray, layout: TileLayout) -> np.ndarray:
    """The views of an atlas :func:`tile_views` made, as they were.

    Parameters
    ----------
    atlas : (H, W[, C]) array
        The atlas.
    layout : TileLayout
        Its layout.

    Returns
    -------
    (V, n, n[, C]) array

    Raises
    ------
    FileFormatError
        An atlas of another shape than the layout's.
    """
    a = np.asarray(atlas)
    if a.shape[:2] != layout.shape:
        raise FileFormatError(expected_got("atlas", f"{layout.shape} pixels for its layout", a.shape[:2]))
    n = layout.side
    out = []
    for k in range(layout.views):
        x, y = layout.origin(k)
        out.append(a[y : y + n, x : x + n])
    return np.ascontiguousarray(np.stack(out))
