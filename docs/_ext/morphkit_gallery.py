"""sphinx-gallery hooks: run each sample script headless into a folder, show the PNGs it wrote.

The samples are command-line scripts (``python samples/x.py OUT [options]``) that write image
files; they stay that way. At the docs build sphinx-gallery runs each one with
``sys.argv = [script, OUT, *GALLERY_ARGS[script]]`` (:func:`reset_argv`), where ``OUT`` is a
folder under ``docs/_build/gallery-out/`` and the options pick sizes small enough for a build of
a few minutes on two cores; :class:`WrittenImages` then moves the images the script wrote into
the gallery (the files matching ``SHOW[script]``, by default every PNG). A new sample needs no
entry here unless it is slow at its default sizes or writes images that should not be shown.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path
from typing import Any

#: Command-line options per sample at the docs build (after the output folder).
GALLERY_ARGS: dict[str, list[str]] = {
    "ground_truth_shadows.py": ["--size", "256"],
    "warped_shadows.py": ["--size", "256", "--positions", "1"],
    "soft_shadows.py": ["--size", "192", "--ground", "192", "--dense", "8"],
    "viewmorph_pairs.py": ["--size", "192", "--baselines", "20"],
    "billboards.py": ["--n", "20", "--size", "320x240", "--frames", "2"],
}

#: Glob patterns (relative to the output folder) of the images shown per sample, in this order
#: (each pattern's files sorted by name, numbers by value); default: every PNG.
SHOW: dict[str, list[str]] = {
    "warped_shadows.py": ["*_warped_reprojected_direct_raycast.png", "*_lightmap_*.png"],
    "viewmorph_pairs.py": ["*/strip.png"],
}

OUT_ROOT = Path(__file__).resolve().parents[1] / "_build" / "gallery-out"


def _natural(path: Path) -> list[Any]:
    """Sort key that orders ``soft5`` before ``soft16``."""
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", path.as_posix())]


def out_dir(src_file: str) -> Path:
    """The folder a sample writes into at the docs build (emptied before it runs)."""
    return OUT_ROOT / Path(src_file).stem


def reset_argv(gallery_conf: dict[str, Any], script_vars: dict[str, Any]) -> list[str]:
    """``sys.argv[1:]`` for a sample: its output folder (made empty) and its gallery options."""
    out = out_dir(script_vars["src_file"])
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    return [str(out), *GALLERY_ARGS.get(Path(script_vars["src_file"]).name, [])]


class WrittenImages:
    """Image scraper: after each code block, move the new images the sample wrote into the gallery."""

    def __repr__(self) -> str:
        return "WrittenImages"

    def __call__(self, block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
        src = Path(block_vars["src_file"])
        out = out_dir(str(src))
        if not out.is_dir():
            return ""
        found = list(dict.fromkeys(p for pattern in SHOW.get(src.name, ["**/*.png"])
                                   for p in sorted(out.glob(pattern), key=_natural)))
        rst = []
        for png, dest in zip(found, block_vars["image_path_iterator"], strict=False):  # iterator: endless
            shutil.move(png, dest)
            rel = Path(dest).relative_to(gallery_conf["src_dir"]).as_posix()
            name = png.relative_to(out).as_posix()
            rst += [f".. figure:: /{rel}", f"   :alt: {name}", "   :class: sphx-glr-single-img", "",
                    f"   ``{name}``", ""]
        return "\n".join(["", *rst]) if rst else ""


#: The scraper instance named in ``sphinx_gallery_conf["image_scrapers"]``.
written_images = WrittenImages()
