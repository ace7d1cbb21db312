"""A mesh's own look, read from its trimesh visuals into plain arrays.

:class:`~morphkit.scene.Item` with ``color=None`` is drawn in its mesh's own
look; :func:`mesh_look` reads it (numpy only; :mod:`morphkit.render` uploads
it). The drawn base colour of a surface point is, as in glTF,

    base colour = factor x texture(uv) x vertex colour

(RGBA; a missing term is 1). Colour spaces: :mod:`morphkit.conventions`.
What each kind of trimesh visual becomes:

* ``ColorVisuals`` without colours (``visual.kind is None``, every mesh
  built from vertices and faces): one colour,
  :data:`~morphkit.conventions.DEFAULT_COLOR`, drawn exactly as an item with
  that colour.
  trimesh's placeholder material (a 2 x 2 grey-100 image with the default
  diffuse, what trimesh gives an OBJ with UVs but no material) counts as none.
* ``ColorVisuals`` with vertex colours: interpolated across each face; with
  face colours: one colour per face. Their alpha is ignored (opaque).
* ``TextureVisuals`` with a ``PBRMaterial`` (glTF): ``baseColorFactor`` x
  ``baseColorTexture``; ``alphaMode`` ``OPAQUE`` (or unset) ignores alpha,
  ``MASK`` cuts out texels whose alpha is below ``alphaCutoff`` (default
  :data:`~morphkit.conventions.ALPHA_CUTOFF`; a cutoff of 0 is opaque),
  ``BLEND`` is drawn as ``MASK`` at :data:`~morphkit.conventions.ALPHA_CUTOFF`
  (order-independent: no blending).
  ``metallicFactor``/``roughnessFactor`` are kept where set; unset ones are
  morphkit's dielectric ``(0.0, 0.9)`` (an item with a colour), not glTF's
  ``(1.0, 1.0)``, which without an environment light draws nearly black.
  Normal, occlusion, emissive and metallic-roughness textures are not drawn.
* ``TextureVisuals`` with a ``SimpleMaterial`` (OBJ/MTL): the image
  (``map_Kd``) when there is one, else the diffuse colour (``Kd``); the two
  are not multiplied (Blender's reading of MTL; trimesh also reports a missing
  ``Kd`` as grey 0.4, which would darken every texture). OBJ has no alpha
  mode: an image with any alpha below 255 is a cut-out at
  :data:`~morphkit.conventions.ALPHA_CUTOFF`.
* **Vertex colours and a texture on one mesh** (glTF ``COLOR_0`` with a
  textured material; trimesh keeps it as ``visual.vertex_attributes["color"]``):
  both apply, multiplied (glTF's rule above), vertex alpha included.
* A texture without UV coordinates: drawn opaque in the texture's mean
  colour (the mean of its sRGB-encoded texels, decoded; times the factor), with a
  :class:`~morphkit.errors.MeshLookWarning` (an :class:`~morphkit.errors.AssetWarning`:
  filter on that); UVs of another length than the vertices are a
  :class:`~morphkit.errors.MeshError`.
* ``TextureVisuals`` with several materials (``MultiMaterial``): refused
  (split the mesh per material).

Every surface is drawn two-sided (a billboard bake sees the backs of cards);
glTF's ``doubleSided = false`` is not honoured.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import trimesh

from .. import tol
from ..conventions import ALPHA_CUTOFF, DEFAULT_COLOR
from ..errors import MeshError, MeshLookWarning, ValidationError, expected_got
from .parts import srgb_to_linear
from .texture import texture_rgba

__all__ = ["SurfaceLook", "MeshLookWarning", "mesh_look", "look_arrays", "DIELECTRIC"]

#: ``(metallic, roughness)`` of every item drawn with a colour, and of a mesh's own
#: look where its material does not set them.
DIELECTRIC = (0.0, 0.9)


@dataclass(frozen=True, eq=False)
class SurfaceLook:
    """How one mesh's surface is drawn (see the module notes for the rules).

    Parameters
    ----------
    base_color : tuple of 4 float
        Base colour factor, linear RGBA (alpha 1 unless the look is cut out).
    texture : (H, W, 4) uint8 or None
        Base colour texture, sRGB RGBA straight alpha, row 0 the image's top
        (UV ``v = 1``).
    uv : (V, 2) float64 or None
        Texture coordinates per vertex (trimesh's: origin at the image's bottom
        left), present when ``texture`` is.
    vertex_colors : (V, 4) uint8 or None
        Colour per vertex, sRGB RGBA.
    face_colors : (F, 4) uint8 or None
        Colour per face, sRGB RGBA.
    alpha_cutoff : float or None
        Base-colour alpha below which a fragment is a hole; ``None``: opaque
        (every alpha above is then 1 / 255).
    metallic, roughness : float
        PBR factors.
    """

    base_color: tuple[float, float, float, float]
    texture: np.ndarray | None = None
    uv: np.ndarray | None = None
    vertex_colors: np.ndarray | None = None
    face_colors: np.ndarray | None = None
    alpha_cutoff: float | None = None
    metallic: float = DIELECTRIC[0]
    roughness: float = DIELECTRIC[1]

    @property
    def plain(self) -> bool:
        """One opaque colour everywhere: drawn exactly as an item with that colour."""
        return (self.texture is None and self.vertex_colors is None and self.face_colors is None
                and self.alpha_cutoff is None)

    @property
    def masked(self) -> bool:
        """Some fragments may be holes (an alpha cutoff is set)."""
        return self.alpha_cutoff is not None


def _colors_uint8(c: Any, n: int, name: str) -> np.ndarray:
    a = np.asarray(c)
    if a.ndim != 2 or a.shape[0] != n or a.shape[1] not in (3, 4):
        raise MeshError(expected_got(name, f"({n}, 3) or ({n}, 4) colours", f"shape {a.shape}"))
    if np.issubdtype(a.dtype, np.floating):
        if not np.all(np.isfinite(a)):
            raise MeshError(expected_got(name, "finite colours", "NaN or inf"))
        a = np.rint(np.clip(a, 0.0, 1.0) * 255.0)
    elif not np.issubdtype(a.dtype, np.integer):
        raise MeshError(expected_got(name, "integer or float colours", f"dtype {a.dtype}"))
    out = np.full((n, 4), 255, np.uint8)
    out[:, : a.shape[1]] = np.clip(a, 0, 255)
    return out


def _factor(rgba_uint8: Any) -> tuple[float, float, float, float]:
    f = np.asarray(rgba_uint8, dtype=np.float64).reshape(-1)
    if f.size == 3:
        f = np.append(f, 255.0)
    return tuple(float(v) / 255.0 for v in f[:4])  # type: ignore[return-value]


def _opaque(look: SurfaceLook) -> SurfaceLook:
    """Every alpha set to 1: alpha is ignored."""
    tex, vc = look.texture, look.vertex_colors
    if tex is not None:
        tex = tex.copy()
        tex[..., 3] = 255
    if vc is not None:
        vc = vc.copy()
        vc[:, 3] = 255
    fc = None if look.face_colors is None else look.face_colors.copy()
    if fc is not None:
        fc[:, 3] = 255
    return SurfaceLook((*look.base_color[:3], 1.0), tex, look.uv, vc, fc, None, look.metallic, look.roughness)


def _cutoff(value: Any) -> float:
    c = ALPHA_CUTOFF if value is None else float(value)
    if not np.isfinite(c) or not 0.0 <= c <= 1.0:
        raise MeshError(expected_got("material alphaCutoff", "a number in [0, 1]", value))
    return c


#: trimesh's placeholder material (see :func:`_placeholder`): its texel and diffuse colour.
_PLACEHOLDER_TEXEL = np.array([100, 100, 100, 255], np.uint8)
_PLACEHOLDER_DIFFUSE = np.array([102, 102, 102, 255], np.uint8)


def _placeholder(mat: Any) -> bool:
    """trimesh's stand-in for "no material" (``empty_material()``: an OBJ with UVs and no
    material, ``TextureVisuals()``): a 2 x 2 image of grey 100 and the default diffuse."""
    if not isinstance(mat, trimesh.visual.material.SimpleMaterial) or mat.image is None:
        return False
    if not np.array_equal(np.asarray(mat.diffuse), _PLACEHOLDER_DIFFUSE):
        return False
    img = np.asarray(mat.image)
    return img.shape == (2, 2, 4) and bool(np.all(img == _PLACEHOLDER_TEXEL))


def _texture_look(mesh: trimesh.Trimesh, visual: Any) -> SurfaceLook:
    mat = visual.material
    if _placeholder(mat) and "color" not in getattr(visual, "vertex_attributes", {}):
        return SurfaceLook((*DEFAULT_COLOR, 1.0))
    metallic, roughness = DIELECTRIC
    if isinstance(mat, trimesh.visual.material.MultiMaterial):
        raise MeshError(expected_got("mesh material", "one material per mesh (split the mesh per material)",
                                     f"a MultiMaterial of {len(mat.materials)}"))
    if isinstance(mat, trimesh.visual.material.PBRMaterial):
        factor = (1.0, 1.0, 1.0, 1.0) if mat.baseColorFactor is None else _factor(mat.baseColorFactor)
        image = mat.baseColorTexture
        mode = (mat.alphaMode or "OPAQUE").upper()
        if mode not in ("OPAQUE", "MASK", "BLEND"):
            raise MeshError(expected_got("material alphaMode", "OPAQUE, MASK or BLEND", mat.alphaMode))
        cutoff = None if mode == "OPAQUE" else _cutoff(mat.alphaCutoff if mode == "MASK" else None)
        cutoff = None if cutoff == 0.0 else cutoff  # no alpha is below 0: opaque
        if mat.metallicFactor is not None:
            metallic = float(mat.metallicFactor)
        if mat.roughnessFactor is not None:
            roughness = float(mat.roughnessFactor)
    elif isinstance(mat, trimesh.visual.material.SimpleMaterial):
        image = mat.image
        factor = (1.0, 1.0, 1.0, 1.0) if image is not None else (*_factor(mat.diffuse)[:3], 1.0)
        cutoff = None  # decided from the image's alpha below
    else:
        raise MeshError(expected_got("mesh material", "a trimesh PBRMaterial or SimpleMaterial",
                                     type(mat).__name__))
    tex = None if image is None else texture_rgba(image, "mesh texture")
    if isinstance(mat, trimesh.visual.material.SimpleMaterial) and tex is not None \
            and bool(np.any(tex[..., 3] < 255)):
        cutoff = ALPHA_CUTOFF
    nv = len(mesh.vertices)
    uv = visual.uv
    if tex is not None and (uv is None or len(uv) == 0):
        mean = tex.reshape(-1, 4).astype(np.float64).mean(0) / 255.0
        warnings.warn("mesh has a texture but no UV coordinates: drawn in the texture's mean colour "
                      f"{np.round(mean[:3], 3).tolist()} (give the mesh UVs, or an Item colour)",
                      MeshLookWarning, stacklevel=3)
        # the mean texel is sRGB-encoded, the factor linear (as meshes.parts merges such a part)
        mean[:3] = srgb_to_linear(mean[:3])
        factor = tuple(float(f * m) for f, m in zip(factor, mean, strict=True))  # type: ignore[assignment]
        tex, uv, cutoff = None, None, None
    if tex is not None:
        uv = np.asarray(uv, dtype=np.float64)
        if uv.shape != (nv, 2) or not np.all(np.isfinite(uv)):
            raise MeshError(expected_got("mesh UV coordinates", f"({nv}, 2) finite values",
                                         f"shape {uv.shape}" if uv.shape != (nv, 2) else "NaN or inf"))
    else:
        uv = None
    vc = visual.vertex_attributes.get("color") if hasattr(visual, "vertex_attributes") else None
    vc = None if vc is None else _colors_uint8(vc, nv, "mesh vertex colours")
    look = SurfaceLook(factor, tex, uv, vc, None, cutoff, metallic, roughness)
    return _opaque(look) if cutoff is None else look


def mesh_look(mesh: trimesh.Trimesh) -> SurfaceLook:
    """The look of ``mesh`` as drawn when an item gives no colour (rules: module notes).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh, with ``ColorVisuals`` or ``TextureVisuals``.

    Returns
    -------
    SurfaceLook
        Its look; :attr:`SurfaceLook.plain` with :data:`~morphkit.conventions.DEFAULT_COLOR`
        when the mesh has no visuals.

    Raises
    ------
    MeshError
        Malformed visuals (UVs or colours of the wrong length, NaN, an unknown material,
        several materials).
    ValidationError
        A texture over the size limits (:func:`morphkit.meshes.texture.texture_rgba`).
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise ValidationError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
    visual = mesh.visual
    if isinstance(visual, trimesh.visual.TextureVisuals):
        return _texture_look(mesh, visual)
    kind = getattr(visual, "kind", None)
    plain = (*DEFAULT_COLOR, 1.0)
    if kind == "vertex":
        vc = _colors_uint8(visual.vertex_colors, len(mesh.vertices), "mesh vertex colours")
        return _opaque(SurfaceLook((1.0, 1.0, 1.0, 1.0), vertex_colors=vc))
    if kind == "face":
        fc = _colors_uint8(visual.face_colors, len(mesh.faces), "mesh face colours")
        return _opaque(SurfaceLook((1.0, 1.0, 1.0, 1.0), face_colors=fc))
    return SurfaceLook(plain)  # type: ignore[arg-type]


def look_arrays(mesh: trimesh.Trimesh, look: SurfaceLook, *, smooth: bool) -> dict[str, Any]:
    """The arrays one GL primitive draws ``mesh`` in ``look`` with (:mod:`morphkit.render`, "Materials").

    A cut-out without a texture gets a 1 x 1 white one (the shader's alpha test needs a texel);
    a cut-out's factor alpha is scaled by ``0.5 / cutoff``, so that one shader test
    (alpha < 0.5) serves every cutoff.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The geometry.
    look : SurfaceLook
        Its look (:func:`mesh_look`).
    smooth : bool
        Shared vertices with vertex normals (indexed), else three vertices per face with the face's
        normal (face colours need the latter).

    Returns
    -------
    dict of str to Any
        ``positions``, ``normals`` (float32 ``(V, 3)``), ``indices`` (``(F, 3)`` or None), ``uv``
        (float32 ``(V, 2)`` or None), ``colors`` (float32 RGBA in ``[0, 1]``, sRGB, or None),
        ``texture`` (RGBA uint8 or None) and ``factor`` (the base colour factor, 4 floats).
    """
    faces = np.asarray(mesh.faces)
    if smooth:
        positions, normals, indices = mesh.vertices, mesh.vertex_normals, faces
        per_vertex = (lambda a: a)  # noqa: E731
    else:
        positions = mesh.vertices[faces].reshape(-1, 3)
        normals = np.repeat(mesh.face_normals, 3, axis=0)
        indices = None
        per_vertex = (lambda a: a[faces].reshape(-1, a.shape[1]))  # noqa: E731
    colors = None
    if look.vertex_colors is not None:
        colors = per_vertex(look.vertex_colors)
    elif look.face_colors is not None:
        colors = np.repeat(look.face_colors, 3, axis=0)
    texture, uv = look.texture, look.uv
    if texture is None and look.masked:  # a cut-out without a texture: the shader's alpha test
        texture, uv = np.full((1, 1, 4), 255, np.uint8), np.zeros((len(mesh.vertices), 2))
    factor = list(look.base_color)
    if look.masked:  # one shader test (alpha < 0.5) for every cutoff
        factor[3] *= 0.5 / max(float(look.alpha_cutoff), tol.ALPHA_FLOOR)
    return {"positions": np.asarray(positions, np.float32), "normals": np.asarray(normals, np.float32),
            "indices": indices, "uv": None if uv is None else np.asarray(per_vertex(uv), np.float32),
            "colors": None if colors is None else colors.astype(np.float32) / 255.0,
            "texture": texture, "factor": factor}
