"""View-dependent billboards (paper 2's system): assets, scenes of many billboards, modes.

One concept per module:

* :mod:`~morphkit.billboard.instances` -- N instances (asset, position, yaw, scale);
* :mod:`~morphkit.billboard.paths` -- camera paths: the paper's pan, an orbit, a fly-through;
* :mod:`~morphkit.billboard.facing` -- axial (the paper's) or screen-aligned quads, viewing azimuths;
* :mod:`~morphkit.billboard.frustum` -- frustum culling, near-plane clipping, quad homographies;
* :mod:`~morphkit.billboard.lod` -- pyramid level from the on-screen size;
* :mod:`~morphkit.billboard.cache` -- the bounded LRU morph cache with hit/miss counts;
* :mod:`~morphkit.billboard.backdrop` -- ground, sky and distance fog;
* :mod:`~morphkit.billboard.scene` -- the scene and its per-frame plan;
* :mod:`~morphkit.billboard.compositor` -- back-to-front premultiplied "over" of warped quads;
* :mod:`~morphkit.billboard.modes` -- morph, classic, nearest, crossfade, and the real meshes.

An asset is anything implementing :class:`morphkit.protocols.BillboardSource`.
Nothing here imports pyrender; the mesh mode renders through a
:class:`morphkit.protocols.SceneRenderer`.
"""

from __future__ import annotations

from .backdrop import Backdrop, Fog, Ground, Sky
from .cache import CacheCounts, MorphCache, morph_key, quantise_s
from .facing import AxialFacing, Facing, ScreenFacing, ViewDirections, paper_angle, view_directions
from .instances import Instance, Instances, place_random
from .modes import (
    BillboardMode,
    ClassicMode,
    CrossfadeMode,
    FrameMode,
    MeshMode,
    MorphMode,
    NearestMode,
)
from .paths import PATHS, CameraPath, FlyPath, OrbitPath, PanPath, make_path
from .scene import BillboardScene, Frame, FramePlan, FrameStats, Placement

__all__ = [
    "Backdrop", "Fog", "Ground", "Sky",
    "CacheCounts", "MorphCache", "morph_key", "quantise_s",
    "Facing", "AxialFacing", "ScreenFacing", "ViewDirections", "view_directions", "paper_angle",
    "Instance", "Instances", "place_random",
    "FrameMode", "BillboardMode", "MorphMode", "ClassicMode", "NearestMode", "CrossfadeMode", "MeshMode",
    "CameraPath", "PanPath", "OrbitPath", "FlyPath", "PATHS", "make_path",
    "BillboardScene", "Frame", "FramePlan", "FrameStats", "Placement",
]
