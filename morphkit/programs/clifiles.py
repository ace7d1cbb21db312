"""The commands that write one file for other programs: ``morphkit export`` (a GLB) and ``morphkit preview``
(a page).

:func:`add_file_commands` adds their parsers to the command line's (:mod:`morphkit.cli`); each
command's work is its program's (:mod:`morphkit.programs.export`, :mod:`morphkit.programs.preview`).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

__all__ = ["add_file_commands"]


def _cmd_export(args: argparse.Namespace) -> int:
    from .export import export_asset, export_line, export_scene

    if args.scene or Path(args.asset).suffix.lower() == ".json":
        if args.plan_asset is not None:
            from ..errors import UsageError, expected_got

            raise UsageError(expected_got("--plan-asset", "an asset to export (a scene's assets are named by "
                                          "the scene)", f"the scene {args.asset!r}"))
        got = export_scene(args.asset, args.out, sun_atlas_size=args.sun_atlas_size, plan=args.plan,
                           overwrite=args.overwrite)
    else:
        got = export_asset(args.asset, args.out, size=args.size, sun_atlas_size=args.sun_atlas_size,
                           up=args.up_axis, impostor=not args.no_impostor, plan=args.plan,
                           plan_asset=args.plan_asset, overwrite=args.overwrite)
    print(export_line(got))
    return 0



def _numbers(text: str | None, n: int, option: str) -> tuple[float, ...] | None:
    from ..errors import UsageError, expected_got

    if text is None:
        return None
    try:
        got = tuple(float(v) for v in text.split(","))
    except ValueError:
        got = ()
    if len(got) != n or not all(math.isfinite(v) for v in got):
        raise UsageError(expected_got(option, f"{n} finite numbers separated by commas", repr(text)))
    return got


def _cmd_preview(args: argparse.Namespace) -> int:
    from .cliargs import parse_size
    from .preview import preview_line, preview_page

    h, w = parse_size(args.size_px)
    got = preview_page(args.asset, args.out, camera=_numbers(args.camera, 3, "--camera"),
                       sun=_numbers(args.sun, 2, "--sun"), image=(w, h), size=args.size,
                       sun_atlas_size=args.sun_atlas_size, up=args.up_axis, scene=args.scene,
                       impostor=not args.no_impostor, overwrite=args.overwrite)
    print(preview_line(got))
    return 0


def _bake_options(p: argparse.ArgumentParser, impostor_help: str) -> None:
    """The options both commands take of what they bake, and ``--overwrite``."""
    p.add_argument("--size", type=int, default=128,
                   help="the dome views' side when baking (default: %(default)s)")
    p.add_argument("--sun-atlas-size", type=int, default=128, metavar="N",
                   help="the sun atlas's side when baking, texels; 0: none (default: %(default)s)")
    p.add_argument("--up-axis", choices=("auto", "y", "z"), default="auto", help="a mesh file's up axis")
    p.add_argument("--no-impostor", action="store_true", help=impostor_help)
    p.add_argument("--overwrite", action="store_true", help="replace an existing OUT")


def add_file_commands(sub: Any) -> None:
    """Add ``export`` and ``preview`` to the command line's subparsers.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        :func:`morphkit.cli.build_parser`'s.
    """
    ex = sub.add_parser(
        "export",
        help="write an asset or a scene as a GLB for engines: meshes, relightable views, sun atlases",
        description="Bake (or read) one asset and write it as a binary glTF: the mesh, the dome's views "
        "tiled into albedo (sRGB), normal and depth (float16 bits) atlases, the sun atlas, and a "
        "sidecar in extras.morphkit (layout, view directions, bounds, pivot, depth range, colour "
        "spaces, normal convention). A scene's assets are each written once, drawn at their instances by "
        "EXT_mesh_gpu_instancing. `morphkit.export.read_dome_glb` reads an asset back bit for bit.",
    )
    ex.add_argument("asset", metavar="ASSET_OR_SCENE",
                    help="a sample mesh name, a mesh file or a dome asset file (.npz); or a scene file "
                    "(.json), or with --scene a glTF scene: its assets and their instances in one GLB")
    ex.add_argument("--scene", action="store_true",
                    help="read a .glb/.gltf as a scene (its meshes, nodes, light), not as one mesh")
    ex.add_argument("-o", "--out", required=True, help="the .glb file")
    ex.add_argument("--plan", metavar="PLAN", default=None,
                    help="`morphkit plan`'s plan.json (or its folder) of a scene holding the asset, or of "
                    "the scene exported: levels of detail as MSFT_lod (the mesh, a crossed card, nothing), "
                    "switched at the screen coverages of the plan's bands")
    ex.add_argument("--plan-asset", metavar="NAME", default=None,
                    help="the plan's name for the asset (default: the asset's own, e.g. the file's stem)")
    _bake_options(ex, "without the octahedral impostor (by default one whose frames take as many bytes as "
                  "the dome's views, baked from the mesh)")
    ex.set_defaults(func=_cmd_export)

    pv = sub.add_parser(
        "preview",
        help="write one self-contained HTML page that morphs the billboards in the browser (WebGL 2)",
        description="Bake (or read) an asset or a scene and write one HTML file, three.js inlined and "
        "nothing loaded from the network: an orbit camera (drag, wheel), each billboard drawn by a "
        "GLSL shader doing morphkit's per-pixel depth morph of its three nearest views, a sun "
        "slider moving the sun and the instances' shadows from their sun atlases, and on-screen "
        "figures; beside a baked asset, its octahedral impostor at equal bytes. The URL fragment sets "
        "the view: #camera=AZ,EL,DIST&fov=DEG&sun=AZ,EL&size=WxH. "
        "A GLB from another tool is drawn as meshes.",
    )
    pv.add_argument("asset", metavar="ASSET_OR_SCENE",
                    help="a sample mesh name, a mesh file, a dome asset file (.npz), a GLB morphkit "
                    "exported or any other GLB (drawn as meshes); or a scene file (.json), or with --scene "
                    "a glTF scene")
    pv.add_argument("--scene", action="store_true",
                    help="read a .glb/.gltf as a scene (its meshes, nodes, light), not as one asset")
    pv.add_argument("-o", "--out", required=True, help="the .html file")
    pv.add_argument("--camera", metavar="AZ,EL,DIST", default=None,
                    help="the first camera: azimuth and elevation (degrees) and distance from the target "
                    "(default: fitted to the scene)")
    pv.add_argument("--sun", metavar="AZ,EL", default=None,
                    help="the first sun: azimuth and elevation, degrees (default: 135,45)")
    pv.add_argument("--size-px", default="640x480", metavar="WxH",
                    help="the canvas when the URL does not set it (default: the window)")
    _bake_options(pv, "no octahedral impostor beside a baked asset (by default one whose frames take as "
                  "many bytes as the dome's views, to compare)")
    pv.set_defaults(func=_cmd_preview)
