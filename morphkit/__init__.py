"""morphkit: shadows and view-dependent billboards by warping images.

The names a user needs are importable from here (``README.md``, "Quick start"), for three jobs:

* a mesh's warped shadow at a position, against the truth (paper 1): :func:`bake_atlas` over a
  :class:`MotionRange`, :meth:`ShadowAtlas.shadow_map` at the position,
  :func:`shadow_visibility` of the ground, against the ray cast :func:`hard_visibility`;
* two photos, and the view between them (paper 2): :class:`ViewMorpher`
  (:meth:`ViewMorpher.from_estimate`, points matched by :func:`from_images`);
* a field of billboards with shadows under a sun: :class:`SunlitField`
  (:meth:`SunlitField.from_meshes`, a sun from :func:`sun`), against the real meshes; a whole
  scene from a file (a JSON scene file or a glTF scene): :func:`load_scene`, drawn by
  :func:`render_scene` into a folder, planned to an error :class:`Budget` by :func:`plan_scene`.

The scene, cameras, meshes, renderer, images and error measures they take are here too
(:class:`Renderer`, :func:`load_mesh`, :func:`perspective`, :func:`shadow_iou`, ...), and the
exceptions of :mod:`morphkit.errors`. Each name stays defined in its module (e.g.
:mod:`morphkit.shadow`); this package imports it on first use, so ``import morphkit`` loads
neither trimesh, OpenCV nor GL.

Conventions (pixels, frames, depth) are stated once in :mod:`morphkit.conventions`.
The pyrender/OpenGL boundary is :mod:`morphkit.render`; nothing else imports pyrender,
so the numpy/OpenCV core works without a GL context.
"""

from __future__ import annotations

import importlib
from typing import Any

from .errors import (
    BudgetError,
    ClusterError,
    DegenerateViewError,
    FileFormatError,
    FoldOverError,
    GeometryError,
    MeshError,
    MorphkitError,
    OutOfRangeError,
    OutputBusyError,
    OutputExistsError,
    OutputWriteError,
    RenderError,
    UsageError,
    ValidationError,
)

#: The package version (as in ``pyproject.toml``).
__version__ = "0.1.0"

#: The names imported on first use (PEP 562), by the module that defines or exports them.
_LAZY: dict[str, tuple[str, ...]] = {
    # the core: scenes, cameras, meshes, rendering, images, truths and error measures
    "morphkit.scene": ("DirectionalLight", "PointLight", "AreaLight", "SceneObject", "Item", "Scene",
                       "Receiver", "translation"),
    "morphkit.camera": ("CameraModel", "look_at", "perspective", "orthographic"),
    "morphkit.meshes": ("load_mesh", "sample_mesh", "sample_file", "normalize"),
    "morphkit.render": ("Renderer",),
    "morphkit.views": ("DomeCameras", "ViewDome"),
    "morphkit.files.fileio": ("read_image", "write_image"),
    "morphkit.imaging.groundtruth": ("hard_visibility", "area_visibility", "receiver_grid"),
    "morphkit.imaging.metrics": ("shadow_iou", "psnr", "ssim", "mean_abs_error"),
    # paper 1: warped shadow maps
    "morphkit.shadow": ("MotionRange", "bake_atlas", "ShadowAtlas", "shadow_visibility", "DirectShadow",
                        "SoftShadow", "bake_soft_atlas"),
    "morphkit.shadow.frame": ("render_frame", "compare_frames"),
    # paper 2: view morphing, view-morphing billboards
    "morphkit.viewmorph": ("ViewMorpher", "from_images", "from_geometry", "plan_view_morph"),
    "morphkit.billboard": ("bake_asset", "bake_dome", "BillboardScene", "place_random", "MorphMode",
                           "ClassicMode", "MeshMode", "PanPath", "OrbitPath"),
    # the two together: billboards under the sun with their shadows
    "morphkit.sunpath": ("sun", "SunPath"),
    "morphkit.sunlit.sunlitfield": ("SunlitField", "FieldComparison"),
    # a user's scene: scene files and glTF scenes, drawn into a folder
    "morphkit.scenes": ("load_scene", "SceneDescription", "write_scene_file"),
    "morphkit.programs.scenerender": ("render_scene",),
    "morphkit.plan": ("Budget",),
    "morphkit.programs.planning.planrun": ("plan_scene",),
}
_EXPORTS: dict[str, str] = {name: module for module, names in _LAZY.items() for name in names}

__all__ = [
    "__version__",
    "MorphkitError",
    "ValidationError",
    "MeshError",
    "OutOfRangeError",
    "GeometryError",
    "FoldOverError",
    "DegenerateViewError",
    "RenderError",
    "FileFormatError",
    "BudgetError",
    "ClusterError",
    "OutputExistsError",
    "OutputBusyError",
    "OutputWriteError",
    "UsageError",
    *_EXPORTS,
]


def __getattr__(name: str) -> Any:
    """A lazily exported name, imported from its module on first use (PEP 562).

    Parameters
    ----------
    name : str
        The attribute asked for.

    Returns
    -------
    object
        The name's object (kept in the package's namespace: later uses cost nothing).

    Raises
    ------
    AttributeError
        ``name`` is not one of morphkit's names.
    """
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'morphkit' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The package's names: its own and the lazily exported ones.

    Returns
    -------
    list of str
        Sorted.
    """
    return sorted(set(globals()) | set(_EXPORTS))
