"""Timing harness shared by every ``morphkit bench`` suite.

A suite is a function ``suite(*, quick: bool) -> list[dict]`` returning rows
built with :func:`make_row`. Each row is a JSON object with at least::

    suite, method, params (object), ms_median, ms_min, ms_max, repeats,
    metrics (object of error figures; may be empty), note (str, may be empty)

Rows of one *case* share ``params``; the table prints each method's ratio to the
case's floor method (``remap`` in the ``warp`` suite). Time every method of a
case in the same run (ideally with :func:`time_calls`, which interleaves them)
so ratios hold on a noisy machine.
"""

from __future__ import annotations

import io
import itertools
import json
import math
import statistics
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import tol
from ..files import fileio
from ..render import gl_info
from .fronts import error_figure

__all__ = [
    "section_name", "pick_sections",
    "Timing",
    "time_call",
    "time_calls",
    "time_cycling",
    "auto_repeats",
    "make_row",
    "case_key",
    "format_table",
    "markdown_table",
    "write_json",
    "write_plots",
]

#: Smallest magnitude the tables print with three decimals; below it ``0.000`` would
#: hide the value, so it is printed in exponent form (``5.0e-04``).
FIXED_DECIMALS_MIN = 1e-3

#: Errors are plotted on a log axis; an error below this (an exact 0 included) is
#: drawn at it, named so in the axis label.
PLOT_ERROR_FLOOR = 1e-9


@dataclass(frozen=True)
class Timing:
    """Wall-clock statistics of repeated calls, in milliseconds.

    Parameters
    ----------
    ms_median : float
        Median duration, ms.
    ms_min : float
        Shortest duration, ms.
    ms_max : float
        Longest duration, ms.
    repeats : int
        Number of timed calls.
    """

    ms_median: float
    ms_min: float
    ms_max: float
    repeats: int

    @classmethod
    def from_seconds(cls, samples: Iterable[float]) -> Timing:
        """The statistics of call durations given in seconds.

        Parameters
        ----------
        samples : iterable of float
            Durations of the timed calls, in seconds (at least one).

        Returns
        -------
        Timing
            Median, minimum and maximum in milliseconds, and the number of samples.
        """
        ms = [1e3 * s for s in samples]
        if not ms:
            raise ValueError("no timing samples")
        return cls(statistics.median(ms), min(ms), max(ms), len(ms))


def section_name(section: Callable[..., Any]) -> str:
    """A suite section's name: its function's name less ``_rows`` and a leading underscore, dashes
    for underscores (``dome_bands_rows`` -> ``dome-bands``, ``_control_grid_rows`` -> ``control-grid``).

    Parameters
    ----------
    section : callable
        A section function.

    Returns
    -------
    str
        The name.
    """
    return section.__name__.removesuffix("_rows").lstrip("_").replace("_", "-")


def pick_sections(names: str | None, sections: Sequence[Callable[..., Any]]) -> list[Callable[..., Any]]:
    """The ``sections`` named in ``names`` (comma-separated, a suite's ``--sections``), in their
    order; all of them when ``names`` is None or empty.

    Parameters
    ----------
    names : str, optional
        E.g. ``"dome-bands,dome-relit"``.
    sections : sequence of callable
        The suite's sections (:func:`section_name` names them).

    Returns
    -------
    list of callable
        The sections to run.

    Raises
    ------
    ValidationError
        A name that is not a section's.
    """
    from ..errors import ValidationError, expected_got

    want = [w.strip() for w in (names or "").split(",") if w.strip()]
    if not want:
        return list(sections)
    known = [section_name(s) for s in sections]
    unknown = [w for w in want if w not in known]
    if unknown:
        raise ValidationError(expected_got("sections", f"names among {known}", unknown))
    return [s for s in sections if section_name(s) in want]


def time_call(fn: Callable[[], Any], *, repeats: int = 7, warmup: int = 1) -> Timing:
    """Time ``fn()``: ``warmup`` untimed calls, then ``repeats`` timed ones (perf_counter).

    Parameters
    ----------
    fn : callable
        Called with no argument.
    repeats : int
        Timed calls (at least 1).
    warmup : int
        Untimed calls first (at least 0).

    Returns
    -------
    Timing
        Statistics of the timed calls.
    """
    for _ in range(max(0, warmup)):
        fn()
    samples = []
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        fn()
        samples.append(time.perf_counter() - t0)
    return Timing.from_seconds(samples)


def time_calls(fns: Mapping[str, Callable[[], Any]], *, repeats: int = 7,
               warmup: int = 1) -> dict[str, Timing]:
    """Time several functions round-robin (warm-up each, then interleave the repeats).

    Interleaving spreads machine noise evenly over the methods, so their ratios
    are steadier than when each is timed in its own block.

    Parameters
    ----------
    fns : mapping of str to callable
        The functions by method name, each called with no argument.
    repeats : int
        Timed rounds (at least 1); each round calls every function once.
    warmup : int
        Untimed calls of each function first (at least 0).

    Returns
    -------
    dict of str to Timing
        Statistics per method name.
    """
    for fn in fns.values():
        for _ in range(max(0, warmup)):
            fn()
    samples: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(max(1, repeats)):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            samples[k].append(time.perf_counter() - t0)
    return {k: Timing.from_seconds(v) for k, v in samples.items()}


def time_cycling(fns: Mapping[str, Callable[[Any], Any]], inputs: Sequence[Any], *,
                 repeats: int = 7, warmup: int = 1) -> dict[str, Timing]:
    """:func:`time_calls` where each call takes the next of ``inputs`` (cycling),
    e.g. object positions, so that successive calls do not repeat the same case.

    Parameters
    ----------
    fns : mapping of str to callable
        Each method, called with one input.
    inputs : sequence
        The inputs, cycled per method.
    repeats : int
        Timed rounds.
    warmup : int
        Untimed rounds first.

    Returns
    -------
    dict of str to Timing
        Per method name.
    """
    if len(inputs) == 0:
        raise ValueError("no inputs to cycle through")
    wrapped = {}
    for name, fn in fns.items():
        it = itertools.cycle(inputs)

        def call(fn: Callable[[Any], Any] = fn, it: Iterator[Any] = it) -> None:
            fn(next(it))

        wrapped[name] = call
    return time_calls(wrapped, repeats=repeats, warmup=warmup)


def auto_repeats(fn: Callable[[], Any], *, budget_s: float, lo: int = 3, hi: int = 50) -> int:
    """Number of repeats of ``fn`` that fit in ``budget_s`` (one probe call), clamped to [lo, hi].

    Parameters
    ----------
    fn : callable
        Called once with no argument, to probe its duration.
    budget_s : float
        Time to spend on the repeats, in seconds.
    lo : int
        Fewest repeats.
    hi : int
        Most repeats.

    Returns
    -------
    int
        ``budget_s // duration``, clamped to ``[lo, hi]``.
    """
    t0 = time.perf_counter()
    fn()
    dt = max(time.perf_counter() - t0, tol.ZERO)
    return int(min(hi, max(lo, budget_s // dt)))


def make_row(suite: str, method: str, params: Mapping[str, Any], timing: Timing, *,
             metrics: Mapping[str, float] | None = None, note: str = "") -> dict[str, Any]:
    """Build one result row (plain JSON types).

    Parameters
    ----------
    suite : str
        The suite's name.
    method : str
        The method timed.
    params : mapping
        The case's parameters (JSON values); rows of one case share them.
    timing : Timing
        The method's timing.
    metrics : mapping of str to float, optional
        Error figures of the method's output (default none).
    note : str
        Free text shown in the table's last column.

    Returns
    -------
    dict
        ``suite``, ``method``, ``params``, ``ms_median``, ``ms_min``, ``ms_max``, ``repeats``,
        ``metrics`` and ``note`` (see the module docstring).
    """
    return {
        "suite": suite,
        "method": method,
        "gl": gl_info(open_context=False),  # GL platform and renderer of this process
        "params": dict(params),
        "ms_median": float(timing.ms_median),
        "ms_min": float(timing.ms_min),
        "ms_max": float(timing.ms_max),
        "repeats": int(timing.repeats),
        "metrics": {k: float(v) for k, v in (metrics or {}).items()},
        "note": note,
    }


def case_key(row: Mapping[str, Any]) -> str:
    """Identify a row's case: its suite and params (method excluded).

    Parameters
    ----------
    row : mapping
        A row from :func:`make_row`.

    Returns
    -------
    str
        ``"<suite>|<params as sorted JSON>"``.
    """
    return row["suite"] + "|" + json.dumps(row["params"], sort_keys=True)


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        if v == 0:
            return "0"
        if abs(v) >= 100:
            return f"{v:.0f}"
        if abs(v) >= 1:
            return f"{v:.2f}"
        if abs(v) >= FIXED_DECIMALS_MIN:
            return f"{v:.3f}"
        return f"{v:.1e}"
    return str(v)


def markdown_table(header: Sequence[str], lines: Sequence[Sequence[str]]) -> list[str]:
    """A markdown table's lines: the header, its rule, one line a row (cells already formatted).

    Parameters
    ----------
    header : sequence of str
        The column titles.
    lines : sequence of sequence of str
        The rows' cells.

    Returns
    -------
    list of str
        ``len(lines) + 2`` lines.

    Examples
    --------
    >>> markdown_table(["a", "b"], [["1", "2"]])
    ['| a | b |', '|---|---|', '| 1 | 2 |']
    """
    return (["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            + ["| " + " | ".join(x) + " |" for x in lines])


def format_table(rows: list[Mapping[str, Any]], *, floor_method: str | None = "remap") -> str:
    """Readable fixed-width table: params, method, median/min/max ms, ratio to the floor, metrics.

    Parameters
    ----------
    rows : list of mapping
        Rows from :func:`make_row`.
    floor_method : str, optional
        The method each case's ratio column divides by; ``None``: no ratio column.

    Returns
    -------
    str
        The table, a header line and a rule first; ``"(no rows)"`` when there are none.
    """
    if not rows:
        return "(no rows)"
    floors = {case_key(r): r["ms_median"] for r in rows if r["method"] == floor_method}
    pkeys: list[str] = []
    mkeys: list[str] = []
    for r in rows:
        pkeys += [k for k in r["params"] if k not in pkeys]
        mkeys += [k for k in r["metrics"] if k not in mkeys]
    ratio_col = f"x_{floor_method}" if floor_method else None
    header = pkeys + ["method", "ms_median", "ms_min", "ms_max", "n"]
    header += [ratio_col] if ratio_col else []
    header += mkeys + ["note"]
    table = [header]
    for r in rows:
        line = [_fmt(r["params"].get(k, "")) for k in pkeys]
        line += [r["method"], _fmt(r["ms_median"]), _fmt(r["ms_min"]), _fmt(r["ms_max"]), str(r["repeats"])]
        if ratio_col:
            f = floors.get(case_key(r))
            line.append(f"{r['ms_median'] / f:.2f}" if f else "")
        line += [_fmt(r["metrics"][k]) if k in r["metrics"] else "" for k in mkeys]
        line.append(r.get("note", ""))
        table.append(line)
    widths = [max(len(row[i]) for row in table) for i in range(len(header) - 1)]
    out = []
    for i, row in enumerate(table):
        cells = [c.rjust(w) if j < len(pkeys) or j > len(pkeys) else c.ljust(w)
                 for j, (c, w) in enumerate(zip(row[:-1], widths, strict=True))]
        out.append("  ".join(cells + [row[-1]]).rstrip())
        if i == 0:
            out.append("-" * len(out[0]))
    return "\n".join(out)


def write_json(rows: list[Mapping[str, Any]], path: str | Path) -> Path:
    """Write the rows as a JSON list (parents created), atomically (:mod:`morphkit.files.fileio`).

    Parameters
    ----------
    rows : list of mapping
        Rows from :func:`make_row`.
    path : str or pathlib.Path
        The JSON file.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    return fileio.write_json(p, list(rows), indent=1)


def _save_figure(fig: Any, path: Path, *, tight: bool = False) -> Path:
    """Render ``fig`` to PNG in memory and write it atomically (:mod:`morphkit.files.fileio`);
    ``tight``: the canvas grown to what is drawn outside the axes (a legend beside them)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, **({"bbox_inches": "tight"} if tight else {}))
    return fileio.write_bytes(path, buf.getvalue())


def write_plots(rows: list[Mapping[str, Any]], plot_path: str | Path, *, size_key: str = "size",
                error_key: str | None = None, panel_keys: tuple[str, ...] = (),
                scene_keys: tuple[str, ...] | None = None, defaults: Sequence[Mapping[str, Any]] = (),
                family: str | None = None, default_label: str = "default") -> list[Path]:
    """Write ``<stem>_time_vs_size.png`` and, where rows carry ``error_key``, ``<stem>_time_vs_error.png``.

    Both go next to ``plot_path`` (its suffix is replaced). The time-vs-size
    figure has one panel per combination of ``panel_keys`` values and one line
    per method (log-log). The time-vs-error figure has one panel per scene and, in
    each, every method's front through its Pareto-optimal rows, its other rows
    faint, and the default configuration starred (:func:`morphkit.bench.fronts.error_figure`).
    Returns the paths written.

    Parameters
    ----------
    rows : list of mapping
        Rows from :func:`make_row`.
    plot_path : str or pathlib.Path
        Where the plots go: its folder (created) and its stem.
    size_key : str
        The ``params`` key of the x axis of the time-vs-size figure (rows without it are left out).
    error_key : str, optional
        The ``metrics`` key of the x axis of the time-vs-error figure; ``None``: no such figure.
    panel_keys : tuple of str
        ``params`` keys whose value combinations get a panel each.
    scene_keys : tuple of str, optional
        ``params`` keys whose value combinations are the scenes of the time-vs-error figure, a
        panel each; ``None``: ``panel_keys``.
    defaults : sequence of mapping
        The default configurations, starred (:func:`morphkit.bench.fronts.is_default`).
    family : str, optional
        A regular expression: the end of a method's name that names its parameter, so that
        ``warp_5``, ``warp_9``, ... are drawn as one method (:func:`morphkit.bench.fronts.method_family`).
    default_label : str
        The legend's and the star's label.

    Returns
    -------
    list of pathlib.Path
        The PNG files written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = Path(plot_path)
    p.parent.mkdir(parents=True, exist_ok=True)
    stem = p.with_suffix("")
    written: list[Path] = []
    methods = list(dict.fromkeys(r["method"] for r in rows))
    palette = plt.get_cmap("tab20").colors  # 20 distinct colours: suites have > 10 methods
    colors = {m: palette[i % len(palette)] for i, m in enumerate(methods)}

    # panels: one per combination of panel_keys among rows that have a size to plot against
    panels = list(dict.fromkeys(tuple(r["params"].get(k) for k in panel_keys) for r in rows
                                if size_key in r["params"]))
    ncol = min(4, max(len(panels), 1))
    nrow = max(math.ceil(len(panels) / ncol), 1)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.4 * nrow), squeeze=False)
    for ax, panel in zip(axes.ravel(), panels, strict=False):
        for m in methods:
            pts = sorted(
                (r["params"][size_key], r["ms_median"], r["ms_min"], r["ms_max"])
                for r in rows
                if r["method"] == m and size_key in r["params"]
                and tuple(r["params"].get(k) for k in panel_keys) == panel
            )
            if not pts:
                continue
            xs, med, lo, hi = zip(*pts, strict=True)
            ax.plot(xs, med, "o-", color=colors[m], label=m, ms=3)
            ax.fill_between(xs, lo, hi, color=colors[m], alpha=0.15, lw=0)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel(size_key)
        ax.set_ylabel("ms (median; band min-max)")
        ax.set_title(", ".join(f"{k}={v}" for k, v in zip(panel_keys, panel, strict=True)) or "all",
                     fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    fig.tight_layout()
    out = Path(f"{stem}_time_vs_size.png")
    try:
        _save_figure(fig, out)
    finally:
        plt.close(fig)
    written.append(out)

    if error_key is not None:
        fig = error_figure(rows, error_key, scene_keys=panel_keys if scene_keys is None else scene_keys,
                           defaults=defaults, family=family, error_floor=PLOT_ERROR_FLOOR,
                           default_label=default_label)
        if fig is not None:
            out = Path(f"{stem}_time_vs_error.png")
            try:
                _save_figure(fig, out, tight=True)
            finally:
                plt.close(fig)
            written.append(out)
    return written
