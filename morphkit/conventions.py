"""Coordinate conventions of morphkit, stated once. Every module points here.

Pixels and images
-----------------
* An image is a numpy array of shape ``(H, W)`` or ``(H, W, C)``; rows first.
* A pixel position is ``(x, y)``: ``x`` grows to the right (column), ``y`` grows
  downwards (row). **The origin is the centre of the top-left pixel**: the pixel
  ``img[r, c]`` is centred at ``(x, y) = (c, r)`` and the image covers
  ``[-0.5, W - 0.5] x [-0.5, H - 0.5]``. This is the convention of
  ``cv2.remap``, ``cv2.warpAffine`` and ``cv2.warpPerspective``.
* Point arrays are ``(N, 2)`` in ``(x, y)`` order (``(N, 3)`` for 3-D points).
* **Colour images are RGB**, ``(H, W, 3)``, or RGBA, ``(H, W, 4)`` (straight alpha
  unless a function says premultiplied), channel last; everything morphkit takes, returns,
  writes (:func:`morphkit.files.fileio.write_image`) and reads
  (:func:`morphkit.files.fileio.read_image`) is in this order. OpenCV's BGR / BGRA
  order appears only at the calls that hand pixels to or take them from OpenCV's
  file and video I/O and colour maps, which swap at that call.
* OpenCV's SIFT keypoints are not quite in this convention: SIFT detects on
  the image doubled (its first octave) and maps keypoints back by halving,
  where ``(x + 0.5) / 2 - 0.5`` would be right, so ``KeyPoint.pt`` lies
  :data:`SIFT_KEYPOINT_OFFSET_PX` right of and below the feature (as measured on
  Gaussian blobs); :mod:`morphkit.viewmorph.matching` subtracts it.
* Output sizes in morphkit's API are array shapes ``(H, W)`` and are named
  ``shape``/``out_shape``. The ``(w, h)`` order appears only at cv2 calls.

Matrices and frames (pytransform3d style)
-----------------------------------------
* ``a2b`` is a 4x4 homogeneous transform that maps a point given in frame ``a``
  to frame ``b``: ``p_b = a2b @ p_a``. ``b2a = inv(a2b)``.
* ``H_dst_src`` is a 3x3 homography that maps pixel positions of image ``src``
  to pixel positions of image ``dst``; ``A_dst_src`` (2x3) is the affine case.
  Warping *with* ``H_dst_src`` fills ``dst`` by sampling ``src`` at
  ``H_dst_src^-1 (x, y, 1)``.
* World frame: right-handed, ``+z`` up; the ground plane is ``z = 0``.
  Mesh files whose up is ``+y`` (glTF by specification, most OBJ exporters) are
  turned ``+z`` up on load by ``+90`` degrees about ``x``; the one table of each
  format's default up axis is in :mod:`morphkit.meshes.loading`.

Camera frames
-------------
* **OpenCV camera frame** (``cam``/``cv``; morphkit's own): ``x`` right,
  ``y`` down, ``z`` forward (the viewing direction). Intrinsics ``K`` map
  ``(X/Z, Y/Z, 1)`` to pixel ``(x, y, 1)`` in the pixel-centre convention above.
  **Depth** means ``Z`` in this frame: distance along the viewing axis, in
  scene units, positive in front of the camera.
* **OpenGL camera frame** (``gl``; pyrender's): ``x`` right, ``y`` up, ``z``
  backward (the camera looks along ``-z``). A pyrender node pose is a
  ``cam_gl2world`` transform.
* The one conversion between them is :data:`CV_FROM_GL` (a 180 degree rotation
  about ``x``, its own inverse): ``cam_cv2world = cam_gl2world @ CV_FROM_GL``
  and ``world2cam_cv = CV_FROM_GL @ world2cam_gl``. Use :func:`gl_pose_from_cv`
  and :func:`cv_pose_from_gl`; do not flip axes anywhere else.

Depth images
------------
* Depth images are float32 ``(H, W)`` of linear depth (``Z`` above).
  Pixels where no surface was hit hold :data:`BACKGROUND_DEPTH` (``+inf``): a
  comparison ``receiver_depth > map_depth`` is then false, i.e. unshadowed.

Colour
------
* **Inputs.** Texture images and vertex/face colours are **sRGB-encoded** (as
  stored in image, PLY and glTF files). An item's ``color`` and a material's
  base-colour factor are **linear** multipliers (glTF's rule), RGB in ``[0, 1]``.
  An item without a colour whose mesh has no visuals is drawn in
  :data:`DEFAULT_COLOR` (:mod:`morphkit.meshes.look` has the rules for the rest).
* **Lit colour** (``Renderer.color_depth``, ``source_view``, the ``color`` pass):
  uint8 RGB, pyrender's lighting computed in linear light and encoded with
  gamma ``1/2.2``; textures and vertex colours are decoded from sRGB (the exact
  curve) before lighting, so a texel and a vertex colour of the same value look
  the same.
* **Albedo** (the ``albedo`` pass): uint8 RGB, unlit, of the base colour
  factor x texture x vertex colour taken in **linear** light as the lit pass
  takes it (texels and vertex colours decoded from sRGB), then **sRGB-encoded**
  (the exact curve), like any colour image: a texture comes out as its own
  texels, a vertex colour as itself, an item with ``color`` ``c`` (or a
  factor ``c``) as ``round(255 srgb(c))`` -- the same as ``c`` baked into a
  texel (e.g. a factor-only part of a merged atlas, :mod:`morphkit.meshes.parts`).
* **Normals** (the ``normal`` pass): float32 ``(H, W, 3)`` unit vectors in the
  **world frame**, of the side of the surface facing the camera (a two-sided
  card seen from behind gives its reversed normal), ``0`` where nothing is
  drawn. They pass through an 8-bit encoding ``127 n + 128`` (0 and +-1
  exact) and are renormalised: angular error at most :data:`NORMAL_ENCODING_DEG`.
* **Alpha** is coverage: the fraction of a pixel covered by surface (1 or 0 at
  one sample a pixel; area-averaged when supersampled). Cut-out texels
  (:data:`ALPHA_CUTOFF`) are holes in colour, depth and alpha alike. Colour
  with alpha is straight (not premultiplied).

Level of detail
---------------
* A billboard's **on-screen height** is the height, in pixels, of its quad
  (:func:`morphkit.billboard.frames.lod.screen_height_px`: ``2 fy h / Z`` for a quad of half
  height ``h`` at depth ``Z``); a plan's bands are octaves of it
  (:mod:`morphkit.plan.representations`).
* glTF's **screen coverage** (``MSFT_screencoverage``, the hint of ``MSFT_lod``) is taken as
  Babylon.js computes it, the one loader that says: the area of the node's bounding sphere's disc
  on screen over the screen's area, ``pi (r fy / d)^2 / (W H)``, the sphere of radius ``r`` about
  the centre of the node's bounding box (half its diagonal) at distance ``d``. A level is drawn
  while the coverage is at least its value; below the last value nothing is drawn. Heights and
  coverages convert with ``d = Z`` (:func:`morphkit.export.lod.screen_coverage`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["CV_FROM_GL", "BACKGROUND_DEPTH", "SIFT_KEYPOINT_OFFSET_PX", "DEFAULT_COLOR", "ALPHA_CUTOFF",
           "NORMAL_ENCODING_DEG", "SUN_DISC_RADIUS_DEG", "gl_pose_from_cv", "cv_pose_from_gl"]

#: 4x4 change of camera frame OpenGL -> OpenCV (equal to its inverse).
CV_FROM_GL: np.ndarray = np.diag([1.0, -1.0, -1.0, 1.0])
CV_FROM_GL.setflags(write=False)

#: Value of depth-image pixels where no surface was hit.
BACKGROUND_DEPTH: float = float("inf")

#: How far (pixels, in x and in y) ``cv2.SIFT`` puts a keypoint right of and
#: below its feature, in the pixels of the image it was given (see above).
SIFT_KEYPOINT_OFFSET_PX: float = 0.25

#: Linear RGB of a surface with no colour of its own: an item without ``color``
#: whose mesh has no visuals (morphkit's one default colour since the start).
DEFAULT_COLOR: tuple[float, float, float] = (0.7, 0.7, 0.7)

#: Base-colour alpha below which a cut-out texel is a hole (glTF's default
#: ``alphaCutoff``); also the cutoff of glTF ``BLEND`` materials and of OBJ
#: textures with alpha, which morphkit draws as cut-outs (no blending).
ALPHA_CUTOFF: float = 0.5

#: Largest angle (degrees) between a normal of the ``normal`` pass and the true
#: one, from its 8-bit encoding ``127 n + 128``: each component is off by at most
#: 0.5/127, an error vector of length at most sqrt(3) 0.5/127, i.e. 0.39 deg.
NORMAL_ENCODING_DEG: float = 0.4


def gl_pose_from_cv(cam_cv2world: np.ndarray) -> np.ndarray:
    """Return ``cam_gl2world`` (a pyrender node pose) from ``cam_cv2world``.

    Parameters
    ----------
    cam_cv2world : (4, 4) float
        Camera-to-world pose in the OpenCV camera frame (x right, y down, z forward).

    Returns
    -------
    (4, 4) float64
        ``cam_gl2world``, the same camera in the OpenGL frame (y up, looking down -z).
    """
    return np.asarray(cam_cv2world, dtype=np.float64) @ CV_FROM_GL


def cv_pose_from_gl(cam_gl2world: np.ndarray) -> np.ndarray:
    """Return ``cam_cv2world`` from a pyrender node pose ``cam_gl2world``.

    Parameters
    ----------
    cam_gl2world : (4, 4) float
        Camera-to-world pose in the OpenGL camera frame (a pyrender node pose).

    Returns
    -------
    (4, 4) float64
        ``cam_cv2world``, the same camera in the OpenCV frame.
    """
    return np.asarray(cam_gl2world, dtype=np.float64) @ CV_FROM_GL

#: The real sun's angular radius seen from the Earth, degrees (its disc is about 0.53 deg
#: across): the default disc of a soft sun (:func:`morphkit.sunlit.receivers.sun_disc`).
SUN_DISC_RADIUS_DEG = 0.267
