"""Tests of morphkit.meshes: sample meshes, normalisation and loading."""

from __future__ import annotations

import time
from importlib import resources
from pathlib import Path

import cv2
import numpy as np
import pytest
import trimesh
from scipy import ndimage

from morphkit.errors import MeshError, ValidationError
from morphkit.meshes import (
    BILLBOARD_MESHES,
    SAMPLE_MESHES,
    chair,
    check_mesh,
    cow,
    implicit,
    load_mesh,
    normalize,
    person,
    sample_mesh,
    samples,
    teapot,
    teapot_face_count,
    tree,
)


def assert_normalised(m: trimesh.Trimesh) -> None:
    lo, hi = m.bounds
    assert np.max(hi - lo) == pytest.approx(1.0, abs=1e-9)
    assert lo[2] == pytest.approx(0.0, abs=1e-12)
    assert (lo[0] + hi[0]) / 2 == pytest.approx(0.0, abs=1e-12)
    assert (lo[1] + hi[1]) / 2 == pytest.approx(0.0, abs=1e-12)
    assert np.all(np.isfinite(m.vertices))


def outward_fraction(m: trimesh.Trimesh, seed: int = 0, n: int = 3000) -> float:
    """Fraction of first ray hits (rays from outside) whose face normal faces the ray."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    origins = m.bounds.mean(axis=0) + 3.0 * d
    dirs = -d + 0.15 * rng.normal(size=d.shape)
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    tri = m.ray.intersects_first(origins, dirs)
    hit = tri >= 0
    assert hit.sum() > n // 10
    dots = np.einsum("ij,ij->i", m.face_normals[tri[hit]], dirs[hit])
    return float(np.mean(dots < 0))


def slice_components(m: trimesh.Trimesh, z: float, step: float = 0.004) -> tuple[int, list, float]:
    """Label the inside of a closed mesh on the plane ``z``: (count, centroids, area).

    The inside is the mesh's cross-section (``Trimesh.section``) filled by the even-odd rule on
    a grid: deterministic (``Trimesh.contains`` casts rays whose direction for ambiguous points
    comes from numpy's global RNG, so its answer changed with the tests run before)."""
    xs = np.arange(-0.5, 0.5 + step, step)
    inside = np.zeros((len(xs), len(xs)), np.uint8)  # [i, j] at (xs[i], xs[j])
    sec = m.section(plane_origin=(0.0, 0.0, z), plane_normal=(0.0, 0.0, 1.0))
    for loop in ([] if sec is None else sec.discrete):
        ij = (np.asarray(loop)[:, :2] - xs[0]) / step  # (i, j) = (x index, y index)
        one = np.zeros_like(inside)
        cv2.fillPoly(one, [np.rint(ij[:, ::-1] * 16).astype(np.int32)], 1, lineType=cv2.LINE_8, shift=4)
        inside ^= one  # even-odd: a hole inside a loop is a loop inside a loop
    inside = inside.astype(bool)
    labels, count = ndimage.label(inside)
    cents = ndimage.center_of_mass(inside, labels, range(1, count + 1))
    cents = [(xs[0] + cx * step, xs[0] + cy * step) for cx, cy in cents]
    return count, cents, float(inside.sum() * step * step)


# --------------------------------------------------------------------------- teapot


def test_teapot_control_data_is_newells_and_symmetric():
    cp = samples._teapot_control_points()
    assert cp.shape == (32, 4, 4, 3)
    data = resources.files("morphkit") / "data"  # the package data, as installed
    with (data / "teapot_vertices.txt").open() as f:
        assert np.loadtxt(f).shape == (306, 3)
    with (data / "teapot_patches.txt").open() as f:
        patches = np.loadtxt(f, dtype=np.int64)
    assert patches.shape == (32, 16) and patches.min() == 1 and patches.max() == 306
    assert not cp.flags.writeable  # cached: callers cannot change the teapot
    rot = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1.0]])  # -90 deg about z
    # Rim, body and lid: 4 quadrant patches, each the previous rotated by -90 deg.
    for first in (0, 4, 8, 20, 24):
        for q in range(4):
            a, b = first + q, first + (q + 1) % 4
            np.testing.assert_array_equal(cp[a] @ rot.T, cp[b])
    # Bottom: the same, turning the other way.
    for q in range(4):
        np.testing.assert_array_equal(cp[28 + q] @ rot, cp[28 + (q + 1) % 4])
    # Handle and spout: the y > 0 patch mirrors the y < 0 one (u reversed).
    mirror = np.diag([1.0, -1.0, 1.0])
    for a in (12, 14, 16, 18):
        np.testing.assert_array_equal(cp[a] @ mirror, cp[a + 1][:, ::-1])
    # Known extremes of the data: spout tip 3.525, handle -3, lid knob 3.15, bottom 0.
    v = cp.reshape(-1, 3)
    np.testing.assert_allclose(v.min(0), [-3.0, -2.0, 0.0])
    np.testing.assert_allclose(v.max(0), [3.525, 2.0, 3.15])


@pytest.mark.parametrize("res, expected", [(4, 992), (6, 2256), (8, 4032), (10, 6320)])
def test_teapot_face_counts(res, expected):
    m = teapot(res, flange=False)
    assert len(m.faces) == expected == teapot_face_count(res, flange=False)
    flanged = teapot(res)
    assert len(flanged.faces) == expected + 32 * res == teapot_face_count(res)
    assert 900 <= len(flanged.faces) <= 7000


def test_teapot_flange_closes_the_lid_gap():
    """Vertical rays through the ring between lid (r = 1.3) and rim (r = 1.4,
    data units) pass through Newell's surface but hit the flanged teapot."""
    bare, closed = teapot(8, flange=False), teapot(8)
    # the gap ring's centre in normalised units: data radius 1.35 about the body axis
    s = 1.0 / 6.525  # data x extent -3.0 .. 3.525
    axis_x = -(3.525 - 3.0) / 2 * s
    ang = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    o = np.c_[axis_x + 1.35 * s * np.cos(ang), 1.35 * s * np.sin(ang), np.full(64, 2.0)]
    d = np.tile([0.0, 0.0, -1.0], (64, 1))
    # through the gap a ray still meets the body's bottom from inside: count hits above it
    def first_hit_z(m):
        loc, idx, _ = m.ray.intersects_location(o, d, multiple_hits=False)
        z = np.full(64, -1.0)
        z[idx] = loc[:, 2]
        return z
    rim_z = 2.4 / 3.15 * 0.49
    assert np.mean(first_hit_z(bare) < 0.1) > 0.5  # most reach the bottom through the gap
    assert np.all(first_hit_z(closed) > rim_z - 0.01)


def test_teapot_is_clean_and_upright():
    m = teapot(flange=False)
    assert len(m.faces) == 4032
    assert_normalised(m)
    assert np.all(m.nondegenerate_faces())
    assert m.is_winding_consistent
    # Seams merged: body+rim+bottom, lid, handle and spout are 4 pieces.
    assert len(m.split(only_watertight=False)) == 4
    np.testing.assert_allclose(m.extents, [1.0, 0.622, 0.490], atol=0.005)
    v = m.vertices
    height = m.extents[2]
    tip = v[np.argmax(v[:, 0])]  # spout tip: +x, high up
    assert tip[0] > 0.45 and tip[2] > 0.7 * height
    back = v[np.argmin(v[:, 0])]  # handle: -x, mid height
    assert back[0] < -0.45 and 0.3 * height < back[2] < 0.8 * height
    knob = v[np.argmax(v[:, 2])]  # lid knob on the axis, at the top
    assert np.hypot(knob[0], knob[1]) < 0.05
    assert abs(np.mean(v[:, 1])) < 1e-6  # symmetric about the xz plane


def test_teapot_normals_point_outwards():
    m = teapot(6)
    assert outward_fraction(m) > 0.95
    flipped = trimesh.Trimesh(m.vertices, m.faces[:, ::-1], process=False)
    assert outward_fraction(flipped) < 0.05


def test_teapot_rejects_bad_resolution():
    for bad in (1, 65, 2.5, "8", True):
        with pytest.raises(ValidationError, match=r"resolution: expected an integer in \[2, 64\]"):
            teapot(bad)
    np.testing.assert_array_equal(teapot(8.0).vertices, teapot(8).vertices)  # an integral float is 8
    with pytest.raises(ValidationError, match="flange: expected a bool"):
        teapot(8, flange=1)


# --------------------------------------------------------------------------- chair


def test_chair_counts_and_normalisation():
    m = chair()
    assert 1300 <= len(m.faces) <= 1700
    assert_normalised(m)
    assert m.is_watertight and m.is_winding_consistent  # closed boxes, concatenated
    assert m.extents[2] == pytest.approx(1.0)  # standing: the back is the tallest extent


def test_chair_stands_on_four_legs():
    m = chair()
    count, cents, area = slice_components(m, 0.02)
    assert count == 4
    xs = sorted(c[0] for c in cents)
    assert xs[0] < -0.15 and xs[-1] > 0.15


@pytest.mark.parametrize("n", [1, 3, 5])
def test_chair_back_has_open_gaps_between_slats(n):
    m = chair(n)
    lo, hi = m.bounds
    seat_top = 0.47 / 0.95  # seat top / total height before normalisation
    rail = 0.87 / 0.95
    ys = np.linspace(lo[1] + 1e-3, hi[1] - 1e-3, 800)
    for zf in (0.3, 0.5, 0.7):
        z = seat_top + zf * (rail - seat_top)
        origins = np.stack([np.full_like(ys, lo[0] - 1.0), ys, np.full_like(ys, z)], axis=1)
        dirs = np.tile([1.0, 0.0, 0.0], (len(ys), 1))
        hit = m.ray.intersects_any(origins, dirs)
        # post, gap, slat, gap, ..., slat, gap, post: n + 1 runs of misses inside.
        runs = np.flatnonzero(np.diff(hit.astype(int)) != 0)
        assert hit[0] and hit[-1]
        assert len(runs) == 2 * (n + 1)
        gaps = np.count_nonzero(~hit) * (ys[1] - ys[0])
        assert gaps > 0.15  # at least 15% of the width lets light through
    # Control: at seat height and through the top rail nothing gets through.
    for z in (0.45 / 0.95, 0.91 / 0.95):
        origins = np.stack([np.full_like(ys, lo[0] - 1.0), ys, np.full_like(ys, z)], axis=1)
        assert m.ray.intersects_any(origins, np.tile([1.0, 0.0, 0.0], (len(ys), 1))).all()


def test_chair_rejects_bad_slats():
    with pytest.raises(ValidationError, match="slats"):
        chair(0)


# --------------------------------------------------------------------------- cow


@pytest.mark.parametrize("faces", [6000, 50_000])
def test_cow_face_count_and_watertight(faces):
    m = cow(faces)
    assert abs(len(m.faces) / faces - 1) < 0.3
    assert m.is_watertight and m.is_winding_consistent
    assert m.body_count == 1
    assert m.volume > 0  # outward normals
    assert np.all(m.nondegenerate_faces())
    assert_normalised(m)


def test_cow_is_deterministic_and_cached_as_copies():
    a = cow(6000)
    a.vertices[:] = 0.0  # must not poison the cache
    b = cow(6000)
    samples.clear_cache()
    c = cow(6000)
    assert np.ptp(b.vertices) > 0
    np.testing.assert_array_equal(b.vertices, c.vertices)
    np.testing.assert_array_equal(b.faces, c.faces)


def test_cow_stands_on_four_legs_facing_plus_x():
    m = cow(6000)
    count, cents, area = slice_components(m, 0.03)
    assert count == 4
    assert sum(c[0] > 0 for c in cents) == 2 and sum(c[1] > 0 for c in cents) == 2
    _, _, body_area = slice_components(m, 0.45)
    assert area < 0.15 * body_area  # legs are thin compared with the body
    top = m.vertices[np.argmax(m.vertices[:, 2])]
    assert top[0] > 0.2  # the head (ears) is the highest part, at +x
    assert m.extents[0] == pytest.approx(1.0)  # long axis is x


def test_cow_shape_is_stable_across_resolutions():
    small, large = cow(6000), cow(50_000)
    np.testing.assert_allclose(small.extents, large.extents, atol=0.01)
    assert small.volume == pytest.approx(large.volume, rel=0.03)


@pytest.mark.slow
def test_cow_one_million_faces():
    samples.clear_cache()
    t0 = time.perf_counter()
    m = cow(1_000_000)
    assert time.perf_counter() - t0 < 20.0
    assert abs(len(m.faces) / 1_000_000 - 1) < 0.3
    assert m.is_watertight
    samples.clear_cache()


def test_cow_rejects_bad_counts():
    for bad in (100, 5_000_000, 6000.5, "6000", True):
        with pytest.raises(ValidationError, match=r"faces: expected an integer in \[4000, 4000000\]"):
            cow(bad)
    assert len(cow(6000.0).faces) == len(cow(6000).faces)  # an integral float is the count


# --------------------------------------------------------------------------- stored and polygonised


@pytest.mark.parametrize("name", ["cow", "tree", "person"])
def test_stored_default_samples_are_the_shapes_marching_cubes_polygonises(name):
    """The default-size samples are package data (the marching-tetrahedra meshes every reference
    was made with); other sizes are polygonised by marching cubes: the same shape within the
    polygonisations' difference. Measured at 6000 requested faces: extents within 0.0093, volume
    within 3.3% (the tree's sharp cone rims), mean surface distance 1.1e-3 to 3.8e-3."""
    stored = samples.sample_mesh(name)
    assert len(stored.faces) == {"cow": 5740, "tree": 5976, "person": 5640}[name]
    assert stored.is_watertight and stored.volume > 0
    assert_normalised(stored)
    made = implicit.polygonise(implicit.SHAPES[name], samples.STORED_FACES)
    assert made.is_watertight and made.is_winding_consistent and made.volume > 0  # outward normals
    assert abs(len(made.faces) / samples.STORED_FACES - 1) < 0.1
    assert_normalised(made)
    np.testing.assert_allclose(made.extents, stored.extents, atol=0.015)
    assert made.volume == pytest.approx(stored.volume, rel=0.05)
    pts = trimesh.sample.sample_surface(made, 2000, seed=0)[0]
    assert np.abs(trimesh.proximity.closest_point(stored, pts)[1]).mean() < 0.006


def test_polygonise_refuses_a_shape_clipped_by_its_box():
    cow_shape = implicit.SHAPES["cow"]
    clipped = implicit.ImplicitShape(cow_shape.field, cow_shape.lo, (1.0, 0.65, 2.0), cow_shape.density)
    with pytest.raises(MeshError, match="implicit surface: expected inside the sampling box"):
        implicit.polygonise(clipped, 5000)


# --------------------------------------------------------------------------- tree and person


@pytest.mark.parametrize("builder", [tree, person])
@pytest.mark.parametrize("faces", [6000, 50_000])
def test_tree_and_person_face_count_and_watertight(builder, faces):
    m = builder(faces)
    assert abs(len(m.faces) / faces - 1) < 0.1
    assert m.is_watertight and m.is_winding_consistent
    assert m.body_count == 1
    assert m.volume > 0  # outward normals
    assert np.all(m.nondegenerate_faces())
    assert_normalised(m)
    assert m.extents[2] == pytest.approx(1.0)  # upright: the height is the largest extent


@pytest.mark.parametrize("builder", [tree, person])
def test_tree_and_person_are_deterministic_and_cached_as_copies(builder):
    a = builder(6000)
    a.vertices[:] = 0.0  # must not poison the cache
    b = builder(6000)
    samples.clear_cache()
    c = builder(6000)
    assert np.ptp(b.vertices) > 0
    np.testing.assert_array_equal(b.vertices, c.vertices)
    np.testing.assert_array_equal(b.faces, c.faces)


def test_tree_is_non_convex_with_overhanging_layers_and_a_branch_to_plus_x():
    m = tree()
    assert m.volume < 0.75 * m.convex_hull.volume
    count, cents, trunk_area = slice_components(m, 0.05)  # below the branch and the foliage: the trunk
    assert count == 1 and np.hypot(*cents[0]) < 0.05
    # the second foliage layer's base (1.3 of 2.98 m: z = 0.436) overhangs the first layer's top:
    # the cross-section grows going up through it (radius 0.47 m -> 0.63 m of the two cones)
    _, _, below = slice_components(m, 0.41)
    _, _, above = slice_components(m, 0.45)
    assert above > 1.3 * below
    assert trunk_area < 0.05 * below
    tip = m.vertices[np.argmax(m.vertices[:, 0])]
    assert tip[2] < 0.3  # the farthest point towards +x is the low branch's blob


def test_person_walks_towards_plus_x_with_limbs_clear_of_the_torso():
    m = person()
    assert m.volume < 0.4 * m.convex_hull.volume
    count, cents, _ = slice_components(m, 0.1)  # the two shins, in stride
    assert count == 2
    front, back = sorted(cents, key=lambda c: -c[0])
    assert front[0] > 0.03 and front[1] > 0  # left (+y) leg forward
    assert back[0] < -0.03 and back[1] < 0
    count, cents, _ = slice_components(m, 0.62)  # torso and two hanging arms, separate
    assert count == 3
    right, torso, left = sorted(cents, key=lambda c: c[1])
    assert abs(torso[1]) < 0.03 and right[1] < -0.12 and left[1] > 0.12
    assert right[0] > 0.03 and left[0] < -0.03  # arms swing opposite to the legs


def test_tree_and_person_reject_bad_counts():
    for builder in (tree, person):
        for bad in (100, 5_000_000, 6000.5):
            with pytest.raises(ValidationError, match="faces: expected an integer in"):
                builder(bad)


# --------------------------------------------------------------------------- normalize


def test_normalize_scales_centres_and_grounds():
    box = trimesh.creation.box(extents=[2.0, 4.0, 1.0])
    box.apply_translation([5.0, -3.0, 7.0])
    before = box.vertices.copy()
    m = normalize(box)
    assert_normalised(m)
    np.testing.assert_allclose(m.extents, [0.5, 1.0, 0.25])
    np.testing.assert_array_equal(box.vertices, before)  # input untouched


def test_normalize_rejects_bad_meshes():
    with pytest.raises(MeshError, match="expected a mesh with at least one face, got 0 faces"):
        normalize(trimesh.Trimesh())
    bad = trimesh.creation.box()
    bad.vertices[0] = np.nan
    with pytest.raises(MeshError, match="expected finite vertex coordinates"):
        normalize(bad)
    flat = trimesh.Trimesh(np.zeros((3, 3)), [[0, 1, 2]], process=False)
    with pytest.raises(MeshError, match="bounding box larger than"):
        normalize(flat)
    with pytest.raises(MeshError, match="expected a trimesh.Trimesh"):
        normalize("teapot")  # type: ignore[arg-type]


# --------------------------------------------------------------------------- check_mesh


def test_check_mesh_returns_good_meshes_unchanged():
    box = trimesh.creation.box()
    assert check_mesh(box, "m") is box
    flat = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], process=False)
    assert check_mesh(flat, "m") is flat  # a planar mesh (one zero extent) has area: fine


def _collinear() -> trimesh.Trimesh:
    """Six vertices on one line, four faces: zero area, a segment's bounding box."""
    v = np.c_[np.linspace(0, 1, 6), 2 * np.linspace(0, 1, 6), np.zeros(6)]
    return trimesh.Trimesh(v, [[0, 1, 2], [1, 2, 3], [2, 3, 4], [3, 4, 5]], process=False)


def _zero_area_faces() -> trimesh.Trimesh:
    """A 3-D bounding box, but every face is a needle (two coincident vertices)."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    return trimesh.Trimesh(v, [[0, 1, 1], [0, 2, 2], [0, 3, 3], [1, 2, 2]], process=False)


def _nan_mesh() -> trimesh.Trimesh:
    m = trimesh.creation.box()
    m.vertices[3] = [np.nan, 0, 0]
    return m


def _inf_mesh() -> trimesh.Trimesh:
    m = trimesh.creation.box()
    m.vertices[[1, 5]] = np.inf
    return m


@pytest.mark.parametrize("mesh, match", [
    ("teapot.obj", r"m: expected a trimesh.Trimesh, got str"),
    (trimesh.PointCloud(np.eye(3)), r"m: expected a trimesh.Trimesh, got PointCloud"),
    (trimesh.Trimesh(), r"m: expected a mesh with at least one face, got 0 faces"),
    (trimesh.Trimesh(np.eye(3), [[0, 1, 5]], process=False),
     r"m: expected face indices in \[0, 3\), got indices up to 5"),
    (_nan_mesh(), r"m: expected finite vertex coordinates, got 1 non-finite vertices"),
    (_inf_mesh(), r"m: expected finite vertex coordinates, got 2 non-finite vertices"),
    (trimesh.Trimesh(np.zeros((3, 3)), [[0, 1, 2]], process=False),
     r"m: expected a bounding box larger than 1e-09, got extent 0.0"),
    (_collinear(), r"m: expected a surface \(a bounding box with at most one zero extent\), "
                   r"got all vertices on one line"),
    (_zero_area_faces(), r"m: expected a surface with area, got 4 faces of zero area"),
], ids=["str", "pointcloud", "empty", "bad-index", "nan", "inf", "point", "collinear", "zero-area"])
def test_check_mesh_refuses_what_cannot_be_drawn(mesh, match):
    with pytest.raises(MeshError, match=match):
        check_mesh(mesh, "m")


@pytest.mark.parametrize("content, match", [
    ("v 0 0 0\nv 1 1 1\nv 2 2 2\nv 3 3 3\nf 1 2 3\nf 2 3 4\n", "all vertices on one line"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 2\nf 1 3 3\nf 1 4 4\n", "faces of zero area"),
])
def test_load_mesh_refuses_meshes_without_area(tmp_path: Path, content: str, match: str):
    path = tmp_path / "degenerate.obj"
    path.write_text(content)
    with pytest.raises(MeshError, match=match):
        load_mesh(path)


# --------------------------------------------------------------------------- load_mesh


@pytest.mark.parametrize("ext", ["obj", "ply", "stl", "glb"])
def test_load_mesh_round_trip(tmp_path: Path, ext: str):
    src = teapot(4)
    src.apply_scale(3.0)  # load_mesh must normalise again
    src.apply_translation([1.0, 2.0, 3.0])
    path = tmp_path / f"teapot.{ext}"
    src.export(path)
    m = load_mesh(path, up="z")  # written as it is, +z up (the +y default of OBJ/glTF: test_mesh_assets)
    ref = normalize(src)
    assert len(m.faces) == len(ref.faces)
    assert len(m.vertices) == len(ref.vertices)  # split vertices (STL) merged again
    np.testing.assert_allclose(m.bounds, ref.bounds, atol=1e-6)
    assert_normalised(m)
    # Same surface: every loaded vertex is a reference vertex.
    d, _ = trimesh.proximity.ProximityQuery(ref).vertex(m.vertices)
    assert d.max() < 1e-6


def test_load_mesh_concatenates_scenes(tmp_path: Path):
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(), geom_name="a")
    scene.add_geometry(
        trimesh.creation.box(), geom_name="b", transform=trimesh.transformations.translation_matrix([3, 0, 0])
    )
    path = tmp_path / "scene.glb"
    scene.export(path)
    m = load_mesh(path)
    assert len(m.faces) == 24
    np.testing.assert_allclose(m.extents, [1.0, 0.25, 0.25])


def test_load_mesh_accepts_str_paths(tmp_path: Path):
    path = tmp_path / "box.stl"
    trimesh.creation.box().export(path)
    assert len(load_mesh(str(path)).faces) == 12


@pytest.mark.parametrize(
    "name, content, match",
    [
        ("empty.obj", "", "expected a mesh with at least one face, got 0 faces"),
        ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "expected a mesh with at least one face, got 0 faces"),
        ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "expected finite vertex coordinates, got 1"),
        ("inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n", "expected finite vertex coordinates, got 1"),
        ("bad.unknownext", "v 0 0 0\n", "expected a file trimesh can read, got .*not supported"),
        ("bad.glb", "definitely not a glb", "expected a file trimesh can read"),
        ("bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n", "trimesh can read"),
    ],
)
def test_load_mesh_bad_files(tmp_path: Path, name: str, content: str, match: str):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(MeshError, match=match):
        load_mesh(path)


def test_load_mesh_missing_path(tmp_path: Path):
    with pytest.raises(MeshError, match=r"expected an existing mesh file, got .*nope\.obj.*file not found"):
        load_mesh(tmp_path / "nope.obj")
    with pytest.raises(MeshError, match=r"\(a directory\)"):
        load_mesh(tmp_path)


# --------------------------------------------------------------------------- sample_mesh


def test_sample_mesh_names():
    assert SAMPLE_MESHES == ("teapot", "chair", "cow")
    assert BILLBOARD_MESHES == ("teapot", "chair", "cow", "tree", "person")
    for name in BILLBOARD_MESHES:
        assert_normalised(sample_mesh(name))
    assert len(sample_mesh("tree", faces=5000).faces) == len(tree(5000).faces)
    assert len(sample_mesh("teapot", resolution=4).faces) == 1120
    assert len(sample_mesh("chair", slats=5).faces) == len(chair(5).faces)


def test_sample_mesh_unknown_name_lists_valid_names():
    with pytest.raises(ValidationError,
                       match=r"expected one of \['teapot', 'chair', 'cow', 'tree', 'person'\], got 'bunny'"):
        sample_mesh("bunny")


def test_sample_mesh_bad_keyword():
    with pytest.raises(ValidationError, match="keywords the builder accepts"):
        sample_mesh("teapot", size=3)
