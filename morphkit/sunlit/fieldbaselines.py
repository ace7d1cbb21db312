"""The baselines of a field's shadow (:mod:`.fieldshadow`): the direct light render and the ray cast.

* **direct** (:func:`direct_field_map`): every posed mesh the field draws rendered from the sun
  into the same field light view (:meth:`~.fieldshadow.FieldShadow.plan`'s camera, the same
  instances): what a sun change costs without atlases.
* **truth** (:func:`ray_cast_field`): a ray from each receiver point towards the exact sun
  against all posed meshes (:func:`morphkit.imaging.groundtruth.hard_visibility`, Embree when
  installed): no clamp at the grazing cut-off. The instances of one asset are posed into one
  mesh that keeps the asset's look (:func:`posed_asset_meshes`), so a cut-out asset (alpha-masked
  leaves) casts through its holes as the renders do; a ray is lit when no asset's mesh blocks it.

Meshes are given by asset name and posed as the atlases are: the *normalised* mesh
(:func:`morphkit.meshes.normalize`) by each instance's ``object2world``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import trimesh

from ..billboard.frames.instances import Instances
from ..errors import ValidationError, expected_got
from ..imaging.groundtruth import hard_visibility
from ..meshes import normalize
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, Item, SceneObject
from ..validate import as_finite_array
from .fieldshadow import FieldMap, FieldShadow, field_sun

__all__ = ["direct_field_map", "ray_cast_field", "posed_field_mesh", "posed_asset_meshes"]


def _normalised(meshes: Mapping[str, trimesh.Trimesh], instances: Instances) -> dict[str, trimesh.Trimesh]:
    missing = [nm for nm in instances.names if nm not in meshes]
    if missing:
        raise ValidationError(expected_got("meshes", "one per asset name of the instances",
                                           f"none for {missing}"))
    return {nm: normalize(meshes[nm]) for nm in instances.names}


def direct_field_map(field: FieldShadow, normalized: Mapping[str, trimesh.Trimesh], renderer: SceneRenderer,
                     instances: Instances, sun_dir_world: np.ndarray, texels_per_unit: float,
                     receiver: tuple[float, float, float, float] | None = None) -> FieldMap:
    """The field's light view rendered directly: all kept posed meshes, one depth draw.

    Parameters
    ----------
    field : FieldShadow
        Gives the camera and the instances kept (:meth:`~.fieldshadow.FieldShadow.plan`).
    normalized : mapping of str to trimesh.Trimesh
        Each asset's *normalised* mesh (:func:`morphkit.meshes.normalize`; not re-normalised
        here, so the timing is the draw's).
    renderer : SceneRenderer
        Draws the depth (e.g. :class:`morphkit.render.Renderer`).
    instances : Instances
        The field.
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    texels_per_unit : float
        The view's resolution.
    receiver : (xmin, ymin, xmax, ymax), optional
        As :meth:`~.fieldshadow.FieldShadow.build`.

    Returns
    -------
    FieldMap
        Same camera and instances as the atlas's map.

    Raises
    ------
    ValidationError
        Bad arguments; an asset without a mesh.
    """
    plan = field.plan(instances, sun_dir_world, texels_per_unit, receiver)
    missing = [nm for nm in instances.names if nm not in normalized]
    if missing:
        raise ValidationError(expected_got("normalized", "one mesh per asset name", f"none for {missing}"))
    if plan.camera is None:
        return plan
    items = [Item(normalized[instances.names[int(instances.asset[k])]], instances.object2world(int(k)))
             for k in plan.kept]
    return FieldMap(plan.camera, renderer.depth(plan.camera, items), plan.kept, plan.skipped)


def posed_field_mesh(meshes: Mapping[str, trimesh.Trimesh], instances: Instances) -> trimesh.Trimesh | None:
    """All instances' normalised meshes posed into one world-frame mesh.

    The concatenation drops textured looks (a cut-out asset's holes included): for a truth
    that honours them use :func:`posed_asset_meshes`.

    Parameters
    ----------
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh (normalised here).
    instances : Instances
        The field.

    Returns
    -------
    trimesh.Trimesh or None
        ``None`` for no instance.
    """
    norm = _normalised(meshes, instances)
    parts = []
    for k in range(len(instances)):
        m = norm[instances.names[int(instances.asset[k])]].copy()
        m.apply_transform(instances.object2world(k))
        parts.append(m)
    return trimesh.util.concatenate(parts) if parts else None


def _posed_copies(mesh: trimesh.Trimesh, poses: list[np.ndarray]) -> trimesh.Trimesh:
    """``mesh`` posed by each of ``poses``, one mesh; a texture's look kept (one material, UVs tiled)."""
    uv = getattr(mesh.visual, "uv", None)
    if not isinstance(mesh.visual, trimesh.visual.TextureVisuals) or uv is None:
        parts = []
        for pose in poses:
            m = mesh.copy()
            m.apply_transform(pose)
            parts.append(m)
        return trimesh.util.concatenate(parts)
    v = np.asarray(mesh.vertices, dtype=np.float64)
    nv = len(v)
    verts = np.concatenate([v @ np.asarray(p)[:3, :3].T + np.asarray(p)[:3, 3] for p in poses])
    faces = np.concatenate([np.asarray(mesh.faces) + k * nv for k in range(len(poses))])
    visual = trimesh.visual.TextureVisuals(uv=np.tile(np.asarray(uv), (len(poses), 1)),
                                           material=mesh.visual.material)
    return trimesh.Trimesh(verts, faces, visual=visual, process=False)


def posed_asset_meshes(meshes: Mapping[str, trimesh.Trimesh], instances: Instances) -> list[trimesh.Trimesh]:
    """The instances of each asset posed into one world-frame mesh that keeps the asset's look.

    A textured asset's copies share its material (UVs tiled), so its cut-out (alpha-masked
    texels, :func:`morphkit.imaging.cutout.mesh_cutout`) holds for every instance.

    Parameters
    ----------
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh (normalised here).
    instances : Instances
        The field.

    Returns
    -------
    list of trimesh.Trimesh
        One mesh per asset with instances, in the order of ``instances.names``; empty for
        no instance.

    Raises
    ------
    ValidationError
        An asset without a mesh.
    """
    norm = _normalised(meshes, instances)
    out = []
    for a, name in enumerate(instances.names):
        idx = np.flatnonzero(np.asarray(instances.asset) == a)
        if len(idx):
            out.append(_posed_copies(norm[name], [instances.object2world(int(k)) for k in idx]))
    return out


def ray_cast_field(meshes: Mapping[str, trimesh.Trimesh], instances: Instances, sun_dir_world: np.ndarray,
                   points: np.ndarray, *,
                   posed: trimesh.Trimesh | Sequence[trimesh.Trimesh] | None = None) -> np.ndarray:
    """The truth: rays from each point towards the exact sun against all posed meshes.

    Parameters
    ----------
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh (normalised here).
    instances : Instances
        The field.
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    points : (N, 3) float
        Receiver points, world frame.
    posed : trimesh.Trimesh or sequence of trimesh.Trimesh, optional
        The field's posed meshes, made once for many suns: :func:`posed_asset_meshes`
        (the default; cut-outs honoured) or :func:`posed_field_mesh`.

    Returns
    -------
    (N,) float32
        1 lit, 0 shadowed; all 1 for a sun at or below the horizon or no instance.
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    if field_sun(sun_dir_world) is None:
        return np.ones(len(pts), np.float32)
    if posed is None:
        bodies = posed_asset_meshes(meshes, instances)
    else:
        bodies = [posed] if isinstance(posed, trimesh.Trimesh) else list(posed)
    d = np.asarray(sun_dir_world, dtype=np.float64)
    light = DirectionalLight(-d / np.linalg.norm(d))
    vis = np.ones(len(pts), np.float32)
    for body in bodies:
        lit = np.flatnonzero(vis > 0.0)  # a ray one asset blocks needs no other
        if len(lit):
            vis[lit] = hard_visibility(pts[lit], light, SceneObject(body))
    return vis
