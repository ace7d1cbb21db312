"""Billboard instances: which asset stands where, turned how far, how large.

A scene holds ``N`` instances, stored as arrays (struct of arrays) so that a
frame can cull and orient 10,000 of them in a few numpy passes. Frames follow
:mod:`morphkit.conventions` (world ``+z`` up, the ground is ``z = 0``): an
instance's ``object2world`` pose is ``translation(x, y, 0) @ Rz(yaw) @ scale``,
so its asset's object frame stands on the ground at ``(x, y)`` with its front
(object ``+x``, azimuth 0) turned ``yaw_deg`` counter-clockwise about ``+z``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import trimesh

from ... import tol
from ...errors import ValidationError, expected_got
from ...scene import Item
from ...validate import as_finite_array, as_int, as_positive

__all__ = ["Instance", "Instances", "place_random", "field_half_size", "footprint_radius", "Separated",
           "separate"]


@dataclass(frozen=True)
class Instance:
    """One billboard instance (a record of :class:`Instances`).

    Parameters
    ----------
    asset : str
        Name of the asset it shows (a key of the scene's assets).
    x, y : float
        Position on the ground, scene units.
    yaw_deg : float
        Turn of the asset's front about ``+z``, degrees, counter-clockwise.
    scale : float
        Uniform scale of the asset (> 0).
    """

    asset: str
    x: float
    y: float
    yaw_deg: float = 0.0
    scale: float = 1.0


@dataclass(frozen=True, eq=False)
class Instances:
    """``N`` billboard instances as arrays.

    Parameters
    ----------
    names : tuple of str
        The distinct asset names; ``asset`` indexes into it.
    asset : (N,) int64
        Asset index of each instance.
    xy : (N, 2) float64
        Ground positions, scene units.
    yaw_deg : (N,) float64
        Yaw of each instance, degrees.
    scale : (N,) float64
        Scale of each instance, > 0.

    Raises
    ------
    ValidationError
        Mismatched lengths, an asset index out of range, non-finite values, a
        scale <= 0, an empty or non-string asset name.

    Examples
    --------
    Three instances of two assets, from records ``(asset, x, y[, yaw_deg[, scale]])``;
    the person at ``(2, 0)`` turned 90 degrees: its object ``+x`` (front) is world ``+y``.

    >>> from morphkit.billboard import Instances
    >>> inst = Instances.from_records([("tree", 0, 0), ("person", 2, 0, 90), ("tree", 0, 3, 0, 2.0)])
    >>> len(inst), inst.names, inst.asset
    (3, ('tree', 'person'), array([0, 1, 0]))
    >>> inst.object2world(1).round(12) + 0.0
    array([[ 0., -1.,  0.,  2.],
           [ 1.,  0.,  0.,  0.],
           [ 0.,  0.,  1.,  0.],
           [ 0.,  0.,  0.,  1.]])

    Pivots (one per asset, object frame) turn and scale with each instance:
    the doubled tree's pivot is twice as high.

    >>> inst.pivots([[0.0, 0.0, 0.5], [0.1, 0.0, 0.5]]).round(12) + 0.0
    array([[0. , 0. , 0.5],
           [2. , 0.1, 0.5],
           [0. , 3. , 1. ]])
    """

    names: tuple[str, ...]
    asset: np.ndarray
    xy: np.ndarray
    yaw_deg: np.ndarray
    scale: np.ndarray

    def __post_init__(self) -> None:
        names = tuple(self.names)
        for nm in names:
            if not isinstance(nm, str) or not nm:
                raise ValidationError(expected_got("asset name", "a non-empty string", repr(nm)))
        asset = np.asarray(self.asset)
        if asset.ndim != 1 or (asset.size and asset.dtype.kind not in "iu"):
            raise ValidationError(expected_got("asset indices", "a 1-D integer array",
                                               f"shape {asset.shape}, dtype {asset.dtype}"))
        n = len(asset)
        asset = asset.astype(np.int64)
        if n and (asset.min() < 0 or asset.max() >= len(names)):
            raise ValidationError(expected_got("asset indices", f"in [0, {len(names)})",
                                               f"[{asset.min()}, {asset.max()}]"))
        xy = as_finite_array(self.xy, "instance positions", shape=(n, 2))
        yaw = as_finite_array(self.yaw_deg, "instance yaw_deg", shape=(n,))
        scale = as_finite_array(self.scale, "instance scale", shape=(n,))
        if n and scale.min() <= 0:
            raise ValidationError(expected_got("instance scale", "values > 0", f"min {scale.min():g}"))
        for name, v in (("names", names), ("asset", asset), ("xy", xy), ("yaw_deg", yaw),
                        ("scale", scale)):
            if isinstance(v, np.ndarray):
                v.setflags(write=False)
            object.__setattr__(self, name, v)

    def __len__(self) -> int:
        return len(self.asset)

    @classmethod
    def from_records(cls, records: Iterable[Instance | Sequence[object]]) -> Instances:
        """Instances from a list of :class:`Instance` or ``(asset, x, y[, yaw_deg[, scale]])`` tuples.

        Parameters
        ----------
        records : iterable of Instance or tuple
            One record per instance.

        Returns
        -------
        Instances
            The instances, asset names in order of first use.

        Raises
        ------
        ValidationError
            A record of the wrong form or with bad values.
        """
        recs: list[Instance] = []
        for r in records:
            if isinstance(r, Instance):
                recs.append(r)
                continue
            try:
                recs.append(Instance(*r))  # type: ignore[arg-type]
            except TypeError as exc:
                raise ValidationError(expected_got("instance record", "(asset, x, y[, yaw_deg[, scale]])",
                                                   repr(r)[:80])) from exc
        names = tuple(dict.fromkeys(r.asset for r in recs))
        index = {nm: k for k, nm in enumerate(names)}
        try:
            xy = np.array([[float(r.x), float(r.y)] for r in recs], dtype=np.float64).reshape(-1, 2)
            yaw = np.array([float(r.yaw_deg) for r in recs], dtype=np.float64)
            scale = np.array([float(r.scale) for r in recs], dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ValidationError(expected_got("instance record", "numbers for x, y, yaw_deg, scale",
                                               str(exc))) from exc
        return cls(names, np.array([index[r.asset] for r in recs], dtype=np.int64), xy, yaw, scale)

    def record(self, k: int) -> Instance:
        """Instance ``k`` as a record.

        Parameters
        ----------
        k : int
            Instance index.

        Returns
        -------
        Instance
            Its record.
        """
        return Instance(self.names[int(self.asset[k])], float(self.xy[k, 0]), float(self.xy[k, 1]),
                        float(self.yaw_deg[k]), float(self.scale[k]))

    def object2world(self, k: int) -> np.ndarray:
        """``object2world`` (4, 4) of instance ``k``: ``translation(x, y, 0) @ Rz(yaw) @ scale``.

        Not rigid when ``scale != 1`` (a uniform scale: render it, do not invert it as a pose).

        Parameters
        ----------
        k : int
            Instance index.

        Returns
        -------
        (4, 4) float64
            ``object2world``.
        """
        return self.objects2world(np.array([k]))[0]

    def objects2world(self, idx: np.ndarray) -> np.ndarray:
        """:meth:`object2world` of the instances ``idx`` at once.

        Parameters
        ----------
        idx : (K,) int
            Instance indices.

        Returns
        -------
        (K, 4, 4) float64
            Each one's ``object2world``.
        """
        idx = np.asarray(idx, np.int64)
        a = np.radians(self.yaw_deg[idx])
        c, s, m = np.cos(a), np.sin(a), self.scale[idx]
        T = np.zeros((len(idx), 4, 4))
        T[:, 0, 0], T[:, 0, 1] = m * c, m * -s
        T[:, 1, 0], T[:, 1, 1] = m * s, m * c
        T[:, 2, 2] = m
        T[:, :2, 3] = self.xy[idx]
        T[:, 3, 3] = 1.0
        return T

    def pivots(self, pivot_by_asset: Sequence[np.ndarray]) -> np.ndarray:
        """World positions ``(N, 3)`` of each instance's asset pivot (object frame ``(3,)``,
        one per name in ``names``), yawed and scaled with the instance.

        Parameters
        ----------
        pivot_by_asset : sequence of (3,) float
            Pivot of each asset in ``names``, object frame.

        Returns
        -------
        (N, 3) float64
            Pivots, world frame.
        """
        piv = np.asarray([np.asarray(p, dtype=np.float64) for p in pivot_by_asset]).reshape(-1, 3)
        if len(piv) != len(self.names):
            raise ValidationError(expected_got("pivots", f"one per asset name ({len(self.names)})",
                                               len(piv)))
        p = piv[self.asset] * self.scale[:, None]
        a = np.radians(self.yaw_deg)
        c, s = np.cos(a), np.sin(a)
        out = np.empty((len(self), 3))
        out[:, 0] = self.xy[:, 0] + c * p[:, 0] - s * p[:, 1]
        out[:, 1] = self.xy[:, 1] + s * p[:, 0] + c * p[:, 1]
        out[:, 2] = p[:, 2]
        return out


def place_random(names: Sequence[str], n: int, rng: np.random.Generator, *,
                 half_size: float | None = None, spacing: float = 1.5,
                 yaw_deg: tuple[float, float] = (0.0, 360.0),
                 scale: tuple[float, float] = (0.8, 1.25)) -> Instances:
    """``n`` instances of the assets ``names``, placed uniformly at random.

    Parameters
    ----------
    names : sequence of str
        Assets to choose from (uniformly).
    n : int
        Number of instances (>= 0).
    rng : numpy.random.Generator
        The random source (``np.random.default_rng(seed)``).
    half_size : float, optional
        Positions are uniform over ``[-half_size, half_size]^2``; default
        ``max(1, spacing * sqrt(n) / 2)``: about one instance per ``spacing^2``.
    spacing : float
        Mean distance between neighbours when ``half_size`` is not given.
    yaw_deg, scale : (lo, hi)
        Uniform ranges of yaw (degrees) and scale (> 0).

    Returns
    -------
    Instances
    """
    if not isinstance(rng, np.random.Generator):
        raise ValidationError(expected_got("rng", "a numpy Generator (np.random.default_rng(seed))",
                                           type(rng).__name__))
    names = tuple(names)
    if not names:
        raise ValidationError(expected_got("asset names", "at least one", "none"))
    n = as_int(n, "instance count", lo=0)
    spacing = as_positive(spacing, "spacing")
    half = field_half_size(n, spacing) if half_size is None else as_positive(half_size, "half_size")
    lo_s, hi_s = (as_positive(v, "scale") for v in scale)
    if hi_s < lo_s:
        raise ValidationError(expected_got("scale range", "lo <= hi", scale))
    y0, y1 = (float(v) for v in yaw_deg)
    xy = rng.uniform(-half, half, size=(n, 2))
    return Instances(names, rng.integers(0, len(names), size=n), xy, rng.uniform(y0, y1, size=n),
                     rng.uniform(lo_s, hi_s, size=n))


def field_half_size(n: int, spacing: float = 1.5) -> float:
    """The half size of :func:`place_random`'s default field: ``max(1, spacing sqrt(n) / 2)``,
    about one instance per ``spacing^2``.

    Parameters
    ----------
    n : int
        Number of instances (>= 0).
    spacing : float
        Mean distance between neighbours (> 0).

    Returns
    -------
    float
        The half size, scene units.
    """
    return max(1.0, as_positive(spacing, "spacing") * float(np.sqrt(as_int(n, "instance count", lo=0))) / 2)


def footprint_radius(items: Iterable[Item]) -> float:
    """The radius about the object frame's vertical axis that holds every vertex of ``items``
    (the parts of one asset, object frame): two instances of footprints ``r_i``, ``r_j`` (times
    their scales) whose positions lie ``r_i s_i + r_j s_j`` apart or more cannot interpenetrate,
    however they are turned.

    Parameters
    ----------
    items : iterable of Item
        The asset's parts (meshes and poses), object frame (``+z`` up, standing at the origin).

    Returns
    -------
    float
        ``max hypot(x, y)`` over the vertices, scene units.

    Raises
    ------
    ValidationError
        No vertices.
    """
    parts = [trimesh.transform_points(np.asarray(it.mesh.vertices, np.float64), it.pose)[:, :2]
             for it in items]
    xy = np.concatenate(parts) if parts else np.zeros((0, 2))
    if len(xy) == 0:
        raise ValidationError(expected_got("footprint parts", "at least one vertex", "none"))
    return float(np.hypot(xy[:, 0], xy[:, 1]).max())


@dataclass(frozen=True)
class Separated:
    """What :func:`separate` did.

    Parameters
    ----------
    instances : Instances
        The instances, with new positions where they were moved.
    moved : int
        Instances given a new position.
    crowded : int
        Instances that still overlap another: no free place was found for them in
        :data:`~morphkit.tol.BB_SCATTER_TRIES` draws (the field is too small for their
        footprints); they keep their first position.
    """

    instances: Instances
    moved: int
    crowded: int


def separate(instances: Instances, radius: Mapping[str, float], rng: np.random.Generator, *,
             half_size: float) -> Separated:
    """Scatter with a minimum spacing: move the instances that would interpenetrate.

    In order, each instance keeps its position when its footprint circle (``radius`` of its
    asset times its scale, about its position) meets none of those kept before it; otherwise
    it is drawn again, uniformly over ``[-half_size, half_size]^2``, up to
    :data:`~morphkit.tol.BB_SCATTER_TRIES` times (dart throwing, a Poisson-disc scatter
    seeded by the first positions). Yaw, scale and asset stay.

    Parameters
    ----------
    instances : Instances
        The first positions (e.g. :func:`place_random`).
    radius : mapping of str to float
        Footprint radius of each asset name at scale 1, scene units (:func:`footprint_radius`,
        or any bound of it such as the quad's half width).
    rng : numpy.random.Generator
        The random source of the new positions.
    half_size : float
        The field's half size (> 0).

    Returns
    -------
    Separated
        The instances and the counts of moved and still crowded ones.

    Raises
    ------
    ValidationError
        A name without a radius, a radius < 0, a bad ``rng`` or ``half_size``.

    Examples
    --------
    Two unit discs 1 apart overlap: the second is moved at least 2 away from the first.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.instances import Instances, separate
    >>> inst = Instances.from_records([("tree", 0.0, 0.0), ("tree", 1.0, 0.0)])
    >>> out = separate(inst, {"tree": 1.0}, np.random.default_rng(0), half_size=5.0)
    >>> out.moved, out.crowded, bool(np.hypot(*out.instances.xy[1]) >= 2.0)
    (1, 0, True)
    """
    if not isinstance(rng, np.random.Generator):
        raise ValidationError(expected_got("rng", "a numpy Generator (np.random.default_rng(seed))",
                                           type(rng).__name__))
    half = as_positive(half_size, "half_size")
    missing = [nm for nm in instances.names if nm not in radius]
    if missing:
        raise ValidationError(expected_got("footprint radius", f"one for each asset {list(instances.names)}",
                                           f"none for {missing}"))
    per_asset = np.array([float(radius[nm]) for nm in instances.names], np.float64)
    if len(per_asset) and (not np.all(np.isfinite(per_asset)) or per_asset.min() < 0):
        raise ValidationError(expected_got("footprint radius", "finite values >= 0", per_asset.tolist()))
    n = len(instances)
    r = per_asset[instances.asset] * instances.scale
    xy = instances.xy.copy()
    cell = max(2.0 * float(r.max()) if n else 1.0, 1e-9)
    grid: dict[tuple[int, int], list[int]] = {}
    moved = crowded = 0

    def clear(k: int, p: np.ndarray) -> bool:
        cx, cy = int(np.floor(p[0] / cell)), int(np.floor(p[1] / cell))
        for gx in (cx - 1, cx, cx + 1):
            for gy in (cy - 1, cy, cy + 1):
                for j in grid.get((gx, gy), ()):
                    if np.hypot(*(xy[j] - p)) < r[k] + r[j]:
                        return False
        return True

    for k in range(n):
        p = xy[k]
        if not clear(k, p):
            for _ in range(tol.BB_SCATTER_TRIES):
                q = rng.uniform(-half, half, size=2)
                if clear(k, q):
                    xy[k] = q
                    moved += 1
                    break
            else:
                crowded += 1
        grid.setdefault((int(np.floor(xy[k, 0] / cell)), int(np.floor(xy[k, 1] / cell))), []).append(k)
    return Separated(replace(instances, xy=xy), moved, crowded)
