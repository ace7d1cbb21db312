"""morphkit.export.lod: a plan's bands turned into an engine's levels of detail (the mesh, a crossed
card, nothing), switched by ``MSFT_lod`` at screen coverages; ``morphkit export --plan`` end to end (GL)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import trimesh
from gltfcheck import validate

from morphkit.cli import main
from morphkit.errors import ValidationError
from morphkit.export import read_dome_glb
from morphkit.export.glb import LOD, NodeLods, read_glb
from morphkit.export.lod import LOD_CARD, LOD_MESH, cross_card, screen_coverage
from morphkit.plan import BandChoice, Budget, ScenePlan, read_plan
from morphkit.plan.lodchain import lod_chain

ROOT = Path(__file__).resolve().parent.parent
BUDGET = Budget.parse(["billboard-psnr=20"])


def _plan(bands: dict, *, shape=(480, 640), h0: int = 128, assets=("tree",)) -> ScenePlan:
    return ScenePlan(BUDGET, BandChoice(bands), True, assets, base_height={a: h0 for a in assets},
                     shape=shape)


def _levels(chain):
    return [(lv.kind, lv.min_height_px) for lv in chain.levels]


def test_screen_coverage_is_the_bounding_discs_share_of_the_screen():
    # a sphere of radius 1 at depth 10 under fy = 500: its disc is 50 px in radius; its quad of half
    # height 0.8 is 2 * 500 * 0.8 / 10 = 80 px high
    shape = (480, 640)
    assert screen_coverage(80.0, shape, 1.0, 0.8) == pytest.approx(math.pi * 50.0**2 / (480 * 640))
    assert screen_coverage(0.0, shape, 1.0, 0.8) == 0.0
    with pytest.raises(ValidationError, match="bounding radius: expected"):
        screen_coverage(10.0, shape, 0.0, 1.0)


def test_each_octave_takes_its_most_exact_elevation_and_the_chain_never_gets_more_exact_going_down():
    # octave 0 (>= 64 px) is culled from above but the mesh at eye level; octave 1 culled; octave 2 (16-32
    # px) a morph at one elevation: the chain is the mesh down to 64 px and a card below (octave 1 takes
    # octave 2's morph), never culled
    bands = {("tree", 0, 0): "mesh", ("tree", 0, 2): "cull", ("tree", 1, 0): "cull",
             ("tree", 2, 0): "cull", ("tree", 2, 1): "morph"}
    chain = lod_chain(_plan(bands), "tree", radius=1.0, half_height=1.0)
    assert _levels(chain) == [(LOD_MESH, 64.0), (LOD_CARD, 0.0)]
    assert chain.levels[1].stands_for == ("morph",)
    # a plan that is not monotone (the mesh small, a card large) is made so by its most exact choice below
    bands = {("tree", 0, 0): "classic", ("tree", 1, 0): "mesh", ("tree", 2, 0): "cull"}
    assert _levels(lod_chain(_plan(bands), "tree", radius=1.0, half_height=1.0)) == [(LOD_MESH, 32.0)]


def test_a_culled_chain_ends_where_the_plan_culls_and_octaves_it_never_saw_take_the_smallest_seen():
    bands = {("tree", 0, 0): "mesh", ("tree", 1, 1): "nearest", ("tree", 2, 0): "classic",
             ("tree", 3, 0): "cull"}
    chain = lod_chain(_plan(bands), "tree", radius=1.0, half_height=1.0)
    assert _levels(chain) == [(LOD_MESH, 64.0), (LOD_CARD, 16.0)]
    assert chain.levels[1].stands_for == ("nearest", "classic")
    cov = chain.coverage()
    assert cov == [pytest.approx(screen_coverage(h, (480, 640), 1.0, 1.0)) for h in (64.0, 16.0)]
    assert cov[0] > cov[1] > 0  # nothing below 16 px
    # the plan saw the tree down to 16-32 px only, as a card: smaller ones stay cards (not culled)
    chain = lod_chain(_plan({("tree", 0, 0): "mesh", ("tree", 2, 0): "classic"}), "tree", radius=1.0,
                      half_height=1.0)
    assert _levels(chain) == [(LOD_MESH, 64.0), (LOD_CARD, 0.0)] and chain.coverage()[-1] == 0.0
    # the mesh then nothing: one level, and a coverage for the empty level after it
    chain = lod_chain(_plan({("tree", 0, 0): "mesh", ("tree", 1, 0): "cull"}), "tree", radius=1.0,
                      half_height=1.0)
    assert _levels(chain) == [(LOD_MESH, 64.0)] and chain.switches
    assert chain.coverage() == [pytest.approx(screen_coverage(64.0, (480, 640), 1.0, 1.0)), 0.0]


def test_on_random_plans_the_chain_is_monotone_and_nowhere_less_exact_than_the_plan():
    rng = np.random.default_rng(40)
    engine = {"cull": 0, "classic": 1, "nearest": 1, "morph": 1, "mesh": 2}
    kind_rank = {LOD_CARD: 1, LOD_MESH: 2}
    for _ in range(200):
        bands = {("tree", int(lv), int(e)): str(rng.choice(list(engine)))
                 for lv, e in zip(rng.integers(0, 5, 6), rng.integers(0, 3, 6), strict=True)}
        chain = lod_chain(_plan(bands), "tree", radius=1.0, half_height=1.0)
        heights = [lv.min_height_px for lv in chain.levels]
        assert heights == sorted(heights, reverse=True) and chain.levels[0].kind == LOD_MESH
        for (_, level, _), rep in bands.items():
            low = 128 / 2 ** (level + 1)  # the band's least height: every height in it is drawn at least so
            drawn = [kind_rank[lv.kind] for lv in chain.levels if low >= lv.min_height_px]
            assert (drawn[0] if drawn else 0) >= engine[rep], (bands, chain.levels)


def test_level_zero_is_always_the_mesh_and_a_plan_of_meshes_switches_nothing():
    chain = lod_chain(_plan({("tree", 1, 0): "classic", ("tree", 2, 0): "cull"}), "tree", radius=0.5,
                      half_height=0.6)
    # the mesh from a coverage of 1 up: the height whose disc is the screen's area
    assert chain.levels[0].kind == LOD_MESH and chain.levels[0].stands_for == ()
    assert chain.coverage()[0] == pytest.approx(1.0)
    assert _levels(chain)[1:] == [(LOD_CARD, 32.0)]
    assert any("coverage of 1" in n for n in chain.notes)
    chain = lod_chain(_plan({("tree", 0, 0): "mesh", ("tree", 1, 2): "mesh"}), "tree", radius=1.0,
                      half_height=1.0)
    assert _levels(chain) == [(LOD_MESH, 0.0)] and not chain.switches
    # an asset the plan planned but never saw: the mesh, said
    chain = lod_chain(_plan({("tree", 0, 0): "mesh"}, assets=("tree", "cow")), "cow", radius=1.0,
                      half_height=1.0)
    assert not chain.switches and "never saw" in chain.notes[0]


def test_a_plan_of_other_assets_or_without_its_heights_or_size_is_refused_or_said():
    bands = {("tree", 0, 0): "mesh", ("tree", 1, 0): "cull"}
    with pytest.raises(ValidationError, match=r"the plan's asset: expected one of \['tree'\], got 'cow'"):
        lod_chain(_plan(bands), "cow", radius=1.0, half_height=1.0)
    bare = ScenePlan(BUDGET, BandChoice(bands), True, ("tree",))
    with pytest.raises(ValidationError, match="its bands' heights"):
        lod_chain(bare, "tree", radius=1.0, half_height=1.0)
    sized = ScenePlan(BUDGET, BandChoice(bands), True, ("tree",), base_height={"tree": 128})
    chain = lod_chain(sized, "tree", radius=1.0, half_height=1.0)
    assert chain.shape == (480, 640) and "does not say its image size" in chain.notes[0]


def test_a_plan_file_gives_back_its_bands_heights_and_image_size(tmp_path):
    plan = _plan({("tree", 0, 0): "mesh", ("tree", 2, 1): "classic"}, shape=(360, 480), h0=96)
    back = read_plan(plan.save(tmp_path / "plan.json"))
    assert back.base_height == {"tree": 96} and back.shape == (360, 480)
    assert json.loads((tmp_path / "plan.json").read_text())["image_size"] == [480, 360]


def test_node_levels_must_have_a_decreasing_coverage_per_level():
    NodeLods(("card",), (0.1, 0.0))
    bad = (((), (0.1,)), (("card",), (0.1,)), (("card",), (0.01, 0.1)), (("card",), (0.1, math.nan)))
    for lower, cov in bad:
        with pytest.raises(ValidationError, match="levels of detail: expected at least one lower level"):
            NodeLods(lower, cov)


@pytest.fixture(scope="module")
def plan_file(tmp_path_factory):
    """A plan of the flyover's kind for the tree: the mesh from 64 px, the card from 16 to 64 px."""
    path = tmp_path_factory.mktemp("plan") / "plan.json"
    _plan({("tree", 0, 0): "mesh", ("tree", 1, 0): "classic", ("tree", 1, 2): "morph",
           ("tree", 2, 1): "nearest", ("tree", 3, 0): "cull"}, h0=128).save(path)
    return path


@pytest.mark.gl
def test_the_crossed_card_seen_from_a_views_own_camera_is_that_view():
    from morphkit.billboard import bake_dome
    from morphkit.meshes import normalize, sample_mesh
    from morphkit.render import Renderer
    from morphkit.scene import Item

    mesh = normalize(sample_mesh("tree"))
    with Renderer() as r:
        asset = bake_dome(mesh, r, name="tree", size=48)
        card = cross_card(asset)
        k = 0  # the lowest ring's view at azimuth 0: the first quad's
        cam = asset.reference_camera(k)
        drawn = r.albedo(cam, [Item(card)])
        depth = r.depth(cam, [Item(card)])
    view = asset.record().rgba[k]
    inside = view[..., 3] >= 192  # well inside the cut-out (bilinear texels at its edge straddle it)
    # the quad is the view's image plane at the pivot: drawn at the pivot's depth wherever the other
    # quad (crossing it at the pivot) is not in front of it
    dist = float(np.linalg.norm(cam.position - asset.pivot))
    on_plane = inside & (np.abs(depth - dist) < 1e-3 * dist)
    assert on_plane.sum() > 0.5 * inside.sum()
    # there its albedo is the view's within one 8-bit level (the texture sampled at its texels' centres;
    # a texel beside a cut-out may blend one level with its neighbour's mip), nearly everywhere exact
    diff = np.abs(drawn[on_plane].astype(int) - view[on_plane][:, :3].astype(int))
    assert np.mean(diff == 0) > 0.9 and np.mean(diff <= 1) > 0.99
    assert len(card.faces) == 4 and card.visual.material.alphaMode == "MASK"


@pytest.mark.gl
def test_export_with_a_plan_writes_its_levels_as_msft_lod(tmp_path, plan_file, capsys):
    out = tmp_path / "tree.glb"
    assert main(["export", "tree", "-o", str(out), "--size", "32", "--sun-atlas-size", "32", "--no-impostor",
                 "--plan", str(plan_file)]) == 0
    said = capsys.readouterr().out
    assert "MSFT_lod from the plan: mesh from 64 px" in said
    assert "card from 16 px" in said and "nothing below 16 px" in said
    glb = read_glb(out)
    nodes = glb.tree["nodes"]
    (base,) = [n for n in nodes if LOD in n.get("extensions", {})]
    assert base["name"] == "mesh" and LOD in glb.tree["extensionsUsed"]
    (low,) = base["extensions"][LOD]["ids"]
    card = nodes[low]
    # the card is drawn in the mesh's place (its transform, out of the scene's roots)
    assert card["name"] == "card" and card["matrix"] == base["matrix"]
    roots = glb.tree["scenes"][0]["nodes"]
    assert low not in roots and nodes.index(base) in roots
    side = glb.sidecar["lod"]
    assert [lv["kind"] for lv in side["levels"]] == ["mesh", "card"]
    assert base["extras"]["MSFT_screencoverage"] == [lv["screen_coverage"] for lv in side["levels"]]
    # what the card errs at the sizes it is drawn at, beside the morph of the same views
    (lod,) = glb.sidecar["measured"]["lod"]["levels"]
    assert lod["height_px"] == 32.0 and len(lod["views"]) == 3  # the top of the card's first octave
    assert all(15.0 < v["card_psnr_db"] < 60.0 and 15.0 < v["morph_psnr_db"] < 60.0 for v in lod["views"])
    assert "card" in glb.sidecar["measured"]
    # the asset still reads back; trimesh (no MSFT_lod) draws the mesh alone
    back = read_dome_glb(out)
    assert back.asset.name == "tree"
    scene = trimesh.load(out)
    assert "card" not in {scene.graph[n][1] for n in scene.graph.nodes_geometry}
    # the card as a glTF reader gets it (texture, UVs flipped to glTF's top-left origin, cut-out; its
    # vertices morphkit's, +z up, its node turning them +y up) draws as the card morphkit measured: the
    # same albedo from the first view's camera
    from morphkit.render import Renderer
    from morphkit.scene import Item

    from_file = scene.geometry["card"]
    assert from_file.visual.material.alphaMode == "MASK"
    cam = back.asset.reference_camera(0)
    with Renderer() as r:
        want = r.albedo(cam, [Item(cross_card(back.asset))])
        got = r.albedo(cam, [Item(from_file)])
    assert np.abs(want.astype(int) - got.astype(int)).max() <= 1 and want.any()
    report = validate(out)
    assert report["errors"] == 0 and report["warnings"] == 0, report["messages"]


@pytest.mark.gl
def test_a_chain_of_the_mesh_then_nothing_switches_to_an_empty_node(tmp_path, capsys):
    plan = tmp_path / "plan.json"
    _plan({("tree", 0, 0): "mesh", ("tree", 1, 0): "cull"}).save(plan)
    out = tmp_path / "tree.glb"
    assert main(["export", "tree", "-o", str(out), "--size", "32", "--sun-atlas-size", "0", "--no-impostor",
                 "--plan", str(plan)]) == 0
    assert "nothing below 64 px" in capsys.readouterr().out
    glb = read_glb(out)
    nodes = glb.tree["nodes"]
    (base,) = [n for n in nodes if LOD in n.get("extensions", {})]
    (low,) = base["extensions"][LOD]["ids"]
    assert "mesh" not in nodes[low] and "children" not in nodes[low]
    assert nodes[low]["matrix"] == base["matrix"]
    assert base["extras"]["MSFT_screencoverage"][1] == 0.0
    assert "card" not in glb.sidecar["measured"]
    assert validate(out)["errors"] == 0


@pytest.mark.gl
def test_a_plan_without_the_asset_or_with_a_scene_is_refused_in_one_line_before_any_work(tmp_path, plan_file,
                                                                                          capsys):
    out = tmp_path / "cow.glb"
    assert main(["export", "cow", "-o", str(out), "--plan", str(plan_file)]) == 1
    err = capsys.readouterr().err
    assert "the plan's asset: expected one of ['tree'] (name it with --plan-asset), got 'cow'" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
    assert main(["export", "tree", "-o", str(out), "--plan", str(tmp_path / "none.json")]) == 1
    assert "plan file" in capsys.readouterr().err and not out.exists()
    scene = ROOT / "samples" / "scenes" / "forest.json"
    assert main(["export", str(scene), "-o", str(out), "--plan", str(plan_file)]) == 1
    err = capsys.readouterr().err
    assert "expected a plan of the scene's assets ['crate', 'person', 'tree'], got one of ['tree']" in err
    assert not out.exists()
    assert main(["export", str(scene), "-o", str(out), "--plan", str(plan_file), "--plan-asset", "tree"]) == 2
    assert "--plan-asset: expected an asset to export" in capsys.readouterr().err and not out.exists()


@pytest.mark.gl
def test_export_writes_a_planned_scene_each_instance_switching_its_own_level(tmp_path, plan_file, capsys):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({
        "morphkit_scene": 1, "assets": [{"name": "tree", "source": "tree", "scale": 2.0}],
        "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 0.0, "yaw_deg": 40.0},
                                 {"asset": "tree", "x": 3.0, "y": 1.0}]},
        "camera": {"path": "orbit"}, "image": {"width": 96, "height": 72}, "frames": 2, "asset_size": 32,
    }))
    out = tmp_path / "scene.glb"
    args = ["export", str(scene), "-o", str(out), "--sun-atlas-size", "0", "--plan", str(plan_file)]
    assert main(args) == 0
    said = capsys.readouterr().out
    assert "the instances of tree nodes of their own" in said and "MSFT_lod from the plan" in said
    glb = read_glb(out)
    names = [n.get("name") for n in glb.tree["nodes"] if LOD in n.get("extensions", {})]
    assert names == ["tree@0", "tree@1"]
    assert read_dome_glb(out).sidecar["instanced"] == "nodes"
    assert validate(out)["errors"] == 0


def test_a_scenes_assets_with_levels_of_detail_have_each_instance_as_a_node_of_its_own(tmp_path, monkeypatch):
    from morphkit import tol
    from morphkit.billboard import Instances
    from morphkit.billboard.analytic import sphere_dome_asset
    from morphkit.export.assetglb import ExportedAsset, write_scene_glb
    from morphkit.export.glb import INSTANCING
    from morphkit.meshes import Y_UP_TO_Z_UP
    from morphkit.scene import Item

    ball = sphere_dome_asset(size=16, levels=1)
    box = sphere_dome_asset(size=16, levels=1, name="box")
    inst = Instances(("ball", "box"), np.array([0, 1, 1, 0, 1]),
                     np.array([[0.0, 0.0], [2.0, 1.0], [-1.5, 3.0], [4.0, -2.0], [1.0, 5.0]]),
                     np.array([0.0, 30.0, 90.0, 200.0, -45.0]), np.array([1.0, 2.0, 0.5, 1.5, 1.0]))
    assets = {"ball": ExportedAsset(ball, [Item(trimesh.creation.icosphere())]),
              "box": ExportedAsset(box, [Item(trimesh.creation.box((0.5, 0.4, 1.0)), color=(0.2, 0.5, 0.1)),
                                         Item(trimesh.creation.box((0.1, 0.1, 2.0)))])}
    chain = lod_chain(_plan({("box", 0, 0): "mesh", ("box", 1, 0): "morph", ("box", 2, 0): "cull"},
                            assets=("ball", "box")), "box", radius=1.0, half_height=1.0)
    path = tmp_path / "scene.glb"
    write_scene_glb(path, assets, inst, {"box": chain})
    glb = read_glb(path)
    nodes = glb.tree["nodes"]
    by_name = {n["name"]: k for k, n in enumerate(nodes)}
    roots = glb.tree["scenes"][0]["nodes"]
    side = glb.sidecar["assets"]
    assert side["box"]["instanced"] == "nodes" and side["ball"]["instanced"] == INSTANCING
    assert side["box"]["lod"]["levels"][1]["kind"] == LOD_CARD
    to_file = np.linalg.inv(Y_UP_TO_Z_UP)
    meshes = set()
    for i, k in enumerate(np.flatnonzero(inst.asset == 1)):
        node = nodes[by_name[f"box@{i}"]]
        matrix = np.array(node["matrix"], float).reshape(4, 4).T  # column-major
        np.testing.assert_allclose(matrix, to_file @ inst.object2world(int(k)), atol=1e-12)
        assert by_name[f"box@{i}"] in roots and INSTANCING not in node.get("extensions", {})
        # its items share one mesh each with every other instance's
        meshes.add(tuple(nodes[c]["mesh"] for c in node["children"]))
        (low,) = node["extensions"][LOD]["ids"]
        assert nodes[low]["name"] == f"box@{i}.card" and nodes[low]["matrix"] == node["matrix"]
        assert low not in roots
        assert node["extras"]["MSFT_screencoverage"] == chain.coverage()
    assert len(meshes) == 1 and len(next(iter(meshes))) == 2
    assert len({nodes[by_name[f"box@{i}.card"]]["mesh"] for i in range(3)}) == 1
    assert validate(path)["errors"] == 0
    monkeypatch.setattr(tol, "EXPORT_MAX_LOD_INSTANCES", 2)
    want = r"instances of 'box' with levels of detail: expected at most 2"
    with pytest.raises(ValidationError, match=want):
        write_scene_glb(tmp_path / "big.glb", assets, inst, {"box": chain})
    assert not (tmp_path / "big.glb").exists()
