"""The real-mesh frame (LitMeshMode) from the one-draw G-buffer against the three-draw passes (#26).

Scene: the field of ``scripts/billboard_shadow_bench.py`` (N instances of the tree and the cow,
random yaws and scales, one camera over the field, sun at azimuth 30, elevation 35 degrees).
Timed, interleaved in one run (the order rotated each repetition), medians of ``--reps``:
``LitMeshMode.render`` with ``gbuffer=True`` (``Renderer.gbuffer_pass``: one flat draw into two
attachments) and ``gbuffer=False`` (``Renderer.passes``: lit colour, albedo, normals: three
draws), unshadowed and with ray-cast shadows (the truth frame); and the two pass calls alone.
Difference: mean and max |rgb| of the two frames, levels of 255, all pixels and channels.

Usage: ``PYTHONPATH=. python scripts/litmesh_gbuffer_bench.py [--n 20] [--size 640x480] [--reps 7]``
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from morphkit.billboard import Backdrop, BillboardScene, MeshMode, place_random
from morphkit.billboard.baking.bakelook import BAKE_AMBIENT
from morphkit.billboard.frames.facing import ViewpointFacing
from morphkit.camera import look_at, perspective
from morphkit.imaging.shading import Lighting
from morphkit.programs.fixtures import FIELD_MESHES, field_domes
from morphkit.render import Renderer, gl_info
from morphkit.sunlit.litmesh import LitMeshMode
from morphkit.sunlit.raycast import RayCastShadow
from morphkit.sunpath import sun


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--asset-size", type=int, default=64, help="the dome bakes (not drawn by LitMeshMode)")
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--seed", type=int, default=3)
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split("x"))
    names = list(FIELD_MESHES)
    with Renderer() as r:
        meshes, assets, items = field_domes(r, a.asset_size)
        inst = place_random(names, a.n, np.random.default_rng(a.seed), half_size=max(2.0, 0.6 * np.sqrt(a.n)))
        scene = BillboardScene(assets, inst, backdrop=Backdrop(), facing=ViewpointFacing())
        half = float(np.abs(inst.xy).max()) if len(inst) else 1.0
        eye = np.array([0.0, -half - 2.0, 1.6])
        cam = perspective(np.radians(50.0), (h, w), look_at(eye, np.array([0.0, 0.0, 0.3]),
                                                            up=np.array([0.0, 0.0, 1.0])))
        lighting = Lighting(BAKE_AMBIENT, (sun(30.0, 35.0),))
        truth = RayCastShadow(meshes)
        posed = MeshMode(r, items).items(scene, scene.plan(cam).visible)
        faces = sum(len(it.mesh.faces) for it in posed)
        info = gl_info()
        print(f"{a.n} instances of tree + cow ({len(posed)} items drawn, {faces} faces), {w}x{h}, "
              f"{info['platform']}: {info['renderer']}")
        cases = {
            "gbuffer_pass": lambda: r.gbuffer_pass(cam, posed),
            "passes": lambda: r.passes(cam, posed, ()),
        }
        for shadow in (None, truth):
            tag = "ray-cast shadow" if shadow is not None else "no shadow"
            for g in (True, False):
                mode = LitMeshMode(r, items, lighting, shadow=shadow, gbuffer=g)
                cases[f"LitMeshMode {tag}, gbuffer={g}"] = lambda m=mode: m.render(scene, cam)
        times: dict[str, list[float]] = {k: [] for k in cases}
        out: dict[str, object] = {}
        for k, fn in cases.items():  # warm: contexts, programs, framebuffers
            out[k] = fn()
        order = list(cases)
        for rep in range(a.reps):  # the order rotated each repetition: no case always follows another
            for k in order[rep % len(order):] + order[:rep % len(order)]:
                t0 = time.perf_counter()
                cases[k]()
                times[k].append(1e3 * (time.perf_counter() - t0))
        med = {k: statistics.median(v) for k, v in times.items()}
        print(f"| case | ms median of {a.reps} | vs the three-draw case |")
        print("|---|---|---|")
        pairs = [("gbuffer_pass", "passes")]
        pairs += [(f"LitMeshMode {t}, gbuffer=True", f"LitMeshMode {t}, gbuffer=False")
                  for t in ("no shadow", "ray-cast shadow")]
        for one, three in pairs:
            print(f"| {one} | {med[one]:.1f} | {med[one] / med[three]:.2f} |")
            print(f"| {three} | {med[three]:.1f} | 1.00 |")
        for t in ("no shadow", "ray-cast shadow"):
            d = np.abs(out[f"LitMeshMode {t}, gbuffer=True"].rgb.astype(np.int16)
                       - out[f"LitMeshMode {t}, gbuffer=False"].rgb.astype(np.int16))
            print(f"{t}: frame rgb |one draw - three draws| mean {d.mean():.4f} levels, max {d.max()}, "
                  f"{int((d > 0).any(axis=2).sum())} of {d.shape[0] * d.shape[1]} pixels differ")


if __name__ == "__main__":
    main()
