"""View-dependent billboards (paper 2's system): assets with reference views on a ring,
view-morphed by viewing direction, and scenes of many of them.

One concept per module.

Asset side:

* :mod:`.protocols` -- :class:`ViewPairing`, :class:`BillboardSource`: what a scene asks of an asset;
* :mod:`.ring` -- :class:`ViewRing`: where the reference views are (K = 2: the paper's
  +-30 degree pair; K >= 3: a full ring) and which pair and fraction serve a viewing azimuth;
* :mod:`.cameras` -- :class:`QuadCameras`: the camera rule and the billboard quad every image
  maps onto;
* :mod:`.asset`, :mod:`.formats.assetfile` -- :class:`BillboardAsset`: references, the front view
  (classic billboard), the pair morphs and their pyramid; one versioned file;
* :mod:`.baking.ringviews` -- :func:`bake_asset`: a mesh's reference views rendered and every
  pair prepared; :mod:`.baking.bakelook` -- the look and light a bake draws, and its hash;
* :mod:`.coverage` -- :func:`splat_coverage`: where the object is in an in-between view, from
  the references' depth (the morph's alpha).

Relightable assets seen from any height, built on the views with depth of :mod:`morphkit.views`
(the dome of directions, its cameras, the surfaces and their per-pixel morph):

* :mod:`.domeasset`, :mod:`.formats.domefile` -- :class:`~.domeasset.DomeAsset`,
  :func:`~.domeasset.bake_dome` and the versioned file; :mod:`.analytic` -- an exact sphere asset (no GL);
* :mod:`.impostor` -- the engines' hemi-octahedral impostor, the anchor baseline.

Relit billboards under the sun, with the field's shadows, are :mod:`morphkit.sunlit` (above this
package and :mod:`morphkit.shadow`).

Scene side:

* :mod:`.frames.instances` -- N instances (asset, position, yaw, scale);
* :mod:`.frames.paths` -- camera paths: the paper's pan, an orbit, a fly-through;
* :mod:`.frames.facing` -- axial (the paper's) or screen-aligned quads, viewing azimuths;
* :mod:`.frames.frustum` -- frustum culling, near-plane clipping, quad homographies;
* :mod:`.frames.lod` -- pyramid level from the on-screen size;
* :mod:`.frames.cache` -- the bounded LRU morph cache with hit/miss counts;
* :mod:`.frames.backdrop` -- ground, sky and distance fog;
* :mod:`.frames.field` -- the billboard scene (:class:`BillboardScene`) and its per-frame plan;
* :mod:`.frames.frametypes` -- the value types of a frame: placements, plan, stats, frame;
* :mod:`.frames.planner` -- the stages of a frame's plan: cull, face, level of detail, clip, order;
* :mod:`.frames.compositor` -- back-to-front premultiplied "over" of warped quads;
* :mod:`.modes` -- morph, classic, nearest, crossfade, and the real meshes;
* :mod:`.compare` -- errors against the meshes and Fig. 5 strips.

A path written to files (frames, a video) and assets from names or files are programs:
:mod:`morphkit.programs.sequence`, :mod:`morphkit.programs.sources`.

An asset is anything implementing :class:`morphkit.billboard.protocols.BillboardSource`.
Nothing here imports pyrender; bakes and the mesh mode render through a
:class:`morphkit.protocols.SceneRenderer`.

Typical use::

    import numpy as np
    from morphkit.billboard import BillboardScene, MorphMode, PanPath, bake_asset, place_random
    from morphkit.meshes import sample_mesh
    from morphkit.render import Renderer

    with Renderer() as r:
        tree = bake_asset(sample_mesh("tree"), r, name="tree", views=8)
    scene = BillboardScene({"tree": tree}, place_random(["tree"], 500, np.random.default_rng(0)))
    mode = MorphMode()
    for cam in PanPath.over(17.0).cameras(48):
        frame = scene.render(cam, mode)      # frame.rgb, frame.stats.hits / misses

Papers: the billboard technique of Kim, Song & Gwon [1]_, built on Seitz & Dyer's view
morphing [2]_.

References
----------
.. [1] S. Kim, J. Song and O. Gwon, "A Billboarding Technique dependent on View Direction using View
   Morphing", KIISE conference paper (digest: ``docs/papers.md``).
.. [2] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.
"""

from __future__ import annotations

from .asset import BAKE_AMBIENT, BillboardAsset, bake_items, bake_lights, look_hash, mesh_hash
from .baking.ringviews import bake_asset
from .cameras import QuadCameras
from .coverage import object_points, splat_coverage
from .domeasset import DomeAsset, bake_dome
from .formats.assetfile import APPEARANCES, FORMAT, VERSION
from .frames.backdrop import Backdrop, Fog, Ground, Sky
from .frames.cache import CacheCounts, MorphCache, bracket_s, morph_key, quantise_s
from .frames.facing import (
    AxialFacing,
    Facing,
    ScreenFacing,
    ViewDirections,
    ViewpointFacing,
    paper_angle,
    view_directions,
)
from .frames.field import BillboardScene, FrameMode
from .frames.frametypes import Frame, FramePlan, FrameStats, Placement
from .frames.instances import Instance, Instances, place_random
from .frames.paths import PATHS, CameraPath, FlyPath, OrbitPath, PanPath, make_path
from .modes import (
    BillboardMode,
    ClassicMode,
    CrossfadeMode,
    MeshMode,
    MorphMode,
    NearestMode,
)
from .protocols import BillboardSource, ViewPairing
from .ring import ViewRing, wrap_deg

__all__ = [
    # interfaces
    "ViewPairing", "BillboardSource",
    # asset side
    "ViewRing", "QuadCameras", "BillboardAsset", "bake_asset", "mesh_hash", "look_hash", "bake_items",
    "bake_lights", "BAKE_AMBIENT", "APPEARANCES", "FORMAT", "VERSION", "wrap_deg", "splat_coverage",
    "object_points", "DomeAsset", "bake_dome",
    # scene side
    "Backdrop", "Fog", "Ground", "Sky",
    "CacheCounts", "MorphCache", "morph_key", "quantise_s", "bracket_s",
    "Facing", "AxialFacing", "ScreenFacing", "ViewpointFacing", "ViewDirections", "view_directions",
    "paper_angle",
    "Instance", "Instances", "place_random",
    "FrameMode", "BillboardMode", "MorphMode", "ClassicMode", "NearestMode", "CrossfadeMode", "MeshMode",
    "CameraPath", "PanPath", "OrbitPath", "FlyPath", "PATHS", "make_path",
    "BillboardScene", "Frame", "FramePlan", "FrameStats", "Placement",
]
