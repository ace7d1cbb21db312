"""The scenes shared by the demo, the benchmarks, the samples and the tests.

One place for each set-up, so that a figure in ``docs/RESULTS.md``, a demo
image and a test are about the same scene:

* the shadow scenes: a normalised sample mesh on a ground square, a
  directional light and a 3/4 view camera (:func:`demo_scene`); the point
  light and range of motion of the warped-shadow scenes (:data:`WARP_LIGHT`,
  :data:`WARP_RANGE`) and the area light of the soft-shadow scenes
  (:data:`SOFT_LIGHT`);
* the view-morphing scenes: cameras on a circle about the object
  (:func:`circle_camera`), the sample meshes with a 3-D colour checker
  (:func:`textured_items`, the look of :func:`morphkit.imaging.appearance.checker_items`)
  and their reference views (:func:`render_pair`);
* textured mesh files written on the fly, no downloads: a photo
  (:func:`photo_texture`, scikit-image's public-domain/CC0 photographs) on a
  UV-mapped OBJ + MTL box (:func:`write_photo_obj`), a PLY with vertex colours
  (:func:`write_color_ply`), a two-part glTF (:func:`write_two_part_gltf`: a
  photo-textured box and a vertex-coloured one, node transforms, embedded or
  external image) and a plant of alpha-masked leaf cards (:func:`write_leaf_plant`);
  in memory, one alpha-masked card (:func:`alpha_card`, e.g. of a
  :func:`checker_alpha` mask) for the cut-out shadow tests.
  All but the PLY are written ``+y`` up, as their formats' exporters do: standing
  along ``+y`` in the file, along ``+z`` after :func:`morphkit.meshes.load_mesh`.

The warped-shadow scenes' light and range are the shadow atlas defaults of
:mod:`morphkit.bake.kinds`, re-exported here. Nothing here imports
:mod:`morphkit.bench`; the benchmark imports from here. The library does not
import this module (``tests/test_structure.py`` checks it): only the
benchmarks, the demo, the CLI, the samples and the tests do.
"""

from __future__ import annotations

import base64
import json
from importlib import resources
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import trimesh
from PIL import Image
from skimage import data as skdata

from ..bake.kinds import WARP_LIGHT, WARP_RANGE
from ..billboard.domeasset import DomeAsset, bake_dome
from ..camera import CameraModel, look_at, perspective
from ..imaging.appearance import checker_items
from ..imaging.groundtruth import hard_visibility
from ..meshes import normalize, sample_mesh
from ..protocols import PassRenderer, SceneRenderer
from ..scene import AreaLight, DirectionalLight, Item, Receiver, Scene, SceneObject
from ..shadow.frame import SKY, render_frame

__all__ = ["DEMO_MESHES", "DEMO_LIGHT_DIRECTION", "demo_scene", "ground_truth_frame", "WARP_RANGE",
           "WARP_LIGHT", "WARP_POSITION", "SOFT_LIGHT", "VIEWMORPH_BASELINE_DEG", "CENTRE_AZIMUTH",
           "circle_camera", "textured_items", "render_pair", "TALL_BOX_EXTENTS", "photo_texture",
           "uv_box", "write_photo_obj", "write_photo_glb", "write_color_ply", "write_two_part_gltf",
           "leaf_texture", "write_leaf_plant", "textured_demo_asset", "checker_alpha", "alpha_card",
           "FIELD_MESHES", "field_domes"]


#: The sample meshes (:func:`morphkit.meshes.sample_mesh` names) every demo scene shows.
DEMO_MESHES = ("teapot", "chair", "cow")

#: The sample meshes of the billboard fields (the demo's shadowed field, the scene scripts).
FIELD_MESHES = ("tree", "cow")


def field_domes(renderer: PassRenderer, size: int, names: tuple[str, ...] = FIELD_MESHES
                ) -> tuple[dict[str, trimesh.Trimesh], dict[str, DomeAsset], dict[str, list[Item]]]:
    """The billboard fields' assets: each sample mesh normalised, its dome asset baked in the
    checker look (:func:`~morphkit.billboard.domeasset.bake_dome`), and its render items in that
    look (the real meshes' frames).

    Parameters
    ----------
    renderer : PassRenderer
        Bakes the domes (e.g. :class:`morphkit.render.Renderer`).
    size : int
        The domes' views' side, pixels.
    names : tuple of str
        Sample mesh names.

    Returns
    -------
    meshes : dict of str to trimesh.Trimesh
        Normalised meshes, by name.
    assets : dict of str to DomeAsset
        Their dome assets.
    items : dict of str to list of Item
        Their render items.
    """
    meshes = {nm: normalize(sample_mesh(nm)) for nm in names}
    assets = {nm: bake_dome(meshes[nm], renderer, name=nm, size=size, appearance="checker")
              for nm in names}
    return meshes, assets, {nm: assets[nm].items(meshes[nm]) for nm in names}


#: The demo light: from the upper right-front, casting shadows back-left.
DEMO_LIGHT_DIRECTION = (-0.55, 0.35, -1.0)


def demo_scene(mesh: trimesh.Trimesh, size: int = 512) -> Scene:
    """A normalised mesh at the origin on the ground, a directional light and a
    3/4 view camera (45 deg vertical field of view).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The object's mesh (normalised by this function).
    size : int, optional
        Side of the square image, pixels.

    Returns
    -------
    Scene
        The demo scene.
    """
    cam = perspective(np.deg2rad(40), (size, size), look_at([1.45, -1.35, 1.05], [-0.2, 0.2, 0.2]),
                      znear=0.1, zfar=20.0)
    return Scene(SceneObject(mesh), DirectionalLight(DEMO_LIGHT_DIRECTION, intensity=2.2), cam,
                 Receiver(half_size=2.0), ambient=0.3)


def ground_truth_frame(renderer: SceneRenderer, scene: Scene) -> dict[str, np.ndarray]:
    """Render ``scene`` and shadow it exactly by ray casting every visible pixel.

    Returns the images ``lit``, ``unlit``, ``depth``, ``visibility`` and ``shaded``.

    Parameters
    ----------
    renderer : SceneRenderer
        Renderer for the colour and depth images.
    scene : Scene
        Scene to render.

    Returns
    -------
    dict of str to numpy.ndarray
        Images keyed ``lit``, ``unlit``, ``depth``, ``visibility``, ``shaded``,
        each of ``scene.camera.shape`` (``depth`` float32 linear, ``+inf`` background).
    """
    return render_frame(renderer, scene, lambda pts, _n: hard_visibility(pts, scene.light, scene.obj),
                        background=SKY)


#: The object position ``(x, y)`` the warped-shadow demo shows.
WARP_POSITION = (0.23, -0.31)  # between the 3 x 3 samples


#: Soft-shadow demo: the warped-shadow light grown into a 0.6 x 0.6 area light.
SOFT_LIGHT = AreaLight(WARP_LIGHT, [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])


#: View-morphing demo: references on a circle around the object, 20 deg apart.
VIEWMORPH_BASELINE_DEG = 20.0


#: Azimuth (degrees) of the view-morphing scenes' middle view.
CENTRE_AZIMUTH = 60.0
RADIUS, HEIGHT = 2.2, 1.0
LOOK_AT = np.array([0.0, 0.0, 0.25])
def circle_camera(azimuth_deg: float, size: int) -> CameraModel:
    """The bench camera at ``azimuth_deg`` on the circle (square image of side ``size``).

    Parameters
    ----------
    azimuth_deg : float
        Azimuth about world ``+z``, degrees, ``0`` on ``+x``.
    size : int
        Image side in pixels.

    Returns
    -------
    CameraModel
        A perspective camera looking at the circle's centre.
    """
    a = np.radians(azimuth_deg)
    eye = np.array([RADIUS * np.cos(a), RADIUS * np.sin(a), HEIGHT])
    return perspective(np.radians(30.0), (size, size), look_at(eye, LOOK_AT))


def textured_items(name: str) -> tuple[Any, list[Any]]:
    """The sample mesh and its colour groups (:func:`checker_items`) as render items.

    Parameters
    ----------
    name : str
        Name of a sample mesh.

    Returns
    -------
    mesh : trimesh.Trimesh
        The sample mesh.
    items : list of Item
        Its colour groups, identity pose.
    """
    mesh = sample_mesh(name)
    return mesh, checker_items(mesh)


def render_pair(renderer: SceneRenderer, items: list[Any], cams: list[CameraModel]
                ) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(rgba, depth)`` for each camera.

    Parameters
    ----------
    renderer : SceneRenderer
        The renderer.
    items : list of Item
        Items to draw, world poses.
    cams : list of CameraModel
        One camera per view.

    Returns
    -------
    list of (rgba, depth)
        Per camera: ``(H, W, 4)`` uint8 straight-alpha RGBA and ``(H, W)``
        float32 linear depth, ``+inf`` background.
    """
    light = [DirectionalLight(np.array([-1.0, -0.5, -1.0]))]
    return [(renderer.source_view(c, items, light), renderer.depth(c, items)) for c in cams]


# --------------------------------------------------------------------------
# Textured mesh files, written on the fly from installed photographs
# --------------------------------------------------------------------------

#: Extents (x, up, depth) of the tall photo box: its up axis is the longest, so a
#: file loaded with the wrong up axis is seen at once.
TALL_BOX_EXTENTS = (0.4, 1.0, 0.25)


def photo_texture(size: int = 64, name: str = "astronaut") -> np.ndarray:
    """A real photograph shipped with scikit-image, resized to ``size x size`` (area average).

    ``astronaut`` (NASA, public domain) or ``coffee`` (Rachel Michetti, CC0), as the
    ``skimage.data`` docstrings state.

    Parameters
    ----------
    size : int, optional
        Side of the square result, texels.
    name : {"astronaut", "coffee"}, optional
        Which photograph.

    Returns
    -------
    (size, size, 3) uint8
        RGB, row 0 the photo's top.
    """
    img = {"astronaut": skdata.astronaut, "coffee": skdata.coffee}[name]()
    return cv2.resize(np.ascontiguousarray(img[..., :3]), (size, size), interpolation=cv2.INTER_AREA)


def uv_box(extents: Any = TALL_BOX_EXTENTS) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A box centred on the origin whose six faces each show a whole texture.

    Parameters
    ----------
    extents : sequence of 3 float, optional
        Size along x, y, z.

    Returns
    -------
    vertices : (24, 3) float64
        Four corners per face (faces do not share vertices: each has its UVs).
    faces : (12, 3) int64
        Two triangles per face, counter-clockwise seen from outside.
    uv : (24, 2) float64
        ``(0, 0), (1, 0), (1, 1), (0, 1)`` on each face (trimesh's UVs: ``v`` up).
    """
    h = np.asarray(extents, dtype=np.float64) / 2.0
    verts, faces, uvs = [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            a = np.zeros(3)
            a[(axis + 1) % 3] = 1.0
            b = np.cross(n, a)
            c = n * h
            corners = [c + (su * a + sv * b) * h for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            k = len(verts)
            verts += corners
            faces += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
            uvs += [[0, 0], [1, 0], [1, 1], [0, 1]]
    return np.array(verts), np.array(faces, dtype=np.int64), np.array(uvs, dtype=np.float64)


def write_photo_obj(folder: str | Path, image: np.ndarray | None = None, name: str = "photo_box") -> Path:
    """Write a UV-textured OBJ + MTL + PNG: the tall box (``+y`` up) with a photo on every face.

    Parameters
    ----------
    folder : str or pathlib.Path
        Existing folder to write into.
    image : (H, W, 3) uint8, optional
        The texture; :func:`photo_texture` by default.
    name : str, optional
        Stem of the three files.

    Returns
    -------
    pathlib.Path
        The ``.obj`` file (``name.mtl`` and ``name.png`` beside it, material ``photo``
        with ``Kd 0.8 0.8 0.8`` and ``map_Kd name.png``).
    """
    folder = Path(folder)
    image = photo_texture() if image is None else image
    Image.fromarray(image).save(folder / f"{name}.png")
    (folder / f"{name}.mtl").write_text(f"newmtl photo\nKd 0.8 0.8 0.8\nmap_Kd {name}.png\n")
    v, f, uv = uv_box()
    lines = [f"mtllib {name}.mtl"] + [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in v]
    lines += [f"vt {a:.6f} {b:.6f}" for a, b in uv] + ["usemtl photo"]
    lines += [f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in f]
    path = folder / f"{name}.obj"
    path.write_text("\n".join(lines) + "\n")
    return path


def write_photo_glb(folder: str | Path, image: np.ndarray | None = None, name: str = "photo_crate") -> Path:
    """Write a binary glTF of the tall photo box (``+y`` up, a ``PBRMaterial`` with the photo).

    ``morphkit/data/photo_crate.glb`` is this file for ``photo_texture(128)``.

    Parameters
    ----------
    folder : str or pathlib.Path
        Existing folder to write into.
    image : (H, W, 3) uint8, optional
        The texture; :func:`photo_texture` by default.
    name : str, optional
        File stem.

    Returns
    -------
    pathlib.Path
        The ``.glb`` file.
    """
    image = photo_texture() if image is None else image
    v, f, uv = uv_box()
    mat = trimesh.visual.material.PBRMaterial(name="photo", baseColorTexture=Image.fromarray(image),
                                              metallicFactor=0.0, roughnessFactor=0.9)
    mesh = trimesh.Trimesh(v, f, process=False, visual=trimesh.visual.TextureVisuals(uv=uv, material=mat))
    path = Path(folder) / f"{name}.glb"
    mesh.export(path)
    return path


def textured_demo_asset() -> Path:
    """The packaged textured demo mesh, ``morphkit/data/photo_crate.glb``.

    :func:`write_photo_glb` with ``photo_texture(128)`` (NASA's astronaut photo, public
    domain; ``morphkit/data/LICENSES.md``), ``+y`` up as glTF is: load it with
    :func:`morphkit.meshes.load_mesh` (``up="auto"``) to have it stand along ``+z``.

    Returns
    -------
    pathlib.Path
        Its path.
    """
    return Path(str(resources.files("morphkit") / "data" / "photo_crate.glb"))


def write_color_ply(folder: str | Path, name: str = "colored") -> Path:
    """Write a PLY icosphere (``+z`` up) with vertex colours: red at the bottom to blue at the top.

    Parameters
    ----------
    folder : str or pathlib.Path
        Existing folder to write into.
    name : str, optional
        File stem.

    Returns
    -------
    pathlib.Path
        The ``.ply`` file; vertex colour ``(255 (1 - t), 64, 255 t, 255)``, ``t`` the
        height from 0 (lowest) to 1, rounded.
    """
    m = trimesh.creation.icosphere(subdivisions=2)
    z = m.vertices[:, 2]
    t = (z - z.min()) / (z.max() - z.min())
    m.visual.vertex_colors = np.c_[np.rint(255 * (1 - t)), np.full_like(t, 64), np.rint(255 * t),
                                   np.full_like(t, 255)].astype(np.uint8)
    path = Path(folder) / f"{name}.ply"
    m.export(path)
    return path


def _export_gltf(scene: trimesh.Scene, path: Path, images: str) -> Path:
    """Export ``scene`` as ``.glb`` (``images="glb"``) or ``.gltf`` with its images as data
    URIs (``"embedded"``) or as PNG files beside it (``"external"``)."""
    if images == "glb":
        path = path.with_suffix(".glb")
        scene.export(path)
        return path
    if images not in ("embedded", "external"):
        raise ValueError(f"images: expected 'glb', 'embedded' or 'external', got {images!r}")
    path = path.with_suffix(".gltf")
    files = scene.export(file_type="gltf")
    gltf = json.loads(files.pop("model.gltf"))
    for b in gltf["buffers"]:  # every buffer as a data URI: the .gltf is then one file
        b["uri"] = "data:application/octet-stream;base64," + base64.b64encode(files[b["uri"]]).decode()
    for i, im in enumerate(gltf.get("images", [])):
        view = gltf["bufferViews"][im.pop("bufferView")]
        raw = base64.b64decode(gltf["buffers"][view["buffer"]]["uri"].split(",", 1)[1])
        png = raw[view.get("byteOffset", 0): view.get("byteOffset", 0) + view["byteLength"]]
        if images == "embedded":
            im["uri"] = "data:image/png;base64," + base64.b64encode(png).decode()
        else:
            im["uri"] = f"{path.stem}_image{i}.png"
            (path.parent / im["uri"]).write_bytes(png)
    path.write_text(json.dumps(gltf))
    return path


def write_two_part_gltf(folder: str | Path, images: str = "glb", image: np.ndarray | None = None,
                        name: str = "two_part") -> Path:
    """Write a glTF of two parts, ``+y`` up: the photo box and a vertex-coloured box beside it.

    Part ``photo``: the tall box of :func:`write_photo_obj` with a ``PBRMaterial``
    (the photo as ``baseColorTexture``, factor 1), at the origin. Part ``painted``: a
    0.3 box with vertex colours (``(40 + 200 i / 7, 200, 90, 255)`` for vertex ``i``),
    moved by its node's transform to ``(0.6, 0.15, 0)`` and turned 30 degrees about
    ``+y``.

    Parameters
    ----------
    folder : str or pathlib.Path
        Existing folder to write into.
    images : {"glb", "embedded", "external"}, optional
        A binary ``.glb``, or a ``.gltf`` with the image as a data URI or as a PNG file.
    image : (H, W, 3) uint8, optional
        The photo; :func:`photo_texture` by default.
    name : str, optional
        File stem.

    Returns
    -------
    pathlib.Path
        The ``.glb`` or ``.gltf`` file.
    """
    image = photo_texture() if image is None else image
    v, f, uv = uv_box()
    mat = trimesh.visual.material.PBRMaterial(name="photo", baseColorTexture=Image.fromarray(image))
    photo = trimesh.Trimesh(v, f, process=False, visual=trimesh.visual.TextureVisuals(uv=uv, material=mat))
    painted = trimesh.creation.box(extents=(0.3, 0.3, 0.3))
    i = np.arange(len(painted.vertices))
    painted.visual.vertex_colors = np.c_[np.rint(40 + 200 * i / 7), np.full((len(i), 3), [200, 90, 255])
                                         ].astype(np.uint8)
    pose = trimesh.transformations.rotation_matrix(np.radians(30.0), [0, 1, 0])
    pose[:3, 3] = [0.6, 0.15, 0.0]
    scene = trimesh.Scene()
    scene.add_geometry(photo, geom_name="photo", node_name="photo")
    scene.add_geometry(painted, geom_name="painted", node_name="painted", transform=pose)
    return _export_gltf(scene, Path(folder) / name, images)


def leaf_texture(size: int = 64) -> np.ndarray:
    """A leaf: green with a lighter midrib, alpha 255 inside a pointed leaf outline and 0 outside.

    Parameters
    ----------
    size : int, optional
        Side of the square texture.

    Returns
    -------
    (size, size, 4) uint8
        RGBA; the leaf's stalk at the bottom row's centre, its tip at the top.
    """
    y, x = np.mgrid[0:size, 0:size] + 0.5
    s = 1.0 - y / size                      # 0 at the bottom, 1 at the top
    half = 0.42 * np.sin(np.pi * np.clip(s, 0, 1)) ** 0.8  # half-width of the blade
    inside = np.abs(x / size - 0.5) < half
    rgba = np.zeros((size, size, 4), np.uint8)
    rgba[..., 0] = np.rint(40 + 50 * s).astype(np.uint8)
    rgba[..., 1] = np.rint(150 + 60 * s).astype(np.uint8)
    rgba[..., 2] = 40
    rib = np.abs(x / size - 0.5) < 0.02
    rgba[rib, 0], rgba[rib, 1] = 170, 230
    rgba[..., 3] = np.where(inside, 255, 0)
    return rgba


def write_leaf_plant(folder: str | Path, name: str = "leaf_plant", cutoff: float = 0.5,
                     images: str = "glb") -> Path:
    """Write a glTF plant, ``+y`` up: a brown stem (base colour factor) and three leaf cards
    (:func:`leaf_texture`, ``alphaMode MASK`` at ``cutoff``), each card its own node.

    Parameters
    ----------
    folder : str or pathlib.Path
        Existing folder to write into.
    name : str, optional
        File stem.
    cutoff : float, optional
        The leaves' ``alphaCutoff``.
    images : {"glb", "embedded", "external"}, optional
        As :func:`write_two_part_gltf`.

    Returns
    -------
    pathlib.Path
        The file. Stem: a 0.05 x 0.6 x 0.05 box from ``y = 0`` to ``0.6``, factor
        ``(0.35, 0.2, 0.08, 1)`` (linear). Cards: 0.4 x 0.4 quads at heights 0.25, 0.4
        and 0.55, turned 0, 120 and 240 degrees about ``+y``.
    """
    stem = trimesh.creation.box(extents=(0.05, 0.6, 0.05))
    stem.apply_translation([0, 0.3, 0])
    stem.visual = trimesh.visual.TextureVisuals(material=trimesh.visual.material.PBRMaterial(
        name="stem", baseColorFactor=[0.35, 0.2, 0.08, 1.0], metallicFactor=0.0, roughnessFactor=0.9))
    leaf = trimesh.visual.material.PBRMaterial(
        name="leaf", baseColorTexture=Image.fromarray(leaf_texture(), "RGBA"), alphaMode="MASK",
        alphaCutoff=cutoff, metallicFactor=0.0, roughnessFactor=0.9, doubleSided=True)
    quad_v = np.array([[0.0, 0.0, 0.0], [0.4, 0.0, 0.0], [0.4, 0.4, 0.0], [0.0, 0.4, 0.0]]) - [0.0, 0.2, 0.0]
    quad_uv = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]])  # stalk at the stem, tip outwards
    scene = trimesh.Scene()
    scene.add_geometry(stem, geom_name="stem", node_name="stem")
    for k, (height, turn) in enumerate(((0.25, 0.0), (0.4, 120.0), (0.55, 240.0))):
        card = trimesh.Trimesh(quad_v, [[0, 1, 2], [0, 2, 3]], process=False,
                               visual=trimesh.visual.TextureVisuals(uv=quad_uv, material=leaf))
        pose = trimesh.transformations.rotation_matrix(np.radians(turn), [0, 1, 0])
        pose[:3, 3] = [0.0, height, 0.0]
        scene.add_geometry(card, geom_name=f"leaf{k}", node_name=f"leaf{k}", transform=pose)
    return _export_gltf(scene, Path(folder) / name, images)


def checker_alpha(cells: int, texels: int) -> np.ndarray:
    """A checkerboard alpha mask: ``cells x cells`` squares of ``texels x texels`` texels,
    the top-left square opaque.

    Parameters
    ----------
    cells : int
        Squares per side.
    texels : int
        Texels per square side.

    Returns
    -------
    (cells * texels, cells * texels) uint8
        255 on opaque squares, 0 on holes.
    """
    r, c = np.indices((cells, cells))
    return np.kron(((r + c) % 2 == 0).astype(np.uint8) * 255, np.ones((texels, texels), np.uint8))


def alpha_card(alpha: np.ndarray, side: float = 1.0, cutoff: float = 0.5) -> trimesh.Trimesh:
    """A square card in the ``z = 0`` plane, centred on the origin, textured green with
    ``alpha`` as a glTF ``MASK`` material (the look of a leaf card, :mod:`morphkit.meshes.look`).

    Parameters
    ----------
    alpha : (H, W) uint8
        Texture alpha; row 0 lies along ``y = +side / 2``, column 0 along ``x = -side / 2``.
    side : float, optional
        Side of the card, scene units.
    cutoff : float, optional
        The material's ``alphaCutoff``.

    Returns
    -------
    trimesh.Trimesh
        Two triangles with ``TextureVisuals`` (UV ``(0, 0)`` at the ``(-x, -y)`` corner).
    """
    a = np.asarray(alpha, dtype=np.uint8)
    rgba = np.zeros((*a.shape, 4), np.uint8)
    rgba[..., 1], rgba[..., 3] = 160, a
    h = side / 2.0
    verts = np.array([[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]])
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    mat = trimesh.visual.material.PBRMaterial(
        name="card", baseColorTexture=Image.fromarray(rgba, "RGBA"), alphaMode="MASK", alphaCutoff=cutoff,
        metallicFactor=0.0, roughnessFactor=0.9, doubleSided=True)
    return trimesh.Trimesh(verts, [[0, 1, 2], [0, 2, 3]], process=False,
                           visual=trimesh.visual.TextureVisuals(uv=uv, material=mat))
