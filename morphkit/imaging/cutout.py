"""Cut-out alpha at points on a mesh's surface, sampled as the renderer samples it.

A mesh whose look (:func:`morphkit.meshes.look.mesh_look`) has an alpha cutoff (glTF
``alphaMode`` ``MASK``, e.g. a leaf card) is a hole wherever its base-colour
alpha is below the cutoff. The renderer discards those fragments (light-view
depth maps have holes there); the ray-cast truth (:mod:`morphkit.imaging.groundtruth`)
asks this module, for each hit (triangle and barycentrics), whether the texel
is opaque. The alpha is the renderer's:

    alpha = base colour factor alpha x texture alpha(uv) x vertex colour alpha

a fragment is a hole where ``alpha < cutoff`` (glTF's rule; the renderer's
shader tests the same inequality, see :mod:`morphkit.render`).

Sampling, as OpenGL samples the uploaded texture (``pyrender.Sampler()``'s
defaults): **bilinear on texel centres** (``GL_LINEAR``) with **repeat** wrapping,
UV ``(u, v)`` with ``v = 1`` the image's top row (trimesh's convention, the one
:class:`~morphkit.meshes.look.SurfaceLook` stores): image column ``x = u W - 1/2``, row
``y = (1 - v) H - 1/2``, texel ``(row r, column c)`` centred at integer ``(c, r)``.
UV and vertex alpha are interpolated with the hit's barycentrics (OpenGL's
perspective-correct interpolation is the same interpolation on the 3-D triangle).
One difference is left: when a texture is minified on screen, OpenGL samples its
mipmaps (``GL_LINEAR_MIPMAP_LINEAR``: alpha averaged over a larger footprint), a ray
samples level 0. Cut-out edges of a depth map coarser than the texture can
therefore sit up to about one depth-map pixel away from the ray-cast edge.

Textured looks are read once per mesh (:func:`cached_look`, an LRU of
:data:`LOOK_CACHE_SIZE` meshes keyed by the mesh and its visual objects, like the
renderer's uploads; the cache holds them): a texture edited in place afterwards is
not seen. Other meshes' looks (no texture to decode) are read each time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from ..errors import ValidationError, expected_got
from ..memo import Memo
from ..meshes.look import SurfaceLook, mesh_look

__all__ = ["Cutout", "sample_texture", "mesh_cutout", "cached_look", "LOOK_CACHE_SIZE"]

#: Meshes whose looks (and cut-outs) are kept (:func:`cached_look`).
LOOK_CACHE_SIZE = 32


def sample_texture(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Bilinear samples of ``image`` at texture coordinates ``uv``, as OpenGL's
    ``GL_LINEAR`` with ``GL_REPEAT`` (module notes: texel centres, ``v = 1`` the top row).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array
        The texture, row 0 its top.
    uv : (N, 2) float
        Texture coordinates.

    Returns
    -------
    (N,) or (N, C) float64
        The samples, in ``image``'s units.

    Examples
    --------
    A 2 x 2 image: ``(0.25, 0.75)`` is the centre of the top-left texel, ``(0.5, 0.5)``
    the mean of all four, ``(0, 0.75)`` halfway between the top row's two texels
    (repeat wrapping: left of column 0 lies column 1).

    >>> import numpy as np
    >>> from morphkit.imaging.cutout import sample_texture
    >>> img = np.array([[0.0, 1.0], [2.0, 3.0]])
    >>> sample_texture(img, np.array([[0.25, 0.75], [0.5, 0.5], [0.0, 0.75]]))
    array([0. , 1.5, 0.5])
    """
    img = np.asarray(image)
    if img.ndim not in (2, 3) or img.shape[0] < 1 or img.shape[1] < 1:
        raise ValidationError(expected_got("image", "an (H, W) or (H, W, C) array", f"shape {img.shape}"))
    uv = np.asarray(uv, dtype=np.float64)
    if uv.ndim != 2 or uv.shape[1] != 2:
        raise ValidationError(expected_got("uv", "an (N, 2) array", f"shape {uv.shape}"))
    H, W = img.shape[:2]
    x = uv[:, 0] * W - 0.5
    y = (1.0 - uv[:, 1]) * H - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = x - x0, y - y0
    c0, r0 = np.mod(x0.astype(np.int64), W), np.mod(y0.astype(np.int64), H)
    c1, r1 = np.mod(c0 + 1, W), np.mod(r0 + 1, H)
    img = img.astype(np.float64, copy=False)
    if img.ndim == 3:
        fx, fy = fx[:, None], fy[:, None]
    top = img[r0, c0] * (1 - fx) + img[r0, c1] * fx
    bottom = img[r1, c0] * (1 - fx) + img[r1, c1] * fx
    return top * (1 - fy) + bottom * fy


@dataclass(frozen=True, eq=False)
class Cutout:
    """The alpha test of one cut-out mesh (module notes).

    Parameters
    ----------
    faces : (F, 3) int
        The mesh's faces.
    cutoff : float
        Alpha below which a point is a hole.
    factor_alpha : float
        Base colour factor alpha.
    texture_alpha : (H, W) float64 or None
        Texture alpha in ``[0, 1]``, row 0 the image's top.
    uv : (V, 2) float64 or None
        Texture coordinates per vertex (present with ``texture_alpha``).
    vertex_alpha : (V,) float64 or None
        Vertex colour alpha in ``[0, 1]``.
    """

    faces: np.ndarray
    cutoff: float
    factor_alpha: float = 1.0
    texture_alpha: np.ndarray | None = None
    uv: np.ndarray | None = None
    vertex_alpha: np.ndarray | None = None

    @classmethod
    def from_look(cls, mesh: trimesh.Trimesh, look: SurfaceLook) -> Cutout | None:
        """The cut-out of ``mesh`` drawn in ``look``; ``None`` when the look is not cut out.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The mesh (its faces index ``look``'s per-vertex arrays).
        look : SurfaceLook
            Its look.

        Returns
        -------
        Cutout or None
            The alpha test, or ``None`` (every point opaque).
        """
        if not look.masked:
            return None
        tex = None if look.texture is None else look.texture[..., 3].astype(np.float64) / 255.0
        va = None if look.vertex_colors is None else look.vertex_colors[:, 3].astype(np.float64) / 255.0
        return cls(np.asarray(mesh.faces), float(look.alpha_cutoff), float(look.base_color[3]), tex,
                   None if tex is None else np.asarray(look.uv, np.float64), va)

    def alpha(self, tri: np.ndarray, bary: np.ndarray) -> np.ndarray:
        """Base-colour alpha at points given by triangle index and barycentrics.

        Parameters
        ----------
        tri : (N,) int
            Face index of each point.
        bary : (N, 3) float
            Barycentric coordinates of each point in its face.

        Returns
        -------
        (N,) float64
            Alpha in ``[0, 1]``.
        """
        tri = np.asarray(tri, dtype=np.int64)
        bary = np.asarray(bary, dtype=np.float64)
        a = np.full(len(tri), self.factor_alpha)
        corners = self.faces[tri]  # (N, 3) vertex ids
        if self.texture_alpha is not None and self.uv is not None:
            uv = np.einsum("nk,nkj->nj", bary, self.uv[corners])
            a = a * sample_texture(self.texture_alpha, uv)
        if self.vertex_alpha is not None:
            a = a * np.einsum("nk,nk->n", bary, self.vertex_alpha[corners])
        return a

    def opaque(self, tri: np.ndarray, bary: np.ndarray) -> np.ndarray:
        """Whether each point is opaque (``alpha >= cutoff``), not a hole.

        Parameters
        ----------
        tri : (N,) int
            Face index of each point.
        bary : (N, 3) float
            Barycentric coordinates of each point in its face.

        Returns
        -------
        (N,) bool
            ``True`` where opaque.
        """
        return self.alpha(tri, bary) >= self.cutoff


_LOOKS: Memo[tuple[int, int, int], tuple[trimesh.Trimesh, object, object, SurfaceLook, Cutout | None]] = \
    Memo(LOOK_CACHE_SIZE)


def _entry(mesh: trimesh.Trimesh) -> tuple[trimesh.Trimesh, object, object, SurfaceLook, Cutout | None]:
    if not isinstance(mesh, trimesh.Trimesh):
        raise ValidationError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
    visual = mesh.visual
    material = getattr(visual, "material", None)
    # the entry holds the mesh, visual and material, so their ids are not reused while it is cached
    key = (id(mesh), id(visual), id(material))

    def make() -> tuple[trimesh.Trimesh, object, object, SurfaceLook, Cutout | None]:
        look = mesh_look(mesh)
        return mesh, visual, material, look, Cutout.from_look(mesh, look)

    return _LOOKS.get(key, make)


def cached_look(mesh: trimesh.Trimesh) -> SurfaceLook:
    """:func:`morphkit.meshes.look.mesh_look` of ``mesh``, read once for a textured mesh (module notes).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh.

    Returns
    -------
    SurfaceLook
        Its look.
    """
    if not isinstance(mesh, trimesh.Trimesh) or not isinstance(mesh.visual, trimesh.visual.TextureVisuals):
        return mesh_look(mesh)  # nothing to decode (or mesh_look's refusal)
    return _entry(mesh)[3]


def mesh_cutout(mesh: trimesh.Trimesh) -> Cutout | None:
    """The alpha test of ``mesh``'s own look; ``None`` when it has no cut-outs.

    Only ``TextureVisuals`` can be cut out (:mod:`morphkit.meshes.look`: vertex and face colours
    of ``ColorVisuals`` are drawn opaque), so any other mesh is answered ``None`` without
    reading its look.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh.

    Returns
    -------
    Cutout or None
        Its alpha test, or ``None``.

    Raises
    ------
    ValidationError
        ``mesh`` is not a ``trimesh.Trimesh``; a texture over the size limits.
    MeshError
        Visuals :func:`morphkit.meshes.look.mesh_look` refuses (the renderer refuses them too).

    Examples
    --------
    A quad whose texture is opaque in its left half only:

    >>> import numpy as np, trimesh
    >>> from PIL import Image
    >>> from morphkit.imaging.cutout import mesh_cutout
    >>> rgba = np.full((2, 2, 4), 255, np.uint8); rgba[:, 1, 3] = 0
    >>> mat = trimesh.visual.material.PBRMaterial(baseColorTexture=Image.fromarray(rgba), alphaMode="MASK")
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> quad = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]],
    ...                        visual=trimesh.visual.TextureVisuals(uv=uv, material=mat), process=False)
    >>> cut = mesh_cutout(quad)
    >>> cut.opaque(np.array([0, 0]), np.array([[0.8, 0.2, 0.0], [0.2, 0.8, 0.0]]))  # x = 0.2, x = 0.8
    array([ True, False])
    >>> mesh_cutout(trimesh.creation.box()) is None
    True
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise ValidationError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
    if not isinstance(mesh.visual, trimesh.visual.TextureVisuals):
        return None
    return _entry(mesh)[4]
