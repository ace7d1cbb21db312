#!/usr/bin/env python3
"""Octahedral impostor figures for #25 (until ``morphkit bench billboards`` has impostor rows).

Usage: ``python scripts/impostor_bench.py [--frames 12] [--sizes 64 96] [--meshes cow tree]``

Per mesh and frame size: bake time (median of ``--repeats`` bakes), ``memory_bytes``, ms per
``surface()`` call at level 0 (median over 60 directions, textures decoded: warm; and the first
call per frame: cold), and against the mesh rendered by the direction's perspective camera
(:meth:`DomeCameras.camera`, the quad's image; 12 random directions per elevation band, the same
for every row): silhouette IoU, albedo PSNR and normal error (:func:`metrics`), for the
engines' one parallax step and a 16-sample ray march (perspective rays), and one step with
orthographic rays.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from morphkit.billboard.baking.bakelook import bake_items
from morphkit.billboard.impostor import bake_impostor
from morphkit.meshes import normalize, sample_mesh
from morphkit.passes import RenderPasses
from morphkit.render import Renderer
from morphkit.views.domecameras import DomeCameras
from morphkit.views.gbuffer import ViewSurface, linear_to_srgb

BANDS = ((0.0, 20.0), (20.0, 40.0), (40.0, 60.0), (60.0, 80.0), (80.0, 90.0))


def metrics(s: ViewSurface, truth: RenderPasses) -> tuple[float, float, float]:
    """Soft IoU of the coverage; PSNR (dB, peak 1) of the premultiplied sRGB-encoded albedo over
    the image; mean angle (degrees) between normals where both cover more than half a pixel."""
    a, t = s.alpha, truth.alpha
    iou = float(np.minimum(a, t).sum() / max(np.maximum(a, t).sum(), 1e-9))
    straight = s.albedo[..., :3] / np.maximum(a, 1e-6)[..., None]
    mine = linear_to_srgb(straight) * a[..., None]
    ref = truth.albedo.astype(np.float32) / 255.0 * t[..., None]
    mse = float(np.mean((mine - ref) ** 2))
    psnr = 10.0 * np.log10(1.0 / max(mse, 1e-12))
    both = (a > 0.5) & (t > 0.5)
    cos = np.clip(np.einsum("ijk,ijk->ij", s.normal, truth.normal)[both], -1.0, 1.0)
    return iou, psnr, float(np.degrees(np.arccos(cos)).mean()) if both.any() else float("nan")


def main() -> None:
    """Run the figures and print them."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 96])
    ap.add_argument("--meshes", nargs="+", default=["cow", "tree"])
    ap.add_argument("--repeats", type=int, default=2)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    with Renderer() as r:
        for name in args.meshes:
            mesh = sample_mesh(name)
            norm = normalize(mesh)
            for size in args.sizes:
                times = []
                for _ in range(args.repeats):
                    t0 = time.perf_counter()
                    imp = bake_impostor(mesh, r, name=name, frames=args.frames, frame_size=size)
                    times.append(time.perf_counter() - t0)
                dirs = [(float(rng.uniform(0, 360)), float(np.degrees(np.arcsin(rng.uniform(0, 1)))))
                        for _ in range(60)]
                cold = []
                for a, e in dirs[:10]:
                    t0 = time.perf_counter()
                    imp.surface(a, e)
                    cold.append(time.perf_counter() - t0)
                for a, e in dirs:  # decode every frame these directions use
                    imp.surface(a, e)
                warm = []
                for a, e in dirs:
                    t0 = time.perf_counter()
                    imp.surface(a, e)
                    warm.append(time.perf_counter() - t0)
                print(f"{name} frames={args.frames} m={size}: bake {np.median(times):.2f} s "
                      f"(runs {', '.join(f'{t:.2f}' for t in times)}), memory {imp.memory_bytes} B, "
                      f"surface() warm {1e3 * np.median(warm):.2f} ms, "
                      f"first calls {1e3 * np.median(cold):.2f} ms")
                cams = DomeCameras.fit(norm, size)
                items = bake_items(norm)
                configs = (("perspective", 1), ("perspective", 16), ("orthographic", 1))
                rows: dict[tuple[str, int], list[str]] = {c: [] for c in configs}
                for lo, hi in BANDS:
                    views = [(float(rng.uniform(0, 360)), float(rng.uniform(lo, hi))) for _ in range(12)]
                    truths = [r.source_passes(cams.camera(a, e), items, []) for a, e in views]
                    for projection, samples in configs:
                        imp.parallax_samples, imp.projection = samples, projection
                        vals = np.array([metrics(imp.surface(a, e), t)
                                         for (a, e), t in zip(views, truths, strict=True)])
                        rows[(projection, samples)].append(
                            f"{lo:.0f}-{hi:.0f}: IoU {vals[:, 0].mean():.3f} / {vals[:, 1].mean():.1f} dB / "
                            f"{vals[:, 2].mean():.1f} deg")
                for (projection, samples), row in rows.items():
                    print(f"  {projection} rays, parallax_samples={samples}: " + "; ".join(row))


if __name__ == "__main__":
    main()
