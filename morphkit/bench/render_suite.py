"""``morphkit bench render``: the rendering boundary's cost and depth accuracy.

Rows:

* ``what=depth``: one light-view depth map (perspective, fitted to the object)
  of the cow-like mesh at ~6k / 50k / 300k / 1M faces, per map size
  (64..1024), with a renderer created once and reused (the floor ``direct``
  of the shadows suite). ``create_context`` times a fresh
  :class:`~morphkit.render.Renderer`'s first (empty) depth map of that size and
  its close: the GL context's creation and deletion, the cost a renderer created
  per frame would pay.

Every row carries ``gl`` (:func:`morphkit.render.gl_info`: the platform,
``osmesa`` or ``egl`` as ``MORPHKIT_GL`` chose, and the ``GL_RENDERER`` string).
* ``what=accuracy``: depth of an analytic plane facing the camera at distance
  ``dist`` (``znear = 0.05``, ``zfar = 100``), orthographic and perspective:
  metrics ``rel_err_max`` over all pixels (morphkit's linearisation) and, for
  orthographic, ``pyrender_raw_rel_err`` (pyrender's own perspective-formula
  value, the bug morphkit corrects).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import trimesh

from ..camera import look_at, orthographic, perspective
from ..meshes import sample_mesh
from ..render import Renderer
from ..scene import PointLight, light_view
from .harness import Timing, make_row, time_call, time_calls

__all__ = ["run", "FLOOR_METHOD", "PLOT_OPTIONS"]

SUITE = "render"
#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "depth_6k"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS = {"size_key": "size", "panel_keys": ("what",)}


def _depth_rows(renderer: Renderer, quick: bool) -> list[dict[str, Any]]:
    from ..scene import Item

    rows = []
    faces = [6000, 50000] if quick else [6000, 50000, 300000, 1000000]
    sizes = [64, 256] if quick else [64, 128, 256, 512, 1024]
    meshes = {f: sample_mesh("cow", faces=f) for f in faces}
    light = PointLight([0.3, -0.2, 2.5])
    for size in sizes:
        fns = {}
        for f, mesh in meshes.items():
            cam = light_view(light, trimesh.bounds.corners(mesh.bounds), (size, size))
            item = [Item(mesh)]
            renderer.depth(cam, item)  # upload once
            fns[f"depth_{f // 1000}k"] = lambda cam=cam, item=item: renderer.depth(cam, item)
        timings = time_calls(fns, repeats=5 if quick else 11, warmup=1)

        def create(cam: Any = cam) -> None:
            with Renderer() as fresh:
                fresh.depth(cam, [])

        timings["create_context"] = time_call(create, repeats=3 if quick else 5, warmup=0)
        for name, t in timings.items():
            f = next((k for k in faces if name == f"depth_{k // 1000}k"), None)
            params = {"what": "depth", "size": size}
            if f is not None:
                params["faces"] = len(meshes[f].faces)
            rows.append(make_row(SUITE, name, params, t))
    return rows


def _accuracy_rows(renderer: Renderer) -> list[dict[str, Any]]:
    from ..scene import Item

    plane = trimesh.Trimesh([[-100, -100, 0], [100, -100, 0], [100, 100, 0], [-100, 100, 0]],
                            [[0, 1, 2], [0, 2, 3]], process=False)
    rows = []
    for dist in (0.5, 1.0, 3.0, 10.0, 50.0):
        pose = look_at([0, 0, dist], [0, 0, 0], up=[0, 1, 0])
        for proj in ("orthographic", "perspective"):
            if proj == "orthographic":
                cam = orthographic(2, 2, (64, 64), pose, znear=0.05, zfar=100)
            else:
                cam = perspective(np.deg2rad(50), (64, 64), pose, znear=0.05, zfar=100)
            d = renderer.depth(cam, [Item(plane)])
            metrics = {"rel_err_max": float(np.abs(d / dist - 1).max())}
            if proj == "orthographic":
                raw = renderer.pyrender_depth(cam, [Item(plane)])
                metrics["pyrender_raw_rel_err"] = float(np.abs(raw / dist - 1).max())
            rows.append(make_row(SUITE, f"plane_{proj}", {"what": "accuracy", "dist": dist},
                                 Timing(0.0, 0.0, 0.0, 1), metrics=metrics))
    return rows


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """Run the suite (the rows are described in the module docstring).

    Parameters
    ----------
    quick : bool
        The reduced sweep (two mesh sizes).

    Returns
    -------
    list of dict
        One row per case, as :func:`morphkit.bench.harness.make_row` makes them.
    """
    from ..render import Renderer

    with Renderer() as renderer:
        return _depth_rows(renderer, quick) + _accuracy_rows(renderer)
