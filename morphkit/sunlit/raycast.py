"""The truth of a relit frame's shadows: rays towards the sun against every posed real mesh.

:class:`RayCastShadow` is a :class:`~.receivers.SceneShadow` like the atlas's
(:class:`~.receivers.AtlasShadow`), so a frame drawn with one compares with the other receiver
for receiver and, under a soft sun, disc direction for disc direction (:func:`~.receivers.sun_disc`;
the receivers' rules are :mod:`.receivers`'). The rays are :func:`~.fieldbaselines.ray_cast_field`'s
(Embree when installed).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import trimesh

from .. import tol
from ..billboard.frames.instances import Instances
from ..conventions import SUN_DISC_RADIUS_DEG
from ..errors import ValidationError, expected_got
from .fieldbaselines import posed_asset_meshes, ray_cast_field
from .fieldshadow import field_sun
from .receivers import FrameShadow, sun_disc

__all__ = ["RayCastShadow"]


class RayCastShadow:
    """The truth: rays towards the sun (each disc direction) against all posed real meshes.

    Parameters
    ----------
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh (normalised by :func:`~.fieldbaselines.ray_cast_field`, as the
        atlases and the dome assets are).
    samples : int
        Directions over the sun's disc.
    disc_deg : float
        The disc's angular radius, degrees.
    name : str
        Its name.
    """

    def __init__(self, meshes: Mapping[str, trimesh.Trimesh], *, samples: int = 1,
                 disc_deg: float = SUN_DISC_RADIUS_DEG, name: str = "raycast") -> None:
        if not isinstance(meshes, Mapping) or not meshes:
            raise ValidationError(expected_got("meshes", "a non-empty mapping name -> trimesh.Trimesh",
                                               type(meshes).__name__))
        sun_disc(np.array([0.0, 0.0, 1.0]), samples, disc_deg)
        self.meshes = dict(meshes)
        self.samples = int(samples)
        self.disc_deg = float(disc_deg)
        self.name = str(name)
        self._posed: tuple[Instances, list[trimesh.Trimesh]] | None = None

    def _bodies(self, instances: Instances) -> list[trimesh.Trimesh]:
        """The posed meshes, one per asset, each keeping its look (its cut-outs cast nothing)."""
        if self._posed is None or self._posed[0] is not instances:
            self._posed = (instances, posed_asset_meshes(self.meshes, instances))
        return self._posed[1]

    def frame(self, instances: Instances, suns: Sequence[np.ndarray], ground: np.ndarray,
              visible: np.ndarray) -> FrameShadow:
        """See :class:`SceneShadow` (``ground`` and ``visible`` are not needed: rays see all).

        Parameters
        ----------
        instances : Instances
            The casters.
        suns : sequence of (3,) float
            Towards each sun.
        ground : (M, 3) float
            Not used.
        visible : (K,) int
            Not used.

        Returns
        -------
        FrameShadow
            One row per sun.
        """
        body = self._bodies(instances)
        per_sun: list[tuple[list, float]] = []
        for d in suns:
            if not body or field_sun(d) is None:
                per_sun.append(([], 0.0))
                continue
            disc = sun_disc(d, self.samples, self.disc_deg)
            fns = [_RayCast(self.meshes, instances, s, body) for s in disc]
            per_sun.append((fns, tol.SUN_RAY_NORMAL_OFFSET))
        return FrameShadow(per_sun)


class _RayCast:
    """``points -> visibility`` of one sun direction by :func:`ray_cast_field`."""

    def __init__(self, meshes: Mapping[str, trimesh.Trimesh], instances: Instances, d: np.ndarray,
                 body: list[trimesh.Trimesh]) -> None:
        self.meshes, self.instances, self.d, self.body = meshes, instances, d, body

    def __call__(self, points: np.ndarray) -> np.ndarray:
        return ray_cast_field(self.meshes, self.instances, self.d, points, posed=self.body)
