"""Built-in sample meshes (the papers' test set).

All meshes returned by this module are **normalised** (see
:func:`~morphkit.meshes.loading.normalize`):
uniformly scaled so that the largest bounding-box extent is 1.0 scene unit,
centred on the origin in ``x`` and ``y`` and resting on the ground plane
(``min z = 0``). The world is ``+z`` up (:mod:`morphkit.conventions`); the
samples are upright and face ``+x`` (the teapot's spout, the cow's head and the
front edge of the chair seat point towards ``+x``).

Samples
-------
``teapot``
    Newell's Utah teapot, tessellated from its original 32 bicubic Bezier
    patches (306 control vertices; public domain). Open surface: the rim and
    the lid are separate, the spout and handle pierce the body, the spout tip
    and the ends of the handle and spout are open. About 1k-6k triangles.
``chair``
    A slatted chair made of closed boxes (seat, four legs, two back posts, a top
    rail and vertical back slats with open gaps between them). About 1.5k
    triangles.
``cow``
    A watertight, genus-0-like organic cow (body, neck, head with muzzle, ears,
    four legs, udder, tail) polygonised from a smooth implicit surface; its
    triangle count follows the ``faces`` parameter from ~6k to ~1M (and more).
``tree``
    A watertight tree: trunk, three stacked foliage cones overhanging each
    other, a low side branch with a foliage blob; ``faces`` like the cow.
``person``
    A watertight walking person (head, torso, arms and legs in mid-stride,
    limbs clear of the torso, so they pass behind each other seen from the
    side); ``faces`` like the cow.

The first three are :data:`SAMPLE_MESHES`; all five are :data:`BILLBOARD_MESHES`.

The cow, tree and person are implicit shapes (:mod:`morphkit.meshes.implicit`);
at their default size (6000 requested triangles, the size every demo, test
reference and measured figure uses) they are read from the package data
(``morphkit/data/<name>_6000.npz``), any other size is polygonised on demand.

Built meshes are cached per parameter set (one :class:`~morphkit.memo.Memo`);
every call returns a fresh copy that the caller may modify.

The teapot's history and data: Crow [1]_.

References
----------
.. [1] F. C. Crow, "The Origins of the Teapot", IEEE Computer Graphics and Applications, 7(1), pp. 8-19,
   1987 (Newell's 1975 Bezier-patch teapot).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from .. import tol
from ..errors import ValidationError, expected_got
from ..memo import Memo
from ..validate import as_flag, as_int
from .implicit import SHAPES, polygonise
from .loading import normalize

__all__ = [
    "SAMPLE_MESHES",
    "teapot",
    "chair",
    "cow",
    "tree",
    "person",
    "BILLBOARD_MESHES",
    "sample_mesh",
    "teapot_face_count",
    "STORED_FACES",
    "clear_cache",
    "SAMPLE_FILES",
    "sample_file",
]

#: The papers' test set (the shadow and view-morphing demos and benches iterate these).
SAMPLE_MESHES: tuple[str, ...] = ("teapot", "chair", "cow")

#: The billboard subjects: the papers' set plus a tree and a person. Every name
#: here is accepted by :func:`sample_mesh`.
BILLBOARD_MESHES: tuple[str, ...] = SAMPLE_MESHES + ("tree", "person")


#: Built samples, by builder and arguments (a 1M-face cow holds ~60 MB).
_BUILT: Memo[Hashable, trimesh.Trimesh] = Memo(maxsize=12)


#: Package data read once (the teapot's control nets).
_DATA: Memo[str, np.ndarray] = Memo(maxsize=None)


def _built(key: Hashable, make: Callable[[], trimesh.Trimesh]) -> trimesh.Trimesh:
    """A copy of the sample cached under ``key`` (made by ``make`` on first use): the cache stays pristine."""
    return _BUILT.get(key, make).copy()


def clear_cache() -> None:
    """Forget every built sample (the next call of a builder builds it again).

    Returns
    -------
    None
    """
    _BUILT.clear()


# --------------------------------------------------------------------------
# Teapot
# --------------------------------------------------------------------------

# Newell's teapot (1975), public domain: its 32 patches (16 one-based indices
# into the 306 control vertices each) are the package data files
# ``morphkit/data/teapot_patches.txt`` and ``teapot_vertices.txt``.


def _teapot_control_points() -> np.ndarray:
    """Return the ``(32, 4, 4, 3)`` control nets of the teapot's patches (read-only; read once)."""
    return _DATA.get("teapot", _read_teapot)


def _read_teapot() -> np.ndarray:
    """Read the teapot's control nets from the package data."""
    data = resources.files("morphkit") / "data"
    with (data / "teapot_patches.txt").open() as f:
        patches = np.loadtxt(f, dtype=np.int64).reshape(32, 16) - 1
    with (data / "teapot_vertices.txt").open() as f:
        verts = np.loadtxt(f, dtype=np.float64).reshape(306, 3)
    cp = verts[patches].reshape(32, 4, 4, 3)
    cp.flags.writeable = False
    return cp


def teapot_face_count(resolution: int, flange: bool = True) -> int:
    """Return the number of triangles :func:`teapot` builds at ``resolution``.

    Each of the 32 patches gives ``2 * resolution**2`` triangles; the 8 patches
    that meet at the lid and bottom poles lose the ``resolution`` triangles that
    collapse to the pole: ``64 r^2 - 8 r``; the lid flange adds ``32 r``.

    Parameters
    ----------
    resolution : int
        Grid cells per patch side, as for :func:`teapot`.
    flange : bool, optional
        Whether the lid flange is counted.

    Returns
    -------
    int
        The triangle count.
    """
    r = as_int(resolution, "resolution", lo=2, hi=64)
    return 64 * r * r - 8 * r + (32 * r if flange else 0)


def teapot(resolution: int = 8, flange: bool = True) -> trimesh.Trimesh:
    """Return Newell's Utah teapot tessellated from its 32 Bezier patches.

    Every bicubic patch is evaluated on a ``(resolution + 1)^2`` grid of
    parameter values and split into ``2 * resolution^2`` triangles. Vertices
    shared by neighbouring patches are merged, the triangles that collapse at
    the lid and bottom poles are removed, and the triangles are wound so that
    their normals point out of the teapot (the patch data is consistently
    oriented; a test checks this with ray casts).

    Triangle counts (``64 r^2 - 8 r`` patches, plus ``32 r`` with the flange;
    see :func:`teapot_face_count`):

    ==========  =========  ============
    resolution  triangles  with flange
    ==========  =========  ============
    4           992        1120
    6           2256       2448
    8           4032       4288
    10          6320       6640
    ==========  =========  ============

    The surface is open, as in Newell's data: the lid is a separate piece
    resting in the rim, the handle and spout are open tubes that pierce the
    body, and the spout tip is open. It is a closed *bottom* version (the
    4 bottom patches are included). Proportions after :func:`normalize`:
    the handle-to-spout length (``x``) is 1.0, the depth (``y``, the body's
    diameter) 0.622 and the height (``z``) 0.490, i.e. about 6.43 : 4.0 : 3.15
    in the data's units. The data carries Jim Blinn's vertical 1/1.3 squash,
    so the pot is flatter than the real one (body diameter : height = 1.27).

    Parameters
    ----------
    resolution : int, default 8
        Segments per patch edge, in ``[2, 64]``.
    flange : bool, default True
        Close the ring-shaped gap between lid (radius 1.3) and rim (radius 1.4)
        with an annulus of ``32 * resolution`` triangles (not counted by
        :func:`teapot_face_count`), so overhead lights cast a solid shadow.
        ``False`` gives Newell's surface exactly.

    Returns
    -------
    trimesh.Trimesh
        The normalised teapot, lid up (``+z``), spout towards ``+x``.
    """
    r = as_int(resolution, "resolution", lo=2, hi=64)
    closed = as_flag(flange, "flange")
    return _built(("teapot", r, closed), lambda: _teapot(r, closed))


def _teapot(r: int, flange: bool) -> trimesh.Trimesh:
    """Build :func:`teapot` (checked arguments)."""
    cp = _teapot_control_points()
    t = np.linspace(0.0, 1.0, r + 1)
    basis = np.stack([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t**2 * (1 - t), t**3], axis=1)
    grid = np.einsum("ui,vj,pijk->puvk", basis, basis, cp)  # (32, r+1, r+1, 3)
    idx = np.arange((r + 1) ** 2).reshape(r + 1, r + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    # (a, c, b) / (a, d, c): with the data's (u, v) order this winds outwards.
    quad = np.concatenate([np.stack([a, c, b], axis=1), np.stack([a, d, c], axis=1)])
    faces = (quad[None] + (np.arange(32) * (r + 1) ** 2)[:, None, None]).reshape(-1, 3)
    verts = grid.reshape(-1, 3)
    if flange:
        # Newell's lid ends at radius 1.3 and the body's rim starts at 1.4, both
        # at z = 2.4: from above, light shines through a ring that the physical
        # teapot (whose lid rests on the rim) does not have. Close it with an
        # annulus at the rim's height.
        n = 16 * r
        ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
        ring = np.concatenate([np.c_[rad * np.cos(ang), rad * np.sin(ang), np.full(n, 2.4)]
                               for rad in (1.3, 1.4)])
        k = np.arange(n)
        k1 = (k + 1) % n
        ann = np.concatenate([np.c_[k, n + k, n + k1], np.c_[k, n + k1, k1]]) + len(verts)
        verts = np.concatenate([verts, ring])
        faces = np.concatenate([faces, ann])  # normals up (+z), out of the pot
    mesh = trimesh.Trimesh(verts, faces, process=False)
    mesh.merge_vertices()
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return normalize(mesh)


# --------------------------------------------------------------------------
# Chair
# --------------------------------------------------------------------------

#: Target edge length (metres, before normalisation) of the chair's box grids;
#: chosen so that the default chair has about 1.5k triangles.
_CHAIR_CELL = 0.045


def _grid_box(lo: np.ndarray, hi: np.ndarray, cell: float) -> trimesh.Trimesh:
    """Return the closed box ``[lo, hi]`` whose faces are grids of cells <= ``cell``."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    counts = np.maximum(1, np.ceil((hi - lo) / cell - tol.REL_EQUAL)).astype(int)
    axes = [np.linspace(lo[k], hi[k], counts[k] + 1) for k in range(3)]
    verts: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    offset = 0
    for axis, (u, v), sign in ((0, (1, 2), 1), (1, (0, 2), -1), (2, (0, 1), 1)):
        # sign: direction of e_u x e_v along the box axis.
        uu, vv = np.meshgrid(axes[u], axes[v], indexing="ij")
        idx = np.arange(uu.size).reshape(uu.shape)
        a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
        c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
        for side, value in ((-1, lo[axis]), (1, hi[axis])):
            pts = np.empty(uu.shape + (3,))
            pts[..., u], pts[..., v], pts[..., axis] = uu, vv, value
            if sign * side > 0:
                f = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
            else:
                f = np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])
            verts.append(pts.reshape(-1, 3))
            faces.append(f + offset)
            offset += uu.size
    box = trimesh.Trimesh(np.concatenate(verts), np.concatenate(faces), process=False)
    box.merge_vertices()  # shared box edges come from the same linspace values
    return box


def chair(slats: int = 3) -> trimesh.Trimesh:
    """Return a slatted chair: seat, four legs, back posts, top rail and slats.

    The chair is a concatenation of closed boxes (no boolean union: boxes
    touch and overlap, e.g. the back posts run through the seat), each box
    face subdivided into a grid so that the default chair has about 1.5k
    triangles (1472 with 3 slats). The back has ``slats`` vertical slats
    between the seat and the top rail, separated by ``slats + 1`` open gaps
    as wide as a slat: light passes between the slats.

    Dimensions before normalisation (metres): seat 0.45 x 0.45 at height
    0.45, back posts 0.95 tall. The seat's front edge faces ``+x``; the back
    is at ``-x``; slats and gaps alternate along ``y``.

    Parameters
    ----------
    slats : int, default 3
        Number of back slats, in ``[1, 8]``.

    Returns
    -------
    trimesh.Trimesh
        The normalised chair, standing on its legs (``+z`` up).
    """
    n = as_int(slats, "slats", lo=1, hi=8)
    return _built(("chair", n), lambda: _chair(n))


def _chair(n: int) -> trimesh.Trimesh:
    """Build :func:`chair` (checked arguments)."""
    w, s, t = 0.45, 0.04, 0.02  # seat width, leg/post side, slat thickness
    h0, h1 = 0.43, 0.47  # seat bottom and top
    top0, top1 = 0.87, 0.95  # top rail
    e = w / 2
    parts = [((-e, -e, h0), (e, e, h1))]  # seat
    for y0 in (-e, e - s):
        parts.append(((e - s, y0, 0.0), (e, y0 + s, h0)))  # front legs
        parts.append(((-e, y0, 0.0), (-e + s, y0 + s, top1)))  # back legs + posts
    inner = w - 2 * s  # free width between the posts
    parts.append(((-e, -e + s, top0), (-e + 0.03, e - s, top1)))  # top rail
    width = inner / (2 * n + 1)  # slats and gaps equally wide
    x0 = -e + 0.005
    for i in range(n):
        y0 = -e + s + (2 * i + 1) * width
        parts.append(((x0, y0, h1), (x0 + t, y0 + width, top0)))
    boxes = [_grid_box(np.array(lo), np.array(hi), _CHAIR_CELL) for lo, hi in parts]
    return normalize(trimesh.util.concatenate(boxes))


# --------------------------------------------------------------------------
# Cow, tree and person: implicit shapes, stored at their default size
# --------------------------------------------------------------------------

#: The requested triangle count of the implicit samples' default size: these
#: meshes are package data (``morphkit/data/<name>_6000.npz``, made by the
#: marching-tetrahedra polygoniser of earlier versions, ``scripts/make_sample_meshes.py``),
#: so the stored reference images and measured figures keep their meshes exactly.
STORED_FACES = 6000


def _stored(name: str) -> trimesh.Trimesh:
    """The stored default-size implicit sample ``name`` (normalised, watertight)."""
    with (resources.files("morphkit") / "data" / f"{name}_{STORED_FACES}.npz").open("rb") as f:
        data = np.load(f)
        verts, faces = data["vertices"], data["faces"].astype(np.int64)
    return trimesh.Trimesh(verts, faces, process=False)


def _implicit(name: str, faces: Any) -> trimesh.Trimesh:
    """The implicit sample ``name`` with about ``faces`` triangles (stored or polygonised), cached."""
    n = as_int(faces, "faces", lo=4000, hi=4_000_000)
    make = (lambda: _stored(name)) if n == STORED_FACES else (lambda: polygonise(SHAPES[name], n))
    return _built((name, n), make)


def cow(faces: int = STORED_FACES) -> trimesh.Trimesh:
    """Return a watertight cow with about ``faces`` triangles.

    The cow is a smooth union of ellipsoids and tapered capsules (barrel,
    rump, chest, neck, head, muzzle, ears, four two-segment legs, udder and a
    tail with a tuft; :data:`morphkit.meshes.implicit.SHAPES`). The default
    size is the stored mesh (5740 triangles; :data:`STORED_FACES`); any other
    count is polygonised by :func:`morphkit.meshes.implicit.polygonise`:
    marching cubes on a regular grid whose spacing is chosen for the requested
    count, Taubin relaxation and projection back onto the implicit surface;
    counts above 40k are reached by polygonising ``faces / 4^k`` triangles and
    applying ``k`` levels of Loop subdivision (each x4), which keeps the mesh
    closed and smooth. The result is deterministic and within about 10% of
    ``faces`` (the tests allow 30%).

    Build times grow about linearly with ``faces`` (``morphkit bench render``
    builds the sizes it renders). Built meshes are cached (the 12 most recent
    samples); each call returns a copy.

    Parameters
    ----------
    faces : int, default 6000
        Requested triangle count, in ``[4000, 4_000_000]``.

    Returns
    -------
    trimesh.Trimesh
        The normalised, watertight cow standing on its legs (``+z`` up),
        head towards ``+x``.
    """
    return _implicit("cow", faces)


def tree(faces: int = STORED_FACES) -> trimesh.Trimesh:
    """Return a watertight, non-convex tree with about ``faces`` triangles.

    A trunk, three stacked rounded foliage cones (each overhanging the next
    lower one), a side branch towards ``+x`` with a foliage blob at its end and
    a foliage blob on the ``-y`` side; stored at the default size (5976
    triangles), polygonised like :func:`cow` at any other; deterministic,
    within about 10% of ``faces``.
    Meant as a billboard subject: not rotationally symmetric, so its views
    change with the azimuth.

    Parameters
    ----------
    faces : int, default 6000
        Requested triangle count, in ``[4000, 4_000_000]``.

    Returns
    -------
    trimesh.Trimesh
        The normalised tree (its height is the largest extent, 1.0), branch towards ``+x``.
    """
    return _implicit("tree", faces)


def person(faces: int = STORED_FACES) -> trimesh.Trimesh:
    """Return a watertight walking person with about ``faces`` triangles.

    Head, neck, torso, pelvis, two arms and two legs (with feet) in mid-stride,
    facing ``+x``: the left leg (``+y``) forward and the right back, the arms
    swinging the other way and hanging clear of the torso. Seen from the side,
    the far arm and leg pass behind the torso and the near limbs -- the case a
    single morph mesh cannot follow (depth layers can). Stored at the default
    size (5640 triangles), polygonised like :func:`cow` at any other;
    deterministic, within about 10% of ``faces``.

    Parameters
    ----------
    faces : int, default 6000
        Requested triangle count, in ``[4000, 4_000_000]``.

    Returns
    -------
    trimesh.Trimesh
        The normalised person (height 1.0), standing on the ground, facing ``+x``.
    """
    return _implicit("person", faces)


_BUILDERS: dict[str, Callable[..., trimesh.Trimesh]] = {"teapot": teapot, "chair": chair, "cow": cow,
                                                        "tree": tree, "person": person}


def sample_mesh(name: str, **kw: Any) -> trimesh.Trimesh:
    """Return the built-in sample mesh ``name`` (one of :data:`BILLBOARD_MESHES`).

    Parameters
    ----------
    name : str
        ``"teapot"``, ``"chair"``, ``"cow"``, ``"tree"`` or ``"person"``.
    **kw
        Passed to the builder (:func:`teapot`, :func:`chair`, :func:`cow`,
        :func:`tree`, :func:`person`).

    Returns
    -------
    trimesh.Trimesh
        A normalised copy of the sample.

    Raises
    ------
    ValidationError
        If ``name`` is not a known sample or ``kw`` does not fit the builder.

    Examples
    --------
    The teapot with each of its 32 patches cut into 4 x 4 cells gives
    :func:`teapot_face_count` triangles, normalised to length 1 (spout to
    handle, along ``x``) and standing on ``z = 0``.

    >>> from morphkit.meshes import sample_mesh, teapot_face_count
    >>> pot = sample_mesh("teapot", resolution=4)
    >>> len(pot.faces) == teapot_face_count(4), len(pot.faces)
    (True, 1120)
    >>> pot.bounds[:, 0], float(pot.bounds[0, 2])
    (array([-0.5,  0.5]), 0.0)
    """
    if name not in _BUILDERS:
        raise ValidationError(expected_got("sample mesh name", f"one of {list(BILLBOARD_MESHES)}",
                                           repr(name)))
    try:
        return _BUILDERS[name](**kw)
    except TypeError as exc:
        raise ValidationError(
            expected_got(f"arguments of sample {name!r}", "keywords the builder accepts", str(exc))
        ) from exc


#: The mesh files shipped in ``morphkit/data`` (licences in ``morphkit/data/LICENSES.md``):
#: ``photo_crate.glb``, a crate textured with a public-domain photograph (NASA's astronaut),
#: ``+y`` up as glTF is.
SAMPLE_FILES: tuple[str, ...] = ("photo_crate.glb",)


def sample_file(name: str) -> Path:
    """The path of a mesh file shipped with morphkit (one of :data:`SAMPLE_FILES`), to load as
    a user's own file is loaded (:func:`~morphkit.meshes.loading.load_mesh`).

    Parameters
    ----------
    name : str
        The file's name, e.g. ``"photo_crate.glb"``.

    Returns
    -------
    pathlib.Path
        The file in the installed package.

    Raises
    ------
    ValidationError
        ``name`` is not one of :data:`SAMPLE_FILES`.

    Examples
    --------
    The photo-textured crate, loaded with its texture and turned ``+z`` up, normalised to size 1:

    >>> from morphkit.meshes import load_mesh, sample_file
    >>> crate = load_mesh(sample_file("photo_crate.glb"))
    >>> crate.visual.kind, round(float(crate.extents.max()), 6)
    ('texture', 1.0)
    """
    if name not in SAMPLE_FILES:
        raise ValidationError(expected_got("sample file name", f"one of {list(SAMPLE_FILES)}", repr(name)))
    return Path(str(resources.files("morphkit") / "data" / name))
