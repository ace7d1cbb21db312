"""Projective shadow lookup: is a world point in the shadow of a light depth map?

Each point is projected into the light camera with its projective-texture
matrix (:meth:`~morphkit.camera.CameraModel.texture_matrix`), the shadow map is
sampled at the nearest texel, and the point is shadowed when it lies farther
from the light than the stored occluder depth plus a bias.

Bias (documented once, here). A depth map stores one depth per texel; a
surface seen at an angle ``theta`` to the light direction changes depth by up
to ``texel * tan(theta)`` across one texel, so comparing a surface with its own
map entry can wrongly report a shadow ("acne"). Too large a bias makes shadows
start late ("peter-panning", visible at contact). morphkit uses

    ``bias = texel_world * (constant + slope * min(tan(theta), max_tan))``

with ``texel_world`` the size of one texel at the point's depth (``1/fx`` for an
orthographic light, ``Z/fx`` for a perspective one), default ``constant = 1.0``,
``slope = 1.0``, ``max_tan = 8``. ``theta`` comes from the surface normal when
given, otherwise ``tan(theta) = 1``. Since morphkit's maps hold the occluder only
(receivers are not drawn into them), a receiver never compares against itself:
acne can only appear in self-shadowing on the object, and contact shadows lose at
most ``bias`` of depth, i.e. about two texels.

Points outside the map's window, or behind a point light, are lit (the light
frustum is fitted to hold the whole occluder, so nothing there occludes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..settings import compile_kernel, use_compiled
from ..validate import as_finite_array

__all__ = ["ShadowBias", "shadow_visibility", "normals_from_points", "check_depth_map"]


@dataclass(frozen=True)
class ShadowBias:
    """Depth-comparison bias in units of one texel's world size (see module doc).

    Parameters
    ----------
    constant : float
        Constant term, in texel world sizes (``bias`` formula in the module docstring).
    slope : float
        Factor of ``min(tan(theta), max_tan)``, in texel world sizes.
    max_tan : float
        Cap on ``tan(theta)`` (grazing light).
    """

    constant: float = 1.0
    slope: float = 1.0
    max_tan: float = 8.0


def normals_from_points(points: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """Unit normals ``(H, W, 3)`` float32 of a grid of world points (e.g. an
    unprojected depth image), from central differences; zero where undefined.

    Oriented towards the camera that produced the grid: with image ``x`` right
    and ``y`` down (:mod:`morphkit.conventions`), ``d/dy x d/dx`` points at the
    viewer, as the normal of a visible surface does.

    Parameters
    ----------
    points : (H, W, 3) float
        World points per pixel.
    valid : (H, W) bool
        Pixels that hold a point.

    Returns
    -------
    (H, W, 3) float32
        Unit normals, world frame.
    """
    p = np.asarray(points, dtype=np.float32)
    dx = np.zeros_like(p)
    dy = np.zeros_like(p)
    dx[:, 1:-1] = p[:, 2:] - p[:, :-2]
    dy[1:-1] = p[2:] - p[:-2]
    n = np.cross(dy, dx)
    norm = np.sqrt(np.einsum("...k,...k->...", n, n))
    ok = (norm > 0) & valid
    ok[:, [0, -1]] = False
    ok[[0, -1], :] = False
    n /= np.where(ok, norm, 1.0)[..., None]
    n[~ok] = 0.0
    return n


def shadow_visibility(points: np.ndarray, depth_map: np.ndarray, light_cam: CameraModel, *,
                      normals: np.ndarray | None = None, bias: ShadowBias | None = None
                      ) -> np.ndarray:
    """Visibility ``(N,)`` float32 (1 lit, 0 shadowed) of world ``points (N, 3)``.

    Only points that project into the map's window are tested (the rest are lit).

    Parameters
    ----------
    points : (N, 3) float
        Points to test, world frame.
    depth_map : (H, W) float32
        Light-view linear depth of the occluder, ``+inf`` where empty.
    light_cam : CameraModel
        The camera ``depth_map`` was made with.
    normals : (N, 3), optional
        Unit surface normals for the slope term of the bias (zero rows: no slope info).
    bias : ShadowBias, optional
        Depth-comparison bias (None: the defaults).

    Returns
    -------
    (N,) float32
        1 where lit, 0 where shadowed.

    Raises
    ------
    ValidationError
        Points not ``(N, 3)`` finite; ``light_cam`` not a :class:`~morphkit.camera.CameraModel`;
        ``depth_map`` not a float array of the camera's shape, or holding NaN or
        ``-inf`` (NaN compares false with every depth, so it would light
        everything behind it; an integer map holds truncated depths).

    References
    ----------
    .. [1] L. Williams, "Casting Curved Shadows on Curved Surfaces", Computer Graphics (Proc. SIGGRAPH
       78), 12(3), pp. 270-274, 1978.
    .. [2] M. Segal, C. Korobkin, R. van Widenfelt, J. Foran and P. Haeberli, "Fast Shadows and Lighting
       Effects Using Texture Mapping", Computer Graphics (Proc. SIGGRAPH 92), 26(2), pp. 249-252, 1992.

    Examples
    --------
    A derivable case: a 4 x 4 orthographic light view of ``[-1, 1]^2`` from
    height 3 (2 texels per unit, so the default bias is ``1 / fx * (1 + 1) = 1``
    unit of depth), with an occluder at depth 1 (height 2) over the middle 2 x 2
    texels. A ground point under it (depth 3 > 1 + 1) is shadowed; a ground
    point beside it, and a point above the ground at depth 1.5, are lit.

    >>> import numpy as np
    >>> from morphkit.camera import look_at, orthographic
    >>> from morphkit.shadow import shadow_visibility
    >>> pose = look_at(np.array([0.0, 0.0, 3.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
    >>> light_cam = orthographic(1.0, 1.0, (4, 4), pose, znear=0.5, zfar=5.0)
    >>> depth_map = np.full((4, 4), np.inf, np.float32)
    >>> depth_map[1:3, 1:3] = 1.0
    >>> points = np.array([[0.25, 0.25, 0.0], [0.75, 0.75, 0.0], [0.25, 0.25, 1.5]])
    >>> shadow_visibility(points, depth_map, light_cam)
    array([0., 1., 1.], dtype=float32)
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    if not isinstance(light_cam, CameraModel):
        raise ValidationError(expected_got("light_cam", "a CameraModel", type(light_cam).__name__))
    dm = check_depth_map(depth_map, light_cam.shape)
    if normals is not None:
        normals = as_finite_array(normals, "normals", shape=(len(pts), 3), dtype=np.float32)
    vis = np.ones(len(pts), np.float32)
    lookup_into(vis, pts, dm, light_cam, normals, ShadowBias() if bias is None else bias)
    return vis


def check_depth_map(depth_map: np.ndarray, shape: tuple[int, int], name: str = "depth_map") -> np.ndarray:
    """Return ``depth_map`` if it is a float32/float64 ``shape`` array of depths that are
    finite or ``+inf`` (empty texels); otherwise raise :class:`~morphkit.errors.ValidationError`.

    Parameters
    ----------
    depth_map : (H, W) float32 or float64
        Linear depth, ``+inf`` background.
    shape : (H, W)
        The shape it must have.
    name : str
        Its name in the error message.

    Returns
    -------
    (H, W) numpy.ndarray
        ``depth_map`` itself.
    """
    if not isinstance(depth_map, np.ndarray):
        raise ValidationError(expected_got(name, "a numpy array", type(depth_map).__name__))
    if depth_map.dtype not in (np.float32, np.float64):
        raise ValidationError(expected_got(name, "a float32/float64 depth map", str(depth_map.dtype)))
    if depth_map.shape != tuple(shape):
        raise ValidationError(expected_got(name, f"shape {tuple(shape)} of the light camera",
                                           depth_map.shape))
    bad = int(np.count_nonzero(np.isnan(depth_map) | (depth_map == -np.inf)))
    if bad:
        raise ValidationError(expected_got(name, "finite or +inf depths", f"{bad} NaN/-inf texels"))
    return depth_map


def lookup_into(vis: np.ndarray, pts: np.ndarray, dm: np.ndarray, light_cam: CameraModel,
                normals: np.ndarray | None, b: ShadowBias) -> None:
    """Set ``vis[k] = 0`` for every shadowed point (inputs already validated).

    One compiled pass (numba) over the points; the numpy path
    (:func:`_lookup_numpy`, the reference the tests compare with) runs without
    numba or with ``MORPHKIT_WARP_NUMPY=1``.
    """
    if not use_compiled(_lookup_kernel):
        _lookup_numpy(vis, pts, dm, light_cam, normals, b)
        return
    persp = light_cam.projection == "perspective"
    L = light_cam.position if persp else np.zeros(3)
    nrm = np.zeros((0, 3), np.float32) if normals is None else np.ascontiguousarray(normals,
                                                                                    np.float32)
    _lookup_kernel(vis, np.ascontiguousarray(pts, np.float64), nrm,
                   np.ascontiguousarray(light_cam.texture_matrix(), np.float64),
                   np.ascontiguousarray(dm, np.float32), persp, float(light_cam.fx),
                   np.asarray(L, np.float64), np.asarray(light_cam.axis, np.float64),
                   float(b.constant), float(b.slope), float(b.max_tan))


def _lookup_numpy(vis: np.ndarray, pts: np.ndarray, dm: np.ndarray, light_cam: CameraModel,
                  normals: np.ndarray | None, b: ShadowBias) -> None:
    T = light_cam.texture_matrix()
    q = pts @ T[:, :3].T + T[:, 3]  # (N, 4): x w, y w, depth, w
    w = q[:, 3]
    h, wd = light_cam.shape
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.rint(q[:, 0] / w)
        r = np.rint(q[:, 1] / w)
    inside = (w > tol.SHADOW_LOOKUP_W_MIN) & (c >= 0) & (c < wd) & (r >= 0) & (r < h)
    idx = np.flatnonzero(inside)
    if len(idx) == 0:
        return
    occ = dm[r[idx].astype(np.intp), c[idx].astype(np.intp)]
    hit = np.isfinite(occ)  # texels holding the occluder
    idx, occ = idx[hit], occ[hit]
    z = q[idx, 2]
    texel = (np.abs(z) if light_cam.projection == "perspective" else 1.0) / light_cam.fx
    if normals is None:
        tan = np.ones(len(idx))
    else:
        n = normals[idx].astype(np.float64)
        if light_cam.projection == "perspective":
            to_light = light_cam.position - pts[idx]
            to_light /= np.sqrt(np.einsum("ij,ij->i", to_light, to_light))[:, None]
            cos = np.abs(np.einsum("ij,ij->i", n, to_light))
        else:
            cos = np.abs(n @ -light_cam.axis)
        has = np.einsum("ij,ij->i", n, n) > 0
        tan = np.where(has, np.sqrt(np.maximum(1 - cos**2, 0)) / np.maximum(cos, tol.SHADOW_GRAZING_COS), 1.0)
    bias_world = texel * (b.constant + b.slope * np.minimum(tan, b.max_tan))
    vis[idx[z > occ + bias_world]] = 0.0


#: The kernel's copies of the tolerances (numba freezes module globals when it compiles).
_W_MIN = tol.SHADOW_LOOKUP_W_MIN
_GRAZING_COS = tol.SHADOW_GRAZING_COS


def _lookup_loop(vis: np.ndarray, pts: np.ndarray, nrm: np.ndarray, T: np.ndarray,
                 dm: np.ndarray, persp: bool, fx: float, L: np.ndarray, axis: np.ndarray,
                 b_const: float, b_slope: float, b_max: float) -> None:
    """The per-point loop of :func:`_lookup_numpy` (same arithmetic, one pass)."""
    h, wd = dm.shape
    has_nrm = nrm.shape[0] > 0
    for k in range(pts.shape[0]):
        x, y, z0 = pts[k, 0], pts[k, 1], pts[k, 2]
        qw = T[3, 0] * x + T[3, 1] * y + T[3, 2] * z0 + T[3, 3]
        if not qw > _W_MIN:
            continue
        c = np.rint((T[0, 0] * x + T[0, 1] * y + T[0, 2] * z0 + T[0, 3]) / qw)
        r = np.rint((T[1, 0] * x + T[1, 1] * y + T[1, 2] * z0 + T[1, 3]) / qw)
        if not (c >= 0 and c < wd and r >= 0 and r < h):
            continue
        occ = np.float64(dm[int(r), int(c)])
        if not np.isfinite(occ):
            continue
        z = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z0 + T[2, 3]
        texel = (abs(z) if persp else 1.0) / fx
        tan = 1.0
        if has_nrm:
            n0, n1, n2 = np.float64(nrm[k, 0]), np.float64(nrm[k, 1]), np.float64(nrm[k, 2])
            if n0 * n0 + n1 * n1 + n2 * n2 > 0:
                if persp:
                    t0, t1, t2 = L[0] - x, L[1] - y, L[2] - z0
                    tl = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
                    cos = abs(n0 * (t0 / tl) + n1 * (t1 / tl) + n2 * (t2 / tl))
                else:
                    cos = abs(-(n0 * axis[0] + n1 * axis[1] + n2 * axis[2]))
                tan = np.sqrt(max(1 - cos * cos, 0.0)) / max(cos, _GRAZING_COS)
        if z > occ + texel * (b_const + b_slope * min(tan, b_max)):
            vis[k] = 0.0


_lookup_kernel = compile_kernel(_lookup_loop)
