"""``morphkit bench preview``: the preview page in headless Chromium against morphkit's own render and the
real mesh, its frame time in software WebGL, and the pages' sizes and first draws.

Scenes and cases:

* ``what=view``: the tree sample (dome asset of 128 px views, sun atlas of 128 texels, baked as
  ``morphkit export`` bakes it), one instance at the origin, seen at three cameras and suns
  (:data:`VIEWS`, 480 x 360). Per camera, timed round-robin over ``repeats`` rounds:

  - ``page``: the page's frame after a camera move (its own ``frame_ms``: the ground and the
    billboard, read back; the light view is drawn again only when the sun moves, so not in these
    frames) in headless Chromium on SwiftShader, the software WebGL 2 Chromium ships;
    ``psnr_ref_db`` is its PSNR against ``reference`` and ``psnr_db`` against ``truth``;
  - ``reference``: :func:`~morphkit.export.previewref.reference_image`, morphkit's own morph of the
    same camera and sun (numpy and OpenCV); ``psnr_db`` against ``truth``;
  - ``truth``: :func:`~morphkit.export.previewref.truth_image`, the real mesh rendered (OSMesa or
    EGL) with its ground shadow ray cast: the baseline;
  - ``page_impostor``: the page of the tree's octahedral impostor (12 x 12 frames, one level, of
    as many bytes as the dome's views), ``psnr_ref_db`` against ``reference_impostor``:
    :func:`~morphkit.export.previewref.reference_image` of the impostor along the same rays.

* ``what=page``: pages written by ``morphkit preview`` -- the tree (its impostor beside it), the forest scene
  (``samples/scenes/forest.json``: 90 instances of three assets, at its first camera key; present in
  a source checkout) and a grid of 100,489 instances of the analytic ball -- with their ``bytes``,
  ``draw_s`` (from loading the page to its ``morphkit: ready``; its first frame draws the light
  view), ``first_frame_ms`` and ``frame_ms`` (the median of camera moves) at 640 x 480.

Needs chromium, chromedriver and selenium (``scripts/setup.sh test``) and GL.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from ..billboard.analytic import sphere_dome_asset
from ..billboard.impostor import bake_impostor, impostor_frame_size
from ..export.browser import Browser
from ..export.preview import PreviewView, asset_entry, impostor_entry, preview_data, write_preview
from ..export.previewref import reference_image, truth_image
from ..imaging.metrics import psnr
from ..render import Renderer
from ..sunlit.sunatlas import sphere_sun_atlas
from ..views.gbuffer import BYTES_PER_PIXEL
from .harness import Timing, make_row

__all__ = ["run", "FLOOR_METHOD", "PLOT_OPTIONS", "VIEWS"]

SUITE = "preview"
#: The baseline the table's ratio column divides by: the real mesh's render and ray cast.
FLOOR_METHOD = "truth"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots`.
PLOT_OPTIONS = {"size_key": "camera", "panel_keys": ("what",), "error_key": "psnr_db"}

#: The compared cameras and suns: low, high, and from behind against the sun.
VIEWS = (PreviewView(30.0, 20.0, 2.2, 40.0, 135.0, 45.0, 480, 360),
         PreviewView(-100.0, 45.0, 2.0, 40.0, 60.0, 30.0, 480, 360),
         PreviewView(170.0, 5.0, 2.6, 40.0, -40.0, 60.0, 480, 360))

_ONE = np.array([[0.0, 0.0, 0.0, 0.0, 1.0]])
_ROOT = Path(__file__).resolve().parents[2]


def _view_rows(browser: Browser, folder: Path, repeats: int) -> list[dict[str, Any]]:
    from ..programs.export import IMPOSTOR_FRAMES, bake_asset_parts

    parts = bake_asset_parts("tree")
    a = parts.asset
    page = write_preview(folder / "tree.html", preview_data(
        [asset_entry(a, parts.sun_atlas, _ONE)], VIEWS[0], a.pivot, 1.0, title="tree"))
    items = a.items(parts.mesh)
    rows: list[dict[str, Any]] = []
    with Renderer() as r:
        m = impostor_frame_size(a.dome.views * a.size[0] * a.size[1] * BYTES_PER_PIXEL,
                                frames=IMPOSTOR_FRAMES, levels=1)
        imp = bake_impostor(parts.mesh, r, name="tree", frames=IMPOSTOR_FRAMES, frame_size=m, levels=1,
                            appearance=a.appearance)
        imp_page = write_preview(folder / "tree_impostor.html", preview_data(
            [impostor_entry(imp, parts.sun_atlas, _ONE)], VIEWS[0], a.pivot, 1.0, title="impostor"))
        for i, view in enumerate(VIEWS):
            frag = view.fragment()
            shot = browser.show(page, frag) if i == 0 else browser.redraw(frag)
            times: dict[str, list[float]] = {"page": [], "reference": [], "truth": []}
            for k in range(repeats + 1):  # one warm-up round
                got = browser.redraw(frag.replace("fov=40", f"fov={40 + 1e-3 * (k + 1):.3f}"))
                t0 = time.perf_counter()
                ref = reference_image(parts.asset, parts.sun_atlas, _ONE, view, parts.asset.pivot)
                t1 = time.perf_counter()
                truth = truth_image(parts.mesh, items, r, view, parts.asset.pivot)
                t2 = time.perf_counter()
                if k:
                    times["page"].append(1e-3 * float(got.stats["frame_ms"]))
                    times["reference"].append(t1 - t0)
                    times["truth"].append(t2 - t1)
            params = {"what": "view", "camera": i, "fragment": frag, "asset": "tree", "size": 128,
                      "image": f"{view.width}x{view.height}", "impostor_frame": m}
            err = {"page": {"psnr_db": psnr(shot.image, truth, data_range=1.0),
                            "psnr_ref_db": psnr(shot.image, ref, data_range=1.0)},
                   "reference": {"psnr_db": psnr(ref, truth, data_range=1.0)}, "truth": {}}
            note = {"page": "headless Chromium, SwiftShader WebGL 2", "reference": "morphkit's morph (numpy)",
                    "truth": "mesh render + ray-cast ground shadow"}
            # the impostor at equal bytes, its page against morphkit's impostor along the same rays
            browser.show(imp_page, frag)
            times["page_impostor"], times["reference_impostor"] = [], []
            for k in range(repeats + 1):
                got_i = browser.redraw(frag.replace("fov=40", f"fov={40 + 1e-3 * (k + 1):.3f}"))
                t0 = time.perf_counter()
                ref_i = reference_image(imp, parts.sun_atlas, _ONE, view, a.pivot)
                if k:
                    times["page_impostor"].append(1e-3 * float(got_i.stats["frame_ms"]))
                    times["reference_impostor"].append(time.perf_counter() - t0)
            shot_i = browser.redraw(frag)
            err["page_impostor"] = {"psnr_db": psnr(shot_i.image, truth, data_range=1.0),
                                    "psnr_ref_db": psnr(shot_i.image, ref_i, data_range=1.0)}
            err["reference_impostor"] = {"psnr_db": psnr(ref_i, truth, data_range=1.0)}
            note["page_impostor"] = f"octahedral impostor {IMPOSTOR_FRAMES}^2 x {m} px, equal bytes; Chromium"
            note["reference_impostor"] = "morphkit's impostor along the same rays (numpy)"
            browser.show(page, frag)
            for meth, samples in times.items():
                rows.append(make_row(SUITE, meth, params, Timing.from_seconds(samples), metrics=err[meth],
                                     note=note[meth]))
    return rows


def _page_row(browser: Browser, page: Path, name: str, view: PreviewView, repeats: int) -> dict[str, Any]:
    """A page's size, first draw and frame time at ``view`` (redrawn at fields of view a thousandth
    of a degree apart, so that each redraw is a new frame)."""
    frag = view.fragment()
    shot = browser.show(page, frag)
    fov = f"fov={view.fov_deg:.3f}".rstrip("0").rstrip(".")
    frames = [1e-3 * float(browser.redraw(frag.replace(fov, f"fov={view.fov_deg + 1e-3 * (k + 1):.3f}"))
                           .stats["frame_ms"]) for k in range(repeats)]
    params = {"what": "page", "camera": name, "instances": int(shot.stats.get("instances", 0)),
              "bytes": page.stat().st_size, "image": "640x480"}
    return make_row(SUITE, f"page_{name}", params, Timing.from_seconds(frames),
                    metrics={"draw_s": shot.seconds, "bytes": float(page.stat().st_size),
                             "first_frame_ms": float(shot.stats.get("frame_ms", 0.0))},
                    note="frame_ms: the page's own redraws; draw_s: load to 'morphkit: ready'")


def _view_of(fragment: str) -> PreviewView:
    """The :class:`PreviewView` of a page's fragment (``preview_page``'s first view)."""
    f = dict(kv.split("=", 1) for kv in fragment.split("&"))
    az, el, dist = (float(v) for v in f["camera"].split(","))
    saz, sel = (float(v) for v in f["sun"].split(","))
    w, h = (int(v) for v in f["size"].split("x"))
    return PreviewView(az, el, dist, float(f["fov"]), saz, sel, w, h)


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """Measure (the module notes).

    Parameters
    ----------
    quick : bool, optional
        Fewer rounds (3, else 7), and no 100k-instance page.

    Returns
    -------
    list of dict
        The rows.
    """
    from ..programs.preview import preview_page

    repeats = 3 if quick else 7
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp, Browser(window=(700, 560), timeout_s=300) as browser:
        folder = Path(tmp)
        rows += _view_rows(browser, folder, repeats)
        got = preview_page("tree", folder / "tree_page.html")
        rows.append(_page_row(browser, folder / "tree_page.html", "tree", _view_of(got["fragment"]), repeats))
        forest = _ROOT / "samples" / "scenes" / "forest.json"
        if forest.is_file():
            got = preview_page(str(forest), folder / "forest.html")
            rows.append(_page_row(browser, folder / "forest.html", "forest", _view_of(got["fragment"]),
                                  repeats))
        if not quick:
            ball = sphere_dome_asset(size=48, levels=1)
            g = (np.arange(317) - 158.5) * 2.0
            x, y = np.meshgrid(g, g)
            rng = np.random.default_rng(3)
            inst = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size), rng.uniform(-180, 180, x.size),
                                    rng.uniform(0.6, 1.4, x.size)])
            view = PreviewView(30.0, 25.0, 40.0, 40.0, 135.0, 45.0, 640, 480)
            page = write_preview(folder / "field.html", preview_data(
                [asset_entry(ball, sphere_sun_atlas(), inst)], view, np.zeros(3), 400.0, title="field"))
            rows.append(_page_row(browser, page, "field_100k", view, 3))
    return rows
