"""The ``morphkit`` command line: ``demo``, ``bench``, ``viewmorph``, ``billboards``, ``bake``, ``shadows``.

Heavy modules are imported inside each subcommand so ``morphkit --help`` is fast
and needs no GL context.

Errors: every command's morphkit errors, OS errors and memory errors are caught in
:func:`main` and printed as one line ``morphkit: error: ...`` on stderr; Ctrl-C prints
``morphkit: interrupted``, SIGTERM ``morphkit: terminated`` (the run unwinds as after Ctrl-C:
temporary files removed). No traceback. Exit codes, decided in one place (``_exit_code``):

* 2, the command line was used wrongly: argparse's usage errors, a bad option value or
  combination (:mod:`morphkit.programs.cliargs`, or a :class:`~morphkit.errors.UsageError` of a
  command's own checks, ``_option_values``), a value naming nothing there is (an unknown
  sample, suite, section or path name, a malformed scheduler address), an ``-o`` that cannot
  be the command's folder (a file, a path under a file) or refused by the overwrite rule
  (:class:`~morphkit.errors.OutputExistsError`), a morphkit environment variable with a value
  it does not take;
* 1, the run failed on its inputs or the machine: a missing, unreadable or unsuitable input
  file, a geometry that cannot be morphed, a scheduler that does not answer, a GL, file
  system or memory failure;
* 130, interrupted (Ctrl-C, SIGINT); 143, terminated (SIGTERM): 128 and the signal's number, as a
  shell reports a process the signal ended.

Warnings print as one line each, ``morphkit: warning: ...`` (``_one_line_warnings``).
"""

from __future__ import annotations

import argparse
import signal
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .conventions import SUN_DISC_RADIUS_DEG
from .errors import MorphkitError, OutputExistsError, Terminated, UsageError, ValidationError, expected_got
from .programs.cliargs import (
    SOFT_FILTER,
    check_args,
    check_output_file,
    same_file,
)
from .programs.clifiles import add_file_commands
from .programs.clistop import Stop, report_stop, stop_signals

if TYPE_CHECKING:
    from .files.outfolder import OutputClaim, OutputRule

#: The bench suites that take ``--sections``.
SECTIONED_SUITES = ("billboards", "scene", "shadows", "render")

@contextmanager
def _option_values() -> Iterator[None]:
    """A :class:`~morphkit.errors.ValidationError` raised in the block is about an option's value:
    re-raised as a :class:`~morphkit.errors.UsageError` (exit code 2, ``_exit_code``)."""
    try:
        yield
    except (UsageError, OutputExistsError):
        raise
    except ValidationError as exc:
        raise UsageError(str(exc)) from exc


def _output_folder(out: str, rule: OutputRule, overwrite: bool = False) -> OutputClaim:
    """``-o``'s folder checked for the command before any work (:func:`morphkit.files.outfolder.claim_output`,
    no side effect): a file, a path under a file, another command's output or a previous run
    without ``--overwrite`` are usage errors (exit 2)."""
    from .files.outfolder import claim_output

    with _option_values():
        return claim_output(out, rule, overwrite=overwrite)


def _cmd_demo(args: argparse.Namespace) -> int:
    from .files.outfolder import DEMO_OUTPUT
    from .programs.demo import previous_demo, run_demo

    old = previous_demo(args.out)
    if old is not None and not args.overwrite:
        print(f"morphkit: error: {args.out} already holds a demo ({old.name}); pass --overwrite to "
              "replace it", file=sys.stderr)
        return 2
    _output_folder(args.out, DEMO_OUTPUT, args.overwrite)  # run_demo claims it again, when it starts
    index = run_demo(Path(args.out), size=args.size, quick=args.quick, overwrite=args.overwrite)
    print(f"morphkit demo: wrote {len(index['files'])} files to {Path(args.out).resolve()}")
    print(f"index: {Path(args.out).resolve() / 'index.json'}")
    return 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench import SUITES, run_suite

    check_output_file(args.json, "--json")
    check_output_file(args.plot, "--plot")
    if args.suite not in SUITES:
        print(f"morphkit: error: unknown suite {args.suite!r}; available: {', '.join(sorted(SUITES))}",
              file=sys.stderr)
        return 2
    options = {}
    if args.workers is not None:
        if args.suite != "bake":
            print("morphkit: error: --workers is an option of `bench bake` only", file=sys.stderr)
            return 2
        options["workers"] = args.workers
    if args.assets is not None:
        if args.suite != "bake":
            print("morphkit: error: --assets is an option of `bench bake` only", file=sys.stderr)
            return 2
        options["assets"] = args.assets
    if args.sections is not None:
        if args.suite not in SECTIONED_SUITES:
            print(f"morphkit: error: --sections is an option of `bench {'|'.join(SECTIONED_SUITES)}` only",
                  file=sys.stderr)
            return 2
        import importlib

        from .bench.harness import pick_sections

        with _option_values():  # an unknown section's name, before any work
            pick_sections(args.sections, importlib.import_module(SUITES[args.suite].__module__).SECTIONS)
        options["sections"] = args.sections
    if args.instances is not None:
        if args.suite != "scene":
            print("morphkit: error: --instances is an option of `bench scene` only", file=sys.stderr)
            return 2
        options["instances"] = args.instances
    run_suite(args.suite, quick=args.quick, json_path=args.json, plot_path=args.plot, options=options)
    return 0


def _cmd_viewmorph(args: argparse.Namespace) -> int:
    import numpy as np

    from .errors import FileFormatError, ValidationError
    from .files.fileio import encode_image, read_image, write_bytes
    from .files.outfolder import VIEWMORPH_OUTPUT, frame_name
    from .viewmorph import ViewMorpher, from_images, load_points

    def encode(path: Path, img: np.ndarray) -> bytes:
        if img.dtype.kind == "f":
            img = np.clip(np.rint(img * 255), 0, 255).astype(np.uint8)
        return encode_image(path, img)  # ValidationError for an unknown extension, before any write

    def write(path: Path, data: bytes) -> None:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            write_bytes(path, data)  # atomic; ValidationError when path is a folder
        except OSError as exc:
            raise ValidationError(expected_got("output", "a writable image path",
                                               f"{str(path)!r}: {exc.strerror or exc}")) from exc

    # the output is checked before the work: an input, a folder, a file in the way, an unknown
    # extension, a file that exists (replaced only with --overwrite): usage errors (exit 2)
    out = Path(args.out)
    with _option_values():
        for option, given in (("LEFT", args.left), ("RIGHT", args.right), ("--points", args.points)):
            if given is not None and same_file(out, Path(given)):
                raise UsageError(expected_got("-o", "a path other than the inputs' (never replaced)",
                                              f"{str(out)!r}, which is {option}"))
        folder = out if args.frames else out.parent
        in_the_way = next((a for a in (folder, *folder.parents) if a.exists() and not a.is_dir()), None)
        if in_the_way is not None:
            expected = "a folder path" if args.frames else "a path whose parents are folders"
            raise ValidationError(expected_got("output" + (" with --frames" if args.frames else ""), expected,
                                               f"{str(out)!r}, where {str(in_the_way)!r} is a file"))
        if not args.frames:
            if out.is_dir():
                raise ValidationError(expected_got("output", "an image file path (or --frames N for a "
                                                   "folder)", f"the folder {str(out)!r}"))
            if out.exists() and not args.overwrite:
                raise OutputExistsError(expected_got("output", "a new file, or --overwrite to replace it",
                                                     f"the existing file {str(out)!r}"))
            encode(out, np.zeros((1, 1, 3), np.uint8))  # an unknown extension is refused here
    claim = _output_folder(args.out, VIEWMORPH_OUTPUT, args.overwrite) if args.frames else None
    left, right = read_image(args.left), read_image(args.right)
    if args.points:
        try:
            corr = load_points(args.points)
        except (MorphkitError, OSError):
            raise
        except (ValueError, TypeError, KeyError, IndexError) as exc:  # a layout load_points did not foresee
            raise FileFormatError(f"points file {args.points!r}: expected x0, y0, x1, y1 rows or "
                                  f'{{"pts0": [[x, y], ...], "pts1": [[x, y], ...]}}, got '
                                  f"{type(exc).__name__}: {exc}") from exc
    else:
        corr = from_images(left, right)  # refuses images that do not seem to show one scene
    vm = ViewMorpher.from_estimate(left, right, corr, prewarp=args.prewarp, fallback=args.fallback)
    rep, fit = vm.report, vm.fit
    print(f"morphkit viewmorph: mode {vm.mode}, pre-warp {vm.rectification.method}, "
          f"{rep.n_used}/{rep.n_input} pairs used ({rep.n_duplicates} duplicates, "
          f"{rep.n_outliers or 0} outliers, {rep.n_dropped_foldover} dropped for fold-overs)"
          + (f", F by {fit.method}: Sampson RMS {fit.sampson_rms:.3f} px" if fit is not None else "")
          + (f"; fallback: {rep.fallback}" if rep.fallback is not None else ""))
    kw = {"post": args.post, "frame": args.frame}
    if claim is not None:
        with claim.writing():
            for i, img in enumerate(vm.frames(args.frames, **kw)):
                name = out / frame_name(i)
                write(name, encode(name, img))
        print(f"wrote {args.frames} frames to {out.resolve()}")
    else:
        write(out, encode(out, vm.morph(args.s, **kw)))
        print(f"wrote {out.resolve()}")
    return 0


def _bake_kinds(args: argparse.Namespace) -> tuple:
    from .bake import BillboardKind, DomeKind, ShadowAtlasKind, SunAtlasKind
    from .errors import ValidationError

    if args.views is not None and not args.billboard:
        raise ValidationError(expected_got("--views", "together with --billboard", "--views alone"))
    given = {"atlas_size": args.atlas_size, "grid": args.grid,
             "range": None if args.range is None else tuple(args.range),
             "light": None if args.light is None else tuple(args.light)}
    atlas = ShadowAtlasKind(**{k: v for k, v in given.items() if v is not None},
                            directional=args.directional)
    if args.directional and args.light is None:
        print(f"morphkit bake: --directional without --light: the light travels {atlas.light} (from the "
              "default point light towards the object)", file=sys.stderr)
    kinds: tuple = (atlas,)
    if args.billboard:
        kinds += (BillboardKind(**({} if args.views is None else {"views": args.views})),)
    if args.dome:
        kinds += (DomeKind(),)
    if args.sun_atlas_size is not None and not args.sun_atlas:
        raise ValidationError(expected_got("--sun-atlas-size", "together with --sun-atlas",
                                           "--sun-atlas-size alone"))
    if args.sun_atlas:
        kinds += (SunAtlasKind(**({} if args.sun_atlas_size is None else {"size": args.sun_atlas_size})),)
    return kinds


def _cmd_bake(args: argparse.Namespace) -> int:
    from .bake import BakeOptions, bake_library
    from .bake.cluster import scheduler_address
    from .files.outfolder import BAKE_OUTPUT

    with _option_values():  # the kinds check their options (--atlas-size, --grid, ...)
        options = BakeOptions(_bake_kinds(args), up=args.up_axis)
        if args.scheduler is not None:
            scheduler_address(args.scheduler)  # its form; whether a scheduler answers is the run's
    _output_folder(args.out, BAKE_OUTPUT)  # before the inputs are searched; bake_library claims it
    manifest = bake_library(args.inputs, args.out, options=options, workers=args.workers,
                            scheduler=args.scheduler, progress=not args.quiet)
    for name, error in sorted(manifest.failed().items()):
        print(f"morphkit bake: failed: {name}: {error}", file=sys.stderr)
    print(f"morphkit bake: {manifest.summary()}; manifest {manifest.path}")
    return 1 if manifest.run.get("failed", 0) else 0


def _cmd_shadows(args: argparse.Namespace) -> int:
    from .files.outfolder import SHADOWS_OUTPUT
    from .programs.playback import (
        CirclePath,
        LinePath,
        PointsPath,
        area_light_for,
        baked_mesh,
        render_shadow_sequence,
    )
    from .render import Renderer
    from .shadow import ShadowAtlas

    if args.samples is not None and args.area_light is None:
        raise UsageError(expected_got("--samples", "together with --area-light", "--samples alone"))
    claim = _output_folder(args.out, SHADOWS_OUTPUT, args.overwrite)
    path_cls = {"line": LinePath, "circle": CirclePath}.get(args.path)
    if path_cls is None:
        if args.frames is not None:
            raise UsageError(expected_got("--frames", "with --path line or circle (a CSV file gives "
                                          "its own positions)", f"--path {args.path}"))
        path = PointsPath.from_csv(args.path)
    else:
        path = path_cls() if args.frames is None else path_cls(args.frames)
    view = {} if args.view is None else {"view": tuple(args.view)}
    atlas = ShadowAtlas.load(args.atlas)
    mesh = baked_mesh(args.atlas, args.mesh, mesh_sha256=atlas.baked.mesh_sha256)
    area = None if args.area_light is None else area_light_for(atlas, *args.area_light)
    with claim.writing() as out, Renderer() as renderer:
        res = render_shadow_sequence(atlas, mesh, path, out, renderer=renderer, size=args.size,
                                     area_light=area, samples=3 if args.samples is None else args.samples,
                                     progress=not args.quiet, **view)
    kind = "hard" if area is None else f"soft, {args.area_light[0]:g} x {args.area_light[1]:g} area light"
    print(f"morphkit shadows: {len(res['frames'])} frames ({kind}) in {out}; video {res['video']}")
    if area is None:
        iou = [e["iou"] for e in res["errors"]]
        print(f"  shadow vs ray cast on the ground: IoU min {min(iou):.3f} mean {sum(iou) / len(iou):.3f}")
    else:
        mae = [e["mae"] for e in res["errors"]]
        print(f"  shadow vs ray cast on the ground: visibility error (mean abs) max {max(mae):.3f} "
              f"mean {sum(mae) / len(mae):.3f}")
    return 0


def _cmd_billboards(args: argparse.Namespace) -> int:
    from .errors import UsageError
    from .programs.scenerender import render_scene, scene_from_flags

    scene = scene_from_flags(args)  # every user error is refused before anything is baked or written
    if args.save_scene:
        from .scenes.jsonfile import write_scene_file

        with _option_values():
            path = write_scene_file(scene, args.save_scene, overwrite=args.overwrite)
        print(f"morphkit billboards: wrote the scene of these options to {path} (nothing rendered; "
              f"morphkit render {path} -o OUT draws it){'; -o not used' if args.out else ''}")
        return 0
    if args.out is None:
        raise UsageError(expected_got("-o/--out", "the output folder (or --save-scene FILE: the scene, "
                                      "nothing rendered)", "none"))
    from .files.outfolder import BILLBOARDS_OUTPUT

    claim = _output_folder(args.out, BILLBOARDS_OUTPUT, args.overwrite)
    render_scene(scene, claim, command="billboards", stem="billboards", path_label=args.path,
                 said=getattr(args, "implied", None) or (), smaller="--n")  # morphkit.programs.cliargs
    return 0


def _cmd_render(args: argparse.Namespace) -> int:
    from .files.outfolder import RENDER_OUTPUT
    from .programs.scenerender import render_scene
    from .scenes import load_scene

    scene = load_scene(args.scene)  # refused before anything is baked or written
    mode = entry = shadows = None
    if args.plan is not None:
        from .plan.planfile import read_plan
        from .scenes.suns import BakeLight

        plan = read_plan(args.plan)
        plan.check_assets(scene.names)
        plan.check_kind(not isinstance(scene.sun, BakeLight) or scene.shadows is not None)
        entry = {"file": str(args.plan), "budget": plan.budget.to_json(), "bands": len(plan.choice.choices)}
        shadows = plan.shadows
        if shadows is not None:
            if scene.shadows is None:
                raise ValidationError(
                    expected_got("plan", "a plan without a shadow for a scene without shadows", "one with")
                )
            entry["shadow"] = {"soft": shadows.soft, "sun_atlas_size": shadows.sun_atlas_size}

        def mode(prep: Any) -> Any:
            return plan.mode(prep.relit, prep.base, prep.shadow, prep.meshes())

    claim = _output_folder(args.out, RENDER_OUTPUT, args.overwrite)
    render_scene(scene, claim, command="render", stem="render", compare=args.compare, mode=mode, plan=entry,
                 shadows=shadows)
    return 0


def _cmd_plan(args: argparse.Namespace) -> int:
    from .files.outfolder import PLAN_OUTPUT
    from .plan import Budget
    from .programs.planning.planrun import plan_scene
    from .scenes import load_scene

    budget = Budget.parse(args.budget or [])  # nonsense budgets: usage errors, before any work
    scene = load_scene(args.scene)
    claim = _output_folder(args.out, PLAN_OUTPUT, args.overwrite)
    plan_scene(scene, budget, claim, sweep=args.sweep, verify=args.verify, tables_cache=args.tables)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The ``morphkit`` argument parser: the ``demo``, ``bench`` and ``viewmorph`` commands.

    Returns
    -------
    argparse.ArgumentParser
        Parsed arguments carry the command's handler as ``func``.
    """
    p = argparse.ArgumentParser(
        prog="morphkit",
        description="Shadows and view-dependent billboards by warping images instead of "
        "re-rendering geometry.",
    )
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    d = sub.add_parser(
        "demo",
        help="render the demo scenes and write PNGs plus index.json to an output folder",
        description="Render each sample mesh (teapot, chair, cow) on a ground plane, lit, with "
        "ray-cast ground-truth hard shadows, and write PNGs and index.json to OUT.",
    )
    d.add_argument("-o", "--out", default="morphkit-demo", help="output folder (default: %(default)s)")
    d.add_argument("--size", type=int, default=512, help="image size in pixels (default: %(default)s)")
    d.add_argument("--quick", action="store_true", help="smaller images and meshes, for a smoke test")
    d.add_argument("--overwrite", action="store_true",
                   help="replace a previous demo in OUT (without it, such a folder is left as it is)")
    d.set_defaults(func=_cmd_demo)

    b = sub.add_parser(
        "bench",
        help="time a suite against its baselines; write a table, JSON and plots",
        description="Time one benchmark suite with warm-up and repeats. Every baseline is timed in "
        "the same run so ratios hold on a noisy machine. Prints a table of medians.",
    )
    from .bench import SUITES  # lazy registry: names only, no suite is imported

    b.add_argument("suite", help=f"suite name: one of {', '.join(sorted(SUITES))}")
    b.add_argument("--quick", action="store_true", help="a reduced sweep that finishes in under a minute")
    b.add_argument("--json", type=Path, default=None, help="write the rows as JSON to this path")
    b.add_argument("--plot", type=Path, default=None,
                   help="write plots to this path (PNG; a suffix is added per plot)")
    b.add_argument("--workers", type=int, nargs="+", default=None, metavar="N",
                   help="bake only: the local worker counts to time (default 1 2; 1 is always included); "
                   "reports the speed-up curve, per-worker start-up and a 16-worker projection")
    b.add_argument("--assets", type=int, default=None, metavar="N",
                   help="bake only: the library's size (its 16 meshes repeated, each copy turned; "
                   "default 16): e.g. 256 on a machine with 16 cores")
    b.add_argument("--sections", default=None, metavar="NAMES",
                   help=f"{', '.join(SECTIONED_SUITES)} only: run only these sections, comma-separated "
                   "(e.g. dome-bands,dome-relit; scene: accuracy,per-asset,receivers,sun-change,atlas-grid,"
                   "temporal,sun-disc,levels,receivers-resolution; "
                   "shadows: accuracy,cutout,control-grid,complexity,frame,frame-once; render: depth,"
                   "accuracy,fidelity,pass; names: the suite's section functions less _rows)")
    b.add_argument("--instances", type=int, nargs="+", default=None, metavar="N",
                   help="scene only: the instance counts of its accuracy, sun-change and levels sections "
                   "(default 10 100 1000 and 100 1000; --quick 10)")
    b.set_defaults(func=_cmd_bench)

    v = sub.add_parser(
        "viewmorph",
        help="view-morph two images of the same object (Seitz & Dyer): the view in between",
        description="Pre-warp LEFT and RIGHT to parallel views, morph them by s and post-warp the "
        "result. Correspondences come from --points (JSON/CSV of x0,y0,x1,y1) or from the images "
        "(SIFT and dense optical flow) with a robust fundamental-matrix fit.",
    )
    v.add_argument("left", help="image at s = 0 (PNG/JPEG; grey, RGB or RGBA)")
    v.add_argument("right", help="image at s = 1")
    v.add_argument("--s", type=float, default=0.5, help="position between the views, in [0, 1] "
                   "(default: %(default)s)")
    v.add_argument("--points", default=None, help="correspondences file (.json or .csv)")
    v.add_argument("--frames", type=int, default=0,
                   help="write N in-between views (s = 0..1) as OUT/frames/frame_NNNN.png instead of one "
                   "image")
    v.add_argument("--prewarp", default="auto", choices=["auto", "opencv", "seitz-dyer", "none"],
                   help="rectification (default: %(default)s; none = plain mesh morph)")
    v.add_argument("--fallback", default="raise", choices=["raise", "morph"],
                   help="if rectification is impossible: refuse, or plain mesh morph (default: %(default)s)")
    v.add_argument("--post", default="interpolate", choices=["interpolate", "rectified"],
                   help="post-warp: interpolated between the views, or none (default: %(default)s)")
    v.add_argument("--frame", default="contain", choices=["contain", "fit", "fixed"],
                   help="crop/size policy (default: %(default)s)")
    v.add_argument("-o", "--out", required=True, help="output image (or folder with --frames)")
    v.add_argument("--overwrite", action="store_true",
                   help="replace an existing OUT image, or with --frames a previous run in OUT")
    v.set_defaults(func=_cmd_viewmorph)

    k = sub.add_parser(
        "bake",
        help="bake every mesh of a library (files or folders) into OUT, on Dask; resumable",
        description="Bake each mesh (any format trimesh loads; folders are searched recursively) into "
        "OUT: one file per asset and kind (a shadow atlas: <name>.atlas.npz) and manifest.json (input "
        "hashes, options, output hashes and sizes, timings, status). Assets whose input and options "
        "match the manifest are skipped. Runs on local worker processes (one GL context each) or on an "
        "existing Dask scheduler. Exit code 1 if any asset failed (listed on stderr and in the manifest).",
    )
    # defaults are morphkit.bake.ShadowAtlasKind's (not imported here: --help stays fast; a test
    # checks that the numbers below are its defaults)
    k.add_argument("inputs", nargs="+", metavar="MESH_OR_FOLDER", help="mesh files and folders")
    k.add_argument("-o", "--out", required=True, help="output folder (created)")
    k.add_argument("--atlas-size", type=int, default=None, metavar="N",
                   help="side of each shadow map in pixels (default: 512)")
    k.add_argument("--grid", type=int, default=None, metavar="K", help="shadow maps per axis, K x K "
                   "(default: 3)")
    k.add_argument("--range", type=float, nargs=4, metavar=("X0", "Y0", "X1", "Y1"), default=None,
                   help="the object's range of motion on the ground (default: -0.6 -0.6 0.6 0.6)")
    k.add_argument("--light", type=float, nargs=3, metavar=("X", "Y", "Z"), default=None,
                   help="point light position (z > 0), or with --directional the direction light "
                   "travels (z < 0) (default: 0.25 -0.2 2.4); with --directional its way to the object, "
                   "-0.25 0.2 -2.4")
    k.add_argument("--directional", action="store_true", help="a directional light (see --light)")
    where = k.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help="local worker processes (default: the CPU count)")
    where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="an existing Dask scheduler, e.g. tcp://host:8786 (see README)")
    k.add_argument("--billboard", action="store_true",
                   help="also bake a view-morphing billboard asset per mesh (<name>.billboard.npz)")
    k.add_argument("--views", type=int, default=None, metavar="K",
                   help="billboard reference views (with --billboard)")
    k.add_argument("--dome", action="store_true",
                   help="also bake a relightable billboard seen from any height per mesh (<name>.dome.npz)")
    k.add_argument("--sun-atlas", action="store_true",
                   help="also bake a sun atlas per mesh (<name>.sunatlas.npz): billboards --shadows with "
                   "the bake's .dome.npz assets then reads it instead of baking it at the start of the run")
    k.add_argument("--sun-atlas-size", type=int, default=None, metavar="N",
                   help="texels a side of the sun atlas views (with --sun-atlas; default 128, as "
                   "billboards')")
    # the table is morphkit.meshes.UP_AXIS_BY_FORMAT's (a test checks it)
    k.add_argument("--up-axis", choices=("auto", "y", "z"), default="auto",
                   help="the mesh files' up axis, turned to morphkit's +z: auto is each format's default "
                   "(glTF/GLB and OBJ y, every other format z); recorded per asset in the manifest, and an "
                   "asset baked with another axis is baked again (default: %(default)s)")
    k.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    k.set_defaults(func=_cmd_bake)

    h = sub.add_parser(
        "shadows",
        help="render a baked atlas's scene along an object path with warped shadows (PNGs + video)",
        description="Move the mesh an atlas was baked from along a path over the atlas's range and "
        "render each frame with the warped shadow: hard, or soft with --area-light. Writes "
        "OUT/frames/frame_NNNN.png and OUT/shadows.webm (VP9). The mesh comes from the bake manifest (its "
        "folder or a parent), hash-checked, or from --mesh.",
    )
    h.add_argument("atlas", help="a baked shadow atlas (.atlas.npz)")
    h.add_argument("--path", default="line", metavar="line|circle|FILE.csv",
                   help="the object's path: the range's diagonal, a circle, or x,y rows (default: "
                   "%(default)s)")
    h.add_argument("--frames", type=int, default=None, metavar="N",
                   help="frames along line or circle (default: 48)")
    h.add_argument("--area-light", type=float, nargs=2, metavar=("W", "H"), default=None,
                   help="soft shadows of a W x H area light centred on the atlas's point light")
    h.add_argument("--samples", type=int, default=None, metavar="N",
                   help="light samples per axis with --area-light (N x N; default: 3)")
    h.add_argument("--size", type=int, default=512, metavar="N",
                   help="frame size in pixels (default: %(default)s)")
    h.add_argument("--mesh", default=None, help="the mesh file the atlas was baked from, if not where "
                   "the manifest says")
    h.add_argument("--view", type=float, nargs=2, metavar=("AZ", "EL"), default=None,
                   help="camera azimuth and elevation in degrees, looking at the range's centre "
                   "(default: -43.2 20.6, a 3/4 view; elevation 5-89)")
    h.add_argument("-o", "--out", required=True, help="output folder (created)")
    h.add_argument("--overwrite", action="store_true", help="replace a previous `shadows` run in OUT")
    h.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    h.set_defaults(func=_cmd_shadows)

    bb = sub.add_parser(
        "billboards",
        help="a scene of view-morphed billboards along a camera path: frames, video, Fig. 5 comparisons",
        description="Bake (or load) billboard assets, place N instances from a seed on a ground, and "
        "render a camera path with view-morphed billboards: OUT/frames/*.png, OUT/billboards.webm (VP9), "
        "OUT/compare_*.png (classic | view-morphed | real meshes) and OUT/billboards.json.",
    )
    bb.add_argument("--asset", action="append", default=None, metavar="NAME_OR_FILE",
                    help="a sample mesh name, a mesh file (.obj, .glb/.gltf, .ply: baked in its own look) "
                    "or a .npz asset file (loaded); repeat for several "
                    "(default: tree and person)")
    bb.add_argument("--n", type=int, default=200,
                    help="number of billboards, scattered from --seed over a field of about one per 1.5 x 1.5"
                    " units and moved apart where one would stand inside another (default: %(default)s)")
    bb.add_argument("--path", default="pan", choices=["pan", "orbit", "fly", "flyover", "topdown"],
                    help="camera path: the paper's pan, an orbit, a fly-through, a fly-over rising from 5 to "
                    "85 degrees or a top-down pan (default: %(default)s)")
    bb.add_argument("--views", default=None, metavar="K|dome",
                    help="reference views per baked asset: 2 is the paper's pair, more a full ring at one "
                    "elevation; 'dome': relightable views over the hemisphere, seen from any height "
                    "(default: what the scene needs, said in one line: dome with --sun-path or for a "
                    "path whose eye looks down from above the ring's band, flyover and topdown; else 8)")
    bb.add_argument("--sun-path", default=None, choices=["day"],
                    help="light the billboards by a sun moving across the sky over the frames "
                    "(relightable dome assets; default: the bake light)")
    bb.add_argument("--shadows", action="store_true",
                    help="the instances cast shadows on the ground and on each other under the sun "
                    "(alone: with the default sun, --sun-path day, and dome views): a sun atlas per "
                    "asset (21 sun directions at 128 texels) is read from the bake beside a .dome.npz "
                    "asset (bake --sun-atlas) or baked from its mesh at the start of the run; the "
                    "comparison strips' real meshes get ray-cast shadows (the truth)")
    bb.add_argument("--soft", default=None, nargs="?", const=SOFT_FILTER, metavar="N|pcss",
                    help="a soft sun for --shadows (implied). --soft alone (or --soft pcss): one map "
                    "along the disc's centre at 1.5 times the atlases' texels, filtered (percentage-closer "
                    "soft "
                    "shadows: at the real sun less error than several maps averaged, in less time; over "
                    "wider discs smoother penumbrae; docs/RESULTS.md, the soft sun); "
                    "--soft N: N directions over its disc, one shadow map each, averaged "
                    "(default: a hard shadow)")
    bb.add_argument("--sun-atlas-size", type=int, default=None, metavar="N",
                    help="for --shadows (implied): texels a side of each asset's sun atlas views "
                    "(default 128, 2 MB for two assets; 256: 8 MB, sharper shadows on the instances and "
                    "meshes themselves, "
                    "for more time a frame under a new sun; docs/RESULTS.md)")
    bb.add_argument("--sun-radius", type=float, default=SUN_DISC_RADIUS_DEG, metavar="DEG",
                    help="for --soft (implied): the sun disc's angular radius, degrees (default: the "
                    "real sun's %(default)s; larger discs give wider penumbrae, up to 15)")
    bb.add_argument("--frames", type=int, default=48, help="frames along the path (default: %(default)s)")
    bb.add_argument("--size", default="640x480", help="frame size WxH (default: %(default)s)")
    bb.add_argument("--asset-size", type=int, default=128,
                    help="reference view side of baked assets, pixels (default: %(default)s)")
    bb.add_argument("--seed", type=int, default=0, help="placement seed (default: %(default)s)")
    bb.add_argument("--up-axis", default="auto", choices=["auto", "y", "z"],
                    help="up axis of --asset mesh files; auto: glTF/OBJ +y, others +z (default: %(default)s)")
    bb.add_argument("--no-fog", action="store_true", help="no distance fog")
    bb.add_argument("-o", "--out", default=None, help="output folder (required unless --save-scene)")
    bb.add_argument("--save-scene", default=None, metavar="FILE",
                    help="write the scene these options describe to FILE (a JSON scene file for "
                    "`morphkit render`) and render nothing")
    bb.add_argument("--overwrite", action="store_true",
                    help="replace a previous `billboards` run in OUT (or the --save-scene FILE)")
    bb.set_defaults(func=_cmd_billboards)

    rs = sub.add_parser(
        "render",
        help="a scene file's frames, video and comparisons against the truth",
        description="Render a scene: a JSON scene file (morphkit's scene schema: assets, instances, "
        "camera, sun, shadows, image) or a glTF scene (.glb/.gltf: each mesh an asset, its nodes the "
        "instances, its directional light the sun, its camera the camera). Writes OUT/frames/*.png, "
        "OUT/render.webm, OUT/compare_*.png (classic | view-morphed | real meshes, ray-cast shadows) "
        "and OUT/render.json (the assets with their instance counts and scales, per-frame errors and times).",
    )
    rs.add_argument("scene", metavar="SCENE", help="a scene file (.json) or a glTF scene (.glb, .gltf)")
    rs.add_argument("-o", "--out", required=True, help="output folder")
    rs.add_argument("--compare", default=3, type=_compare_count, metavar="N|all",
                    help="frames also drawn with the real meshes (ray-cast shadows under a sun) and "
                    "measured against them, spread over the path: their strips and per-billboard "
                    "errors in render.json (default: %(default)s; all: every frame)")
    rs.add_argument("--plan", default=None, metavar="PLAN",
                    help="draw each band of billboards as `morphkit plan` chose (its plan.json, or its "
                    "output folder)")
    rs.add_argument("--overwrite", action="store_true", help="replace a previous `render` run in OUT")
    rs.set_defaults(func=_cmd_render)

    pl = sub.add_parser(
        "plan",
        help="choose each band of a scene's billboards' representation to an error budget, verified",
        description="Plan a scene (as `render` takes it) to an error budget: measure each asset's error "
        "in every representation against its own mesh (tables over on-screen size and elevation), predict "
        "every frame's error, choose per asset and band of on-screen size and elevation the cheapest "
        "representation (culled, classic card, nearest view, view morph, real mesh) predicted to meet the "
        "budget (with shadow-iou, also the sun atlases' texels and the sun's softness measured to meet it), "
        "and verify "
        "the plan on held-out frames against the real meshes, timed against the default. Writes "
        "OUT/plan.json, OUT/plan.png and OUT/tables/. Exit 1 with the best reachable figure when no "
        "choice meets the budget (nothing written); exit 2 for a nonsense budget.",
    )
    pl.add_argument("scene", metavar="SCENE", help="a scene file (.json) or a glTF scene (.glb, .gltf)")
    pl.add_argument("--budget", action="append", metavar="KEY=VALUE",
                    help="billboard-psnr=DB, billboard-iou=X, shadow-iou=X (a scene with shadows), "
                    "time-ms=MS, frames=FRACTION (default 0.95); once per key")
    pl.add_argument("-o", "--out", required=True, help="output folder")
    pl.add_argument("--sweep", action="store_true",
                    help="also verify each representation everywhere (the cheapest meeting the budget in "
                    "plan.json's time_ms.cheapest_sweep)")
    pl.add_argument("--verify", type=int, default=6, metavar="N",
                    help="held-out frames verified against the real meshes (default: %(default)s)")
    pl.add_argument("--tables", default=None, metavar="DIR",
                    help="where the error tables are kept between runs (default: tables/ in $MORPHKIT_CACHE, "
                    "~/.cache/morphkit)")
    pl.add_argument("--overwrite", action="store_true",
                    help="replace a previous `plan` in OUT (its error tables are reused where they match)")
    pl.set_defaults(func=_cmd_plan)

    add_file_commands(sub)
    return p


def _compare_count(text: str) -> int | None:
    """``render --compare``: a count of frames >= 0, or ``all`` (None)."""
    if text.strip().lower() == "all":
        return None
    try:
        n = int(text)
    except ValueError:
        n = -1
    if n < 0:
        raise argparse.ArgumentTypeError(f"expected a number of frames >= 0 or 'all', got {text!r}")
    return n


def _out_of_memory(exc: BaseException) -> bool:
    """``exc`` is a failed allocation: a ``MemoryError``, or OpenCV's (``cv2.error`` with code
    ``StsNoMem``, -4, "Insufficient memory"), which is not a MemoryError."""
    return isinstance(exc, MemoryError) or (type(exc).__module__ == "cv2" and type(exc).__name__ == "error"
                                            and getattr(exc, "code", None) == -4)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``morphkit`` command line.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 on success; 2 for a usage error (argparse's, a bad option value or
        environment variable, an output refused without ``--overwrite``); 1 after any other
        :class:`~morphkit.errors.MorphkitError`, an ``OSError`` (a file system failure: disk
        full, folder removed) or a failed allocation (a ``MemoryError`` or OpenCV's: sizes past
        the process's memory); each printed to stderr as one line ``morphkit: error: ...``;
        130 after Ctrl-C (``morphkit: interrupted``); 143 after SIGTERM (``morphkit: terminated``),
        which the run unwinds like Ctrl-C (128 + the signal's number: what a shell reports).
    """
    with _one_line_warnings():
        try:
            with _option_values():  # a usage error (exit 2), even for --help
                from . import settings  # a variable it cannot read is refused when it is imported

                settings.check_environment()
        except MorphkitError as exc:
            return _error(exc)
        args = build_parser().parse_args(argv)
        with stop_signals() as stop:
            return _run(args, stop)


def _exit_code(exc: MorphkitError | OSError) -> int:
    """The exit code of an error (the rule in this module's docstring): 2 for a usage error, 1 for a
    run that failed."""
    return 2 if isinstance(exc, UsageError | OutputExistsError) else 1


def _error(exc: MorphkitError | OSError) -> int:
    """Print ``exc`` as one line ``morphkit: error: ...``; its exit code."""
    msg = " ".join(str(exc).split()) or type(exc).__name__  # one line
    print(f"morphkit: error: {msg}", file=sys.stderr)
    return _exit_code(exc)


@contextmanager
def _one_line_warnings() -> Iterator[None]:
    """While the block runs, a warning prints as one line ``morphkit: warning: MESSAGE`` on stderr
    (no source path, no code line); Python's own printer is restored after."""
    previous = warnings.showwarning

    def show(message: Warning | str, category: type[Warning], filename: str, lineno: int,
             file: Any = None, line: str | None = None) -> None:
        text = " ".join(str(message).split()) or category.__name__
        print(f"morphkit: warning: {text}", file=sys.stderr if file is None else file)

    warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = previous


def _run(args: argparse.Namespace, stop: Stop) -> int:
    """Check the options, run the command; print morphkit's errors, file system failures, failed
    allocations and interrupts as one line (:func:`main`)."""
    try:
        with _option_values():
            check_args(args)  # every option refused before any work (morphkit.programs.cliargs)
        return int(args.func(args))
    except KeyboardInterrupt as exc:  # Ctrl-C or SIGTERM: one line; atomic writes removed their temporaries
        return report_stop(signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
    except Exception as exc:
        if stop.signum is not None:
            # Ctrl-C inside a library's C callback (numba saving a kernel it was compiling): the
            # KeyboardInterrupt was swallowed there and the library failed instead: an interrupt
            return report_stop(stop.signum)
        if isinstance(exc, (MorphkitError, OSError)):
            return _error(exc)
        if not _out_of_memory(exc):  # sizes that need more memory than the process may have: one line
            raise
        why = " ".join(str(exc).split("error: ", 1)[-1].split()) or "an allocation failed"  # cv2: its reason
        print(f"morphkit: error: out of memory: {why} (the sizes asked for need more memory than this "
              "process may use: choose smaller ones)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
