"""A whole frame: camera render, per-pixel light visibility, composite.

The camera view is rendered lit and unlit (:mod:`morphkit.render`): in one draw where the
renderer is a :class:`~morphkit.protocols.FrameRenderer` (:meth:`Renderer.frame_pass
<morphkit.render.Renderer.frame_pass>`: the lit pixels and, from the same fragments,
the unlit ones), else (or with ``one_pass=False``) in two draws, lit then unlit. Its depth is
unprojected to world points (:meth:`~morphkit.camera.CameraModel.unproject`) with normals
(:func:`~morphkit.shadow.lookup.normals_from_points`), in one compiled pass over the drawn
pixels (:func:`~morphkit.shadow.pixels.drawn_pixels`), and each visible point gets a light
visibility from a callable: a shadow-map lookup (:func:`~morphkit.shadow.lookup.shadow_visibility`)
or the ray-cast ground truth. :func:`~morphkit.imaging.composite.shade` blends lit and unlit by it.

The object is drawn in its mesh's own look (:mod:`morphkit.meshes.look`: texture,
vertex or face colours, cut-outs, an ``Item`` without a colour) where the mesh
has one, and in the scene object's colour (``SceneObject.color``) where it has
none (every sample mesh: their frames are those of earlier versions). Receivers
keep their colours. A cut-out object's holes are holes in the frame's colour and
depth, so the ground seen through them is shaded like any ground pixel.

``receiver_only=True`` is Kang & Ihm's mode (their hardware could only project
the shadow texture onto receivers): the object itself is never shadowed, so
self-shadowing is off. Default: every visible point is tested, object included.
The object's pixels are those the one-pass draw marks as the object's, or in two draws
those where an object-only depth image agrees with the frame's (a third draw).

The two ways give the same image within :data:`morphkit.tol.FRAME_ONCE_MEAN_LEVELS` (mean
absolute difference of ``shaded``, tested on the demo scenes): the one pass draws offscreen,
where depth rounds slightly differently from the two draws' buffer (module notes of
:mod:`morphkit.render`, "One-pass frame"), which can flip a shadow-edge pixel's visibility.

Warped shadow maps: Kang & Ihm [1]_; the projective depth test: Segal et al. [2]_.

References
----------
.. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
   (digest: ``docs/papers.md``).
.. [2] M. Segal, C. Korobkin, R. van Widenfelt, J. Foran and P. Haeberli, "Fast Shadows and Lighting
   Effects Using Texture Mapping", Computer Graphics (Proc. SIGGRAPH 92), 26(2), pp. 249-252, 1992.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..imaging.composite import shade
from ..imaging.cutout import cached_look
from ..imaging.groundtruth import hard_visibility
from ..protocols import FrameRenderer, SceneRenderer
from ..scene import Item, Scene, scene_items
from .lookup import shadow_visibility
from .method import ShadowMethod
from .pixels import drawn_pixels

__all__ = ["render_frame", "compare_frames", "frame_items", "VisibilityFn"]

#: A visibility function: world points (N, 3) and unit normals (N, 3) -> (N,) in [0, 1].
VisibilityFn = Callable[[np.ndarray, np.ndarray], np.ndarray]

SKY = (0.62, 0.71, 0.82)


def frame_items(scene: Scene) -> list[Item]:
    """The items a frame draws: the receivers in their colours, the object in its mesh's
    own look where it has one (an ``Item`` colour of ``None``), else in ``scene.obj.color``.

    Parameters
    ----------
    scene : morphkit.scene.Scene
        The scene.

    Returns
    -------
    list of Item
        Receivers first, then the object.
    """
    obj = scene.obj
    own = not cached_look(obj.mesh).plain
    return [*scene_items(scene, obj=False), Item(obj.mesh, obj.pose, None if own else obj.color)]


def render_frame(renderer: SceneRenderer, scene: Scene, visibility: VisibilityFn, *,
                 receiver_only: bool = False, background: tuple[float, float, float] = SKY,
                 one_pass: bool = True) -> dict[str, np.ndarray]:
    """Render ``scene`` from its camera and shadow it with ``visibility``.

    Returns the images ``lit``, ``unlit`` (uint8 RGB), ``depth`` (float32),
    ``visibility`` (float32 in [0, 1], 1 on the background), ``shaded``, and
    ``facing`` (bool: visible points whose normal faces the light, the pixels
    where a shadow changes the image; on the others diffuse light is zero anyway).

    Parameters
    ----------
    renderer : morphkit.protocols.SceneRenderer
        Renders the colour and depth images.
    scene : morphkit.scene.Scene
        Camera, light, receiver and object.
    visibility : callable
        ``visibility(points (N, 3) world frame, normals (N, 3)) -> (N,)`` values
        in ``[0, 1]``.
    receiver_only : bool
        Test only the receiver's pixels (the object's own pixels stay lit).
    background : (3,) float
        Background RGB in ``[0, 1]``.
    one_pass : bool
        Draw the camera once where ``renderer`` is a :class:`~morphkit.protocols.FrameRenderer`
        (default); False: twice, lit then unlit (the reference the one pass
        is tested against).

    Returns
    -------
    dict of str to numpy.ndarray
        The images named above, each ``(H, W)`` or ``(H, W, 3)`` of the scene
        camera.

    Raises
    ------
    ValidationError
        ``renderer`` is not a :class:`~morphkit.protocols.SceneRenderer`, ``scene``
        not a :class:`~morphkit.scene.Scene`, ``visibility`` not callable, or what it
        returns is not ``(N,)`` values in ``[0, 1]`` for the ``N`` points it was given.
    """
    if not isinstance(renderer, SceneRenderer):
        raise ValidationError(expected_got("renderer", "a SceneRenderer (depth, color_depth, source_view)",
                                           type(renderer).__name__))
    if not isinstance(scene, Scene):
        raise ValidationError(expected_got("scene", "a morphkit.scene.Scene", type(scene).__name__))
    if not callable(visibility):
        raise ValidationError(expected_got("visibility", "a callable (points, normals) -> (N,) values",
                                           type(visibility).__name__))
    items = frame_items(scene)
    cam = scene.camera
    if one_pass and isinstance(renderer, FrameRenderer):
        drawn = renderer.frame_pass(cam, items, [scene.light], ambient=scene.ambient, background=background,
                                    marked=[len(items) - 1] if receiver_only else ())
        lit, unlit, depth, on_object = drawn.lit, drawn.unlit, drawn.depth, drawn.marked
    else:
        lit, depth = renderer.color_depth(cam, items, [scene.light], ambient=scene.ambient,
                                          background=background)
        unlit, _ = renderer.color_depth(cam, items, [], ambient=scene.ambient, background=background)
        on_object = _object_pixels(renderer, scene, depth) if receiver_only else None
    # the drawn pixels' points, normals and light facing in one pass (module morphkit.shadow.pixels)
    drawn, points, pixel_normals, facing = drawn_pixels(cam, depth, scene.light)
    vis = np.ones(cam.shape, np.float32)
    tested = None if on_object is None else ~on_object.reshape(-1).take(drawn)
    if tested is not None and not tested.all():  # by index: several times faster than a boolean mask
        keep = np.flatnonzero(tested)
        drawn, points, pixel_normals = (drawn.take(keep), points.take(keep, axis=0),
                                        pixel_normals.take(keep, axis=0))
    if len(drawn):
        vis.reshape(-1)[drawn] = _checked_visibility(visibility(points, pixel_normals), len(drawn))
    return {"lit": lit, "unlit": unlit, "depth": depth, "visibility": vis,
            "shaded": shade(lit, unlit, vis), "facing": facing}


def _object_pixels(renderer: SceneRenderer, scene: Scene, depth: np.ndarray) -> np.ndarray:
    """The pixels of ``depth`` (the frame's) where the object is the visible surface: an
    object-only depth image agrees with it (a third draw)."""
    obj_depth = renderer.depth(scene.camera, [Item(scene.obj.mesh, scene.obj.pose)])
    with np.errstate(invalid="ignore"):  # inf - inf on the background
        same = np.abs(obj_depth - depth) <= tol.DEPTH_SAME_SURFACE_REL * np.abs(depth)
    return np.isfinite(obj_depth) & same


def _checked_visibility(v: object, n: int) -> np.ndarray:
    """``v`` as ``(n,)`` float32 values in [0, 1], or a ValidationError."""
    what, want = "visibility(points, normals)", f"({n},) values in [0, 1]"
    if not isinstance(v, np.ndarray) or v.dtype.kind not in "fiub":
        raise ValidationError(expected_got(what, want, type(v).__name__ if not isinstance(v, np.ndarray)
                                           else f"dtype {v.dtype}"))
    if v.shape != (n,):
        raise ValidationError(expected_got(what, want, f"shape {v.shape}"))
    bad = int(np.count_nonzero(~((v >= 0) & (v <= 1))))
    if bad:
        raise ValidationError(expected_got(what, want, f"{bad} values outside [0, 1] or NaN"))
    return v.astype(np.float32, copy=False)


def compare_frames(renderer: SceneRenderer, scene: Scene, methods: dict[str, ShadowMethod], xy: np.ndarray
                   ) -> dict[str, dict[str, np.ndarray]]:
    """Frames of ``scene`` with its object at ``xy``, shadowed by each method's
    shadow map (``method.shadow_map(xy) -> (depth, light_cam)``) and by the ray-cast
    ground truth (key ``"raycast"``).

    Parameters
    ----------
    renderer : morphkit.protocols.SceneRenderer
        Renders the frames.
    scene : morphkit.scene.Scene
        The scene; its object is moved to ``xy``.
    methods : dict of str to morphkit.shadow.method.ShadowMethod
        The shadow methods, by name.
    xy : (2,) float
        The object's ground translation (world units).

    Returns
    -------
    dict of str to dict
        Per method name (and ``"raycast"``), the images of :func:`render_frame`.
    """
    pose = scene.obj.pose.copy()
    pose[:2, 3] = xy
    sc = scene.with_object_pose(pose)
    out = {}
    for name, m in methods.items():
        d, lcam = m.shadow_map(xy)
        out[name] = render_frame(renderer, sc, lambda p, n, d=d, c=lcam: shadow_visibility(
            p, d, c, normals=n))
    out["raycast"] = render_frame(renderer, sc, lambda p, _n: hard_visibility(p, sc.light, sc.obj))
    return out
