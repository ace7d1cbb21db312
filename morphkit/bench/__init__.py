"""``morphkit bench``: benchmark suites, each timed against its baselines in one run.

Registering a suite
-------------------
A suite is a callable ``suite(*, quick: bool) -> list[dict]`` (rows from
:func:`morphkit.bench.harness.make_row`). Add it to :data:`SUITES`, preferably
lazily so that importing :mod:`morphkit.bench` stays cheap::

    SUITES["shadows"] = lazy_suite("morphkit.bench.shadow_suite", "run")

or call :func:`register_suite` from the suite's own module. A suite module may
define ``PLOT_OPTIONS`` (keyword arguments of
:func:`morphkit.bench.harness.write_plots`, e.g. ``error_key``, ``panel_keys``)
and ``FLOOR_METHOD`` (the method the table's ratio column divides by).

Outputs of :func:`run_suite`: a table on stdout; ``json_path``: the rows as a
JSON list; ``plot_path``: ``<stem>_time_vs_size.png`` and (when rows carry
errors) ``<stem>_time_vs_error.png`` next to it.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .harness import format_table, write_json, write_plots

__all__ = ["SUITES", "run_suite", "register_suite", "lazy_suite"]

Suite = Callable[..., list[dict[str, Any]]]


def lazy_suite(module: str, attr: str = "run") -> Suite:
    """A suite callable that imports ``module`` only when run.

    Parameters
    ----------
    module : str
        Dotted name of the suite's module, e.g. ``"morphkit.bench.shadow_suite"``.
    attr : str
        The suite function in ``module``.

    Returns
    -------
    callable
        ``suite(*, quick=False) -> list of dict``; its ``__module__`` is ``module`` (so
        :func:`run_suite` finds ``PLOT_OPTIONS`` and ``FLOOR_METHOD`` there).
    """

    def suite(*, quick: bool = False, **options: Any) -> list[dict[str, Any]]:
        return getattr(importlib.import_module(module), attr)(quick=quick, **options)

    suite.__module__ = module  # so run_suite finds PLOT_OPTIONS / FLOOR_METHOD
    suite.__qualname__ = f"lazy_suite({module!r}, {attr!r})"
    return suite


#: Registered suites by name.
SUITES: dict[str, Suite] = {
    "warp": lazy_suite("morphkit.bench.warp_suite", "run"),
    "shadows": lazy_suite("morphkit.bench.shadow_suite", "run"),
    "render": lazy_suite("morphkit.bench.render_suite", "run"),
    "viewmorph": lazy_suite("morphkit.bench.viewmorph_suite", "run"),
    "soft": lazy_suite("morphkit.bench.soft_suite", "run"),
    "bake": lazy_suite("morphkit.bench.bake_suite", "run"),
    "billboards": lazy_suite("morphkit.bench.billboard_suite", "run"),
    "scene": lazy_suite("morphkit.bench.scene_suite", "run"),
    "plan": lazy_suite("morphkit.bench.plan_suite", "run"),
    "preview": lazy_suite("morphkit.bench.preview_suite", "run"),
}


def register_suite(name: str, fn: Suite) -> Suite:
    """Register (or replace) suite ``name``; returns ``fn`` (usable as a decorator factory's body).

    Parameters
    ----------
    name : str
        The suite's name (``morphkit bench <name>``).
    fn : callable
        ``fn(*, quick: bool) -> list of dict``, rows from
        :func:`morphkit.bench.harness.make_row`.

    Returns
    -------
    callable
        ``fn``.
    """
    SUITES[name] = fn
    return fn


def run_suite(name: str, *, quick: bool = False, json_path: str | Path | None = None,
              plot_path: str | Path | None = None, options: dict[str, Any] | None = None
              ) -> list[dict[str, Any]]:
    """Run suite ``name``, print its table, write JSON/plots when paths are given; return the rows.

    Raises :class:`~morphkit.errors.ValidationError` for an unknown ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`SUITES`.
    quick : bool
        Fewer and smaller cases (a smoke run).
    json_path : str or pathlib.Path, optional
        Write the rows there as a JSON list.
    plot_path : str or pathlib.Path, optional
        Write the plots next to it (:func:`morphkit.bench.harness.write_plots`).
    options : dict, optional
        Further keyword arguments of the suite (e.g. ``{"workers": [1, 2, 4]}`` for ``bake``).

    Returns
    -------
    list of dict
        The suite's rows (:func:`morphkit.bench.harness.make_row`).
    """
    if name not in SUITES:
        from ..errors import ValidationError, expected_got

        raise ValidationError(expected_got("bench suite", f"one of {', '.join(sorted(SUITES))}",
                                           f"unknown suite {name!r}"))
    fn = SUITES[name]
    rows = fn(quick=quick, **(options or {}))
    try:
        mod = importlib.import_module(getattr(fn, "__module__", "") or "")
    except ImportError:
        mod = None
    floor = getattr(mod, "FLOOR_METHOD", "remap")
    print(format_table(rows, floor_method=floor), flush=True)
    if json_path is not None:
        print(f"wrote {write_json(rows, json_path)}")
    if plot_path is not None:
        for p in write_plots(rows, plot_path, **getattr(mod, "PLOT_OPTIONS", {})):
            print(f"wrote {p}")
    return rows
