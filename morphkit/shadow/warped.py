"""The piecewise-affine mesh warps of a shadow atlas (Kang & Ihm 2002), as shadow methods.

* :class:`ComposedWarp` (the default, ``"warp"``): each of the cell's 4 maps is
  warped once, straight to the destination control points, and the warps are
  blended with bilinear weights in one fused pass
  (:func:`morphkit.warp.accumulate_warps`); with ``nearest=True`` only the sample
  with the largest weight is warped (``"warp_nearest"``).
* :class:`ThreeWarps` (``"warp_three"``): the paper's scheme, two row morphs at
  the horizontal fraction, then a column morph at the vertical one.

Destination control points are the anchors projected at the exact position
(default) or, with ``interpolate=True`` (the paper), bilinearly interpolated
from the 4 maps' control points; both ``interpolate=True`` and
:class:`ThreeWarps` need control points in one-to-one correspondence across
maps (atlas anchors ``"shared"`` or ``"plane"``).

Maps are warped as coverage-depth planes (:mod:`morphkit.shadow.planes`), so
bilinear sampling never mixes object depth with the background. A warp that
would fold falls back to the plane anchors (counted in
:attr:`AtlasRuntime.fallbacks <morphkit.shadow.runtime.AtlasRuntime>`). The
conventions of the warp (backward, pixel centres) are those of
:mod:`morphkit.warp`.

The three warps: Kang & Ihm [1]_; piecewise-affine (piecewise linear) mapping: Goshtasby [2]_.

References
----------
.. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
   (digest: ``docs/papers.md``).
.. [2] A. Goshtasby, "Piecewise linear mapping functions for image registration", Pattern Recognition,
   19(6), pp. 459-466, 1986.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import FoldOverError, ValidationError, expected_got
from ..validate import as_flag
from ..warp import accumulate_warps, roi_union
from .baked import BakedAtlas
from .method import AtlasMethodBase, bilinear_weights
from .planes import add_planes, planes_to_depth, warp_planes
from .runtime import AtlasRuntime

__all__ = ["ComposedWarp", "ThreeWarps"]


def _check_correspondence(baked: BakedAtlas, what: str) -> None:
    if baked.anchor_kind == "sample":
        raise ValidationError(expected_got(
            "atlas anchors", f"'shared' or 'plane' anchors for {what} (they need control points in "
            "correspondence across maps)", "'sample' anchors"))


class ComposedWarp(AtlasMethodBase):
    """Warp the cell's maps once each to the destination and blend them (a :class:`ShadowMethod`).

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The atlas's run time (and, in it, its baked data).
    interpolate : bool
        Destination control points interpolated bilinearly from the 4 maps (the
        paper) instead of projected exactly; needs ``"shared"`` or ``"plane"`` anchors.
    nearest : bool
        Warp only the sample map with the largest weight (ties: the lower index):
        a quarter of the work, less accurate, and the shadow may change abruptly
        where the nearest sample changes.

    Notes
    -----
    Keeps one accumulation buffer: one object serves one thread at a time.
    """

    def __init__(self, runtime: AtlasRuntime, *, interpolate: bool = False, nearest: bool = False) -> None:
        super().__init__(runtime)
        self.interpolate = as_flag(interpolate, "interpolate")
        self.nearest = as_flag(nearest, "nearest")
        if self.interpolate:
            _check_correspondence(runtime.baked, "dst='interpolate'")
        self.name = "warp_nearest" if self.nearest else "warp"
        self._acc: np.ndarray | None = None

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
        rt, a = self.runtime, self.runtime.baked
        eq, _pos, cam = a.rig.resolve(xy, light_offset, clamp=clamp)
        nb = bilinear_weights(*a.cell(eq))
        # the destination control points interpolated from all 4 maps (the paper)
        interp = sum(w * a.control[jj, ii] for (jj, ii), w in nb) if self.interpolate else None
        if self.nearest:
            nb = [(max(nb, key=lambda n: n[1])[0], 1.0)]  # max() keeps the first of ties
        acc = self._acc  # kept between calls, all zeros
        if acc is None:
            acc = self._acc = np.zeros((2, *a.shape), np.float32)
        jobs = []
        box = (0, 0, 0, 0)
        for (jj, ii), w in nb:
            if w <= 0.0:
                continue
            c_dst = interp if interp is not None else rt.dst_points(jj, ii, eq)
            if float(np.abs(c_dst - a.control[jj, ii]).max()) <= tol.PX_EQUAL:
                # identity: exact sample position, or a directional light
                box = (0, a.shape[0], 0, a.shape[1])
                add_planes(acc, (box, rt.source_planes(jj, ii)), w)
            else:
                jobs.append(rt.warp_job(jj, ii, c_dst, eq, w))
        try:
            box = roi_union(box, accumulate_warps(jobs, acc))
            # clear=True: the buffer is all zeros again for the next call
            return planes_to_depth(acc, rt.anchor_depth(eq), box, clear=True), cam
        except BaseException:
            acc.fill(0.0)
            raise


class ThreeWarps(AtlasMethodBase):
    """Kang & Ihm's three warps: row morphs at the fraction ``u``, then a column morph at ``v``.

    Parameters
    ----------
    runtime : morphkit.shadow.runtime.AtlasRuntime
        The run time of an atlas baked with ``"shared"`` or ``"plane"`` anchors.
    interpolate : bool
        Destination control points interpolated from the 4 maps (the paper)
        instead of projected exactly.

    Notes
    -----
    If a warp folds, the whole computation is redone with plane anchors
    (documented fallback, counted in ``runtime.fallbacks``).
    """

    name = "warp_three"

    def __init__(self, runtime: AtlasRuntime, *, interpolate: bool = False) -> None:
        super().__init__(runtime)
        self.interpolate = as_flag(interpolate, "interpolate")
        _check_correspondence(runtime.baked, "dst='interpolate' or warps='three'")

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
        j, i, v, u = a.cell(eq)
        try:
            return self._warps(a.control, a.anchors, eq, j, i, u, v), cam
        except FoldOverError:
            self.runtime.count_fallback()
            return self._warps(a.plane_control, a.plane_anchors, eq, j, i, u, v), cam

    def _warps(self, C: np.ndarray, anchors: np.ndarray, eq: np.ndarray, j: int, i: int,
               u: float, v: float) -> np.ndarray:
        rt, a = self.runtime, self.runtime.baked
        c_dst = (rt.project(eq, anchors[j, i]) if not self.interpolate else
                 (1 - v) * ((1 - u) * C[j, i] + u * C[j, i + 1])
                 + v * ((1 - u) * C[j + 1, i] + u * C[j + 1, i + 1]))
        full = (0, a.shape[0], 0, a.shape[1])
        rows = []
        for jj in (j, j + 1):
            c_row = (1 - u) * C[jj, i] + u * C[jj, i + 1]
            row = np.zeros((2, *a.shape), np.float32)
            for ii, w in ((i, 1 - u), (i + 1, u)):
                if w > 0:
                    src = rt.source_planes(jj, ii)
                    warped = src if np.allclose(c_row, C[jj, ii], rtol=0, atol=tol.PX_EQUAL) else warp_planes(
                        src, C[jj, ii], c_row, a.triangles, a.shape)
                    add_planes(row, (full, warped), w)
            rows.append((c_row, row))  # premultiplied: a row morph is again a source
        acc = np.zeros((2, *a.shape), np.float32)
        for (c_row, row), w in zip(rows, (1 - v, v), strict=True):
            if w > 0:
                warped = row if np.allclose(c_row, c_dst, rtol=0, atol=tol.PX_EQUAL) else warp_planes(
                    row, c_row, c_dst, a.triangles, a.shape)
                add_planes(acc, (full, warped), w)
        return planes_to_depth(acc, rt.anchor_depth(eq))
