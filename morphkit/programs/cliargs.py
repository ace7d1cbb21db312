"""Every command line option checked before any work: counts, sizes, seeds, numbers.

:func:`check_args` runs on the parsed arguments of any ``morphkit`` command before
its handler: a bad value is a one-line :class:`~morphkit.errors.ValidationError`
before anything is loaded, baked, rendered or written, and every count that
allocates in proportion to its value has a cap (named in :mod:`morphkit.tol`,
with its reason there). The library functions the commands call check the same
values again (the API's own contract); this module only makes the command line
refuse them first. Output folders are checked by :mod:`morphkit.files.outfolder`.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from .. import tol
from ..conventions import SUN_DISC_RADIUS_DEG
from ..errors import UsageError, ValidationError, expected_got
from ..validate import as_int

__all__ = ["check_args", "implied_sun_options", "parse_size", "check_output_file",
           "same_file", "choose_views", "MIN_FRAME_SIDE", "MAX_FRAME_SIDE", "SOFT_FILTER"]

#: Smallest frame side a command renders (pixels): below it a frame shows nothing.
MIN_FRAME_SIDE = 16
#: Largest frame side a command renders (pixels); a square frame of it is
#: :data:`morphkit.tol.MAX_IMAGE_PIXELS`.
MAX_FRAME_SIDE = 8192


def _count(args: argparse.Namespace, attr: str, option: str, lo: int, hi: int) -> None:
    """``args.<attr>`` (when given) as an integer in ``[lo, hi]``."""
    v = getattr(args, attr, None)
    if v is not None:
        as_int(v, option, lo=lo, hi=hi)


def _counts(args: argparse.Namespace, attr: str, option: str, lo: int, hi: int) -> None:
    """Each of ``args.<attr>`` (a list, when given) as an integer in ``[lo, hi]``."""
    v = getattr(args, attr, None)
    if v is not None:
        setattr(args, attr, [as_int(x, option, lo=lo, hi=hi) for x in v])


def _finite(args: argparse.Namespace, attr: str, option: str) -> None:
    """Every number of ``args.<attr>`` (when given) finite."""
    v = getattr(args, attr, None)
    values = [] if v is None else list(v) if isinstance(v, list | tuple) else [v]
    if any(not math.isfinite(x) for x in values):
        raise ValidationError(expected_got(option, "finite numbers", " ".join(map(str, values))))


def _demo(args: argparse.Namespace) -> None:
    _count(args, "size", "--size", MIN_FRAME_SIDE, MAX_FRAME_SIDE)


def _billboards(args: argparse.Namespace) -> None:
    args.implied = implied_sun_options(args)
    _asset_names(args.asset or [])
    _count(args, "n", "--n", 0, tol.MAX_INSTANCES)
    _count(args, "frames", "--frames", 1, tol.MAX_FRAMES)
    if args.views is not None and str(args.views) != "dome":  # a ring of K views, or "dome"
        try:
            k = int(str(args.views).strip())
        except ValueError:
            raise ValidationError(expected_got("--views", f"an integer in [2, {tol.MAX_BILLBOARD_VIEWS}] "
                                               "(a ring) or 'dome'", repr(args.views))) from None
        as_int(k, "--views", lo=2, hi=tol.MAX_BILLBOARD_VIEWS)
        if getattr(args, "sun_path", None):
            raise ValidationError(expected_got(
                "--views with --sun-path", "dome (relighting needs albedo, normals and depth: --views dome)",
                f"a ring of {k} baked under its bake light"
                + (f" ({'; '.join(args.implied)})" if args.implied else "")))
    _billboard_shadows(args)
    _count(args, "asset_size", "--asset-size", 16, tol.MAX_BILLBOARD_SIDE)
    _count(args, "seed", "--seed", 0, tol.MAX_SEED)
    parts = str(args.size).lower().split("x")  # the form is parse_size's to check; here its area
    if len(parts) == 2 and all(p.strip().isdigit() for p in parts) \
            and int(parts[0]) * int(parts[1]) > tol.MAX_IMAGE_PIXELS:
        raise ValidationError(expected_got("--size", f"at most {tol.MAX_IMAGE_PIXELS} pixels "
                                           "(tol.MAX_IMAGE_PIXELS)", args.size))


def _asset_names(specs: Sequence[str]) -> None:
    """``--asset``: a value that can never be an asset, neither a sample name nor a path of an
    asset file's kind, is a usage error (a mesh or ``.npz`` file that is missing or cannot be
    read is the run's input failing: :func:`morphkit.programs.sources.check_specs`)."""
    from ..meshes import BILLBOARD_MESHES
    from .sources import MESH_SUFFIXES  # lazy: only billboards' checks need the wing

    kinds = (*MESH_SUFFIXES, ".npz")
    for spec in specs:
        path = Path(spec)
        if spec in BILLBOARD_MESHES or path.suffix.lower() in kinds:
            continue
        if not spec.strip():
            got = "an empty name"
        elif path.exists():
            got = f"{spec!r}, a {'folder' if path.is_dir() else 'file'} of another kind"
        else:
            got = f"{spec!r}, no sample of that name (and no file)"
        raise UsageError(expected_got("--asset", f"a sample mesh name ({', '.join(BILLBOARD_MESHES)}) or a "
                                      f"mesh or asset file ({', '.join(kinds)})", got))


#: ``billboards --soft`` (alone, or ``--soft pcss``): the sun's disc filtered from one map
#: (:class:`morphkit.sunlit.receivers.FilteredAtlasShadow`) instead of N maps averaged.
SOFT_FILTER = "pcss"


def implied_sun_options(args: argparse.Namespace) -> list[str]:
    """``billboards``: a sun option given alone does what it says, taking what it needs.

    ``--sun-radius`` (other than the real sun's) alone is a soft sun (``--soft``, the
    filtered disc); ``--soft`` or ``--sun-atlas-size`` alone cast shadows (``--shadows``);
    ``--shadows`` alone has the default sun (``--sun-path day``, which takes dome views
    where ``--views`` is not given). ``args`` is updated in place.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``billboards`` arguments.

    Returns
    -------
    list of str
        What was implied, one phrase each (``"--soft implies --shadows"``), in the order of
        the chain; empty when nothing was.
    """
    said: list[str] = []
    radius = getattr(args, "sun_radius", None)
    if radius is not None and radius != SUN_DISC_RADIUS_DEG and getattr(args, "soft", None) is None:
        args.soft = SOFT_FILTER
        said.append(f"--sun-radius implies --soft ({SOFT_FILTER})")
    if not getattr(args, "shadows", False):
        given = [o for o, a in (("--soft", "soft"), ("--sun-atlas-size", "sun_atlas_size"))
                 if getattr(args, a, None) is not None]
        if given:
            args.shadows = True
            said.append(f"{' and '.join(given)} {'implies' if len(given) == 1 else 'imply'} --shadows")
    if getattr(args, "shadows", False) and not getattr(args, "sun_path", None):
        args.sun_path = "day"
        said.append("--shadows implies --sun-path day (a default sun)")
    return said


def _billboard_shadows(args: argparse.Namespace) -> None:
    """``--shadows``, ``--soft``, ``--sun-radius``, ``--sun-atlas-size`` of ``billboards``: the
    combinations that mean something (after :func:`implied_sun_options`)."""
    shadows = getattr(args, "shadows", False)
    atlas_size = getattr(args, "sun_atlas_size", None)
    if atlas_size is not None:
        args.sun_atlas_size = as_int(atlas_size, "--sun-atlas-size", lo=tol.MIN_SUN_ATLAS_SIZE,
                                     hi=tol.MAX_SUN_ATLAS_SIZE)
    radius = getattr(args, "sun_radius", None)
    if not shadows:
        return
    if args.views is not None and str(args.views) != "dome":
        raise ValidationError(expected_got("--shadows", "dome views (--views dome: relit billboards)",
                                           f"--views {args.views}"))
    soft = getattr(args, "soft", None)
    if soft is not None and str(soft).strip().lower() == SOFT_FILTER:
        args.soft = SOFT_FILTER
    elif soft is not None:
        try:
            count = int(str(soft))
        except ValueError:
            raise ValidationError(expected_got("--soft", f"an integer in [1, {tol.MAX_SUN_SAMPLES}] or "
                                               f"{SOFT_FILTER}", soft)) from None
        args.soft = as_int(count, "--soft", lo=1, hi=tol.MAX_SUN_SAMPLES)
    _finite(args, "sun_radius", "--sun-radius")
    if radius is not None and not 0.0 <= radius <= tol.MAX_SUN_DISC_DEG:
        raise ValidationError(expected_got("--sun-radius", f"degrees in [0, {tol.MAX_SUN_DISC_DEG:g}]",
                                           radius))


def _shadows(args: argparse.Namespace) -> None:
    path = getattr(args, "path", None)
    if path is not None and path not in ("line", "circle") and not str(path).lower().endswith(".csv") \
            and not Path(path).is_file():
        raise UsageError(expected_got("--path", "line, circle or a CSV file of x,y rows (FILE.csv)",
                                      f"{path!r}, no path of that name (and no file)"))
    _count(args, "frames", "--frames", 1, tol.MAX_FRAMES)
    _count(args, "size", "--size", MIN_FRAME_SIDE, tol.MAX_VIDEO_SIDE)  # its frames make a video too
    # N x N samples, at most tol.MAX_LIGHT_SAMPLES in all
    _count(args, "samples", "--samples", 1, math.isqrt(tol.MAX_LIGHT_SAMPLES))
    _finite(args, "area_light", "--area-light")
    _finite(args, "view", "--view")
    if getattr(args, "view", None) is not None and not 5.0 <= args.view[1] <= 89.0:
        raise ValidationError(expected_got("--view", "an azimuth and an elevation in [5, 89] degrees",
                                           " ".join(map(str, args.view))))
    if args.area_light is not None and min(args.area_light) <= 0:
        raise ValidationError(expected_got("--area-light", "a width and height > 0",
                                           " ".join(map(str, args.area_light))))


def _viewmorph(args: argparse.Namespace) -> None:
    if args.frames != 0:  # 0: one image at --s
        _count(args, "frames", "--frames", 2, tol.MAX_FRAMES)
    _finite(args, "s", "--s")
    if not 0.0 <= args.s <= 1.0:
        raise ValidationError(expected_got("--s", "a position in [0, 1]", args.s))


def _bake(args: argparse.Namespace) -> None:
    # the kinds' options (--atlas-size, --grid, --range, --light, --views) are checked by the
    # kinds themselves (morphkit.bake.kinds) before the bake starts
    _count(args, "workers", "--workers", 1, tol.MAX_LOCAL_WORKERS)


def _bench(args: argparse.Namespace) -> None:
    # every count option of `bench` (which suite takes which is cli._cmd_bench's to say)
    _counts(args, "workers", "--workers", 1, tol.MAX_LOCAL_WORKERS)
    _count(args, "assets", "--assets", 1, tol.MAX_BENCH_ASSETS)
    _counts(args, "instances", "--instances", 1, tol.MAX_BENCH_INSTANCES)
    sections = getattr(args, "sections", None)
    if sections is not None:
        names = [s.strip() for s in str(sections).split(",")]
        if not any(names) or not all(names):
            raise ValidationError(expected_got("--sections", "section names, comma-separated (e.g. "
                                               "accuracy,sun-change)", repr(sections)))
        args.sections = ",".join(names)


_CHECKS: dict[str, Callable[[argparse.Namespace], None]] = {
    "bench": _bench, "demo": _demo, "billboards": _billboards, "shadows": _shadows, "viewmorph": _viewmorph,
    "bake": _bake}


def check_args(args: argparse.Namespace) -> None:
    """Refuse a bad option value of any command before the command runs.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of :func:`morphkit.cli.build_parser` (``args.command`` names the command).

    Raises
    ------
    ValidationError
        A count, size or seed outside its range (caps in :mod:`morphkit.tol`), or a number
        that is not finite.
    """
    check = _CHECKS.get(getattr(args, "command", None) or "")
    if check is not None:
        check(args)


def choose_views(views: int | str | None, relit_by: str | None, path: str, cameras: Sequence[Any],
                 specs: Sequence[str], head: str = "morphkit billboards: ") -> tuple[int | None, str]:
    """The views a scene's assets are baked with: K for a ring, None for relightable views over the
    hemisphere (``dome``), and, when ``views`` is None, the line saying which representation the
    scene takes and why: dome views for a sun that relights them or for a path whose eye looks
    down from above the ring's band (:attr:`morphkit.billboard.ring.ViewRing.band_deg`), else a
    ring of 8 (``.npz`` asset files load as they were baked: dome files as a dome, ring files as
    a ring).

    Parameters
    ----------
    views : int, "dome" or None
        Asked for (None: what the scene needs).
    relit_by : str or None
        What relights the assets (``"--sun-path"``, ``"the scene's sun"``), None when nothing does.
    path : str
        The camera path's name, for the line.
    cameras : sequence of CameraModel
        The path's cameras (their look-down angle decides).
    specs : sequence of str
        The assets' sources (dome and ring asset files are told apart by their metadata).
    head : str, optional
        The line's start (the command).

    Returns
    -------
    views : int or None
        Ring views, or None for dome views.
    said : str
        The line saying what was chosen and why; empty when ``views`` was given.

    Raises
    ------
    UsageError
        Dome asset files with ring files, or with ``views`` K.
    """
    from ..billboard.formats.domefile import is_dome_file  # lazy: checking arguments imports no wing
    from ..billboard.frames.paths import look_down_deg
    from ..billboard.ring import ViewRing

    v = views
    files = [sp for sp in specs if sp.lower().endswith(".npz")]
    domes = [sp for sp in files if is_dome_file(sp)]
    if domes and (len(domes) < len(files) or (v is not None and v != "dome")):
        rings = [sp for sp in files if sp not in domes]
        got = f"dome {', '.join(domes)}" + (f" with ring {', '.join(rings)}" if rings
                                            else f" with --views {v}")
        raise UsageError(expected_got("--asset files", "assets of one kind: dome files (relightable) or "
                                      "ring files (--views K)", got))
    if v is not None:
        return (None if v == "dome" else int(v)), ""
    if domes:
        return None, head + "dome views (the --asset files are dome assets)"
    if relit_by:
        return None, head + f"dome views ({relit_by} relights them: albedo, normals and depth)"
    ring = ViewRing(8)
    lo, hi = ring.band_deg
    top = float(look_down_deg(cameras).max()) if len(cameras) else 0.0
    if top <= hi:
        return 8, (head + f"a ring of 8 views (the {path} path's eye looks down by at most "
                   f"{top:.0f} degrees, inside the ring's band of {lo:g}-{hi:g}; --views dome for views "
                   "from any height)")
    if files:
        return 8, (head + f"a ring of 8 views: asset files load as they were baked (the {path} "
                   f"path's eye looks down by up to {top:.0f} degrees, above the ring's band of "
                   f"{lo:g}-{hi:g}: --views dome for dome asset files)")
    return None, (head + f"dome views (the {path} path's eye looks down by up to {top:.0f} degrees, "
                  f"above the ring's band of {lo:g}-{hi:g}, where a ring loses the shape from above; "
                  "--views K for a ring)")


def parse_size(text: str) -> tuple[int, int]:
    """``"WxH"`` (e.g. ``640x480``) as an image shape ``(H, W)``.

    Parameters
    ----------
    text : str
        Width and height in pixels joined by ``x`` (case-insensitive), e.g. ``"640x480"``.

    Returns
    -------
    tuple of (int, int)
        ``(H, W)``, each in 1..8190 (:data:`morphkit.tol.MAX_VIDEO_SIDE`: the frames make a
        video).

    Raises
    ------
    UsageError
        Not two positive integers joined by ``x`` (a :class:`~morphkit.errors.ValidationError`).
    """
    parts = str(text).lower().split("x")
    try:
        w, h = (int(v) for v in parts)
    except ValueError:
        w = h = 0
    hi = tol.MAX_VIDEO_SIDE
    if len(parts) != 2 or w < 1 or h < 1 or w > hi or h > hi:
        raise UsageError(expected_got("--size", f"WIDTHxHEIGHT, two integers in 1..{hi} (e.g. 640x480; "
                                      f"{hi}: the video's limit, tol.MAX_VIDEO_SIDE)", repr(text)))
    return h, w


def check_output_file(path: Path | None, what: str) -> None:
    """Refuse, before any work, an output file path that is a folder or lies under a file.

    Parameters
    ----------
    path : pathlib.Path or None
        The output file (None: nothing to check).
    what : str
        The option, for the message (``"--json"``).

    Raises
    ------
    UsageError
        ``path`` is a folder, or a parent of it is a file.
    """
    if path is None:
        return
    if path.is_dir():
        raise UsageError(expected_got(what, "a file path", f"the folder {path}"))
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise UsageError(expected_got(what, "a path under a folder", f"{path} (under the file "
                                              f"{parent})"))
            break


def same_file(a: Path, b: Path) -> bool:
    """``a`` and ``b`` name the same file (one path resolved, or one file by two names).

    Parameters
    ----------
    a, b : pathlib.Path
        The paths.

    Returns
    -------
    bool
        True for one file (False when either cannot be looked at).
    """
    try:
        if a.exists() and b.exists():
            return a.samefile(b)
        return a.resolve() == b.resolve()
    except OSError:
        return False
