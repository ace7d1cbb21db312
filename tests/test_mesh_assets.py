"""Real assets: load_mesh keeps a file's look, turns +y-up files +z up, merges parts (issue #24).

The assets are written on the fly (morphkit.programs.fixtures) from scikit-image's photographs;
every expected colour is derived from the source image, factor or vertex colour, never
read back through the code under test.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from morphkit.errors import AssetWarning, MeshError
from morphkit.meshes import (
    UP_AXIS_BY_FORMAT,
    Y_UP_TO_Z_UP,
    face_base_colors,
    load_mesh,
    merge_parts,
    normalize,
    resolve_up,
    scene_parts,
)
from morphkit.meshes.parts import PLAIN_PART_COLOR, linear_to_srgb, srgb_to_linear
from morphkit.programs import fixtures as F

#: One 8-bit level: merged colours agree with their source within it (sRGB-encoded).
LEVEL = 1.0 / 255.0


def _srgb(linear_rgba: np.ndarray) -> np.ndarray:
    """Linear RGBA -> sRGB-encoded RGB in [0, 1] (for comparing in 8-bit levels)."""
    return linear_to_srgb(np.asarray(linear_rgba)[..., :3])


def _texel_at(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Nearest texel of ``image`` (row 0 = v 1) at each UV, as linear RGB (the truth)."""
    h, w = image.shape[:2]
    col = np.clip(np.floor(uv[:, 0] * w).astype(int), 0, w - 1)
    row = np.clip(np.floor((1.0 - uv[:, 1]) * h).astype(int), 0, h - 1)
    return srgb_to_linear(image[row, col, :3] / 255.0)


# --------------------------------------------------------------------------- up axis


def test_up_axis_table_and_refusals():
    assert UP_AXIS_BY_FORMAT == {"gltf": "y", "glb": "y", "obj": "y"}
    for name, up in [("a.glb", "y"), ("a.GLTF", "y"), ("a.obj", "y"), ("a.ply", "z"), ("a.stl", "z"),
                     ("a.off", "z"), ("a.dae", "z")]:
        assert resolve_up(name) == up
        assert resolve_up(name, "z") == "z" and resolve_up(name, "Y") == "y"
    with pytest.raises(MeshError, match=r"up axis: expected 'auto', 'z' or 'y' .*got 'x'"):
        resolve_up("a.glb", "x")
    with pytest.raises(MeshError, match=r"up axis: expected .*got None"):
        load_mesh("whatever.obj", up=None)  # type: ignore[arg-type]


def test_y_up_rotation_keeps_handedness():
    r = Y_UP_TO_Z_UP[:3, :3]
    np.testing.assert_array_equal(r @ r.T, np.eye(3))
    assert np.linalg.det(r) == 1.0  # a rotation, not a mirror
    np.testing.assert_array_equal(r @ [0, 1, 0], [0, 0, 1])  # file up -> world up
    np.testing.assert_array_equal(r @ [0, 0, 1], [0, -1, 0])  # glTF front (+z) -> -y
    np.testing.assert_array_equal(r @ [1, 0, 0], [1, 0, 0])


@pytest.mark.parametrize("ext", ["glb", "gltf", "obj"])
def test_a_tall_box_written_y_up_stands_along_z(tmp_path: Path, ext: str):
    """Derivable: a box 0.4 x 1.0 x 0.25 written +y up is 1.0 tall along +z once loaded."""
    box = trimesh.creation.box(extents=F.TALL_BOX_EXTENTS)
    box.apply_translation([0.0, 0.5, 0.0])  # standing on y = 0
    path = tmp_path / f"tall.{ext}"
    if ext == "gltf":  # a .gltf with its buffer in a file beside it
        for k, data in trimesh.Scene(box).export(file_type="gltf").items():
            (tmp_path / (path.name if k == "model.gltf" else k)).write_bytes(data)
    else:
        box.export(path)
    m = load_mesh(path)
    np.testing.assert_allclose(m.extents, [0.4, 0.25, 1.0], atol=1e-6)
    # the file's up axis honoured, not guessed from the shape: told "z", it lies on its side
    np.testing.assert_allclose(load_mesh(path, up="z").extents, [0.4, 1.0, 0.25], atol=1e-6)


def test_y_up_keeps_which_side_is_front_and_top(tmp_path: Path):
    """A marked asymmetric mesh: a tetrahedron with its apex on +y (top) and a spike on +z (front)."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0], [0, 0, 0.5]], float)
    path = tmp_path / "tet.glb"
    trimesh.Trimesh(v, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], process=False).export(path)
    m = load_mesh(path)
    top = m.vertices[np.argmax(m.vertices[:, 2])]
    front = m.vertices[np.argmin(m.vertices[:, 1])]
    assert top[2] == pytest.approx(1.0)  # the +y apex is the highest point
    assert front[2] == pytest.approx(0.0) and front[1] < top[1]  # +z spike now towards -y
    assert m.volume > 0  # faces still wound outwards: no mirror


@pytest.mark.parametrize("ext", ["ply", "stl", "off"])
def test_z_up_formats_are_not_turned(tmp_path: Path, ext: str):
    box = trimesh.creation.box(extents=[0.4, 0.25, 1.0])
    path = tmp_path / f"tall.{ext}"
    box.export(path)
    np.testing.assert_allclose(load_mesh(path).extents, [0.4, 0.25, 1.0], atol=1e-6)


# --------------------------------------------------------------------------- visuals kept


def test_normalize_moves_vertices_only():
    v, f, uv = F.uv_box()
    img = F.photo_texture(16)
    m = trimesh.Trimesh(v * 3 + 5, f, process=False,
                        visual=trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(img)))
    n = normalize(m)
    assert isinstance(n.visual, trimesh.visual.TextureVisuals)
    np.testing.assert_array_equal(n.visual.uv, uv)
    np.testing.assert_array_equal(np.asarray(n.visual.material.image), img)
    c = trimesh.creation.icosphere(1)
    c.visual.vertex_colors = np.arange(len(c.vertices) * 4).reshape(-1, 4) % 256
    np.testing.assert_array_equal(normalize(c).visual.vertex_colors, c.visual.vertex_colors)


def test_photo_obj_loads_with_its_texture(tmp_path: Path):
    img = F.photo_texture(32)
    m = load_mesh(F.write_photo_obj(tmp_path, img))
    assert isinstance(m.visual.material, trimesh.visual.material.SimpleMaterial)
    np.testing.assert_array_equal(np.asarray(m.visual.material.image.convert("RGB")), img)
    assert len(m.faces) == 12 and len(m.visual.uv) == len(m.vertices)  # UV seams not merged away
    got = face_base_colors(m)[:, :3]
    want = _texel_at(img, m.visual.uv[m.faces].mean(1))
    assert np.abs(_srgb(got) - _srgb(want)).max() <= LEVEL


def test_ply_keeps_vertex_colours(tmp_path: Path):
    path = F.write_color_ply(tmp_path)
    src = trimesh.load(path, process=False)
    m = load_mesh(path)
    assert m.visual.kind == "vertex"
    np.testing.assert_array_equal(m.visual.vertex_colors, src.visual.vertex_colors)
    # the colours still follow the height: red at the bottom, blue on top
    lo, hi = np.argmin(m.vertices[:, 2]), np.argmax(m.vertices[:, 2])
    np.testing.assert_array_equal(m.visual.vertex_colors[lo], [255, 64, 0, 255])
    np.testing.assert_array_equal(m.visual.vertex_colors[hi], [0, 64, 255, 255])


def test_vertex_colours_and_texture_in_one_file_keeps_both(tmp_path: Path):
    """Documented: both kept (vertex colours in vertex_attributes["color"]); the renderer multiplies."""
    v, f, uv = F.uv_box()
    img = F.photo_texture(8)
    m = trimesh.Trimesh(v, f, process=False, visual=trimesh.visual.TextureVisuals(
        uv=uv, material=trimesh.visual.material.PBRMaterial(baseColorTexture=Image.fromarray(img))))
    vc = np.tile([[255, 128, 0, 255]], (len(v), 1)).astype(np.uint8)
    m.visual.vertex_attributes["color"] = vc
    m.export(tmp_path / "both.glb")
    got = load_mesh(tmp_path / "both.glb")
    np.testing.assert_array_equal(got.visual.vertex_attributes["color"], vc)
    np.testing.assert_array_equal(np.asarray(got.visual.material.baseColorTexture.convert("RGB")), img)
    want = _texel_at(img, got.visual.uv[got.faces].mean(1)) * srgb_to_linear(np.array([1.0, 128 / 255, 0.0]))
    assert np.abs(_srgb(face_base_colors(got)) - _srgb(want)).max() <= LEVEL


# --------------------------------------------------------------------------- glTF images, multi-part


def _two_part_truth(tmp_path: Path, images: str) -> tuple[trimesh.Trimesh, np.ndarray]:
    img = F.photo_texture(32)
    return load_mesh(F.write_two_part_gltf(tmp_path, images, image=img)), img


@pytest.mark.parametrize("images", ["glb", "embedded", "external"])
def test_two_part_gltf_keeps_each_parts_look(tmp_path: Path, images: str):
    m, img = _two_part_truth(tmp_path, images)
    if images == "external":
        assert (tmp_path / "two_part_image0.png").is_file()
        assert "data:image" not in (tmp_path / "two_part.gltf").read_text()
    # parts in the order of their node names: "painted" (12 faces), then "photo" (12 faces)
    assert len(m.faces) == 24 and m.visual.material.alphaMode == "OPAQUE"
    colors = face_base_colors(m)
    painted_faces, photo_faces = slice(0, 12), slice(12, 24)
    # photo part: the photo's texel at each face's UV centroid, read from the source image
    # (the UVs of the source box, identical for every face: (0,0),(1,0),(1,1) and (0,0),(1,1),(0,1))
    src_uv = np.array([[2 / 3, 1 / 3], [1 / 3, 2 / 3]] * 6)
    want_photo = _texel_at(img, src_uv)
    assert np.abs(_srgb(colors[photo_faces]) - _srgb(want_photo)).max() <= LEVEL
    # painted part: the mean of its three (decoded) vertex colours on a white texel
    box = trimesh.creation.box(extents=(0.3, 0.3, 0.3))
    i = np.arange(8)
    vc = np.c_[np.rint(40 + 200 * i / 7), np.full((8, 3), [200, 90, 255])] / 255.0
    want_painted = srgb_to_linear(vc[box.faces][..., :3]).mean(1)
    assert np.abs(_srgb(colors[painted_faces]) - _srgb(want_painted)).max() <= 1e-9
    # node transform applied: the painted box stands beside the photo box, turned 30 deg
    painted = m.vertices[np.unique(m.faces[painted_faces])]
    photo = m.vertices[np.unique(m.faces[photo_faces])]
    assert painted[:, 0].min() > photo[:, 0].max()


def test_nested_node_transforms_are_composed(tmp_path: Path):
    """A child node under a moved and scaled parent: the part lands at parent @ child."""
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(), geom_name="root_box", node_name="root_box")
    parent = trimesh.transformations.translation_matrix([4.0, 0.0, 0.0]) @ np.diag([2.0, 2.0, 2.0, 1.0])
    scene.graph.update(frame_to="parent", frame_from=scene.graph.base_frame, matrix=parent)
    child = trimesh.transformations.translation_matrix([0.0, 1.0, 0.0])
    scene.add_geometry(trimesh.creation.box(), geom_name="child_box", node_name="child",
                       parent_node_name="parent", transform=child)
    path = tmp_path / "nested.glb"
    scene.export(path)
    parts = scene_parts(trimesh.load(path, process=False))
    centres = sorted(tuple(np.round(p.bounds.mean(0), 6)) for p in parts)
    assert centres == [(0.0, 0.0, 0.0), (4.0, 2.0, 0.0)]
    assert sorted(float(np.round(p.extents[0], 6)) for p in parts) == [1.0, 2.0]


def test_merge_keeps_colours_within_one_level(tmp_path: Path):
    """Before/after packing: each part's colour per face, as the renderer reads it, within 1/255."""
    img = F.photo_texture(32, "coffee")
    parts = scene_parts(trimesh.load(F.write_two_part_gltf(tmp_path, image=img), process=False))
    red = trimesh.creation.icosphere(1)  # face colours
    red.visual.face_colors = np.tile([200, 30, 30, 255], (len(red.faces), 1))
    red.apply_translation([2, 0, 0])
    tinted = parts[1].copy()  # the photo box with a factor, to be baked into the texels
    tinted.visual.material.baseColorFactor = [0.5, 1.0, 0.25, 1.0]
    kd = trimesh.creation.box()  # an OBJ-style Kd colour, no image
    kd.visual = trimesh.visual.TextureVisuals(
        material=trimesh.visual.material.SimpleMaterial(diffuse=[51, 153, 76]))
    plain = trimesh.creation.box()  # no visuals at all
    parts += [red, tinted, kd, plain]
    merged = merge_parts(parts)
    after = face_base_colors(merged)
    before = np.vstack([face_base_colors(p) for p in parts])
    assert after.shape == before.shape
    assert np.abs(_srgb(after) - _srgb(before)).max() <= LEVEL
    # each part's colour from its own source, not from face_base_colors
    f0 = 24 + len(red.faces)
    np.testing.assert_allclose(_srgb(after[24:f0]), np.tile([200, 30, 30], (len(red.faces), 1)) / 255,
                               atol=1e-9)
    factor = np.array([128, 255, 64]) / 255  # trimesh keeps baseColorFactor as uint8
    want_tint = _texel_at(img, np.array([[2 / 3, 1 / 3], [1 / 3, 2 / 3]] * 6)) * factor
    assert np.abs(_srgb(after[f0:f0 + 12]) - _srgb(want_tint)).max() <= LEVEL / 2 + 1e-12  # one rounding
    # Kd is a linear factor (the renderer's reading of MTL, as glTF's baseColorFactor)
    assert np.abs(_srgb(after[f0 + 12:f0 + 24]) - _srgb(np.array([51, 153, 76]) / 255)).max() <= LEVEL
    assert np.abs(_srgb(after[f0 + 24:]) - _srgb(np.array(PLAIN_PART_COLOR))).max() <= LEVEL


def test_trimesh_own_concatenation_loses_the_looks(tmp_path: Path):
    """Why merge_parts exists: trimesh 5.2's concatenate drops the cut-out of a leaf plant."""
    scene = trimesh.load(F.write_leaf_plant(tmp_path), process=False)
    theirs = trimesh.util.concatenate(scene.dump())
    assert (theirs.visual.material.alphaMode or "OPAQUE") != "MASK"
    assert load_mesh(F.write_leaf_plant(tmp_path)).visual.material.alphaMode == "MASK"


def _alpha_at(mesh: trimesh.Trimesh, faces: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Texture alpha (nearest texel) at barycentric points of the given faces."""
    img = np.asarray(mesh.visual.material.baseColorTexture.convert("RGBA"))
    uv = np.einsum("fk,fkd->fd", bary, mesh.visual.uv[mesh.faces[faces]])
    h, w = img.shape[:2]
    return img[np.floor((1 - uv[:, 1]) * h).astype(int), np.floor(uv[:, 0] * w).astype(int), 3]


def test_leaf_plant_keeps_its_cut_outs(tmp_path: Path):
    m = load_mesh(F.write_leaf_plant(tmp_path, cutoff=0.3))
    mat = m.visual.material
    assert mat.alphaMode == "MASK" and mat.alphaCutoff == pytest.approx(0.3)
    leaves, stem = np.arange(6), np.arange(6, 18)  # node names leaf0..leaf2 < stem
    rng = np.random.default_rng(0)
    b = rng.dirichlet([1, 1, 1], size=400)
    assert np.all(_alpha_at(m, np.repeat(stem, 400 // 12 + 1)[:400], b) == 255)  # the stem: opaque
    # a card's alpha where the leaf texture has it: derived from leaf_texture at the source UVs
    card_uv = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]])[[0, 1, 2, 0, 2, 3]].reshape(2, 3, 2)
    leaf = F.leaf_texture()
    for k in range(6):
        uv = np.einsum("fk,kd->fd", b, card_uv[k % 2])
        h, w = leaf.shape[:2]
        want = leaf[np.floor((1 - uv[:, 1]) * h).astype(int).clip(0, h - 1),
                    np.floor(uv[:, 0] * w).astype(int).clip(0, w - 1), 3]
        np.testing.assert_array_equal(_alpha_at(m, np.full(400, leaves[k]), b), want)
    frac = np.mean(leaf[..., 3] == 0)
    assert 0.2 < frac < 0.6  # the leaf really has holes


def test_parts_with_different_cutoffs_are_made_binary(tmp_path: Path):
    """Documented: cut-outs at 0.3 and 0.7 -> alpha 0/255 each at its own cutoff, MASK at 0.5."""
    quad = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]],
                           process=False)
    ramp = np.zeros((4, 4, 4), np.uint8)
    ramp[..., :3] = 128
    ramp[..., 3] = np.arange(16).reshape(4, 4) * 17  # 0 .. 255
    parts = []
    for cut in (0.3, 0.7):
        p = quad.copy()
        p.visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]],
                                                 material=trimesh.visual.material.PBRMaterial(
                                                     baseColorTexture=Image.fromarray(ramp, "RGBA"),
                                                     alphaMode="MASK", alphaCutoff=cut))
        parts.append(p)
    m = merge_parts(parts)
    assert m.visual.material.alphaMode == "MASK" and m.visual.material.alphaCutoff == 0.5
    atlas = np.asarray(m.visual.material.baseColorTexture)
    assert set(np.unique(atlas[..., 3])) <= {0, 255}
    b = np.random.default_rng(1).dirichlet([1, 1, 1], 1000)
    kept = [np.mean(_alpha_at(m, np.full(1000, 2 * i), b) > 0) for i in range(2)]
    assert kept[0] > kept[1]  # the lower cutoff keeps more


# --------------------------------------------------------------------------- hard cases


def test_obj_with_missing_map_kd_warns_and_keeps_kd(tmp_path: Path):
    path = F.write_photo_obj(tmp_path)
    (tmp_path / "photo_box.png").unlink()
    with pytest.warns(AssetWarning, match=r"texture 'photo_box.png' of material 'photo' .*not found; "
                                          r"drawn in its Kd colour \['0.8', '0.8', '0.8'\]"):
        m = load_mesh(path)
    assert m.visual.material.image is None
    np.testing.assert_array_equal(m.visual.material.diffuse, [204, 204, 204, 255])


def test_obj_with_missing_mtllib_warns(tmp_path: Path):
    path = F.write_photo_obj(tmp_path)
    (tmp_path / "photo_box.mtl").unlink()
    with pytest.warns(AssetWarning, match=r"material library 'photo_box.mtl' not found"):
        assert len(load_mesh(path).faces) == 12


def test_two_material_obj_with_one_missing_texture(tmp_path: Path):
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 0.8 0.1 0.1\nnewmtl tex\nKd 0.2 0.6 0.3\n"
                                    "map_Kd gone.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                                    "vt 1 1\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3\nusemtl tex\nf 1/1 3/3 4/4\n")
    with pytest.warns(AssetWarning, match="'gone.png' of material 'tex'"):
        m = load_mesh(tmp_path / "m.obj")
    got = _srgb(face_base_colors(m))
    kds = _srgb(np.array([[0.8, 0.1, 0.1], [0.2, 0.6, 0.3]]))  # the materials' (linear) Kd colours
    for row in got:
        assert np.min(np.abs(row - kds).max(1)) <= LEVEL


def test_gltf_with_missing_external_image_warns(tmp_path: Path):
    path = F.write_two_part_gltf(tmp_path, "external")
    (tmp_path / "two_part_image0.png").unlink()
    with pytest.warns(AssetWarning, match=r"image 0 'two_part_image0.png' not found; .*baseColorFactor"):
        m = load_mesh(path)
    # the photo box falls back to its factor (white, glTF's default), the painted box is unchanged
    np.testing.assert_allclose(face_base_colors(m)[12:, :3], 1.0)


def test_scene_with_zero_geometries_is_refused(tmp_path: Path):
    path = tmp_path / "empty.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}]}))
    with pytest.raises(MeshError, match=r"empty.gltf'.*expected a mesh with at least one face, "
                                        r"got 0 faces \(a scene of 0 geometries, none a mesh\)"):
        load_mesh(path)


def test_texture_without_uvs_in_a_merge_warns(tmp_path: Path):
    a = trimesh.creation.box()
    a.visual = trimesh.visual.TextureVisuals(material=trimesh.visual.material.PBRMaterial(
        baseColorTexture=Image.fromarray(np.full((2, 2, 3), [10, 200, 30], np.uint8))))
    with pytest.warns(AssetWarning, match=r"a texture but no UV coordinates; merged in the texture's mean"):
        m = merge_parts([a, trimesh.creation.icosphere(1)])
    np.testing.assert_allclose(_srgb(face_base_colors(m)[:12]), np.tile([10, 200, 30], (12, 1)) / 255,
                               atol=1e-9)


def test_repeated_textures_are_tiled(tmp_path: Path):
    """UVs from 0 to 2 repeat the texture twice: the merged texel is the same as sampled with repeat."""
    img = F.photo_texture(8)
    v, f, uv = F.uv_box()
    uv2 = uv * 2.0 - 0.5  # -0.5 .. 1.5: three repeats' worth of range on each axis
    a = trimesh.Trimesh(v, f, process=False,
                        visual=trimesh.visual.TextureVisuals(uv=uv2, image=Image.fromarray(img)))
    m = merge_parts([a, trimesh.creation.icosphere(1)])
    c = uv2[f].mean(1)
    want = _texel_at(img, np.mod(c, 1.0))
    assert np.abs(_srgb(face_base_colors(m)[:12]) - _srgb(want)).max() <= LEVEL
    huge = a.copy()
    huge.visual.uv = uv * 5000.0
    with pytest.raises(MeshError, match=r"UV coordinates: expected a repeated texture of at most"):
        merge_parts([huge, trimesh.creation.icosphere(1)])


def test_atlas_keeps_each_textures_mip_levels(tmp_path: Path):
    """The atlas's 2x2 box-filtered levels over a cell are the photo's own levels (GL mip-maps)."""
    img = F.photo_texture(64)
    parts = scene_parts(trimesh.load(F.write_two_part_gltf(tmp_path, image=img), process=False))
    m = merge_parts(parts)
    atlas = np.asarray(m.visual.material.baseColorTexture).astype(np.float64)
    ah, aw = atlas.shape[:2]
    assert ah & (ah - 1) == 0 and aw & (aw - 1) == 0  # power-of-two sides
    photo_uv = m.visual.uv[np.unique(m.faces[12:])]
    x0 = int(round(photo_uv[:, 0].min() * aw))  # the photo box's UVs span the whole photo
    y0 = int(round((1.0 - photo_uv[:, 1].max()) * ah))
    np.testing.assert_array_equal(atlas[y0:y0 + 64, x0:x0 + 64, :3], img)
    a, b = atlas[..., :3], img.astype(np.float64)
    for level in range(1, 6):
        a = (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2]) / 4
        b = (b[0::2, 0::2] + b[1::2, 0::2] + b[0::2, 1::2] + b[1::2, 1::2]) / 4
        k = 2 ** level
        assert y0 % k == 0 and x0 % k == 0
        np.testing.assert_allclose(a[y0 // k: y0 // k + 64 // k, x0 // k: x0 // k + 64 // k], b, atol=1e-9)


def test_compact_atlas_when_an_aligned_one_is_too_large(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    from morphkit.meshes import parts as parts_module
    monkeypatch.setattr(parts_module, "ALIGNED_ATLAS_MAX_SIDE", 64)
    img = F.photo_texture(64)
    parts = scene_parts(trimesh.load(F.write_two_part_gltf(tmp_path, image=img), process=False))
    m = merge_parts(parts)
    atlas = np.asarray(m.visual.material.baseColorTexture)
    assert max(atlas.shape[:2]) > 64 and (atlas.shape[0] & (atlas.shape[0] - 1)) != 0  # compact: not aligned
    before = np.vstack([face_base_colors(p) for p in parts])
    assert np.abs(_srgb(face_base_colors(m)) - _srgb(before)).max() <= LEVEL


def test_parts_without_textures_stay_colour_visuals():
    plain = [trimesh.creation.box(), trimesh.creation.icosphere(1)]
    m = merge_parts(plain)
    assert m.visual.kind is None and len(m.faces) == 12 + 80
    faces = [p.copy() for p in plain]
    for k, p in enumerate(faces):
        p.visual.face_colors = [50 * k, 100, 200, 255]
    m = merge_parts(faces)
    assert m.visual.kind == "face"
    np.testing.assert_array_equal(m.visual.face_colors[:12, :3], np.tile([0, 100, 200], (12, 1)))
    np.testing.assert_array_equal(m.visual.face_colors[12:, :3], np.tile([50, 100, 200], (80, 1)))
    vc = plain[1].copy()
    vc.visual.vertex_colors = np.tile([9, 8, 7, 255], (len(vc.vertices), 1))
    m = merge_parts([faces[0], vc, plain[0]])  # face colours, vertex colours, none
    assert m.visual.kind == "vertex"
    got = _srgb(face_base_colors(m))
    want = np.vstack([np.tile([0, 100, 200], (12, 1)) / 255, np.tile([9, 8, 7], (80, 1)) / 255,
                      np.tile(_srgb(np.array(PLAIN_PART_COLOR)), (12, 1))])
    assert np.abs(got - want).max() <= LEVEL


def test_merge_parts_refuses_nothing():
    with pytest.raises(MeshError, match="expected at least one mesh, got none"):
        merge_parts([])
    one = trimesh.creation.box()
    assert merge_parts([one]) is one  # a single part is untouched


# --------------------------------------------------------------------------- the demo asset


def test_demo_asset_is_small_licensed_and_textured(tmp_path: Path):
    path = F.textured_demo_asset()
    assert path.stat().st_size < 200_000
    assert "photo_crate.glb" in (path.parent / "LICENSES.md").read_text()
    # it is what the fixture writes (rebuildable, as LICENSES.md says)
    again = load_mesh(F.write_photo_glb(tmp_path, F.photo_texture(128)))
    np.testing.assert_array_equal(np.asarray(again.visual.material.baseColorTexture),
                                  np.asarray(load_mesh(path).visual.material.baseColorTexture))
    m = load_mesh(path)
    assert isinstance(m.visual.material, trimesh.visual.material.PBRMaterial)
    assert np.asarray(m.visual.material.baseColorTexture).shape[:2] == (128, 128)
    assert m.extents[2] == pytest.approx(1.0)  # written +y up, stands along +z
