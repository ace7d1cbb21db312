"""morphkit.files.fileio: atomic writes leave the old file or the new one, never half of one."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from morphkit.errors import FileFormatError, ValidationError
from morphkit.files.fileio import atomic_write, read_image, write_image, write_json, write_text


def test_write_replaces_and_leaves_no_temporary(tmp_path: Path) -> None:
    p = tmp_path / "a.txt"
    write_text(p, "old")
    write_text(p, "new")
    assert p.read_text() == "new"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.txt"]


def test_failed_write_keeps_the_old_file(tmp_path: Path) -> None:
    p = tmp_path / "a.bin"
    p.write_bytes(b"good")

    def half(f):  # writes part of the content, then fails (a full disk, a crash)
        f.write(b"ba")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        atomic_write(p, half)
    assert p.read_bytes() == b"good"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.bin"]


def test_folder_target_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValidationError, match="expected a file path, got the folder"):
        write_text(tmp_path, "x")


def test_json_refuses_nan(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="not JSON compliant"):
        write_json(tmp_path / "a.json", {"x": float("nan")})
    assert not (tmp_path / "a.json").exists()


def test_image_round_trip_and_bad_extension(tmp_path: Path) -> None:
    img = np.random.default_rng(0).integers(0, 256, (8, 9, 3), dtype=np.uint8)
    write_image(tmp_path / "a.png", img)
    np.testing.assert_array_equal(read_image(tmp_path / "a.png"), img)
    # RGB in morphkit, BGR in OpenCV's reading of the same file: the swap is at the boundary
    np.testing.assert_array_equal(cv2.imread(str(tmp_path / "a.png")), img[..., ::-1])
    with pytest.raises(ValidationError, match=r"image for \.xyz"):
        write_image(tmp_path / "a.xyz", img)
    with pytest.raises(ValidationError, match="an extension such as"):
        write_image(tmp_path / "noext", img)
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.png"]


@pytest.mark.parametrize(("shape", "dtype"), [((5, 7), np.uint8), ((5, 7, 4), np.uint8),
                                              ((5, 7, 3), np.uint16), ((5, 7), np.uint16)])
def test_read_image_keeps_channels_and_dtype(tmp_path: Path, shape: tuple[int, ...], dtype: type) -> None:
    img = np.random.default_rng(1).integers(0, np.iinfo(dtype).max + 1, shape).astype(dtype)
    back = read_image(write_image(tmp_path / "a.png", img))
    assert back.dtype == dtype and back.shape == shape
    np.testing.assert_array_equal(back, img)
    if len(shape) == 3:  # RGBA: alpha stays last, red and blue swap in the file only
        np.testing.assert_array_equal(cv2.imread(str(tmp_path / "a.png"), cv2.IMREAD_UNCHANGED)[..., 2],
                                      img[..., 0])


def test_read_image_errors(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match=r"image '.*nothing\.png': expected an existing file, "
                                              "got nothing there"):
        read_image(tmp_path / "nothing.png")
    with pytest.raises(FileFormatError, match="expected an existing file, got a folder"):
        read_image(tmp_path)
    (tmp_path / "bad.png").write_bytes(b"not a png")
    with pytest.raises(FileFormatError, match="expected an image file OpenCV can decode, got 9 bytes"):
        read_image(tmp_path / "bad.png")
    (tmp_path / "empty.png").write_bytes(b"")
    with pytest.raises(FileFormatError, match="got 0 bytes it cannot"):
        read_image(tmp_path / "empty.png")


def test_atomic_output_renames_on_success_and_cleans_up_on_failure(tmp_path: Path) -> None:
    from morphkit.files.fileio import atomic_output

    target = tmp_path / "clip.mp4"
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError, match="writer crashed"), atomic_output(target) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".mp4" and tmp != target
        tmp.write_bytes(b"half")
        raise RuntimeError("writer crashed")
    assert target.read_bytes() == b"old"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["clip.mp4"]
    with atomic_output(target) as tmp:
        tmp.write_bytes(b"new")
        assert target.read_bytes() == b"old"  # not renamed before the block ends
    assert target.read_bytes() == b"new"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["clip.mp4"]


def test_append_lines_appends_and_refuses_newlines(tmp_path: Path) -> None:
    from morphkit.files.fileio import append_lines

    log = tmp_path / "log.jsonl"
    append_lines(log, ['{"a": 1}'])
    append_lines(log, ['{"b": 2}', '{"c": 3}'])
    assert log.read_text() == '{"a": 1}\n{"b": 2}\n{"c": 3}\n'
    with pytest.raises(ValidationError, match="expected one line without newlines, got 2 lines"):
        append_lines(log, ["fine", "x\ny"])
    assert log.read_text() == '{"a": 1}\n{"b": 2}\n{"c": 3}\n'  # nothing of the refused batch


def test_append_lines_leaves_no_half_line(tmp_path: Path, monkeypatch) -> None:
    """A write cut short (a full disk) is cut back off; a line a crash cut short is closed first, so
    the next lines stay whole (a journal reader skips only the cut one)."""
    import errno
    import os

    from morphkit.files import fileio

    log = tmp_path / "log.jsonl"
    fileio.append_lines(log, ['{"a": 1}'])
    real_write = os.write

    def half_then_full(fd, data):
        if len(data) > 4:
            return real_write(fd, bytes(data[:4]))
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(fileio.os, "write", half_then_full)
    with pytest.raises(OSError, match="No space left on device"):
        fileio.append_lines(log, ['{"b": 2}'])
    monkeypatch.undo()
    assert log.read_text() == '{"a": 1}\n'  # as it was
    with open(log, "a") as f:
        f.write('{"c": ')  # a crash in the middle of a line
    fileio.append_lines(log, ['{"d": 4}'])
    assert log.read_text().splitlines() == ['{"a": 1}', '{"c": ', '{"d": 4}']


def test_open_regular_refuses_what_is_not_a_regular_file_without_waiting(tmp_path):
    import os

    from morphkit.errors import MeshError
    from morphkit.files.fileio import open_regular

    (tmp_path / "a.txt").write_bytes(b"content")
    with open_regular(tmp_path / "a.txt", "a file") as f:
        assert f.read() == b"content"
    os.mkfifo(tmp_path / "fifo")  # no writer: a plain open would wait forever
    (tmp_path / "folder").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "folder", target_is_directory=True)
    kinds = {"fifo": r"a FIFO \(named pipe\)", "folder": "a directory", "link": "a directory"}
    for name, kind in kinds.items():
        got = rf"^points file: expected a regular file, got '.*{name}': {kind}$"
        with pytest.raises(FileFormatError, match=got):
            with open_regular(tmp_path / name, "points file"):
                pass
    with pytest.raises(MeshError, match=r"^mesh: expected an existing file, got nothing at '.*nothing'$"):
        with open_regular(tmp_path / "nothing", "mesh", MeshError):
            pass
    with pytest.raises(FileFormatError, match=r"image '.*fifo': expected a regular file, got .*: a FIFO"):
        read_image(tmp_path / "fifo")
