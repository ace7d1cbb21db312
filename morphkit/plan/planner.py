"""Choosing each band's representation to an error budget, from the error tables.

:func:`predict_frames` sees every frame of a camera path as its own plan draws it
(:meth:`~morphkit.billboard.BillboardScene.plan`) and looks every drawn billboard up in the table of
its asset under every representation (:meth:`~.errortable.ErrorTable.lookup`): a
:class:`FramePredictions`, from which the frame's figures under any assignment of representations to
bands follow as :func:`~morphkit.billboard.compare.frame_errors` measures them, over the pixels of the
billboards' boxes: the frame's mean squared error is the mean of its billboards' (each
``255^2 10^(-PSNR/10)`` of its table's box PSNR) weighted by the pixels of its box inside the frame,
its IoU the mean of theirs weighted alike. What the tables cannot know (one billboard whole and
alone per cell) stays unknown: overlapping boxes count twice, a cut one is predicted as whole.

:func:`choose` looks for the cheapest assignment whose predicted figures meet the budget's
fraction of frames by a margin (each representation's: how far its calibration frames fell short of
their prediction, at least :data:`morphkit.tol.PLAN_MARGIN_DB` and
:data:`~morphkit.tol.PLAN_MARGIN_IOU`; a frame's, the margins of the representations it draws weighted
by their pixels). It starts from each representation everywhere that meets the budget so predicted, or
that was *measured* to meet it on the calibration frames (then the descent keeps the frames'
predicted figures at the budget or the start's own, the lower: no plan is dearer than a
representation everywhere shown to meet the budget), then moves bands to cheaper representations
one at a time, the move that saves the most cost (its billboards over the path times the difference of
the representations' costs per billboard, as measured) per margin of slack it uses first, as long as
the frames stay within the budget: a greedy descent whose every step is checked against the frames'
budget, not against a per-band guess; the cheapest of the descents wins. A budget no representation
everywhere meets is refused (:class:`~morphkit.errors.BudgetError`) with the figure the best
representation everywhere reaches in the budget's fraction of frames and the band that bounds it.
A ``time-ms`` budget turns the search round (:func:`choose`, "Time"): the least error whose
predicted median frame time is within it.
"""

from __future__ import annotations

import dataclasses
import heapq
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .. import tol
from ..billboard import BillboardScene, Instances
from ..billboard.compare import PSNR_CAP_DB
from ..camera import CameraModel
from ..errors import BudgetError, ValidationError, expected_got
from .budget import Budget, reached_by
from .errortable import ErrorTable
from .representations import REPRESENTATIONS, Band, BandChoice, band_label, elevation_band, representation

__all__ = [
    "FramePredictions",
    "sample_scene",
    "predict_frames",
    "Choice",
    "choose",
    "reached",
]


@dataclass(frozen=True)
class FramePredictions:
    """Every drawn billboard of every frame, its band and its predicted error in each representation.

    Parameters
    ----------
    representations : tuple of str
        The representations predicted, in :data:`~.representations.REPRESENTATIONS`' order.
    bands : list of Band
        Every band a frame draws a billboard in.
    band_index : list of (n_k,) int64
        Per frame, each drawn billboard's index in ``bands``.
    psnr_db, iou : list of (R, n_k) float64
        Per frame, each representation's predicted error of each drawn billboard.
    pixels : list of (n_k,) float64
        Per frame, the pixels of each drawn billboard's screen box inside the frame.
    base_height : dict of str to int
        Each asset's image height at level 0 (:func:`~.representations.band_label`).
    instances, predicted_instances : int, optional
        The scene's instances, and how many of them were predicted (a sample of a larger scene,
        :func:`predict_frames`): the band counts are the sample's.
    """

    representations: tuple[str, ...]
    bands: list[Band]
    band_index: list[np.ndarray]
    psnr_db: list[np.ndarray]
    iou: list[np.ndarray]
    pixels: list[np.ndarray]
    base_height: dict[str, int]
    instances: int = 0
    predicted_instances: int = 0

    def shifted(self, offsets: Mapping[str | tuple[str, Band], tuple[float, float]]) -> FramePredictions:
        """The predictions with each representation's billboards moved by its offset (the
        calibration of :func:`~.calibration.calibration_offsets` and
        :func:`~.calibration.band_offsets`): ``+dB`` to every PSNR, ``+IoU`` to every IoU (clipped
        to ``[0, 1]``).

        Parameters
        ----------
        offsets : mapping of str or (str, Band) to (float, float)
            ``(dB, IoU)`` per representation, or per representation and band (which then takes
            that band's place of the representation's); a representation not named keeps its
            predictions.

        Returns
        -------
        FramePredictions
        """
        d = np.zeros((len(self.representations), len(self.bands), 2))
        for r, name in enumerate(self.representations):
            d[r] = offsets.get(name, (0.0, 0.0))
            for k, band in enumerate(self.bands):
                d[r, k] = offsets.get((name, band), d[r, k])
        return dataclasses.replace(
            self,
            psnr_db=[p + d[:, b, 0] for p, b in zip(self.psnr_db, self.band_index, strict=True)],
            iou=[np.clip(i + d[:, b, 1], 0.0, 1.0) for i, b in zip(self.iou, self.band_index, strict=True)],
        )

    def counts(self) -> np.ndarray:
        """How many billboards each band draws over all the frames.

        Returns
        -------
        int64 array
            ``(B,)``, in the order of :attr:`bands`.
        """
        out = np.zeros(len(self.bands), np.int64)
        for b in self.band_index:
            out += np.bincount(b, minlength=len(self.bands))
        return out

    def pick_of(self, choice: BandChoice) -> np.ndarray:
        """Each band's representation index under ``choice``, ``(B,)`` int64.

        Parameters
        ----------
        choice : BandChoice
            The bands' representations.

        Returns
        -------
        (B,) int64
        """
        names = [choice.choices.get(b, choice.default) for b in self.bands]
        return np.array([self.representations.index(n) for n in names], np.int64)

    def choice_of(self, pick: np.ndarray) -> BandChoice:
        """The :class:`~.representations.BandChoice` of a pick (every band seen listed).

        Parameters
        ----------
        pick : (B,) int
            Representation index per band.

        Returns
        -------
        BandChoice
        """
        return BandChoice({b: self.representations[int(r)] for b, r in zip(self.bands, pick, strict=True)})

    def frame_times(self, pick: np.ndarray, cost: np.ndarray, fixed: np.ndarray | None = None,
                    base: float = 0.0) -> np.ndarray:
        """Each frame's predicted time under ``pick``: its billboards' costs summed (scaled from a
        sample to the scene's instances), and the fixed cost of each representation the frame draws
        at all (the real mesh's render of the frame).

        Parameters
        ----------
        pick : (B,) int
            Representation index per band.
        cost : (R,) float
            Each representation's cost per billboard (milliseconds).
        fixed : (R,) float, optional
            Each representation's cost per frame that draws it (milliseconds; default none).
        base : float, optional
            What every frame costs (milliseconds).

        Returns
        -------
        (F,) float64
        """
        scale = self.instances / self.predicted_instances if self.predicted_instances else 1.0
        pick = np.asarray(pick, np.int64)
        c = np.asarray(cost, np.float64)[pick]
        out = np.array([float(c[b].sum()) * scale + base for b in self.band_index])
        if fixed is not None:
            f = np.asarray(fixed, np.float64)
            out += [float(f[np.unique(pick[b])].sum()) if len(b) else 0.0 for b in self.band_index]
        return out

    def frame_errors(self, pick: np.ndarray) -> list[dict[str, float | None]]:
        """Each frame's predicted figures under ``pick`` (the module notes),
        ``{"billboard-psnr", "billboard-iou"}`` (None: nothing drawn).

        Parameters
        ----------
        pick : (B,) int
            Representation index per band.

        Returns
        -------
        list of dict
        """
        out: list[dict[str, float | None]] = []
        for b, p, q, w in zip(self.band_index, self.psnr_db, self.iou, self.pixels, strict=True):
            if len(b) == 0:
                out.append({"billboard-psnr": None, "billboard-iou": None})
                continue
            r = pick[b]
            cols = np.arange(len(b))
            w = w / w.sum()
            mse = float(np.sum(w * 10.0 ** (-p[r, cols] / 10.0)))
            db = PSNR_CAP_DB if mse <= 10.0 ** (-PSNR_CAP_DB / 10.0) else -10.0 * np.log10(mse)
            out.append({"billboard-psnr": float(db), "billboard-iou": float(np.sum(w * q[r, cols]))})
        return out


def sample_scene(
    scene: BillboardScene, max_instances: int = tol.PLAN_MAX_INSTANCES, rng: np.random.Generator | None = None
) -> BillboardScene:
    """``scene`` with at most ``max_instances`` of its instances, drawn at random (the scene itself
    when it has no more): what a plan predicts and calibrates a large scene from.

    Parameters
    ----------
    scene : BillboardScene
        The scene.
    max_instances : int, optional
        The most instances kept (:data:`morphkit.tol.PLAN_MAX_INSTANCES`).
    rng : numpy.random.Generator, optional
        Draws them (default ``numpy.random.default_rng(0)``: the same sample on every run).

    Returns
    -------
    BillboardScene
    """
    n = len(scene)
    if n <= max_instances:
        return scene
    keep = np.sort((rng or np.random.default_rng(0)).choice(n, max_instances, replace=False))
    inst = scene.instances
    sub = Instances(inst.names, inst.asset[keep], inst.xy[keep], inst.yaw_deg[keep], inst.scale[keep])
    return BillboardScene(
        scene.assets, sub, backdrop=scene.backdrop, facing=scene.facing, min_pixels=scene.min_pixels
    )


def predict_frames(
    tables: Mapping[tuple[str, str], ErrorTable],
    scene: BillboardScene,
    cameras: Sequence[CameraModel],
    *,
    max_instances: int = tol.PLAN_MAX_INSTANCES,
    rng: np.random.Generator | None = None,
) -> FramePredictions:
    """Every frame's drawn billboards and their predicted errors (the module notes).

    A scene of more than ``max_instances`` instances is predicted from that many drawn at random
    (``rng``): a frame's figures are means over its billboards, which a random sample estimates
    without bias, so planning does not grow with the instances.

    Parameters
    ----------
    tables : mapping of (asset, representation) to ErrorTable
        A table per asset drawn and per representation of :data:`~.representations.REPRESENTATIONS`.
    scene : BillboardScene
        The scene.
    cameras : sequence of CameraModel
        The frames.
    max_instances : int, optional
        The most instances predicted (:data:`morphkit.tol.PLAN_MAX_INSTANCES`).
    rng : numpy.random.Generator, optional
        Draws the sample (default ``numpy.random.default_rng(0)``: the same plan on every run).

    Returns
    -------
    FramePredictions

    Raises
    ------
    ValidationError
        A drawn asset without a table of every representation.
    """
    n_all = len(scene)
    scene = sample_scene(scene, max_instances, rng)
    reps = tuple(r.name for r in REPRESENTATIONS)
    names = list(scene.instances.names)
    band_ids: dict[Band, int] = {}
    band_index, psnr, iou, pixels = [], [], [], []
    for cam in cameras:
        placements = scene.plan(cam).placements
        n = len(placements)
        p = np.empty((len(reps), n))
        q = np.empty((len(reps), n))
        idx = np.empty(n, np.int64)
        area = np.array(
            [max(1, (pl.roi[1] - pl.roi[0]) * (pl.roi[3] - pl.roi[2])) for pl in placements], float
        )
        if n:
            kind = np.array([names.index(pl.asset) for pl in placements], np.int64)
            height = np.array([pl.height_px for pl in placements])
            elev = np.array([pl.elevation_deg for pl in placements])
            level = np.array([pl.level for pl in placements], np.int64)
            eband = elevation_band(elev)
            keys, inverse = np.unique(np.stack([kind, level, eband], axis=1), axis=0, return_inverse=True)
            ids = np.array(
                [band_ids.setdefault(Band(names[a], int(lv), int(e)), len(band_ids)) for a, lv, e in keys]
            )
            idx[:] = ids[inverse.reshape(-1)]
            for k in np.unique(kind):
                sel = kind == k
                for r, rep in enumerate(reps):
                    t = tables.get((names[k], rep))
                    if t is None:
                        raise ValidationError(
                            expected_got(
                                "tables",
                                f"an ErrorTable of {names[k]!r} as {rep!r}",
                                f"tables of {sorted(tables)}",
                            )
                        )
                    p[r, sel], q[r, sel] = t.lookup(height[sel], elev[sel])
        band_index.append(idx)
        psnr.append(p)
        iou.append(q)
        pixels.append(area)
    base = {nm: int(a.size[0]) for nm, a in scene.assets.items()}
    return FramePredictions(reps, list(band_ids), band_index, psnr, iou, pixels, base, n_all, len(scene))


@dataclass(frozen=True)
class Choice:
    """What :func:`choose` chose.

    Parameters
    ----------
    choice : BandChoice
        Every band seen, with its representation.
    predicted : list of dict
        Each frame's predicted figures under it (:meth:`FramePredictions.frame_errors`).
    default_predicted : list of dict
        The same for every band in the view morph (today's default).
    steps : int
        How many bands were moved from the representation the search started from.
    predicted_ms : float, optional
        The median of the frames' predicted times (:meth:`FramePredictions.frame_times`).
    """

    choice: BandChoice
    predicted: list[dict[str, float | None]]
    default_predicted: list[dict[str, float | None]]
    steps: int
    predicted_ms: float = 0.0


def _shifted(frames: list[dict[str, float | None]], margins: np.ndarray) -> list[dict[str, float | None]]:
    """The figures less each frame's margin (``margins``: ``(F, 2)``, dB and IoU)."""
    return [
        {k: None if v is None else v - float(m[0 if k == "billboard-psnr" else 1]) for k, v in f.items()}
        for f, m in zip(frames, margins, strict=True)
    ]


def _frame_margins(pred: FramePredictions, pick: np.ndarray, margin: np.ndarray) -> np.ndarray:
    """Each frame's margin ``(F, 2)`` under ``pick``: the representations' margins (``margin``:
    ``(R, 2)``) weighted by the pixels each draws in the frame."""
    out = np.zeros((len(pred.band_index), 2))
    for f, (b, w) in enumerate(zip(pred.band_index, pred.pixels, strict=True)):
        if len(b):
            out[f] = (w[:, None] * margin[pick[b]]).sum(axis=0) / w.sum()
    return out


def reached(budget: Budget, frames: Sequence[Mapping[str, float | None]]) -> dict[str, float | None]:
    """The figure of each budget key that ``budget.frames`` of the frames reach (the quantile: the
    value at least that fraction of frames meets or beats); None where no frame has one.

    Parameters
    ----------
    budget : Budget
        The budget (its keys and fraction).
    frames : sequence of mapping
        Each frame's figures.

    Returns
    -------
    dict of str to float or None
        Per error key of the budget.
    """
    return {key: reached_by((f.get(key) for f in frames), budget.frames) for key, _ in budget.error_keys()}


def _bound(pred: FramePredictions, pick: np.ndarray, key: str) -> str:
    """The band that bounds ``key`` under ``pick``: the lowest mean predicted figure among the bands
    drawn most (at least 5 % of the billboards)."""
    counts = pred.counts()
    sums = np.zeros(len(pred.bands))
    for b, p, q in zip(pred.band_index, pred.psnr_db, pred.iou, strict=True):
        vals = (p if key == "billboard-psnr" else q)[pick[b], np.arange(len(b))]
        np.add.at(sums, b, vals)
    mean = np.where(counts > 0, sums / np.maximum(counts, 1), np.inf)
    mean[counts < 0.05 * counts.sum()] = np.inf
    k = int(np.argmin(mean))
    unit = " dB" if key == "billboard-psnr" else ""
    return (
        f"{band_label(pred.bands[k], pred.base_height[pred.bands[k][0]])} "
        f"({pred.representations[int(pick[k])]}: {mean[k]:.3g}{unit} on average)"
    )


def choose(
    pred: FramePredictions,
    budget: Budget,
    *,
    costs: Mapping[str, float] | None = None,
    margin: tuple[float, float] | Mapping[str, tuple[float, float]] | None = None,
    proven: Sequence[str] = (),
    fixed: Mapping[str, float] | None = None,
    base_ms: float = 0.0,
) -> Choice:
    """The cheapest choice of representation per band predicted to meet ``budget`` (module notes);
    with a ``time-ms`` budget, the least error within that time ("Time" below).

    Parameters
    ----------
    pred : FramePredictions
        The frames' predictions.
    budget : Budget
        The error budget (its error keys ``billboard-psnr`` and ``billboard-iou``, and ``time-ms``).
    costs : mapping of str to float, optional
        Each representation's cost per billboard drawn (e.g. milliseconds, as measured); default
        the cost order of :data:`~.representations.REPRESENTATIONS`.
    margin : (float, float) or mapping of str to (float, float), optional
        How far, in dB and in IoU, a choice's predicted figures must beat the budget: one pair, or one
        per representation (a frame's margin is then theirs weighted by the pixels each draws in it);
        default :data:`morphkit.tol.PLAN_MARGIN_DB`, :data:`morphkit.tol.PLAN_MARGIN_IOU`.
    proven : sequence of str, optional
        Representations measured to meet the budget when drawn everywhere (on calibration frames):
        each is a start even where its prediction less the margin falls short, and the descent from it
        keeps the predicted figures at the budget or at the start's, the lower.
    fixed : mapping of str to float, optional
        Each representation's cost per frame that draws it at all, above the cheapest's (e.g. the
        real mesh's render of the frame; :meth:`FramePredictions.frame_times`); default none.
    base_ms : float, optional
        What every frame costs whatever it draws (milliseconds: the frames' predicted times hold it).

    Returns
    -------
    Choice

    Raises
    ------
    BudgetError
        No representation everywhere is predicted to meet the budget by the margin, and none is
        proven to; with ``time-ms``, the cheapest representation everywhere is predicted slower, or
        no choice within the time is predicted to meet the error keys.

    Notes
    -----
    **Time.** A frame's predicted time is the sum of its billboards' costs per billboard and of the
    fixed costs of the representations it draws (:meth:`FramePredictions.frame_times`; the
    calibration's). With ``time-ms``, the search starts from the cheapest representation
    everywhere (refused if its frames' median predicted time is over the budget) and moves one band
    at a time to another representation, the move that raises the frames' figures (each error key's
    reached by the budget's fraction of frames, less the margin, in margins above the budget; the
    PSNR where the budget has no error key; the frames' mean breaking ties) most per millisecond it
    adds first, a move that raises them and saves time first of all, while the median predicted time
    stays within ``time-ms``. The error keys, when given, must then be met.
    """
    reps = pred.representations
    if margin is None:
        margin = (tol.PLAN_MARGIN_DB, tol.PLAN_MARGIN_IOU)
    per_rep = np.array(
        [margin[n] for n in reps] if isinstance(margin, Mapping) else [margin] * len(reps), np.float64
    )
    cost = np.array([float(costs[n]) if costs is not None else representation(n).cost + 1.0 for n in reps])
    per_frame = np.array([float(fixed.get(n, 0.0)) if fixed is not None else 0.0 for n in reps])
    counts = pred.counts()
    morph = reps.index("morph")
    default = pred.frame_errors(np.full(len(pred.bands), morph, np.int64))

    def shifted(pick: np.ndarray) -> list[dict[str, float | None]]:
        return _shifted(pred.frame_errors(pick), _frame_margins(pred, pick, per_rep))

    def meets(pick: np.ndarray, to: Budget = budget) -> bool:
        return bool(to.verdict(shifted(pick))["met"])

    def total(pick: np.ndarray) -> float:
        if not per_frame.any():
            return float(np.sum(counts * cost[pick]))
        return float(np.sum(pred.frame_times(pick, cost, per_frame)))

    if budget.time_ms is not None:
        return _within_time(pred, budget, cost, shifted, default, per_frame, base_ms)

    starts: list[tuple[np.ndarray, Budget]] = []
    for r, name in enumerate(reps):
        start = np.full(len(pred.bands), r, np.int64)
        if meets(start):
            starts.append((start, budget))
        elif name in proven:  # measured to meet it: the descent keeps what the start is predicted
            got = reached(budget, shifted(start))
            lowered = {
                key.replace("-", "_"): min(want, got[key])  # type: ignore[type-var]
                for key, want in budget.error_keys()
                if got.get(key) is not None
            }
            starts.append((start, dataclasses.replace(budget, **lowered)))
    unit = {"billboard-psnr": tol.PLAN_MARGIN_DB, "billboard-iou": tol.PLAN_MARGIN_IOU}
    if not starts:
        # the best reachable: the representation everywhere that falls least short, in margins
        def short(r: int) -> float:
            got = reached(budget, shifted(np.full(len(pred.bands), r, np.int64)))
            return min(
                ((got[k] - want) / unit[k] for k, want in budget.error_keys() if got.get(k) is not None),
                default=-np.inf,
            )

        best_r = max(range(len(reps)), key=short)
        pick = np.full(len(pred.bands), best_r, np.int64)
        got = reached(budget, shifted(pick))
        parts = []
        for key, want in budget.error_keys():
            v = got.get(key)
            if v is not None and v < want:
                parts.append(
                    f"{key} {v:.3g} (with the prediction's margin) in {budget.frames:.0%} of the frames, "
                    f"against {want:g}; bounded by {_bound(pred, pick, key)}"
                )
        raise BudgetError(
            "no representation meets the budget: the best reachable is "
            + ("; ".join(parts) or "below the budget")
            + f" ({reps[best_r]} everywhere)"
        )

    def slack(pick: np.ndarray, to: Budget) -> float:
        """How far, in margins, the pick's figures in the budget's fraction of frames clear it."""
        got = reached(to, shifted(pick))
        return min(
            ((got[k] - want) / unit[k] for k, want in to.error_keys() if got.get(k) is not None),
            default=0.0,
        )

    def descend(start: np.ndarray, to: Budget) -> tuple[np.ndarray, int]:
        """Every band moved to a cheaper representation, the move saving most cost per margin of
        slack it uses first, while the frames stay within ``to`` (a lazy greedy: a move's ratio is
        computed again only when it comes to the top)."""
        pick, steps = start.copy(), 0
        s0, c0 = slack(pick, to), total(start)
        heap = [
            (-np.inf, b, r)
            for b in range(len(pred.bands))
            for r in range(len(reps))
            if cost[r] < cost[pick[b]]
        ]
        heapq.heapify(heap)
        fresh: set[tuple[int, int]] = set()
        while heap:
            _, b, r = heapq.heappop(heap)
            if cost[r] >= cost[pick[b]]:
                continue
            old = pick[b]
            pick[b] = r
            ok = meets(pick, to)
            s1 = slack(pick, to) if ok else -np.inf
            c1 = total(pick)
            pick[b] = old
            if not ok or c1 >= c0:
                continue  # dropped: the moves after it leave the frames less slack, not more
            ratio = (c0 - c1) / max(s0 - s1, 1e-3)
            if (b, r) in fresh or not heap or -ratio <= heap[0][0]:
                pick[b], s0, c0, steps = r, s1, c1, steps + 1
                fresh.clear()
                heap = [(p, bb, rr) for p, bb, rr in heap if bb != b] + [
                    (-np.inf, b, rr) for rr in range(len(reps)) if cost[rr] < cost[r]
                ]
                heapq.heapify(heap)
            else:
                fresh.add((b, r))
                heapq.heappush(heap, (-ratio, b, r))
        return pick, steps

    best, best_steps = None, 0
    for start, to in starts:  # each representation everywhere that meets it, then every band made cheaper
        pick, steps = descend(start, to)
        if best is None or total(pick) < total(best):
            best, best_steps = pick, steps
    assert best is not None
    ms = float(np.median(pred.frame_times(best, cost, per_frame, base_ms))) if pred.band_index else 0.0
    return Choice(pred.choice_of(best), pred.frame_errors(best), default, best_steps, ms)


def _within_time(
    pred: FramePredictions,
    budget: Budget,
    cost: np.ndarray,
    shifted: Callable[[np.ndarray], list[dict[str, float | None]]],
    default: list[dict[str, float | None]],
    per_frame: np.ndarray,
    base_ms: float,
) -> Choice:
    """The least error within ``budget.time_ms`` (:func:`choose`, "Time"): from the cheapest
    representation everywhere, the move (a band to another representation) that raises the frames'
    figures most per millisecond it adds first (a move that saves time and raises them at once goes
    first), as long as the frames' predicted median time stays within the budget."""
    reps = pred.representations
    # the figures raised: the budget's error keys, or the PSNR where it has none
    target = budget if budget.error_keys() else Budget(billboard_psnr=1.0, frames=budget.frames)
    unit = {"billboard-psnr": tol.PLAN_MARGIN_DB, "billboard-iou": tol.PLAN_MARGIN_IOU}
    limit = float(budget.time_ms)  # type: ignore[arg-type]

    def score(pick: np.ndarray) -> float:
        """The figures reached by the budget's fraction of frames, in margins above the budget; the
        frames' mean a thousandth of it, so a move that raises only frames above that quantile
        still counts (least error in every frame the time allows)."""
        frames = shifted(pick)
        got = reached(target, frames)
        keys = target.error_keys()
        at = min(((got[k] - v) / unit[k] for k, v in keys if got.get(k) is not None), default=0.0)
        each = [
            min((f[k] - v) / unit[k] for k, v in keys if f.get(k) is not None)  # type: ignore[operator]
            for f in frames
            if any(f.get(k) is not None for k, _ in keys)
        ]
        return at + 1e-3 * (float(np.mean(each)) if each else 0.0)

    def ms(pick: np.ndarray) -> float:
        return float(np.median(pred.frame_times(pick, cost, per_frame, base_ms))) if pred.band_index else 0.0

    cheapest = int(np.argmin([ms(np.full(len(pred.bands), r, np.int64)) for r in range(len(reps))]))
    pick = np.full(len(pred.bands), cheapest, np.int64)
    if ms(pick) > limit:
        raise BudgetError(
            f"no representation draws the frames within {limit:g} ms: the cheapest, {reps[cheapest]} "
            f"everywhere, is predicted {ms(pick):.0f} ms a frame (the median of the planning frames)"
        )
    s0, t0, steps = score(pick), ms(pick), 0
    heap = [(-np.inf, b, r) for b in range(len(pred.bands)) for r in range(len(reps)) if r != pick[b]]
    heapq.heapify(heap)
    fresh: set[tuple[int, int]] = set()
    while heap:
        _, b, r = heapq.heappop(heap)
        if r == pick[b]:
            continue
        old = pick[b]
        pick[b] = r
        t1 = ms(pick)
        s1 = score(pick) if t1 <= limit else -np.inf
        pick[b] = old
        if s1 <= s0:
            continue  # dropped: no better (or over the time) now, and the moves after leave less time
        ratio = (s1 - s0) / max(t1 - t0, 1e-6) if t1 > t0 else np.inf
        if (b, r) in fresh or not heap or -ratio <= heap[0][0]:
            pick[b], s0, t0, steps = r, s1, t1, steps + 1
            fresh.clear()
            heap = [(p, bb, rr) for p, bb, rr in heap if bb != b] + [
                (-np.inf, b, rr) for rr in range(len(reps)) if rr != r
            ]
            heapq.heapify(heap)
        else:
            fresh.add((b, r))
            heapq.heappush(heap, (-ratio, b, r))
    if budget.error_keys() and not budget.verdict(shifted(pick))["met"]:
        got = reached(budget, shifted(pick))
        parts = [
            f"{k} {got[k]:.3g} (with the prediction's margin) in {budget.frames:.0%} of the frames, "
            f"against {v:g}"
            for k, v in budget.error_keys()
            if got.get(k) is not None and got[k] < v  # type: ignore[operator]
        ]
        raise BudgetError(
            f"no choice within {limit:g} ms meets the budget: the best reachable is "
            + ("; ".join(parts) or "below the budget")
            + f" (predicted {t0:.0f} ms a frame)"
        )
    return Choice(pred.choice_of(pick), pred.frame_errors(pick), default, steps, t0)
