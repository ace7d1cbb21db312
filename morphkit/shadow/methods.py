"""The shadow methods of an atlas, by option: :func:`build_method` and its cache :class:`AtlasMethods`.

An atlas's run-time algorithms are shadow methods of their own
(:class:`~morphkit.shadow.method.ShadowMethod`):
:class:`~morphkit.shadow.warped.ComposedWarp` (default),
:class:`~morphkit.shadow.warped.ThreeWarps` and
:class:`~morphkit.shadow.reprojection.method.ReprojectedMaps`. This module maps the
options of :meth:`ShadowAtlas.method <morphkit.shadow.atlas.ShadowAtlas.method>`
(``warps``, ``dst``, ``blend``, ``layers``) to one of them, built over the
atlas's :class:`~morphkit.shadow.runtime.AtlasRuntime`, and keeps each built
object per option set (it holds run-time buffers).
"""

from __future__ import annotations

from typing import Any, Literal

from ..errors import ValidationError, expected_got
from ..memo import Memo
from ..validate import as_flag
from .method import ShadowMethod
from .reprojection.method import ReprojectedMaps
from .runtime import AtlasRuntime
from .warped import ComposedWarp, ThreeWarps

__all__ = ["WARPS", "AtlasMethods", "build_method"]

#: The values of ``warps``: the mesh warps composed, the paper's three warps, per-pixel reprojection.
WARPS = ("composed", "three", "reproject")

Warps = Literal["composed", "three", "reproject"]
Dst = Literal["project", "interpolate"]
Blend = Literal["bilinear", "nearest"]


def _check_options(warps: Any, dst: Any, blend: Any, layers: Any) -> tuple[str, str, str, bool]:
    """The options, checked one by one (values, then the flag)."""
    if warps not in WARPS or dst not in ("project", "interpolate") or blend not in ("bilinear", "nearest"):
        raise ValidationError(expected_got(
            "warps/dst/blend", "'composed'|'three'|'reproject', 'project'|'interpolate' and "
            "'bilinear'|'nearest'", f"{warps!r}/{dst!r}/{blend!r}"))
    return warps, dst, blend, as_flag(layers, "layers")


def build_method(runtime: AtlasRuntime, *, warps: Warps = "composed", dst: Dst = "project",
                 blend: Blend = "bilinear", layers: bool = True) -> ShadowMethod:
    """A new shadow method object over ``runtime`` for these options (uncached; see :class:`AtlasMethods`).

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The atlas's run time (and, in it, its baked data).
    warps : {"composed", "three", "reproject"}
        The algorithm.
    dst : {"project", "interpolate"}
        How destination control points are made.
    blend : {"bilinear", "nearest"}
        Blend of the cell's samples.
    layers : bool
        Reproject hidden layers (``warps="reproject"`` only).

    Returns
    -------
    morphkit.shadow.method.ShadowMethod
        The method object.

    Raises
    ------
    ValidationError
        Unknown option values or combinations that have no algorithm
        (``blend="nearest"`` with ``warps="three"``, ``dst="interpolate"`` with
        ``warps="reproject"``), or ``dst="interpolate"``/``warps="three"`` on
        an atlas of ``"sample"`` anchors.
    """
    warps, dst, blend, layers = _check_options(warps, dst, blend, layers)
    interpolate, nearest = dst == "interpolate", blend == "nearest"
    if warps == "reproject":
        if interpolate:
            raise ValidationError(expected_got("dst", "'project' with warps='reproject' (it moves "
                                               "pixels, not control points)", repr(dst)))
        return ReprojectedMaps(runtime, nearest=nearest, layers=layers)
    if warps == "three":
        if nearest:
            raise ValidationError(expected_got("warps", "'composed' with blend='nearest' (one map "
                                               "is warped once)", "'three'"))
        return ThreeWarps(runtime, interpolate=interpolate)
    return ComposedWarp(runtime, interpolate=interpolate, nearest=nearest)


class AtlasMethods:
    """The shadow methods of one atlas, each built once per option set and kept.

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The atlas's run time, shared by every method built here.
    """

    def __init__(self, runtime: AtlasRuntime) -> None:
        self.runtime = runtime
        self._built: Memo[tuple[str, str, str, bool], ShadowMethod] = Memo()

    def get(self, *, warps: Warps = "composed", dst: Dst = "project", blend: Blend = "bilinear",
            layers: bool = True) -> ShadowMethod:
        """The method for these options (:func:`build_method`), built on first use and kept.

        Parameters
        ----------
        warps, dst, blend, layers
            As in :func:`build_method` (checked on every call).

        Returns
        -------
        morphkit.shadow.method.ShadowMethod
            The method object (the same object for the same options).
        """
        key = _check_options(warps, dst, blend, layers)
        return self._built.get(key, lambda: build_method(
            self.runtime, warps=key[0], dst=key[1], blend=key[2], layers=key[3]))
