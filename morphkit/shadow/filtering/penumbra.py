"""Smooth penumbrae from few light samples: each sample's map answers for its cell of the light.

:class:`~morphkit.shadow.soft.SoftShadow` averages ``N`` hard shadows (Kang &
Ihm's accumulation with ``alpha = 1/N``, Heckbert & Herf's), so a point's
visibility is a multiple of ``1/N`` and the penumbra shows ``N + 1`` flat bands.
The methods here take the *same* ``N`` maps, from any
:class:`~morphkit.shadow.method.ShadowMethod` (warped, reprojected or
re-rendered), and replace each hard lookup by a filtered one
(:mod:`morphkit.shadow.filtering.filtered`): the fraction of the sample's *cell* of the
light (the ``1/N`` of the light around it) that the point sees, estimated from
that one map with a box kernel as wide as the shadow moves while the light sweeps
the cell. The average of the ``N`` cell fractions is then a continuous function
of the receiver point, and the bands are gone.

The family differs in the occluder depth that sizes the kernel:

* :class:`PcfSoftShadow` -- percentage-closer filtering with a kernel as wide as
  the shift between neighbouring light samples on the receiver, for one occluder
  depth per map (the mean depth of its occluder texels). Cheapest; it blurs
  contact shadows, whose occluder is nearer the receiver than the mean.
* :class:`PcssSoftShadow` -- percentage-closer *soft* shadows (Fernando 2005):
  each point first averages the depths of the occluder texels in front of it
  within reach of the cell (or, next to the point, the depth of a blocker nearer
  it: contact hardening), then filters with the kernel that depth gives, so the
  penumbra narrows to nothing where the object touches the receiver.

Measured (``morphkit bench soft``, ``docs/RESULTS.md``): PCSS has the lower
error, and on the atlas's *reprojected* maps (``atlas.method(warps="reproject")``,
as accurate as re-rendering and faster than the mesh warp) it is the default soft
shadow of ``morphkit shadows --area-light`` and the demo: :func:`default_soft_shadow`.

Cells. With a grid of samples (``k`` or ``(n_u, n_v)``, jittered or not) the cell
of a sample is its grid cell, half-extents ``u / n_u`` and ``v / n_v``; with an
explicit array of ``N`` samples it is ``u / sqrt(N)`` by ``v / sqrt(N)`` (the
light's area shared equally).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from ...errors import ValidationError, expected_got
from ...scene import AreaLight
from ...validate import as_finite_array
from ..atlas import ShadowAtlas
from ..lookup import ShadowBias
from ..method import ShadowMethod
from ..soft import SoftShadow, light_offsets
from .depthtables import DepthTables
from .filtered import BlockerDepth, cell_half_widths, filter_into, point_chunks

__all__ = ["PenumbraSoftShadow", "PcfSoftShadow", "PcssSoftShadow", "light_cell",
           "SOFT_SHADOW_METHODS", "soft_shadow_class", "default_soft_shadow"]


def light_cell(light: AreaLight, samples: Any = (3, 3)) -> np.ndarray:
    """Half-extent vectors ``(2, 3)`` of the part of the light each sample stands for
    (module docstring).

    Parameters
    ----------
    light : morphkit.scene.AreaLight
        The area light.
    samples : int, (n_u, n_v) or (N, 2) array
        As for :func:`~morphkit.shadow.soft.light_offsets`.

    Returns
    -------
    (2, 3) float64
        ``e_u, e_v``, world frame.
    """
    n = len(light_offsets(light, samples))  # validates light and samples
    arr = np.asarray(samples, dtype=np.float64)
    if arr.ndim == 2:
        n_u = n_v = float(np.sqrt(n))
    elif arr.ndim == 0:
        n_u = n_v = float(arr)
    else:
        n_u, n_v = float(arr[0]), float(arr[1])
    return np.stack([light.u / n_u, light.v / n_v])


class PenumbraSoftShadow(SoftShadow):
    """Area-light visibility from ``N`` maps with a filtered lookup per map (module docstring).

    Same parameters, conditions and maps as :class:`~morphkit.shadow.soft.SoftShadow`;
    only the per-sample lookup differs. Subclasses set :attr:`blocker`.

    Parameters
    ----------
    method : ShadowMethod
        Any shadow method made for a point light at the area light's centre.
    light : AreaLight
        The area light (parallel to the motion plane).
    samples
        ``k``, ``(n_u, n_v)`` or an ``(N, 2)`` array of light coordinates.
    rng : numpy.random.Generator, optional
        Jitter the grid samples (drawn once).
    bias : ShadowBias, optional
        Depth-comparison bias of every lookup.
    """

    #: Where the kernel's occluder depth comes from (:data:`~.filtered.BlockerDepth`).
    blocker: ClassVar[BlockerDepth] = "search"

    def __init__(self, method: ShadowMethod, light: AreaLight, samples: Any = (3, 3), *,
                 rng: np.random.Generator | None = None, bias: ShadowBias | None = None) -> None:
        super().__init__(method, light, samples, rng=rng, bias=bias)
        self.cell = light_cell(light, samples)

    def visibility(self, xy: Any, points: Any, normals: np.ndarray | None = None, *,
                   clamp: bool = False) -> np.ndarray:
        """Fraction ``(P,)`` float32 of the light each world point sees, with the
        object at ``xy``: the mean of the ``N`` cell fractions, continuous in the point.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        points : (P, 3) float
            Points, world frame.
        normals : (P, 3) float, optional
            Unit normals for the slope bias.
        clamp : bool
            Clamp into the range instead of raising.

        Returns
        -------
        (P,) float32
            Fraction of the light seen.
        """
        pts = as_finite_array(points, "points", shape=(None, 3))
        if normals is not None:
            normals = as_finite_array(normals, "normals", shape=(len(pts), 3), dtype=np.float32)
        bias = ShadowBias() if self.bias is None else self.bias
        mode = {"mean": 0, "search": 1}[self.blocker]
        acc = np.zeros(len(pts), np.float32)
        lit = np.empty(len(pts), np.float32)
        pts = np.ascontiguousarray(pts, np.float64)
        chunks = point_chunks(pts)  # the same points for every map
        for depth, cam in self.maps(xy, clamp=clamp):  # a ShadowMethod's maps: checked there
            filter_into(lit, pts, depth, cam, cell_half_widths(self.cell, cam), mode, normals, bias,
                        DepthTables.of(depth), chunks)
            acc += lit
        acc /= np.float32(self.n_samples)
        return np.clip(acc, 0.0, 1.0)


class PcfSoftShadow(PenumbraSoftShadow):
    """Percentage-closer filtering sized by the light-sample spacing, one occluder
    depth per map (module docstring).

    Parameters
    ----------
    method : ShadowMethod
        Any shadow method made for a point light at the area light's centre.
    light : AreaLight
        The area light.
    samples
        ``k``, ``(n_u, n_v)`` or an ``(N, 2)`` array of light coordinates.
    rng : numpy.random.Generator, optional
        Jitter the grid samples.
    bias : ShadowBias, optional
        Depth-comparison bias.
    """

    blocker: ClassVar[BlockerDepth] = "mean"


class PcssSoftShadow(PenumbraSoftShadow):
    """Percentage-closer soft shadows: a blocker search per point and map sizes its
    kernel, so contact shadows stay sharp (module docstring).

    Parameters
    ----------
    method : ShadowMethod
        Any shadow method made for a point light at the area light's centre.
    light : AreaLight
        The area light.
    samples
        ``k``, ``(n_u, n_v)`` or an ``(N, 2)`` array of light coordinates.
    rng : numpy.random.Generator, optional
        Jitter the grid samples.
    bias : ShadowBias, optional
        Depth-comparison bias.
    """

    blocker: ClassVar[BlockerDepth] = "search"


#: The soft-shadow methods by name: ``"average"`` (plain averaging of hard
#: shadows, :class:`~morphkit.shadow.soft.SoftShadow`), ``"pcf"``, ``"pcss"``.
SOFT_SHADOW_METHODS: dict[str, type[SoftShadow]] = {
    "average": SoftShadow, "pcf": PcfSoftShadow, "pcss": PcssSoftShadow}


def soft_shadow_class(name: str) -> type[SoftShadow]:
    """The soft-shadow class called ``name`` (:data:`SOFT_SHADOW_METHODS`).

    Parameters
    ----------
    name : str
        ``"average"``, ``"pcf"`` or ``"pcss"``.

    Returns
    -------
    type
        The class.
    """
    if name not in SOFT_SHADOW_METHODS:
        raise ValidationError(expected_got("soft-shadow method", f"one of {sorted(SOFT_SHADOW_METHODS)}",
                                           repr(name)))
    return SOFT_SHADOW_METHODS[name]


def default_soft_shadow(atlas: ShadowAtlas, light: AreaLight, samples: Any = (3, 3), *,
                        rng: np.random.Generator | None = None,
                        bias: ShadowBias | None = None) -> PcssSoftShadow:
    """The soft shadow morphkit uses by default: PCSS on the atlas's reprojected maps.

    Parameters
    ----------
    atlas : morphkit.shadow.atlas.ShadowAtlas
        An atlas for a point light at the area light's centre, over the grown range
        (:func:`~morphkit.shadow.soft.bake_soft_atlas`).
    light : AreaLight
        The area light.
    samples
        ``k``, ``(n_u, n_v)`` or an ``(N, 2)`` array of light coordinates.
    rng : numpy.random.Generator, optional
        Jitter the grid samples.
    bias : ShadowBias, optional
        Depth-comparison bias.

    Returns
    -------
    PcssSoftShadow
        The soft shadow.
    """
    return PcssSoftShadow(atlas.method(warps="reproject"), light, samples, rng=rng, bias=bias)
