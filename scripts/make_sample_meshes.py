"""Rebuild the stored default-size implicit samples: ``morphkit/data/{cow,tree,person}_6000.npz``.

Run once (``python scripts/make_sample_meshes.py [--check]``). The files hold the
meshes that morphkit's samples had at their default size (6000 requested
triangles) when they were polygonised by the hand-written marching-tetrahedra
polygoniser below (morphkit <= 0.1.0, ``morphkit/meshes.py``): every stored
reference image (tests/reference) and measured figure (docs/RESULTS.md) was
made with them. The package now reads these files at the default size and
polygonises other sizes with scikit-image's marching cubes
(:func:`morphkit.meshes.implicit.polygonise`), which gives the same shapes
but not the same triangles. ``--check`` compares the files with a rebuild
instead of writing them.

The implicit fields and boxes are the package's
(:data:`morphkit.meshes.implicit.SHAPES`); the densities below are the marching
tetrahedra's first guesses of the grid spacing (they pick the grid, so they are
part of the result).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import trimesh

from morphkit.meshes import normalize
from morphkit.meshes.implicit import SHAPES, ImplicitShape, person_field, project
from morphkit.meshes.samples import STORED_FACES

DATA = Path(__file__).resolve().parent.parent / "morphkit" / "data"
#: Triangles times grid spacing squared of the marching tetrahedra, per shape.
MT_DENSITY = {"cow": 72.0, "tree": 89.0, "person": 16.6}


def _tet_table() -> list[list[tuple[tuple[int, int], ...]]]:
    """Triangles (as tet edges) of the iso-surface in a tetrahedron, per inside-bit case."""
    table: list[list[tuple[tuple[int, int], ...]]] = []
    for case in range(16):
        ins = [i for i in range(4) if case >> i & 1]
        out = [i for i in range(4) if not case >> i & 1]
        if len(ins) == 1:
            tris = [tuple((ins[0], o) for o in out)]
        elif len(ins) == 3:
            tris = [tuple((out[0], i) for i in ins)]
        elif len(ins) == 2:
            e0, e1 = (ins[0], out[0]), (ins[0], out[1])
            e2, e3 = (ins[1], out[1]), (ins[1], out[0])
            tris = [(e0, e1, e2), (e0, e2, e3)]
        else:
            tris = []
        table.append(tris)
    return table


_TET_TABLE = _tet_table()

#: Kuhn (Freudenthal) split of a cube into 6 tetrahedra along its main diagonal;
#: corners are numbered ``dx + 2 dy + 4 dz``. The split is conforming between
#: neighbouring cubes, so the extracted surface is closed.
_KUHN_TETS = np.array(
    [[0, 1 << a, (1 << a) | (1 << b), 7] for a, b in ((0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1))]
)


def _marching_tetrahedra(
    field: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray, h: float
) -> tuple[np.ndarray, np.ndarray]:
    """Polygonise ``field < 0`` on a grid of spacing ``h`` over ``[lo, hi]``.

    Returns ``(vertices, faces)`` of a closed, consistently outward-wound
    triangle mesh (the field must be positive on the box boundary).
    """
    shape = np.maximum(2, np.ceil((hi - lo) / h).astype(int) + 1)
    axes = [lo[k] + h * np.arange(shape[k]) for k in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    f = field(pts.reshape(-1, 3))
    # Keep grid values off zero so every sign-changing edge has a proper crossing.
    eps = 1e-9 * h
    f = np.where(np.abs(f) < eps, eps, f)
    inside = (f < 0).reshape(shape)
    if inside[0].any() or inside[-1].any() or inside[:, 0].any() or inside[:, -1].any() \
            or inside[:, :, 0].any() or inside[:, :, -1].any():
        raise SystemExit("the implicit surface is clipped by its sampling box")
    nx, ny, nz = (int(s) for s in shape)
    n_inside = np.zeros((nx - 1, ny - 1, nz - 1), dtype=np.int8)
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                n_inside += inside[dx : nx - 1 + dx, dy : ny - 1 + dy, dz : nz - 1 + dz]
    ci, cj, ck = np.nonzero((n_inside > 0) & (n_inside < 8))
    base = (ci * ny + cj) * nz + ck
    corner_off = np.array([dx * ny * nz + dy * nz + dz for dz in (0, 1) for dy in (0, 1) for dx in (0, 1)])
    corners = base[:, None] + corner_off[None, :]  # (M, 8) global grid ids
    ins_flat = inside.ravel()
    keys: list[np.ndarray] = []
    refs: list[np.ndarray] = []
    n_total = nx * ny * nz
    for tet in _KUHN_TETS:
        ids = corners[:, tet]  # (M, 4)
        bits = ins_flat[ids].astype(np.int64)
        case = bits[:, 0] | bits[:, 1] << 1 | bits[:, 2] << 2 | bits[:, 3] << 3
        for c in range(1, 15):
            sel = ids[case == c]
            if len(sel) == 0:
                continue
            inside_local = np.array([c >> i & 1 for i in range(4)], dtype=bool)
            for tri in _TET_TABLE[c]:
                k = np.empty((len(sel), 3), dtype=np.int64)
                for m, (va, vb) in enumerate(tri):
                    ga, gb = sel[:, va], sel[:, vb]
                    k[:, m] = np.minimum(ga, gb) * n_total + np.maximum(ga, gb)
                keys.append(k)
                # Reference direction inside -> outside (orientation of the triangle).
                refs.append(
                    pts.reshape(-1, 3)[sel[:, ~inside_local]].mean(axis=1)
                    - pts.reshape(-1, 3)[sel[:, inside_local]].mean(axis=1)
                )
    all_keys = np.concatenate(keys)
    ref = np.concatenate(refs)
    uniq, faces = np.unique(all_keys, return_inverse=True)
    faces = faces.reshape(-1, 3)
    ga, gb = uniq // n_total, uniq % n_total
    fa, fb = f[ga], f[gb]
    pa, pb = pts.reshape(-1, 3)[ga], pts.reshape(-1, 3)[gb]
    verts = pa + (fa / (fa - fb))[:, None] * (pb - pa)
    tri = verts[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", normal, ref) < 0
    faces[flip] = faces[flip][:, ::-1]
    return verts, faces


def build(shape: ImplicitShape, density: float, target: int) -> trimesh.Trimesh:
    """The old pipeline at ``target`` <= 40k triangles: MT, Taubin, projection, normalisation."""
    lo, hi = np.asarray(shape.lo, dtype=np.float64), np.asarray(shape.hi, dtype=np.float64)
    h = math.sqrt(density / target)
    verts, faces = _marching_tetrahedra(shape.field, lo, hi, h)
    for _ in range(3):
        if abs(len(faces) / target - 1.0) < 0.08:
            break
        h *= math.sqrt(len(faces) / target)
        verts, faces = _marching_tetrahedra(shape.field, lo, hi, h)
    mesh = trimesh.Trimesh(verts, faces, process=False)
    trimesh.smoothing.filter_taubin(mesh, iterations=40)  # relax MT slivers
    mesh.vertices = project(shape.field, np.asarray(mesh.vertices))
    return normalize(mesh)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="compare with the files instead of writing them")
    args = ap.parse_args()
    bad = 0
    for name, shape in SHAPES.items():
        if name == "person":  # the arms' shoulder joints came later (thin rods, for fine grids)
            shape = ImplicitShape(lambda p: person_field(p, shoulder_joints=False), shape.lo, shape.hi,
                                  shape.density)
        mesh = build(shape, MT_DENSITY[name], STORED_FACES)
        path = DATA / f"{name}_{STORED_FACES}.npz"
        faces = np.asarray(mesh.faces)
        assert faces.max() < 2**16
        if args.check:
            with np.load(path) as old:
                same = np.array_equal(old["vertices"], mesh.vertices) and np.array_equal(old["faces"], faces)
            print(f"{path.name}: {'same' if same else 'DIFFERENT'}")
            bad += not same
        else:
            np.savez_compressed(path, vertices=np.asarray(mesh.vertices, dtype=np.float64),
                                faces=faces.astype(np.uint16))
            size = path.stat().st_size
            print(f"{path.name}: {len(mesh.vertices)} vertices, {len(faces)} faces, {size} bytes")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
