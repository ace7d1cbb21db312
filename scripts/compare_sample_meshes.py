"""Compare today's sample meshes with those of an earlier morphkit (a reference ``.npz``).

    git archive <commit> morphkit | tar -x -C /tmp/old
    (cd /tmp/old && python /path/to/scripts/compare_sample_meshes.py --save /tmp/old_meshes.npz)
    python scripts/compare_sample_meshes.py /tmp/old_meshes.npz

For each sample and size: triangle and vertex counts, volume, bounds, whether the
arrays are identical, and the symmetric surface distance (Hausdorff-like: the
largest and mean distance of 20k surface samples of each mesh to the other,
``trimesh.proximity``), in units of the normalised size (1.0).
"""

from __future__ import annotations

import argparse

import numpy as np
import trimesh

from morphkit.meshes import sample_mesh

CASES = [("teapot", {}), ("teapot", {"resolution": 4}), ("chair", {}), ("chair", {"slats": 5}),
         ("cow", {}), ("tree", {}), ("person", {}), ("cow", {"faces": 50000}), ("tree", {"faces": 50000}),
         ("person", {"faces": 50000}), ("cow", {"faces": 300000})]


def _key(name: str, kw: dict) -> str:
    return name + "_" + "_".join(f"{k}{v}" for k, v in kw.items())


def _distance(a: trimesh.Trimesh, b: trimesh.Trimesh, n: int = 20000) -> tuple[float, float]:
    pa = trimesh.sample.sample_surface(a, n, seed=1)[0]
    pb = trimesh.sample.sample_surface(b, n, seed=2)[0]
    d1 = np.abs(trimesh.proximity.closest_point(b, pa)[1])
    d2 = np.abs(trimesh.proximity.closest_point(a, pb)[1])
    return float(max(d1.max(), d2.max())), float((d1.mean() + d2.mean()) / 2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference", nargs="?", help="the reference .npz to compare with")
    ap.add_argument("--save", help="write this morphkit's meshes to this .npz instead")
    args = ap.parse_args()
    if args.save:
        out = {}
        for name, kw in CASES:
            m = sample_mesh(name, **kw)
            out[_key(name, kw) + "_v"], out[_key(name, kw) + "_f"] = m.vertices, m.faces
        np.savez(args.save, **out)
        return
    ref = np.load(args.reference)
    for name, kw in CASES:
        new = sample_mesh(name, **kw)
        k = _key(name, kw)
        old = trimesh.Trimesh(ref[k + "_v"], ref[k + "_f"], process=False)
        same = (old.vertices.shape == new.vertices.shape and np.array_equal(old.vertices, new.vertices)
                and np.array_equal(old.faces, new.faces))
        hd, mean = (0.0, 0.0) if same else _distance(old, new)
        print(f"{k:22s} identical={same!s:5s} faces {len(old.faces):7d} -> {len(new.faces):7d}  "
              f"verts {len(old.vertices):7d} -> {len(new.vertices):7d}  volume {old.volume:.5f} -> "
              f"{new.volume:.5f}  bounds max diff {np.abs(old.bounds - new.bounds).max():.1e}  "
              f"distance max {hd:.1e} mean {mean:.1e}")


if __name__ == "__main__":
    main()
