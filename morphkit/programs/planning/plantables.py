"""A plan's error tables (:class:`~morphkit.plan.errortable.ErrorTable`): each drawn asset's grid of
on-screen heights and elevations, only what the scene's frames need (:func:`table_grids`), and its
table in every representation, read from a cache where one was measured of the same asset under the
same conditions, else measured and cached at once (:func:`scene_tables`).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ... import tol
from ...errors import FileFormatError
from ...plan.errortable import ErrorTable, default_elevations, measure_error_table
from ...plan.mixed import uniform_mode
from ...plan.planner import sample_scene
from ...plan.representations import REPRESENTATIONS, RealMesh
from ...render import Renderer
from ..scenerender import PreparedScene

__all__ = ["PLAN_AZIMUTHS_DEG", "scene_tables", "table_grids"]

#: Azimuths (degrees, object frame) each cell of a plan's tables averages: six, whose offsets from the
#: references of rings of 12, 8, 6 and 4 views spread over the pair between (a card's and a nearest
#: view's error change with the azimuth more than the morph's: three azimuths missed them by 2 dB).
PLAN_AZIMUTHS_DEG: tuple[float, ...] = (18.0, 70.0, 124.0, 190.0, 276.0, 330.0)


def _table_params(prep: PreparedScene, focal_px: float, light: Any) -> dict[str, Any]:
    """What a table is measured under (a cached table is reused only when they are equal)."""
    sun = (
        None if light is None else [np.asarray(lt.direction, float).round(6).tolist() for lt in light.lights]
    )
    fog = prep.scene.backdrop.fog
    return {"focal_px": float(focal_px), "sun": sun, "fog": fog is not None, "relit": prep.relit,
            "frame_px": tol.PLAN_MAX_TABLE_FRAME_PX}


def _bracket(bins: Sequence[float], lo: float, hi: float) -> list[float]:
    """The bins from the last at or below ``lo`` to the first at or above ``hi``."""
    b = sorted(bins)
    first = max([k for k, v in enumerate(b) if v <= lo], default=0)
    last = min([k for k, v in enumerate(b) if v >= hi], default=len(b) - 1)
    return b[first : max(last, first + 1) + 1] if len(b) > 1 else b


def table_grids(prep: PreparedScene, cameras: Sequence[Any]) -> dict[str, tuple[list[float], list[float]]]:
    """Each drawn asset's table grid, only what the frames need: the on-screen heights (doubling from
    :data:`morphkit.tol.PLAN_MIN_TABLE_HEIGHT_PX` up to :data:`morphkit.tol.PLAN_MAX_TABLE_HEIGHT_PX`;
    taller billboards are looked up at the top row) and
    the elevations (:func:`~morphkit.plan.errortable.default_elevations`) that bracket the billboards
    the frames draw of it.

    Parameters
    ----------
    prep : PreparedScene
        The scene.
    cameras : sequence of CameraModel
        Its frames.

    Returns
    -------
    dict of str to (heights, elevations)
    """
    seen: dict[str, list[tuple[float, float]]] = {}
    scene = sample_scene(prep.scene)
    for cam in cameras:
        for pl in scene.plan(cam).placements:
            seen.setdefault(pl.asset, []).append((pl.height_px, pl.elevation_deg))
    doubling = [tol.PLAN_MIN_TABLE_HEIGHT_PX]
    while doubling[-1] < tol.PLAN_MAX_TABLE_HEIGHT_PX:
        doubling.append(2.0 * doubling[-1])
    out = {}
    for nm, hv in seen.items():
        h = np.array([x for x, _ in hv])
        e = np.array([x for _, x in hv])
        out[nm] = (
            _bracket(doubling, float(h.min()), float(min(h.max(), doubling[-1]))),
            _bracket(default_elevations(prep.scene.assets[nm]), float(e.min()), float(e.max())),
        )
    return out


def _table_key(
    nm: str, asset: Any, want: Mapping[str, Any], heights: Sequence[float], elevations: Sequence[float]
) -> str:
    """The cache name of a table: what it is measured of and under, hashed."""
    what = {
        "asset": nm,
        "mesh": asset.mesh_hash,
        "kind": type(asset).__name__,
        "size": list(asset.size),
        "levels": int(asset.levels),
        "heights": list(heights),
        "elevations": list(elevations),
        **want,
    }
    return hashlib.sha256(json.dumps(what, sort_keys=True, default=str).encode()).hexdigest()[:16]


def scene_tables(
    prep: PreparedScene,
    renderer: Renderer,
    focal_px: float,
    grids: Mapping[str, tuple[list[float], list[float]]],
    cache: Path,
    previous: Path,
    head: str,
) -> tuple[dict[tuple[str, str], ErrorTable], list[str]]:
    """Every used asset's table in every representation: read from ``cache`` (or a previous plan's
    ``previous`` folder) when one there was measured of the same asset under the same conditions,
    else measured and written to ``cache`` at once (a plan that fails its budget keeps them); the real
    mesh's is exact (:meth:`~morphkit.plan.errortable.ErrorTable.exact`).

    Parameters
    ----------
    prep : PreparedScene
        The scene (its assets, instances, lights and backdrop).
    renderer : Renderer
        Draws the tables' frames.
    focal_px : float
        The scene's focal length (pixels): the tables are measured under it.
    grids : mapping of str to (heights, elevations)
        Each drawn asset's grid (:func:`table_grids`).
    cache : Path
        The folder tables are kept in between runs.
    previous : Path
        A previous plan's ``tables`` folder (read where its tables match).
    head : str
        What the printed line starts with.

    Returns
    -------
    tables : dict of (asset, representation) to ErrorTable
        Every table.
    measured : list of str
        The ``asset.representation`` names measured in this call.
    """
    light = prep.lighting[len(prep.lighting) // 2] if prep.lighting else None
    want = _table_params(prep, focal_px, light)
    want["azimuths_deg"] = list(PLAN_AZIMUTHS_DEG)
    tables: dict[tuple[str, str], ErrorTable] = {}
    measured: list[str] = []
    reused = exact = 0
    for nm, (heights, elevations) in grids.items():
        asset = prep.scene.assets[nm]
        inst = prep.scene.instances
        scale = float(np.median(inst.scale[inst.asset == inst.names.index(nm)]))
        want_asset = {**want, "scale": scale}
        key = _table_key(nm, asset, want_asset, heights, elevations)
        for rep in REPRESENTATIONS:
            if isinstance(rep, RealMesh):  # the truth's own drawing
                tables[(nm, rep.name)] = ErrorTable.exact(
                    nm, asset.mesh_hash, rep.name, heights, elevations, want_asset
                )
                exact += 1
                continue
            for path in (cache / f"{nm}.{rep.name}.{key}.npz", previous / f"{nm}.{rep.name}.npz"):
                if not path.is_file():
                    continue
                try:
                    t = ErrorTable.load(path, mesh_hash=asset.mesh_hash)
                except FileFormatError:
                    continue
                same = (
                    t.heights_px.tolist() == list(heights)
                    and t.elevations_deg.tolist() == list(elevations)
                    and t.representation == rep.name
                    and all(t.params.get(k) == v for k, v in want_asset.items())
                )
                if same:
                    tables[(nm, rep.name)] = t
                    reused += 1
                    break
            if (nm, rep.name) in tables:
                continue
            mode = uniform_mode(rep, prep.relit, light, None, prep.meshes())  # alone, as the scene lights it
            t = measure_error_table(
                asset,
                prep.resolved.items[nm],
                renderer,
                mode,
                heights_px=heights,
                elevations_deg=elevations,
                azimuths_deg=PLAN_AZIMUTHS_DEG,
                lighting=light,
                representation=rep.name,
                params=want_asset,
                focal_px=focal_px,
                facing=prep.scene.facing,
                backdrop=prep.scene.backdrop,
                scale=scale,
            )
            tables[(nm, rep.name)] = t
            cache.mkdir(parents=True, exist_ok=True)
            t.save(cache / f"{nm}.{rep.name}.{key}.npz")
            measured.append(f"{nm}.{rep.name}")
    print(
        f"{head}error tables: {len(measured)} measured, {reused} read (cache {cache}), {exact} exact "
        "(the real mesh: the truth's own drawing)",
        flush=True,
    )
    return tables, measured
