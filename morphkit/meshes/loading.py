"""Mesh loading and validation: the user's meshes, checked and normalised.

Every mesh morphkit draws passes :func:`check_mesh`; :func:`load_mesh` reads a
file and :func:`normalize` scales it to the package's unit size: uniformly
scaled so that the largest bounding-box extent is 1.0 scene unit, centred on the
origin in ``x`` and ``y`` and resting on the ground plane (``min z = 0``).
Normalising moves vertices only: a mesh's visuals (textures, UVs, vertex and
face colours, materials) are kept.

Up axis of mesh files
---------------------
morphkit's world is ``+z`` up (:mod:`morphkit.conventions`). A file whose up is
``+y`` is turned on load by ``+90`` degrees about ``x`` (:data:`Y_UP_TO_Z_UP`:
``(x, y, z) -> (x, -z, y)``, a rotation, so handedness is kept and glTF's front
``+z`` becomes ``-y``, as Blender imports it). ``load_mesh(path, up=...)`` takes
``"z"``, ``"y"`` or ``"auto"``, the format's documented default (the one table;
:func:`resolve_up` gives it for a path, for recording in asset files):

=====================  ======  ==========================================
format (extension)     auto    why
=====================  ======  ==========================================
glTF (``.gltf/.glb``)  ``y``   ``+y`` up by the glTF 2.0 specification
OBJ (``.obj``)         ``y``   most exporters (Blender, Maya, 3ds Max
                               export default) write ``+y`` up
every other format     ``z``   PLY, STL, OFF, ... carry no convention;
                               scans and CAD files are mostly ``+z`` up
=====================  ======  ==========================================

trimesh does not turn glTF files itself (it applies their node transforms only).

Looks and multi-part files
--------------------------
A file's visuals are loaded as trimesh reads them (``TextureVisuals`` with UVs
and a ``PBRMaterial`` for glTF, a ``SimpleMaterial`` for OBJ/MTL, ``ColorVisuals``
for PLY vertex or face colours) and kept. A file of several parts (a glTF scene,
an OBJ with several materials) becomes one mesh: node transforms applied, parts
merged (in the order of their node names) by
:func:`morphkit.meshes.parts.merge_parts`, which keeps each part's look in one
atlas material. A mesh with both vertex colours and a texture (glTF ``COLOR_0``
with a textured material) keeps both (trimesh puts the colours in
``visual.vertex_attributes["color"]``); the renderer multiplies them. An OBJ whose
``mtllib`` or ``map_Kd`` file is missing loads with an
:class:`~morphkit.errors.AssetWarning`: the material keeps its ``Kd`` colour (trimesh
drops the missing image silently); so does a ``.gltf`` whose external image is missing
(its materials keep their ``baseColorFactor``). The same fallback, with the same warning
naming the file, the texture and why, holds for a texture that is there but cannot be drawn:
unreadable, empty, not an image, or damaged (every image, a file or one a glTF holds in a
data URI or a buffer view, is decoded whole before the load,
:func:`morphkit.meshes.texture.image_problem`; trimesh drops one it cannot open without a word, and
a damaged one failed only when first drawn), and for a ``map_Kd`` image found but not taken
by trimesh's OBJ reader (a line with options). Every file a mesh file refers to is read through
:mod:`morphkit.meshes.assets`: from inside the asset root only (default the file's folder; one
outside it is not opened, with an :class:`~morphkit.errors.AssetWarning`) and only if it is a
regular file (a FIFO is a :class:`~morphkit.errors.MeshError` before any read). Vertices are
merged where position and UV agree (OBJ/STL split them), except on meshes with vertex colours
(left as stored).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import IO, Any

import numpy as np
import trimesh

from .. import settings, tol
from ..errors import AssetWarning, MeshError, expected_got
from . import assets, gltf
from .assets import AssetResolver, locate, read_regular
from .parts import copy_with_look, merge_parts, scene_parts
from .texture import image_problem

__all__ = ["normalize", "check_mesh", "closed_volume", "load_mesh", "resolve_up", "gltf_warnings",
           "trimesh_load", "loaded_looks", "check_parts", "UP_AXES",
           "UP_AXIS_BY_FORMAT", "Y_UP_TO_Z_UP"]

#: The up axes :func:`load_mesh` accepts besides ``"auto"``.
UP_AXES = ("z", "y")

#: ``up="auto"`` per file extension (lower case, no dot); every other extension is ``"z"``.
UP_AXIS_BY_FORMAT: dict[str, str] = {"gltf": "y", "glb": "y", "obj": "y"}

#: 4x4 rotation turning a ``+y``-up file into morphkit's ``+z``-up world (+90 deg about x).
Y_UP_TO_Z_UP: np.ndarray = np.array([[1.0, 0.0, 0.0, 0.0],
                                     [0.0, 0.0, -1.0, 0.0],
                                     [0.0, 1.0, 0.0, 0.0],
                                     [0.0, 0.0, 0.0, 1.0]])
Y_UP_TO_Z_UP.setflags(write=False)


# --------------------------------------------------------------------------
# Normalisation
# --------------------------------------------------------------------------


def normalize(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Return a normalised copy of ``mesh``: unit size, centred, on the ground.

    The copy is scaled uniformly so that the largest axis-aligned bounding-box
    extent is 1.0 scene unit, translated so that the bounding box is centred on
    the origin in ``x`` and ``y``, and translated in ``z`` so that its lowest
    vertex lies on the ground plane (``min z = 0``). The orientation is kept:
    the world is ``+z`` up (:mod:`morphkit.conventions`).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Mesh with at least one face and finite vertices. It is not modified.

    Returns
    -------
    trimesh.Trimesh
        The normalised copy.

    Raises
    ------
    MeshError
        If ``mesh`` is not a ``trimesh.Trimesh``, has no faces, has non-finite
        vertices or a bounding box smaller than ``tol.MIN_EXTENT``.

    Examples
    --------
    A 2 x 4 x 1 box centred on the origin becomes 0.5 x 1 x 0.25 (its longest
    side, ``y``, is 1), centred in ``x`` and ``y``, on the ground.

    >>> import trimesh
    >>> from morphkit.meshes import normalize
    >>> normalize(trimesh.creation.box(extents=(2.0, 4.0, 1.0))).bounds
    array([[-0.25, -0.5 ,  0.  ],
           [ 0.25,  0.5 ,  0.25]])
    """
    check_mesh(mesh, "mesh")
    out = copy_with_look(mesh)
    lo, hi = out.bounds
    extent = float(np.max(hi - lo))
    if not extent > tol.MIN_EXTENT:
        raise MeshError(
            expected_got("mesh", f"a bounding box larger than {tol.MIN_EXTENT}", f"extent {extent}")
        )
    centre = np.array([(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0, lo[2]])
    out.apply_translation(-centre)
    out.apply_scale(1.0 / extent)
    # Exact ground contact and centring despite rounding in the two steps above.
    lo, hi = out.bounds
    out.apply_translation([-(lo[0] + hi[0]) / 2.0, -(lo[1] + hi[1]) / 2.0, -lo[2]])
    return out


def check_mesh(mesh: Any, name: str) -> trimesh.Trimesh:
    """Check that ``mesh`` is a triangle mesh morphkit can draw, and return it unchanged.

    Every entry point that takes a user's mesh calls this first (:func:`load_mesh`,
    :func:`normalize`, :func:`morphkit.shadow.bake_atlas`, ...), so a bad mesh is a
    :class:`~morphkit.errors.MeshError` naming what is wrong, never a raw
    ``TypeError``/``IndexError`` later, nor an empty result (an all-collinear mesh
    bakes an empty shadow atlas).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh (any frame; not modified).
    name : str
        How the error message names it (``"mesh"``, ``"mesh file 'x.obj'"``).

    Returns
    -------
    trimesh.Trimesh
        ``mesh`` itself.

    Raises
    ------
    MeshError
        ``mesh`` is not a ``trimesh.Trimesh``; has no faces; has face indices
        outside its vertices; has NaN/inf vertex coordinates; its bounding box
        is at most ``tol.MIN_EXTENT`` (a point); all its vertices lie on one
        line (a bounding box with a zero extent, relative to the largest,
        ``tol.MESH_ZERO_LENGTH_REL``, in all but one axis); or every face has
        zero area (below ``tol.MESH_ZERO_AREA_REL`` times the largest extent
        squared).

    Examples
    --------
    A triangle whose three corners lie on one line is refused, naming the mesh:

    >>> import trimesh
    >>> from morphkit.meshes import check_mesh
    >>> line = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0]], faces=[[0, 1, 2]])
    >>> check_mesh(line, "mesh 'line'")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    morphkit.errors.MeshError: mesh 'line': expected a surface (...), got all vertices on one line
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise MeshError(expected_got(name, "a trimesh.Trimesh", type(mesh).__name__))
    faces = np.asarray(mesh.faces)
    if len(faces) == 0:
        raise MeshError(expected_got(name, "a mesh with at least one face", "0 faces"))
    v = np.asarray(mesh.vertices)
    if v.ndim != 2 or v.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(expected_got(name, "(N, 3) vertices and (M, 3) triangles",
                                     f"vertices {v.shape}, faces {faces.shape}"))
    if faces.min() < 0 or faces.max() >= len(v):
        raise MeshError(expected_got(name, f"face indices in [0, {len(v)})",
                                     f"indices up to {int(faces.max())}"))
    if not np.all(np.isfinite(v)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(v), axis=1)))
        raise MeshError(expected_got(name, "finite vertex coordinates", f"{bad} non-finite vertices"))
    used = v[np.unique(faces)]
    ext = np.sort(used.max(0) - used.min(0))
    if not ext[2] > tol.MIN_EXTENT:
        raise MeshError(expected_got(name, f"a bounding box larger than {tol.MIN_EXTENT}",
                                     f"extent {float(ext[2])}"))
    # a line: project the vertices off their principal direction (not only the
    # axis-aligned box: a diagonal line has three non-zero box extents)
    c = used - used.mean(0)
    sv = np.linalg.svd(c, compute_uv=False)
    if sv[1] <= tol.MESH_ZERO_LENGTH_REL * sv[0] or ext[1] <= tol.MESH_ZERO_LENGTH_REL * ext[2]:
        raise MeshError(expected_got(name, "a surface (a bounding box with at most one zero extent)",
                                     "all vertices on one line"))
    tri = v[faces]
    area2 = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    if not np.any(area2 / 2 > tol.MESH_ZERO_AREA_REL * ext[2] ** 2):
        raise MeshError(expected_got(name, "a surface with area", f"{len(faces)} faces of zero area"))
    return mesh


# --------------------------------------------------------------------------
# Loading and lookup
# --------------------------------------------------------------------------


def resolve_up(path: str | Path, up: str = "auto") -> str:
    """The up axis :func:`load_mesh` uses for ``path``: ``up`` itself, or the format's default.

    Parameters
    ----------
    path : str or pathlib.Path
        Mesh file path; only its extension is read (for ``up="auto"``).
    up : {"auto", "z", "y"}, optional
        The requested up axis; ``"auto"`` is the table of the module notes.

    Returns
    -------
    str
        ``"z"`` or ``"y"``.

    Raises
    ------
    MeshError
        ``up`` is not one of ``"auto"``, ``"z"``, ``"y"``.
    """
    if not isinstance(up, str) or up.lower() not in ("auto", *UP_AXES):
        raise MeshError(expected_got("up axis", "'auto', 'z' or 'y' (morphkit's world is +z up)", repr(up)))
    up = up.lower()
    if up != "auto":
        return up
    return UP_AXIS_BY_FORMAT.get(Path(path).suffix.lower().lstrip("."), "z")


def _outside(obj: Path, kind: str, name: str, root: Path, fallback: str, folder: Path | None = None) -> None:
    where = f"{kind} {name!r} lies outside"
    link = Path(os.path.normpath((folder or obj.parent).resolve() / name))
    if link.is_relative_to(root) and not link.resolve().is_relative_to(root):
        where = f"{kind} {name!r} is a link to {str(link.resolve())!r}, outside"
    warnings.warn(f"mesh file {str(obj)!r}: {where} the asset root {str(root)!r}; not opened, {fallback} "
                  "(asset_root= / MORPHKIT_ASSET_ROOT widens the root)", AssetWarning, stacklevel=4)


#: What an OBJ material whose ``map_Kd`` image cannot be drawn falls back to.
_KD_FALLBACK = "drawn in its Kd colour {kd}"
#: What the materials of a glTF image that cannot be drawn fall back to.
_FACTOR_FALLBACK = "its materials are drawn in their baseColorFactor"


def _mtl_warnings(obj: Path, root: Path, resolver: AssetResolver) -> dict[str, str]:
    """Check an OBJ's material libraries and ``map_Kd`` images before trimesh reads them.

    Warns about those that are not there or lie outside ``root`` (never opened), and about
    images that cannot be read or decoded (withheld from trimesh:
    :meth:`morphkit.meshes.assets.AssetResolver.check_image`); raises
    :class:`~morphkit.errors.MeshError` for one that is not a regular file (a FIFO). Returns,
    per material whose image was found and decodes, the warning to give if trimesh still
    comes back without it.
    """
    try:
        lines = read_regular(obj, f"mesh file {str(obj)!r}").decode(errors="replace").splitlines()
    except MeshError:
        return {}  # trimesh's error follows
    name = f"mesh file {str(obj)!r}"
    libs = []
    for ln in lines:
        if ln.startswith("mtllib") and len(ln.split()) > 1:
            rest = ln.split(None, 1)[1].strip()  # one name with spaces, or several names
            libs += [rest] if locate(obj.parent, rest, root, f"material library {rest!r} of {name}")[0] \
                else rest.split()
    expected: dict[str, str] = {}
    for lib in libs:
        mtl, outside = locate(obj.parent, lib, root, f"material library {lib!r} of {name}")
        if outside:
            _outside(obj, "material library", lib, root, "its parts are drawn without their materials")
            continue
        if mtl is None:
            warnings.warn(f"mesh file {str(obj)!r}: material library {lib!r} not found; its parts are drawn "
                          "without their materials", AssetWarning, stacklevel=3)
            continue
        material, kd = "?", "the default"
        text = read_regular(mtl, f"material library {lib!r} of {name}").decode(errors="replace")
        for ln in text.splitlines():
            words = ln.split()
            if not words:
                continue
            if words[0] == "newmtl":
                material, kd = " ".join(words[1:]), "the default"
            elif words[0] == "Kd" and len(words) >= 4:
                kd = str(words[1:4])
            elif words[0] == "map_Kd" and len(words) > 1:
                tex = words[-1]
                what = f"texture {tex!r} of material {material!r} ({lib}) of {name}"
                head = f"mesh file {str(obj)!r}: texture {tex!r} of material {material!r} ({lib})"
                fallback = _KD_FALLBACK.format(kd=kd)
                found, outside = locate(mtl.parent, tex, root, what)
                if outside:
                    _outside(obj, "texture", tex, root, f"material {material!r} is {fallback}", mtl.parent)
                elif found is None:
                    warnings.warn(f"{head} not found; {fallback}", AssetWarning, stacklevel=3)
                elif (why := resolver.check_image(found, what)) is not None:
                    warnings.warn(f"{head} {why}; {fallback}", AssetWarning, stacklevel=3)
                else:
                    options = f" (its map_Kd line has options, {' '.join(words[1:-1])!r}, which trimesh's " \
                              "OBJ reader takes for the file name)" if len(words) > 2 else ""
                    expected[material] = f"{head} was found but not loaded{options}; {fallback}"
    return expected


def gltf_warnings(path: Path, root: Path, doc: dict[str, Any], resolver: AssetResolver) -> int:
    """Check a ``.gltf``'s or ``.glb``'s external buffers and its images (its JSON: ``doc``) before
    trimesh reads them; the number of images warned about.

    Warns about images that are not there, lie outside ``root`` (trimesh drops them silently),
    or cannot be read or decoded (those in files are withheld from trimesh:
    :meth:`morphkit.meshes.assets.AssetResolver.check_image`; those the file holds itself,
    :func:`morphkit.meshes.gltf.embedded_images`, are dropped after the load when trimesh has
    kept them).

    Parameters
    ----------
    path : pathlib.Path
        The glTF file.
    root : pathlib.Path
        The asset root (:func:`morphkit.meshes.assets.asset_root`).
    doc : dict
        Its JSON (:func:`morphkit.meshes.gltf.gltf_document`).
    resolver : AssetResolver
        The resolver the load will use (images checked here are served from it).

    Returns
    -------
    int
        The number of images warned about.

    Raises
    ------
    MeshError
        A buffer or image that is not a regular file (a FIFO), or a buffer outside ``root``.

    Warns
    -----
    AssetWarning
        An image missing, outside ``root``, unreadable or damaged (its materials keep their
        ``baseColorFactor``).
    """
    name = f"mesh file {str(path)!r}"
    bad = 0

    def warn(message: str) -> None:
        nonlocal bad
        bad += 1
        warnings.warn(f"{name}: {message}; {_FACTOR_FALLBACK}", AssetWarning, stacklevel=4)

    for kind in ("buffers", "images"):
        entries = doc.get(kind, [])
        for i, entry in enumerate(entries if isinstance(entries, list) else []):
            uri = entry.get("uri") if isinstance(entry, dict) else None
            if kind == "images" and isinstance(entry, dict) and uri is None and "bufferView" not in entry:
                warn(f"image {i} has neither a uri nor a bufferView")
            if not isinstance(uri, str) or uri.startswith("data:"):
                continue
            what = f"{kind[:-1]} {i} {uri!r} of {name}"
            found, outside = locate(path.parent, uri, root, what)
            if kind == "buffers" and outside:
                raise MeshError(expected_got(f"{kind[:-1]} {i} of {name}", f"a file inside the asset root "
                                             f"{str(root)!r} (asset_root= / MORPHKIT_ASSET_ROOT widens it)",
                                             f"{uri!r}, outside it (not opened)"))
            if kind == "images" and outside:
                bad += 1
                _outside(path, f"image {i}", uri, root, _FACTOR_FALLBACK)
            elif kind == "images" and found is None:
                warn(f"image {i} {uri!r} not found")
            elif kind == "images" and (why := resolver.check_image(found, what)) is not None:
                warn(f"image {i} {uri!r} {why}")

    def external(uri: str) -> bytes | None:
        try:
            return resolver.get(uri)
        except OSError:
            return None

    for i, (where, data) in sorted(gltf.embedded_images(path, doc, name, external).items()):
        why = "cannot be taken out of the file" if data is None else image_problem(data)
        if why is not None:
            warn(f"image {i} (in {where}) {why}")
    return bad


#: The attributes of trimesh's materials that hold an image.
_IMAGE_ATTRIBUTES = ("image", "baseColorTexture", "metallicRoughnessTexture", "normalTexture",
                     "emissiveTexture", "occlusionTexture")


def trimesh_load(source: Path | IO[bytes], name: str, resolver: AssetResolver, *,
                 file_type: str | None = None) -> Any:
    """``trimesh.load`` of a mesh file through ``resolver``, its failures as morphkit's errors.

    Parameters
    ----------
    source : pathlib.Path or binary file object
        The file, or its bytes (then ``file_type`` says the format).
    name : str
        The file in error messages.
    resolver : AssetResolver
        Every file the mesh refers to is read through it (:mod:`morphkit.meshes.assets`).
    file_type : str, optional
        The format (``"glb"``, ``"gltf"``, ...) of a file object.

    Returns
    -------
    trimesh.Trimesh or trimesh.Scene or Any
        What trimesh read (``process=False``: trimesh's processing would silently drop
        non-finite vertices).

    Raises
    ------
    MeshError
        trimesh cannot read the file; a file it refers to is not a regular file or lies
        outside the asset root (recorded by the resolver, which trimesh partly swallows).
    """
    try:
        if isinstance(source, Path):
            loaded = trimesh.load(str(source), process=False, resolver=resolver)
        else:
            loaded = trimesh.load(source, file_type=file_type, process=False, resolver=resolver)
    except Exception as exc:  # trimesh raises many types for bad files
        if resolver.errors:
            raise resolver.errors[0] from exc
        if resolver.outside:
            raise MeshError(expected_got(
                f"file {resolver.outside[0]!r} referred to by {name}", f"a file inside the asset root "
                f"{str(resolver.root)!r} (asset_root= / MORPHKIT_ASSET_ROOT widens it)",
                "one outside it (not opened)")) from exc
        raise MeshError(
            expected_got(name, "a file trimesh can read", f"{type(exc).__name__}: {exc}"[:200])
        ) from exc
    if resolver.errors:  # trimesh swallows a material's or an image's read errors
        raise resolver.errors[0]
    return loaded


def loaded_looks(loaded: Any, name: str, expected: dict[str, str], warned: bool) -> None:
    """After trimesh's load: an image that does not decode is dropped from its material (trimesh
    opens images lazily: a damaged one failed only when first read), with a warning unless
    the checks before the load gave one; an OBJ material whose image was found and decodes
    (``expected``: its warning) but came back without it is said.

    Parameters
    ----------
    loaded : trimesh.Trimesh or trimesh.Scene
        What :func:`trimesh_load` read; its materials are changed in place.
    name : str
        The file in warnings.
    expected : dict
        OBJ material name -> the warning to give if it came back without its image.
    warned : bool
        Whether the checks before the load warned already (:func:`gltf_warnings`).

    Warns
    -----
    AssetWarning
        A damaged image dropped, or an OBJ image not loaded.
    """
    geoms = loaded.geometry.values() if isinstance(loaded, trimesh.Scene) else [loaded]
    for g in geoms:
        material = getattr(getattr(g, "visual", None), "material", None)
        if material is None:
            continue
        for attr in _IMAGE_ATTRIBUTES:
            img = getattr(material, attr, None)
            if img is None or not hasattr(img, "load"):
                continue
            try:
                img.load()
            except Exception as exc:  # Pillow's decoders raise many types for damaged data
                setattr(material, attr, None)
                if not warned:
                    warnings.warn(f"{name}: the {attr} image of material {getattr(material, 'name', '?')!r} "
                                  f"is damaged ({type(exc).__name__}: {exc}); drawn without it", AssetWarning,
                                  stacklevel=4)
        said = expected.get(str(getattr(material, "name", None)))
        if said is not None and getattr(material, "image", "") is None and getattr(g.visual, "uv", None) \
                is not None:
            warnings.warn(said, AssetWarning, stacklevel=4)


def _has_vertex_colors(mesh: trimesh.Trimesh) -> bool:
    v = mesh.visual
    if isinstance(v, trimesh.visual.TextureVisuals):
        return "color" in v.vertex_attributes
    return v.kind == "vertex"


def check_parts(parts: list[trimesh.Trimesh], name: str) -> None:
    """Check the triangle meshes a file loaded as, and merge their split vertices, in place.

    Face indices past the vertices and coordinates beyond :data:`morphkit.tol.MESH_MAX_COORD`
    are refused before trimesh indexes or hashes them; vertices are merged where position and
    UV agree (OBJ/STL split them), except on meshes with vertex colours (left as stored).

    Parameters
    ----------
    parts : list of trimesh.Trimesh
        The parts, changed in place (vertices merged).
    name : str
        The file in error messages.

    Raises
    ------
    MeshError
        A face index out of range, a coordinate too large, vertex attributes trimesh cannot merge.
    """
    for part in parts:
        # a damaged file's faces may index past its vertices: refused before trimesh indexes them
        faces = np.asarray(part.faces)
        if faces.min() < 0 or faces.max() >= len(part.vertices):
            raise MeshError(expected_got(name, f"face indices in [0, {len(part.vertices)})",
                                         f"indices from {int(faces.min())} to {int(faces.max())}"))
        v = np.asarray(part.vertices)
        big = np.isfinite(v) & (np.abs(v) > tol.MESH_MAX_COORD)  # NaN/inf: check_mesh's message
        if big.any():
            raise MeshError(expected_got(name, f"vertex coordinates within +-{tol.MESH_MAX_COORD:g}",
                                         f"{int(np.count_nonzero(big.any(axis=1)))} vertices beyond"))
        if np.all(np.isfinite(part.vertices)) and not _has_vertex_colors(part):
            try:
                part.merge_vertices()  # formats like OBJ/STL split vertices per face or per normal
            except (ArithmeticError, IndexError, ValueError, TypeError) as exc:
                # damaged UVs or normals (huge values) overflow trimesh's hashing of them
                raise MeshError(expected_got(name, "vertex attributes trimesh can merge",
                                             f"{type(exc).__name__}: {exc}"[:200])) from exc


def load_mesh(path: str | Path, *, up: str = "auto",
              asset_root: str | os.PathLike[str] | None = None) -> trimesh.Trimesh:
    """Load a mesh file with its look, turn it ``+z`` up and return it normalised.

    Any format trimesh reads (OBJ, PLY, STL, GLB/GLTF, OFF, ...) is accepted. The
    up axis, visuals and multi-part files follow the module notes: a ``+y``-up
    file is turned ``+z`` up, every part keeps its look, several parts are merged
    into one mesh with their node transforms applied. Then :func:`normalize`.

    Parameters
    ----------
    path : str or pathlib.Path
        Path of the file; the format is taken from its extension.
    up : {"auto", "z", "y"}, optional
        The file's up axis; ``"auto"`` is the format's default (:func:`resolve_up`).
    asset_root : str or os.PathLike, optional
        The folder every file the mesh refers to (materials, textures, buffers) must lie
        in (:mod:`morphkit.meshes.assets`); default :data:`morphkit.settings.ASSET_ROOT`
        (``MORPHKIT_ASSET_ROOT``), else the mesh file's own folder.

    Returns
    -------
    trimesh.Trimesh
        The normalised mesh, with the file's visuals.

    Raises
    ------
    MeshError
        If ``up`` is not ``"auto"``, ``"z"`` or ``"y"``; the file does not exist,
        cannot be read or has an unsupported format; a glTF's nodes are more than
        :data:`morphkit.tol.MAX_GLTF_NODES` or do not form trees (a cycle:
        :mod:`morphkit.meshes.gltf`); a file it refers to is not a regular
        file (a FIFO), or is a buffer outside the asset root; ``asset_root`` does not hold it;
        it holds no triangles (e.g. a
        point cloud, a scene without geometry); or the mesh fails :func:`check_mesh`.

    Warns
    -----
    AssetWarning
        An OBJ's ``mtllib`` or ``map_Kd`` file or a glTF's external image is missing, or lies
        outside the asset root (not opened); a texture (a file, or held in a glTF) cannot be
        read or decoded, and its material is drawn without it (module notes); a texture
        without UVs in a multi-part file.
    """
    p = Path(path)
    axis = resolve_up(p, up)
    if not p.is_file():
        why = "a directory" if p.is_dir() else "file not found"
        raise MeshError(expected_got("mesh path", "an existing mesh file", f"{str(p)!r} ({why})"))
    name = f"mesh file {str(p)!r}"
    root = assets.asset_root(p, asset_root if asset_root is not None else settings.ASSET_ROOT)
    resolver = AssetResolver(p, root)
    expected: dict[str, str] = {}  # OBJ materials whose image was checked and decodes
    warned = 0
    if p.suffix.lower() == ".obj":
        expected = _mtl_warnings(p, root, resolver)
    elif p.suffix.lower() in (".gltf", ".glb"):
        doc = gltf.gltf_document(p, name)  # None: not glTF JSON, trimesh's error follows
        if doc is not None:
            gltf.check_node_graph(doc, name)  # bounded before trimesh walks it (morphkit.meshes.gltf)
            warned = gltf_warnings(p, root, doc, resolver)
    loaded = trimesh_load(p, name, resolver)
    loaded_looks(loaded, name, expected, warned > 0)
    if isinstance(loaded, trimesh.Scene):
        parts = scene_parts(loaded)
        if not parts:
            got = f"0 faces (a scene of {len(loaded.geometry)} geometries, none a mesh)"
            raise MeshError(expected_got(name, "a mesh with at least one face", got))
    elif isinstance(loaded, trimesh.Trimesh) and len(loaded.faces):
        parts = [loaded]
    else:
        raise MeshError(expected_got(name, "a mesh with at least one face", "0 faces"))
    check_parts(parts, name)
    mesh = check_mesh(merge_parts(parts, name), name)
    if axis == "y":
        mesh.apply_transform(Y_UP_TO_Z_UP)
    return normalize(mesh)


def closed_volume(mesh: trimesh.Trimesh) -> bool:
    """Whether ``mesh`` bounds a volume with outward faces: seen from outside, its front faces
    hide every back face (so its ``DEPTH_ONLY`` depth, back faces culled, is complete).

    Every directed edge ``a -> b`` must occur once, with its reverse ``b -> a`` (closed and
    consistently wound; vertices at one position count as one where the indices alone fail,
    as at UV seams), and the signed volume must be positive (outward).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh.

    Returns
    -------
    bool
        True for a closed, consistently and outward wound surface.
    """
    faces = np.asarray(mesh.faces, dtype=np.int64)
    verts = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    if len(faces) == 0:
        return False

    def paired(ids: np.ndarray) -> bool:
        a, b, n = ids.reshape(-1), ids[:, [1, 2, 0]].reshape(-1), int(ids.max()) + 1
        fwd = np.sort(a * n + b)
        return not np.any(fwd[1:] == fwd[:-1]) and np.array_equal(fwd, np.sort(b * n + a))

    if not paired(faces):
        rows = verts.view(np.dtype((np.void, verts.dtype.itemsize * 3))).reshape(-1)
        if not paired(np.unique(rows, return_inverse=True)[1].reshape(-1)[faces]):
            return False
    v = verts[faces]
    return float(np.einsum("ij,ij->", v[:, 0], np.cross(v[:, 1], v[:, 2]))) > 0.0
