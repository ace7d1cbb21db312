"""Billboard assets: reference views of one mesh on a ring, and the view morphs between them.

An asset holds, for one (normalised) mesh, ``K`` reference views rendered on a
:class:`~morphkit.billboard.ring.ViewRing` by the camera rule of
:class:`~morphkit.billboard.cameras.QuadCameras` (premultiplied RGBA and linear
depth), a front view for the classic billboard, and for each pair of
neighbouring references the correspondences their view morph needs. Every
image it returns -- a reference, a morph at any ``s``, a crossfade -- is in the
image frame of the camera of the rule at its azimuth, so it maps onto the
billboard quad by one rule (:mod:`.cameras`): the quad's geometry does not
depend on ``s`` or on the level.

The morph
---------
For a pair ``(i, j)`` and ``s`` in ``(0, 1)``: a
:class:`~morphkit.viewmorph.ViewMorpher` of the two references with dense
correspondences from their depth maps (:func:`~morphkit.viewmorph.from_depth`),
plus each view's outline points the other does not see (:data:`~.baking.ringviews.RIM_STEP`),
F estimated from them, the pre-warps, and depth layers where parts cross
(:data:`DEFAULT_LAYERS`, keys from :func:`~morphkit.viewmorph.pair_depth`; a layer's
pixels hidden by a nearer layer in one view are filled from the other view,
``fill_occluded=True``), morphed
at ``s`` and post-warped to the in-between camera
(:meth:`~morphkit.billboard.QuadCameras.chord_camera`: centre ``(1 - s) C_i + s C_j``,
image plane and quad by the rule; ``post=camera``, the least-squares homography
taking the morphed correspondences to their projections in that camera -- exact
in theory, since the morph is the view from that centre). ``s`` is the chord
fraction of :mod:`.ring`. At ``s = 0`` and ``s = 1`` exactly, the reference
itself is returned (no resampling).

Alpha from depth
----------------
A part only one reference sees (a flank turning away, a leg passing behind the
body) has no partner in the other view, and the view morph cross-dissolves it
with the other view's background: half-transparent lobes where the object is
not, a thinned object where it is. By default (``morph(..., coverage=True)``)
the colour comes from the view morph and the alpha from the references' depth:
both references' object pixels projected into the in-between camera
(:meth:`BillboardAsset.coverage`, :mod:`.coverage`). Pixels wholly inside that
coverage are opaque, pixels wholly outside it clear, and outline pixels keep
the morph's anti-aliased alpha (so just off a reference the morph is still that
reference); a pixel where the morph has no colour to show (alpha at most
:data:`tol.BB_COVERAGE_MIN_ALPHA`) stays clear. ``coverage=False`` is the paper's
view morph alone (a bench row).

Level of detail
---------------
Level ``l`` (``0 <= l < levels``) images have shape ``cameras.level_shape(l)``,
about ``2^-l`` of level 0: the premultiplied references area-averaged
(``cv2.resize``, ``INTER_AREA``, which keeps the image's edges on the quad's
edges). A level's morpher uses the level-0 correspondences projected into the
level's cameras, thinned to ``4^-l`` of them (spread over the image,
:func:`~morphkit.viewmorph.from_geometry`), and the depth keys resized
(nearest). **The bake builds every pair's level-0 morpher**, so a pair that
cannot be morphed is refused there, never at frame time; the other levels, and
every morpher of a loaded asset (from the same stored data), are built
**lazily** on first use, or all at once by :meth:`BillboardAsset.prepare`. A
lower level whose morpher cannot be built falls back to the level-0 morph,
area-averaged (:attr:`BillboardAsset.level_fallbacks`).

Appearance and lighting
-----------------------
The bake (:mod:`morphkit.billboard.baking.ringviews`) renders :func:`bake_items` in one of
:data:`APPEARANCES`: ``"own"`` (the default) is the mesh's own look --
textures, vertex and face colours, material factors, cut-outs
(:func:`morphkit.meshes.look.mesh_look`; a mesh without visuals is
:data:`~morphkit.conventions.DEFAULT_COLOR`); ``"checker"`` is morphkit's 3-D
checker (:func:`morphkit.imaging.appearance.checker_items`), texture for matching and
PSNR on meshes without a look of their own (the benches' choice). The
references, the morphs' colours and the alpha from depth all come from the same
renders, so a cut-out texel is a hole in colour, depth and coverage alike. The
asset records its appearance (:attr:`BillboardAsset.appearance`) and its
:func:`mesh_hash` covers the look, so a ground truth drawn with
:meth:`BillboardAsset.items` shows the look the asset was baked in.

Everything is lit by :func:`bake_lights` (one directional light straight down)
with ambient :data:`BAKE_AMBIENT`: the lighting does not depend on the view or
on an instance's yaw, so a ground truth rendered from any direction with the
same items and lights matches. Shading model of a one-colour (linear ``c``)
Lambertian surface with unit normal ``n``: pyrender's lit colour
``c (BAKE_AMBIENT + I max(0, n_z) / pi)`` (``I = 3``, the light's
intensity; pyrender's metallic-roughness BRDF adds a small specular term), in
linear light, encoded with gamma ``1/2.2`` (:mod:`morphkit.conventions`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel
from ..errors import (
    DegenerateViewError,
    FileFormatError,
    GeometryError,
    MeshError,
    ValidationError,
    expected_got,
)
from ..imaging.composite import from_premultiplied, to_premultiplied
from ..memo import Memo
from ..meshes import normalize
from ..scene import Item
from ..validate import as_flag, as_int
from ..viewmorph import Correspondences, ViewMorpher, from_geometry, pair_depth
from .baking.bakelook import (
    BAKE_AMBIENT,
    bake_items,
    bake_lights,
    check_appearance,
    check_source_up,
    look_hash,
    mesh_hash,
)
from .cameras import QuadCameras
from .coverage import object_points, splat_coverage
from .formats.assetfile import APPEARANCES, AssetRecord, read_record, write_record
from .ring import ViewRing

__all__ = ["BillboardAsset", "mesh_hash", "look_hash", "bake_items", "bake_lights", "BAKE_AMBIENT",
           "DEFAULT_LAYERS", "APPEARANCES", "check_appearance", "check_source_up", "check_levels"]

#: ``ViewMorpher(layers=...)`` of the assets' morphs: three depth layers. Neighbouring
#: references 30-60 degrees apart see parts pass behind each other for every sample
#: mesh, so ``"auto"`` always layered (with two); three followed the crossings better
#: (``morphkit bench billboards``; docs/RESULTS.md).
DEFAULT_LAYERS: int | str = 3


def _unit_premultiplied(rgba: np.ndarray) -> np.ndarray:
    """uint8 straight RGBA -> premultiplied float32 RGBA, colour and alpha in [0, 1]."""
    p = to_premultiplied(rgba, 4)  # colour in 0..255 times alpha, alpha in [0, 1]
    p[..., :3] *= np.float32(1.0 / 255.0)
    return p


def check_levels(levels: Any, cameras: QuadCameras) -> int:
    """``levels`` as an int >= 1 whose smallest level is at least 8 px on a side.

    Parameters
    ----------
    levels : int
        Pyramid levels asked for.
    cameras : QuadCameras
        The camera rule (its level shapes).

    Returns
    -------
    int
        ``levels``.

    Raises
    ------
    ValidationError
        Not an int >= 1, or its smallest level under 8 px.
    """
    levels = as_int(levels, "levels", lo=1)
    if min(cameras.level_shape(levels - 1)) < 8:
        raise ValidationError(expected_got("levels", "levels whose smallest image is >= 8 px",
                                           f"{levels} levels of {cameras.shape}"))
    return levels


def _check_level(level: Any, levels: int) -> int:
    return as_int(level, "level", lo=0, hi=levels - 1)


def _check_s(s: Any) -> float:
    try:
        v = float(s)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got("s", "a number in [0, 1]", repr(s))) from exc
    if not 0.0 <= v <= 1.0:
        raise ValidationError(expected_got("s", "a number in [0, 1]", v))
    return v


class BillboardAsset:
    """One mesh's reference views, front view and pair morphs (see the module docstring).

    Build one with :func:`~.baking.ringviews.bake_asset` or :meth:`load`; the constructor takes the
    stored data (an :class:`~morphkit.billboard.formats.assetfile.AssetRecord`).

    Parameters
    ----------
    record : AssetRecord
        The stored data, as read by :func:`~morphkit.billboard.formats.assetfile.read_record`.

    Attributes
    ----------
    name : str
    mesh_hash : str
        :func:`mesh_hash` of the mesh the asset was baked from (shape and look).
    appearance : str
        The look it was baked in (:data:`APPEARANCES`); :meth:`items` draws a mesh in it.
    source_up : str or None
        The up axis its mesh file was loaded with (``"z"`` or ``"y"``), None when not known.
    ring : ViewRing
    cameras : QuadCameras
        The camera rule and quad.
    levels : int
        Pyramid levels (level ``l``: ``cameras.level_shape(l)``).
    layers : int or "auto"
        ``ViewMorpher(layers=...)`` of the morphs.
    """

    def __init__(self, record: AssetRecord) -> None:
        self.name = record.name
        if not self.name:
            raise ValidationError(expected_got("name", "a non-empty string", repr(self.name)))
        self.mesh_hash = record.mesh_hash
        self.appearance = check_appearance(record.appearance)
        self.source_up = check_source_up(record.source_up)
        self.ring = ViewRing(record.ring["views"], record.ring["arc_deg"], record.ring["elevation_deg"])
        q = record.quad
        self.cameras = QuadCameras(np.asarray(q["pivot"], dtype=np.float64), q["distance"],
                                   q["elevation_deg"], tuple(q["half_extent"]), tuple(q["shape"]))
        if self.cameras.elevation_deg != self.ring.elevation_deg:
            raise ValidationError(expected_got("quad elevation", f"the ring's {self.ring.elevation_deg}",
                                               self.cameras.elevation_deg))
        if [tuple(p) for p in record.pairs] != self.ring.pairs():
            raise ValidationError(expected_got("pairs", self.ring.pairs(), record.pairs))
        self.levels = check_levels(record.levels, self.cameras)
        if not (record.layers == "auto" or (isinstance(record.layers, int) and record.layers >= 1)):
            raise ValidationError(expected_got("layers", "an int >= 1 or 'auto'", repr(record.layers)))
        self.layers = record.layers
        k = self.ring.views
        h, w = self.cameras.shape
        if record.images.shape != (k, h, w, 4) or record.images.dtype != np.uint8:
            raise ValidationError(expected_got("images", f"uint8 ({k}, {h}, {w}, 4)",
                                               f"{record.images.dtype} {record.images.shape}"))
        if record.depth.shape != (k, h, w):
            raise ValidationError(expected_got("depth", f"({k}, {h}, {w})", record.depth.shape))
        self._record = record
        az = self.ring.azimuths_deg()
        self._front_view = int(record.front_view)
        if self._front_view >= 0 and az[self._front_view] != 0.0:
            raise ValidationError(expected_got("front_view", "a reference at azimuth 0",
                                               f"view {self._front_view} at {az[self._front_view]}"))
        # premultiplied float32 pyramids, read-only: [level] -> (K, h, w, 4); front: [level] -> (h, w, 4)
        base = np.stack([_unit_premultiplied(im) for im in record.images])
        self._prem = [self._pyramid_level(base, lv) for lv in range(self.levels)]
        if self._front_view < 0:
            fb = _unit_premultiplied(record.front)
            self._front = [self._pyramid_level(fb[None], lv)[0] for lv in range(self.levels)]
        else:
            self._front = [p[self._front_view] for p in self._prem]
        self._depth = np.asarray(record.depth, dtype=np.float32)
        offs = record.offsets
        self._points = [np.asarray(record.points3d[offs[p]:offs[p + 1]], dtype=np.float64)
                        for p in range(len(self.ring.pairs()))]
        self._morphers: dict[tuple[int, int], ViewMorpher] = {}
        self._cams: Memo[tuple[int, int], CameraModel] = Memo()  # (reference, level) -> camera
        self._obj_points: Memo[int, np.ndarray] = Memo()  # level-0 surface points of each reference
        #: (pair, level) whose morpher could not be built: those morphs are the level-0 morph
        #: area-averaged (never seen on the bench meshes; see :meth:`morph`).
        self.level_fallbacks: set[tuple[int, int]] = set()
        #: (pair, level) -> the depth layers its morpher was built with, where the asset's
        #: ``layers`` could not be (a slice whose pairs all fold over; see :meth:`morpher`).
        self.layer_fallbacks: dict[tuple[int, int], int | str] = {}

    # ------------------------------------------------------------------ data
    def _pyramid_level(self, base: np.ndarray, level: int) -> np.ndarray:
        if level == 0:
            out = np.ascontiguousarray(base, dtype=np.float32)
        else:
            h, w = self.cameras.level_shape(level)
            out = np.stack([cv2.resize(b, (w, h), interpolation=cv2.INTER_AREA) for b in base])
        out.setflags(write=False)
        return out

    @property
    def size(self) -> tuple[int, int]:
        """``(H, W)`` of the level-0 images."""
        return self.cameras.shape

    @property
    def half_extent(self) -> tuple[float, float]:
        """``(half_width, half_height)`` of the billboard quad, scene units (object frame)."""
        return self.cameras.half_extent

    @property
    def pivot(self) -> np.ndarray:
        """``(3,)`` quad centre in the object frame."""
        return self.cameras.pivot

    @property
    def image_bytes(self) -> int:
        """Bytes of the colour images at 8 bits per channel (RGBA), all levels: the references
        and, when it is not one of them, the front view (what a texture memory would hold)."""
        n = sum(4 * self.ring.views * int(np.prod(self.cameras.level_shape(lv))) for lv in range(self.levels))
        if self._front_view < 0:
            n += sum(4 * int(np.prod(self.cameras.level_shape(lv))) for lv in range(self.levels))
        return n

    @property
    def memory_bytes(self) -> int:
        """Bytes of the asset's data at its storage precision: :attr:`image_bytes`, plus the
        float16 depth maps (level 0) and the float32 correspondence points its morphs are
        built from. (Built morphers hold more; they are caches.)"""
        rec = self._record
        return self.image_bytes + int(rec.depth.nbytes) + int(rec.points3d.nbytes) + int(rec.offsets.nbytes)

    def camera(self, azimuth_deg: float, level: int = 0) -> CameraModel:
        """The camera of the view the asset shows for a viewing azimuth, at ``level``.

        ``ring.pair(azimuth_deg)`` gives ``(i, j, s)``; this is the in-between camera of that
        morph (:meth:`QuadCameras.chord_camera`), the frame of :meth:`morph` ``(i, j, s)``
        (render the mesh with it for a ground truth). For ``K = 2`` outside the arc, the
        clamped reference's camera (the true view from there is ``cameras.camera(azimuth_deg)``).

        Parameters
        ----------
        azimuth_deg : float
            Viewing azimuth, degrees, object frame.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        CameraModel
            The camera of the view shown, object frame, images of ``cameras.level_shape(level)``.
        """
        level = _check_level(level, self.levels)
        i, j, s, _ = self.ring.pair(azimuth_deg)
        az = self.ring.azimuths_deg()
        return self.cameras.chord_camera(az[i], az[j], s, level)

    def reference(self, k: int, level: int = 0) -> np.ndarray:
        """Reference view ``k``: premultiplied RGBA float32 ``(h, w, 4)`` in [0, 1], read-only.

        Parameters
        ----------
        k : int
            Reference view index.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA, read-only.
        """
        k = as_int(k, "view index k", lo=0, hi=self.ring.views - 1)
        return self._prem[_check_level(level, self.levels)][k]

    def classic(self, level: int = 0) -> np.ndarray:
        """The front view (azimuth 0): the classic billboard's one image for every direction.
        Premultiplied RGBA float32 ``(h, w, 4)`` in [0, 1], read-only.

        Parameters
        ----------
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA, read-only.
        """
        return self._front[_check_level(level, self.levels)]

    def crossfade(self, i: int, j: int, s: float, level: int = 0) -> np.ndarray:
        """Baseline: ``(1 - s) reference(i) + s reference(j)`` (premultiplied), new float32 array.

        Parameters
        ----------
        i, j : int
            Reference view indices.
        s : float
            Blend weight of ``j``, in ``[0, 1]``.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA.
        """
        i, j = self.ring.check_pair(i, j)
        s = _check_s(s)
        return cv2.addWeighted(self.reference(i, level), 1.0 - s, self.reference(j, level), s, 0.0)

    def nearest(self, i: int, j: int, s: float, level: int = 0) -> np.ndarray:
        """Baseline: the nearer reference (``i`` for ``s <= 1/2``), read-only.

        Parameters
        ----------
        i, j : int
            Reference view indices.
        s : float
            Fraction in ``[0, 1]`` from ``i`` to ``j``.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA, read-only.
        """
        i, j = self.ring.check_pair(i, j)
        return self.reference(i if _check_s(s) <= 0.5 else j, level)

    def morph(self, i: int, j: int, s: float, level: int = 0, *, coverage: bool = True) -> np.ndarray:
        """The view at fraction ``s`` from reference ``i`` to ``j`` (neighbours; either order).

        Parameters
        ----------
        i, j : int
            Neighbouring references (:meth:`ViewRing.pairs`, or reversed).
        s : float
            In [0, 1], the chord fraction (:mod:`.ring`); the view's azimuth is
            ``ring.pair_azimuth_deg(i, j, s)`` and its camera ``cameras.chord_camera``.
        level : int
            Pyramid level.
        coverage : bool
            Take the alpha from the references' depth (:meth:`coverage`) and the colour from
            the view morph (default); False: the paper's view morph alone, alpha included.

        Returns
        -------
        numpy.ndarray
            Premultiplied RGBA float32 ``(h, w, 4)`` in [0, 1] (a new array) in the frame of
            :meth:`camera` at that azimuth and level; exactly :meth:`reference` at ``s = 0, 1``.

        Raises
        ------
        ValidationError
            Not neighbours, ``s`` outside [0, 1], a bad level.

        Notes
        -----
        The first morph of a (pair, level) builds its morpher (the bake builds level 0;
        :meth:`prepare` builds the rest ahead). A level whose morpher cannot be built --
        its level-0 morpher was built at bake time, from the same points -- falls back to
        the level-0 morph, area-averaged, and is listed in :attr:`level_fallbacks`:
        never an error at frame time.
        """
        i, j = self.ring.check_pair(i, j)
        s = _check_s(s)
        level = _check_level(level, self.levels)
        coverage = as_flag(coverage, "coverage")
        if (i, j) not in self.ring.pairs():
            i, j, s = j, i, 1.0 - s
        if s == 0.0:
            return self.reference(i, level).copy()
        if s == 1.0:
            return self.reference(j, level).copy()
        p = self.ring.pairs().index((i, j))
        if level > 0 and (p, level) not in self.level_fallbacks:
            try:
                self.morpher(p, level)
            except DegenerateViewError:  # level 0 of this pair was built at bake time
                self.level_fallbacks.add((p, level))
        if (p, level) in self.level_fallbacks:
            h, w = self.cameras.level_shape(level)
            return cv2.resize(self.morph(i, j, s, 0, coverage=coverage), (w, h), interpolation=cv2.INTER_AREA)
        vm = self.morpher(p, level)
        az = self.ring.azimuths_deg()
        cam = self.cameras.chord_camera(az[i], az[j], s, level)
        out = to_premultiplied(vm.morph(s, post=cam, frame="fixed"), 4)
        if not coverage:
            return out
        cov = self._coverage(i, j, cam)
        alpha = out[..., 3:]
        has_colour = alpha > np.float32(tol.BB_COVERAGE_MIN_ALPHA)
        # wholly inside the object: opaque; wholly outside: clear; on the outline (coverage
        # between): the morph's own anti-aliased alpha (exact at the references)
        c = cov[..., None]
        inside = np.where(c >= 1.0, np.float32(1.0), np.where(c <= 0.0, np.float32(0.0), alpha))
        new_alpha = np.where(has_colour, inside, np.float32(0.0))
        out[..., :3] *= new_alpha / np.where(has_colour, alpha, np.float32(1.0))
        out[..., 3:] = new_alpha
        return out

    def coverage(self, i: int, j: int, s: float, level: int = 0) -> np.ndarray:
        """Where the object is in the view :meth:`morph` ``(i, j, s, level)`` shows: both
        references' object pixels (their depth maps) projected into its camera
        (:func:`~morphkit.billboard.coverage.splat_coverage`).

        Parameters
        ----------
        i, j : int
            Neighbouring references.
        s : float
            In [0, 1], the chord fraction.
        level : int
            Pyramid level.

        Returns
        -------
        (h, w) float32
            Coverage in [0, 1] of ``cameras.level_shape(level)``.
        """
        i, j = self.ring.check_pair(i, j)
        s = _check_s(s)
        level = _check_level(level, self.levels)
        az = self.ring.azimuths_deg()
        return self._coverage(i, j, self.cameras.chord_camera(az[i], az[j], s, level))

    def _coverage(self, i: int, j: int, camera: CameraModel) -> np.ndarray:
        return splat_coverage(np.concatenate([self._object_points(i), self._object_points(j)]), camera)

    def _object_points(self, k: int) -> np.ndarray:
        return self._obj_points.get(k, lambda: object_points(self._ref_camera(k, 0), self._depth[k]))

    # ------------------------------------------------------------------ morphers
    def correspondences(self, pair: int, level: int = 0) -> Correspondences:
        """The correspondences of ``ring.pairs()[pair]`` at ``level``: the stored points
        projected into the pair's level cameras (thinned to ``4^-level`` of them).

        Parameters
        ----------
        pair : int
            Index into ``ring.pairs()``.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        Correspondences
            Matched pixels of the pair's two level views.
        """
        pairs = self.ring.pairs()
        pair = as_int(pair, "pair", lo=0, hi=len(pairs) - 1)
        level = _check_level(level, self.levels)
        i, j = pairs[int(pair)]
        ci, cj = self._ref_camera(i, level), self._ref_camera(j, level)
        pts = self._points[int(pair)]
        n = len(pts) if level == 0 else max(tol.BB_MIN_CORRESPONDENCES, math.ceil(len(pts) / 4**level))
        return from_geometry(pts, ci, cj, max_points=n, rng=np.random.default_rng(0))

    def morpher(self, pair: int, level: int = 0) -> ViewMorpher:
        """The (cached) :class:`ViewMorpher` of ``ring.pairs()[pair]`` at ``level``: straight
        RGBA float32 references of that level in, the pair's correspondences, depth keys.

        Parameters
        ----------
        pair : int
            Index into ``ring.pairs()``.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        ViewMorpher
            The pair's morpher (shared, cached).

        Raises
        ------
        DegenerateViewError
            No number of depth layers gives a morph (the message names the pair and level).

        Notes
        -----
        A depth slice whose pairs all cross (every one dropped to fold-overs) has no mesh;
        the morpher is then built with one layer fewer, down to one, and the count used is
        listed in :attr:`layer_fallbacks`. The same stored data gives the same choice on load.
        """
        level = _check_level(level, self.levels)
        key = (int(pair), level)
        vm = self._morphers.get(key)
        if vm is not None:
            return vm
        corr = self.correspondences(pair, level)
        i, j = self.ring.pairs()[int(pair)]
        az = self.ring.azimuths_deg()
        ci, cj = self._ref_camera(i, level), self._ref_camera(j, level)
        h, w = self.cameras.level_shape(level)
        di, dj = (self._depth[k] if level == 0 else
                  cv2.resize(self._depth[k], (w, h), interpolation=cv2.INTER_NEAREST) for k in (i, j))
        imgs = [from_premultiplied(self._prem[level][k], 4, np.dtype(np.float32)) for k in (i, j)]
        keys = pair_depth(ci, cj, di, dj)
        # fewer depth layers when a layer's mesh cannot be built (a slice whose pairs all cross)
        tries: list[int | str] = (["auto", 1] if self.layers == "auto"
                                  else list(range(int(self.layers), 0, -1)))
        failure: Exception | None = None
        for layers in tries:
            try:
                vm = ViewMorpher.from_estimate(imgs[0], imgs[1], corr, layers=layers, layer_depth=keys,
                                               fill_occluded=True)
            except (ValidationError, GeometryError) as exc:
                failure = exc
                continue
            if layers != self.layers:
                self.layer_fallbacks[key] = layers
            self._morphers[key] = vm
            return vm
        raise DegenerateViewError(expected_got(
            f"billboard pair {(i, j)} (azimuths {az[i]:g}, {az[j]:g} deg) at level {level}",
            f"two views a view morph can join (tried layers {tries})",
            f"{type(failure).__name__}: {failure}")) from failure

    def _ref_camera(self, k: int, level: int) -> CameraModel:
        return self._cams.get((k, level), lambda: self.cameras.camera(self.ring.azimuths_deg()[k], level))

    def prepare(self, levels: Sequence[int] | None = None) -> BillboardAsset:
        """Build the morphers of every pair at ``levels`` (default: all) now, instead of on
        first use. The bake builds level 0 (so every pair is checked there); call this
        before timing frames so no frame pays for a build. Returns ``self``.

        Parameters
        ----------
        levels : sequence of int, optional
            Pyramid levels to build; all levels by default.

        Returns
        -------
        BillboardAsset
            ``self``.

        Raises
        ------
        DegenerateViewError
            A pair cannot be morphed at some level (the message names the pair and level).
        """
        for lv in range(self.levels) if levels is None else levels:
            for p in range(len(self.ring.pairs())):
                self.morpher(p, lv)
        return self

    def items(self, mesh: trimesh.Trimesh) -> list[Item]:
        """The render items of ``mesh`` in this asset's look (:func:`bake_items` of the
        normalised mesh with :attr:`appearance`): the ground truth of its billboards.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The mesh the asset was baked from (any pose and scale: it is normalised).

        Returns
        -------
        list of Item
            Object frame, identity pose.

        Raises
        ------
        MeshError
            Not a Trimesh.
        ValidationError
            ``mesh`` (shape or look) is not the one the asset was baked from; the message
            names both hashes.
        """
        if not isinstance(mesh, trimesh.Trimesh):
            raise MeshError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
        want = mesh_hash(mesh, self.appearance)
        if want != self.mesh_hash:
            raise ValidationError(expected_got(
                f"mesh of billboard asset {self.name!r}",
                f"the mesh it was baked from (hash {self.mesh_hash})",
                f"a mesh of hash {want} (another shape or look)"))
        return bake_items(normalize(mesh), self.appearance)

    # ------------------------------------------------------------------ files
    def record(self) -> AssetRecord:
        """The stored data (what :meth:`save` writes).

        Returns
        -------
        AssetRecord
            The asset's stored data.
        """
        return self._record

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the asset to one versioned ``.npz`` file (:mod:`.assetfile`), atomically.

        Parameters
        ----------
        path : str or os.PathLike
            Output file; its folder must exist.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        return write_record(path, self._record)

    @classmethod
    def load(cls, path: str | os.PathLike[str], *, mesh: trimesh.Trimesh | None = None) -> BillboardAsset:
        """Read an asset written by :meth:`save`; morphers are built on first use.

        Parameters
        ----------
        path : path-like
        mesh : trimesh.Trimesh, optional
            The mesh the asset is meant for; its :func:`mesh_hash` must be the file's.

        Returns
        -------
        BillboardAsset
            The asset.

        Raises
        ------
        FileFormatError
            Missing, truncated or corrupt file, another format or version (an older one:
            re-bake), missing keys, inconsistent contents (cameras that do not follow the
            rule); with ``mesh``, an asset baked from another mesh or the same shape in
            another look (the message names both hashes).
        """
        rec = read_record(path)
        if mesh is not None:
            want = mesh_hash(mesh, rec.appearance if rec.appearance in APPEARANCES else "own")
            if want != rec.mesh_hash:
                raise FileFormatError(expected_got(
                    f"billboard asset {Path(path).name} mesh hash", f"{want} (the given mesh's, "
                    f"shape and {rec.appearance!r} look)", f"{rec.mesh_hash} (baked from another mesh "
                    "or another look: re-bake it for this mesh)"))
        try:
            asset = cls(rec)
        except (ValidationError, GeometryError) as exc:
            raise FileFormatError(expected_got(f"billboard asset {Path(path).name}", "consistent contents",
                                               str(exc))) from exc
        asset._check_cameras()
        return asset

    def _check_cameras(self) -> None:
        for k, (a, c) in enumerate(zip(self.ring.azimuths_deg(), self._record.cameras, strict=True)):
            cam = self.cameras.camera(a)
            try:
                ok = (float(c["azimuth_deg"]) == float(a)
                      and np.allclose(np.asarray(c["K"], dtype=np.float64), cam.K, rtol=0,
                                      atol=tol.BB_FILE_CAMERA_ATOL)
                      and np.allclose(np.asarray(c["cam2world"], dtype=np.float64), cam.cam2world,
                                      rtol=0, atol=tol.BB_FILE_CAMERA_ATOL))
            except (KeyError, TypeError, ValueError):
                ok = False
            if not ok:
                raise FileFormatError(expected_got(f"billboard asset camera {k}",
                                                   "the camera rule's (quad and ring in the file)", c))
