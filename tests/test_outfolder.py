"""morphkit.files.outfolder: one rule for every command's output folder (no GL)."""

from __future__ import annotations

import json
import os

import pytest

from morphkit.errors import OutputBusyError, OutputExistsError, ValidationError
from morphkit.files.outfolder import (
    BAKE_OUTPUT,
    BILLBOARDS_OUTPUT,
    DEMO_OUTPUT,
    LOCK_NAME,
    MARKER_NAME,
    SHADOWS_OUTPUT,
    claim_output,
    previous_run,
)


def _write_frames(folder, n):
    for i in range(n):
        (folder / f"frame_{i:04d}.png").write_bytes(b"new %d" % i)
    (folder / "shadows.webm").write_bytes(b"video")


def test_a_new_folder_is_created_only_when_writing(tmp_path):
    out = tmp_path / "a" / "b"
    claim = claim_output(out, SHADOWS_OUTPUT)
    assert not (tmp_path / "a").exists()  # the check creates nothing
    with claim.writing() as folder:
        assert folder == out and sorted(q.name for q in out.iterdir()) == [MARKER_NAME]  # no lock file
        assert json.loads((out / MARKER_NAME).read_text())["status"] == "running"
        _write_frames(folder, 2)
    marker = json.loads((out / MARKER_NAME).read_text())
    assert marker["command"] == "shadows" and marker["status"] == "complete"
    assert previous_run(out, SHADOWS_OUTPUT) == out / MARKER_NAME
    assert previous_run(out, DEMO_OUTPUT) is None


def test_a_run_that_fails_before_writing_leaves_nothing(tmp_path):
    out = tmp_path / "a" / "b"
    for exc in (RuntimeError("boom"), KeyboardInterrupt()):
        with pytest.raises(type(exc)), claim_output(out, SHADOWS_OUTPUT).writing():
            raise exc
        assert list(tmp_path.iterdir()) == []  # neither the folders nor the marker and lock
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(KeyboardInterrupt), claim_output(empty, SHADOWS_OUTPUT).writing():
        raise KeyboardInterrupt
    assert empty.is_dir() and list(empty.iterdir()) == []  # it was there: kept, as it was


def test_a_folder_with_other_files_is_refused_and_left_as_it_is(tmp_path):
    (tmp_path / "holiday.png").write_bytes(b"mine")
    for rule in (SHADOWS_OUTPUT, DEMO_OUTPUT, BAKE_OUTPUT):
        for overwrite in (False, True):
            with pytest.raises(OutputExistsError, match=rf"{rule.command} output folder: expected a new or "
                               rf"empty folder, or a previous {rule.command} run, got .* holding 1 entries "
                               r"that are not one, e.g. 'holiday.png'"):
                claim_output(tmp_path, rule, overwrite=overwrite)
    assert [p.name for p in tmp_path.iterdir()] == ["holiday.png"]
    assert (tmp_path / "holiday.png").read_bytes() == b"mine"


def test_a_file_or_a_path_under_a_file_is_refused(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    with pytest.raises(ValidationError, match=r"shadows output folder: expected a folder, got the file .*f$"):
        claim_output(f, SHADOWS_OUTPUT)
    with pytest.raises(ValidationError, match=r"shadows output folder: expected a folder morphkit can create "
                       r"and write, got '.*f/sub' \(NotADirectoryError: .*f is a file\)"):
        claim_output(f / "sub", SHADOWS_OUTPUT)


def test_another_commands_output_is_refused(tmp_path):
    with claim_output(tmp_path / "o", SHADOWS_OUTPUT).writing() as out:
        _write_frames(out, 1)
    with pytest.raises(OutputExistsError, match="holding the output of morphkit shadows"):
        claim_output(tmp_path / "o", DEMO_OUTPUT, overwrite=True)


def test_a_previous_run_is_replaced_only_with_overwrite_and_never_mixed(tmp_path):
    out = tmp_path / "o"
    with claim_output(out, SHADOWS_OUTPUT).writing():
        _write_frames(out, 5)
    (out / "notes.txt").write_text("mine")  # the user's, beside the run
    with pytest.raises(OutputExistsError, match=r"shadows output folder: expected one without a previous "
                       r"shadows \(--overwrite / overwrite=True replaces it\), got .* holding "
                       + MARKER_NAME.replace(".", r"\.")):
        claim_output(out, SHADOWS_OUTPUT)
    with claim_output(out, SHADOWS_OUTPUT, overwrite=True).writing():
        _write_frames(out, 2)  # fewer frames than before
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted([MARKER_NAME, "frame_0000.png", "frame_0001.png", "shadows.webm",
                            "notes.txt"])  # old frames 2..4 gone, the user's file kept


def test_a_bake_folder_is_resumed_without_overwrite(tmp_path):
    (tmp_path / "manifest.json").write_text('{"format": "morphkit-bake-manifest", "version": 1}')  # no marker
    (tmp_path / "box.atlas.npz").write_bytes(b"atlas")
    claim = claim_output(tmp_path, BAKE_OUTPUT)
    assert claim.previous
    with claim.writing():
        pass
    assert (tmp_path / "box.atlas.npz").read_bytes() == b"atlas"  # resumed: nothing removed


WEB_MANIFEST = '{"name": "My App", "short_name": "app", "start_url": "/", "icons": []}'


@pytest.mark.parametrize("others", [(), ("index.html",), (MARKER_NAME,)])
def test_another_programs_manifest_is_never_taken_for_a_bake(tmp_path, others):
    """A web app's manifest.json was taken for a bake's: resumed into, refused only once the bake
    had marked the folder (exit 1: 'expected morphkit-bake-manifest, got None')."""
    (tmp_path / "manifest.json").write_text(WEB_MANIFEST)
    for name in others:  # beside the site's page, or a bake's marker left by that refused run
        (tmp_path / name).write_text('{"morphkit_output": 1, "command": "bake"}' if name == MARKER_NAME
                                     else "<html>")
    before = sorted(p.name for p in tmp_path.iterdir())
    marked = others == (MARKER_NAME,)
    assert previous_run(tmp_path, BAKE_OUTPUT) == (tmp_path / MARKER_NAME if marked else None)
    with pytest.raises(OutputExistsError, match=r"bake output folder: expected a new or empty folder, or a "
                       r"previous bake run, got .* holding 'manifest\.json' of another program \(not "
                       r"morphkit bake's; it is never replaced: choose another folder\)"):
        claim_output(tmp_path, BAKE_OUTPUT)
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert (tmp_path / "manifest.json").read_text() == WEB_MANIFEST


def test_a_damaged_bake_manifest_is_still_a_bake(tmp_path):
    (tmp_path / "manifest.json").write_text('{"format": "morphkit-bake-manifest", "version": 1, "ass')
    assert claim_output(tmp_path, BAKE_OUTPUT).previous  # its bake reports the damage (FileFormatError)


@pytest.mark.parametrize("rule, index, key", [(DEMO_OUTPUT, "index.json", "morphkit_demo"),
                                              (BILLBOARDS_OUTPUT, "billboards.json", "morphkit_billboards")])
def test_another_programs_index_is_not_a_run_whose_files_overwrite_removes(tmp_path, rule, index, key):
    """A site's index.json listing its files was a previous demo: --overwrite would have removed
    the files it lists that the demo did not write again."""
    (tmp_path / index).write_text(json.dumps({"files": ["notes.txt"]}))
    (tmp_path / "notes.txt").write_text("mine")
    assert previous_run(tmp_path, rule) is None
    with pytest.raises(OutputExistsError, match=rf"holding '{index}' of another program"):
        claim_output(tmp_path, rule, overwrite=True)
    (tmp_path / index).write_text(json.dumps({key: 1, "files": ["notes.txt"]}))  # the command's own
    assert previous_run(tmp_path, rule) == tmp_path / index


def test_an_interrupted_run_counts_as_a_previous_run(tmp_path):
    out = tmp_path / "o"
    with pytest.raises(KeyboardInterrupt), claim_output(out, SHADOWS_OUTPUT).writing():
        _write_frames(out, 3)
        raise KeyboardInterrupt
    assert json.loads((out / MARKER_NAME).read_text())["status"] == "running"
    with pytest.raises(OutputExistsError, match="pass|--overwrite"):
        claim_output(out, SHADOWS_OUTPUT)
    with claim_output(out, SHADOWS_OUTPUT, overwrite=True).writing():
        _write_frames(out, 1)
    assert sorted(p.name for p in out.glob("frame_*")) == ["frame_0000.png"]


def test_a_second_writer_is_refused_while_the_first_holds_the_lock(tmp_path):
    out = tmp_path / "o"
    with claim_output(out, BAKE_OUTPUT).writing():
        with pytest.raises(OutputBusyError, match=rf"bake output folder .*: expected one no other run is "
                           rf"writing to \(wait for it to finish, or choose another folder\), got one "
                           rf"locked by process {os.getpid()}"):
            with claim_output(out, BAKE_OUTPUT).writing():
                pass  # pragma: no cover
        assert (out / MARKER_NAME).is_file()  # the first run's marker is untouched
    with claim_output(out, BAKE_OUTPUT).writing():  # released: the next run goes on
        pass


def test_a_killed_runs_temporary_files_are_removed_by_the_next_run(tmp_path):
    import tempfile

    out = tmp_path / "o"
    with claim_output(out, BAKE_OUTPUT).writing():
        (out / "sub").mkdir()
        (out / "sub" / "oak.atlas.npz").write_bytes(b"done")
        # what SIGKILL leaves of fileio.atomic_output("sub/elm.atlas.npz"): its temporary file
        fd, left = tempfile.mkstemp(prefix=".elm.atlas.", suffix=".part.npz", dir=out / "sub")
        os.write(fd, b"half")
        os.close(fd)
        (out / ".notes.part").write_text("the user's")  # not a temporary file's name
    with claim_output(out, BAKE_OUTPUT).writing():
        pass
    assert not os.path.exists(left) and (out / "sub" / "oak.atlas.npz").read_bytes() == b"done"
    assert (out / ".notes.part").read_text() == "the user's"


def test_overwrite_removes_only_what_the_previous_run_recorded(tmp_path):
    """The user's PNGs beside a demo and in its subfolders, and their edited copies of a
    billboards run's frames, survive --overwrite; the run's own files not written again go."""
    from morphkit.files.outfolder import BILLBOARDS_OUTPUT

    demo = tmp_path / "demo"
    with claim_output(demo, DEMO_OUTPUT).writing():
        for name in ("cow_scene.png", "cow_viewmorph.png", "index.json"):
            (demo / name).write_bytes(b'{"morphkit_demo": 1}' if name == "index.json" else b"demo")
    assert json.loads((demo / MARKER_NAME).read_text())["files"] == ["cow_scene.png", "cow_viewmorph.png",
                                                                     "index.json"]
    (demo / "holiday.png").write_bytes(b"mine")
    (demo / "album").mkdir()
    (demo / "album" / "beach.png").write_bytes(b"mine too")
    with claim_output(demo, DEMO_OUTPUT, overwrite=True).writing():
        for name in ("cow_scene.png", "index.json"):  # the new demo does not write cow_viewmorph.png
            (demo / name).write_bytes(b'{"morphkit_demo": 2}' if name == "index.json" else b"new")
    assert not (demo / "cow_viewmorph.png").exists()
    assert (demo / "holiday.png").read_bytes() == b"mine"
    assert (demo / "album" / "beach.png").read_bytes() == b"mine too"

    bb = tmp_path / "bb"
    with claim_output(bb, BILLBOARDS_OUTPUT).writing():
        (bb / "frames").mkdir()
        for i in range(3):
            (bb / "frames" / f"frame_{i:04d}.png").write_bytes(b"frame")
        (bb / "compare_0000.png").write_bytes(b"compare")
        (bb / "billboards.json").write_text('{"morphkit_billboards": 1}')
    (bb / "compare_0000 - edited.png").write_bytes(b"edited")
    (bb / "frames" / "frame_0000 (copy).png").write_bytes(b"copy")
    with claim_output(bb, BILLBOARDS_OUTPUT, overwrite=True).writing():
        (bb / "frames" / "frame_0000.png").write_bytes(b"new")
        (bb / "billboards.json").write_text('{"morphkit_billboards": 1}')
    assert sorted(p.name for p in (bb / "frames").iterdir()) == ["frame_0000 (copy).png", "frame_0000.png"]
    assert sorted(p.name for p in bb.glob("compare_*")) == ["compare_0000 - edited.png"]
    assert json.loads((bb / MARKER_NAME).read_text())["files"] == ["billboards.json", "frames/frame_0000.png"]


def test_a_previous_run_without_a_record_is_replaced_by_the_commands_exact_names(tmp_path):
    """A killed run (its marker says running, no file list): its frames go, a copy the user made stays."""
    out = tmp_path / "o"
    out.mkdir()
    (out / MARKER_NAME).write_text(json.dumps({"command": "shadows", "status": "running"}))
    _write_frames(out, 3)
    (out / "frame_0001 (copy).png").write_bytes(b"mine")
    with claim_output(out, SHADOWS_OUTPUT, overwrite=True).writing():
        _write_frames(out, 1)
    assert sorted(p.name for p in out.glob("frame_*")) == ["frame_0000.png", "frame_0001 (copy).png"]


def test_an_older_versions_lock_file_is_removed_and_none_is_left(tmp_path):
    out = tmp_path / "o"
    with claim_output(out, SHADOWS_OUTPUT).writing():
        _write_frames(out, 1)
    (out / LOCK_NAME).write_text("4242")  # what an older morphkit left beside its marker
    with claim_output(out, SHADOWS_OUTPUT, overwrite=True).writing():
        _write_frames(out, 1)
    own = [p.name for p in out.iterdir() if p.name.startswith(".")]
    assert own == [MARKER_NAME]


def _snapshot(folder):
    """Every file (its bytes) and folder under ``folder``."""
    return {p.relative_to(folder).as_posix(): (p.read_bytes() if p.is_file() else None)
            for p in sorted(folder.rglob("*"))}


def test_a_run_refused_after_making_a_subfolder_leaves_the_folder_as_it_was(tmp_path):
    from morphkit.files.outfolder import BILLBOARDS_OUTPUT

    out = tmp_path / "a" / "b"
    claim = claim_output(out, BILLBOARDS_OUTPUT)
    with pytest.raises(ValidationError, match="the video writer"), claim.writing():
        (out / "frames").mkdir()  # the run's first step, then it finds a bad input
        (out / "frames" / ".frame_0000.ab12cd34.part.png").write_bytes(b"half")
        raise ValidationError("the video writer")
    assert list(tmp_path.iterdir()) == []  # no frames/, no marker, no folders
    # a previous run: the folder is left byte for byte as it was (its marker says complete still)
    with claim_output(out, BILLBOARDS_OUTPUT).writing():
        (out / "frames").mkdir()
        (out / "frames" / "frame_0000.png").write_bytes(b"frame")
    (out / "notes").mkdir()
    before = _snapshot(out)
    for exc in (ValidationError("a bad asset"), KeyboardInterrupt()):
        with pytest.raises(type(exc)), claim_output(out, BILLBOARDS_OUTPUT, overwrite=True).writing():
            (out / "compare").mkdir()
            (out / "frames" / "more").mkdir()
            raise exc
        assert _snapshot(out) == before
    assert json.loads((out / MARKER_NAME).read_text())["status"] == "complete"


def test_an_empty_subfolder_morphkit_makes_never_blocks_a_run(tmp_path):
    from morphkit.files.outfolder import BILLBOARDS_OUTPUT, subfolders

    assert subfolders() == {"frames", "tables"}  # tables: morphkit plan's error tables
    out = tmp_path / "o"
    (out / "frames").mkdir(parents=True)  # what an older version left of a run refused at its start
    (out / "frames" / ".frame_0000.ab12cd34.part.png").write_bytes(b"half")
    for rule in (BILLBOARDS_OUTPUT, SHADOWS_OUTPUT):
        for overwrite in (False, True):
            assert claim_output(out, rule, overwrite=overwrite).previous is False
    with claim_output(out, BILLBOARDS_OUTPUT, overwrite=True).writing():
        (out / "frames" / "frame_0000.png").write_bytes(b"frame")
    assert sorted(_snapshot(out)) == [MARKER_NAME, "frames", "frames/frame_0000.png"]
    # a subfolder holding a file of the user's, or another empty folder, is not morphkit's
    for extra in ("frames2/", "frames/mine.txt"):
        other = tmp_path / extra.replace("/", "_")
        (other / "frames").mkdir(parents=True)
        target = other / extra
        target.mkdir() if extra.endswith("/") else target.write_text("mine")
        with pytest.raises(OutputExistsError, match=r"holding \d entries that are not one"):
            claim_output(other, BILLBOARDS_OUTPUT, overwrite=True)
