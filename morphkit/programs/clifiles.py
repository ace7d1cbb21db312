"""The commands that write one file for other programs: ``morphkit export`` (a GLB).

:func:`add_file_commands` adds their parsers to the command line's (:mod:`morphkit.cli`); each
command's work is its program's (:mod:`.export`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_file_commands"]


def _cmd_export(args: argparse.Namespace) -> int:
    from .export import export_asset, export_line, export_scene

    if args.scene or Path(args.asset).suffix.lower() == ".json":
        got = export_scene(args.asset, args.out, sun_atlas_size=args.sun_atlas_size, overwrite=args.overwrite)
    else:
        got = export_asset(args.asset, args.out, size=args.size, sun_atlas_size=args.sun_atlas_size,
                           up=args.up_axis, overwrite=args.overwrite)
    print(export_line(got))
    return 0



def add_file_commands(sub: Any) -> None:
    """Add ``export`` to the command line's subparsers.

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
    ex.add_argument("--size", type=int, default=128,
                    help="the dome views' side when baking (default: %(default)s)")
    ex.add_argument("--sun-atlas-size", type=int, default=128, metavar="N",
                    help="the sun atlas's side when baking, texels; 0: none (default: %(default)s)")
    ex.add_argument("--up-axis", choices=("auto", "y", "z"), default="auto", help="a mesh file's up axis")
    ex.add_argument("--overwrite", action="store_true", help="replace an existing OUT")
    ex.set_defaults(func=_cmd_export)
