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
    b.add_argument("suite", help="suite name (e.g. warp)")
    b.add_argument("--quick", action="store_true", help="a reduced sweep that finishes in under a minute")
    b.add_argument("--json", type=Path, default=None, help="write the rows as JSON to this path")
    b.add_argument("--plot", type=Path, default=None,
                   help="write plots to this path (PNG; a suffix is added per plot)")
    b.set_defaults(func=_cmd_bench)
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
