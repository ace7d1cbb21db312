"""Billboards: classic, view-morphed and real meshes
=================================================

Write billboard comparison strips: classic | view-morphed | real meshes (the paper's Fig. 5).
Bakes the tree and the person (a ring of 8 views, 128^2), places 40 of them on
a checkered ground from a seed, and for five cameras of the paper's pan (its
Fig. 6) writes OUT/strip_<k>.png -- classic billboards | view-morphed
billboards | the real meshes rendered from the same camera -- and prints each
mode's mean per-billboard silhouette IoU and PSNR against the meshes.

The assets are baked here from morphkit's sample meshes in a 3-D colour checker
(``appearance="checker"``); bake your own mesh in its own look with
``morphkit.bake_asset(morphkit.load_mesh("model.glb"), renderer, name="model")``.

Usage::

    python samples/billboards.py [OUT] [--n 40] [--views 8] [--size 640x480] [--frames 5]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import morphkit
from morphkit.billboard import BAKE_AMBIENT, Backdrop, bake_lights
from morphkit.billboard.compare import compare_modes

ASSETS = ("tree", "person")


def size_arg(text: str) -> tuple[int, int]:
    """``"WxH"`` as an image shape ``(H, W)``."""
    w, _, h = text.lower().partition("x")
    try:
        return int(h), int(w)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxH (e.g. 640x480), got {text!r}") from None


def main() -> None:
    ap = argparse.ArgumentParser(description="billboard comparison strips (classic | morph | meshes)")
    ap.add_argument("out", nargs="?", default="billboard-samples")
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--views", type=int, default=8)
    ap.add_argument("--size", type=size_arg, default=(480, 640), help="frame size WxH")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--frames", type=int, default=5, help="cameras along the pan")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with morphkit.Renderer() as r:
        meshes = {nm: morphkit.sample_mesh(nm) for nm in ASSETS}
        assets = {nm: morphkit.bake_asset(mesh, r, name=nm, views=args.views, size=128, progress=True,
                                          appearance="checker") for nm, mesh in meshes.items()}
        items = {nm: assets[nm].items(mesh) for nm, mesh in meshes.items()}  # the real meshes, same look
        inst = morphkit.place_random(list(assets), args.n, np.random.default_rng(args.seed))
        scene = morphkit.BillboardScene(assets, inst, backdrop=Backdrop())
        truth = morphkit.MeshMode(r, items, bake_lights(), BAKE_AMBIENT, supersample=2)
        modes = {"classic": morphkit.ClassicMode(), "morph": morphkit.MorphMode()}
        half = float(np.abs(inst.xy).max())
        for k, cam in enumerate(morphkit.PanPath.over(half).cameras(args.frames, args.size)):
            cmp = compare_modes(scene, cam, modes, truth)
            path = morphkit.write_image(out / f"strip_{k}.png", cmp.strip)
            figs = "; ".join(f"{m}: IoU {e['iou']:.3f}, PSNR {e['psnr']:.1f} dB"
                             for m, e in cmp.errors.items())
            print(f"{path}: {len(cmp.frames['morph'].placements)} billboards; vs meshes {figs}")


if __name__ == "__main__":
    main()
