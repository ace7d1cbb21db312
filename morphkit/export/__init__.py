"""Out of Python: morphkit's bakes as glTF files engines read.

* :mod:`.tiles` -- an asset's views tiled into one image, each view padded by its own edge pixels
  so that the texture's mip levels do not bleed one view into the next;
* :mod:`.glb` -- the binary glTF container: a mesh (by trimesh), images and a sidecar in
  ``extras.morphkit``, written and read back;
* :mod:`.assetglb` -- a relightable dome asset (its views' albedo, normals and depth) with its mesh
  and its sun atlas as one GLB, and read back bit for bit.

The command is ``morphkit export`` (:mod:`morphkit.programs.export`).
"""

from .assetglb import DomeGlb, read_dome_glb, write_dome_glb

__all__ = ["DomeGlb", "read_dome_glb", "write_dome_glb"]
