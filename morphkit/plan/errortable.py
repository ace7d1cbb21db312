"""The error of one representation of an asset against the asset's own mesh, over on-screen size and
elevation: measured once (at bake time), stored, looked up per billboard.

:func:`measure_error_table` stands **one** instance of the asset at the origin of a
:class:`~morphkit.billboard.BillboardScene` and, for every on-screen height (pixels), viewing
elevation and azimuth of the grid, puts a camera looking at its pivot from the distance that
makes the billboard that tall (``height_px = 2 fy half_height / d`` with the pivot's depth ``d``,
:func:`~morphkit.billboard.frames.lod.screen_height_px`), renders the representation's mode and
the real mesh (the truth mode), and takes the per-billboard error exactly as
:func:`~morphkit.billboard.compare.compare_modes` does (:func:`~morphkit.billboard.compare.box_errors`:
box PSNR of the final RGB, data range 255, capped at :data:`~morphkit.billboard.compare.PSNR_CAP_DB`,
and silhouette IoU). A cell of the table is the mean over the azimuths
(:func:`~morphkit.billboard.compare.mean_errors`).

The perspective a billboard is seen with depends on its distance in asset sizes, so a table is
measured for one focal length ``focal_px`` (pixels; default that of the scene cameras' default
field of view over their default frame height, :data:`DEFAULT_FOCAL_PX`): a scene drawn with about
that focal length sees its billboards from the distances the table did. Each frame is only as large
as the billboard's quad needs (:func:`fit_frame`), its principal point at the centre; the focal length,
not the frame, fixes the distance.

:class:`ErrorTable` holds the grid and its two ``(S, E)`` arrays; :meth:`ErrorTable.lookup` is
bilinear in ``(log2 height, elevation)`` -- the height bins double, so a billboard halfway (in
pixels ratio) between two bins takes the mean of theirs -- and clamped at the ends of the grid.
:meth:`ErrorTable.save` writes a versioned ``.npz`` (arrays and a JSON ``meta``), atomically;
:meth:`ErrorTable.load` checks it and refuses another version, a damaged file or, when asked, a
table of another mesh (:class:`~morphkit.errors.FileFormatError`).
"""

from __future__ import annotations

import io
import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import tol
from ..billboard import BAKE_AMBIENT, Backdrop, BillboardScene, Instances, MeshMode, bake_lights
from ..billboard.compare import PSNR_CAP_DB, box_errors, mean_errors
from ..billboard.frames.facing import AxialFacing, Facing, ViewpointFacing
from ..billboard.frames.field import FrameMode
from ..billboard.protocols import BillboardSource
from ..camera import CameraModel, look_at, perspective
from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import ARCHIVE_ERRORS, array_digest, open_regular, write_bytes
from ..imaging.shading import Lighting
from ..sunlit.litmesh import LitMeshMode
from ..sunlit.litmodes import Relit

__all__ = ["ErrorTable", "measure_error_table", "default_elevations", "frame_shape", "fit_frame",
           "table_camera", "DEFAULT_HEIGHTS_PX", "DEFAULT_ELEVATIONS_DEG", "DEFAULT_AZIMUTHS_DEG",
           "DEFAULT_FOCAL_PX", "TABLE_FORMAT", "TABLE_VERSION"]

#: On-screen heights (pixels) of the default grid: doubling from a billboard barely drawn to one
#: as large as a level-0 image.
DEFAULT_HEIGHTS_PX: tuple[float, ...] = (16.0, 32.0, 64.0, 128.0, 256.0)
#: Viewing elevations (degrees) of the default grid: from eye level to nearly overhead.
DEFAULT_ELEVATIONS_DEG: tuple[float, ...] = (0.0, 20.0, 40.0, 60.0, 80.0)
#: Azimuths (degrees, object frame) each cell averages: three, over 100 degrees apart, whose offsets
#: from the references of rings of 12, 8, 6 and 4 views (30, 45, 60, 90 degrees apart) spread over the
#: pair between (near a reference, a third and halfway): a ring's error depends on where between its
#: references a billboard is seen, and a scene's instances are seen from anywhere.
DEFAULT_AZIMUTHS_DEG: tuple[float, ...] = (18.0, 124.0, 276.0)
#: The focal length (pixels) of the scene cameras' default: a 50-degree vertical field of view
#: over 480 rows (:class:`morphkit.scenes.camerapaths.NamedPath`'s defaults).
DEFAULT_FOCAL_PX: float = 240.0 / math.tan(math.radians(25.0))
#: The ``format`` entry of a table file's meta.
TABLE_FORMAT = "morphkit-error-table"
#: The table file's version: another is refused on load.
TABLE_VERSION = 1

def default_elevations(asset: Any) -> tuple[float, ...]:
    """The elevation bins of ``asset``'s table: :data:`DEFAULT_ELEVATIONS_DEG`, with a ring asset's
    bake elevation (``asset.cameras.elevation_deg``) added: there its views are exact in elevation,
    so its error peaks there, and a bilinear lookup between the neighbouring bins would miss it.

    Parameters
    ----------
    asset : Placeable
        A billboard asset.

    Returns
    -------
    tuple of float
        Strictly increasing elevations, degrees.
    """
    out = set(DEFAULT_ELEVATIONS_DEG)
    e = getattr(getattr(asset, "cameras", None), "elevation_deg", None)
    if isinstance(asset, BillboardSource) and isinstance(e, int | float) and math.isfinite(e):
        out.add(float(e))
    return tuple(sorted(out))


_ARRAYS = ("heights_px", "elevations_deg", "psnr_db", "iou")


def _grid(values: Any, what: str, lo: float, hi: float) -> np.ndarray:
    a = np.asarray(values, dtype=np.float64).reshape(-1)
    if a.size < 1 or not np.all(np.isfinite(a)) or np.any(np.diff(a) <= 0) or a[0] < lo or a[-1] >= hi:
        raise ValidationError(expected_got(what, f"finite values strictly increasing in [{lo:g}, {hi:g})",
                                           np.asarray(values).tolist()))
    a.setflags(write=False)
    return a


def _axis(x: np.ndarray, bins: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lower bin index, upper bin index and weight of the upper one, for values ``x`` clamped
    to ``[bins[0], bins[-1]]`` (one bin: weight 0)."""
    if len(bins) == 1:
        z = np.zeros(x.shape, np.int64)
        return z, z, np.zeros(x.shape)
    xc = np.clip(x, bins[0], bins[-1])
    hi = np.clip(np.searchsorted(bins, xc, side="right"), 1, len(bins) - 1)
    lo = hi - 1
    t = (xc - bins[lo]) / (bins[hi] - bins[lo])
    return lo, hi, t


@dataclass(frozen=True, eq=False)
class ErrorTable:
    """One representation's error against its asset's mesh over on-screen height and elevation.

    Parameters
    ----------
    asset : str
        The asset's name.
    mesh_hash : str
        :func:`morphkit.billboard.asset.mesh_hash` of the mesh it was measured against.
    representation : str
        A short label of the representation (e.g. ``"dome-morph-128"``).
    heights_px : (S,) float64
        On-screen heights of the billboard (pixels, strictly increasing, > 0): the bins.
    elevations_deg : (E,) float64
        Viewing elevations (degrees, strictly increasing, in ``(-90, 90)``).
    psnr_db : (S, E) float64
        Mean box PSNR (dB) of the representation against the mesh per cell (NaN: nothing measured).
    iou : (S, E) float64
        Mean silhouette IoU per cell.
    params : dict, optional
        What made the representation and the measure (JSON values): views, size, mode, focal length,
        azimuths, ...

    Raises
    ------
    ValidationError
        Bins that are not strictly increasing, arrays of another shape, an empty label.

    Examples
    --------
    A table of two heights and two elevations, looked up between its bins and outside them:

    >>> import numpy as np
    >>> from morphkit.plan.errortable import ErrorTable
    >>> t = ErrorTable("tree", "0" * 64, "classic", np.array([16.0, 64.0]), np.array([0.0, 40.0]),
    ...                np.array([[20.0, 24.0], [28.0, 32.0]]), np.array([[0.8, 0.9], [0.6, 0.7]]))
    >>> t.lookup(32.0, 20.0)  # halfway in log2 height and in elevation
    (array(26.), array(0.75))
    >>> t.lookup(8.0, 90.0)  # clamped to (16, 40)
    (array(24.), array(0.9))
    """

    asset: str
    mesh_hash: str
    representation: str
    heights_px: np.ndarray
    elevations_deg: np.ndarray
    psnr_db: np.ndarray
    iou: np.ndarray
    params: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for nm in ("asset", "mesh_hash", "representation"):
            v = getattr(self, nm)
            if not isinstance(v, str) or not v:
                raise ValidationError(expected_got(f"error table {nm}", "a non-empty string", repr(v)))
        h = _grid(self.heights_px, "heights_px", 0.0, math.inf)
        if h[0] <= 0:
            raise ValidationError(expected_got("heights_px", "values > 0", h.tolist()))
        e = _grid(self.elevations_deg, "elevations_deg", -90.0, 90.0)
        object.__setattr__(self, "heights_px", h)
        object.__setattr__(self, "elevations_deg", e)
        for nm in ("psnr_db", "iou"):
            a = np.array(getattr(self, nm), dtype=np.float64)
            if a.shape != (len(h), len(e)):
                raise ValidationError(expected_got(f"error table {nm}", f"shape {(len(h), len(e))}", a.shape))
            a.setflags(write=False)
            object.__setattr__(self, nm, a)
        if not isinstance(self.params, Mapping):
            raise ValidationError(expected_got("error table params", "a dict", type(self.params).__name__))
        object.__setattr__(self, "params", dict(self.params))

    @classmethod
    def exact(cls, asset: str, mesh_hash: str, representation: str, heights_px: Sequence[float],
              elevations_deg: Sequence[float], params: Mapping[str, Any] | None = None) -> ErrorTable:
        """The table of a representation that draws what the truth draws (the real mesh, drawn by the
        truth's own code): every cell at the PSNR cap and an IoU of 1, by construction, not measured.

        Parameters
        ----------
        asset, mesh_hash, representation : str
            As the table's fields.
        heights_px, elevations_deg : sequence of float
            The grid.
        params : mapping, optional
            What it stands for (recorded with ``"exact": True``).

        Returns
        -------
        ErrorTable

        Examples
        --------
        >>> from morphkit.plan.errortable import ErrorTable
        >>> ErrorTable.exact("tree", "ab" * 32, "mesh", [16.0, 32.0], [0.0, 40.0]).lookup(20.0, 10.0)
        (array(100.), array(1.))
        """
        shape = (len(heights_px), len(elevations_deg))
        return cls(asset, mesh_hash, representation, np.asarray(heights_px, np.float64),
                   np.asarray(elevations_deg, np.float64), np.full(shape, PSNR_CAP_DB), np.ones(shape),
                   {**dict(params or {}), "exact": True})

    def lookup(self, height_px: Any, elevation_deg: Any) -> tuple[np.ndarray, np.ndarray]:
        """The table's PSNR and IoU at on-screen heights and elevations (arrays broadcast together).

        Bilinear in ``(log2 height, elevation)`` between the four bins around each point; a
        point outside the grid takes the value at the nearest point of its edge (clamped: a
        billboard taller than the last height bin, or ``inf`` at the near plane, is looked up at
        the last bin). At a bin the cell itself is returned.

        Parameters
        ----------
        height_px : float or array of float
            On-screen heights, pixels (> 0; ``inf`` allowed).
        elevation_deg : float or array of float
            Viewing elevations, degrees.

        Returns
        -------
        psnr : ndarray of float64
            Interpolated PSNR, dB (the broadcast shape of the arguments).
        iou : ndarray of float64
            Interpolated IoU.

        Raises
        ------
        ValidationError
            A height <= 0 or NaN, an elevation NaN.
        """
        h, e = np.broadcast_arrays(np.asarray(height_px, dtype=np.float64),
                                   np.asarray(elevation_deg, dtype=np.float64))
        if np.any(~(h > 0)) or np.any(np.isnan(e)):
            raise ValidationError(expected_got("lookup", "heights > 0 and elevations that are numbers",
                                               f"heights {np.asarray(height_px).tolist()}, "
                                               f"elevations {np.asarray(elevation_deg).tolist()}"))
        i0, i1, u = _axis(np.log2(h), np.log2(self.heights_px))
        j0, j1, v = _axis(e, self.elevations_deg)

        def bil(a: np.ndarray) -> np.ndarray:
            return ((1 - u) * (1 - v) * a[i0, j0] + u * (1 - v) * a[i1, j0]
                    + (1 - u) * v * a[i0, j1] + u * v * a[i1, j1])

        return np.asarray(bil(self.psnr_db)), np.asarray(bil(self.iou))

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the table to ``path`` (a ``.npz``: its four arrays and a JSON ``meta`` with the
        format, version, names, params and the arrays' checksums), atomically.

        Parameters
        ----------
        path : path-like
            The file (its folder must exist).

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        arrays = {k: np.ascontiguousarray(getattr(self, k)) for k in _ARRAYS}
        meta = {"format": TABLE_FORMAT, "version": TABLE_VERSION, "asset": self.asset,
                "mesh_hash": self.mesh_hash, "representation": self.representation, "params": self.params,
                "sha256": {k: array_digest(a) for k, a in arrays.items()}}
        buf = io.BytesIO()
        np.savez(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
        return write_bytes(path, buf.getvalue())

    @classmethod
    def load(cls, path: str | os.PathLike[str], *, mesh_hash: str | None = None) -> ErrorTable:
        """Read a table written by :meth:`save`.

        Parameters
        ----------
        path : path-like
            The file.
        mesh_hash : str, optional
            The hash of the mesh the table must have been measured against.

        Returns
        -------
        ErrorTable

        Raises
        ------
        FileFormatError
            No such regular file, not a table file, another version, a damaged file (unreadable,
            an array missing or not matching its checksum, bad meta), or another mesh's hash than
            ``mesh_hash``: each names what was expected and what was found.
        """
        p = Path(path)
        what = f"error table file {p.name}"

        def bad(part: str, expected: Any, got: Any) -> FileFormatError:
            return FileFormatError(expected_got(f"{what}: {part}", expected, got))

        try:
            with open_regular(p, what) as f:
                data = f.read()
            with np.load(io.BytesIO(data), allow_pickle=False) as z:
                names = set(z.files)
                if "meta" not in names:
                    raise bad("arrays", "a 'meta' array", sorted(names))
                meta = json.loads(bytes(z["meta"]).decode("utf-8"))
                if not isinstance(meta, dict):
                    raise bad("meta", "a JSON object", type(meta).__name__)
                if meta.get("format") != TABLE_FORMAT:
                    raise bad("format", TABLE_FORMAT, repr(meta.get("format")))
                if meta.get("version") != TABLE_VERSION:
                    raise bad("version", TABLE_VERSION, repr(meta.get("version")))
                missing = [k for k in _ARRAYS if k not in names]
                if missing:
                    raise bad("arrays", f"all of {list(_ARRAYS)}", f"{missing} missing")
                arrays = {k: z[k] for k in _ARRAYS}
        except FileFormatError:
            raise
        except ARCHIVE_ERRORS as exc:
            raise bad("contents", f"a complete {TABLE_FORMAT} .npz file",
                      f"an unreadable file ({type(exc).__name__}: {str(exc)[:120]})") from exc
        sums = meta.get("sha256")
        if not isinstance(sums, dict):
            raise bad("meta", "a 'sha256' object", repr(sums)[:80])
        for k, a in arrays.items():
            if sums.get(k) != array_digest(a):
                raise bad(f"array {k!r}", "the checksum recorded in meta", "different bytes (damaged file)")
        got = meta.get("mesh_hash")
        if mesh_hash is not None and got != mesh_hash:
            raise bad("mesh_hash", f"{mesh_hash} (the mesh asked for)",
                      f"{got} (measured against another mesh)")
        try:
            return cls(meta.get("asset"), got, meta.get("representation"), arrays["heights_px"],
                       arrays["elevations_deg"], arrays["psnr_db"], arrays["iou"], meta.get("params", {}))
        except ValidationError as exc:
            raise bad("contents", "a valid error table", str(exc)) from exc


def frame_shape(height_px: float, aspect: float) -> tuple[int, int]:
    """The frame a table cell is drawn in: a square just holding the billboard's quad
    ``height_px`` high and ``aspect`` times as wide from any elevation (its diagonal, one pixel to
    spare each side), even sides so the pivot lands on the centre.

    Parameters
    ----------
    height_px : float
        On-screen height of the billboard, pixels.
    aspect : float
        The quad's width over its height.

    Returns
    -------
    (H, W)
        The frame's shape, pixels.
    """
    side = int(math.ceil(height_px * math.hypot(1.0, aspect))) + 2
    side += side % 2
    return side, side


def fit_frame(scene: BillboardScene, camera: CameraModel) -> tuple[int, int]:
    """The smallest square frame, centred where ``camera``'s is, holding the whole quad of the one
    billboard ``scene`` places for ``camera`` (a quad seen from above through its own facing can
    be wider than high: an upright quad close under a high eye flares at its top), one pixel
    to spare, even sides, at most about 8 times ``camera``'s and at most
    :data:`morphkit.tol.PLAN_MAX_TABLE_FRAME_PX` a side (a quad wider than that is cut at the
    frame's edges); ``camera.shape`` when it places none.

    Parameters
    ----------
    scene : BillboardScene
        A scene of one instance.
    camera : CameraModel
        A perspective camera, principal point at the image centre.

    Returns
    -------
    (H, W)
        The frame's shape, pixels.
    """
    placed = scene.plan(camera).placements
    if not placed:
        return camera.shape
    c = placed[0].H_screen_unit @ np.array([[0.0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]).T
    xy = c[:2] / c[2]
    reach = min(float(np.abs(xy - np.array([[camera.cx], [camera.cy]])).max()), 4.0 * max(camera.shape))
    side = min(2 * int(math.ceil(reach)) + 4, tol.PLAN_MAX_TABLE_FRAME_PX)
    return side, side


def table_camera(pivot: np.ndarray, half_height: float, height_px: float, elevation_deg: float,
                 azimuth_deg: float, shape: tuple[int, int], focal_px: float) -> CameraModel:
    """The camera of one cell: looking at ``pivot`` from azimuth ``azimuth_deg`` (world, degrees
    counter-clockwise from ``+x``) and elevation ``elevation_deg``, at the distance
    ``d = 2 focal_px half_height / height_px`` that makes the quad ``height_px`` high on screen, with
    vertical focal length ``focal_px`` over a frame of ``shape``.

    Parameters
    ----------
    pivot : (3,) float
        The billboard's pivot, world frame.
    half_height : float
        The quad's half height, scene units.
    height_px, elevation_deg, azimuth_deg : float
        The cell's on-screen height (pixels) and viewing direction (degrees).
    shape : (H, W)
        Frame shape, pixels.
    focal_px : float
        Vertical focal length, pixels.

    Returns
    -------
    CameraModel
        A perspective camera, the pivot at the image centre.
    """
    d = 2.0 * focal_px * half_height / height_px
    e, a = math.radians(elevation_deg), math.radians(azimuth_deg)
    eye = np.asarray(pivot, np.float64) + d * np.array([math.cos(e) * math.cos(a),
                                                        math.cos(e) * math.sin(a), math.sin(e)])
    yfov = 2.0 * math.atan(shape[0] / (2.0 * focal_px))
    return perspective(yfov, shape, look_at(eye, np.asarray(pivot, np.float64)),
                       znear=min(0.05, d / 4.0), zfar=max(100.0, 4.0 * d))


def measure_error_table(asset: Any, items: Sequence[Any] | None, renderer: Any, mode: FrameMode,
                        truth: FrameMode | None = None, *, heights_px: Sequence[float] = DEFAULT_HEIGHTS_PX,
                        elevations_deg: Sequence[float] | None = None,
                        azimuths_deg: Sequence[float] = DEFAULT_AZIMUTHS_DEG,
                        shape: tuple[int, int] | None = None, lighting: Lighting | None = None,
                        representation: str | None = None, params: Mapping[str, Any] | None = None,
                        focal_px: float = DEFAULT_FOCAL_PX, facing: Facing | None = None,
                        backdrop: Backdrop | None = None, mesh_hash: str | None = None,
                        scale: float = 1.0) -> ErrorTable:
    """Measure ``mode``'s error against ``truth`` for one asset over a grid of on-screen heights,
    elevations and azimuths (see the module notes).

    Parameters
    ----------
    asset : Placeable
        A billboard asset (ring, dome or impostor), its name the scene's.
    items : sequence of Item or None
        The asset's mesh items (object frame, in its look: ``asset.items(mesh)``), which the default
        ``truth`` draws.
    renderer : Renderer or None
        Draws the default ``truth`` (one renderer serves every cell: the caller's, which its modes
        draw with too).
    mode : FrameMode
        The representation (e.g. ``MorphMode(MorphCache())``, ``LitMode(MorphSurface(), lighting)``).
    truth : FrameMode, optional
        The real mesh; default, as ``morphkit render`` compares: ``MeshMode(renderer, {name: items},
        bake_lights(), BAKE_AMBIENT)`` for a ring asset, else ``LitMeshMode(renderer, {name: items},
        lighting)`` (``lighting`` defaulting to the bake's light and ambient).
    heights_px : sequence of float, optional
        On-screen heights, pixels (strictly increasing).
    elevations_deg : sequence of float, optional
        Viewing elevations, degrees, in ``(-90, 90)`` (strictly increasing); default
        :func:`default_elevations` of the asset.
    azimuths_deg : sequence of float, optional
        Azimuths averaged per cell (object frame: the instance stands unturned).
    shape : (H, W), optional
        One frame shape for every cell (the billboard must fit); default the frame each cell's
        quad needs (:func:`fit_frame` of a first camera of :func:`frame_shape`).
    lighting : Lighting, optional
        Set on ``mode`` and ``truth`` where they are relit (:class:`~morphkit.sunlit.litmodes.Relit`).
    representation : str, optional
        The table's label (default ``mode.name``).
    params : mapping, optional
        What made the representation (JSON values), recorded with the measure's own.
    focal_px : float, optional
        Vertical focal length the distances follow (:data:`DEFAULT_FOCAL_PX`).
    facing : Facing, optional
        The billboard's facing: default :class:`~morphkit.billboard.frames.facing.AxialFacing` for a ring
        asset (:class:`~morphkit.billboard.protocols.BillboardSource`), else
        :class:`~morphkit.billboard.frames.facing.ViewpointFacing` (as ``morphkit render`` chooses).
    backdrop : Backdrop, optional
        Ground and sky both frames are composited over (default :class:`~morphkit.billboard.Backdrop`).
    mesh_hash : str, optional
        The mesh's hash (default the asset's ``mesh_hash``).
    scale : float, optional
        The instance's scale (a scene's instances of the asset): a billboard as tall on screen
        stands ``scale`` times as far, which the perspective does not see but the backdrop's fog
        does.

    Returns
    -------
    ErrorTable
        ``params`` holds ``params``, ``azimuths_deg``, ``focal_px``, ``mode`` and ``facing``.

    Raises
    ------
    ValidationError
        A bad grid, no mesh hash, a cell whose billboard is not drawn (a ``shape`` too small).
    """
    h_bins = _grid(heights_px, "heights_px", 0.0, math.inf)
    e_bins = _grid(default_elevations(asset) if elevations_deg is None else elevations_deg,
                   "elevations_deg", -90.0, 90.0)
    az = np.asarray(azimuths_deg, dtype=np.float64).reshape(-1)
    if az.size < 1 or not np.all(np.isfinite(az)):
        raise ValidationError(expected_got("azimuths_deg", "at least one finite azimuth", az.tolist()))
    if not (math.isfinite(focal_px) and focal_px > 0):
        raise ValidationError(expected_got("focal_px", "a focal length > 0", focal_px))
    digest = mesh_hash if mesh_hash is not None else getattr(asset, "mesh_hash", None)
    if not isinstance(digest, str) or not digest:
        raise ValidationError(expected_got("mesh_hash", "the asset's mesh hash (or mesh_hash=...)",
                                           repr(digest)))
    if facing is None:
        facing = AxialFacing() if isinstance(asset, BillboardSource) else ViewpointFacing()
    if truth is None:
        if items is None or renderer is None:
            raise ValidationError(expected_got("truth", "a truth mode, or the asset's items and a renderer",
                                               "neither"))
        if isinstance(asset, BillboardSource):
            truth = MeshMode(renderer, {asset.name: list(items)}, bake_lights(), BAKE_AMBIENT)
        else:
            base = lighting if lighting is not None else Lighting(BAKE_AMBIENT, tuple(bake_lights()))
            truth = LitMeshMode(renderer, {asset.name: list(items)}, base)
    if lighting is not None:
        for m in (mode, truth):
            if isinstance(m, Relit):
                m.lighting = lighting
    if not (math.isfinite(scale) and scale > 0):
        raise ValidationError(expected_got("scale", "a scale > 0", scale))
    inst = Instances((asset.name,), np.zeros(1, np.int64), np.zeros((1, 2)), np.zeros(1),
                     np.full(1, float(scale)))
    scene = BillboardScene({asset.name: asset}, inst, backdrop=backdrop or Backdrop(), facing=facing)
    pivot = scene.pivots[0]
    hw, hh = (float(x) * scale for x in asset.half_extent)
    psnr_db = np.full((len(h_bins), len(e_bins)), np.nan)
    iou = np.full_like(psnr_db, np.nan)
    for i, hp in enumerate(h_bins):
        frame = shape if shape is not None else frame_shape(float(hp), hw / hh)
        for j, el in enumerate(e_bins):
            errs: list[dict[str, Any]] = []
            for a in az:
                cam = table_camera(pivot, hh, float(hp), float(el), float(a), frame, focal_px)
                if shape is None:
                    cam = table_camera(pivot, hh, float(hp), float(el), float(a), fit_frame(scene, cam),
                                       focal_px)
                got = box_errors(scene.render(cam, mode), scene.render(cam, truth))
                if len(got) != 1:
                    raise ValidationError(expected_got(
                        f"cell ({hp:g} px, {el:g} deg, azimuth {a:g})", "the billboard drawn once",
                        f"{len(got)} billboards (frame {frame} too small?)"))
                errs += got
            m = mean_errors(errs)
            psnr_db[i, j], iou[i, j] = m["psnr"], m["iou"]
    record = dict(params or {})
    record.update({"azimuths_deg": az.tolist(), "focal_px": float(focal_px), "mode": mode.name,
                   "scale": float(scale), "facing": type(facing).__name__,
                   "items": None if items is None else len(items)})
    return ErrorTable(asset.name, digest, representation or mode.name, h_bins, e_bins, psnr_db, iou, record)
