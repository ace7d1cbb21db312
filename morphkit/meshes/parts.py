"""Multi-part mesh files merged into one mesh that keeps every part's look.

A glTF, or an OBJ with several materials, loads as several meshes (one per
material, each with its node transform). morphkit draws one
``trimesh.Trimesh`` per object, and the renderer draws one material per mesh,
so :func:`merge_parts` merges the parts into one mesh with **one** glTF-style
material (``PBRMaterial``) whose base-colour texture is an atlas of every
part's look. trimesh's own concatenation (``trimesh.util.concatenate``,
``material.pack``, 5.2) is not used: it drops ``alphaMode`` (cut-outs become
opaque), multiplies base-colour factors into sRGB texels as if they were
linear, resizes textures, and turns vertex colours into one texel per vertex.

What each part becomes in the merged mesh (the renderer's rules,
``base colour = factor x texture(uv) x vertex colour``, stay true per part):

* **a texture** (glTF ``baseColorTexture``, OBJ ``map_Kd``): copied texel for
  texel into its own cell of the atlas (no resampling), its UVs mapped onto the
  cell. UVs outside ``[0, 1]`` (a repeated texture) repeat the image in the
  cell as often as the UVs reach (at most :data:`morphkit.tol.MAX_IMAGE_PIXELS`
  texels per cell, else a :class:`~morphkit.errors.MeshError`). A glTF
  ``baseColorFactor`` is baked into the texels in linear light:
  ``srgb(factor x linear(texel))`` for RGB, ``factor x texel`` for alpha, so
  the lit colour is kept within rounding (1/2 of an 8-bit level). Parts with the
  same (baked) image share one cell.
* **the atlas layout** keeps mip-maps: each cell sits in a square power-of-two
  slot twice its size, the image a quarter slot in from the corner and repeated
  around it (so bilinear filtering at its border wraps as ``REPEAT`` does), every
  slot at a multiple of its side in a power-of-two atlas; a power-of-two image's
  mip levels are then the atlas's, all but the last. An atlas that would exceed
  :data:`ALIGNED_ATLAS_MAX_SIDE` is laid out compactly instead (cells padded by
  :data:`ATLAS_PADDING` repeated texels; mip-maps then mix neighbours).
* **a colour without texture** (glTF factor only; OBJ ``Kd`` only; a part
  without any visuals: :data:`~morphkit.conventions.DEFAULT_COLOR`): a one-texel cell of that
  colour (sRGB-encoded), every UV at its centre.
* **vertex colours** (PLY, glTF ``COLOR_0``): kept as vertex colours
  (``visual.vertex_attributes["color"]``; they multiply the texture), the part's
  UVs on a white cell, so they still interpolate linearly across each face. The
  other parts get white vertex colours (only when some part has vertex colours).
  **Face colours** become vertex colours of unshared vertices (each face its own three).
* **alpha**: an opaque part's texels (and vertex colours) get alpha 255. The
  merged material is ``OPAQUE`` when no part is cut out, else ``MASK``: at the
  cut-out parts' ``alphaCutoff`` when they share one (alpha kept as is), else at
  0.5 with each cut-out part's alpha made 0 or 255 at its own cutoff (texels)
  — their vertex alpha is then dropped (set to 255). glTF ``BLEND`` counts as
  ``MASK`` at 0.5 and an OBJ texture with any alpha below 255 as a cut-out at 0.5
  (the renderer's reading).
* ``metallicFactor``/``roughnessFactor`` are kept when every part has the same
  (else unset: the renderer's default). Normal, occlusion, emissive and
  metallic-roughness textures are dropped (the renderer does not draw them).

A file with one part is never merged: its visuals are returned untouched. Parts
without any material or texture stay ``ColorVisuals`` (no atlas): no visuals if no
part has colours, face colours if every part has face colours, else vertex colours
(a face-coloured part's faces unshared, a part without colours in
:data:`~morphkit.conventions.DEFAULT_COLOR`).

Against drawing the parts as separate items (the views of
:func:`morphkit.programs.fixtures.write_two_part_gltf` and
:func:`morphkit.programs.fixtures.write_leaf_plant`) the coverage is identical and lit colour
and albedo differ only by rounding (the albedo pass encodes a factor as it encodes
the texel it is baked into: :mod:`morphkit.conventions`, "Colour").
A compact atlas differs where textures are minified (its mipmaps average the packed
neighbours' texels too). The atlas is subject to the renderer's texture size limits.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import trimesh
from PIL import Image

from .. import tol
from ..conventions import DEFAULT_COLOR
from ..errors import AssetWarning, MeshError, expected_got

__all__ = ["ATLAS_PADDING", "ALIGNED_ATLAS_MAX_SIDE", "PLAIN_PART_COLOR", "merge_parts", "scene_parts",
           "copy_with_look", "face_base_colors", "srgb_to_linear", "linear_to_srgb"]

#: Texels of border repeated around each cell of a compact atlas (one too large to align).
ATLAS_PADDING = 2

#: Largest side of a mip-aligned atlas: 4096, the side of the renderer's texture budget
#: (4096^2 texels); an atlas that would be larger is laid out compactly instead.
ALIGNED_ATLAS_MAX_SIDE = 4096

#: Linear RGB of a part without visuals when merged with parts that have some: the
#: renderer's default colour, :data:`morphkit.conventions.DEFAULT_COLOR` itself (this name
#: is kept for existing imports).
PLAIN_PART_COLOR: tuple[float, float, float] = DEFAULT_COLOR

#: The cut-out threshold of glTF ``BLEND`` materials and of OBJ textures with alpha
#: (glTF's default ``alphaCutoff``).
_DEFAULT_CUTOFF = 0.5


def srgb_to_linear(v: Any) -> np.ndarray:
    """Decode sRGB values in ``[0, 1]`` to linear light (the exact sRGB curve).

    Parameters
    ----------
    v : array_like of float
        sRGB-encoded values in ``[0, 1]``.

    Returns
    -------
    numpy.ndarray of float64
        Linear values, same shape.
    """
    v = np.asarray(v, dtype=np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v: Any) -> np.ndarray:
    """Encode linear values in ``[0, 1]`` with the sRGB curve.

    Parameters
    ----------
    v : array_like of float
        Linear values in ``[0, 1]``.

    Returns
    -------
    numpy.ndarray of float64
        sRGB-encoded values, same shape.
    """
    v = np.clip(np.asarray(v, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1.0 / 2.4) - 0.055)


def copy_with_look(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """A copy of ``mesh`` with all its visuals.

    trimesh 5.2's ``copy`` of ``TextureVisuals`` keeps the UVs but drops the other
    vertex attributes (glTF ``COLOR_0`` vertex colours); they are copied here too.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh.

    Returns
    -------
    trimesh.Trimesh
        The copy.
    """
    out = mesh.copy()
    if isinstance(mesh.visual, trimesh.visual.TextureVisuals):
        for key, value in mesh.visual.vertex_attributes.items():
            if key not in out.visual.vertex_attributes:
                out.visual.vertex_attributes[key] = np.array(value, copy=True)
    return out


def scene_parts(scene: trimesh.Scene) -> list[trimesh.Trimesh]:
    """Every triangle mesh of a scene, moved by its node's transform, in the order of the node names.

    Copies with their visuals (:func:`copy_with_look`); points, paths and meshes without
    faces are left out.

    Parameters
    ----------
    scene : trimesh.Scene
        The scene (e.g. a loaded glTF).

    Returns
    -------
    list of trimesh.Trimesh
        One mesh per node that instances a mesh (a mesh instanced twice comes twice).
    """
    out = []
    for node in sorted(scene.graph.nodes_geometry):
        transform, geom = scene.graph[node]
        g = scene.geometry.get(geom)
        if isinstance(g, trimesh.Trimesh) and len(g.faces):
            part = copy_with_look(g)
            part.apply_transform(transform)
            out.append(part)
    return out


def _rgba(image: Any) -> np.ndarray:
    """A texture (PIL or array) as ``(H, W, 4)`` uint8 (8-bit values as stored)."""
    if isinstance(image, Image.Image):
        if image.mode in ("I;16", "I;16B", "I;16L", "I;16N", "I"):
            a = np.asarray(image, dtype=np.float64) / 257.0
            g = np.clip(np.rint(a), 0, 255).astype(np.uint8)
            return np.dstack([g, g, g, np.full_like(g, 255)])
        return np.asarray(image.convert("RGBA"), dtype=np.uint8).copy()
    a = np.asarray(image)
    if a.ndim == 2:
        a = a[..., None]
    if a.dtype == np.uint16:
        a = np.rint(a / 257.0)
    elif np.issubdtype(a.dtype, np.floating):
        a = np.rint(np.clip(a, 0.0, 1.0) * 255.0)
    a = np.clip(a, 0, 255).astype(np.uint8)
    c = a.shape[2]
    out = np.full(a.shape[:2] + (4,), 255, np.uint8)
    if c in (1, 2):
        out[..., :3] = a[..., :1]
        if c == 2:
            out[..., 3] = a[..., 1]
    else:
        out[..., : min(c, 4)] = a[..., :4]
    return out


def _factor(c: Any) -> np.ndarray:
    """A trimesh colour (uint8 RGB(A) or float) as float RGBA in ``[0, 1]``."""
    a = np.asarray(c).reshape(-1)
    f = a.astype(np.float64) / 255.0 if np.issubdtype(a.dtype, np.integer) else a.astype(np.float64)
    return np.append(f, 1.0)[:4] if f.size == 3 else f[:4]


def _flat(rgba_float: np.ndarray) -> np.ndarray:
    """A one-texel cell of a linear RGBA colour, sRGB-encoded."""
    out = np.empty(4)
    out[:3] = linear_to_srgb(rgba_float[:3])
    out[3] = rgba_float[3]
    return np.rint(out * 255.0).astype(np.uint8).reshape(1, 1, 4)


def _placeholder(mat: Any) -> bool:
    """trimesh's stand-in for "no material": a 2 x 2 image of grey 100, diffuse 102."""
    if not isinstance(mat, trimesh.visual.material.SimpleMaterial) or mat.image is None:
        return False
    img = _rgba(mat.image)
    return (img.shape == (2, 2, 4) and bool(np.all(img == [100, 100, 100, 255]))
            and np.array_equal(np.asarray(mat.diffuse), [102, 102, 102, 255]))


@dataclass
class _Part:
    """One part's look, ready to be packed."""

    mesh: trimesh.Trimesh
    cell: np.ndarray            # (h, w, 4) uint8: one tile (factor baked, alpha per mode)
    uv: np.ndarray | None       # (V, 2) UVs into the tile; None: every vertex at the cell centre
    vcolor: np.ndarray | None   # (V, 4) uint8 vertex colours
    cutoff: float | None        # None: opaque
    mr: tuple[float | None, float | None]


def _texture_part(mesh: trimesh.Trimesh, name: str, cache: dict[Any, Any]) -> _Part:
    visual = mesh.visual
    mat = visual.material
    nv = len(mesh.vertices)
    mr: tuple[float | None, float | None] = (None, None)
    if isinstance(mat, trimesh.visual.material.MultiMaterial):
        raise MeshError(expected_got(name, "one material per part",
                                     f"a MultiMaterial of {len(mat.materials)}"))
    if _placeholder(mat):
        image, factor, cutoff = None, np.array([*DEFAULT_COLOR, 1.0]), None
    elif isinstance(mat, trimesh.visual.material.PBRMaterial):
        factor = np.ones(4) if mat.baseColorFactor is None else _factor(mat.baseColorFactor)
        image = mat.baseColorTexture
        mode = (mat.alphaMode or "OPAQUE").upper()
        cutoff = {"OPAQUE": None, "MASK": mat.alphaCutoff if mat.alphaCutoff is not None else _DEFAULT_CUTOFF,
                  "BLEND": _DEFAULT_CUTOFF}.get(mode, None)
        mr = (mat.metallicFactor, mat.roughnessFactor)
    elif isinstance(mat, trimesh.visual.material.SimpleMaterial):
        image = mat.image
        factor = np.ones(4) if image is not None else np.append(_factor(mat.diffuse)[:3], 1.0)
        cutoff = None
    else:
        raise MeshError(expected_got(name, "a PBRMaterial or SimpleMaterial", type(mat).__name__))
    uv = visual.uv
    vcol = visual.vertex_attributes.get("color") if hasattr(visual, "vertex_attributes") else None
    if image is None:
        cell = _flat(factor)
        uv = None
    else:
        simple = isinstance(mat, trimesh.visual.material.SimpleMaterial)
        tex = _rgba(image)
        key = (tex.shape, tex.tobytes(), tuple(factor), simple, cutoff)  # one conversion per image
        if key not in cache:
            cut = _DEFAULT_CUTOFF if simple and bool(np.any(tex[..., 3] < 255)) else cutoff
            cut = None if cut is not None and float(cut) <= 0.0 else cut
            baked = tex.copy()
            if np.any(factor[:3] != 1.0):  # (a factor of 1 keeps every texel: the round trip is exact)
                lin = srgb_to_linear(tex[..., :3] / 255.0) * factor[:3]
                baked[..., :3] = np.rint(linear_to_srgb(lin) * 255.0)
            baked[..., 3] = 255 if cut is None else np.rint(np.clip(tex[..., 3] * factor[3], 0, 255))
            cache[key] = (baked, cut)
        cell, cutoff = cache[key]
        if uv is None or len(uv) == 0:
            mean = cell.reshape(-1, 4).mean(0)
            warnings.warn(f"{name}: a texture but no UV coordinates; merged in the texture's mean colour "
                          f"{np.round(mean[:3]).astype(int).tolist()}", AssetWarning, stacklevel=4)
            cell, uv = np.rint(mean).astype(np.uint8).reshape(1, 1, 4), None
        else:
            uv = np.asarray(uv, dtype=np.float64)
            if uv.shape != (nv, 2) or not np.all(np.isfinite(uv)):
                raise MeshError(expected_got(f"{name} UV coordinates", f"({nv}, 2) finite values",
                                             f"shape {uv.shape}" if uv.shape != (nv, 2) else "NaN or inf"))
    if cutoff is not None and float(cutoff) <= 0.0:
        cutoff = None
    if vcol is not None:
        vcol = np.asarray(vcol)
        vcol = (np.rint(np.clip(vcol, 0, 1) * 255) if np.issubdtype(vcol.dtype, np.floating) else vcol)
        v4 = np.full((nv, 4), 255, np.uint8)
        v4[:, : vcol.shape[1]] = vcol[:, :4]
        vcol = v4
    if cutoff is None:
        if np.any(cell[..., 3] != 255):
            cell = cell.copy()
            cell[..., 3] = 255
        if vcol is not None:
            vcol[:, 3] = 255
    return _Part(mesh, cell, uv, vcol, None if cutoff is None else float(cutoff), mr)


def _part(mesh: trimesh.Trimesh, name: str, cache: dict[Any, Any] | None = None) -> _Part:
    visual = mesh.visual
    if isinstance(visual, trimesh.visual.TextureVisuals):
        return _texture_part(mesh, name, {} if cache is None else cache)
    white = np.full((1, 1, 4), 255, np.uint8)
    if visual.kind == "vertex":
        vc = np.asarray(visual.vertex_colors, np.uint8).copy()
        vc[:, 3] = 255
        return _Part(mesh, white, None, vc, None, (None, None))
    if visual.kind == "face":
        f = np.asarray(mesh.faces)
        split = trimesh.Trimesh(mesh.vertices[f].reshape(-1, 3), np.arange(3 * len(f)).reshape(-1, 3),
                                process=False)
        vc = np.repeat(np.asarray(visual.face_colors, np.uint8), 3, axis=0)
        vc[:, 3] = 255
        return _Part(split, white, None, vc, None, (None, None))
    return _Part(mesh, _flat(np.array([*DEFAULT_COLOR, 1.0])), None, None, None, (None, None))


def _tiles(part: _Part, name: str) -> tuple[np.ndarray, np.ndarray]:
    """The cell image (the tile repeated over the UVs' integer range) and its UV origin."""
    if part.uv is None:
        return part.cell, np.zeros(2)
    lo = np.floor(part.uv.min(0) + tol.UV_TILE_SLACK)
    hi = np.maximum(np.ceil(part.uv.max(0) - tol.UV_TILE_SLACK), lo + 1)
    nx, ny = (hi - lo).astype(int)
    h, w = part.cell.shape[:2]
    if nx * ny * h * w > tol.MAX_IMAGE_PIXELS:
        raise MeshError(expected_got(f"{name} UV coordinates",
                                     f"a repeated texture of at most {tol.MAX_IMAGE_PIXELS} texels in all",
                                     f"{nx} x {ny} repeats of a {w} x {h} texture"))
    cell = part.cell if nx == ny == 1 else np.tile(part.cell, (ny, nx, 1))
    return cell, np.array([lo[0], lo[1] + ny])


def _pot(n: int) -> int:
    """The smallest power of two >= ``n`` (>= 1)."""
    return 1 << max(0, int(n) - 1).bit_length()


def _shelves(sides: list[tuple[int, int]], width: int) -> tuple[list[tuple[int, int]], int]:
    """Top-left corners of ``(h, w)`` boxes on shelves of ``width``, in the order given; total height."""
    corners: list[tuple[int, int]] = []
    x = y = shelf = 0
    for h, w in sides:
        if x + w > width:
            x, y, shelf = 0, y + shelf, 0
        corners.append((y, x))
        x, shelf = x + w, max(shelf, h)
    return corners, y + shelf


def _aligned_layout(images: list[np.ndarray]) -> tuple[np.ndarray, list[tuple[int, int]]] | None:
    """Mip-aligned atlas: each image in a square power-of-two slot twice its (power-of-two)
    size, at a quarter of the slot from its corner, the rest of the slot the image repeated;
    slots largest first on shelves of a power-of-two atlas, so each lands at a multiple of its
    side. ``None`` if the atlas would be wider or taller than :data:`ALIGNED_ATLAS_MAX_SIDE`."""
    slots = [2 * max(_pot(im.shape[0]), _pot(im.shape[1])) for im in images]
    order = sorted(range(len(images)), key=lambda i: -slots[i])
    width = max(max(slots), _pot(int(np.ceil(np.sqrt(sum(s * s for s in slots))))))
    placed, height = _shelves([(slots[i], slots[i]) for i in order], width)
    height = _pot(height)
    if max(width, height) > ALIGNED_ATLAS_MAX_SIDE:
        return None
    atlas = np.zeros((height, width, 4), np.uint8)
    origins: list[tuple[int, int]] = [(0, 0)] * len(images)
    for i, (y0, x0) in zip(order, placed, strict=True):
        im, s = images[i], slots[i]
        h, w = im.shape[:2]
        oy, ox = _pot(h) // 2, _pot(w) // 2
        atlas[y0: y0 + s, x0: x0 + s] = np.pad(im, ((oy, s - h - oy), (ox, s - w - ox), (0, 0)), mode="wrap")
        origins[i] = (y0 + oy, x0 + ox)
    return atlas, origins


def _compact_layout(images: list[np.ndarray]) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Each image padded by :data:`ATLAS_PADDING` repeated texels, tallest first on shelves."""
    p = ATLAS_PADDING
    padded = [np.pad(im, ((p, p), (p, p), (0, 0)), mode="wrap") for im in images]
    order = sorted(range(len(images)), key=lambda i: -padded[i].shape[0])
    width = max(max(im.shape[1] for im in padded), int(np.ceil(np.sqrt(sum(im.size // 4 for im in padded)))))
    placed, height = _shelves([padded[i].shape[:2] for i in order], width)
    atlas = np.zeros((height, width, 4), np.uint8)
    origins: list[tuple[int, int]] = [(0, 0)] * len(images)
    for i, (y0, x0) in zip(order, placed, strict=True):
        atlas[y0: y0 + padded[i].shape[0], x0: x0 + padded[i].shape[1]] = padded[i]
        origins[i] = (y0 + p, x0 + p)
    return atlas, origins


def _merge_colors(parts: list[trimesh.Trimesh]) -> trimesh.Trimesh:
    """Parts with ``ColorVisuals`` only: no visuals, face colours, or vertex colours."""
    kinds = {p.visual.kind for p in parts}
    if kinds == {None}:
        return trimesh.util.concatenate([trimesh.Trimesh(p.vertices, p.faces, process=False) for p in parts])
    if kinds == {"face"}:
        geom = trimesh.util.concatenate([trimesh.Trimesh(p.vertices, p.faces, process=False) for p in parts])
        geom.visual = trimesh.visual.ColorVisuals(geom, face_colors=np.vstack([p.visual.face_colors
                                                                                for p in parts]))
        return geom
    looks = [_part(p, "mesh") for p in parts]
    verts = [np.asarray(lk.mesh.vertices, dtype=np.float64) for lk in looks]
    offsets = np.cumsum([0] + [len(v) for v in verts])
    faces = np.vstack([np.asarray(lk.mesh.faces) + o for lk, o in zip(looks, offsets, strict=False)])
    colors = np.vstack([lk.vcolor if lk.vcolor is not None
                        else np.tile(lk.cell[0, 0], (len(lk.mesh.vertices), 1)) for lk in looks])
    out = trimesh.Trimesh(np.vstack(verts), faces, process=False)
    out.visual = trimesh.visual.ColorVisuals(out, vertex_colors=colors)
    return out


def merge_parts(parts: Sequence[trimesh.Trimesh], name: str = "mesh") -> trimesh.Trimesh:
    """Merge meshes (in one frame) into one whose single material keeps every part's look.

    The rules are in the module notes. One part is returned as it is.

    Parameters
    ----------
    parts : sequence of trimesh.Trimesh
        The parts, their transforms already applied. Not modified.
    name : str, optional
        How messages name the file.

    Returns
    -------
    trimesh.Trimesh
        The merged mesh: ``TextureVisuals`` with a ``PBRMaterial`` (atlas texture,
        ``OPAQUE`` or ``MASK``) and UVs, plus vertex colours where a part had some;
        when no part has a texture or material, ``ColorVisuals`` instead: none (no
        part has colours), face colours (every part has), else vertex colours.

    Raises
    ------
    MeshError
        No parts; a part with a ``MultiMaterial`` or an unknown material, UVs of the
        wrong length, or a repeated texture too large to lay out.
    """
    parts = list(parts)
    if not parts:
        raise MeshError(expected_got(name, "at least one mesh", "none"))
    if len(parts) == 1:
        return parts[0]
    if not any(isinstance(p.visual, trimesh.visual.TextureVisuals) for p in parts):
        return _merge_colors(parts)
    cache: dict[Any, Any] = {}
    looks = [_part(p, f"{name} part {i}", cache) for i, p in enumerate(parts)]
    cutoffs = sorted({lk.cutoff for lk in looks if lk.cutoff is not None})
    if len(cutoffs) > 1:  # one threshold for all: each cut-out part's alpha made 0/255 at its own
        binary: dict[tuple[int, float], np.ndarray] = {}
        for lk in looks:
            if lk.cutoff is not None:
                key = (id(lk.cell), lk.cutoff)
                if key not in binary:
                    b = lk.cell.copy()
                    b[..., 3] = np.where(b[..., 3] >= lk.cutoff * 255.0, 255, 0)
                    binary[key] = b
                lk.cell = binary[key]
                if lk.vcolor is not None:
                    lk.vcolor[:, 3] = 255
    cutoff = None if not cutoffs else (cutoffs[0] if len(cutoffs) == 1 else _DEFAULT_CUTOFF)
    tiled = [_tiles(lk, f"{name} part {i}") for i, lk in enumerate(looks)]
    cell_of: dict[tuple[tuple[int, ...], bytes], int] = {}  # parts with the same image share a cell
    seen: dict[int, int] = {}  # id of an image (alive in ``tiled``) -> its cell
    which = []
    for img, _ in tiled:
        if id(img) not in seen:
            seen[id(img)] = cell_of.setdefault((img.shape, img.tobytes()), len(cell_of))
        which.append(seen[id(img)])
    images: list[np.ndarray] = [np.empty(0)] * len(cell_of)
    for (img, _), c in zip(tiled, which, strict=True):
        images[c] = img
    atlas, cell_origins = _aligned_layout(images) or _compact_layout(images)
    ah, aw = atlas.shape[:2]
    uvs, vcols, verts, faces, offset = [], [], [], [], 0
    any_vc = any(lk.vcolor is not None for lk in looks)
    for lk, (_, origin), c in zip(looks, tiled, which, strict=True):
        oy, ox = cell_origins[c]
        nv = len(lk.mesh.vertices)
        if lk.uv is None:
            uv = np.tile([(ox + 0.5) / aw, 1.0 - (oy + 0.5) / ah], (nv, 1))
        else:
            th, tw = lk.cell.shape[:2]
            uv = np.c_[(ox + (lk.uv[:, 0] - origin[0]) * tw) / aw,
                       1.0 - (oy + (origin[1] - lk.uv[:, 1]) * th) / ah]
        uvs.append(uv)
        if any_vc:
            vcols.append(lk.vcolor if lk.vcolor is not None else np.full((nv, 4), 255, np.uint8))
        verts.append(np.asarray(lk.mesh.vertices, dtype=np.float64))
        faces.append(np.asarray(lk.mesh.faces) + offset)
        offset += nv
    mrs = {lk.mr for lk in looks}
    metallic, roughness = mrs.pop() if len(mrs) == 1 else (None, None)
    mat = trimesh.visual.material.PBRMaterial(
        name="merged", baseColorTexture=Image.fromarray(atlas, "RGBA"),
        alphaMode="OPAQUE" if cutoff is None else "MASK", alphaCutoff=cutoff,
        metallicFactor=metallic, roughnessFactor=roughness, doubleSided=True)
    visual = trimesh.visual.TextureVisuals(uv=np.vstack(uvs), material=mat)
    out = trimesh.Trimesh(np.vstack(verts), np.vstack(faces), visual=visual, process=False)
    if any_vc:
        out.visual.vertex_attributes["color"] = np.vstack(vcols)
    return out



def face_base_colors(mesh: trimesh.Trimesh) -> np.ndarray:
    """The base colour of each face at its UV centroid, linear RGBA (a measurement).

    ``factor x texture x vertex colour`` as the module notes read a mesh's visuals:
    the texture's nearest texel to the face's UV centroid (UVs repeat), sRGB-decoded;
    the mean of the face's three vertex colours, decoded; face colours decoded; a mesh
    without visuals :data:`~morphkit.conventions.DEFAULT_COLOR`. Alpha is linear
    (``texel / 255``), 1 for opaque looks. Used to check that merging keeps every part's colour.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh, with any visuals.

    Returns
    -------
    (F, 4) float64
        Base colour per face.
    """
    look = _part(mesh, "mesh")
    f = np.asarray(look.mesh.faces)
    cell = look.cell
    if look.uv is None:
        texel = np.broadcast_to(cell[0, 0], (len(f), 4)).astype(np.float64)
    else:
        c = look.uv[f].mean(1)
        h, w = cell.shape[:2]
        col = np.floor(np.mod(c[:, 0], 1.0) * w).astype(int) % w
        row = np.floor((1.0 - np.mod(c[:, 1], 1.0)) * h).astype(int) % h
        texel = cell[row, col].astype(np.float64)
    out = np.c_[srgb_to_linear(texel[:, :3] / 255.0), texel[:, 3] / 255.0]
    if look.vcolor is not None:
        vc = look.vcolor[f].astype(np.float64) / 255.0
        out[:, :3] *= srgb_to_linear(vc[..., :3]).mean(1)
        out[:, 3] *= vc[..., 3].mean(1)
    return out
