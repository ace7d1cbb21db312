"""The value types of one billboard frame: what the plan decides and what a mode returns.

:class:`Placement` -- one billboard drawn in one frame (where, which pyramid
level, its viewing azimuth); :class:`FramePlan` -- every placement of a frame,
back to front, with the counts of what was skipped and why
(:meth:`~.field.BillboardScene.plan`); :class:`FrameStats` and :class:`Frame` --
a rendered frame (:mod:`~.modes`) and its counts and timing. Plain frozen
dataclasses: the planner, the compositor and the modes all import them from
here, and this module imports nothing of the billboard package.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Placement", "FramePlan", "FrameStats", "Frame"]


@dataclass(frozen=True, eq=False)
class Placement:
    """One billboard drawn in one frame.

    Parameters
    ----------
    index : int
        Instance index.
    asset : str
        Asset name.
    azimuth_deg, elevation_deg : float
        Viewing direction in the instance's object frame (see :mod:`~.facing`).
    above : bool
        The directly-above fallback was used.
    depth, distance : float
        Camera depth ``Z`` and distance of the pivot, scene units.
    height_px : float
        On-screen height of the quad, pixels (``inf`` at the near plane).
    level : int
        Pyramid level of the image to draw.
    H_screen_unit : (3, 3) float64
        The quad's unit square to screen pixels (:func:`~.frustum.quad_homographies`).
    roi : (r0, r1, c0, c1)
        Screen box of the (clipped) quad, inside the image.
    clip_px : (K, 2) float64 or None
        The quad's screen polygon after near-plane clipping; None when the quad
        lies wholly in front of the near plane.
    fog : float
        Fog factor at the pivot's distance (0 without fog).
    """

    index: int
    asset: str
    azimuth_deg: float
    elevation_deg: float
    above: bool
    depth: float
    distance: float
    height_px: float
    level: int
    H_screen_unit: np.ndarray
    roi: tuple[int, int, int, int]
    clip_px: np.ndarray | None
    fog: float


@dataclass(frozen=True, eq=False)
class FramePlan:
    """What one camera sees of a scene.

    Parameters
    ----------
    placements : list of Placement
        Billboards to draw, back to front.
    visible : (M,) int64
        Instances whose bounding sphere meets the frustum (drawn or not).
    n_instances, n_frustum_culled, n_behind, n_offscreen, n_small, n_near_clipped, n_above : int
        Instances in the scene; culled by the frustum test; left with nothing in
        front of the near plane; whose clipped quad misses the image; under the
        pixel size or area; cut by the near plane (and drawn); in the frustum and
        seen from directly above (the facing fallback).
    """

    placements: list[Placement]
    visible: np.ndarray
    n_instances: int
    n_frustum_culled: int
    n_behind: int
    n_offscreen: int
    n_small: int
    n_near_clipped: int
    n_above: int


@dataclass(frozen=True)
class FrameStats:
    """Counts and timings of one rendered frame.

    Parameters
    ----------
    mode : str
        The mode's name.
    n_instances, n_drawn, n_frustum_culled, n_behind, n_offscreen, n_small, n_near_clipped, n_above : int
        See :class:`FramePlan` (``n_drawn = len(placements)``).
    hits, misses, evictions : int
        Cache counts during this frame (0 for modes without a cache).
    cache_entries, cache_bytes : int
        Cache size after the frame.
    max_outside_deg : float
        Largest azimuth beyond a partial ring's arc among the drawn billboards
        (0 inside; the image there is clamped to the nearer reference).
    ms : float
        Wall time of the frame, milliseconds.
    """

    mode: str
    n_instances: int
    n_drawn: int
    n_frustum_culled: int
    n_behind: int
    n_offscreen: int
    n_small: int
    n_near_clipped: int
    n_above: int
    hits: int = 0
    misses: int = 0
    evictions: int = 0
    cache_entries: int = 0
    cache_bytes: int = 0
    max_outside_deg: float = 0.0
    ms: float = 0.0

    @property
    def hit_rate(self) -> float:
        """``hits / (hits + misses)`` (1.0 when the frame asked the cache nothing)."""
        n = self.hits + self.misses
        return 1.0 if n == 0 else self.hits / n


@dataclass(frozen=True, eq=False)
class Frame:
    """One rendered frame.

    Parameters
    ----------
    rgb : (H, W, 3) uint8
        The final image (billboards over the backdrop), RGB.
    layer : (H, W, 4) float32
        The billboards (or meshes) alone: premultiplied RGB in ``[0, 1]`` and coverage alpha.
    placements : list of Placement
        The billboards drawn, back to front (their screen boxes for per-billboard errors).
    stats : FrameStats
    """

    rgb: np.ndarray
    layer: np.ndarray
    placements: list[Placement]
    stats: FrameStats
