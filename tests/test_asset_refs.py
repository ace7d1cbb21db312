"""The files a mesh file refers to (morphkit.meshes.assets): confined to the asset root, regular
files only (no GL).

A FIFO is opened only in a child process under a timeout: the code before this resolver blocked
on it forever.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit.errors import AssetWarning, MeshError
from morphkit.meshes import load_mesh
from morphkit.meshes.assets import AssetResolver, asset_root, locate

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}
TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl SENTINEL_MATERIAL\nf 1/1 2/2 3/3\n"
SENTINEL_MTL = "newmtl SENTINEL_MATERIAL\nKd 1 0 0\nmap_Kd not_there.png\n"


def _obj(folder: Path, mtllib: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "m.obj").write_text(f"mtllib {mtllib}\n{TRIANGLE}")
    return folder / "m.obj"


def _load(path: Path, **kw: object) -> tuple[trimesh.Trimesh, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = load_mesh(path, **kw)
    return mesh, [str(w.message) for w in caught if issubclass(w.category, AssetWarning)]


@pytest.mark.parametrize("how", ["relative", "absolute"])
def test_a_material_library_outside_the_folder_is_not_opened(tmp_path, how):
    sentinel = tmp_path / "outside.mtl"
    sentinel.write_text(SENTINEL_MTL)
    obj = _obj(tmp_path / "asset", "../outside.mtl" if how == "relative" else str(sentinel))
    mesh, said = _load(obj)
    assert len(said) == 1, said  # one line, naming the library, not what is in it
    assert f"material library {'../outside.mtl' if how == 'relative' else str(sentinel)!r} lies outside " \
           f"the asset root {str(obj.parent)!r}; not opened" in said[0]
    assert "SENTINEL" not in said[0]
    assert getattr(mesh.visual, "material", None) is None or \
        not np.allclose(mesh.visual.material.main_color[:3], (255, 0, 0))  # its Kd was not read


def test_a_wider_asset_root_given_explicitly_reads_the_library(tmp_path):
    (tmp_path / "outside.mtl").write_text("newmtl SENTINEL_MATERIAL\nKd 1 0 0\n")
    obj = _obj(tmp_path / "asset", "../outside.mtl")
    mesh, said = _load(obj, asset_root=tmp_path)
    assert said == []
    assert np.allclose(mesh.visual.material.main_color[:3], (255, 0, 0))  # Kd 1 0 0 read


def test_an_asset_root_must_hold_the_mesh(tmp_path):
    other = tmp_path / "other"
    other.mkdir()
    obj = _obj(tmp_path / "asset", "m.mtl")
    with pytest.raises(MeshError, match=r"asset root: expected a folder holding the mesh file '.*m\.obj'"):
        asset_root(obj, other)
    with pytest.raises(MeshError, match=r"asset root: expected a folder, got '.*nothere'"):
        asset_root(obj, tmp_path / "nothere")


def test_the_resolver_refuses_names_outside_its_root_and_records_them(tmp_path):
    (tmp_path / "secret.txt").write_text("secret")
    (tmp_path / "asset").mkdir()
    (tmp_path / "asset" / "ok.bin").write_bytes(b"ok")
    os.symlink(tmp_path / "secret.txt", tmp_path / "asset" / "link.bin")  # a link out of the folder
    r = AssetResolver(tmp_path / "asset" / "m.gltf")
    assert r.get("ok.bin") == b"ok" and r["ok.bin"] == b"ok"
    for name in ("../secret.txt", str(tmp_path / "secret.txt"), "link.bin"):
        with pytest.raises(FileNotFoundError):
            r.get(name)
    assert r.outside == ["../secret.txt", str(tmp_path / "secret.txt"), "link.bin"]
    assert locate(tmp_path / "asset", "../secret.txt", tmp_path, "x") == ((tmp_path / "secret.txt"), False)


def test_a_gltf_buffer_outside_the_folder_is_refused_cleanly(tmp_path):
    trimesh.creation.box().export(tmp_path / "m.gltf")
    (tmp_path / "asset").mkdir()
    gltf = (tmp_path / "m.gltf").read_text().replace('"gltf_buffer_0.bin"', '"../gltf_buffer_0.bin"')
    (tmp_path / "asset" / "m.gltf").write_text(gltf)
    (tmp_path / "asset" / "gltf_buffer_1.bin").write_bytes((tmp_path / "gltf_buffer_1.bin").read_bytes())
    with pytest.raises(MeshError, match=r"buffer 0 of mesh file '.*m\.gltf': expected a file inside the "
                       r"asset root '.*asset' \(asset_root= / MORPHKIT_ASSET_ROOT widens it\), got "
                       r"'\.\./gltf_buffer_0\.bin', outside it \(not opened\)"):
        load_mesh(tmp_path / "asset" / "m.gltf")
    assert len(load_mesh(tmp_path / "asset" / "m.gltf", asset_root=tmp_path).faces) == 12


def _fifo_asset(tmp_path: Path, kind: str) -> tuple[Path, str]:
    """A mesh file one of whose references is a FIFO; the message expected."""
    if kind == "mtl":
        obj = _obj(tmp_path, "f.mtl")
        os.mkfifo(tmp_path / "f.mtl")
        return obj, r"material library 'f\.mtl' of mesh file '.*m\.obj': expected a regular file, got " \
                    r"'.*f\.mtl': a FIFO \(named pipe\)"
    if kind == "texture":
        obj = _obj(tmp_path, "m.mtl")
        (tmp_path / "m.mtl").write_text("newmtl SENTINEL_MATERIAL\nKd 1 1 1\nmap_Kd t.png\n")
        os.mkfifo(tmp_path / "t.png")
        return obj, r"texture 't\.png' of material 'SENTINEL_MATERIAL' \(m\.mtl\) of mesh file '.*m\.obj': " \
                    r"expected a regular file, got '.*t\.png': a FIFO \(named pipe\)"
    trimesh.creation.box().export(tmp_path / "m.gltf")
    (tmp_path / "gltf_buffer_0.bin").unlink()
    os.mkfifo(tmp_path / "gltf_buffer_0.bin")
    return tmp_path / "m.gltf", r"buffer 0 'gltf_buffer_0\.bin' of mesh file '.*m\.gltf': expected a " \
                                r"regular file, got '.*gltf_buffer_0\.bin': a FIFO \(named pipe\)"


@pytest.mark.parametrize("kind", ["mtl", "texture", "buffer"])
def test_a_fifo_a_mesh_refers_to_is_a_clear_error_not_a_hang(tmp_path, kind):
    path, message = _fifo_asset(tmp_path, kind)
    code = ("import sys\nfrom morphkit.errors import MeshError\nfrom morphkit.meshes import load_mesh\n"
            "try:\n    load_mesh(sys.argv[1])\nexcept MeshError as e:\n    print(e)\n")
    done = subprocess.run([sys.executable, "-c", code, str(path)], env=ENV, capture_output=True, text=True,
                          timeout=60)
    assert re.fullmatch(message, done.stdout.strip()), done.stdout + done.stderr


def test_billboards_with_a_fifo_texture_stops_with_one_line(tmp_path):
    path, message = _fifo_asset(tmp_path / "asset", "texture")
    done = subprocess.run([sys.executable, "-m", "morphkit", "billboards", "--asset", str(path), "--n", "2",
                           "--views", "8",  # given: no line saying which views were chosen
                           "--frames", "1", "-o", str(tmp_path / "out")], env=ENV, capture_output=True,
                          text=True, timeout=60)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 1 and len(lines) == 1, done.stderr
    assert re.fullmatch("morphkit: error: " + message, lines[0]), lines[0]
    assert not (tmp_path / "out").exists()  # refused before any work


def test_a_bake_library_with_a_fifo_texture_bakes_the_rest(tmp_path):
    lib = tmp_path / "lib"
    _fifo_asset(lib, "texture")
    trimesh.creation.box([1.0, 0.6, 0.8]).export(lib / "box.ply")
    done = subprocess.run([sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(tmp_path / "out")],
                          env=ENV, capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    assert "failed: m: MeshError: texture 't.png' of material 'SENTINEL_MATERIAL' (m.mtl) of mesh file " \
           in done.stderr and "expected a regular file" in done.stderr
    assert "1 baked, 0 skipped, 1 failed" in done.stdout + done.stderr
    assert (tmp_path / "out" / "box.atlas.npz").is_file()
