"""The commands under a memory cap (issue 28): ``resource.setrlimit(RLIMIT_AS)`` in a child process,
each command at the largest sizes :mod:`morphkit.tol` documents. The process must end by itself with
exit 0 (it fitted) or 1 and one line on stderr that says memory ran short: never a signal (a
segfault in GL), a traceback, or a worker's log of one.

The cap is set relative to what the child already holds once morphkit and a GL context are up
(address space after the imports, plus :data:`HEADROOM`), so it means the same on a machine with
more cores (llvmpipe starts a thread per core). Largest documented sizes: frame sides
(``cliargs.MAX_FRAME_SIDE``, ``tol.MAX_VIDEO_SIDE``), images of ``tol.MAX_IMAGE_PIXELS``, an atlas
near ``tol.MAX_BUFFER_BYTES`` (3 x 3 maps of 8192^2). All five run in one child (one start-up).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.files.fileio import write_image
from morphkit.programs.cliargs import MAX_FRAME_SIDE

ROOT = Path(__file__).resolve().parents[1]

#: Address space (bytes) the child may take on top of what it holds after start-up: far below
#: every command's need at these sizes (GB), far above a small command's.
HEADROOM = 1 << 30

CHILD = textwrap.dedent('''
    import io, json, resource, sys, time
    from contextlib import redirect_stderr

    def vm_size():
        for line in open("/proc/self/status"):
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024

    if __name__ == "__main__":
        from morphkit.cli import main
        from morphkit.render import Renderer
        from morphkit.camera import look_at, perspective
        from morphkit.scene import Item
        import trimesh
        with Renderer() as r:  # GL up (llvmpipe's threads started) before the cap is measured
            cam = perspective(0.8, (16, 16), look_at([2.0, 0.0, 1.0], [0.0, 0.0, 0.0]), znear=0.1, zfar=9.0)
            r.depth(cam, [Item(trimesh.creation.box())])
        cap = vm_size() + int(sys.argv[1])
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        for argv in json.loads(sys.argv[2]):
            err = io.StringIO()
            t0 = time.perf_counter()
            with redirect_stderr(err):
                try:
                    rc = main(argv)
                except SystemExit as exc:
                    rc = exc.code
            print(json.dumps({"argv": argv, "rc": rc, "stderr": err.getvalue(),
                              "s": round(time.perf_counter() - t0, 1)}), flush=True)
''')


@pytest.mark.gl
@pytest.mark.slow  # ~12 s on 2 busy cores: the bake's local cluster starts (~4 s), SIFT on 8192^2 (~4 s)
def test_the_largest_documented_sizes_under_a_memory_cap_fail_in_one_line(tmp_path, renderer):
    from morphkit.bake import ShadowAtlasKind
    from morphkit.meshes import load_mesh

    side = int(np.sqrt(tol.MAX_IMAGE_PIXELS))
    image = np.zeros((side, side, 3), np.uint8)
    image[::64] = 255
    image[:, ::64] = 200
    write_image(tmp_path / "big.jpg", image)  # JPEG: written 3x faster than PNG (the test's time)
    lib = tmp_path / "lib"
    lib.mkdir()
    trimesh.creation.box([1.0, 0.6, 0.8]).export(lib / "box.ply")
    ShadowAtlasKind(atlas_size=32, grid=3).bake(load_mesh(lib / "box.ply"), renderer, "z").save(
        tmp_path / "box.atlas.npz")  # a small atlas, shown at the largest frame size
    commands = [
        ["demo", "--size", str(MAX_FRAME_SIDE), "-o", str(tmp_path / "demo")],
        ["viewmorph", str(tmp_path / "big.jpg"), str(tmp_path / "big.jpg"), "-o", str(tmp_path / "vm.png")],
        ["bake", str(lib), "-o", str(tmp_path / "bake"), "--atlas-size", "8192", "--grid", "3",
         "--workers", "1", "-q"],
        ["shadows", str(tmp_path / "box.atlas.npz"), "--mesh", str(lib / "box.ply"), "--size",
         str(tol.MAX_VIDEO_SIDE), "--frames", "1", "-o", str(tmp_path / "shadows"), "-q"],
        ["billboards", "--size", f"{tol.MAX_VIDEO_SIDE}x{tol.MAX_VIDEO_SIDE}", "--frames", "1", "--n", "1",
         "--views", "2", "--asset-size", "32", "-o", str(tmp_path / "billboards")],
    ]
    (tmp_path / "child.py").write_text(CHILD)
    r = subprocess.run([sys.executable, str(tmp_path / "child.py"), str(HEADROOM), json.dumps(commands)],
                       capture_output=True, text=True, timeout=600,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, (r.returncode, r.stderr[-3000:])  # no signal, nothing uncaught
    results = [json.loads(line) for line in r.stdout.splitlines() if line.startswith("{")]
    assert [x["argv"][0] for x in results] == [c[0] for c in commands]
    assert "Traceback" not in r.stderr and "Compute Failed" not in r.stderr, r.stderr[-3000:]
    for x in results:
        print(x["argv"][0], x["rc"], f'{x["s"]} s', x["stderr"].strip())
        lines = x["stderr"].strip().splitlines()
        assert x["rc"] in (0, 1), x
        if x["rc"] == 0:
            continue
        assert "Traceback" not in x["stderr"]
        if x["argv"][0] == "bake":  # the asset failed (recorded), the run did not
            assert len(lines) == 1 and lines[0].startswith("morphkit bake: failed: box: "), lines
        else:
            assert len(lines) == 1 and lines[0].startswith("morphkit: error: "), lines
        assert "memory" in lines[0].lower(), lines[0]
