"""What ``plan.json`` and ``plan.png`` report of a plan's configurations: per budget key the
frames' median and the figure the budget's fraction reaches, the gap between predicted and measured
figures, and the plot of error against time (:mod:`morphkit.programs.planning.planrun`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ...files.fileio import write_bytes
from ...plan import Budget
from ...plan.budget import ERROR_KEYS
from ...plan.planner import reached

__all__ = ["prediction_gap", "budget_figures", "shown_budget", "plot_plan"]


def prediction_gap(
    predicted: Sequence[Mapping[str, float | None]], measured: Sequence[Mapping[str, float | None]]
) -> dict[str, float | None]:
    """The median absolute gap between predicted and measured figures, per key.

    Parameters
    ----------
    predicted, measured : sequence of mapping
        Each frame's figures (keys of :data:`~morphkit.plan.budget.ERROR_KEYS`; None: nothing).

    Returns
    -------
    dict of str to float or None
        Per key measured (``shadow-iou`` only where the frames have it); None where no frame has both.
    """
    out: dict[str, float | None] = {}
    for key in ERROR_KEYS:
        g = [
            abs(p[key] - m[key])  # type: ignore[operator]
            for p, m in zip(predicted, measured, strict=True)
            if p.get(key) is not None and m.get(key) is not None
        ]
        if key == "shadow-iou" and not any(key in m for m in measured):
            continue  # not measured (a budget without shadows)
        out[key] = float(np.median(g)) if g else None
    return out


def budget_figures(budget: Budget, frames: Sequence[Mapping[str, float | None]]) -> dict[str, Any]:
    """Per budget key: the median over the frames and the figure the budget's fraction reaches.

    Parameters
    ----------
    budget : Budget
        Its error keys and fraction.
    frames : sequence of mapping
        Each frame's figures.

    Returns
    -------
    dict
        Per key ``{"median", "at_fraction"}`` (None where no frame has one).
    """
    at = reached(budget, frames)
    out: dict[str, Any] = {}
    for key, _ in budget.error_keys():
        vals = [f[key] for f in frames if f.get(key) is not None]
        out[key] = {"median": float(np.median(vals)) if vals else None, "at_fraction": at[key]}
    return out


def shown_budget(budget: Budget) -> Budget:
    """The budget whose keys a plan's figures are reported for: ``budget``, or, for a budget of time
    alone, both billboard keys (their values unused) at its fraction of frames.

    Parameters
    ----------
    budget : Budget
        The plan's budget.

    Returns
    -------
    Budget
    """
    if budget.error_keys():
        return budget
    return Budget(billboard_psnr=1.0, billboard_iou=1.0, frames=budget.frames)


def plot_plan(path: Path, budget: Budget, shown: Budget, rows: Mapping[str, Mapping[str, Any]]) -> None:
    """``plan.png``: per key of ``shown``, each configuration's figure (reached by the budget's fraction
    of the held-out frames) against its median frame time; predicted beside measured; ``budget``'s
    values drawn as lines.

    Parameters
    ----------
    path : pathlib.Path
        The PNG (written atomically).
    budget : Budget
        The plan's budget (its lines).
    shown : Budget
        The keys drawn (:func:`shown_budget`).
    rows : mapping of str to mapping
        Each configuration's ``time_ms``, ``measured`` and ``predicted`` figures.
    """
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = [k for k, _ in shown.error_keys()]
    limits = dict(budget.error_keys())
    fig, axes = plt.subplots(1, len(keys), figsize=(5.2 * len(keys), 4.0), squeeze=False)
    for ax, key in zip(axes[0], keys, strict=True):
        for nm, row in rows.items():
            t = row["time_ms"]
            got = row["measured"][key]["at_fraction"]
            style = {"plan": ("*", "C3", 14), "default": ("s", "C0", 9)}.get(nm, ("o", "0.4", 7))
            if got is not None:
                ax.plot([t], [got], style[0], color=style[1], ms=style[2], label=f"{nm} (measured)")
                ax.annotate(nm, (t, got), textcoords="offset points", xytext=(6, 4), fontsize=8)
            pred = row.get("predicted", {}).get(key, {}).get("at_fraction")
            if pred is not None:
                ax.plot(
                    [t], [pred], style[0], mfc="none", color=style[1], ms=style[2], label=f"{nm} (predicted)"
                )
        if key in limits:
            ax.axhline(limits[key], color="C2", ls="--", lw=1, label="budget")
        if budget.time_ms is not None:
            ax.axvline(budget.time_ms, color="C2", ls=":", lw=1, label="time budget")
        ax.set_xlabel("median frame time, ms (held-out frames)")
        ax.set_ylabel(f"{key} reached by {budget.frames:.0%} of frames")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    fig.suptitle(
        "morphkit plan: error against time (filled: measured against the real meshes; "
        "hollow: predicted from the tables)",
        fontsize=9,
    )
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    plt.close(fig)
    write_bytes(path, buf.getvalue())
