"""The interface every hard-shadow method implements: :class:`ShadowMethod`.

A shadow method turns an object position on the motion plane (and, for a point
light, a light offset) into a light-view depth map and the light camera it
belongs to. The warped atlas methods (:class:`~morphkit.shadow.warped.ComposedWarp`,
:class:`~morphkit.shadow.warped.ThreeWarps`,
:class:`~morphkit.shadow.reprojection.method.ReprojectedMaps`, built by
:mod:`morphkit.shadow.methods`, and the atlas itself with its default), re-rendering
(:class:`~morphkit.shadow.baselines.DirectShadow`)
and the image-based baseline (:class:`~morphkit.shadow.baselines.ImageBasedShadow`)
all implement it, so :class:`~morphkit.shadow.soft.SoftShadow`,
:func:`~morphkit.shadow.frame.compare_frames` and the benchmarks take any of them.

Frames and units follow :mod:`morphkit.conventions`; the light rig's model of
motion is stated in :mod:`morphkit.shadow.rig`.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..camera import CameraModel
from .baked import BakedAtlas
from .rig import LightRig
from .runtime import AtlasRuntime

__all__ = ["ShadowMethod", "AtlasMethodBase", "bilinear_weights"]


@runtime_checkable
class ShadowMethod(Protocol):
    """A source of light depth maps for an object moving over a plane.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol describes objects, it is not instantiated.

    Attributes
    ----------
    name : str
        Short label (bench rows, frame names), e.g. ``"warp"``, ``"direct"``.
    rig : LightRig
        The light camera and range of motion the maps are made for.
    memory_bytes : int
        Bytes of precomputed data the method keeps (0 for re-rendering).
    """

    name: str

    @property
    def rig(self) -> LightRig:
        """The light camera and range of motion the maps are made for."""
        ...

    @property
    def memory_bytes(self) -> int:
        """Bytes of precomputed data the method keeps (0 for re-rendering)."""
        ...

    def shadow_map(self, xy: Any, *, light_offset: Any = None, clamp: bool = False
                   ) -> tuple[np.ndarray, CameraModel]:
        """The light depth map with the object at ``xy`` (world ``(x, y)`` on the motion plane).

        Parameters
        ----------
        xy : array_like, shape (2,)
            Object translation on the motion plane, world units.
        light_offset : array_like, shape (2,), optional
            A point light moved by this much in its plane (equivalent to the object
            moved the other way: :meth:`~morphkit.shadow.rig.LightRig.resolve`).
        clamp : bool
            Outside the baked range: clamp to it with a
            :class:`~morphkit.shadow.rig.RangeClampWarning` instead of raising
            :class:`~morphkit.errors.OutOfRangeError`.

        Returns
        -------
        depth : ndarray, float32, shape (H, W)
            Linear light depth, ``+inf`` where the object is absent.
        camera : CameraModel
            The light camera the map belongs to.
        """
        ...


class AtlasMethodBase:
    """What the shadow methods of an atlas share: its run time, baked data, rig and persisted bytes.

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The atlas's run-time caches and counts (its baked data: ``runtime.baked``).
    """

    name = "warp"

    def __init__(self, runtime: AtlasRuntime) -> None:
        self.runtime = runtime

    @property
    def baked(self) -> BakedAtlas:
        """The atlas's baked data (read, never changed)."""
        return self.runtime.baked

    @property
    def rig(self) -> LightRig:
        """The atlas's light rig."""
        return self.runtime.baked.rig

    @property
    def memory_bytes(self) -> int:
        """The atlas's persisted bytes (:attr:`~morphkit.shadow.baked.BakedAtlas.memory_bytes`)."""
        return self.runtime.baked.memory_bytes


def bilinear_weights(j: int, i: int, v: float, u: float) -> list[tuple[tuple[int, int], float]]:
    """The 4 samples of a grid cell with their bilinear weights.

    Parameters
    ----------
    j, i : int
        Row and column index of the cell's lower sample.
    v, u : float
        Fractions in ``[0, 1]`` along the rows (``y``) and columns (``x``).

    Returns
    -------
    list of ((j, i), weight)
        Lower-left, lower-right, upper-left, upper-right; weights sum to 1.

    Examples
    --------
    A quarter of the way up and halfway across cell ``(0, 1)``:

    >>> from morphkit.shadow import bilinear_weights
    >>> bilinear_weights(0, 1, 0.25, 0.5)
    [((0, 1), 0.375), ((0, 2), 0.375), ((1, 1), 0.125), ((1, 2), 0.125)]
    """
    return [((j, i), (1 - u) * (1 - v)), ((j, i + 1), u * (1 - v)),
            ((j + 1, i), (1 - u) * v), ((j + 1, i + 1), u * v)]
