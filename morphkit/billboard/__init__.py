"""View-dependent billboards (paper 2): assets with reference views on a ring, view-morphed
by viewing direction.

Asset side (this package's :mod:`.ring`, :mod:`.cameras`, :mod:`.asset`, :mod:`.assetfile`):

* :class:`ViewRing` -- where the reference views are (K = 2: the paper's +-30 degree
  pair; K >= 3: a full ring) and which pair and fraction serve a viewing azimuth;
* :class:`QuadCameras` -- the camera rule and the billboard quad every image maps onto;
* :class:`BillboardAsset` / :func:`bake_asset` -- references, the front view (classic
  billboard), the pair morphs and their pyramid; one versioned file per asset.

Typical use::

    from morphkit.billboard import bake_asset
    from morphkit.meshes import sample_mesh
    from morphkit.render import Renderer

    with Renderer() as r:
        asset = bake_asset(sample_mesh("tree"), r, name="tree", views=8)
    i, j, s, _ = asset.ring.pair(100.0)
    image = asset.morph(i, j, s)     # premultiplied RGBA on the quad facing azimuth 100
"""

from __future__ import annotations

from .asset import BAKE_AMBIENT, BillboardAsset, bake_asset, bake_items, bake_lights, mesh_hash
from .assetfile import FORMAT, VERSION
from .cameras import QuadCameras
from .ring import ViewRing, wrap_deg

__all__ = ["ViewRing", "QuadCameras", "BillboardAsset", "bake_asset", "mesh_hash", "bake_items",
           "bake_lights", "BAKE_AMBIENT", "FORMAT", "VERSION", "wrap_deg"]
