"""Out of Python: morphkit's bakes as glTF files engines read.

* :mod:`.tiles` -- an asset's views tiled into one image, each view padded by its own edge pixels
  so that the texture's mip levels do not bleed one view into the next;
* :mod:`.glb` -- the binary glTF container: a mesh (by trimesh), images and a sidecar in
  ``extras.morphkit``, written and read back;
* :mod:`.assetglb` -- a relightable dome asset (its views' albedo, normals and depth) with its mesh
  and its sun atlas as one GLB, and read back bit for bit;
* :mod:`.lod` -- levels of detail for engines: a chain of levels, the crossed card engines draw in
  place of the billboards, and glTF's screen coverage;
* :mod:`.preview` -- what a preview page shows (its camera, sun and data); :mod:`.page` -- the page
  itself, one HTML file with three.js inlined; :mod:`.previewref` -- the same view drawn by morphkit
  (and of the real mesh), which the page is held to; :mod:`.browser` -- a page drawn in headless
  Chromium.

The commands are ``morphkit export`` (:mod:`morphkit.programs.export`) and ``morphkit preview``
(:mod:`morphkit.programs.preview`).
"""

from .assetglb import DomeGlb, read_dome_glb, write_dome_glb
from .preview import PreviewView, asset_entry, preview_data, write_preview

__all__ = ["DomeGlb", "read_dome_glb", "write_dome_glb", "PreviewView", "asset_entry", "preview_data",
           "write_preview"]
