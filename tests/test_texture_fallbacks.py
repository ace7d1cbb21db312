"""A texture that cannot be drawn is said, never dropped without a word (no GL but the CLI run).

A mesh file's texture that is missing, outside the asset root, unreadable, not an image,
empty or damaged is one :class:`~morphkit.errors.AssetWarning` naming the mesh file, the
texture and why, and the material is drawn without it: an OBJ material in its ``Kd`` colour,
a glTF material in its ``baseColorFactor``. trimesh itself drops such an image silently (the
asset was drawn plain white, exit 0), and a truncated one failed later with a bare
``OSError: image file is truncated``. The root's user reads every file, so an unreadable
texture is simulated by refusing its ``os.open``.
"""

from __future__ import annotations

import io
import json
import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from clirun import one_line, run
from PIL import Image

from morphkit.errors import AssetWarning
from morphkit.meshes import face_base_colors, load_mesh
from morphkit.meshes.texture import image_problem
from morphkit.programs import fixtures as F

KD = r"drawn in its Kd colour \['0\.8', '0\.8', '0\.8'\]"
FACTOR = "its materials are drawn in their baseColorFactor"


def _load(path: Path) -> tuple[object, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = load_mesh(path)
    return mesh, [str(w.message) for w in caught if issubclass(w.category, AssetWarning)]


def _damage(texture: Path, how: str, monkeypatch: pytest.MonkeyPatch) -> str:
    """Spoil ``texture`` as ``how`` says; the reason the warning must give (a regex)."""
    data = texture.read_bytes()
    if how == "not an image":
        texture.write_bytes(b"\x89PNG\r\n\x1a\n" + b"not a PNG at all")
        return r"is not an image morphkit can decode \(PNG, JPEG, or another format Pillow reads\)"
    if how == "empty":
        texture.write_bytes(b"")
        return "is empty"
    if how == "truncated":
        texture.write_bytes(data[:200])
        return r"is damaged \(OSError: image file is truncated.*\)"
    real = os.open

    def refuse(path: object, *args: object, **kw: object) -> int:
        if Path(os.fspath(path)).name == texture.name:
            raise PermissionError(13, "Permission denied")
        return real(path, *args, **kw)

    monkeypatch.setattr(os, "open", refuse)
    return r"cannot be read \(Permission denied\)"


HOWS = ["not an image", "empty", "truncated", "unreadable"]


@pytest.mark.parametrize("how", HOWS)
def test_an_obj_texture_that_cannot_be_drawn_warns_and_keeps_kd(tmp_path, monkeypatch, how):
    path = F.write_photo_obj(tmp_path)
    why = _damage(tmp_path / "photo_box.png", how, monkeypatch)
    mesh, said = _load(path)
    assert len(said) == 1, said
    assert re.fullmatch(rf"mesh file '{re.escape(str(path))}': texture 'photo_box\.png' of material 'photo' "
                        rf"\(photo_box\.mtl\) {why}; {KD}", said[0]), said[0]
    assert mesh.visual.material.image is None
    np.testing.assert_array_equal(mesh.visual.material.diffuse, [204, 204, 204, 255])


@pytest.mark.parametrize("how", HOWS)
def test_a_gltf_image_file_that_cannot_be_drawn_warns_and_keeps_the_factor(tmp_path, monkeypatch, how):
    path = F.write_two_part_gltf(tmp_path, "external")
    why = _damage(tmp_path / "two_part_image0.png", how, monkeypatch)
    mesh, said = _load(path)
    assert len(said) == 1, said
    head = rf"mesh file '{re.escape(str(path))}': image 0 'two_part_image0\.png'"
    assert re.fullmatch(rf"{head} {why}; {FACTOR}", said[0]), said[0]
    np.testing.assert_allclose(face_base_colors(mesh)[12:, :3], 1.0)  # the photo box: its factor, white


@pytest.mark.parametrize("how", ["signature", "data"])
def test_a_damaged_image_inside_a_glb_warns(tmp_path, how):
    path = F.write_photo_glb(tmp_path)
    blob = bytearray(path.read_bytes())
    start = blob.index(b"\x89PNG")
    if how == "signature":  # not an image: trimesh's open fails and it drops the image
        blob[start:start + 4] = b"XXXX"
        why = r"is not an image morphkit can decode \(.*\)"
    else:  # a PNG whose pixel data is spoilt: it opens and fails when first read
        idat = blob.index(b"IDAT", start)
        blob[idat + 8:idat + 40] = bytes(32)
        why = r"is damaged \(.*\)"
    path.write_bytes(bytes(blob))
    mesh, said = _load(path)
    assert len(said) == 1, said
    head = rf"mesh file '{re.escape(str(path))}': image 0 \(in buffer view \d+\)"
    assert re.fullmatch(rf"{head} {why}; {FACTOR}", said[0]), said[0]
    assert mesh.visual.material.baseColorTexture is None


def test_an_embedded_data_uri_that_is_not_base64_warns(tmp_path):
    path = F.write_two_part_gltf(tmp_path, "embedded")
    doc = json.loads(path.read_text())
    doc["images"][0]["uri"] = "data:image/png;base64,@@@not base64@@@"
    path.write_text(json.dumps(doc))
    _, said = _load(path)
    assert said == [f"mesh file {str(path)!r}: image 0 (in a data URI) cannot be taken out of the file; "
                    f"{FACTOR}"]


def test_a_texture_behind_a_link_out_of_the_folder_names_the_link(tmp_path):
    (tmp_path / "asset").mkdir()
    path = F.write_photo_obj(tmp_path / "asset")
    outside = tmp_path / "elsewhere.png"
    (tmp_path / "asset" / "photo_box.png").rename(outside)
    os.symlink(outside, tmp_path / "asset" / "photo_box.png")
    mesh, said = _load(path)
    assert len(said) == 1, said
    assert f"texture 'photo_box.png' is a link to {str(outside)!r}, outside the asset root " \
           f"{str(tmp_path / 'asset')!r}; not opened, material 'photo' is drawn in its Kd colour" in said[0]
    assert mesh.visual.material.image is None


def test_a_texture_behind_a_link_inside_the_folder_is_drawn(tmp_path):
    path = F.write_photo_obj(tmp_path)
    (tmp_path / "photo_box.png").rename(tmp_path / "real.png")
    os.symlink(tmp_path / "real.png", tmp_path / "photo_box.png")
    mesh, said = _load(path)
    assert said == [] and mesh.visual.material.image is not None


def test_map_kd_options_trimesh_cannot_read_are_said(tmp_path):
    path = F.write_photo_obj(tmp_path)
    mtl = tmp_path / "photo_box.mtl"
    mtl.write_text(mtl.read_text().replace("map_Kd ", "map_Kd -s 1 1 1 "))
    mesh, said = _load(path)
    assert said == [f"mesh file {str(path)!r}: texture 'photo_box.png' of material 'photo' (photo_box.mtl) "
                    "was found but not loaded (its map_Kd line has options, '-s 1 1 1', which trimesh's OBJ "
                    "reader takes for the file name); drawn in its Kd colour ['0.8', '0.8', '0.8']"]
    assert mesh.visual.material.image is None


def test_image_problem_reads_every_texel():
    buf = io.BytesIO()
    Image.fromarray(F.photo_texture(32)).save(buf, format="PNG")
    png = buf.getvalue()
    assert image_problem(png) is None
    assert image_problem(b"") == "is empty"
    assert image_problem(b"GIF89a") == "is not an image morphkit can decode (PNG, JPEG, or another format " \
                                       "Pillow reads)"
    # the header and the first rows are there: it opens, and fails only when every texel is read
    half = png[:len(png) // 2]
    assert re.fullmatch(r"is damaged \(OSError: image file is truncated.*\)", image_problem(half))


@pytest.mark.gl
def test_billboards_with_a_damaged_texture_says_so_in_one_line(tmp_path, capfd):
    (tmp_path / "asset").mkdir()
    path = F.write_photo_obj(tmp_path / "asset")
    (tmp_path / "asset" / "photo_box.png").write_bytes(b"\x89PNG\r\n\x1a\nnot a PNG")
    rc, out, err = run(capfd, "billboards", "--asset", path, "--n", "2", "--views", "2", "--frames", "1",
                       "--size", "64x48", "--asset-size", "32", "-o", tmp_path / "out")
    assert rc == 0, err
    line = one_line(err, "morphkit: warning: ")
    head = rf"morphkit: warning: mesh file '{re.escape(str(path))}': texture 'photo_box\.png'"
    assert re.fullmatch(rf"{head} of material 'photo' \(photo_box\.mtl\) is not an image morphkit can decode "
                        rf"\(.*\); {KD}", line), line
    assert (tmp_path / "out" / "billboards.json").is_file()


@pytest.mark.gl
def test_a_bake_says_a_workers_texture_warning_in_one_line(tmp_path, capfd):
    """A worker process printed the warning in Python's two-line form (its source line and code)."""
    (tmp_path / "lib").mkdir()
    path = F.write_photo_obj(tmp_path / "lib")
    (tmp_path / "lib" / "photo_box.png").write_bytes(b"")
    rc, out, err = run(capfd, "bake", tmp_path / "lib", "--atlas-size", "32", "--grid", "2", "--workers", "1",
                       "-q", "-o", tmp_path / "out")
    assert rc == 0 and "1 baked" in out, err
    assert one_line(err, "morphkit: warning: ") == (
        f"morphkit: warning: mesh file {str(path)!r}: texture 'photo_box.png' of material 'photo' "
        "(photo_box.mtl) is empty; drawn in its Kd colour ['0.8', '0.8', '0.8']")
