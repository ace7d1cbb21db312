"""Point correspondences between two views, behind one type.

* :func:`from_geometry` -- project known 3-D points (mesh vertices) into both
  cameras, keeping those visible in both (depth test against each view's depth
  map);
* :func:`from_depth` -- the same from the two views' depth maps alone: every
  ``step``-th object pixel and every ``contour_step``-th silhouette pixel of
  each view, unprojected and kept where visible in the other (dense pairs that
  follow the outline: what a piecewise-affine morph of a thin or holed object
  needs); :func:`pair_depth` gives each pixel the same depth key for layered
  morphs;
* :func:`morphkit.viewmorph.matching.from_images` (its own module) -- from
  the images alone;
* :func:`load_points` -- a JSON or CSV file of point pairs given by the user
  (:func:`save_points` writes both formats).

All of them return :class:`Correspondences`: ``pts0[i]`` in image 0 corresponds
to ``pts1[i]`` in image 1, pixel ``(x, y)`` with the origin at the centre of the
top-left pixel (:mod:`morphkit.conventions`).

Cleaning (:meth:`Correspondences.cleaned`): exact and near duplicates (closer
than :data:`morphkit.tol.VM_DUPLICATE_PX` in *either* image to an earlier pair)
are dropped, keeping the first; NaN/inf coordinates are refused
(:class:`~morphkit.errors.ValidationError`), never dropped silently.
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import open_regular, write_text
from ..validate import as_finite_array, as_image, as_int, as_points
from ..warp.mesh import as_mesh_points

__all__ = [
    "Correspondences",
    "HasVertices",
    "from_depth",
    "from_geometry",
    "pair_depth",
    "load_points",
    "save_points",
    "around_centre",
    "spread_subset",
    "visible_in",
]

SOURCES = ("geometry", "features", "user")


@runtime_checkable
class HasVertices(Protocol):
    """A mesh-like object whose ``vertices`` are ``(N, 3)`` world points (e.g. ``trimesh.Trimesh``).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol describes objects, it is not instantiated.
    """

    vertices: Any


@dataclass(frozen=True)
class Correspondences:
    """Matched pixel positions in two images.

    Parameters
    ----------
    pts0, pts1 : (N, 2) float64
        ``(x, y)`` pixel positions in image 0 and image 1 (pixel-centre origin).
    source : {"geometry", "features", "user"}
        Where the pairs came from.
    points3d : (N, 3) float64 or None
        World points behind the pairs (``from_geometry`` only); used to post-warp
        to a target camera.
    depth : (N,) float64 or None
        Mean depth of each pair's point in the two views (``from_geometry``
        only); when present, fold-overs of the morph mesh are resolved by
        dropping the farthest point of a folding triangle.
    """

    pts0: np.ndarray
    pts1: np.ndarray
    source: str = "user"
    points3d: np.ndarray | None = field(default=None, repr=False)
    depth: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        # pixel positions: finite and within tol.MAX_COORD_PX, as every mesh warp's control point
        p0 = as_mesh_points(self.pts0, "pts0")
        p1 = as_mesh_points(self.pts1, "pts1")
        if p0.shape != p1.shape:
            raise ValidationError(expected_got("pts1", f"{p0.shape[0]} points (as many as pts0)",
                                               f"{p1.shape[0]}"))
        if self.source not in SOURCES:
            raise ValidationError(expected_got("source", f"one of {SOURCES}", repr(self.source)))
        p3 = None
        if self.points3d is not None:
            p3 = as_points(self.points3d, "points3d", dim=3)
            if p3.shape[0] != p0.shape[0]:
                raise ValidationError(expected_got("points3d", f"{p0.shape[0]} points", f"{p3.shape[0]}"))
            p3.setflags(write=False)
        dep = None
        if self.depth is not None:
            dep = as_finite_array(self.depth, "depth", shape=(p0.shape[0],))
            dep.setflags(write=False)
        object.__setattr__(self, "depth", dep)
        p0.setflags(write=False)
        p1.setflags(write=False)
        object.__setattr__(self, "pts0", p0)
        object.__setattr__(self, "pts1", p1)
        object.__setattr__(self, "points3d", p3)

    def __len__(self) -> int:
        return int(self.pts0.shape[0])

    def subset(self, keep: Any) -> Correspondences:
        """The pairs selected by a boolean mask or an index array.

        Parameters
        ----------
        keep : (N,) bool or (k,) int
            A mask over the pairs or indices into them.

        Returns
        -------
        Correspondences
            The selected pairs (with their ``points3d``/``depth``), same source.
        """
        keep = np.asarray(keep)
        return Correspondences(self.pts0[keep], self.pts1[keep], self.source,
                               None if self.points3d is None else self.points3d[keep],
                               None if self.depth is None else self.depth[keep])

    def swapped(self) -> Correspondences:
        """The same pairs with the images exchanged.

        Returns
        -------
        Correspondences
            ``pts0`` and ``pts1`` swapped; ``points3d`` and ``depth`` (symmetric) kept.
        """
        return Correspondences(self.pts1, self.pts0, self.source, self.points3d, self.depth)

    def duplicates(self, tol_px: float = tol.VM_DUPLICATE_PX) -> np.ndarray:
        """Boolean mask of pairs that repeat an earlier pair in either image.

        A pair is a duplicate when its point in image 0 *or* its point in image
        1 lies within ``tol_px`` (Chebyshev distance) of the point of an earlier
        pair in the same image: both exact repeats and conflicting matches (one
        point matched twice) would give zero-area mesh triangles.

        Parameters
        ----------
        tol_px : float
            Distance (pixels, Chebyshev) under which two points count as one.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` bool: True for pairs that repeat an earlier one.
        """
        dup = np.zeros(len(self), dtype=bool)
        for pts in (self.pts0, self.pts1):
            q = np.floor(pts / max(tol_px, tol.PX_EQUAL)).astype(np.int64)
            # Neighbouring cells too, so that pairs straddling a cell border are found.
            seen: dict[tuple[int, int], int] = {}
            for i, (cx, cy) in enumerate(q):
                hit = False
                for dx in (-1, 0, 1):
                    for dy in (-1, 0, 1):
                        j = seen.get((cx + dx, cy + dy))
                        if j is not None and np.max(np.abs(pts[j] - pts[i])) <= tol_px:
                            hit = True
                            break
                    if hit:
                        break
                if hit:
                    dup[i] = True
                else:
                    seen.setdefault((int(cx), int(cy)), i)
        return dup

    def cleaned(self, tol_px: float = tol.VM_DUPLICATE_PX) -> tuple[Correspondences, int]:
        """Drop duplicates (see :meth:`duplicates`); return the rest and how many were dropped.

        Parameters
        ----------
        tol_px : float
            See :meth:`duplicates`.

        Returns
        -------
        kept : Correspondences
            The pairs that repeat no earlier pair, in order.
        n_dropped : int
            How many pairs were dropped.
        """
        dup = self.duplicates(tol_px)
        return self.subset(~dup), int(dup.sum())


# --------------------------------------------------------------------------- geometry


def visible_in(camera: CameraModel, points: np.ndarray, depth: np.ndarray | None, *,
               rtol: float = tol.VM_VISIBILITY_RTOL) -> tuple[np.ndarray, np.ndarray]:
    """Project world ``points`` and test which are visible in ``camera``.

    A point is visible when it is in front of the camera, inside the image
    (``[-0.5, W - 0.5] x [-0.5, H - 0.5]``) and, if ``depth`` is given, not
    farther than ``(1 + rtol)`` times the *smallest* depth among the (up to 4)
    pixel centres around its projection (a conservative test near depth edges:
    a point on the far side of a silhouette is dropped; a point on the
    silhouette of its own surface, whose neighbouring centres see background
    ``+inf``, is kept). A projection on a pixel centre (within
    :data:`morphkit.tol.PX_EQUAL`) meets that centre alone (:func:`around_centre`), so
    the test does not turn on the last bits of the projection.

    Parameters
    ----------
    camera : CameraModel
        The view (its ``world2cam``, image shape ``(H, W)`` and near plane).
    points : (N, 3) float
        World points.
    depth : (H, W) float or None
        The view's depth map (the measure of :meth:`CameraModel.project`'s
        depth; ``+inf`` for background), or None for no occlusion test.
    rtol : float
        Relative depth tolerance of the occlusion test.

    Returns
    -------
    px : (N, 2) float64
        Projections (NaN for points behind the camera).
    visible : (N,) bool
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    cam_pts = (np.c_[pts, np.ones(len(pts))] @ camera.world2cam.T)[:, :3]
    front = cam_pts[:, 2] > camera.znear
    px = np.full((len(pts), 2), np.nan)
    z = np.full(len(pts), np.nan)
    if front.any():
        px[front], z[front] = camera.project(pts[front])
    h, w = camera.shape
    with np.errstate(invalid="ignore"):
        inside = (front & (px[:, 0] >= -0.5) & (px[:, 0] <= w - 0.5)
                  & (px[:, 1] >= -0.5) & (px[:, 1] <= h - 0.5))
    vis = inside.copy()
    if depth is not None:
        d = as_image(depth, "depth", channels=(1,), allow_nonfinite=True)
        if d.shape != camera.shape:
            raise ValidationError(expected_got("depth", f"shape {camera.shape}", f"shape {d.shape}"))
        idx = np.flatnonzero(inside)
        x0, x1 = around_centre(px[idx, 0], w)
        y0, y1 = around_centre(px[idx, 1], h)
        dd = np.stack([d[y0, x0], d[y0, x1], d[y1, x0], d[y1, x1]], axis=1).astype(np.float64)
        dmin = np.min(dd, axis=1)
        vis[idx] = z[idx] <= dmin * (1.0 + rtol)
    return px, vis


def around_centre(coord: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray]:
    """The pixel centres on either side of each coordinate along one image axis.

    A coordinate within :data:`morphkit.tol.PX_EQUAL` of a pixel centre has that centre
    on both sides (``lo == hi``): a point projected onto a centre -- a depth map's own
    pixel, unprojected and projected again -- then meets that pixel alone, whichever way
    its last bits rounded, instead of one neighbour or the other by the rounding.

    Parameters
    ----------
    coord : (N,) float
        Coordinates along the axis, pixels (:mod:`morphkit.conventions`: centres at integers).
    size : int
        Pixels along the axis; the indices are clipped to ``[0, size - 1]``.

    Returns
    -------
    lo, hi : (N,) int64
        ``floor(coord)`` and ``floor(coord) + 1``, or the centre twice.

    Examples
    --------
    >>> import numpy as np
    >>> from morphkit.viewmorph.correspondences import around_centre
    >>> lo, hi = around_centre(np.array([2.0 - 1e-12, 2.0 + 1e-12, 2.5]), 8)
    >>> lo.tolist(), hi.tolist()
    ([2, 2, 2], [2, 2, 3])
    """
    c = np.asarray(coord, np.float64)
    near = np.rint(c)
    on = np.abs(c - near) <= tol.PX_EQUAL
    lo = np.where(on, near, np.floor(c))
    hi = np.where(on, near, lo + 1.0)
    return (np.clip(lo, 0, size - 1).astype(np.int64), np.clip(hi, 0, size - 1).astype(np.int64))


def spread_subset(px: np.ndarray, max_points: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of at most ``max_points`` rows of ``px``, spread evenly over the image.

    Shuffle, then keep a point only if its grid cell (sized so that the points'
    bounding box holds about ``max_points`` cells) is still empty; fill up with
    the remaining shuffled points if fewer cells were occupied.

    Parameters
    ----------
    px : (N, 2) float
        Pixel positions (any one image's frame).
    max_points : int
        Most indices returned.
    rng : numpy.random.Generator
        Draws the shuffles.

    Returns
    -------
    numpy.ndarray
        ``(min(N, max_points),)`` int64 row indices into ``px``, sorted
        (all of ``0 .. N - 1`` when ``N <= max_points``).
    """
    n = len(px)
    if n <= max_points:
        return np.arange(n)
    order = rng.permutation(n)
    lo, hi = px.min(axis=0), px.max(axis=0)
    area = max(float(np.prod(np.maximum(hi - lo, 1.0))), 1.0)
    cell = max(np.sqrt(area / max_points), tol.PX_EQUAL)
    key = np.floor((px[order] - lo) / cell).astype(np.int64)
    _, first = np.unique(key[:, 0] * 1_000_003 + key[:, 1], return_index=True)
    chosen = order[np.sort(first)]
    if len(chosen) >= max_points:
        return np.sort(chosen[:max_points])
    rest = np.setdiff1d(order, chosen, assume_unique=True)
    rest = rest[rng.permutation(len(rest))][: max_points - len(chosen)]
    return np.sort(np.r_[chosen, rest])


def from_geometry(points: Any, camera0: CameraModel, camera1: CameraModel, *,
                  depth0: np.ndarray | None = None, depth1: np.ndarray | None = None,
                  max_points: int = 500, rtol: float = tol.VM_VISIBILITY_RTOL,
                  rng: np.random.Generator | None = None) -> Correspondences:
    """Correspondences from known geometry: project 3-D points into both views.

    Parameters
    ----------
    points : (N, 3) array or HasVertices
        World points (a mesh, e.g. ``trimesh.Trimesh``, gives its vertices).
    camera0, camera1 : CameraModel
        The two views.
    depth0, depth1 : (H, W) float, optional
        Linear depth maps of the two views (e.g. ``Renderer.depth``); without
        them no occlusion test is made (only "in front and inside the image").
    max_points : int
        Keep at most this many pairs, spread evenly over image 0.
    rtol : float
        Relative depth tolerance of the visibility test (:func:`visible_in`).
    rng : numpy.random.Generator, optional
        For the subsampling (default ``np.random.default_rng(0)``).

    Returns
    -------
    Correspondences
        ``source="geometry"`` with ``points3d`` set; only points visible in both views.
    """
    verts = points.vertices if isinstance(points, HasVertices) else points
    pts = as_finite_array(verts, "points", shape=(None, 3))
    max_points = as_int(max_points, "max_points", lo=1)
    px0, v0 = visible_in(camera0, pts, depth0, rtol=rtol)
    px1, v1 = visible_in(camera1, pts, depth1, rtol=rtol)
    both = np.flatnonzero(v0 & v1)
    rng = np.random.default_rng(0) if rng is None else rng
    keep = both[spread_subset(px0[both], max_points, rng)]
    z = 0.5 * (_depth(camera0, pts[keep]) + _depth(camera1, pts[keep]))
    return Correspondences(px0[keep], px1[keep], "geometry", pts[keep], z)


def _depth(camera: CameraModel, pts: np.ndarray) -> np.ndarray:
    return (np.c_[pts, np.ones(len(pts))] @ camera.world2cam[2])


def _depth_map(camera: CameraModel, depth: Any, name: str) -> np.ndarray:
    d = as_image(depth, name, channels=(1,), allow_nonfinite=True).astype(np.float64)
    if d.shape != camera.shape:
        raise ValidationError(expected_got(name, f"shape {camera.shape} (the camera's)", f"shape {d.shape}"))
    return d


def _object_samples(camera: CameraModel, depth: np.ndarray, step: int, contour_step: int) -> np.ndarray:
    """World points of every ``step``-th object pixel (a grid) and every ``contour_step``-th
    pixel along each silhouette contour (object = finite depth)."""
    mask = np.isfinite(depth) & (depth > 0)
    h, w = depth.shape
    pix = [np.zeros((0, 2), np.int64)]
    if step > 0:
        ys, xs = np.mgrid[0:h:step, 0:w:step]
        on = mask[ys, xs]
        pix.append(np.stack([xs[on], ys[on]], axis=1))
    if contour_step > 0:
        contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
        pix += [c[::contour_step, 0, :] for c in contours]
    px = np.concatenate(pix).astype(np.int64)
    pts, _ = camera.unproject(depth)
    return pts[px[:, 1], px[:, 0]]


def from_depth(camera0: CameraModel, camera1: CameraModel, depth0: np.ndarray, depth1: np.ndarray, *,
               step: int = 6, contour_step: int = 2, max_points: int | None = None,
               rtol: float = tol.VM_VISIBILITY_RTOL, rng: np.random.Generator | None = None
               ) -> Correspondences:
    """Dense correspondences from two views' depth maps (no mesh needed).

    Samples of each view -- its object pixels on a ``step``-pixel grid and its
    silhouette contours (:func:`cv2.findContours`) every ``contour_step``
    pixels -- are unprojected with that view's depth and kept where
    :func:`visible_in` both views. The contour samples put morph-mesh vertices
    along the outline, so a piecewise-affine morph keeps thin parts and holes
    (chair slats and legs) that the mesh's own vertices leave to interpolation.

    Parameters
    ----------
    camera0, camera1 : CameraModel
    depth0, depth1 : (H, W) float
        Linear depth of each view, background non-finite (``Renderer.depth``).
    step : int
        Grid spacing (pixels) of the interior samples; 0 for none.
    contour_step : int
        Spacing (contour pixels) of the outline samples; 0 for none.
    max_points : int, optional
        Keep at most this many pairs, spread over image 0 (default: all).
    rtol : float
        Relative depth tolerance of the visibility test. ``inf`` keeps every
        sample that projects into both images: a sample is always seen by its own
        view, and the other's pixel is then where it *would* be (e.g. a view's
        silhouette points, which the other view sees from behind).
    rng : numpy.random.Generator, optional
        For the subsampling (default ``np.random.default_rng(0)``).

    Returns
    -------
    Correspondences
        ``source="geometry"``, ``points3d`` and ``depth`` (mean depth in the two
        views, the key of :func:`pair_depth`) set.
    """
    step = as_int(step, "step", lo=0)
    contour_step = as_int(contour_step, "contour_step", lo=0)
    if step == 0 and contour_step == 0:
        raise ValidationError(expected_got("step, contour_step", "interior or outline samples (not both 0)",
                                           (step, contour_step)))
    d0 = _depth_map(camera0, depth0, "depth0")
    d1 = _depth_map(camera1, depth1, "depth1")
    pts = np.r_[_object_samples(camera0, d0, step, contour_step),
                _object_samples(camera1, d1, step, contour_step)]
    if len(pts) == 0:
        raise ValidationError(expected_got("depth maps", "some finite (object) pixels", "none"))
    n = len(pts) if max_points is None else as_int(max_points, "max_points", lo=1)
    return from_geometry(pts, camera0, camera1, depth0=d0, depth1=d1, max_points=n, rtol=rtol, rng=rng)


def pair_depth(camera0: CameraModel, camera1: CameraModel, depth0: np.ndarray, depth1: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Per-pixel depth keys of both views, in the measure of :attr:`Correspondences.depth`.

    The key of a pixel of view ``i`` is the mean of its surface point's depth
    in the two cameras (``+inf`` for background), the value a correspondence
    through that point carries -- so pixels and pairs can be split into the
    same depth layers (``plan_view_morph(..., layers=k, layer_depth=pair_depth(...))``).

    Parameters
    ----------
    camera0, camera1 : CameraModel
        The two views.
    depth0, depth1 : (H_i, W_i) float
        Their depth maps (``+inf`` for background), of the cameras' shapes.

    Returns
    -------
    key0, key1 : (H_i, W_i) float64
        Each pixel's key, ``+inf`` for background.
    """
    keys = []
    for cam, other, d, name in ((camera0, camera1, depth0, "depth0"), (camera1, camera0, depth1, "depth1")):
        dm = _depth_map(cam, d, name)
        pts, valid = cam.unproject(dm)
        key = np.full(dm.shape, np.inf)
        key[valid] = 0.5 * (dm[valid] + _depth(other, pts[valid]))
        keys.append(key)
    return keys[0], keys[1]


# --------------------------------------------------------------------------- files


def load_points(path: str | Path) -> Correspondences:
    """Read user correspondences from JSON or CSV.

    Formats (pixel-centre ``(x, y)`` coordinates):

    * JSON: ``{"pts0": [[x, y], ...], "pts1": [[x, y], ...]}``, or a list of
      ``[x0, y0, x1, y1]`` rows, or a list of ``{"x0", "y0", "x1", "y1"}`` objects;
    * CSV: four columns ``x0, y0, x1, y1``, with or without that header line.

    Parameters
    ----------
    path : str or Path
        A ``.json``, ``.csv`` or ``.txt`` (CSV) file.

    Returns
    -------
    Correspondences
        The pairs, ``source="user"``.

    Raises
    ------
    FileFormatError
        Unreadable file or unrecognised layout.
    ValidationError
        NaN/inf values or mismatched counts.
    """
    p = Path(path)
    try:
        with open_regular(p, "points file") as f:  # a FIFO or a folder is refused, never waited on
            text = f.read().decode("utf-8")
    except OSError as exc:
        raise FileFormatError(expected_got("points file", "a readable file", f"{p}: {exc}")) from exc
    except UnicodeDecodeError as exc:
        raise FileFormatError(expected_got("points file", "UTF-8 text (JSON or CSV)", f"{p}: {exc}")) from exc
    if p.suffix.lower() == ".json":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise FileFormatError(expected_got("points file", "valid JSON", f"{p}: {exc}")) from exc
        if isinstance(data, dict) and "pts0" in data and "pts1" in data:
            pts = [_point_array(data[k], f"points file {k}", p) for k in ("pts0", "pts1")]
            return Correspondences(pts[0], pts[1], "user")
        if isinstance(data, list) and data and isinstance(data[0], dict):
            try:
                rows = [[r["x0"], r["y0"], r["x1"], r["y1"]] for r in data]
            except (KeyError, TypeError) as exc:
                raise FileFormatError(expected_got("points file", "objects with x0, y0, x1, y1",
                                                   f"{p}: {exc!r}")) from exc
        elif isinstance(data, list):
            rows = data
        else:
            raise FileFormatError(expected_got("points file", '{"pts0": ..., "pts1": ...} or a list of rows',
                                               f"{type(data).__name__} in {p}"))
    elif p.suffix.lower() in (".csv", ".txt"):
        rows = []
        for i, rec in enumerate(csv.reader(text.splitlines())):
            if not rec or all(not c.strip() for c in rec):
                continue
            if i == 0 and not _is_number(rec[0]):
                continue  # header
            rows.append(rec)
    else:
        raise FileFormatError(expected_got("points file", "a .json or .csv file", str(p)))
    try:
        arr = np.asarray(rows, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as exc:
        raise FileFormatError(expected_got("points file", "numeric rows x0, y0, x1, y1",
                                           f"{p}: {exc}")) from exc
    if arr.ndim != 2 or arr.shape[1] != 4:
        raise FileFormatError(expected_got("points file", "rows of 4 numbers (x0, y0, x1, y1)",
                                           f"shape {arr.shape} in {p}"))
    return Correspondences(arr[:, :2], arr[:, 2:], "user")


def _point_array(v: Any, what: str, p: Path) -> np.ndarray:
    """``v`` (a JSON value) as ``(N, 2)`` float64, or a FileFormatError naming ``what`` in ``p``."""
    try:
        a = np.asarray(v, dtype=np.float64)
    except (TypeError, ValueError, OverflowError) as exc:
        raise FileFormatError(expected_got(what, "a list of [x, y] numbers", f"{p}: {exc}")) from exc
    if a.size == 0:
        return a.reshape(0, 2)
    if a.ndim != 2 or a.shape[1] != 2:
        raise FileFormatError(expected_got(what, "a list of [x, y] numbers", f"shape {a.shape} in {p}"))
    return a


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def save_points(path: str | Path, corr: Correspondences) -> Path:
    """Write ``corr`` as JSON (``{"pts0", "pts1"}``) or CSV (``x0,y0,x1,y1``) by suffix.

    Parameters
    ----------
    path : str or Path
        A ``.json`` or ``.csv`` file name (parent folders are created); written
        atomically (:func:`morphkit.files.fileio.write_text`).
    corr : Correspondences
        The pairs (only ``pts0``/``pts1`` are written).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValidationError
        Another suffix.
    """
    p = Path(path)
    if p.suffix.lower() == ".json":
        text = json.dumps({"pts0": corr.pts0.tolist(), "pts1": corr.pts1.tolist()}) + "\n"
    elif p.suffix.lower() == ".csv":
        buf = io.StringIO(newline="")
        w = csv.writer(buf)
        w.writerow(["x0", "y0", "x1", "y1"])
        for a, b in zip(corr.pts0, corr.pts1, strict=True):
            w.writerow([repr(float(a[0])), repr(float(a[1])), repr(float(b[0])), repr(float(b[1]))])
        text = buf.getvalue()
    else:
        raise ValidationError(expected_got("path", "a .json or .csv file name", str(p)))
    p.parent.mkdir(parents=True, exist_ok=True)
    return write_text(p, text)
