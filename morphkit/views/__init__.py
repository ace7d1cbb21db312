"""Views of one object over directions, with depth: the core both papers share.

* :mod:`.framing` -- the distance and margin every baked view of an object is taken with;
* :mod:`.dome`, :mod:`.domecameras` -- :class:`~.dome.ViewDome` (directions over the upper
  hemisphere) and :class:`~.domecameras.DomeCameras` (the camera and quad of each direction);
* :mod:`.gbuffer` -- :class:`~.gbuffer.ViewSurface`: albedo, normals and depth of one view;
* :mod:`.depthmorph` -- the per-pixel morph of three views with their depth.

The billboards (:mod:`morphkit.billboard`) and the field's shadows (:mod:`morphkit.shadow`) both
build on these; this package imports neither. The dome, its cameras and the view surface are
re-exported here: ``from morphkit.views import DomeCameras``.
"""

from __future__ import annotations

from .dome import ViewDome
from .domecameras import DomeCameras, direction
from .gbuffer import ViewSurface

__all__ = ["ViewDome", "DomeCameras", "direction", "ViewSurface"]
