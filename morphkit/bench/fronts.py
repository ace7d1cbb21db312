"""Speed against error: each method's front of Pareto-optimal rows, drawn per scene.

A bench row is one method's time (``ms_median``) and error (a ``metrics`` value) on one piece of
work. Rows with the same values of a suite's *scene keys* measure the same scene; within a scene,
a method's rows differ by its own sizes or parameters. The method's *front* is the set of those
rows that none of its other rows beats in both time and error: the trade the method offers.
:func:`pareto_front` finds it; :func:`error_figure` draws one panel per scene, each method's front
as a line through its points and its dominated points faint, and marks the rows of the suite's
default configuration (:func:`is_default`) with a star.

Methods that are one method at several parameters (``warp_5``, ``warp_9``, ``warp_16``) are drawn
as one *family* (:func:`method_family`), so their front runs over that parameter too.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["pareto_front", "method_family", "is_default", "error_figure"]

#: Opacity of a point off its method's front.
DOMINATED_ALPHA = 0.25


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points that no other point beats in both coordinates (lower is better).

    A point is dominated when another is no worse in both coordinates and better in at least one.
    Of points equal in both, the first is kept. A point with a non-finite coordinate is never on
    the front.

    Parameters
    ----------
    points : sequence of (float, float)
        ``(error, time)`` pairs (any two coordinates to minimise).

    Returns
    -------
    list of int
        Indices into ``points``, by increasing first coordinate (so, along the front, by
        decreasing second coordinate).

    Examples
    --------
    >>> pareto_front([(0.1, 5.0), (0.2, 1.0), (0.3, 2.0), (0.05, 9.0)])
    [3, 0, 1]
    """
    finite = [i for i, (e, t) in enumerate(points) if math.isfinite(e) and math.isfinite(t)]
    front: list[int] = []
    fastest = math.inf
    for i in sorted(finite, key=lambda i: (points[i][0], points[i][1], i)):
        if points[i][1] < fastest:  # faster than every point of lower or equal error
            front.append(i)
            fastest = points[i][1]
    return front


def method_family(method: str, family: str | None) -> str:
    """The name a method is drawn under: ``method`` less the part matching ``family`` at its end.

    Parameters
    ----------
    method : str
        A row's method.
    family : str, optional
        A regular expression matched at the end of the name (e.g. ``r"_\\d+$"``: ``warp_9`` ->
        ``warp``); ``None``: every method is its own family.

    Returns
    -------
    str
        The family's name.

    Examples
    --------
    >>> method_family("pcss-reproject_9", r"_\\d+$"), method_family("warp_nearest", r"_\\d+$")
    ('pcss-reproject', 'warp_nearest')
    """
    if family is None:
        return method
    return re.sub(f"(?:{family})$", "", method) or method


def is_default(row: Mapping[str, Any], defaults: Sequence[Mapping[str, Any]]) -> bool:
    """Whether ``row`` is one of the default configurations.

    Parameters
    ----------
    row : mapping
        A bench row (:func:`morphkit.bench.harness.make_row`).
    defaults : sequence of mapping
        Each a ``"method"`` and the ``params`` values the default has (``{"method": "warp",
        "size": 512}``); a parameter the row does not have is not compared.

    Returns
    -------
    bool
        True when the row's method is a default's and it agrees with that default's parameters.
    """
    params = row["params"]
    return any(row["method"] == d["method"]
               and all(params[k] == v for k, v in d.items() if k != "method" and k in params)
               for d in defaults)


def _title(keys: Sequence[str], scene: tuple[Any, ...]) -> str:
    text = ", ".join(f"{k}={v}" for k, v in zip(keys, scene, strict=True) if v is not None) or "all"
    return "\n".join(textwrap.wrap(text, 44))


def _log_ticks(axis: Any, values: Sequence[float]) -> None:
    """Plain labels on a log axis: 1, 2 and 5 a decade over at most two decades, else decades."""
    from matplotlib import ticker

    pos = [v for v in values if v > 0 and math.isfinite(v)]
    decades = math.log10(max(pos) / min(pos)) if pos else 0.0
    if decades <= 2:
        axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    else:
        axis.set_major_locator(ticker.LogLocator(numticks=6))
        axis.set_major_formatter(ticker.LogFormatterSciNotation())
    axis.set_minor_formatter(ticker.NullFormatter())


def error_figure(rows: Sequence[Mapping[str, Any]], error_key: str, *, scene_keys: Sequence[str] = (),
                 defaults: Sequence[Mapping[str, Any]] = (), family: str | None = None,
                 error_floor: float = 1e-9, default_label: str = "default") -> Any:
    """A matplotlib figure of time against error: a panel per scene, each method's front in it.

    Parameters
    ----------
    rows : sequence of mapping
        Bench rows; those without ``error_key`` in their ``metrics`` are left out.
    error_key : str
        The ``metrics`` key on the x axis.
    scene_keys : sequence of str
        ``params`` keys whose values name a scene (a row without a key has ``None`` there).
    defaults : sequence of mapping
        The default configurations (:func:`is_default`), drawn as stars.
    family : str, optional
        Method names drawn as one (:func:`method_family`).
    error_floor : float
        Errors below it (an exact 0 included) are drawn at it, on the log axis.
    default_label : str
        The stars' legend entry (each star is labelled "default" in its panel).

    Returns
    -------
    matplotlib.figure.Figure or None
        The figure (the caller saves and closes it); ``None`` when no row has ``error_key``.
    """
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    err_rows = [r for r in rows if error_key in r["metrics"]]
    if not err_rows:
        return None
    names = list(dict.fromkeys(method_family(r["method"], family) for r in err_rows))
    palette = plt.get_cmap("tab20").colors
    colors = {m: palette[i % len(palette)] for i, m in enumerate(names)}
    scene_of = [tuple(r["params"].get(k) for k in scene_keys) for r in err_rows]
    scenes = list(dict.fromkeys(scene_of))
    many = len(scenes) > 9
    ncol = min(4 if many else 3, len(scenes))
    nrow = math.ceil(len(scenes) / ncol)
    width, height = (3.6, 2.9) if many else (4.6, 3.6)
    fig, axes = plt.subplots(nrow, ncol, figsize=(width * ncol, height * nrow), squeeze=False)
    for ax, scene in zip(axes.ravel(), scenes, strict=False):
        in_scene = [r for r, s in zip(err_rows, scene_of, strict=True) if s == scene]
        for name in names:
            mine = [r for r in in_scene if method_family(r["method"], family) == name]
            if not mine:
                continue
            pts = [(float(r["metrics"][error_key]), float(r["ms_median"])) for r in mine]
            on = pareto_front(pts)
            off = sorted(set(range(len(pts))) - set(on))
            ax.scatter([max(pts[i][0], error_floor) for i in off], [pts[i][1] for i in off], s=12,
                       color=colors[name], alpha=DOMINATED_ALPHA, lw=0)
            ax.plot([max(pts[i][0], error_floor) for i in on], [pts[i][1] for i in on], "o-",
                    color=colors[name], ms=4, lw=1.2)
            stars = [i for i in range(len(pts)) if is_default(mine[i], defaults)]
            ax.scatter([max(pts[i][0], error_floor) for i in stars], [pts[i][1] for i in stars],
                       marker="*", s=150, color=colors[name], edgecolors="black", linewidths=0.8,
                       zorder=5)
            if len(stars) == 1:
                i = stars[0]
                ax.annotate("default", (max(pts[i][0], error_floor), pts[i][1]),
                            xytext=(6, 6), textcoords="offset points", fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        xs = [max(float(r["metrics"][error_key]), error_floor) for r in in_scene]
        _log_ticks(ax.xaxis, xs)
        _log_ticks(ax.yaxis, [float(r["ms_median"]) for r in in_scene])
        ax.tick_params(labelsize=7)
        ax.set_title(_title(scene_keys, scene), fontsize=9)
        ax.set_xlabel(error_key, fontsize=8)
        ax.set_ylabel("ms (median)", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes.ravel()[len(scenes):]:
        ax.set_visible(False)
    handles = [Line2D([], [], color=colors[m], marker="o", ms=4, label=m) for m in names]
    handles += [Line2D([], [], color="grey", marker="o", ms=4, ls="none", alpha=DOMINATED_ALPHA,
                       label="off its method's front"),
                Line2D([], [], color="grey", marker="*", ms=11, ls="none", markeredgecolor="black",
                       label=default_label)]
    fig.legend(handles=handles, loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8)
    fig.suptitle(f"time against {error_key}: each method's front (lines), per scene; errors below "
                 f"{error_floor:g} drawn at {error_floor:g}", fontsize=9, y=1.0, va="bottom")
    fig.tight_layout()
    return fig
