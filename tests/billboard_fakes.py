"""Test doubles of a billboard asset (no GL): a ring of views and ellipse images.

:class:`FakeRing` follows the :class:`morphkit.billboard.protocols.ViewPairing` contract
(two views on an arc, clamped outside it; or K views over 360 degrees).
:class:`FakeAsset` draws its "view" of azimuth ``a`` as an anti-aliased ellipse
whose colour and width depend on ``a``: references are the views at the ring's
azimuths, ``morph(i, j, s)`` is the view at the interpolated azimuth (a
deterministic function of ``s``), ``crossfade`` the premultiplied blend of the
two references. It counts its calls, so cache tests can see what was computed.
"""

from __future__ import annotations

import cv2
import numpy as np


class FakeRing:
    """K views: two at +-arc/2 about azimuth 0, or K over the full circle from azimuth 0."""

    def __init__(self, views: int = 2, arc_deg: float = 60.0) -> None:
        self.views = int(views)
        self.arc_deg = float(arc_deg) if views == 2 else 360.0

    def azimuths_deg(self) -> np.ndarray:
        if self.views == 2:
            return np.array([-self.arc_deg / 2, self.arc_deg / 2])
        return np.arange(self.views) * (360.0 / self.views)

    def pair(self, azimuth_deg: float) -> tuple[int, int, float, float]:
        if self.views == 2:
            a = (float(azimuth_deg) + 180.0) % 360.0 - 180.0
            lo, hi = -self.arc_deg / 2, self.arc_deg / 2
            if lo <= a <= hi:
                return 0, 1, (a - lo) / self.arc_deg, 0.0
            d_lo = (lo - a) % 360.0
            d_hi = (a - hi) % 360.0
            return (0, 1, 0.0, d_lo) if d_lo <= d_hi else (0, 1, 1.0, d_hi)
        step = 360.0 / self.views
        a = float(azimuth_deg) % 360.0
        i = int(a // step) % self.views
        s = (a - i * step) / step
        return i, (i + 1) % self.views, min(max(s, 0.0), 1.0), 0.0


def ellipse_view(azimuth_deg: float, shape: tuple[int, int]) -> np.ndarray:
    """The fake asset's view from ``azimuth_deg``: premultiplied RGBA float32 ``shape + (4,)``."""
    h, w = shape
    a = np.radians(azimuth_deg)
    color = np.array([0.5 + 0.5 * np.cos(a), 0.5 + 0.5 * np.sin(a), 0.3], np.float32)
    ax = max(1, int(round((0.25 + 0.2 * abs(np.cos(a))) * w)))
    ay = max(1, int(round(0.45 * h)))
    mask = np.zeros((h, w), np.uint8)
    cv2.ellipse(mask, ((w - 1) // 2, (h - 1) // 2), (ax, ay), 0, 0, 360, 255, -1, cv2.LINE_AA)
    alpha = mask.astype(np.float32) / 255.0
    return np.ascontiguousarray(np.dstack([color[None, None] * alpha[..., None], alpha]))


class FakeAsset:
    """A :class:`morphkit.billboard.protocols.BillboardSource` double; see the module notes."""

    def __init__(self, name: str = "fake", views: int = 2, arc_deg: float = 60.0,
                 size: tuple[int, int] = (64, 48), levels: int = 3,
                 half_extent: tuple[float, float] = (0.3, 0.4), solid: bool = False) -> None:
        self.name = name
        self.ring = FakeRing(views, arc_deg)
        self.size = size
        self.levels = levels
        self.half_extent = half_extent
        self.pivot = np.array([0.0, 0.0, half_extent[1]])
        self.solid = solid
        self.calls = {"morph": 0, "crossfade": 0, "reference": 0}
        self.memory_bytes = views * size[0] * size[1] * 4 * 4

    def shape(self, level: int) -> tuple[int, int]:
        return self.size[0] >> level, self.size[1] >> level

    def view(self, azimuth_deg: float, level: int) -> np.ndarray:
        if self.solid:  # an opaque image: its coverage is exactly the quad
            img = np.ones(self.shape(level) + (4,), np.float32)
            img[..., :3] = (0.2, 0.4, 0.8)
            return img
        return ellipse_view(azimuth_deg, self.shape(level))

    def reference(self, k: int, level: int = 0) -> np.ndarray:
        self.calls["reference"] += 1
        return self.view(self.ring.azimuths_deg()[k], level)

    def classic(self, level: int = 0) -> np.ndarray:
        return self.view(0.0, level)

    def _az(self, i: int, j: int, s: float) -> float:
        az = self.ring.azimuths_deg()
        span = (az[j] - az[i]) % 360.0 or 360.0
        return float(az[i] + s * span)

    def morph(self, i: int, j: int, s: float, level: int = 0, *, coverage: bool = True) -> np.ndarray:
        self.calls["morph"] += 1
        return self.view(self._az(i, j, s), level)

    def crossfade(self, i: int, j: int, s: float, level: int = 0) -> np.ndarray:
        self.calls["crossfade"] += 1
        az = self.ring.azimuths_deg()
        return ((1 - s) * self.view(az[i], level) + s * self.view(az[j], level)).astype(np.float32)
