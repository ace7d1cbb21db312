"""Shadows in a relit billboard frame (issue 26, receivers): the hard cases.

The analytic sphere's atlases (radius 0.6 about ``(0, 0, 1)``, no GL, as in
``tests/test_fieldshadow.py``) give the field's shadows without rendering; the frame tests
(``render``) use a small box asset, tiny frames and 16-texel atlases.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.billboard.analytic import SPHERE_PIVOT, SPHERE_RADIUS, sphere_view
from morphkit.billboard.frames.instances import Instances
from morphkit.cli import main
from morphkit.errors import ValidationError
from morphkit.imaging.shading import shade_suns, sun_shadow_factor
from morphkit.sunlit.receivers import (
    AtlasShadow,
    FilteredAtlasShadow,
    FrameShadow,
    bake_scene_atlases,
    frame_receiver,
    sun_disc,
)
from morphkit.sunlit.sunatlas import SunAtlas, sun_direction
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras
from morphkit.views.gbuffer import ViewSurface

DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
N = 48
TPU = 30.0


@pytest.fixture(scope="module")
def atlases() -> dict[str, SunAtlas]:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (N, N))
    depths = [sphere_view(cams.ortho_camera(a, e, (N, N)))[2]
              for a, e in zip(DOME.azimuths_deg(), DOME.elevations_deg(), strict=True)]
    return {"ball": SunAtlas.from_depths(DOME, cams, np.stack(depths))}


def _grid(x0: float, y0: float, x1: float, y1: float, n: int = 60) -> np.ndarray:
    X, Y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def _shadowed_truth(points: np.ndarray, centre: np.ndarray, sun: np.ndarray) -> np.ndarray:
    v = centre - points
    along = v @ sun
    return (np.linalg.norm(v - along[:, None] * sun, axis=1) < SPHERE_RADIUS) & (along > 0)


def _vis(atlases, inst, sun, ground, visible=(), samples=1, disc=0.267) -> np.ndarray:
    fs = AtlasShadow(atlases, samples=samples, disc_deg=disc, texels_per_unit=TPU).frame(
        inst, [sun], ground, np.asarray(visible, np.int64))
    return fs.visibility(ground)[0]


def test_a_filtered_sun_disc_is_the_hard_shadow_at_zero_radius_and_soft_beyond(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    g = _grid(-3.0, -3.0, 1.0, 1.0, 120)
    sun = sun_direction(0.0, 45.0)  # the shadow falls towards -x
    hard = _vis(atlases, inst, sun, g, [0])

    def filtered(disc: float) -> np.ndarray:
        shadow = FilteredAtlasShadow(atlases, disc_deg=disc, texels_per_unit=TPU)
        return shadow.frame(inst, [sun], g, np.array([0])).visibility(g)[0]

    np.testing.assert_array_equal(filtered(0.0), hard)
    soft = filtered(3.0)
    pen = (soft > 0.0) & (soft < 1.0)
    assert pen.sum() > 3 * ((hard > 0.0) & (hard < 1.0)).sum() + 100  # a penumbra where hard had none
    # the umbra lies inside the hard shadow, and the hard shadow is (all but its rim) darkened
    assert np.all(hard[soft == 0.0] == 0.0) and (soft == 0.0).sum() > 100
    assert (soft[hard == 0.0] < 1.0).mean() > 0.95
    with pytest.raises(ValidationError, match="radius"):
        FilteredAtlasShadow(atlases, disc_deg=90.0)


def test_a_filtered_sun_draws_its_one_map_finer_by_the_map_scale(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    g = _grid(-3.0, -3.0, 1.0, 1.0, 40)
    sun = sun_direction(0.0, 45.0)
    plain, filt = AtlasShadow(atlases), FilteredAtlasShadow(atlases, disc_deg=0.5)
    plain.frame(inst, [sun], g, np.array([0]))
    filt.frame(inst, [sun], g, np.array([0]))
    (mp,), (mf,) = plain.last_maps, filt.last_maps
    assert mf.camera.fx == pytest.approx(tol.SUN_DISC_MAP_SCALE * mp.camera.fx, rel=1e-9)
    given = FilteredAtlasShadow(atlases, disc_deg=0.5, texels_per_unit=TPU)
    given.frame(inst, [sun], g, np.array([0]))
    assert given.last_maps[0].camera.fx == pytest.approx(TPU, rel=1e-9)  # a resolution given is kept


# ------------------------------------------------------------------ the sun's disc
def test_sun_disc_one_sample_is_the_centre_and_n_samples_lie_on_the_disc():
    d = sun_direction(40.0, 30.0)
    assert np.allclose(sun_disc(d, 1, 5.0), d[None])
    many = sun_disc(d, 16, 2.0)
    ang = np.degrees(np.arccos(np.clip(many @ d, -1, 1)))
    assert many.shape == (16, 3) and ang.max() < 2.0 and ang.min() > 0.0
    assert np.degrees(np.arccos(np.clip(many.mean(0) @ d / np.linalg.norm(many.mean(0)), -1, 1))) < 0.3


@pytest.mark.parametrize("n, r", [(0, 1.0), (tol.MAX_SUN_SAMPLES + 1, 1.0), (4, -1.0),
                                  (4, tol.MAX_SUN_DISC_DEG + 1)])
def test_sun_disc_refuses_counts_and_radii_out_of_range(n, r):
    with pytest.raises(ValidationError, match="sun"):
        sun_disc(np.array([0.0, 0.0, 1.0]), n, r)


# ------------------------------------------------------------------ the model's visibility
def test_shade_suns_visibility_scales_the_sun_terms_only():
    h, w = 2, 3
    albedo = np.full((h, w, 4), 0.5, np.float32)
    albedo[..., 3] = 1.0
    normal = np.zeros((h, w, 3), np.float32)
    normal[..., 2] = 1.0
    surf = ViewSurface(albedo, normal, np.ones((h, w), np.float32))
    terms = np.array([[0.0, 0.0, 0.6]], np.float32)
    lit = shade_suns(surf, 0.2, terms)
    dark = shade_suns(surf, 0.2, terms, np.zeros((h, w), np.float32))
    half = shade_suns(surf, 0.2, terms, np.full((1, h, w), 0.5, np.float32))
    assert np.allclose(lit[..., 0], 0.5 * 0.8) and np.allclose(dark[..., 0], 0.5 * 0.2)
    assert np.allclose(half[..., 0], 0.5 * 0.5)
    with pytest.raises(ValidationError, match="visibility"):
        shade_suns(surf, 0.2, terms, np.zeros((2, h, w), np.float32))
    f = sun_shadow_factor(np.array([0.0, 0.0, 1.0]), 0.2, terms, np.array([0.0, 1.0]))
    assert np.allclose(f, [0.25, 1.0])


# ------------------------------------------------------------------ hard cases of the field
@pytest.mark.parametrize("elevation", [-10.0, 0.0])
def test_a_sun_at_or_below_the_horizon_shadows_nothing(atlases, elevation):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    fs = AtlasShadow(atlases).frame(inst, [sun_direction(30.0, elevation)], _grid(-3, -3, 3, 3),
                                    np.array([0]))
    assert not fs.casts and np.all(fs.visibility(_grid(-3, -3, 3, 3)) == 1.0)


def test_a_grazing_sun_is_clamped_not_refused(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    g = _grid(-1.0, -12.0, 1.0, 1.0, 80)
    vis = _vis(atlases, inst, sun_direction(90.0, 1.0), g, [0])
    assert 0 < int((vis < 0.5).sum()) and np.all(np.isfinite(vis))


def test_a_sun_straight_above_shadows_the_ground_under_the_ball(atlases):
    inst = Instances.from_records([("ball", 1.0, -1.0, 33.0)])
    g = _grid(-1.0, -3.0, 3.0, 1.0)
    sun = np.array([0.0, 0.0, 1.0])
    vis = _vis(atlases, inst, sun, g, [0])
    truth = _shadowed_truth(g, np.array([1.0, -1.0, 0.0]) + SPHERE_PIVOT, sun)
    assert ((vis < 0.5) == truth).mean() > 0.98 and truth.sum() > 10


def test_a_caster_outside_the_frame_still_shadows_the_ground_inside_it(atlases):
    # the ball stands at x = -4, out of the frame's ground [0, 3]^2; a low sun from -x
    # throws its shadow (over 10 units long) across the frame
    inst = Instances.from_records([("ball", -4.0, 1.5)])
    sun = sun_direction(180.0, 8.0)
    frame_ground = _grid(0.0, 0.0, 3.0, 3.0)
    rect = frame_receiver(frame_ground, *AtlasShadow(atlases).field.spheres(inst), np.zeros(0, np.int64), sun)
    assert rect is not None and rect[0] <= 0.0 and rect[2] >= 3.0  # it covers the frame's ground
    vis = _vis(atlases, inst, sun, frame_ground)
    truth = _shadowed_truth(frame_ground, np.array([-4.0, 1.5, 0.0]) + SPHERE_PIVOT, sun)
    assert truth.sum() > 20 and ((vis < 0.5) == truth).mean() > 0.97


def test_a_caster_inside_the_frame_whose_shadow_falls_outside_is_kept_and_lights_the_frame(atlases):
    inst = Instances.from_records([("ball", 1.5, 1.5)])
    sun = sun_direction(180.0, 20.0)  # the shadow runs towards +x, out of the frame [0, 2]^2 ... mostly
    frame_ground = _grid(0.0, 0.0, 1.0, 3.0)  # the ground on the sun's side of the ball
    shadow = AtlasShadow(atlases, texels_per_unit=TPU)
    vis = shadow.frame(inst, [sun], frame_ground, np.array([0])).visibility(frame_ground)[0]
    assert np.all(vis == 1.0)
    assert [list(m.kept) for m in shadow.last_maps] == [[0]]  # drawn: it receives, it is seen


def test_two_instances_at_the_same_spot_cast_one_shadow(atlases):
    g = _grid(-3.0, -3.0, 3.0, 3.0)
    sun = sun_direction(-40.0, 45.0)
    one = _vis(atlases, Instances.from_records([("ball", 0.2, 0.1, 10.0)]), sun, g, [0])
    same = _vis(atlases, Instances.from_records([("ball", 0.2, 0.1, 10.0), ("ball", 0.2, 0.1, 10.0)]),
                sun, g, [0, 1])
    assert (one < 0.5).sum() > 10 and np.array_equal(one, same)
    # turned another way, the ball's points come from other atlas views: the same shadow up to
    # its outline (the grid's step is 1.2 field texels here)
    turned = _vis(atlases, Instances.from_records([("ball", 0.2, 0.1, 10.0), ("ball", 0.2, 0.1, 70.0)]),
                  sun, g, [0, 1])
    assert np.count_nonzero((one < 0.5) != (turned < 0.5)) <= 0.05 * np.count_nonzero(one < 0.5)


def test_zero_instances_shadow_nothing(atlases):
    empty = Instances(("ball",), np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0), np.zeros(0))
    fs = AtlasShadow(atlases).frame(empty, [sun_direction(0.0, 40.0)], _grid(-1, -1, 1, 1), np.zeros(0))
    assert not fs.casts and np.all(fs.visibility(_grid(-1, -1, 1, 1)) == 1.0)


def test_a_soft_sun_averages_its_directions(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0)])
    g = _grid(-2.0, -2.0, 2.0, 2.0, 120)
    sun = sun_direction(0.0, 50.0)
    soft = _vis(atlases, inst, sun, g, [0], samples=8, disc=6.0)
    hard = _vis(atlases, inst, sun, g, [0])
    levels = np.unique(np.round(soft * 8))
    assert np.allclose(soft * 8, np.round(soft * 8), atol=1e-4)  # steps of 1/N
    assert len(levels) > 3 and abs(float((soft < 0.5).mean()) - float((hard < 0.5).mean())) < 0.01


def test_frame_shadow_moves_receivers_along_their_normal():
    seen = []
    fs = FrameShadow([([lambda p: seen.append(p.copy()) or np.ones(len(p), np.float32)], 0.5)])
    fs.visibility(np.zeros((2, 3)), np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    fs.visibility(np.zeros((1, 3)))
    assert np.allclose(seen[0], [[0, 0, 0.5], [0.5, 0, 0]]) and np.allclose(seen[1], 0.0)


# ------------------------------------------------------------------ atlases on demand
def test_an_atlas_of_another_mesh_is_refused_naming_the_hash(atlases):
    box = trimesh.creation.box((0.4, 0.4, 1.0))
    with pytest.raises(ValidationError, match=r"asset 'ball'.*hash 000000000000"):
        bake_scene_atlases({"ball": box}, renderer=None, atlases=dict(atlases))  # type: ignore[arg-type]


@pytest.mark.gl
def test_an_asset_without_an_atlas_gets_one_baked_on_demand_and_kept(renderer):
    box = trimesh.creation.box((0.4, 0.4, 1.0))
    cache: dict[str, SunAtlas] = {}
    got = bake_scene_atlases({"box": box}, renderer, cache, size=16)
    assert got is cache and got["box"].size == 16 and got["box"].dome.views == 21
    again = bake_scene_atlases({"box": box}, renderer, cache, size=16)
    assert again["box"] is got["box"]  # not baked twice
    got["box"].check_mesh(box)


# ------------------------------------------------------------------ frames
@pytest.fixture(scope="module")
def box_scene(renderer):
    from morphkit.billboard import Backdrop, BillboardScene
    from morphkit.billboard.domeasset import bake_dome
    from morphkit.billboard.frames.facing import ViewpointFacing
    from morphkit.meshes import normalize

    box = normalize(trimesh.creation.box((0.4, 0.4, 1.0)))
    asset = bake_dome(box, renderer, name="box", size=24, levels=1, appearance="checker")
    inst = Instances.from_records([("box", 0.0, 0.0, 20.0), ("box", 1.2, 0.4, 65.0)])
    scene = BillboardScene({"box": asset}, inst, backdrop=Backdrop(), facing=ViewpointFacing())
    return scene, {"box": box}, {"box": asset.items(box)}


def _camera():
    from morphkit.camera import look_at, perspective

    pose = look_at(np.array([0.6, -4.0, 2.2]), np.array([0.6, 0.0, 0.3]), up=np.array([0.0, 0.0, 1.0]))
    return perspective(np.radians(50.0), (48, 64), pose)


@pytest.mark.gl
@pytest.mark.parametrize("elevation", [35.0, -5.0])
def test_billboard_and_mesh_frames_darken_the_same_ground(renderer, box_scene, elevation):
    from morphkit.billboard.baking.bakelook import BAKE_AMBIENT
    from morphkit.imaging.shading import Lighting
    from morphkit.sunlit.litmesh import LitMeshMode
    from morphkit.sunlit.litmodes import LitMode
    from morphkit.sunlit.raycast import RayCastShadow
    from morphkit.sunpath import sun

    scene, meshes, items = box_scene
    atl = bake_scene_atlases(meshes, renderer, size=16)
    cam = _camera()
    lighting = Lighting(BAKE_AMBIENT, (sun(150.0, elevation),))
    b0 = LitMode(lighting=lighting).render(scene, cam).rgb.astype(int)
    b1 = LitMode(lighting=lighting, shadow=AtlasShadow(atl)).render(scene, cam).rgb.astype(int)
    m0 = LitMeshMode(renderer, items, lighting).render(scene, cam).rgb.astype(int)
    truth = LitMeshMode(renderer, items, lighting, shadow=RayCastShadow(meshes))
    m1 = truth.render(scene, cam).rgb.astype(int)
    db, dm = (b0 - b1).max(axis=2) >= 3, (m0 - m1).max(axis=2) >= 3
    assert (b1 <= b0 + 1).all() and (m1 <= m0 + 1).all()  # shadows only darken
    if elevation < 0:
        assert not db.any() and not dm.any()
    else:
        assert dm.sum() > 20 and (db & dm).sum() / (db | dm).sum() > 0.5


def test_modes_refuse_a_shadow_that_is_not_one():
    from morphkit.sunlit.litmodes import LitMode

    with pytest.raises(ValidationError, match="SceneShadow"):
        LitMode(shadow="atlas")  # type: ignore[arg-type]


# ------------------------------------------------------------------ command line
@pytest.mark.parametrize("argv, message", [
    (["--shadows", "--sun-path", "day", "--soft", "0"], "--soft: expected an integer"),
    (["--soft", "0"], "--soft: expected an integer"),
    (["--shadows", "--sun-path", "day", "--soft", "2", "--sun-radius", "99"], "--sun-radius"),
    (["--sun-radius", "99"], "--sun-radius: expected degrees in [0, 15]"),
    (["--shadows", "--sun-path", "day", "--soft", "many"], "--soft: expected an integer in [1, 64] or pcss"),
    (["--shadows", "--sun-path", "day", "--sun-atlas-size", "8"], "--sun-atlas-size"),
    (["--shadows", "--sun-path", "day", "--sun-atlas-size", "4096"], "--sun-atlas-size"),
    (["--shadows", "--views", "8"], "--views with --sun-path: expected dome"),
    (["--shadows", "--sun-path", "day", "--views", "8"], "--views with --sun-path: expected dome"),
])
def test_the_cli_refuses_bad_shadow_combinations(tmp_path, capsys, argv, message):
    assert main(["billboards", *argv, "-o", str(tmp_path / "o")]) == 2  # a usage mistake
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and not (tmp_path / "o").exists()


@pytest.mark.parametrize("soft, want", [([], None), (["--soft"], "pcss"), (["--soft", "PCSS"], "pcss"),
                                        (["--soft", "4"], 4)])
def test_soft_alone_is_the_filtered_disc_and_a_count_averages(tmp_path, soft, want):
    from morphkit.cli import build_parser
    from morphkit.programs.cliargs import SOFT_FILTER, check_args

    argv = ["billboards", "--shadows", "--sun-path", "day", *soft, "-o", str(tmp_path)]
    args = build_parser().parse_args(argv)
    check_args(args)
    assert args.soft == want and (want != "pcss" or args.soft == SOFT_FILTER)


@pytest.mark.parametrize("given, shadows, sun_path, soft, said", [
    (["--shadows"], True, "day", None, ["--shadows implies --sun-path day (a default sun)"]),
    (["--soft"], True, "day", "pcss", ["--soft implies --shadows", "--shadows implies --sun-path day"]),
    (["--soft", "4", "--sun-path", "day"], True, "day", 4, ["--soft implies --shadows"]),
    (["--sun-atlas-size", "64"], True, "day", None, ["--sun-atlas-size implies --shadows",
                                                     "--shadows implies --sun-path day"]),
    (["--sun-radius", "2"], True, "day", "pcss", ["--sun-radius implies --soft (pcss)",
                                                  "--soft implies --shadows", "--shadows implies"]),
    (["--sun-path", "day"], False, "day", None, []),
    ([], False, None, None, []),
])
def test_a_sun_option_alone_takes_what_it_needs(tmp_path, given, shadows, sun_path, soft, said):
    from morphkit.cli import build_parser
    from morphkit.programs.cliargs import check_args

    args = build_parser().parse_args(["billboards", *given, "-o", str(tmp_path)])
    check_args(args)
    assert (args.shadows, args.sun_path, args.soft) == (shadows, sun_path, soft)
    assert all(g.startswith(w) for g, w in zip(args.implied, said, strict=True))


def test_the_cli_says_in_one_line_what_a_flag_alone_implied(tmp_path, capsys):
    broken = tmp_path / "broken.ply"  # the run stops at loading it: after the line, before any bake
    broken.write_text("not a mesh")
    assert main(["billboards", "--asset", str(broken), "--shadows", "-o", str(tmp_path / "o")]) == 1
    out, err = capsys.readouterr()
    assert "morphkit billboards: --shadows implies --sun-path day (a default sun)\n" in out
    assert "broken.ply" in err and len(err.strip().splitlines()) == 1 and "--shadows: expected" not in err


def test_the_ground_keeps_its_colour_in_full_sun_and_darkens_under_the_fog():
    from morphkit.billboard import Backdrop, Fog
    from morphkit.imaging.shading import LIT_GAMMA

    cam = _camera()
    for back in (Backdrop(), Backdrop(fog=Fog(density=0.2))):
        hit, pts = back.ground_points(cam)
        assert len(pts) == int(hit.sum()) > 0 and np.allclose(pts[:, 2], 0.0)
        plain = back.draw(cam)
        assert np.array_equal(back.draw(cam, np.ones(len(pts))), plain)
        half = back.draw(cam, np.full(len(pts), 0.5))
        ratio = half[hit] / plain[hit]
        if back.fog is None:  # the factor in linear light, on the encoded colour
            assert np.allclose(ratio, 0.5 ** LIT_GAMMA, atol=1e-5)
        else:  # the fog is added after the shadow: less darkened, never brighter
            assert np.all(ratio <= 1.0 + 1e-6) and np.all(ratio > 0.5 ** LIT_GAMMA - 1e-5)
        with pytest.raises(ValidationError, match="ground_factor"):
            back.draw(cam, np.ones(3))


def test_the_map_of_an_unchanged_sun_is_reused(atlases):
    inst = Instances.from_records([("ball", 0.0, 0.0, 10.0), ("ball", 2.0, 0.0, 80.0)])
    shadow = AtlasShadow(atlases, texels_per_unit=TPU)
    g = _grid(-2.0, -2.0, 3.0, 2.0, 10)
    shadow.frame(inst, [sun_direction(10.0, 40.0)], g, np.array([0, 1]))
    first = shadow.last_maps[0]
    shadow.frame(inst, [sun_direction(10.0, 40.0)], g, np.array([0, 1]))
    assert shadow.last_maps[0] is first and shadow.field.reused == 1  # the same sun: reused
    shadow.frame(inst, [sun_direction(40.0, 45.0)], g, np.array([0, 1]))
    assert shadow.last_maps[0] is not first and shadow.field.reused == 0  # another sun: cleared, made anew


@pytest.mark.gl
def test_the_cli_draws_a_filtered_soft_sun(tmp_path, capsys):
    out = tmp_path / "o"
    argv = ["billboards", "--n", "4", "--frames", "2", "--size", "96x72", "--asset-size", "32", "--sun-path",
            "day", "--shadows", "--soft", "PCSS", "--sun-radius", "2", "--sun-atlas-size", "48",
            "-o", str(out)]
    assert main(argv) == 0
    got = capsys.readouterr()
    assert "the disc filtered from one map" in got.out and "(48 texels)" in got.err
    assert (out / "billboards.json").exists() and len(list((out / "frames").glob("*.png"))) == 2
