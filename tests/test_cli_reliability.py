"""The CLI against what a real machine does to it (issue 28): output folders that hold a user's
files, scheduler addresses that are not a scheduler, Ctrl-C, two bakes into one folder, options
that would allocate without bound, and a library on a real file system (odd names, links, FIFOs).

Every failure is one line on stderr (``morphkit: error: ...`` or ``morphkit: interrupted``), no
traceback, nothing of the user's replaced and no temporary file left.
"""

from __future__ import annotations

import contextlib
import http.server
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import types
from pathlib import Path

import numpy as np
import pytest
import trimesh
from clirun import one_line, run

from morphkit.bake import Manifest
from morphkit.bake import cluster as bake_cluster
from morphkit.bake import pipeline as bake_pipeline
from morphkit.cli import main
from morphkit.files import fileio
from morphkit.files.outfolder import BAKE_OUTPUT, MARKER_NAME, claim_output

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def library(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box([1.0, 0.6, 0.8]).export(folder / "box.ply")
    return folder


class NoWork(BaseException):
    """Raised where a command would start its work: the options got through."""


@pytest.fixture
def no_work(monkeypatch):
    """Any render or bake cluster raises NoWork."""
    import morphkit.programs.demo
    import morphkit.render
    from morphkit.viewmorph import ViewMorpher

    def stop(*_a, **_k):
        raise NoWork

    monkeypatch.setattr(morphkit.render, "Renderer", stop)
    monkeypatch.setattr(morphkit.programs.demo, "Renderer", stop)
    monkeypatch.setattr(bake_pipeline, "open_client", stop)
    monkeypatch.setattr(ViewMorpher, "from_estimate", classmethod(stop))


# ------------------------------------------------------------------ output folders
def _commands(tmp: Path) -> dict[str, list[object]]:
    """Each command that writes into a folder, without its ``-o``."""
    return {"demo": ["demo", "--quick"],
            "shadows": ["shadows", tmp / "a.atlas.npz"],
            "billboards": ["billboards", "--frames", "2"],
            "bake": ["bake", library(tmp / "lib")],
            "viewmorph": ["viewmorph", tmp / "l.png", tmp / "r.png", "--frames", "3"]}


@pytest.mark.parametrize("command", ["demo", "shadows", "billboards", "bake", "viewmorph"])
def test_a_folder_holding_the_users_files_is_refused_by_every_command(tmp_path, capfd, no_work, command):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "frame_0000.png").write_bytes(b"the user's picture")
    for extra in ([], [] if command == "bake" else ["--overwrite"]):  # a bake resumes: no --overwrite
        rc, _o, err = run(capfd, *_commands(tmp_path)[command], "-o", out, *extra)
        assert rc == 2
        assert (f"{command} output folder: expected a new or empty folder, or a previous {command} run, "
                f"got {out} holding 1 entries that are not one, e.g. 'frame_0000.png'") in one_line(err)
    assert [p.name for p in out.iterdir()] == ["frame_0000.png"]
    assert (out / "frame_0000.png").read_bytes() == b"the user's picture"


@pytest.mark.parametrize("command", ["demo", "shadows", "billboards", "viewmorph"])
def test_a_previous_run_is_kept_without_overwrite(tmp_path, capfd, no_work, command):
    out = tmp_path / "prev"
    out.mkdir()
    (out / MARKER_NAME).write_text(json.dumps({"command": command, "status": "complete"}))
    (out / "frame_0000.png").write_bytes(b"old")
    rc, _o, err = run(capfd, *_commands(tmp_path)[command], "-o", out)
    assert rc == 2 and "--overwrite" in one_line(err)
    assert (out / "frame_0000.png").read_bytes() == b"old"


def test_shadows_overwrite_replaces_the_previous_frames_and_keeps_the_users_files(tmp_path, capfd,
                                                                                  monkeypatch):
    """The command's wiring (the render is a stand-in writing N frames; test_bake renders for real)."""
    import morphkit.programs.playback as playback
    import morphkit.render
    import morphkit.shadow

    def fake_render(atlas, mesh, path, out, **_kw):
        n = path.frames
        frames = [fileio.write_bytes(Path(out) / f"frame_{i:04d}.png", b"frame") for i in range(n)]
        return {"frames": frames, "video": fileio.write_bytes(Path(out) / "shadows.webm", b"v"),
                "errors": [{"iou": 1.0}] * n}

    loaded = types.SimpleNamespace(baked=types.SimpleNamespace(mesh_sha256=None))
    monkeypatch.setattr(morphkit.shadow.ShadowAtlas, "load", staticmethod(lambda _p: loaded))
    monkeypatch.setattr(playback, "baked_mesh", lambda *_a, **_k: None)
    monkeypatch.setattr(playback, "render_shadow_sequence", fake_render)
    monkeypatch.setattr(morphkit.render, "Renderer", contextlib.nullcontext)
    out = tmp_path / "f"
    assert run(capfd, "shadows", "a.atlas.npz", "--frames", "5", "-o", out)[0] == 0
    (out / "notes.txt").write_text("mine")
    rc, _o, err = run(capfd, "shadows", "a.atlas.npz", "--frames", "2", "-o", out)
    assert rc == 2 and "--overwrite" in one_line(err)
    assert run(capfd, "shadows", "a.atlas.npz", "--frames", "2", "--overwrite", "-o", out)[0] == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [MARKER_NAME, "frame_0000.png", "frame_0001.png", "shadows.webm", "notes.txt"])


def test_a_refused_bake_leaves_no_folder_behind(tmp_path, capfd, monkeypatch):
    monkeypatch.setattr(bake_cluster, "CONNECT_TIMEOUT_S", 1.0)
    lib = library(tmp_path / "lib")
    rc, _o, err = run(capfd, "bake", lib, "-o", tmp_path / "new" / "out", "--scheduler", "tcp://127.0.0.1:9")
    assert rc == 1 and "Dask scheduler: expected one answering at 'tcp://127.0.0.1:9'" in one_line(err)
    assert not (tmp_path / "new").exists()


def test_a_bake_folder_with_foreign_files_is_refused_and_a_bake_is_resumed(tmp_path, capfd, no_work):
    lib = library(tmp_path / "lib")
    rc, _o, err = run(capfd, "bake", lib, "-o", lib)  # the library itself is not an output folder
    assert rc == 2 and "holding 1 entries that are not one, e.g. 'box.ply'" in one_line(err)
    out = tmp_path / "out"
    out.mkdir()
    (out / "manifest.json").write_text(json.dumps({"format": "morphkit-bake-manifest", "version": 1,
                                                   "assets": {}, "options": {}, "run": {}}))
    with pytest.raises(NoWork):  # resumed: it gets as far as starting the cluster
        main(["bake", str(lib), "-o", str(out), "-q"])


# ------------------------------------------------------------------ scheduler addresses
@pytest.fixture
def not_schedulers():
    """An HTTP server and a port that accepts but never answers, both on loopback."""
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
    httpd.RequestHandlerClass.log_message = lambda *_a: None
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    silent = socket.socket()
    silent.bind(("127.0.0.1", 0))
    silent.listen(8)
    yield {"http": f"tcp://127.0.0.1:{httpd.server_address[1]}",
           "silent": f"127.0.0.1:{silent.getsockname()[1]}"}
    httpd.shutdown()
    httpd.server_close()
    silent.close()


@pytest.mark.parametrize(("which", "message"), [
    ("http", r"Dask scheduler: expected one answering at 'tcp://127.0.0.1:\d+' within 1 s, got"),
    ("silent", r"Dask scheduler: expected one answering at '127.0.0.1:\d+' within 1 s, got no answer"),
    ("tcp://127.0.0.1:99999", r"Dask scheduler address: expected tcp://HOST:PORT \(PORT 1..65535\)"),
    ("udp://127.0.0.1:8786", r"Dask scheduler address: expected tcp://HOST:PORT"),
    ("http://127.0.0.1:8786", r"Dask scheduler address: expected tcp://HOST:PORT"),
    ("tcp://[::1", r"Dask scheduler address: expected tcp://HOST:PORT"),
    ("nonsense", r"Dask scheduler address: expected tcp://HOST:PORT"),
    ("", r"Dask scheduler address: expected tcp://HOST:PORT"),
])
def test_an_address_that_is_not_a_scheduler_is_one_line(tmp_path, capfd, monkeypatch, not_schedulers, which,
                                                        message):
    import re

    monkeypatch.setattr(bake_cluster, "CONNECT_TIMEOUT_S", 1.0)  # default 5 s; the same code path
    lib = library(tmp_path / "lib")
    address = not_schedulers.get(which, which)
    rc, _o, err = run(capfd, "bake", lib, "-o", tmp_path / "out", "--scheduler", address)
    malformed = message.startswith("Dask scheduler address")  # a bad value: usage (2); no answer: 1
    assert rc == (2 if malformed else 1) and re.search(message, one_line(err)), err
    assert not (tmp_path / "out").exists()


def test_an_http_server_as_scheduler_in_a_subprocess(tmp_path, not_schedulers):
    """The real entry point with the default timeout (5 s): one line, no Dask log or traceback."""
    lib = library(tmp_path / "lib")
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(tmp_path / "out"),
                        "--scheduler", not_schedulers["http"]], capture_output=True, text=True, env=ENV,
                       timeout=120)  # a hang guard: Dask's own client waited here without end
    elapsed = time.perf_counter() - t0
    assert r.returncode == 1
    assert "within 5 s" in one_line(r.stderr)
    print(f"http server as scheduler: refused after {elapsed:.1f} s (process start included)")


# ------------------------------------------------------------------ interrupts
def test_ctrl_c_is_one_line_exit_130_and_leaves_nothing(tmp_path, capfd, monkeypatch):
    def interrupt(*_a, **_k):
        raise KeyboardInterrupt

    monkeypatch.setattr(bake_pipeline.Manifest, "open", interrupt)
    lib = library(tmp_path / "lib")
    rc, out, err = run(capfd, "bake", lib, "-o", tmp_path / "out")
    assert rc == 130 and out == "" and err == "morphkit: interrupted\n"
    assert not (tmp_path / "out").exists()  # the run had written nothing: its folder is gone


def test_ctrl_c_in_the_middle_of_a_write_leaves_no_temporary_file(tmp_path, capfd, monkeypatch):
    target = fileio.write_bytes(tmp_path / "a.png", b"old")

    def half_then_interrupt(f):
        f.write(b"half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        fileio.atomic_write(target, half_then_interrupt)
    with pytest.raises(KeyboardInterrupt), fileio.atomic_output(tmp_path / "v.mp4") as tmp:
        tmp.write_bytes(b"half a video")
        raise KeyboardInterrupt
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png"] and target.read_bytes() == b"old"

    # a command interrupted between two frames: one line; the frames written so far stay with the
    # folder's marker ("running"), so a rerun replaces them only with --overwrite
    from morphkit.viewmorph import ViewMorpher

    class Fake:
        mode, rectification, fit = "morph", type("R", (), {"method": "none"}), None
        report = type("Rep", (), {"n_used": 9, "n_input": 9, "n_duplicates": 0, "n_outliers": 0,
                                  "n_dropped_foldover": 0, "fallback": None})

        def frames(self, n, **_kw):
            yield np.zeros((4, 4, 3), np.uint8)
            raise KeyboardInterrupt

    monkeypatch.setattr(ViewMorpher, "from_estimate", classmethod(lambda *_a, **_k: Fake()))
    for name in ("l.png", "r.png"):
        fileio.write_image(tmp_path / name, np.zeros((8, 8, 3), np.uint8))
    out = tmp_path / "frames"
    argv = ["viewmorph", tmp_path / "l.png", tmp_path / "r.png", "--points", tmp_path / "p.json",
            "--frames", "3", "-o", out]
    (tmp_path / "p.json").write_text(json.dumps([[1, 1, 1, 1]] * 4))
    rc, _o, err = run(capfd, *argv)
    assert rc == 130 and err.strip().splitlines()[-1] == "morphkit: interrupted" and "Traceback" not in err
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*")) == [
        MARKER_NAME, "frames", "frames/frame_0000.png"]
    assert json.loads((out / MARKER_NAME).read_text())["status"] == "running"
    assert run(capfd, *argv)[0] == 2


@pytest.mark.gl
def test_sigint_to_a_running_demo(tmp_path):
    out = tmp_path / "demo"
    # the full demo (over a minute of work after it claims its folder), interrupted a second after
    # the claim: it is always mid-work then (--quick could finish first on a quiet machine, and an
    # interrupt that arrives after the work would not be tested); it is not run to its end
    # SIGINT back to its default in the child: a test run started in the background by a
    # non-interactive shell inherits SIGINT ignored, and Python then installs no handler for it
    p = subprocess.Popen([sys.executable, "-m", "morphkit", "demo", "-o", str(out)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while not (out / MARKER_NAME).exists() and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)  # the demo has claimed its folder: it is rendering
    time.sleep(1.0)
    assert p.poll() is None, p.communicate()[1]
    p.send_signal(signal.SIGINT)
    _stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 130, stderr
    assert stderr.strip().splitlines()[-1] == "morphkit: interrupted" and "Traceback" not in stderr
    assert not [f.name for f in out.rglob("*") if ".part" in f.name]  # no temporary file left


# ------------------------------------------------------------------ two bakes, one folder
def test_a_bake_into_a_locked_folder_is_refused(tmp_path):
    lib = library(tmp_path / "lib")
    out = tmp_path / "out"
    with claim_output(out, BAKE_OUTPUT).writing():  # this process is "the first bake"
        r = subprocess.run([sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(out), "-q"],
                           capture_output=True, text=True, env=ENV, timeout=120)
    assert r.returncode == 1
    assert f"expected one no other run is writing to (wait for it to finish, or choose another folder), " \
           f"got one locked by process {os.getpid()}" in one_line(r.stderr)
    assert not (out / "manifest.json").exists()


@pytest.mark.gl
def test_two_bakes_into_one_folder_at_once(tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    for i in range(3):
        trimesh.creation.box([1.0, 0.5 + 0.1 * i, 0.8]).export(lib / f"box{i}.ply")
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(out), "--workers", "1",
           "--atlas-size", "32", "-q"]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
             for _ in range(2)]
    results = [(p.wait(timeout=300), p.stderr.read()) for p in procs]
    for p in procs:
        p.stdout.close()
        p.stderr.close()
    for rc, err in results:  # each ran (or found everything done), or was refused by the lock
        assert rc == 0 or (rc == 1 and "locked by process" in one_line(err)), err
    assert any(rc == 0 for rc, _ in results)
    print("two bakes, exit codes:", [rc for rc, _ in results])
    m = Manifest.open(out)  # valid, and every asset baked exactly once
    assert sorted(m.assets) == ["box0", "box1", "box2"]
    assert all(r.status in ("baked", "skipped") for r in m.assets.values())
    assert len(list(out.glob("*.atlas.npz"))) == 3 and not list(out.glob(".*.part*"))
    assert not (out / "manifest.journal").exists()


# ------------------------------------------------------------------ options checked before any work
@pytest.mark.parametrize(("args", "message"), [
    (["demo", "--size", "0"], r"--size: expected an integer in \[16, 8192\], got 0"),
    (["demo", "--size", "100000"], r"--size: expected an integer in \[16, 8192\], got 100000"),
    (["billboards", "--n", "100000000000"], r"--n: expected an integer in \[0, 100000\]"),
    (["billboards", "--frames", "100000000"], r"--frames: expected an integer in \[1, 100000\]"),
    (["billboards", "--views", "100000"], r"--views: expected an integer in \[2, 64\]"),
    (["billboards", "--asset-size", "100000"], r"--asset-size: expected an integer in \[16, 2048\]"),
    (["billboards", "--seed", "-1"], r"--seed: expected an integer in \[0, 18446744073709551615\], got -1"),
    (["billboards", "--seed", "1" + "0" * 30], r"--seed: expected an integer in \[0, "),
    (["billboards", "--size", "16384x16384"], r"--size: expected at most 67108864 pixels"),
    (["shadows", "{tmp}/a.atlas.npz", "--frames", "0"], r"--frames: expected an integer in \[1, 100000\]"),
    (["shadows", "{tmp}/a.atlas.npz", "--frames", "100000000"], r"--frames: expected an integer in"),
    (["shadows", "{tmp}/a.atlas.npz", "--size", "5"], r"--size: expected an integer in \[16, 8190\], got 5"),
    (["shadows", "{tmp}/a.atlas.npz", "--size", "8192"], r"--size: expected an integer in \[16, 8190\]"),
    (["billboards", "--size", "8192x1024"], r"--size: expected WIDTHxHEIGHT, two integers in 1\.\.8190 "),
    (["shadows", "{tmp}/a.atlas.npz", "--area-light", "1", "1", "--samples", "1000"],
     r"--samples: expected an integer in \[1, 64\], got 1000"),
    (["shadows", "{tmp}/a.atlas.npz", "--area-light", "nan", "1"], r"--area-light: expected finite numbers"),
    (["shadows", "{tmp}/a.atlas.npz", "--area-light", "0", "1"], r"--area-light: expected a width and"),
    (["viewmorph", "{tmp}/l.png", "{tmp}/l.png", "--frames", "-3"], r"--frames: expected an integer in"),
    (["viewmorph", "{tmp}/l.png", "{tmp}/l.png", "--frames", "100000000"], r"--frames: expected an integer"),
    (["viewmorph", "{tmp}/l.png", "{tmp}/l.png", "--s", "nan"], r"--s: expected finite numbers, got nan"),
    (["viewmorph", "{tmp}/l.png", "{tmp}/l.png", "--s", "5"], r"--s: expected a position in \[0, 1\], got 5"),
    (["bake", "{tmp}/lib", "--workers", "100000"], r"--workers: expected an integer in \[1, 256\]"),
])
def test_options_are_refused_before_any_work(tmp_path, capfd, no_work, args, message):
    import re

    library(tmp_path / "lib")
    argv = [a.format(tmp=tmp_path) for a in args] + ["-o", str(tmp_path / "out")]
    rc, _o, err = run(capfd, *argv)
    assert rc == 2 and re.search(message, one_line(err)), err  # a bad option value: a usage error
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------------------ a real file system
@pytest.mark.gl
def test_a_library_with_odd_names_links_and_a_fifo_bakes_what_it_can(tmp_path, capfd):
    lib = library(tmp_path / "lib")
    data = (lib / "box.ply").read_bytes()
    odd = os.path.join(os.fsencode(lib), b"caf\xe9.ply")  # Latin-1, not UTF-8
    with open(odd, "wb") as f:
        f.write(data)
    (lib / "broken.ply").symlink_to("nowhere.ply")
    (lib / "loopa.ply").symlink_to("loopb.ply")
    (lib / "loopb.ply").symlink_to("loopa.ply")
    os.mkfifo(lib / "fifo.ply")  # opening it would wait for a writer forever
    (lib / "sub").mkdir()
    (lib / "sub" / "up").symlink_to(lib)  # a folder loop (not followed)
    out = tmp_path / "out"
    rc, _o, err = run(capfd, "bake", lib, "-o", out, "--workers", "1", "--atlas-size", "32", "-q")
    assert rc == 1 and "Traceback" not in err
    failed = [line for line in err.splitlines() if line.startswith("morphkit bake: failed: ")]
    assert len(failed) == len(err.strip().splitlines()) == 4, err
    m = Manifest.open(out)
    status = {k: (r.status, r.error) for k, r in m.assets.items()}
    odd_name = "caf\udce9"
    assert status["box"][0] == status[odd_name][0] == "baked"
    assert status["broken"] == ("failed", "FileNotFoundError: cannot read the input: No such file or "
                                "directory")
    assert status["fifo"] == ("failed", "OSError: cannot read the input: not a regular file (a FIFO, device "
                              "or socket)")
    assert status["loopa"][0] == status["loopb"][0] == "failed"
    assert os.path.exists(os.path.join(os.fsencode(out), b"caf\xe9.atlas.npz"))
    rc, _o, err = run(capfd, "bake", lib, "-o", out, "--workers", "1", "--atlas-size", "32", "-q")
    m = Manifest.open(out)  # a rerun: the baked ones are kept, the bad ones fail again
    assert rc == 1 and m.assets["box"].status == m.assets[odd_name].status == "skipped"


def test_an_interrupt_a_library_swallowed_is_still_an_interrupt(monkeypatch, capsys):
    """Seen with numba: Ctrl-C while it saved a kernel it was compiling landed in a C callback,
    where the KeyboardInterrupt was dropped, and numba then failed with a RuntimeError; the
    command must still end as interrupted (130, one line), not with that traceback."""
    from morphkit import cli

    def swallowing_command(args):
        import ctypes

        def callback():
            os.kill(os.getpid(), signal.SIGINT)  # the handler runs in the callback and raises
            time.sleep(1.0)

        ctypes.CFUNCTYPE(None)(callback)()  # a C callback: the KeyboardInterrupt is dropped there
        raise RuntimeError("no compiled object yet")

    def plain_failure(args):
        raise RuntimeError("a bug, not an interrupt")

    # Python's own handler, as in a terminal (a test run in the background may inherit SIGINT ignored)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        monkeypatch.setattr(cli, "_cmd_demo", swallowing_command)
        hook = sys.unraisablehook
        assert cli.main(["demo", "-o", "unused"]) == 130
        err = capsys.readouterr().err
        assert err.strip().splitlines()[-1] == "morphkit: interrupted" and "Traceback" not in err
        assert sys.unraisablehook is hook  # restored
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
        monkeypatch.setattr(cli, "_cmd_demo", plain_failure)
        with pytest.raises(RuntimeError, match="a bug, not an interrupt"):
            cli.main(["demo", "-o", "unused"])
    finally:
        signal.signal(signal.SIGINT, old)
