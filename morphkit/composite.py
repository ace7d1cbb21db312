"""Compositing shadows into a rendered frame.

A frame is rendered twice by :mod:`morphkit.render`: ``lit`` (ambient + the
light) and ``unlit`` (ambient only). A pixel that sees a fraction ``v`` of the
light is ``unlit + v (lit - unlit)``: ``v = 1`` is fully lit, ``v = 0`` is in
full shadow (only the ambient term is left), fractional ``v`` is a penumbra.
This is exact for one light and a shading model linear in the light's
intensity (pyrender's is). Visibility comes from a shadow map lookup or from
:mod:`morphkit.groundtruth`.
"""

from __future__ import annotations

import numpy as np

from .errors import ValidationError, expected_got
from .validate import as_image

__all__ = ["shade"]


def shade(lit: np.ndarray, unlit: np.ndarray, visibility: np.ndarray) -> np.ndarray:
    """Blend ``unlit`` and ``lit`` uint8 ``(H, W, 3)`` frames by ``visibility (H, W)`` in [0, 1]."""
    lit = as_image(lit, "lit", channels=(3,))
    unlit = as_image(unlit, "unlit", channels=(3,))
    vis = as_image(np.asarray(visibility, dtype=np.float32), "visibility", channels=(1,))
    if lit.shape != unlit.shape or vis.shape != lit.shape[:2]:
        raise ValidationError(expected_got("shade inputs", "lit, unlit (H, W, 3) and visibility (H, W)",
                                           f"{lit.shape}, {unlit.shape}, {vis.shape}"))
    if vis.min() < 0 or vis.max() > 1:
        raise ValidationError(expected_got("visibility", "values in [0, 1]",
                                           f"[{vis.min():g}, {vis.max():g}]"))
    lo, hi = unlit.astype(np.float32), lit.astype(np.float32)
    out = lo + vis[..., None] * (hi - lo)
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)
