"""The ``morphkit`` command line: ``demo``, ``bench`` (and later ``viewmorph``).

Heavy modules are imported inside each subcommand so ``morphkit --help`` is fast
and needs no GL context.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from .errors import MorphkitError


def _cmd_demo(args: argparse.Namespace) -> int:
    from .demo import run_demo

    index = run_demo(Path(args.out), size=args.size, quick=args.quick)
    print(f"morphkit demo: wrote {len(index['files'])} files to {Path(args.out).resolve()}")
    print(f"index: {Path(args.out).resolve() / 'index.json'}")
    return 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench import SUITES, run_suite

    if args.suite not in SUITES:
        print(f"unknown suite {args.suite!r}; available: {', '.join(sorted(SUITES))}",
              file=sys.stderr)
        return 2
    run_suite(args.suite, quick=args.quick, json_path=args.json, plot_path=args.plot)
    return 0


def _cmd_viewmorph(args: argparse.Namespace) -> int:
    import cv2
    import numpy as np

    from .errors import FileFormatError, ValidationError, expected_got
    from .fileio import encode_image, write_bytes
    from .viewmorph import ViewMorpher, from_images, load_points

    def read(path: str) -> np.ndarray:
        # decoded from bytes: cv2.imread prints its own warning for a missing file
        p = Path(path)
        if not p.is_file():
            raise FileFormatError(expected_got(f"image {path!r}", "an existing file",
                                               "a folder" if p.is_dir() else "nothing there"))
        try:
            data = np.fromfile(p, dtype=np.uint8)
        except OSError as exc:
            raise FileFormatError(expected_got(f"image {path!r}", "a readable file",
                                               exc.strerror or exc)) from exc
        img = cv2.imdecode(data, cv2.IMREAD_UNCHANGED) if data.size else None
        if img is None:
            raise FileFormatError(expected_got(f"image {path!r}", "an image file OpenCV can decode",
                                               f"{data.size} bytes it cannot"))
        if img.ndim == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA if img.shape[2] == 4 else cv2.COLOR_BGR2RGB)
        return img

    def encode(path: Path, img: np.ndarray) -> bytes:
        if img.ndim == 3:
            img = cv2.cvtColor(img, cv2.COLOR_RGBA2BGRA if img.shape[2] == 4 else cv2.COLOR_RGB2BGR)
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

    # the output is checked before the work: a folder, a file in the way, an unknown extension
    out = Path(args.out)
    folder = out if args.frames else out.parent
    in_the_way = next((a for a in (folder, *folder.parents) if a.exists() and not a.is_dir()), None)
    if in_the_way is not None:
        expected = "a folder path" if args.frames else "a path whose parents are folders"
        raise ValidationError(expected_got("output" + (" with --frames" if args.frames else ""), expected,
                                           f"{str(out)!r}, where {str(in_the_way)!r} is a file"))
    if not args.frames:
        if out.is_dir():
            raise ValidationError(expected_got("output", "an image file path (or --frames N for a folder)",
                                               f"the folder {str(out)!r}"))
        encode(out, np.zeros((1, 1, 3), np.uint8))  # an unknown extension is refused here
    left, right = read(args.left), read(args.right)
    corr = load_points(args.points) if args.points else from_images(left, right)
    vm = ViewMorpher(left, right, corr, prewarp=args.prewarp, fallback=args.fallback)
    rep = vm.report
    fit = rep.get("fundamental", {})
    print(f"morphkit viewmorph: mode {vm.mode}, pre-warp {vm.rectification.method}, "
          f"{rep['n_used']}/{rep['n_input']} pairs used ({rep['n_duplicates']} duplicates, "
          f"{rep.get('n_outliers', 0)} outliers, {rep['n_dropped_foldover']} dropped for fold-overs)"
          + (f", F by {fit['method']}: Sampson RMS {fit['sampson_rms_px']:.3f} px" if fit else "")
          + (f"; fallback: {rep['fallback']}" if "fallback" in rep else ""))
    kw = {"post": args.post, "frame": args.frame}
    if args.frames:
        for i, img in enumerate(vm.frames(args.frames, **kw)):
            name = out / f"frame_{i:03d}.png"
            write(name, encode(name, img))
        print(f"wrote {args.frames} frames to {out.resolve()}")
    else:
        write(out, encode(out, vm.morph(args.s, **kw)))
        print(f"wrote {out.resolve()}")
    return 0


def build_parser() -> argparse.ArgumentParser:
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
                   help="write N in-between views (s = 0..1) as OUT/frame_NNN.png instead of one image")
    v.add_argument("--prewarp", default="auto", choices=["auto", "opencv", "seitz-dyer", "none"],
                   help="rectification (default: %(default)s; none = plain mesh morph)")
    v.add_argument("--fallback", default="raise", choices=["raise", "morph"],
                   help="if rectification is impossible: refuse, or plain mesh morph (default: %(default)s)")
    v.add_argument("--post", default="interpolate", choices=["interpolate", "rectified"],
                   help="post-warp: interpolated between the views, or none (default: %(default)s)")
    v.add_argument("--frame", default="contain", choices=["contain", "fit", "fixed"],
                   help="crop/size policy (default: %(default)s)")
    v.add_argument("-o", "--out", required=True, help="output image (or folder with --frames)")
    v.set_defaults(func=_cmd_viewmorph)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except MorphkitError as exc:
        print(f"morphkit: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
