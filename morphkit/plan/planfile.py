"""A scene's plan as a file: ``plan.json``, written by ``morphkit plan`` and drawn by
``morphkit render SCENE --plan PLAN``.

The file is one JSON object, versioned by ``"morphkit_plan": 1`` (:data:`PLAN_VERSION`; another
version is refused on reading):

* ``"budget"`` -- the budget planned to (:meth:`~.budget.Budget.to_json`);
* ``"relit"`` -- whether the plan is of relit dome assets (a sun) or ring assets;
* ``"assets"`` -- the asset names it plans;
* ``"default"`` -- the representation of a band the plan does not list;
* ``"choices"`` -- one entry per band seen: ``asset``, ``level``, ``elevation_band``, the band in
  words (``band``), its on-screen height and elevation ranges (``height_px``: ``[lo, hi]``, ``hi``
  None for level 0; ``elevation_deg``), the ``representation`` and how many billboards it draws over
  the path (``billboards``);
* ``"image_size"`` -- ``[W, H]``, the frames' size the bands' heights are of (a plan written before
  it was recorded has none);
* ``"shadow"`` -- with a ``shadow-iou`` budget, the frames' shadow chosen (:mod:`.shadowchoice`):
  its ``soft`` (null, ``"pcss"`` or N) and ``sun_atlas_size``, read back and drawn by
  ``render --plan``, with what was measured of every candidate (kept as written);
* what ``morphkit plan`` measured: ``"verified"``, ``"time_ms"``, ``"error"``, ``"predicted"``,
  ``"sweep"`` (:mod:`morphkit.programs.planning.planrun`), kept as written and not read back.

:class:`ScenePlan` holds what drawing needs (budget, bands, kind) and makes the frames' mode
(:meth:`ScenePlan.mode`).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import read_json, write_json
from ..imaging.shading import Lighting
from ..scenes.description import SceneShadows
from .budget import Budget
from .mixed import banded_mode
from .representations import ELEVATION_EDGES_DEG, BandChoice, band_label

__all__ = ["ScenePlan", "PLAN_VERSION", "PLAN_NAME", "read_plan"]

#: The ``"morphkit_plan"`` version this module writes and reads.
PLAN_VERSION = 1
#: The plan's file name in ``morphkit plan``'s output folder.
PLAN_NAME = "plan.json"


@dataclass(frozen=True)
class ScenePlan:
    """A plan: the bands' representations, for a scene's assets (the module notes).

    Parameters
    ----------
    budget : Budget
        The budget planned to.
    choice : BandChoice
        The bands' representations.
    relit : bool
        Relit dome assets, else ring assets.
    assets : tuple of str
        The asset names planned.
    counts : dict of Band to int, optional
        Billboards each band draws over the path (reported).
    base_height : dict of str to int, optional
        Each asset's image height at level 0 (the bands in words).
    report : dict, optional
        What was measured (written as the file's other entries).
    shadows : SceneShadows, optional
        The frames' shadow chosen (None: the scene's own); the scene's sun disc is kept.
    shape : (H, W), optional
        The frames' size (None: not recorded).
    """

    budget: Budget
    choice: BandChoice
    relit: bool
    assets: tuple[str, ...]
    counts: dict[tuple[str, int, int], int] = field(default_factory=dict)
    base_height: dict[str, int] = field(default_factory=dict)
    report: dict[str, Any] = field(default_factory=dict)
    shadows: SceneShadows | None = None
    shape: tuple[int, int] | None = None

    def check_kind(self, relit: bool) -> None:
        """Refuse a plan of the other kind of asset.

        Parameters
        ----------
        relit : bool
            The scene's assets are relit dome assets (it has a sun).

        Raises
        ------
        ValidationError
            A plan of ring assets for relit ones, or the reverse.
        """
        if relit != self.relit:
            kinds = {True: "relit dome assets (a scene with a sun)", False: "ring assets (no sun)"}
            raise ValidationError(
                expected_got("plan", f"a plan of {kinds[relit]}", f"one of {kinds[self.relit]}")
            )

    def mode(self, relit: bool, base: Lighting, shadow: Any = None, meshes: Any = None) -> Any:
        """The frames' mode: each billboard in its band's representation, the bands of the real mesh
        drawn as meshes (:mod:`~morphkit.plan.mixed`).

        Parameters
        ----------
        relit : bool
            The scene's assets are relit dome assets.
        base : Lighting
            The relit mode's lighting until a frame sets its sun.
        shadow : SceneShadow, optional
            The frames' shadow (relit).
        meshes : LitMeshMode or MeshMode, optional
            Draws the real meshes (needed when a band is the real mesh).

        Returns
        -------
        FrameMode

        Raises
        ------
        ValidationError
            A plan of the other kind of asset (:meth:`check_kind`); a plan with bands of the real
            mesh and no ``meshes``.
        """
        self.check_kind(relit)
        return banded_mode(self.choice, relit, base, shadow, meshes)

    def check_assets(self, names: Sequence[str]) -> None:
        """Refuse a scene whose assets are not the plan's.

        Parameters
        ----------
        names : sequence of str
            The scene's asset names.

        Raises
        ------
        ValidationError
            Other names.
        """
        if sorted(names) != sorted(self.assets):
            raise ValidationError(
                expected_got(
                    "plan", f"a plan of the scene's assets {sorted(names)}", f"one of {sorted(self.assets)}"
                )
            )

    def to_json(self) -> dict[str, Any]:
        """The plan's file content (the module notes).

        Returns
        -------
        dict
        """
        edges = (0.0, *ELEVATION_EDGES_DEG, 90.0)
        choices = []
        for band, rep in sorted(self.choice.choices.items()):
            name, level, e = band
            h0 = self.base_height.get(name)
            entry: dict[str, Any] = {"asset": name, "level": level, "elevation_band": e}
            if h0 is not None:
                hi = h0 / 2.0**level
                entry["band"] = band_label(band, h0)
                entry["height_px"] = [hi / 2.0, None if level == 0 else hi]
            entry["elevation_deg"] = [edges[e], edges[e + 1]]
            entry["representation"] = rep
            entry["billboards"] = int(self.counts.get(band, 0))
            choices.append(entry)
        out: dict[str, Any] = {
            "morphkit_plan": PLAN_VERSION,
            "budget": self.budget.to_json(),
            "relit": self.relit,
            "assets": list(self.assets),
            "default": self.choice.default,
            "choices": choices,
        }
        if self.shape is not None:
            out["image_size"] = [int(self.shape[1]), int(self.shape[0])]
        out.update(self.report)
        if self.shadows is not None:
            chosen = {"soft": self.shadows.soft, "sun_atlas_size": self.shadows.sun_atlas_size}
            out["shadow"] = {**out.get("shadow", {}), **chosen}
        return out

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the plan to ``path`` atomically.

        Parameters
        ----------
        path : path-like
            The file.

        Returns
        -------
        pathlib.Path
        """
        return write_json(path, self.to_json())


def _budget(obj: Any) -> Budget:
    if not isinstance(obj, dict) or not obj:
        raise FileFormatError(expected_got("plan budget", "an object of budget keys", repr(obj)[:80]))
    try:
        return Budget.parse(f"{k}={v}" for k, v in obj.items())
    except ValidationError as exc:
        raise FileFormatError(f"plan budget: {exc}") from exc


def read_plan(path: str | os.PathLike[str]) -> ScenePlan:
    """The plan in ``path`` (``morphkit plan``'s ``plan.json``, or its folder).

    Parameters
    ----------
    path : path-like
        The file, or a folder holding :data:`PLAN_NAME`.

    Returns
    -------
    ScenePlan

    Raises
    ------
    FileFormatError
        No such file, not JSON, another version, entries missing or of the wrong kind.
    """
    p = Path(path)
    if p.is_dir():
        p = p / PLAN_NAME
    obj = read_json(p, "plan file")
    if not isinstance(obj, dict) or "morphkit_plan" not in obj:
        raise FileFormatError(
            expected_got(
                f"plan file {p}",
                "a morphkit plan (a 'morphkit_plan' entry)",
                type(obj).__name__ if not isinstance(obj, dict) else sorted(obj)[:5],
            )
        )
    if obj["morphkit_plan"] != PLAN_VERSION:
        raise FileFormatError(
            expected_got(f"plan file {p}", f"morphkit_plan {PLAN_VERSION}", repr(obj["morphkit_plan"]))
        )
    try:
        relit = obj["relit"]
        assets = obj["assets"]
        if (
            not isinstance(relit, bool)
            or not isinstance(assets, list)
            or not all(isinstance(a, str) for a in assets)
        ):
            raise TypeError("relit must be true or false, assets a list of names")
        bands = {}
        counts = {}
        base: dict[str, int] = {}
        for c in obj["choices"]:
            band = (c["asset"], c["level"], c["elevation_band"])
            bands[band] = c["representation"]
            counts[band] = int(c.get("billboards", 0))
            if c.get("height_px") is not None:  # lo = h0 / 2^(level + 1)
                base[c["asset"]] = int(round(float(c["height_px"][0]) * 2.0 ** (int(c["level"]) + 1)))
        size = obj.get("image_size")
        shape = None
        if size is not None:
            if not isinstance(size, list) or len(size) != 2:
                raise TypeError("image_size must be [W, H]")
            shape = (int(size[1]), int(size[0]))
        choice = BandChoice(bands, obj.get("default", "morph"))
        shadow = obj.get("shadow")
        shadows = None
        if shadow is not None:
            if not isinstance(shadow, dict):
                raise TypeError("shadow must be an object of soft and sun_atlas_size")
            shadows = SceneShadows(soft=shadow["soft"], sun_atlas_size=shadow["sun_atlas_size"])
    except (KeyError, TypeError, ValueError, ValidationError) as exc:
        raise FileFormatError(
            expected_got(
                f"plan file {p}", "relit, assets and choices of a plan", f"{type(exc).__name__}: {exc}"
            )
        ) from exc
    return ScenePlan(_budget(obj.get("budget")), choice, relit, tuple(assets), counts, base, shadows=shadows,
                     shape=shape)
