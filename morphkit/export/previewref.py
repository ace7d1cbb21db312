"""What a preview page should draw, drawn by morphkit: the reference its screenshots are held to.

:func:`reference_image` casts the page camera's rays (:meth:`~.preview.PreviewView.camera`) and
draws, as the page does: the ground plane ``z = 0`` in :data:`~.preview.GROUND_ALBEDO` and the sky
in :data:`~.preview.SKY`; each instance's billboard by morphkit's per-pixel depth morph of its
three views around the direction towards the eye (:func:`morphkit.views.depthmorph.morph_views`,
in the instance's object frame); the billboards shaded by :func:`morphkit.imaging.shading.shade`
under ``Lighting(BAKE_AMBIENT, (sun(a, e),))`` and the ground alike; the ground shadowed by each
instance's sun atlas (:func:`morphkit.sunlit.sunatlas.ground_shadow`); billboards composited over
the ground in front of it. Billboards are not shadowed (neither here nor on the page). A
billboard's march takes :func:`~morphkit.views.depthmorph.steps_for` its image on screen (the side
of its quad, in pixels), as morphkit's scenes do at the image's size, not the whole screen's.

:func:`truth_image` is the same view of the real mesh (one instance at the origin): its G-buffer
drawn by the renderer and shaded by :func:`morphkit.imaging.shading.shade_passes` (no shadow on the
mesh either), the ground shadowed by ray casting against the mesh
(:func:`morphkit.imaging.groundtruth.hard_visibility`). :func:`stand_in_image` draws a stand-in
mesh (an engine's level of detail) alike, its ground shadowed by the asset's sun atlas.

A scene of several instances is drawn with each instance's own light view; the page draws one
light view for the whole scene (:data:`~.preview.SHADOW_MAX_TEXELS` at most), so its shadows are
coarser where the scene is wide: the comparison holds exactly for one instance.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import cv2
import numpy as np
import trimesh

from .. import tol
from ..billboard.baking.bakelook import BAKE_AMBIENT
from ..billboard.domeasset import DomeAsset
from ..billboard.impostor import OctahedralImpostor
from ..camera import CameraModel
from ..imaging.groundtruth import hard_visibility
from ..imaging.shading import Lighting, shade, shade_passes
from ..protocols import PassRenderer
from ..scene import Item, SceneObject
from ..sunlit.sunatlas import SunAtlas, ground_shadow
from ..sunpath import SUN_INTENSITY, sun
from ..views.depthmorph import morph_views, remap_points, steps_for
from ..views.gbuffer import ViewSurface
from .preview import GROUND_ALBEDO, SKY, PreviewView

__all__ = ["reference_image", "truth_image", "stand_in_image", "impostor_rays"]


def _yaw(deg: float) -> np.ndarray:
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _encode(linear: np.ndarray) -> np.ndarray:
    return np.power(np.clip(linear, 0.0, 1.0), 1.0 / 2.2)


def impostor_rays(impostor: OctahedralImpostor, origins: np.ndarray, dirs: np.ndarray,
                  frames: list[tuple[int, float]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The octahedral impostor along rays of any origin (module docstring of
    :mod:`morphkit.billboard.impostor`: each frame read where the ray meets its plane, moved by
    one parallax step, the frames blended by weight), as the engines' shaders do from the real eye.

    Parameters
    ----------
    impostor : OctahedralImpostor
        Its frames (level 0).
    origins, dirs : (P, 3) float
        Rays, object frame (unit directions).
    frames : list of (int, float)
        :meth:`~morphkit.billboard.impostor.OctahedralImpostor.weights` of the view's direction.

    Returns
    -------
    albedo : (P, 4) float32
        Premultiplied linear albedo and alpha (0 where empty).
    normal : (P, 3) float32
        Unit normals (0 where empty).
    t : (P,) float32
        The ray parameter of the surface shown (``inf`` where empty).
    """
    m = impostor.frame_side
    scale, centre = m / (2.0 * float(impostor.half_extent[0])), (m - 1) / 2.0
    op = np.asarray(origins, np.float64) - impostor.pivot
    d = np.asarray(dirs, np.float64)
    dist = np.float32(impostor.distance)
    p = len(op)
    albedo = np.zeros((p, 4), np.float32)
    normal = np.zeros((p, 3), np.float32)
    dsum = np.zeros(p, np.float32)
    floor = np.float32(tol.ALPHA_FLOOR)
    for k, w in frames:
        s = impostor.frame_surface(k)
        a = s.alpha
        h = np.where(np.isfinite(s.depth), dist - s.depth, np.float32(0.0)) * a
        tex_h = np.ascontiguousarray(np.stack([a, h], axis=-1), np.float32)
        tex_n = np.ascontiguousarray(s.normal, np.float32)
        dk, rk, uk = impostor.frame_dirs[k], impostor.frame_right[k], impostor.frame_up[k]
        base = (op @ dk).astype(np.float32)
        qk = np.minimum(d @ dk, -tol.IMP_MIN_COS).astype(np.float32)
        fx0, fy0 = (op @ rk).astype(np.float32), (op @ uk).astype(np.float32)
        qx, qy = (d @ rk).astype(np.float32), (d @ uk).astype(np.float32)

        def at(t: np.ndarray, fx0: np.ndarray = fx0, fy0: np.ndarray = fy0, qx: np.ndarray = qx,
               qy: np.ndarray = qy) -> tuple[np.ndarray, np.ndarray]:
            return ((fx0 + t * qx) * np.float32(scale) + np.float32(centre)).astype(np.float32), \
                (-(fy0 + t * qy) * np.float32(scale) + np.float32(centre)).astype(np.float32)

        def height(t: np.ndarray, tex_h: np.ndarray = tex_h) -> tuple[np.ndarray, np.ndarray]:
            ah = remap_points(tex_h, *at(t), cv2.INTER_LINEAR, 0.0)
            hh = np.where(ah[:, 0] > floor, ah[:, 1] / np.maximum(ah[:, 0], floor), np.float32(0.0))
            return ah[:, 0], hh

        _, hk = height(-base / qk)
        t = (hk - base) / qk
        u, v = at(t)
        fa = remap_points(np.ascontiguousarray(s.albedo, np.float32), u, v, cv2.INTER_LINEAR, 0.0)
        fn = remap_points(tex_n, u, v, cv2.INTER_LINEAR, 0.0)
        ah = remap_points(tex_h, u, v, cv2.INTER_LINEAR, 0.0)
        hk = np.where(fa[:, 3] > floor, ah[:, 1] / np.maximum(fa[:, 3], floor), np.float32(0.0))
        t = (hk - base) / qk
        wk = np.float32(w)
        albedo += wk * fa
        normal += wk * fn
        dsum += wk * fa[:, 3] * t
    alpha = albedo[:, 3]
    drawn = alpha > floor
    norm = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.where(drawn[:, None] & (norm > 0), normal / np.maximum(norm, floor), np.float32(0.0))
    albedo = np.where(drawn[:, None], np.clip(albedo, 0.0, 1.0), np.float32(0.0))
    t = np.where(drawn, dsum / np.maximum(alpha, floor), np.float32(np.inf))
    return albedo.astype(np.float32), normal.astype(np.float32), t.astype(np.float32)


def reference_image(asset: DomeAsset | OctahedralImpostor, sun_atlas: SunAtlas | None, instances: np.ndarray,
                    view: PreviewView, target: np.ndarray) -> np.ndarray:
    """The page's image of ``view``, drawn by morphkit (module docstring).

    Parameters
    ----------
    asset : DomeAsset or OctahedralImpostor
        The billboards' views: morphed (a dome asset), or an impostor's frames
        (:func:`impostor_rays`).
    sun_atlas : SunAtlas or None
        Their sun atlas (None: no shadows).
    instances : (N, 5) float
        ``(x, y, z, yaw_deg, scale)`` per instance, world frame.
    view : PreviewView
        The camera and sun.
    target : (3,) float
        The point the camera orbits.

    Returns
    -------
    (h, w, 3) float32
        Encoded colour in ``[0, 1]``.
    """
    cam = view.camera(target)
    h, w = cam.shape
    sun_dir = view.sun_direction()
    lighting = Lighting(BAKE_AMBIENT, (sun(view.sun_azimuth_deg, view.sun_elevation_deg),))
    inst = np.asarray(instances, np.float64).reshape(-1, 5)

    def shadow(pts: np.ndarray) -> np.ndarray:
        vis = np.ones(len(pts), np.float32)
        if sun_atlas is not None:
            for x, y, z, yaw, s in inst:
                pose = np.eye(4)
                pose[:3, :3] = s * _yaw(yaw)
                pose[:3, 3] = (x, y, z)
                vis *= ground_shadow(sun_atlas, pose, sun_dir, pts)
        return vis

    image, depth = _ground(cam, view, shadow)
    for x, y, z, yaw, s in inst:
        R = _yaw(yaw)
        pose = np.eye(4)
        pose[:3, :3] = R.T @ cam.cam2world[:3, :3]
        pose[:3, 3] = R.T @ (cam.position - np.array([x, y, z])) / s
        local = cam.with_pose(pose)
        rel = pose[:3, 3] - asset.pivot
        az = float(np.degrees(np.arctan2(rel[1], rel[0])))
        el = float(np.degrees(np.arcsin(np.clip(rel[2] / np.linalg.norm(rel), -1.0, 1.0))))
        if isinstance(asset, OctahedralImpostor):
            o, d = local.rays()
            alb, nrm, t = impostor_rays(asset, o.reshape(-1, 3), d.reshape(-1, 3), asset.weights(az, el))
            zc = t * (d.reshape(-1, 3) @ local.axis)
            surf = ViewSurface(alb.reshape(h, w, 4), nrm.reshape(h, w, 3),
                               zc.reshape(h, w).astype(np.float32))
        else:
            views, weights = asset.dome.weights(az, el)
            used = [(asset.reference_camera(int(k)), asset.reference_surface(int(k)), float(wt))
                    for k, wt in zip(views, weights, strict=True) if wt > 0]
            # the march's samples: those of the instance's image on screen (its quad's side, pixels)
            side = 2.0 * asset.half_extent[0] * s * cam.fy / (np.linalg.norm(rel) * s)
            steps = steps_for((int(min(side, 1e6)), 0))
            surf = morph_views(local, asset.pivot, asset.cameras.radius, used, steps=steps)
        turn = np.eye(4)
        turn[:3, :3] = R.T
        rgba = shade(surf, lighting.in_frame(turn)).reshape(-1, 4)
        zb = surf.depth.reshape(-1) * s
        front = (rgba[:, 3] > 0) & (zb < depth)
        a = rgba[front, 3:4]
        image[front] = rgba[front, :3] + (1.0 - a) * image[front]
        depth[front] = zb[front]
    return image.reshape(h, w, 3)


def _ground(cam: CameraModel, view: PreviewView, shadow: Callable[[np.ndarray], np.ndarray]
            ) -> tuple[np.ndarray, np.ndarray]:
    """The sky and the lit ground of ``cam`` (``(h w, 3)`` encoded, ``(h w,)`` depth along its
    axis, inf on the sky), the ground's sun visibility by ``shadow(points)``."""
    o, d = cam.rays()
    o, d = o.reshape(-1, 3), d.reshape(-1, 3)
    sun_dir = view.sun_direction()
    image = np.empty((len(o), 3), np.float32)
    image[:] = SKY
    depth = np.full(len(o), np.inf)
    on = (d[:, 2] < 0) & (o[:, 2] > 0)
    tg = np.where(on, -o[:, 2] / np.where(on, d[:, 2], -1.0), np.inf)
    pts = o[on] + tg[on, None] * d[on]
    if sun_dir[2] > 0:
        e = BAKE_AMBIENT + (SUN_INTENSITY / np.pi) * float(sun_dir[2]) * shadow(pts)
    else:
        e = np.full(len(pts), BAKE_AMBIENT)
    image[on] = _encode(np.asarray(GROUND_ALBEDO)[None, :] * np.asarray(e)[:, None])
    depth[on] = tg[on] * (d[on] @ cam.axis)
    return image, depth


def truth_image(mesh: trimesh.Trimesh, items: Sequence[Item], renderer: PassRenderer, view: PreviewView,
                target: np.ndarray) -> np.ndarray:
    """The page's view of the real mesh at the origin (module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The normalised mesh (the asset's frame): the ground's occluder.
    items : sequence of Item
        Its render items in the asset's look (:meth:`~morphkit.billboard.DomeAsset.items`).
    renderer : PassRenderer
        E.g. :class:`morphkit.render.Renderer`.
    view : PreviewView
        The camera and sun.
    target : (3,) float
        The point the camera orbits.

    Returns
    -------
    (h, w, 3) float32
        Encoded colour in ``[0, 1]``.
    """
    light = sun(view.sun_azimuth_deg, view.sun_elevation_deg)
    occluder = SceneObject(mesh)
    return _drawn(items, renderer, view, target, lambda pts: hard_visibility(pts, light, occluder))


def stand_in_image(items: Sequence[Item], sun_atlas: SunAtlas | None, renderer: PassRenderer,
                   view: PreviewView, target: np.ndarray) -> np.ndarray:
    """The page's view of a stand-in drawn as a mesh (e.g. :func:`~.lod.cross_card`, one instance at
    the origin), shaded as :func:`truth_image` shades the mesh, its ground shadowed by the asset's
    sun atlas as :func:`reference_image` shadows the billboards'.

    Parameters
    ----------
    items : sequence of Item
        The stand-in's render items, object frame.
    sun_atlas : SunAtlas or None
        The asset's sun atlas (None: no shadow).
    renderer : PassRenderer
        E.g. :class:`morphkit.render.Renderer`.
    view : PreviewView
        The camera and sun.
    target : (3,) float
        The point the camera orbits.

    Returns
    -------
    (h, w, 3) float32
        Encoded colour in ``[0, 1]``.
    """
    sun_dir = view.sun_direction()

    def shadow(pts: np.ndarray) -> np.ndarray:
        if sun_atlas is None:
            return np.ones(len(pts), np.float32)
        return ground_shadow(sun_atlas, np.eye(4), sun_dir, pts)

    return _drawn(items, renderer, view, target, shadow)


def _drawn(items: Sequence[Item], renderer: PassRenderer, view: PreviewView, target: np.ndarray,
           shadow: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """``items`` drawn and shaded over the ground, its sun visibility by ``shadow(points)``."""
    cam = view.camera(target)
    h, w = cam.shape
    light = sun(view.sun_azimuth_deg, view.sun_elevation_deg)
    image, depth = _ground(cam, view, shadow)
    passes = renderer.gbuffer_pass(cam, items)
    rgba = shade_passes(passes, Lighting(BAKE_AMBIENT, (light,)), cam).reshape(-1, 4)
    zb = passes.depth.reshape(-1)
    front = (rgba[:, 3] > 0) & (zb < depth)
    a = rgba[front, 3:4]
    image[front] = rgba[front, :3] + (1.0 - a) * image[front]
    return image.reshape(h, w, 3)
