"""A small declarative scene: receiver, one object with a pose, one light, one camera.

Pure data (numpy + trimesh); :mod:`morphkit.render` turns it into GL nodes,
built once and updated by pose ("model only what a scene needs": moving the
object changes a node pose, not the scene). Frames follow
:mod:`morphkit.conventions` (world ``+z`` up, ground plane ``z = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import trimesh

from . import tol
from .camera import CameraModel, look_at, orthographic
from .errors import DegenerateViewError, MeshError, ValidationError, expected_got
from .validate import as_direction, as_finite_array, as_int, as_pose, as_positive

__all__ = [
    "Receiver",
    "DirectionalLight",
    "PointLight",
    "AreaLight",
    "Light",
    "SceneObject",
    "Scene",
    "translation",
    "light_view",
    "Item",
    "scene_items",
]


def translation(x: float, y: float, z: float = 0.0) -> np.ndarray:
    """A 4x4 pure translation.

    Parameters
    ----------
    x, y, z : float
        Translation, scene units.

    Returns
    -------
    (4, 4) float64
        The homogeneous transform.

    Examples
    --------
    >>> import numpy as np
    >>> from morphkit.scene import translation
    >>> translation(1.0, 2.0) @ np.array([0.0, 0.0, 0.5, 1.0])
    array([1. , 2. , 0.5, 1. ])
    """
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


@dataclass(frozen=True)
class Receiver:
    """Shadow receivers: a square ground plane ``z = 0`` of half size
    ``half_size`` centred on the origin, and optionally a wall, the plane
    ``x = wall_x`` facing ``-x``, of height ``wall_height``.

    Receivers receive shadows; they are not occluders.

    Parameters
    ----------
    half_size : float, optional
        Half side of the ground square, scene units.
    wall_x : float or None, optional
        ``x`` of the wall plane, world frame; ``None`` for no wall.
    wall_height : float, optional
        Wall height above the ground, scene units.
    color : tuple of 3 float, optional
        Receiver RGB in ``[0, 1]``.
    """

    half_size: float = 2.0
    wall_x: float | None = None
    wall_height: float = 2.0
    color: tuple[float, float, float] = (0.82, 0.80, 0.76)

    def __post_init__(self) -> None:
        as_positive(self.half_size, "half_size")
        as_positive(self.wall_height, "wall_height")

    @cached_property
    def meshes(self) -> tuple[trimesh.Trimesh, ...]:
        """The receiver surfaces as thin-free triangle meshes (two triangles each)."""
        h = self.half_size
        ground = trimesh.Trimesh(
            vertices=[[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]],
            faces=[[0, 1, 2], [0, 2, 3]], process=False)
        out = [ground]
        if self.wall_x is not None:
            x, H = float(self.wall_x), self.wall_height
            wall = trimesh.Trimesh(
                vertices=[[x, -h, 0], [x, h, 0], [x, h, H], [x, -h, H]],
                faces=[[0, 2, 1], [0, 3, 2]], process=False)
            out.append(wall)
        return tuple(out)


@dataclass(frozen=True)
class DirectionalLight:
    """A light at infinity. ``direction`` is the direction light travels
    (from the light towards the scene), normalised on construction.

    Parameters
    ----------
    direction : (3,) float
        Direction the light travels, world frame (normalised on construction).
    intensity : float, optional
        Light intensity (pyrender units).

    Examples
    --------
    Straight down, given with any length; the way towards the light is the
    opposite direction, at infinite distance.

    >>> import numpy as np
    >>> from morphkit.scene import DirectionalLight
    >>> light = DirectionalLight(np.array([0.0, 0.0, -2.0]))
    >>> light.direction
    array([ 0.,  0., -1.])
    >>> towards, distance = light.to_light(np.zeros((1, 3)))
    >>> towards + 0.0, distance  # + 0.0 prints -0.0 as 0.0
    (array([[0., 0., 1.]]), array([inf]))
    """

    direction: np.ndarray
    intensity: float = 3.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "direction", as_direction(self.direction, "direction"))
        as_positive(self.intensity, "intensity")

    def to_light(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit directions from ``points (N, 3)`` towards the light, and the
        distance to it (``inf``).

        Parameters
        ----------
        points : (N, 3) float
            Points, world frame.

        Returns
        -------
        directions : (N, 3) float64
            Unit directions towards the light, world frame.
        distances : (N,) float64
            ``inf`` for every point.
        """
        d = np.broadcast_to(-self.direction, points.shape).copy()
        return d, np.full(len(points), np.inf)


@dataclass(frozen=True)
class PointLight:
    """A point light at ``position`` (a spot light when used for a perspective
    light view).

    Parameters
    ----------
    position : (3,) float
        Light position, world frame.
    intensity : float, optional
        Light intensity (pyrender units).
    """

    position: np.ndarray
    intensity: float = 30.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", as_finite_array(self.position, "position", shape=(3,)))
        as_positive(self.intensity, "intensity")

    def to_light(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit directions from ``points (N, 3)`` towards the light and distances.

        Parameters
        ----------
        points : (N, 3) float
            Points, world frame.

        Returns
        -------
        directions : (N, 3) float64
            Unit directions towards the light, world frame.
        distances : (N,) float64
            Distances to the light, scene units.
        """
        v = self.position - points
        dist = np.linalg.norm(v, axis=1)
        if np.any(dist < tol.MIN_EXTENT):
            raise ValidationError(expected_got("points", "points away from the point light",
                                               "a point at the light position"))
        return v / dist[:, None], dist


@dataclass(frozen=True)
class AreaLight:
    """A rectangular area light: ``center + a u + b v`` for ``a, b in [-1, 1]``.

    ``u`` and ``v`` are half-extent vectors (scene units); both must be non-zero
    and not parallel (a zero-size light is refused: use :class:`PointLight`).

    Parameters
    ----------
    center : (3,) float
        Centre of the rectangle, world frame.
    u, v : (3,) float
        Half-extent vectors, world frame, scene units.
    intensity : float, optional
        Total light intensity (pyrender units), shared by its samples.
    """

    center: np.ndarray
    u: np.ndarray
    v: np.ndarray
    intensity: float = 30.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", as_finite_array(self.center, "center", shape=(3,)))
        u = as_finite_array(self.u, "u", shape=(3,))
        v = as_finite_array(self.v, "v", shape=(3,))
        area = float(np.linalg.norm(np.cross(u, v)))
        if area < tol.MIN_EXTENT:
            raise ValidationError(expected_got(
                "area light extent", "non-zero, non-parallel half-extent vectors u, v",
                f"u={u.tolist()}, v={v.tolist()} (area {4 * area:g})"))
        object.__setattr__(self, "u", u)
        object.__setattr__(self, "v", v)
        as_positive(self.intensity, "intensity")

    def samples(self, n_u: int, n_v: int | None = None,
                rng: np.random.Generator | None = None) -> np.ndarray:
        """``n_u * n_v`` sample positions ``(N, 3)``: centres of an ``n_u x n_v``
        grid of cells, jittered uniformly inside each cell when ``rng`` is given.

        ``n_u``, ``n_v`` are integers >= 1 with ``n_u * n_v`` at most
        :data:`morphkit.tol.MAX_LIGHT_SAMPLES` (checked before allocating).

        Parameters
        ----------
        n_u : int
            Cells along ``u``.
        n_v : int, optional
            Cells along ``v``; defaults to ``n_u``.
        rng : numpy.random.Generator, optional
            Jitter source; ``None`` for cell centres.

        Returns
        -------
        (n_u * n_v, 3) float64
            Sample positions, world frame.
        """
        n_v = n_u if n_v is None else n_v
        n_u, n_v = as_int(n_u, "n_u"), as_int(n_v, "n_v")
        if n_u < 1 or n_v < 1:
            raise ValidationError(expected_got("light samples", "n_u, n_v >= 1", (n_u, n_v)))
        if n_u * n_v > tol.MAX_LIGHT_SAMPLES:
            raise ValidationError(expected_got(
                "light samples", f"at most {tol.MAX_LIGHT_SAMPLES} (morphkit.tol.MAX_LIGHT_SAMPLES)",
                f"{n_u} x {n_v}"))
        a = (np.arange(n_u) + 0.5) / n_u
        b = (np.arange(n_v) + 0.5) / n_v
        A, B = np.meshgrid(a, b, indexing="ij")
        if rng is not None:
            A = A + (rng.random(A.shape) - 0.5) / n_u
            B = B + (rng.random(B.shape) - 0.5) / n_v
        A, B = 2 * A.ravel() - 1, 2 * B.ravel() - 1
        return self.center + A[:, None] * self.u + B[:, None] * self.v

    def point_lights(self, n_u: int, n_v: int | None = None,
                     rng: np.random.Generator | None = None) -> list[PointLight]:
        """The area light as point lights sharing its intensity equally.

        Parameters
        ----------
        n_u : int
            Cells along ``u``.
        n_v : int, optional
            Cells along ``v``; defaults to ``n_u``.
        rng : numpy.random.Generator, optional
            Jitter source; ``None`` for cell centres.

        Returns
        -------
        list of PointLight
            One light at each of :meth:`samples`' positions, each with
            ``intensity / (n_u * n_v)``.
        """
        pos = self.samples(n_u, n_v, rng)
        return [PointLight(p, self.intensity / len(pos)) for p in pos]


#: Any of the light types.
Light = DirectionalLight | PointLight | AreaLight


@dataclass(frozen=True)
class SceneObject:
    """One occluding object: a mesh and its ``object2world`` pose.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Geometry, object frame.
    pose : (4, 4) float64, optional
        ``object2world``; identity by default.
    color : tuple of 3 float, optional
        Base RGB in ``[0, 1]``.

    Examples
    --------
    A unit cube (centred on its origin) lifted to height 1.5 spans ``z`` in
    ``[1, 2]``; :meth:`moved` shares the mesh at another pose.

    >>> import trimesh
    >>> from morphkit.scene import SceneObject, translation
    >>> cube = SceneObject(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), translation(0.0, 0.0, 1.5))
    >>> cube.world_bounds()
    array([[-0.5, -0.5,  1. ],
           [ 0.5,  0.5,  2. ]])
    >>> cube.moved(translation(2.0, 0.0, 0.5)).world_bounds()[:, 0]
    array([1.5, 2.5])
    """

    mesh: trimesh.Trimesh
    pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    color: tuple[float, float, float] = (0.75, 0.35, 0.25)

    def __post_init__(self) -> None:
        if not isinstance(self.mesh, trimesh.Trimesh):
            raise MeshError(expected_got("mesh", "a trimesh.Trimesh", type(self.mesh).__name__))
        if len(self.mesh.faces) == 0:
            raise MeshError(expected_got("mesh", "at least one face", "an empty mesh"))
        object.__setattr__(self, "pose", as_pose(self.pose, "object pose"))

    def world_bounds(self) -> np.ndarray:
        """(2, 3) axis-aligned bounds of the posed mesh in world coordinates.

        Returns
        -------
        (2, 3) float64
            ``[lo, hi]`` corners, world frame.
        """
        corners = trimesh.bounds.corners(self.mesh.bounds)
        w = corners @ self.pose[:3, :3].T + self.pose[:3, 3]
        return np.array([w.min(0), w.max(0)])

    def world_mesh(self) -> trimesh.Trimesh:
        """A copy of the mesh in world coordinates (for ray casting).

        Returns
        -------
        trimesh.Trimesh
            The posed mesh, world frame.
        """
        m = self.mesh.copy()
        m.apply_transform(self.pose)
        return m

    def moved(self, pose: np.ndarray) -> SceneObject:
        """The same object at another pose (the mesh is shared, not copied).

        Parameters
        ----------
        pose : (4, 4) float64
            New ``object2world``.

        Returns
        -------
        SceneObject
            The object at ``pose``.
        """
        return replace(self, pose=pose)


@dataclass(frozen=True)
class Scene:
    """Receiver + one object + one light + one camera.

    Raises :class:`~morphkit.errors.DegenerateViewError` when the camera is
    inside the object's bounds.

    Parameters
    ----------
    obj : SceneObject
        The occluder.
    light : DirectionalLight, PointLight or AreaLight
        The light.
    camera : CameraModel
        The view camera.
    receiver : Receiver, optional
        Ground (and wall); a default :class:`Receiver` if omitted.
    ambient : float, optional
        Ambient light level in ``[0, 1]``.
    """

    obj: SceneObject
    light: Light
    camera: CameraModel
    receiver: Receiver = field(default_factory=Receiver)
    ambient: float = 0.35

    def __post_init__(self) -> None:
        lo, hi = self.obj.world_bounds()
        self.camera.assert_outside(lo, hi, "object")
        if not 0.0 <= float(self.ambient) <= 1.0:
            raise ValidationError(expected_got("ambient", "a number in [0, 1]", self.ambient))

    def with_object_pose(self, pose: np.ndarray) -> Scene:
        """The same scene with the object moved.

        Parameters
        ----------
        pose : (4, 4) float64
            New ``object2world`` of the object.

        Returns
        -------
        Scene
            A copy with the object at ``pose``.
        """
        return replace(self, obj=self.obj.moved(pose))


def light_view(light: DirectionalLight | PointLight, points: np.ndarray, shape: tuple[int, int], *,
               margin: float = 0.02) -> CameraModel:
    """The tightest light-view camera that sees every point of ``points (N, 3)``.

    "Model only what a scene needs": fit the shadow map to the occluder (over its
    range of motion, if ``points`` covers it), not to the whole scene.

    * Directional light: an orthographic camera looking along ``light.direction``,
      its window the bounding rectangle of the points across the light (plus
      ``margin`` of its size on each side), its depth range the points' range.
    * Point light: a perspective camera at the light, looking at the points'
      bounding-box centre, principal point and focal lengths fitted so the
      points' projections fill the image (square pixels are not required).

    Parameters
    ----------
    light : DirectionalLight or PointLight
        The light whose view is fitted.
    points : (N, 3) float
        Points to cover, world frame.
    shape : (H, W)
        Shadow-map shape in pixels.
    margin : float, optional
        Extra window on each side, as a fraction of its size.

    Returns
    -------
    CameraModel
        Orthographic (directional light) or perspective (point light) camera.

    Raises
    ------
    DegenerateViewError
        A point light inside (or on the plane of) the points' bounds.

    Examples
    --------
    The light view of the cube above, lit from straight above, with no
    margin: an orthographic window of half size 0.5 (64 pixels over 1 unit:
    ``fx = 64``), and a depth range holding exactly the cube's height
    (``zfar - znear = 1``).

    >>> import numpy as np
    >>> import trimesh
    >>> from morphkit.scene import DirectionalLight, SceneObject, light_view, translation
    >>> cube = SceneObject(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), translation(0.0, 0.0, 1.5))
    >>> view = light_view(DirectionalLight(np.array([0.0, 0.0, -1.0])), cube.world_bounds(), (64, 64),
    ...                   margin=0.0)
    >>> view.projection, view.fx, round(view.zfar - view.znear, 9)
    ('orthographic', 64.0, 1.0)
    >>> view.axis
    array([ 0.,  0., -1.])
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    if len(pts) == 0:
        raise ValidationError(expected_got("points", "at least one point", "none"))
    h, w = shape
    lo, hi = pts.min(0), pts.max(0)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, tol.MIN_EXTENT)
    if isinstance(light, DirectionalLight):
        pose = look_at(centre - light.direction * (2 * radius + 1.0), centre)
        cam = (pts - pose[:3, 3]) @ pose[:3, :3]
        xy_lo, xy_hi = cam[:, :2].min(0), cam[:, :2].max(0)
        half = np.maximum((xy_hi - xy_lo) / 2, tol.MIN_EXTENT) * (1 + 2 * margin)
        mid = (xy_lo + xy_hi) / 2
        pose = pose.copy()
        pose[:3, 3] += pose[:3, :2] @ mid  # shift the window onto the points
        zlo, zhi = cam[:, 2].min(), cam[:, 2].max()
        pad = margin * max(zhi - zlo, radius)
        return orthographic(half[0], half[1], (h, w), pose, znear=max(zlo - pad, tol.LIGHT_FIT_MIN_ZNEAR),
                            zfar=zhi + pad)
    if isinstance(light, PointLight):
        if np.linalg.norm(centre - light.position) < tol.MIN_EXTENT:
            raise DegenerateViewError(expected_got("point light", "outside the occluder's bounds",
                                                   f"at its centre {light.position.tolist()}"))
        pose = look_at(light.position, centre)
        cam = (pts - pose[:3, 3]) @ pose[:3, :3]
        if np.any(cam[:, 2] <= tol.MIN_EXTENT):
            raise DegenerateViewError(expected_got(
                "point light", "all occluder points in front of the light (a frustum < 180 deg)",
                f"{int(np.count_nonzero(cam[:, 2] <= tol.MIN_EXTENT))} points beside or behind it"))
        u, v = cam[:, 0] / cam[:, 2], cam[:, 1] / cam[:, 2]
        ulo, uhi, vlo, vhi = u.min(), u.max(), v.min(), v.max()
        du = max(uhi - ulo, tol.MIN_EXTENT) * (1 + 2 * margin)  # frustum extents (tangents)
        dv = max(vhi - vlo, tol.MIN_EXTENT) * (1 + 2 * margin)
        fx, fy = w / du, h / dv
        cx = (w - 1) / 2 - fx * (ulo + uhi) / 2
        cy = (h - 1) / 2 - fy * (vlo + vhi) / 2
        zlo, zhi = cam[:, 2].min(), cam[:, 2].max()
        pad = margin * (zhi - zlo) + tol.LIGHT_FIT_DEPTH_PAD
        return CameraModel("perspective", (h, w), fx, fy, cx, cy, max(zlo - pad, zlo * 0.5),
                           zhi + pad, pose)
    raise ValidationError(expected_got("light", "a DirectionalLight or PointLight (sample an "
                                       "AreaLight first)", type(light).__name__))


@dataclass(frozen=True)
class Item:
    """One mesh to draw: geometry, ``object2world`` pose and look.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Geometry, object frame.
    pose : (4, 4) float64, optional
        ``object2world``; identity by default.
    color : tuple of 3 float or None, optional
        ``None`` (default): the mesh's own look, its texture or vertex/face
        colours (:mod:`morphkit.meshes.look`), or
        :data:`~morphkit.conventions.DEFAULT_COLOR` when it has none. A colour
        (linear RGB in ``[0, 1]``) draws the whole mesh in that one colour,
        whatever its visuals.
    """

    mesh: trimesh.Trimesh
    pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    color: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.color is not None:
            c = as_finite_array(self.color, "item color", shape=(3,))
            if np.any(c < 0.0) or np.any(c > 1.0):
                raise ValidationError(expected_got("item color", "RGB in [0, 1]", c.tolist()))
            object.__setattr__(self, "color", tuple(float(v) for v in c))


def scene_items(scene: Scene, *, receivers: bool = True, obj: bool = True) -> list[Item]:
    """The drawable items of a :class:`~morphkit.scene.Scene`.

    Parameters
    ----------
    scene : Scene
        The scene.
    receivers : bool, optional
        Include the ground (and wall).
    obj : bool, optional
        Include the object.

    Returns
    -------
    list of Item
        The items, world poses.
    """
    items: list[Item] = []
    if receivers:
        items += [Item(m, np.eye(4), scene.receiver.color) for m in scene.receiver.meshes]
    if obj:
        items.append(Item(scene.obj.mesh, scene.obj.pose, scene.obj.color))
    return items
