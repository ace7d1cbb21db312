"""The implicit sample shapes (cow, tree, person) and their polygonisation.

Each shape is a signed field (negative inside, metres, ``+z`` up, facing
``+x``) built from smooth unions of ellipsoids, tapered capsules and cones
(:class:`ImplicitShape`, :data:`SHAPES`). :func:`polygonise` turns a shape into
a closed, normalised triangle mesh of about a requested triangle count:
scikit-image's marching cubes on a regular grid whose spacing is chosen for the
count, Taubin relaxation, Newton projection back onto the surface, and Loop
subdivision above :data:`BASE_MAX` triangles.

The default-size samples (6000 requested triangles) are not polygonised here
but read from the package data (:mod:`morphkit.meshes.samples`): they are the
meshes every stored reference image and measured figure was made with, by the
marching-tetrahedra polygoniser of earlier versions (``scripts/make_sample_meshes.py``
rebuilds them).

Polygonised by marching cubes [1]_ (scikit-image's implementation, after Lewiner et al. [2]_),
then relaxed by Taubin smoothing [3]_.

References
----------
.. [1] W. E. Lorensen and H. E. Cline, "Marching Cubes: A High Resolution 3D Surface Construction
   Algorithm", Computer Graphics (Proc. SIGGRAPH 87), 21(4), pp. 163-169, 1987.
.. [2] T. Lewiner, H. Lopes, A. W. Vieira and G. Tavares, "Efficient Implementation of Marching Cubes'
   Cases with Topological Guarantees", Journal of Graphics Tools, 8(2), pp. 1-15, 2003 (scikit-image's
   ``marching_cubes``).
.. [3] G. Taubin, "A Signal Processing Approach to Fair Surface Design", Proc. SIGGRAPH 95, pp. 351-358,
   1995 (trimesh's ``filter_taubin``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import trimesh
from skimage.measure import marching_cubes

from .. import tol
from ..errors import MeshError, expected_got
from .loading import normalize

__all__ = ["ImplicitShape", "SHAPES", "cow_field", "tree_field", "person_field", "BASE_MAX", "project",
           "polygonise"]

#: Largest triangle count polygonised directly; above it the base mesh is
#: Loop-subdivided (x4 triangles per level).
BASE_MAX = 40_000


@dataclass(frozen=True)
class ImplicitShape:
    """A closed shape given by a signed field, and the box it lies in.

    Parameters
    ----------
    field : callable
        ``(N, 3)`` points (metres) to ``(N,)`` signed values, negative inside.
    lo, hi : tuple of float
        Corners of an axis-aligned box that contains the surface with margin
        (the field is positive on its boundary).
    density : float
        Triangles times grid spacing squared that marching cubes gives for this
        shape (calibrated; only the first guess of the spacing for a count).
    """

    field: Callable[[np.ndarray], np.ndarray]
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    density: float


# --------------------------------------------------------------------------
# Signed-distance primitives
# --------------------------------------------------------------------------


def _sd_ellipsoid(p: np.ndarray, c: tuple[float, ...], r: tuple[float, ...]) -> np.ndarray:
    """Approximate signed distance to an axis-aligned ellipsoid (exact sign)."""
    rr = np.asarray(r)
    q = (p - np.asarray(c)) / rr
    k0 = np.sqrt(np.einsum("...i,...i->...", q, q))
    q1 = q / rr
    k1 = np.sqrt(np.einsum("...i,...i->...", q1, q1))
    return k0 * (k0 - 1.0) / np.maximum(k1, tol.ZERO)


def _sd_capsule(
    p: np.ndarray, a: tuple[float, ...], b: tuple[float, ...], ra: float, rb: float
) -> np.ndarray:
    """Approximate signed distance to a segment ``a``-``b`` with radius ``ra`` -> ``rb``."""
    av, bv = np.asarray(a), np.asarray(b)
    pa = p - av
    ba = bv - av
    h = np.clip(pa @ ba / (ba @ ba), 0.0, 1.0)
    d = pa - h[..., None] * ba
    return np.sqrt(np.einsum("...i,...i->...", d, d)) - (ra + (rb - ra) * h)


def _smin(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Polynomial smooth minimum (smooth union) with blend radius ``k``."""
    h = np.clip(0.5 + 0.5 * (b - a) / k, 0.0, 1.0)
    return b * (1.0 - h) + a * h - k * h * (1.0 - h)


def _sd_cone(p: np.ndarray, z0: float, z1: float, radius: float) -> np.ndarray:
    """Approximate signed distance to an upright cone about the ``z`` axis: flat base of
    ``radius`` at height ``z0``, apex at ``z1`` (exact sign)."""
    r = np.sqrt(p[..., 0] ** 2 + p[..., 1] ** 2)
    slope = radius / (z1 - z0)
    side = (r - slope * (z1 - p[..., 2])) / math.sqrt(1.0 + slope * slope)
    return np.maximum(side, z0 - p[..., 2])


# --------------------------------------------------------------------------
# The shapes
# --------------------------------------------------------------------------


def cow_field(p: np.ndarray) -> np.ndarray:
    """Signed field of the cow (negative inside), metres, facing ``+x``, ``+z`` up.

    Parameters
    ----------
    p : numpy.ndarray
        ``(..., 3)`` points, metres.

    Returns
    -------
    numpy.ndarray
        ``(...)`` signed values, negative inside (about the distance to the surface near it).
    """
    d = _sd_ellipsoid(p, (0.05, 0.0, 1.2), (0.95, 0.42, 0.42))  # barrel
    d = _smin(d, _sd_ellipsoid(p, (-0.55, 0.0, 1.22), (0.45, 0.42, 0.42)), 0.15)  # rump
    d = _smin(d, _sd_ellipsoid(p, (0.5, 0.0, 1.18), (0.45, 0.38, 0.45)), 0.15)  # chest
    d = _smin(d, _sd_capsule(p, (0.7, 0.0, 1.3), (1.15, 0.0, 1.55), 0.26, 0.17), 0.12)  # neck
    d = _smin(d, _sd_ellipsoid(p, (1.3, 0.0, 1.52), (0.28, 0.17, 0.2)), 0.08)  # head
    d = _smin(d, _sd_ellipsoid(p, (1.52, 0.0, 1.38), (0.17, 0.15, 0.14)), 0.08)  # muzzle
    for y in (-1.0, 1.0):
        d = _smin(d, _sd_ellipsoid(p, (1.2, 0.26 * y, 1.66), (0.06, 0.14, 0.06)), 0.05)  # ears
    for x in (0.55, -0.6):
        for y in (-0.22, 0.22):
            upper = _sd_capsule(p, (x, y, 1.0), (x, y, 0.45), 0.13, 0.09)
            lower = _sd_capsule(p, (x, y, 0.45), (x, y, 0.07), 0.09, 0.075)
            d = _smin(d, _smin(upper, lower, 0.05), 0.12)  # legs
    d = _smin(d, _sd_ellipsoid(p, (-0.35, 0.0, 0.82), (0.17, 0.15, 0.11)), 0.08)  # udder
    tail = _sd_capsule(p, (-0.95, 0.0, 1.45), (-1.08, 0.0, 0.78), 0.06, 0.05)
    tail = _smin(tail, _sd_ellipsoid(p, (-1.08, 0.0, 0.74), (0.08, 0.08, 0.1)), 0.04)
    return _smin(d, tail, 0.06)


def tree_field(p: np.ndarray) -> np.ndarray:
    """Signed field of the tree (negative inside), metres, ``+z`` up.

    A trunk, three stacked foliage cones (a plain union: each cone's flat base
    overhangs the cone below, with a hollow under its rim) and a low side branch
    towards ``+x`` ending in a foliage blob, plus a blob on the ``-y`` side: not
    rotationally symmetric, and from most directions one part passes in front
    of another (the branch before or behind the trunk).

    Parameters
    ----------
    p : numpy.ndarray
        ``(..., 3)`` points, metres.

    Returns
    -------
    numpy.ndarray
        ``(...)`` signed values, negative inside (about the distance to the surface near it).
    """
    d = np.maximum(_sd_capsule(p, (0.0, 0.0, -0.2), (0.0, 0.0, 2.2), 0.12, 0.07), -p[..., 2])  # trunk
    for z0, z1, radius in ((0.7, 1.9, 0.8), (1.3, 2.5, 0.65), (1.9, 3.0, 0.48)):
        d = np.minimum(d, _sd_cone(p, z0, z1, radius))  # foliage layers
    branch = _sd_capsule(p, (0.0, 0.0, 0.3), (0.55, 0.2, 0.5), 0.06, 0.045)
    branch = _smin(branch, _sd_ellipsoid(p, (0.68, 0.25, 0.52), (0.24, 0.2, 0.17)), 0.05)
    d = _smin(d, branch, 0.04)
    return np.minimum(d, _sd_ellipsoid(p, (0.05, -0.6, 1.25), (0.22, 0.2, 0.18)))  # side blob


def person_field(p: np.ndarray, shoulder_joints: bool = True) -> np.ndarray:
    """Signed field of a walking person (negative inside), metres, facing ``+x``, ``+z`` up.

    Torso, pelvis, neck and head; the left leg (``+y``) steps forward, the right
    leg back; the arms swing opposite to the legs and hang clear of the torso
    (a gap of a few centimetres), so from the side the far arm and leg pass
    behind the near ones and the torso.

    Parameters
    ----------
    p : numpy.ndarray
        ``(..., 3)`` points, metres.
    shoulder_joints : bool, optional
        Join each arm to the torso by a thin rod (without it the arm hangs ~1 cm
        off the torso at ``x = 0``: a gap that coarse grids bridge and fine ones
        do not). ``False`` is the field of morphkit <= 0.1.0, the one the stored
        person was made with (``scripts/make_sample_meshes.py``).

    Returns
    -------
    numpy.ndarray
        ``(...)`` signed values, negative inside (about the distance to the surface near it).
    """
    d = _sd_ellipsoid(p, (0.0, 0.0, 1.27), (0.13, 0.2, 0.28))  # torso
    d = _smin(d, _sd_ellipsoid(p, (0.0, 0.0, 0.96), (0.12, 0.17, 0.13)), 0.06)  # pelvis
    d = _smin(d, _sd_capsule(p, (0.0, 0.0, 1.5), (0.01, 0.0, 1.62), 0.05, 0.045), 0.04)  # neck
    d = _smin(d, _sd_ellipsoid(p, (0.02, 0.0, 1.72), (0.1, 0.09, 0.12)), 0.03)  # head
    d = _smin(d, _sd_ellipsoid(p, (0.11, 0.0, 1.7), (0.03, 0.025, 0.035)), 0.02)  # nose
    legs = (  # hip, knee, ankle, toe
        ((0.0, 0.095, 0.92), (0.17, 0.1, 0.52), (0.13, 0.1, 0.08), (0.3, 0.1, 0.04)),
        ((0.0, -0.095, 0.92), (-0.1, -0.1, 0.5), (-0.26, -0.1, 0.12), (-0.13, -0.1, 0.03)),
    )
    for hip, knee, ankle, toe in legs:
        leg = _smin(_sd_capsule(p, hip, knee, 0.085, 0.06), _sd_capsule(p, knee, ankle, 0.058, 0.045), 0.02)
        leg = _smin(leg, _sd_capsule(p, ankle, toe, 0.045, 0.035), 0.02)
        d = _smin(d, leg, 0.03)
    arms = (  # shoulder, elbow, hand: the right arm (-y) swings forward, the left back
        ((0.0, -0.24, 1.47), (0.1, -0.29, 1.2), (0.27, -0.29, 1.03)),
        ((0.0, 0.24, 1.47), (-0.1, 0.29, 1.2), (-0.22, 0.3, 1.0)),
    )
    for shoulder, elbow, hand in arms:
        arm = _smin(_sd_capsule(p, shoulder, elbow, 0.055, 0.045), _sd_capsule(p, elbow, hand, 0.045, 0.04),
                    0.015)
        arm = _smin(arm, _sd_ellipsoid(p, hand, (0.05, 0.035, 0.06)), 0.015)
        d = _smin(d, arm, 0.025)
    if shoulder_joints:  # without them the person falls apart into 2-3 bodies above ~10k faces
        for shoulder, _elbow, _hand in arms:
            d = np.minimum(d, _sd_capsule(p, (0.0, 0.7 * shoulder[1], shoulder[2]), shoulder, 0.03, 0.03))
    return d


#: The implicit samples by name. Boxes in metres (before normalisation);
#: densities calibrated for marching cubes (triangles x spacing^2).
SHAPES: dict[str, ImplicitShape] = {
    "cow": ImplicitShape(cow_field, (-1.35, -0.65, -0.2), (1.9, 0.65, 2.0), 23.0),
    "tree": ImplicitShape(tree_field, (-1.0, -1.0, -0.15), (1.15, 1.0, 3.1), 29.5),
    "person": ImplicitShape(person_field, (-0.45, -0.5, -0.12), (0.55, 0.5, 1.95), 5.4),
}


# --------------------------------------------------------------------------
# Polygonisation
# --------------------------------------------------------------------------


def project(field: Callable[[np.ndarray], np.ndarray], v: np.ndarray, steps: int = 2) -> np.ndarray:
    """Move points onto the zero set of ``field`` by Newton steps along the gradient.

    Parameters
    ----------
    field : callable
        ``(N, 3)`` points to ``(N,)`` signed values.
    v : numpy.ndarray
        ``(N, 3)`` points near the surface.
    steps : int, optional
        Newton steps (central-difference gradient, step ``tol.SDF_GRADIENT_STEP``).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` points on (or much nearer) the zero set.
    """
    d = tol.SDF_GRADIENT_STEP
    for _ in range(steps):
        f0 = field(v)
        g = np.stack(
            [(field(v + d * e) - field(v - d * e)) / (2 * d) for e in np.eye(3)], axis=1
        )
        g2 = np.maximum(np.einsum("ij,ij->i", g, g), tol.SDF_GRADIENT_FLOOR)
        v = v - (f0 / g2)[:, None] * g
    return v


def _marching_cubes(shape: ImplicitShape, h: float) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices, faces)`` of ``field < 0`` on a grid of spacing ``h``, wound outwards."""
    lo, hi = np.asarray(shape.lo, dtype=np.float64), np.asarray(shape.hi, dtype=np.float64)
    n = np.maximum(2, np.ceil((hi - lo) / h).astype(int) + 1)
    axes = [lo[k] + h * np.arange(n[k]) for k in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    f = shape.field(pts.reshape(-1, 3)).reshape(pts.shape[:3])
    if min(f[0].min(), f[-1].min(), f[:, 0].min(), f[:, -1].min(), f[:, :, 0].min(), f[:, :, -1].min()) <= 0:
        raise MeshError(expected_got("implicit surface", "inside the sampling box", "a clipped surface"))
    # gradient_direction="descent" (the default): the field decreases into the
    # object, and the triangles' normals point out of it (a test checks the volume's sign)
    verts, faces, _normals, _values = marching_cubes(f, 0.0, spacing=(h, h, h), allow_degenerate=False)
    return verts + lo, np.asarray(faces, dtype=np.int64)


def _base(shape: ImplicitShape, target: int) -> trimesh.Trimesh:
    """Polygonise ``shape`` with about ``target`` triangles (within ~8%): the shape's density
    gives the first grid spacing, up to three secant steps on the spacing refine the count."""
    h = math.sqrt(shape.density / target)
    verts, faces = _marching_cubes(shape, h)
    for _ in range(3):
        if abs(len(faces) / target - 1.0) < 0.08:
            break
        h *= math.sqrt(len(faces) / target)
        verts, faces = _marching_cubes(shape, h)
    mesh = trimesh.Trimesh(verts, faces, process=False)
    trimesh.smoothing.filter_taubin(mesh, iterations=40)  # relax marching-cubes slivers
    mesh.vertices = project(shape.field, np.asarray(mesh.vertices))
    return mesh


def polygonise(shape: ImplicitShape, faces: int) -> trimesh.Trimesh:
    """The normalised closed mesh of ``shape`` with about ``faces`` triangles.

    Polygonised directly up to :data:`BASE_MAX` triangles; above that ``faces /
    4^k`` triangles and ``k`` levels of Loop subdivision (each x4, keeps the mesh
    closed and smooth).

    Parameters
    ----------
    shape : ImplicitShape
        The shape (one of :data:`SHAPES`).
    faces : int
        Requested triangle count (the result is within about 10%).

    Returns
    -------
    trimesh.Trimesh
        The normalised, watertight mesh, wound outwards.
    """
    k = 0
    while faces / 4**k > BASE_MAX:
        k += 1
    mesh = _base(shape, round(faces / 4**k))
    if k:
        v, f = trimesh.remesh.subdivide_loop(mesh.vertices, mesh.faces, iterations=k)
        mesh = trimesh.Trimesh(v, f, process=False)
    return normalize(mesh)
