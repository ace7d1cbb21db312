"""Where a scene's instances stand: listed one by one, or scattered from a seed.

Each is a :class:`ScenePlacement`. Instances stand on the ground (``z = 0``, world ``+z`` up,
:mod:`morphkit.conventions`) at ``(x, y)``, turned by ``yaw_deg`` about ``+z`` and scaled by
``scale`` (times their asset's scale, :class:`~morphkit.scenes.description.SceneAsset`). A scene
file writes them as (:func:`placement_from_json` reads it back):

* ``{"listed": [{"asset": NAME, "x": X, "y": Y, "yaw_deg": 0, "scale": 1}, ...]}`` -- where they
  are; two whose footprints overlap are drawn where they are, and counted
  (:meth:`Placed.overlapping`);
* ``{"scatter": {"count": N, "seed": S, "spacing": 1.5, "apart": true}}`` -- ``N`` instances of
  the scene's assets, uniformly over a square field of about one per ``spacing x spacing`` units
  (:func:`~morphkit.billboard.frames.instances.place_random`); with ``apart`` those that would
  stand inside another are moved apart (:func:`~morphkit.billboard.frames.instances.separate`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from scipy.spatial import cKDTree

from .. import tol
from ..billboard.frames.instances import Instance, Instances, field_half_size, place_random, separate
from ..errors import ValidationError, expected_got
from ..validate import as_int, as_positive

__all__ = ["ScenePlacement", "Placed", "Listed", "Scatter", "placement_from_json", "overlapping"]


def overlapping(instances: Instances, radius: Mapping[str, float]) -> int:
    """How many instances stand inside another: footprint circles (``radius`` of the asset times
    the instance's scale) that meet another's.

    Parameters
    ----------
    instances : Instances
    radius : mapping of str to float
        Footprint radius of each asset at scale 1, scene units.

    Returns
    -------
    int
        Instances whose footprint meets at least one other's.

    Examples
    --------
    >>> from morphkit.billboard import Instances
    >>> from morphkit.scenes.placing import overlapping
    >>> overlapping(Instances.from_records([("a", 0, 0), ("a", 0, 0), ("a", 5, 0)]), {"a": 0.5})
    2
    """
    n = len(instances)
    if n < 2:
        return 0
    r = np.array([radius[nm] for nm in instances.names], np.float64)[instances.asset] * instances.scale
    pairs = cKDTree(instances.xy).query_pairs(2.0 * float(r.max()), output_type="ndarray")
    if not len(pairs):
        return 0
    d = np.linalg.norm(instances.xy[pairs[:, 0]] - instances.xy[pairs[:, 1]], axis=1)
    hit = pairs[d < r[pairs[:, 0]] + r[pairs[:, 1]]]
    return int(len(np.unique(hit)))


@dataclass(frozen=True, eq=False)
class Placed:
    """What placing gave: the instances, how many were moved apart, how many still overlap.

    Parameters
    ----------
    instances : Instances
    moved : int
        Instances moved apart so that none stands inside another.
    overlapping : int
        Instances that still stand inside another (listed ones are not moved).
    """

    instances: Instances
    moved: int = 0
    overlapping: int = 0


@runtime_checkable
class ScenePlacement(Protocol):
    """How a scene's instances are placed, and their JSON form.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def first(self, names: Sequence[str]) -> Instances:
        """The instances before any is moved apart (the camera path is fitted to these).

        Parameters
        ----------
        names : sequence of str
            The scene's asset names, in its order.

        Returns
        -------
        Instances
        """
        ...

    def place(self, names: Sequence[str], radius: Mapping[str, float]) -> Placed:
        """The instances, moved apart where the placement does so.

        Parameters
        ----------
        names : sequence of str
            The scene's asset names, in its order.
        radius : mapping of str to float
            Footprint radius of each asset at scale 1 (times its asset's scale), scene units.

        Returns
        -------
        Placed
        """
        ...

    def to_json(self) -> dict[str, Any]:
        """The placement as a scene file writes it.

        Returns
        -------
        dict
        """
        ...


@dataclass(frozen=True, eq=False)
class Listed:
    """Instances where they are listed.

    Parameters
    ----------
    instances : Instances
        Their asset names must be the scene's (checked by :meth:`first`).
    """

    instances: Instances

    def __post_init__(self) -> None:
        if not isinstance(self.instances, Instances):
            raise ValidationError(
                expected_got("listed instances", "Instances", type(self.instances).__name__)
            )
        as_int(len(self.instances), "listed instances", hi=tol.MAX_INSTANCES)  # before any work

    def first(self, names: Sequence[str]) -> Instances:
        """See :class:`ScenePlacement`: the instances, their asset names checked against the scene's.

        Parameters
        ----------
        names : sequence of str
            The scene's asset names.

        Returns
        -------
        Instances
            With the scene's names, in its order.

        Raises
        ------
        ValidationError
            An instance of an asset the scene does not have.
        """
        names = tuple(names)
        inst = self.instances
        unknown = sorted(set(inst.names) - set(names))
        if unknown:
            raise ValidationError(
                expected_got("instances' assets", f"the scene's assets {list(names)}", f"{unknown}")
            )
        index = np.array([names.index(nm) for nm in inst.names], np.int64)
        return Instances(
            names, index[inst.asset] if len(inst) else inst.asset, inst.xy, inst.yaw_deg, inst.scale
        )

    def place(self, names: Sequence[str], radius: Mapping[str, float]) -> Placed:
        """See :class:`ScenePlacement`: listed instances stay; those that overlap are counted.

        Parameters
        ----------
        names : sequence of str
            The scene's asset names.
        radius : mapping of str to float
            Footprint radii at scale 1.

        Returns
        -------
        Placed
        """
        inst = self.first(names)
        return Placed(inst, 0, overlapping(inst, radius))

    def to_json(self) -> dict[str, Any]:
        """See :class:`ScenePlacement`.

        Returns
        -------
        dict
            ``{"listed": [{"asset", "x", "y", "yaw_deg", "scale"}, ...]}``.
        """
        inst = self.instances
        return {
            "listed": [
                {
                    "asset": inst.names[int(a)],
                    "x": float(x),
                    "y": float(y),
                    "yaw_deg": float(w),
                    "scale": float(s),
                }
                for a, (x, y), w, s in zip(inst.asset, inst.xy, inst.yaw_deg, inst.scale, strict=True)
            ]
        }


@dataclass(frozen=True)
class Scatter:
    """``count`` instances of the scene's assets scattered from ``seed``.

    Parameters
    ----------
    count : int
        Number of instances, >= 0.
    seed : int
        The scatter's seed (``numpy.random.default_rng(seed)``), >= 0.
    spacing : float, optional
        Mean distance between neighbours, scene units (> 0): the field's side is
        ``spacing * sqrt(count)`` (:func:`~morphkit.billboard.frames.instances.field_half_size`).
    apart : bool, optional
        Move apart the instances that would stand inside another.

    Examples
    --------
    >>> from morphkit.scenes.placing import Scatter
    >>> placed = Scatter(50, seed=0).place(["tree"], {"tree": 0.3})
    >>> len(placed.instances), placed.overlapping
    (50, 0)
    """

    count: int
    seed: int = 0
    spacing: float = 1.5
    apart: bool = True

    def __post_init__(self) -> None:
        # a scene too large is refused here, before any work (tol.MAX_INSTANCES)
        object.__setattr__(self, "count", as_int(self.count, "scatter count", lo=0, hi=tol.MAX_INSTANCES))
        object.__setattr__(self, "seed", as_int(self.seed, "scatter seed", lo=0, hi=tol.MAX_SEED))
        object.__setattr__(self, "spacing", as_positive(self.spacing, "scatter spacing"))
        if not isinstance(self.apart, bool):
            raise ValidationError(expected_got("scatter apart", "true or false", repr(self.apart)))

    def first(self, names: Sequence[str]) -> Instances:
        """See :class:`ScenePlacement`.

        Parameters
        ----------
        names : sequence of str
            The assets to choose from, uniformly.

        Returns
        -------
        Instances
        """
        return place_random(names, self.count, np.random.default_rng(self.seed), spacing=self.spacing)

    def place(self, names: Sequence[str], radius: Mapping[str, float]) -> Placed:
        """See :class:`ScenePlacement`.

        Parameters
        ----------
        names : sequence of str
            The scene's asset names.
        radius : mapping of str to float
            Footprint radii at scale 1.

        Returns
        -------
        Placed
        """
        inst = self.first(names)
        if not self.apart:
            return Placed(inst, 0, overlapping(inst, radius))
        half = field_half_size(len(inst), self.spacing)
        out = separate(inst, radius, np.random.default_rng([self.seed, 1]), half_size=half)
        return Placed(out.instances, out.moved, out.crowded)

    def to_json(self) -> dict[str, Any]:
        """See :class:`ScenePlacement`.

        Returns
        -------
        dict
            ``{"scatter": {"count", "seed", "spacing", "apart"}}``.
        """
        return {
            "scatter": {"count": self.count, "seed": self.seed, "spacing": self.spacing, "apart": self.apart}
        }


def placement_from_json(obj: Mapping[str, Any]) -> Listed | Scatter:
    """The placement a scene file's ``"instances"`` object describes (the module notes).

    Parameters
    ----------
    obj : mapping
        Checked by the scene schema first.

    Returns
    -------
    Listed or Scatter

    Raises
    ------
    ValidationError
        Neither form, or bad values.
    """
    if "scatter" in obj:
        s = obj["scatter"]
        return Scatter(s["count"], s.get("seed", 0), s.get("spacing", 1.5), s.get("apart", True))
    if "listed" in obj:
        as_int(len(obj["listed"]), "listed instances", hi=tol.MAX_INSTANCES)  # before building them
        recs = [
            Instance(r["asset"], r["x"], r["y"], r.get("yaw_deg", 0.0), r.get("scale", 1.0))
            for r in obj["listed"]
        ]
        if not recs:
            return Listed(Instances((), np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0), np.zeros(0)))
        return Listed(Instances.from_records(recs))
    raise ValidationError(expected_got("instances", '{"listed": [...]} or {"scatter": {...}}', sorted(obj)))
