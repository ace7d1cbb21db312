"""``morphkit bench bake``'s model of a larger cluster (:func:`project_bake`) and its options."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.bench.bake_suite import idle_makespan, project_bake
from morphkit.cli import main
from morphkit.errors import ValidationError


def test_projection_of_equal_tasks_is_the_closed_form():
    # 256 tasks of 1 s on 16 workers: 16 rounds; start-up paid once (in parallel), fixed once
    t16 = project_bake([1.0], assets=256, workers=16, fixed_s=2.0, worker_start_s=3.0, per_task_s=0.001)
    t1 = project_bake([1.0], assets=256, workers=1, fixed_s=2.0, worker_start_s=3.0, per_task_s=0.001)
    assert t16 == pytest.approx(2.0 + 3.0 + 16.0)
    assert t1 == pytest.approx(2.0 + 3.0 + 256.0)


def test_projection_is_bounded_by_the_serial_per_task_work():
    # the scheduler and driver at 0.5 s a task cannot keep 16 workers of 1 s tasks busy
    t = project_bake([1.0], assets=64, workers=16, fixed_s=0.0, worker_start_s=0.0, per_task_s=0.5)
    assert t == pytest.approx(32.0)


def test_projection_contention_grows_tasks_beyond_one_worker():
    base = project_bake([2.0, 1.0], assets=8, workers=4, fixed_s=0.0, worker_start_s=0.0, per_task_s=0.0)
    grown = project_bake([2.0, 1.0], assets=8, workers=4, fixed_s=0.0, worker_start_s=0.0, per_task_s=0.0,
                         growth_per_worker=0.1)
    # list scheduling in submission order (2, 1, 2, 1, ...): the fifth task goes to a worker that
    # ran a 1 s task, the seventh to one that ran 2 s: 4 s
    assert base == pytest.approx(idle_makespan([2.0, 1.0] * 4, 0.0, 4))
    assert base == pytest.approx(4.0)
    assert grown == pytest.approx(4.0 * 1.3)
    one = project_bake([2.0, 1.0], assets=8, workers=1, fixed_s=0.0, worker_start_s=0.0, per_task_s=0.0,
                       growth_per_worker=0.1)
    assert one == pytest.approx(12.0)  # no contention with one worker


def test_projection_refuses_empty_inputs():
    with pytest.raises(ValidationError, match="project_bake inputs"):
        project_bake([], assets=4, workers=2, fixed_s=0.0, worker_start_s=0.0, per_task_s=0.0)


def test_workers_is_an_option_of_bench_bake_only(capsys):
    assert main(["bench", "warp", "--quick", "--workers", "1", "2"]) == 2
    assert "--workers is an option of `bench bake` only" in capsys.readouterr().err


def test_run_suite_passes_suite_options(monkeypatch, capsys):
    from morphkit import bench
    from morphkit.bench.harness import Timing, make_row

    seen = {}

    def toy(*, quick: bool = False, workers=(1,)):
        seen["workers"] = list(workers)
        return [make_row("toy", "m", {"size": 1}, Timing(1.0, 1.0, 1.0, 1))]

    monkeypatch.setitem(bench.SUITES, "toy", toy)
    rows = bench.run_suite("toy", quick=True, options={"workers": [1, 4]})
    assert seen["workers"] == [1, 4] and rows[0]["gl"]["platform"] in ("osmesa", "egl")
    capsys.readouterr()


def test_library_meshes_load_upright(tmp_path):
    """OBJ reads +y up: the suite writes its Z-up teapots +y up, so they load as built, upright."""
    from morphkit.bench.bake_suite import write_library
    from morphkit.meshes import load_mesh, normalize, teapot

    paths = write_library(tmp_path, quick=True)
    objs = [p for p in paths if p.suffix == ".obj"]
    assert objs
    for p in objs:
        built = normalize(teapot(resolution=int(p.stem.split("_")[1])))
        loaded = load_mesh(p)
        np.testing.assert_allclose(loaded.bounds, built.bounds, atol=1e-6)
        np.testing.assert_allclose(loaded.extents, built.extents, atol=1e-6)
        assert loaded.extents[2] < loaded.extents[:2].max()  # the teapot is wider than high


def test_library_of_n_assets_repeats_its_meshes_each_copy_turned(tmp_path):
    """--assets N: N distinct inputs (distinct hashes), copy k turned k degrees about the up axis."""
    import hashlib

    import trimesh

    from morphkit.bench.bake_suite import LIBRARY, write_library
    from morphkit.meshes import load_mesh

    n_lib = len(LIBRARY[::2])
    paths = write_library(tmp_path, quick=True, assets=n_lib + 3)
    assert len(paths) == n_lib + 3
    assert len({hashlib.sha256(p.read_bytes()).hexdigest() for p in paths}) == len(paths)
    assert paths[0].suffix == ".ply"  # written as built (+z up)
    first, copy = (trimesh.load(paths[i], process=False) for i in (0, n_lib))  # the same mesh, copy 1
    c, s = np.cos(np.deg2rad(1.0)), np.sin(np.deg2rad(1.0))
    turned = first.vertices @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(copy.vertices, turned, atol=1e-5)
    assert len(load_mesh(paths[n_lib]).faces) == len(first.faces)
    with pytest.raises(ValidationError, match="library assets"):
        write_library(tmp_path / "none", quick=True, assets=0)


def test_assets_is_an_option_of_bench_bake_only(capsys):
    assert main(["bench", "warp", "--quick", "--assets", "32"]) == 2
    assert "--assets is an option of `bench bake` only" in capsys.readouterr().err
