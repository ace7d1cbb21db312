"""The frame's shadow chosen to a ``shadow-iou`` budget: the sun atlases' texels and the sun's disc
(hard, the disc filtered from one map, or N directions averaged).

A **shadow candidate** is a :class:`~morphkit.scenes.description.SceneShadows` (its ``soft`` and
``sun_atlas_size``; the scene's sun disc kept): :func:`shadow_candidates` lists a scene's, each
texel size of :data:`SHADOW_TEXELS` (and the scene's own) under the scene's own softness and, for a
soft scene, also hard and filtered (``"pcss"``): a hard sun is the cheap approximation of a soft
one, a hard scene's truth is hard and a soft candidate only blurs it. The truth stays the scene's:
the ray cast over the scene's own sun directions.

Unlike a billboard's error, which a table of one billboard alone predicts (:mod:`.errortable`), a
frame's shadow is the whole field's: the shadows of casters off screen, overlapping shadows. So each
candidate is **measured**, not predicted from a table: on the plan's calibration frames, drawn with
the real meshes under the candidate's shadow against the same meshes under the ray cast, timed in
the same run. The figure is the shadow on the ground
(:func:`~morphkit.sunlit.shadowing.darkened_iou`), which the instances cast and do not receive: it
depends on how they are drawn only where they hide the ground, so the candidates' figures hold for
whatever representation the billboards take (the held-out frames check it;
:mod:`morphkit.programs.planning.shadowplanrun`). :func:`choose_shadow` takes the cheapest candidate
whose measured figure, less its margin (:meth:`ShadowMeasure.margin`: how far a calibration frame
fell below what the others predict of it, at least :data:`morphkit.tol.PLAN_MARGIN_IOU`: a sun that
moves over the path moves the shadows between the frames measured), meets the budget in its fraction
of those frames, cheapest by the work model (:attr:`ShadowMeasure.work`: the atlases' texels squared
times the maps a sun takes), not by the times measured: the candidates' frames differ by less than a
shared machine's noise on a few drawings (their times are reported, and the choice's above the
scene's own added to the plan's predicted time), and a choice that flipped with the noise would not
be the same plan twice. A held-out frame's figure is predicted from the calibration frames around it
(:func:`interpolate_frames`: the path's frames change slowly).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .. import tol
from ..errors import BudgetError, ValidationError, expected_got
from ..scenes.description import SOFT_PCSS, SceneShadows
from ..sunlit.receivers import SCENE_ATLAS_SIZE
from .budget import Budget, reached_by

__all__ = [
    "SHADOW_TEXELS",
    "shadow_name",
    "shadow_candidates",
    "ShadowMeasure",
    "choose_shadow",
    "interpolate_frames",
]

#: The sun atlases' sides (texels) a plan chooses among: the default's (128,
#: :data:`~morphkit.sunlit.receivers.SCENE_ATLAS_SIZE`), half and twice and four times it (the
#: instances' own surfaces reach their best at 512, ``docs/RESULTS.md``, "The field's shadows").
SHADOW_TEXELS: tuple[int, ...] = (64, 128, 256, 512)


def shadow_name(shadows: SceneShadows) -> str:
    """A shadow in words: ``hard-128``, ``pcss-256``, ``disc4-512`` (softness, then atlas texels).

    Parameters
    ----------
    shadows : SceneShadows
        The shadow.

    Returns
    -------
    str

    Examples
    --------
    >>> from morphkit.plan.shadowchoice import shadow_name
    >>> from morphkit.scenes.description import SceneShadows
    >>> shadow_name(SceneShadows(soft=4, sun_atlas_size=256)), shadow_name(SceneShadows())
    ('disc4-256', 'hard-128')
    """
    size = SCENE_ATLAS_SIZE if shadows.sun_atlas_size is None else shadows.sun_atlas_size
    soft = shadows.soft
    kind = "pcss" if soft == SOFT_PCSS else "hard" if soft in (None, 1) else f"disc{soft}"
    return f"{kind}-{size}"


def shadow_candidates(scene: SceneShadows) -> list[SceneShadows]:
    """The shadows a plan of ``scene``'s chooses among (the module notes), the scene's own first.

    Parameters
    ----------
    scene : SceneShadows
        The scene's shadows.

    Returns
    -------
    list of SceneShadows
        Every ``sun_atlas_size`` set; no two alike.

    Examples
    --------
    >>> from morphkit.plan.shadowchoice import shadow_candidates, shadow_name
    >>> from morphkit.scenes.description import SceneShadows
    >>> [shadow_name(s) for s in shadow_candidates(SceneShadows())]
    ['hard-128', 'hard-64', 'hard-256', 'hard-512']
    >>> len(shadow_candidates(SceneShadows(soft="pcss")))
    8
    """
    if not isinstance(scene, SceneShadows):
        raise ValidationError(expected_got("shadows", "a SceneShadows", type(scene).__name__))
    own = dataclasses.replace(
        scene, sun_atlas_size=SCENE_ATLAS_SIZE if scene.sun_atlas_size is None else scene.sun_atlas_size
    )
    softs: list[str | int | None] = [own.soft]
    if own.soft not in (None, 1):
        softs += [s for s in (None, SOFT_PCSS) if s != own.soft]
    sizes = [own.sun_atlas_size, *(t for t in SHADOW_TEXELS if t != own.sun_atlas_size)]
    return [dataclasses.replace(own, soft=s, sun_atlas_size=t) for s in softs for t in sizes]


@dataclass(frozen=True)
class ShadowMeasure:
    """One shadow candidate measured on the calibration frames.

    Parameters
    ----------
    shadows : SceneShadows
        The candidate.
    frames : tuple of int
        The frames measured (indices into the path).
    iou : tuple of float or None
        Its ``shadow-iou`` on each (None: nothing shadowed there).
    ms : float
        Its median frame time over them (milliseconds, the frames drawn interleaved with the other
        candidates').
    """

    shadows: SceneShadows
    frames: tuple[int, ...]
    iou: tuple[float | None, ...]
    ms: float

    @property
    def name(self) -> str:
        """:func:`shadow_name` of the candidate."""
        return shadow_name(self.shadows)

    @property
    def work(self) -> int:
        """The work model the choice ranks by: the atlases' texels squared (the field map's
        resolution follows them) times the maps a sun takes (1 hard, N for N directions, 2 for a map
        filtered over the disc: the map and its filter).

        Returns
        -------
        int
        """
        soft = self.shadows.soft
        maps = 2 if soft == SOFT_PCSS else int(soft or 1)
        return int(self.shadows.sun_atlas_size or 0) ** 2 * maps

    def reached(self, budget: Budget) -> float | None:
        """The ``shadow-iou`` the budget's fraction of the frames reaches (None: none measured).

        Parameters
        ----------
        budget : Budget
            Its ``frames``.

        Returns
        -------
        float or None
        """
        return reached_by(self.iou, budget.frames)

    def margin(self, floor: float = tol.PLAN_MARGIN_IOU) -> float:
        """How far the prediction of a frame may fall short: the most a calibration frame fell below
        its prediction from the other calibration frames (:func:`interpolate_frames`, each left out
        in turn), at least ``floor``.

        Parameters
        ----------
        floor : float, optional
            The least margin (IoU).

        Returns
        -------
        float
        """
        worst = floor
        for k, got in enumerate(self.iou):
            if got is None:
                continue
            rest = [j for j in range(len(self.frames)) if j != k]
            (pred,) = interpolate_frames([self.frames[j] for j in rest], [self.iou[j] for j in rest],
                                         [self.frames[k]])
            if pred is not None:
                worst = max(worst, pred - float(got))
        return worst

    def meets(self, budget: Budget, margin: float = tol.PLAN_MARGIN_IOU) -> bool:
        """Whether the candidate's frames, less its margin (:meth:`margin`, at least ``margin``),
        meet ``budget.shadow_iou`` in its fraction of them (a budget without ``shadow-iou``, or
        frames with nothing shadowed, meet it).

        Parameters
        ----------
        budget : Budget
            The budget.
        margin : float, optional
            The least IoU taken off each frame's figure.

        Returns
        -------
        bool
        """
        got = self.reached(budget)
        return budget.shadow_iou is None or got is None or got - self.margin(margin) >= budget.shadow_iou


def choose_shadow(
    measures: Sequence[ShadowMeasure], budget: Budget, margin: float = tol.PLAN_MARGIN_IOU
) -> ShadowMeasure:
    """The cheapest candidate by the work model (:attr:`ShadowMeasure.work`; the module notes) that
    meets ``budget`` by ``margin`` (:meth:`ShadowMeasure.meets`); among equal work the first listed.

    Parameters
    ----------
    measures : sequence of ShadowMeasure
        The candidates measured.
    budget : Budget
        With ``shadow-iou``.
    margin : float, optional
        IoU.

    Returns
    -------
    ShadowMeasure

    Raises
    ------
    BudgetError
        No candidate meets it: the line names the best reachable figure, the candidate reaching it,
        and what bounds it.
    ValidationError
        No candidates.
    """
    if not measures:
        raise ValidationError(expected_got("shadow candidates", "at least one measured", "none"))
    ok = [m for m in measures if m.meets(budget, margin)]
    if ok:
        return min(ok, key=lambda m: m.work)
    best = max(measures, key=lambda m: -np.inf if m.reached(budget) is None else m.reached(budget))
    finest = max(m.shadows.sun_atlas_size for m in measures)
    bound = (
        f"the sun atlases' texels ({finest}, the finest candidate's)"
        if best.shadows.sun_atlas_size == finest
        else "the sun's softness, not the atlases' texels (finer atlases reach less)"
    )
    got, m = best.reached(budget), best.margin(margin)
    raise BudgetError(
        f"no shadow meets the budget: the best reachable is shadow-iou {got - m:.3g} (with its margin "
        f"of {m:.3g}) in {budget.frames:.0%} of the {len(best.frames)} calibration frames, "
        f"against {budget.shadow_iou:g}, with {best.name}; bounded by {bound}"
    )


def interpolate_frames(
    known: Sequence[int], values: Sequence[float | None], at: Sequence[int]
) -> list[float | None]:
    """Each frame of ``at``'s figure predicted from the frames ``known`` around it: linear in the
    frame's index between the two nearest measured, the nearest's beyond them (None: none measured).

    Parameters
    ----------
    known : sequence of int
        The frames measured.
    values : sequence of float or None
        Their figures (None: nothing measured there, left out).
    at : sequence of int
        The frames predicted.

    Returns
    -------
    list of float or None

    Examples
    --------
    >>> from morphkit.plan.shadowchoice import interpolate_frames
    >>> [round(v, 3) for v in interpolate_frames([0, 10], [0.8, 0.9], [5, 20])]
    [0.85, 0.9]
    """
    pairs = sorted((int(k), float(v)) for k, v in zip(known, values, strict=True) if v is not None)
    if not pairs:
        return [None for _ in at]
    x, y = np.array([p[0] for p in pairs], float), np.array([p[1] for p in pairs], float)
    return [float(np.interp(float(k), x, y)) for k in at]
