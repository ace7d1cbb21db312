"""Per-pixel 3-D reprojection of a shadow atlas's maps, as a shadow method.

:class:`ReprojectedMaps` moves every pixel of the cell's maps in 3-D instead of
warping a mesh (exact for every surface point a map saw; no control points)
and keeps the nearest depth (the kernels and their conventions:
:mod:`morphkit.shadow.reprojection`). The largest-weight map is reprojected
whole and, with ``layers=True``, of the others only their *hidden layers*
(what the first does not hold: built once per pair of neighbouring samples by
:meth:`AtlasRuntime.hidden_layer <morphkit.shadow.runtime.AtlasRuntime.hidden_layer>`,
on first use or by :meth:`~morphkit.shadow.runtime.AtlasRuntime.prepare`);
``layers=False`` reprojects every map whole. ``morphkit bench shadows``
compares the two (rows ``reproject`` and ``reproject_full``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ... import settings
from ...camera import CameraModel
from ...validate import as_flag
from ..method import AtlasMethodBase, bilinear_weights
from ..runtime import AtlasRuntime
from . import PARALLEL_MIN_SOURCE_PIXELS, reproject_maps

__all__ = ["ReprojectedMaps"]


class ReprojectedMaps(AtlasMethodBase):
    """The cell's maps reprojected per pixel into one z-buffer (a :class:`ShadowMethod`).

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The atlas's run time (and, in it, its baked data).
    nearest : bool
        Reproject only the sample map with the largest weight (holes where it saw nothing).
    layers : bool
        Of the maps after the first, reproject only their hidden layers (default)
        instead of the whole maps.

    Notes
    -----
    The z-buffer is split into bands of rows over :data:`morphkit.settings.WARP_THREADS`
    threads (read per call); the result does not depend on the thread count
    (:func:`~morphkit.shadow.reprojection.reproject_maps`).
    """

    def __init__(self, runtime: AtlasRuntime, *, nearest: bool = False, layers: bool = True) -> None:
        super().__init__(runtime)
        self.nearest = as_flag(nearest, "nearest")
        self.layers = as_flag(layers, "layers")
        self.name = "reproject" + ("_nearest" if self.nearest else "") + ("" if self.layers else "_full")

    def shadow_map(self, xy: Any, *, light_offset: Any = None, clamp: bool = False
                   ) -> tuple[np.ndarray, CameraModel]:
        """See :meth:`ShadowMethod.shadow_map <morphkit.shadow.method.ShadowMethod.shadow_map>`.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane.
        clamp : bool
            Clamp ``xy`` into the motion range instead of refusing it.

        Returns
        -------
        depth : (H, W) float32
            Light-view linear depth, ``+inf`` background.
        camera : morphkit.camera.CameraModel
            The light camera of ``depth``.
        """
        a = self.runtime.baked
        eq, _pos, cam = a.rig.resolve(xy, light_offset, clamp=clamp)
        nb = bilinear_weights(*a.cell(eq))
        if self.nearest:
            nb = [(max(nb, key=lambda n: n[1])[0], 1.0)]  # max() keeps the first of ties
        # the largest weight first: the others then mostly fill what it left
        order = sorted((n for n in nb if n[1] > 0.0), key=lambda n: -n[1])
        return self._reprojected(eq, [n for n, _w in order]), cam

    def _reprojected(self, eq: np.ndarray, sources: list[tuple[int, int]]) -> np.ndarray:
        rt, a = self.runtime, self.runtime.baked
        c_dst = a.rig.principal_point(eq)
        jobs = []
        pixels = 0
        for k, (jj, ii) in enumerate(sources):
            src = rt.reprojection_source(jj, ii)[0]
            if k > 0 and self.layers:
                src = rt.hidden_layer(sources[0], (jj, ii))
            rp = rt.moved(jj, ii, c_dst, eq - np.array([a.xs[ii], a.ys[jj]]))
            pixels += int(src.cum[-1])
            jobs.append((src, rp))
        out = np.full(a.shape, np.inf, np.float32)
        threads = settings.WARP_THREADS if pixels >= PARALLEL_MIN_SOURCE_PIXELS else 1
        reproject_maps(jobs, out, threads=threads)
        return out
