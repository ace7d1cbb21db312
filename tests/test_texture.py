"""Texture conversion (morphkit.meshes.texture) and a mesh's own look (morphkit.meshes.look), without GL."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from PIL import Image

from morphkit import tol
from morphkit.conventions import ALPHA_CUTOFF, DEFAULT_COLOR
from morphkit.errors import MeshError, ValidationError
from morphkit.imaging.fidelity import gradient_quad, quad, textured_quad
from morphkit.meshes.look import DIELECTRIC, MeshLookWarning, mesh_look
from morphkit.meshes.parts import srgb_to_linear
from morphkit.meshes.texture import texture_rgba, texture_shape
from morphkit.scene import Item


def test_texture_layouts_become_rgba_uint8(rng):
    grey = rng.integers(0, 256, (5, 7), dtype=np.uint8)
    for img in (grey, grey[..., None], Image.fromarray(grey)):
        out = texture_rgba(img)
        assert out.shape == (5, 7, 4) and out.dtype == np.uint8 and out.flags.c_contiguous
        assert np.all(out[..., :3] == grey[..., None]) and np.all(out[..., 3] == 255)
    la = np.stack([grey, 255 - grey], -1)
    for img in (la, Image.fromarray(la, "LA")):
        out = texture_rgba(img)
        assert np.all(out[..., 0] == grey) and np.all(out[..., 3] == 255 - grey)
    rgb = rng.integers(0, 256, (5, 7, 3), dtype=np.uint8)
    assert np.all(texture_rgba(rgb)[..., :3] == rgb) and np.all(texture_rgba(rgb)[..., 3] == 255)
    rgba = rng.integers(0, 256, (5, 7, 4), dtype=np.uint8)
    out = texture_rgba(Image.fromarray(rgba, "RGBA"))
    assert np.array_equal(out, rgba) and out is not rgba
    pal = Image.fromarray(rgb).convert("P", palette=Image.ADAPTIVE, colors=8)
    assert np.array_equal(texture_rgba(pal)[..., :3], np.asarray(pal.convert("RGB")))
    assert np.array_equal(texture_rgba(np.array([[True, False]]))[0, :, 0], [255, 0])


def test_sixteen_bit_and_float_textures_round_to_eight_bits():
    v8 = np.arange(256, dtype=np.uint8).reshape(16, 16)
    v16 = v8.astype(np.uint16) * 257  # the 16-bit value of each 8-bit level
    for img in (v16, Image.fromarray(v16)):  # PIL: mode I;16
        assert np.array_equal(texture_rgba(img)[..., 0], v8)
    up = np.minimum(v16.astype(np.int64) + 128, 65535).astype(np.uint16)
    assert np.array_equal(texture_rgba(up)[..., 0], v8)  # rounds: 128 / 257 < 0.5
    assert np.array_equal(texture_rgba(v8 / 255.0)[..., 1], v8)
    assert np.array_equal(texture_rgba(Image.fromarray((v8 / 255.0).astype(np.float32), "F"))[..., 2], v8)


def test_bad_textures_are_refused():
    with pytest.raises(ValidationError, match="MAX_TEXTURE_PIXELS"):
        texture_rgba(np.broadcast_to(np.zeros((1, 1, 3), np.uint8), (4097, 4096, 3)))
    with pytest.raises(ValidationError, match="MAX_TEXTURE_SIDE"):
        texture_shape(np.broadcast_to(np.zeros((1, 1), np.uint8), (2, tol.MAX_TEXTURE_SIDE + 1)))
    with pytest.raises(ValidationError, match="at least one texel"):
        texture_rgba(np.zeros((0, 4, 3), np.uint8))
    with pytest.raises(ValidationError, match="dtype int32"):
        texture_rgba(np.zeros((2, 2), np.int32))
    with pytest.raises(ValidationError, match="NaN or inf"):
        texture_rgba(np.full((2, 2), np.nan))
    with pytest.raises(ValidationError, match="1 to 4 channels"):
        texture_rgba(np.zeros((2, 2, 5), np.uint8))
    with pytest.raises(ValidationError, match="a PIL image or a numpy array"):
        texture_rgba("texture.png")


def test_the_size_limit_is_checked_before_converting():
    """A PIL image over the limit is refused from its size alone (no pixels are read)."""
    big = Image.new("L", (4097, 4096))
    with pytest.raises(ValidationError, match=r"4097 x 4096 texels"):
        texture_rgba(big)


def test_a_mesh_without_visuals_has_the_default_colour():
    look = mesh_look(quad())
    assert look.plain and look.base_color == (*DEFAULT_COLOR, 1.0)
    assert (look.metallic, look.roughness) == DIELECTRIC


def test_trimesh_placeholder_material_is_no_visuals(tmp_path):
    """An OBJ with UVs and no material loads with trimesh's grey-100 placeholder texture:
    drawn in the default colour as before, not darker."""
    p = tmp_path / "uv.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n")
    m = trimesh.load(p, process=False)
    assert isinstance(m.visual, trimesh.visual.TextureVisuals)
    assert mesh_look(m).plain and mesh_look(m).base_color == (*DEFAULT_COLOR, 1.0)
    m.visual.material.image = Image.new("RGBA", (2, 2), (100, 100, 101, 255))  # a real texture
    assert mesh_look(m).texture is not None


def test_vertex_and_face_colours_are_opaque_looks():
    look = mesh_look(gradient_quad())
    assert not look.plain and look.vertex_colors.shape == (4, 4) and look.vertex_colors[1].tolist() == [
        255, 0, 0, 255]
    m = quad()
    m.visual.face_colors = [[10, 20, 30, 40], [50, 60, 70, 80]]
    look = mesh_look(m)
    assert look.face_colors[:, :3].tolist() == [[10, 20, 30], [50, 60, 70]]
    assert np.all(look.face_colors[:, 3] == 255) and look.alpha_cutoff is None  # alpha ignored


def test_alpha_modes():
    tex = np.zeros((2, 2, 4), np.uint8)
    tex[..., 3] = 100
    opaque = mesh_look(textured_quad(tex))
    assert opaque.alpha_cutoff is None and np.all(opaque.texture[..., 3] == 255)
    mask = mesh_look(textured_quad(tex, alpha_mode="MASK", alpha_cutoff=0.3))
    assert mask.alpha_cutoff == pytest.approx(0.3) and np.all(mask.texture[..., 3] == 100)
    assert mesh_look(textured_quad(tex, alpha_mode="MASK")).alpha_cutoff == ALPHA_CUTOFF
    assert mesh_look(textured_quad(tex, alpha_mode="BLEND", alpha_cutoff=0.1)).alpha_cutoff == ALPHA_CUTOFF
    assert mesh_look(textured_quad(tex, alpha_mode="MASK", alpha_cutoff=0.0)).alpha_cutoff is None
    with pytest.raises(MeshError, match="alphaCutoff: expected a number in"):
        mesh_look(textured_quad(tex, alpha_mode="MASK", alpha_cutoff=1.5))


def test_simple_material_texture_is_not_darkened_by_the_default_diffuse():
    """trimesh gives a SimpleMaterial without Kd the diffuse grey 102: the image alone is drawn."""
    m = quad()
    m.visual = trimesh.visual.TextureVisuals(uv=np.zeros((4, 2)), image=Image.new("RGB", (2, 2), (9, 8, 7)))
    assert m.visual.material.diffuse.tolist() == [102, 102, 102, 255]
    look = mesh_look(m)
    assert look.base_color == (1.0, 1.0, 1.0, 1.0) and look.texture[0, 0].tolist() == [9, 8, 7, 255]
    assert look.alpha_cutoff is None
    m.visual.material.image = None  # no map_Kd: the diffuse colour
    assert mesh_look(m).base_color == pytest.approx((0.4, 0.4, 0.4, 1.0))
    m.visual.material.image = Image.new("RGBA", (2, 2), (9, 8, 7, 0))  # OBJ image with alpha: a cut-out
    assert mesh_look(m).alpha_cutoff == ALPHA_CUTOFF


def test_texture_without_uv_falls_back_to_its_mean_colour():
    m = quad()
    tex = np.zeros((2, 2, 3), np.uint8)
    tex[0] = 200
    m.visual = trimesh.visual.TextureVisuals(uv=None, image=tex)
    with pytest.warns(MeshLookWarning, match="no UV coordinates: drawn in the texture's mean colour"):
        look = mesh_look(m)
    assert look.texture is None and look.plain
    lin = float(srgb_to_linear(100 / 255))  # the mean texel, sRGB-encoded: decoded into the factor
    assert look.base_color == pytest.approx((lin, lin, lin, 1.0))


def test_malformed_visuals_are_refused():
    m = textured_quad(np.zeros((2, 2, 3), np.uint8))
    m.visual.uv = np.zeros((3, 2))
    with pytest.raises(MeshError, match=r"UV coordinates: expected \(4, 2\)"):
        mesh_look(m)
    m = textured_quad(np.zeros((2, 2, 3), np.uint8))
    m.visual.vertex_attributes["color"] = np.zeros((3, 4), np.uint8)
    with pytest.raises(MeshError, match="vertex colours"):
        mesh_look(m)
    mats = [trimesh.visual.material.PBRMaterial(), trimesh.visual.material.PBRMaterial()]
    m.visual = trimesh.visual.TextureVisuals(uv=np.zeros((4, 2)),
                                             material=trimesh.visual.material.MultiMaterial(mats))
    with pytest.raises(MeshError, match="one material per mesh"):
        mesh_look(m)


def test_vertex_colours_with_a_texture_are_both_kept():
    m = textured_quad(np.zeros((2, 2, 4), np.uint8), alpha_mode="MASK")
    m.visual.vertex_attributes["color"] = np.tile([[1.0, 0.5, 0.25, 0.5]], (4, 1))  # glTF float COLOR_0
    look = mesh_look(m)
    assert look.texture is not None and look.vertex_colors[0].tolist() == [255, 128, 64, 128]


def test_item_colour_is_validated():
    assert Item(quad()).color is None
    assert Item(quad(), color=np.array([0.1, 0.2, 0.3])).color == (0.1, 0.2, 0.3)
    with pytest.raises(ValidationError, match="item color: expected RGB in"):
        Item(quad(), color=(0.1, 0.2, 2.0))
    with pytest.raises(ValidationError, match="item color"):
        Item(quad(), color=(0.1, 0.2))
