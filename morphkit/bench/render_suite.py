"""``morphkit bench render``: the rendering boundary's cost and depth accuracy.

Rows:

* ``what=depth``: one light-view depth map (perspective, fitted to the object)
  of the cow-like mesh at ~6k / 50k / 300k / 1M faces, per map size
  (64..1024), with a renderer created once and reused (the floor ``direct``
  of the shadows suite). ``create_context`` times a fresh
  :class:`~morphkit.render.Renderer`'s first (empty) depth map of that size and
  its close: the GL context's creation and deletion, the cost a renderer created
  per frame would pay.
* ``what=accuracy``: depth of an analytic plane facing the camera at distance
  ``dist`` (``znear = 0.05``, ``zfar = 100``), orthographic and perspective:
  metrics ``rel_err_max`` over all pixels (morphkit's linearisation) and, for
  orthographic, ``pyrender_raw_rel_err`` (pyrender's own perspective-formula
  value, the bug morphkit corrects).
* ``what=fidelity`` (no timing): the renderer against derivable truths
  (:mod:`morphkit.imaging.fidelity`, interior pixels only). ``quad``: a photo-textured
  quad seen head-on, albedo pass against the texture sampled at each pixel
  centre's UV, ``psnr_db`` and ``max_err`` (8-bit levels), at ``px_per_texel``
  1.8 (magnified) and 0.9 (minified: mipmapped, so below the bilinear truth);
  ``gradient``: a vertex-colour gradient, ``max_err`` against the analytic colour;
  ``normals_plane`` / ``normals_sphere``: ``max_err_deg`` of the normals pass
  against a tilted plane's normal and a flat-shaded icosphere's face normals
  (the triangle hit by each pixel centre's ray; pixels on triangle edges skipped).
* ``what=passes``: the cost of each pass at 512 x 512 for the ~6k-face cow in
  each ``look``: ``color`` (an item colour: today's flat material), ``own`` (no
  colour, no visuals: the default colour), ``vertex`` (vertex colours),
  ``texture`` (a 512^2 photo texture on spherical UVs), ``cutout`` (the same
  texture with an alpha mask, glTF ``MASK``: depth then comes from a flat draw).
  Methods: ``depth_6k`` (:meth:`Renderer.depth`, the ratio column's floor),
  ``lit_6k`` (:meth:`Renderer.color_depth`), ``albedo_6k``, ``normal_6k``, and
  ``passes_6k`` (:meth:`Renderer.passes`: the three draws). Timed round-robin.

Every row carries ``gl`` (:func:`morphkit.render.gl_info`: the platform,
``osmesa`` or ``egl`` as ``MORPHKIT_GL`` chose, and the ``GL_RENDERER`` string).
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import trimesh

from ..camera import look_at, orthographic, perspective
from ..imaging import fidelity
from ..imaging.metrics import psnr
from ..meshes import sample_mesh
from ..render import Renderer
from ..scene import PointLight, light_view
from .harness import Timing, make_row, pick_sections, section_name, time_call, time_calls

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


def _photo(shape: tuple[int, int]) -> tuple[np.ndarray, str]:
    """A photograph (scikit-image's astronaut, a test extra) resized to ``shape``, or a
    seeded synthetic texture when scikit-image is not installed; and which one it is."""
    try:
        import skimage.data
    except ImportError:  # pragma: no cover - scikit-image is a test extra
        rng = np.random.default_rng(0)
        img = cv2.GaussianBlur(rng.random((*shape, 3)).astype(np.float32), (0, 0), 2.0)
        img = (img - img.min()) / (img.max() - img.min())
        return np.rint(img * 255).astype(np.uint8), "synthetic (no scikit-image)"
    return cv2.resize(skimage.data.astronaut(), shape[::-1], interpolation=cv2.INTER_AREA), "photo"


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.sum(a * b, -1), -1.0, 1.0)))


def _fidelity_rows(renderer: Renderer) -> list[dict[str, Any]]:
    from ..scene import Item

    rows = []
    none = Timing(0.0, 0.0, 0.0, 1)
    shape = (256, 256)
    cam = fidelity.head_on_camera(shape)  # the quad spans 0.9 x 256 = 230 px
    uv, inside = fidelity.quad_uv(cam)
    for texels, ppt in ((128, 1.8), (256, 0.9)):
        tex, kind = _photo((texels, texels))
        got = renderer.albedo(cam, [Item(fidelity.textured_quad(tex))]).astype(np.float64)
        truth = fidelity.sample_texture(tex, uv)
        rows.append(make_row(SUITE, "quad", {"what": "fidelity", "px_per_texel": ppt}, none, metrics={
            "psnr_db": psnr(got, truth, data_range=255, mask=inside),
            "max_err": float(np.abs(got - truth)[inside].max())}, note=f"{kind} {texels}^2, albedo pass"))
    got = renderer.albedo(cam, [Item(fidelity.gradient_quad())]).astype(np.float64)
    rows.append(make_row(SUITE, "gradient", {"what": "fidelity"}, none, metrics={
        "max_err": float(np.abs(got - fidelity.gradient_truth(uv))[inside].max())},
        note="vertex colours, albedo pass, 8-bit levels"))
    n = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    plane = fidelity.quad(0.8)
    plane.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], n))
    pcam = perspective(np.radians(40), (128, 128), look_at(3 * n + [0.2, 0.1, 0], [0, 0, 0]),
                       znear=0.5, zfar=10)
    p = renderer.passes(pcam, [Item(plane)], [])
    rows.append(make_row(SUITE, "normals_plane", {"what": "fidelity"}, none, metrics={
        "max_err_deg": float(_angle_deg(p.normal[p.alpha == 1], n).max())}))
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=0.5)
    scam = perspective(np.radians(35), (128, 128), look_at([0.5, -2.0, 1.2], [0, 0, 0]), znear=0.5, zfar=10)
    got = renderer.normals(scam, [Item(sphere)])
    o, d = scam.rays()
    tri = sphere.ray.intersects_first(o.reshape(-1, 3), d.reshape(-1, 3)).reshape(scam.shape)
    same = tri >= 0
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            same &= np.roll(tri, (dy, dx), (0, 1)) == tri
    rows.append(make_row(SUITE, "normals_sphere", {"what": "fidelity"}, none, metrics={
        "max_err_deg": float(_angle_deg(got[same], sphere.face_normals[tri[same]]).max())},
        note=f"{int(same.sum())} interior pixels"))
    return rows


def _pass_rows(renderer: Renderer, quick: bool) -> list[dict[str, Any]]:
    from ..scene import DirectionalLight, Item

    mesh = sample_mesh("cow", faces=6000)
    c = mesh.bounds.mean(0)
    p = mesh.vertices - c
    uv = np.column_stack([np.arctan2(p[:, 1], p[:, 0]) / (2 * np.pi) + 0.5,
                          (p[:, 2] - p[:, 2].min()) / np.ptp(p[:, 2])])
    tex, _ = _photo((512, 512))
    yy, xx = np.mgrid[:512, :512]
    alpha = np.where(((xx // 32 + yy // 32) % 4) == 0, 0, 255).astype(np.uint8)  # 1/4 cut out
    looks = {"color": Item(mesh, color=(0.7, 0.7, 0.7)), "own": Item(mesh)}
    vc = mesh.copy()
    vc.visual.vertex_colors = np.column_stack([np.rint(255 * uv[:, 0]), np.rint(255 * uv[:, 1]),
                                               np.full(len(uv), 128), np.full(len(uv), 255)]).astype(np.uint8)
    looks["vertex"] = Item(vc)
    for name, image, mode in (("texture", tex, None), ("cutout", np.dstack([tex, alpha]), "MASK")):
        m = mesh.copy()
        m.visual = trimesh.visual.TextureVisuals(uv=uv, material=trimesh.visual.material.PBRMaterial(
            baseColorTexture=image, alphaMode=mode))
        looks[name] = Item(m)
    cam = perspective(np.radians(40), (512, 512), look_at(c + [1.6, -1.2, 0.9], c), znear=0.1, zfar=10)
    lights = [DirectionalLight([-0.4, 0.6, -1.0])]
    rows = []
    for look, item in looks.items():
        items = [item]
        renderer.passes(cam, items, lights)  # upload once
        fns = {"depth_6k": lambda items=items: renderer.depth(cam, items),
               "lit_6k": lambda items=items: renderer.color_depth(cam, items, lights),
               "albedo_6k": lambda items=items: renderer.albedo(cam, items),
               "normal_6k": lambda items=items: renderer.normals(cam, items),
               "passes_6k": lambda items=items: renderer.passes(cam, items, lights)}
        for name, t in time_calls(fns, repeats=5 if quick else 11, warmup=1).items():
            rows.append(make_row(SUITE, name, {"what": "passes", "size": 512, "look": look}, t))
    return rows


#: The suite's sections in their order (``--sections``: depth, accuracy, fidelity, pass).
SECTIONS = (_depth_rows, _accuracy_rows, _fidelity_rows, _pass_rows)


def run(*, quick: bool = False, sections: str | None = None) -> list[dict[str, Any]]:
    """Run the suite (the rows are described in the module docstring).

    Parameters
    ----------
    quick : bool
        The reduced sweep (two mesh sizes).
    sections : str, optional
        Comma-separated names of the sections to run (``SECTIONS``); all when None.

    Returns
    -------
    list of dict
        One row per case, as :func:`morphkit.bench.harness.make_row` makes them.
    """
    from ..render import Renderer

    picked = {section_name(s) for s in pick_sections(sections, SECTIONS)}
    rows: list[dict[str, Any]] = []
    with Renderer() as renderer:
        for section in SECTIONS:
            if section_name(section) not in picked:
                continue
            rows += section(renderer, quick) if section in (_depth_rows, _pass_rows) else section(renderer)
    return rows
