"""Numerical tolerances, in one place (as trimesh does).

Every threshold morphkit uses to decide that something is degenerate, equal or
valid lives here, with the reason for its value. Tests import these rather than
repeating numbers.
"""

from __future__ import annotations

#: Smallest |signed area| (pixels^2) of a warp triangle that still counts as a
#: triangle. A 1e-6 px^2 triangle maps its whole source onto a point.
TRIANGLE_AREA_PX2 = 1e-6

#: Relative tolerance used when asking "is this matrix orthonormal / this
#: vector unit length" on poses given by users (float32 poses round to ~1e-7).
POSE_ORTHO = 1e-5

#: Smallest extent (scene units) of a light, camera frustum or bounding box.
MIN_EXTENT = 1e-9

#: Depth-buffer values pyrender reports as "no surface" (it writes 0.0).
PYRENDER_BACKGROUND = 0.0

#: Minimum relative distance (fraction of object size) of a camera from an
#: object's bounding box before the camera is considered inside the object.
CAMERA_CLEARANCE = 1e-3

#: Ray origins for ray-cast shadows are pushed this far (scene units) towards the
#: light, so a point lying on the occluder's surface does not hit itself. Embree
#: intersects in float32: ~1e-7 relative, i.e. 1e-7 units on a unit-size
#: object; 1e-4 is 1000x that and 1/10000 of the object size (sample meshes
#: are normalised to size 1), far below a shadow-map texel.
RAY_OFFSET = 1e-4

#: Outward margin (pixels) by which a warp's destination mesh boundary is pushed
#: when deciding which output pixel centres it covers, so that centres lying on
#: the boundary (the last row/column of an identity warp over the whole image)
#: are covered, as a closed mesh should. Rounding in user coordinates is ~1e-12 px,
#: far below it; samples at such centres move by < 1e-6 px (invisible).
MESH_BOUNDARY_PX = 1e-6
