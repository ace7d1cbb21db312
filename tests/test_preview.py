"""morphkit preview: the page's data and file (no browser), and the page drawn in headless Chromium held to
morphkit's own render of the same camera and sun (``browser``), its hard cases and a video it plays."""

from __future__ import annotations

import base64
import json
import os
import re
import zlib
from pathlib import Path

import numpy as np
import pytest

from morphkit import tol
from morphkit.billboard.analytic import sphere_dome_asset, sphere_impostor
from morphkit.cli import main
from morphkit.errors import OutputExistsError, ValidationError
from morphkit.export.browser import READY, Browser, browser_available
from morphkit.export.page import THREE_VERSION
from morphkit.export.preview import (
    GROUND_ALBEDO,
    SKY,
    PreviewView,
    asset_entry,
    preview_data,
    write_preview,
)
from morphkit.export.previewref import reference_image
from morphkit.imaging.metrics import psnr
from morphkit.sunlit.sunatlas import sphere_sun_atlas
from morphkit.views.domecameras import direction

ROOT = Path(__file__).resolve().parent.parent
ONE = np.array([[0.0, 0.0, 0.0, 0.0, 1.0]])


@pytest.fixture(scope="module")
def ball():
    return sphere_dome_asset(size=48, levels=1), sphere_sun_atlas()


def _data(asset, atlas, view, instances=ONE, **kw):
    return preview_data([asset_entry(asset, atlas, instances)], view, asset.pivot, 1.0, title="ball", **kw)


# ---------------------------------------------------------------------------------------------- no browser
def test_a_view_says_itself_as_a_url_fragment_and_refuses_nonsense():
    v = PreviewView(30.0, 20.5, 3.25, 45.0, 120.0, 35.0, 320, 240)
    assert v.fragment() == "camera=30,20.5,3.25&fov=45&sun=120,35&size=320x240"
    cam = v.camera(np.zeros(3))
    # the camera sits at the fragment's direction and distance, looking at the target
    np.testing.assert_allclose(np.linalg.norm(cam.position), 3.25)
    np.testing.assert_allclose(cam.axis, -cam.position / 3.25, atol=1e-12)
    assert cam.shape == (240, 320)
    with pytest.raises(ValidationError, match=r"elevation_deg: expected degrees in \[-89, 89\]"):
        PreviewView(elevation_deg=90.0)
    with pytest.raises(ValidationError, match="distance: expected > 0"):
        PreviewView(distance=0.0)
    with pytest.raises(ValidationError, match="fov_deg: expected a finite number"):
        PreviewView(fov_deg=float("nan"))


def test_the_page_data_packs_the_views_as_stored(ball):
    asset, atlas = ball
    e = asset_entry(asset, atlas, ONE)
    rec = asset.record()

    def unpack(s, dtype):
        return np.frombuffer(zlib.decompress(base64.b64decode(s)), dtype)

    assert np.array_equal(unpack(e["rgba"], np.uint8), rec.rgba.reshape(-1))
    normal = unpack(e["normal"], np.uint8).reshape(*rec.normal.shape[:3], 4)
    assert np.array_equal(normal[..., :3].astype(np.int16) - 128, rec.normal)
    depth = unpack(e["depth"], np.float16)
    stored = rec.depth.reshape(-1)
    assert np.array_equal(depth[np.isfinite(stored)], stored[np.isfinite(stored)])
    assert np.all(depth[~np.isfinite(stored)] == np.float16(65504.0))  # the page's empty texel
    assert len(e["views"]) == asset.dome.views and len(e["dome"]["triangles"]) == len(asset.dome.triangles())
    # each triangle's inverse gives the dome's own barycentric weights
    views, weights = asset.dome.weights(33.0, 41.0)
    t = e["dome"]["triangles"].index(views.tolist())
    lam = np.asarray(e["dome"]["inverse"][t]).reshape(3, 3) @ direction(33.0, 41.0)
    np.testing.assert_allclose(lam / lam.sum(), weights, atol=1e-9)
    assert e["sun_atlas"]["size"] == atlas.size


def test_the_page_refuses_views_past_webgl_s_texture_side_and_bad_instances(ball, monkeypatch):
    asset, atlas = ball
    monkeypatch.setattr(tol, "EXPORT_MAX_TEXTURE_SIDE", 32)
    with pytest.raises(ValidationError, match=r"views: expected sides of at most 32 px .*WebGL.*got 48 px"):
        asset_entry(asset, atlas, ONE)
    monkeypatch.undo()
    with pytest.raises(ValidationError, match=r"instances: expected \(N, 5\) finite"):
        asset_entry(asset, atlas, np.array([[0.0, 0.0, 0.0, 0.0, -1.0]]))
    with pytest.raises(ValidationError, match="asset: expected a DomeAsset, got str"):
        asset_entry("tree", atlas, ONE)


def test_the_page_is_one_file_that_loads_nothing_and_counts_its_bytes(ball, tmp_path):
    asset, atlas = ball
    path = write_preview(tmp_path / "p.html", _data(asset, atlas, PreviewView()))
    html = path.read_text()
    assert f"three.js {THREE_VERSION}" in html
    # no element loads anything from outside: no src/href attributes, no <link>
    assert not re.search(r"<(script|img|link|iframe|video)[^>]*\s(src|href)=", html)
    data = json.loads(re.search(r'<script type="application/json" id="morphkit-data">(.*?)</script>', html,
                                re.S).group(1))
    assert int(data["page_bytes"]) == path.stat().st_size
    # the import map's modules are data: URLs
    imap = re.search(r'<script type="importmap">(.*?)</script>', html, re.S).group(1)
    imports = json.loads(imap)["imports"]
    assert set(imports) >= {"three", "three/addons/loaders/GLTFLoader.js"}
    assert all(u.startswith("data:text/javascript;base64,") for u in imports.values())


def test_an_existing_page_is_kept_unless_overwrite_is_given(ball, tmp_path):
    asset, atlas = ball
    p = tmp_path / "p.html"
    p.write_text("mine")
    with pytest.raises(OutputExistsError, match="expected a new file, or --overwrite to replace it"):
        write_preview(p, _data(asset, atlas, PreviewView()))
    assert p.read_text() == "mine"
    write_preview(p, _data(asset, atlas, PreviewView()), overwrite=True)
    assert p.read_text().startswith("<!DOCTYPE html>")
    with pytest.raises(ValidationError, match=r"-o: expected an \.html file path, got '.*p\.txt'"):
        write_preview(tmp_path / "p.txt", {})


def test_a_page_without_a_sun_atlas_says_its_asset_casts_no_shadow(ball):
    asset, _ = ball
    data = _data(asset, None, PreviewView())
    assert data["notes"] == ["ball: no sun atlas, so it casts no shadow here"]
    assert data["assets"][0]["sun_atlas"] is None


def test_the_reference_s_ground_is_the_analytic_lit_ground_and_shadowed_under_a_sun_overhead(ball):
    asset, atlas = ball
    # camera looking down from 6 units, the sun at 45 degrees over +x: the ball (radius 0.6 about
    # (0, 0, 1)) shadows the ground about (-1, 0, 0), ambient light only there; the ground at +x is
    # lit, encode(rho (a + I/pi sin 45))
    view = PreviewView(0.0, 89.0, 6.0, 40.0, 0.0, 45.0, 96, 96)
    img = reference_image(asset, atlas, ONE, view, np.array([0.0, 0.0, 0.0]))
    from morphkit.billboard.baking.bakelook import BAKE_AMBIENT
    from morphkit.sunpath import SUN_INTENSITY

    lit = (np.asarray(GROUND_ALBEDO) * (BAKE_AMBIENT + SUN_INTENSITY / np.pi * np.sin(np.radians(45.0))))
    dark = np.asarray(GROUND_ALBEDO) * BAKE_AMBIENT
    cam = view.camera(np.zeros(3))
    px, _ = cam.project(np.array([[1.5, 0.0, 0.0], [-1.2, 0.0, 0.0], [-1.0, 0.3, 0.0]]))
    (u0, v0), (u1, v1), (u2, v2) = np.rint(px).astype(int)
    np.testing.assert_allclose(img[v0, u0], lit ** (1 / 2.2), atol=1e-5)
    np.testing.assert_allclose(img[v1, u1], dark ** (1 / 2.2), atol=1e-5)
    np.testing.assert_allclose(img[v2, u2], dark ** (1 / 2.2), atol=1e-5)
    assert not np.allclose(SKY, lit)


def test_the_preview_command_writes_a_page_of_a_dome_asset_file_and_keeps_an_existing_one(ball, tmp_path,
                                                                                         capsys):
    asset, _ = ball
    npz = asset.save(tmp_path / "ball.npz")
    out = tmp_path / "ball.html"
    assert main(["preview", str(npz), "-o", str(out), "--camera", "30,20,4", "--sun", "100,40"]) == 0
    said = capsys.readouterr().out
    assert "an asset, 1 instances" in said and "no sun atlas, so it casts no shadow here" in said
    assert "no octahedral impostor beside it (an asset file has no mesh to bake it from)" in said
    assert "#camera=30,20,4&fov=40&sun=100,40&size=640x480" in said
    assert main(["preview", str(npz), "-o", str(out)]) == 2
    assert "expected a new file, or --overwrite" in capsys.readouterr().err
    assert main(["preview", str(npz), "-o", str(out), "--camera", "30,20"]) == 2
    assert "--camera: expected 3 finite numbers separated by commas, got '30,20'" in capsys.readouterr().err
    assert main(["preview", str(tmp_path / "nothere.glb"), "-o", str(tmp_path / "n.html")]) == 1
    assert "ASSET_OR_SCENE: expected an existing .glb or .gltf file, got" in capsys.readouterr().err
    assert not (tmp_path / "n.html").exists()


# ------------------------------------------------------------------------------------------------ browser
def _need_browser() -> None:
    why = browser_available()
    if why is not None:
        if os.environ.get("MORPHKIT_REQUIRE_BROWSER"):
            pytest.fail(f"the browser test cannot run: {why}")
        pytest.skip(why)


@pytest.fixture(scope="module")
def browser():
    _need_browser()
    with Browser(window=(700, 560)) as b:
        yield b


#: Three cameras and suns of the held-out comparison: low, high and from behind against the sun.
VIEWS = (PreviewView(30.0, 20.0, 2.2, 40.0, 135.0, 45.0, 320, 240),
         PreviewView(-100.0, 45.0, 2.0, 40.0, 60.0, 30.0, 320, 240),
         PreviewView(170.0, 5.0, 2.6, 40.0, -40.0, 60.0, 320, 240))


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    from morphkit.programs.export import bake_asset_parts

    parts = bake_asset_parts("tree")
    page = tmp_path_factory.mktemp("tree") / "tree.html"
    write_preview(page, preview_data([asset_entry(parts.asset, parts.sun_atlas, ONE)], VIEWS[0],
                                     parts.asset.pivot, 1.0, title="tree"))
    return parts, page


@pytest.mark.browser
@pytest.mark.gl
def test_the_page_draws_what_morphkit_draws_at_three_cameras(browser, tree):
    """The page's canvas against morphkit's own render of the same camera and sun
    (:func:`~morphkit.export.previewref.reference_image`), PSNR >= 30 dB: the issue's target. The two
    compute the same morph in float32 on different machines (SwiftShader's GLSL against numpy and
    OpenCV), so they differ by rounding at silhouettes and shadow edges, not by the method."""
    parts, page = tree
    for i, view in enumerate(VIEWS):
        shot = browser.show(page, view.fragment()) if i == 0 else browser.redraw(view.fragment())
        assert shot.title == READY and not shot.errors, shot.errors
        assert shot.image.shape == (240, 320, 3)
        ref = reference_image(parts.asset, parts.sun_atlas, ONE, view, parts.asset.pivot)
        assert psnr(shot.image, ref, data_range=1.0) >= 30.0, i
        assert shot.stats["instances"] == 1 and shot.stats["shadow_texels"] == parts.sun_atlas.size
    # and nothing was fetched but the page itself and its inlined modules
    urls = browser.requests()
    assert urls and all(u.startswith(("file:", "data:")) for u in urls), [u[:80] for u in urls]


@pytest.mark.browser
@pytest.mark.gl
def test_the_page_errs_against_the_real_mesh_as_morphkit_s_morph_does(browser, tree):
    """Against the real mesh (rendered, its ground shadow ray cast: ``truth_image``) the page's PSNR is
    within 1 dB of morphkit's own morph's (the issue's target)."""
    from morphkit.export.previewref import truth_image
    from morphkit.render import Renderer

    parts, page = tree
    items = parts.asset.items(parts.mesh)
    with Renderer() as r:
        for i, view in enumerate(VIEWS):
            shot = browser.show(page, view.fragment()) if i == 0 else browser.redraw(view.fragment())
            truth = truth_image(parts.mesh, items, r, view, parts.asset.pivot)
            ref = reference_image(parts.asset, parts.sun_atlas, ONE, view, parts.asset.pivot)
            gap = psnr(ref, truth, data_range=1.0) - psnr(shot.image, truth, data_range=1.0)
            assert abs(gap) <= 1.0, (i, gap)


def test_an_impostor_is_packed_with_its_frames_as_stored_and_their_axes(ball):
    from morphkit.export.preview import impostor_entry

    _, atlas = ball
    imp = sphere_impostor()
    e = impostor_entry(imp, atlas, ONE)
    assert e["kind"] == "impostor" and e["frames"] == 8 and e["size"] == 32
    axes = np.asarray(e["frame_axes"]).reshape(3, 64, 4)[..., :3]
    np.testing.assert_allclose(axes[0], imp.frame_dirs, atol=1e-7)
    np.testing.assert_allclose(axes[2], imp.frame_up, atol=1e-7)
    depth = np.frombuffer(zlib.decompress(base64.b64decode(e["depth"])), np.float16).reshape(64, 32, 32)
    stored = imp.stored_frame(5).depth
    assert np.array_equal(depth[5][np.isfinite(stored)], stored[np.isfinite(stored)])
    assert e["view_bytes"] == 64 * 32 * 32 * 9
    with pytest.raises(ValidationError, match="impostor: expected an OctahedralImpostor, got DomeAsset"):
        impostor_entry(ball[0], atlas, ONE)


@pytest.mark.browser
def test_the_page_s_impostor_draws_what_morphkit_s_impostor_draws(browser, ball, tmp_path):
    """The octahedral impostor's shader (one parallax step a frame, the engines') against
    :func:`~morphkit.export.previewref.impostor_rays` along the same rays: PSNR >= 30 dB, as the
    morph's (float rounding at silhouettes, not the method)."""
    from morphkit.export.preview import impostor_entry

    _, atlas = ball
    imp = sphere_impostor()
    view = PreviewView(40.0, 25.0, 4.0, 40.0, 120.0, 40.0, 320, 240)
    page = write_preview(tmp_path / "imp.html", preview_data([impostor_entry(imp, atlas, ONE)], view,
                                                             imp.pivot, 1.0, title="impostor"))
    shot = browser.show(page, view.fragment())
    assert shot.title == READY and not shot.errors, shot.errors
    ref = reference_image(imp, atlas, ONE, view, imp.pivot)
    assert psnr(shot.image, ref, data_range=1.0) >= 30.0
    # and the ball is drawn: its pixels are neither ground nor sky
    ground = reference_image(imp, None, np.zeros((0, 5)), view, imp.pivot)
    assert np.abs(ref - ground).max(axis=2).mean() > 0.02


@pytest.mark.browser
def test_the_sun_slider_moves_the_shadow(browser, ball, tmp_path):
    asset, atlas = ball
    page = write_preview(tmp_path / "b.html", _data(asset, atlas, VIEWS[0]))
    a = browser.show(page, VIEWS[0].fragment())
    b = browser.trigger("const s = document.getElementById('sun-az');"
                        "s.value = -45; s.dispatchEvent(new Event('input'));")
    assert a.title == b.title == READY
    assert "sun=-45,45" in browser.run_script("return location.hash")  # the fragment follows the slider
    moved = np.abs(a.image - b.image).max(axis=2) > 0.05
    assert moved.mean() > 0.01  # the shadow left one side of the ball for the other


@pytest.mark.browser
def test_a_browser_without_webgl_is_told_so_instead_of_a_blank_canvas(ball, tmp_path):
    _need_browser()
    asset, atlas = ball
    page = write_preview(tmp_path / "b.html", _data(asset, atlas, PreviewView()))
    with Browser(webgl=False, window=(400, 300)) as b:
        shot = b.show(page)
    assert shot.title == "morphkit: no WebGL" and shot.image is None
    assert "This page needs WebGL 2" in shot.message


@pytest.mark.browser
def test_a_page_without_a_sun_atlas_draws_and_says_so_on_the_page(browser, ball, tmp_path):
    asset, _ = ball
    page = write_preview(tmp_path / "n.html", _data(asset, None, VIEWS[0]))
    shot = browser.show(page, VIEWS[0].fragment())
    assert shot.title == READY and shot.stats["shadow_texels"] == 0
    assert "no sun atlas, so it casts no shadow here" in browser.run_script(
        "return document.getElementById('figures').textContent")


@pytest.mark.browser
def test_a_glb_from_another_tool_is_previewed_as_meshes(browser, tmp_path, capsys):
    out = tmp_path / "crate.html"
    assert main(["preview", str(ROOT / "morphkit" / "data" / "photo_crate.glb"), "-o", str(out)]) == 0
    assert "meshes (a glTF file from another tool)" in capsys.readouterr().out
    shot = browser.show(out, "size=320x240")
    assert shot.title == READY and not shot.errors, shot.errors
    # the crate stands in the middle of the picture: its pixels are neither sky nor ground
    centre = shot.image[90:150, 140:180].reshape(-1, 3)
    corner = shot.image[:20, :20].reshape(-1, 3)
    assert np.abs(centre.mean(0) - corner.mean(0)).max() > 0.05


@pytest.mark.browser
@pytest.mark.slow
def test_a_scene_of_100k_instances_is_instanced_and_its_page_stays_small(browser, ball, tmp_path):
    asset, atlas = ball
    side = 317  # 100,489 instances on a grid 2 units apart
    g = (np.arange(side) - side / 2) * 2.0
    x, y = np.meshgrid(g, g)
    rng = np.random.default_rng(3)
    inst = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size), rng.uniform(-180, 180, x.size),
                            rng.uniform(0.6, 1.4, x.size)])
    view = PreviewView(30.0, 25.0, 40.0, 40.0, 135.0, 45.0, 320, 240)
    page = write_preview(tmp_path / "field.html", preview_data([asset_entry(asset, atlas, inst)], view,
                                                               np.zeros(3), 400.0, title="field"))
    assert page.stat().st_size <= 20_000_000  # the page bound
    shot = browser.show(page, view.fragment())
    assert shot.title == READY and not shot.errors, shot.errors
    assert shot.stats["instances"] == len(inst)
    assert shot.stats["shadow_texels"] == 2048  # the scene's light view, capped


@pytest.mark.browser
def test_the_browser_plays_the_videos_morphkit_writes(browser, tmp_path):
    from morphkit.programs.video import VIDEO_SUFFIX, VideoFile

    rng = np.random.default_rng(0)
    path = tmp_path / f"clip{VIDEO_SUFFIX}"
    with VideoFile(path, 10.0, (64, 96)) as v:
        for _ in range(20):
            v.write(rng.integers(0, 256, (64, 96, 3), dtype=np.uint8))
    page = tmp_path / "video.html"
    page.write_text(f'<!DOCTYPE html><video id="v" muted src="{path.name}"></video>')
    browser.load(page)
    played = browser.run_script(
        "const v = document.getElementById('v');"
        "return new Promise((ok) => { v.onended = () => ok([v.videoWidth, v.videoHeight, v.currentTime]);"
        "v.onerror = () => ok(['error', v.error && v.error.code]); v.play(); });")
    assert played[:2] == [96, 64] and played[2] > 1.5, played


@pytest.mark.browser
@pytest.mark.gl
@pytest.mark.slow
def test_the_forest_scene_s_page_starts_at_its_camera_and_sun_and_stays_small(browser, tmp_path, capsys):
    out = tmp_path / "forest.html"
    assert main(["preview", str(ROOT / "samples" / "scenes" / "forest.json"), "-o", str(out)]) == 0
    said = capsys.readouterr().out
    # the scene's first camera key (eye (-12, -16, 1.7) at the target (-4, -6, 1.5), 55 degrees) and sun
    assert "a scene, 90 instances" in said and "&fov=55&sun=150,48&" in said
    assert out.stat().st_size <= 20_000_000  # the bound for the demo scene's page
    shot = browser.show(out, "size=320x240")
    assert shot.title == READY and not shot.errors, shot.errors
    assert shot.stats["instances"] == 90 and shot.stats["shadow_texels"] > 0
    # trees, people and crates stand in front of the sky: the picture is not the empty ground
    assert np.abs(shot.image - shot.image.mean(axis=(0, 1))).max() > 0.3


@pytest.mark.browser
def test_turned_scaled_and_moved_instances_draw_as_morphkit_draws_them(browser, ball, tmp_path):
    """Three balls (the analytic sphere's checker turns with its yaw) at other places, yaws and
    scales, against morphkit's render of the same instances: the instance frames of the shader
    (object from world, the sun turned by the yaw) are morphkit's. The page's one light view of the
    scene has the sun atlas's texel density, morphkit's one light view per instance: PSNR >= 30 dB."""
    asset, atlas = ball
    inst = np.array([[0.0, 0.0, 0.0, 0.0, 1.0], [2.5, 0.5, 0.0, 70.0, 0.7], [-1.0, 2.6, 0.0, -135.0, 1.3]])
    view = PreviewView(20.0, 30.0, 8.0, 40.0, 150.0, 40.0, 320, 240)
    target = np.array([0.5, 1.0, 0.8])
    page = write_preview(tmp_path / "three.html", preview_data([asset_entry(asset, atlas, inst)], view,
                                                               target, 3.0, title="three"))
    shot = browser.show(page, view.fragment())
    assert shot.title == READY and not shot.errors, shot.errors
    ref = reference_image(asset, atlas, inst, view, target)
    assert psnr(shot.image, ref, data_range=1.0) >= 30.0
    # the yaws matter: the same balls unturned draw another picture
    flat = reference_image(asset, atlas, inst * [1, 1, 1, 0, 1], view, target)
    assert psnr(flat, ref, data_range=1.0) < psnr(shot.image, ref, data_range=1.0) - 3.0
