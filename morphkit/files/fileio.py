"""Writing files atomically: one place for every file morphkit writes (and reads images).

A file is written to a temporary file in the same folder, flushed and
``fsync``-ed, then renamed over the target (``os.replace``, atomic on POSIX and
Windows within one file system). A crash, a full disk or a killed process in
the middle of a write leaves either the old file or the new one, never half of
one; the temporary file is removed on failure.

Two writes are not a whole file at once: :func:`atomic_output` gives a writer
that needs a file name (``cv2.VideoWriter``) a temporary path beside the
target, renamed over it on success; :func:`append_lines` appends lines to a
log (a journal), flushed and ``fsync``-ed, so a crash leaves at most a
truncated last line, which readers skip.

Images are encoded in memory first (``cv2.imencode``), so an unknown extension
or an image OpenCV cannot encode is a :class:`~morphkit.errors.ValidationError`
before anything touches the disk.

Images here are in morphkit's channel order, RGB / RGBA (see
:mod:`morphkit.conventions`): :func:`encode_image` and :func:`write_image` take it
and :func:`read_image` returns it; the swap to and from OpenCV's BGR / BGRA
happens here and nowhere else.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import struct
import tempfile
import zipfile
import zlib
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO, Any

import cv2
import numpy as np

from ..errors import FileFormatError, MorphkitError, RenderError, ValidationError, expected_got

__all__ = ["array_digest", "ARCHIVE_ERRORS", "check_writable", "atomic_write", "atomic_output",
           "open_video_writer", "quiet_stderr", "append_lines", "write_bytes", "write_text", "write_json",
           "encode_image", "decode_image", "write_image", "read_image", "file_kind", "open_regular",
           "read_json"]

#: What reading a damaged or foreign ``.npz`` (a zip of ``.npy`` arrays) with ``np.load`` can
#: raise: every file loader catches these and raises a FileFormatError naming the file and what
#: it expected (a truncated deflate stream is a ``zlib.error``, a damaged header a
#: ``struct.error``, a foreign compression method ``NotImplementedError``, an encrypted member
#: ``RuntimeError``, a bad ``.npy`` header ``ValueError``/``SyntaxError``).
ARCHIVE_ERRORS: tuple[type[Exception], ...] = (
    OSError, EOFError, ValueError, KeyError, TypeError, SyntaxError, zipfile.BadZipFile, zlib.error,
    struct.error, NotImplementedError, RuntimeError, UnicodeDecodeError, OverflowError)

#: OpenCV's channel order of a 3- or 4-channel image from morphkit's (and back:
#: the permutation is its own inverse).
_SWAP_RB = {3: [2, 1, 0], 4: [2, 1, 0, 3]}


def _swap_red_blue(image: np.ndarray) -> np.ndarray:
    """RGB(A) <-> BGR(A) of a 3- or 4-channel image; other images as they are."""
    if image.ndim == 3 and image.shape[2] in _SWAP_RB:
        return image[..., _SWAP_RB[image.shape[2]]]
    return image


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], Any]) -> Path:
    """Call ``write(f)`` on a temporary binary file beside ``path``, then rename it to ``path``.

    Parameters
    ----------
    path : path-like
        The target file. Its folder must exist; an existing file is replaced
        only once the new content is complete.
    write : callable
        Writes the whole content to the open binary file it is given.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValidationError
        ``path`` is an existing folder.
    OSError
        The folder is missing or not writable, the disk is full, ...; the
        target is then untouched and no temporary file is left.

    Examples
    --------
    A write that fails half-way leaves the previous file as it was, and no temporary file:

    >>> import json, tempfile
    >>> from pathlib import Path
    >>> from morphkit.files.fileio import atomic_write, write_json
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = write_json(Path(tmp.name) / "rows.json", {"iou": 0.97})
    >>> def fail(f):
    ...     f.write(b'{"iou": 0.')
    ...     raise OSError("disk full")
    >>> atomic_write(path, fail)
    Traceback (most recent call last):
    ...
    OSError: disk full
    >>> json.loads(path.read_text())
    {'iou': 0.97}
    >>> [p.name for p in Path(tmp.name).iterdir()]
    ['rows.json']
    >>> tmp.cleanup()
    """
    with atomic_output(path) as tmp, open(tmp, "wb") as f:
        write(f)
    return Path(path)


@contextmanager
def atomic_output(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary path beside ``path`` (same suffix) to write; renamed to ``path`` on success.

    For writers that open the file themselves (``cv2.VideoWriter`` picks the
    container from the suffix). On a clean exit of the ``with`` block the
    temporary file is ``fsync``-ed and renamed over ``path``; on an exception
    it is removed and ``path`` is untouched.

    Parameters
    ----------
    path : path-like
        The target file; its folder must exist.

    Yields
    ------
    pathlib.Path
        The temporary path (an empty file exists there).

    Raises
    ------
    ValidationError
        ``path`` is an existing folder, or the block left no file at the temporary path.
    """
    p = Path(path)
    if p.is_dir():
        raise ValidationError(expected_got("output path", "a file path", f"the folder {p}"))
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=f".part{p.suffix}",
                                   dir=p.parent if str(p.parent) else ".")
    except OSError as exc:  # name the target, not the temporary file
        raise type(exc)(exc.errno, f"cannot write {p}: {exc.strerror}") from exc
    try:
        os.close(fd)
        yield Path(tmp)
        if not os.path.isfile(tmp):
            raise ValidationError(expected_got(f"temporary output for {p.name}", "a written file",
                                               "nothing"))
        with open(tmp, "rb") as f:
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


@contextmanager
def quiet_stderr() -> Iterator[None]:
    """Hold back what native code writes on the process's stderr (file descriptor 2) inside the
    block: a C library's diagnostics that morphkit reports in its own words. Python's
    ``sys.stderr`` is flushed first; the descriptor is restored on leaving, also by an exception.

    Yields
    ------
    None
    """
    import sys

    with suppress(Exception):
        sys.stderr.flush()
    try:
        saved = os.dup(2)
    except OSError:  # no stderr to hold back
        yield
        return
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def open_video_writer(path: str | os.PathLike[str], fourcc: str, fps: float,
                      shape: tuple[int, int]) -> cv2.VideoWriter:
    """An open ``cv2.VideoWriter`` of ``shape`` frames at ``path``, or a one-line error saying why not.

    OpenCV only answers "not opened" (and logs its reason on stderr); here its log is held back
    -- and the FFmpeg backend's own line on stderr while the writer opens (WebM has no codec
    tags, so any FourCC for it is "not supported ... fallback") -- and the cause told apart:
    a writer that opens for 16 x 16 frames but not for ``shape`` was refused the size (the
    encoder's buffers need more memory than the process may use, or pass the codec's own
    limits), one that never opens is missing from this OpenCV build.

    Parameters
    ----------
    path : path-like
        The video file (its suffix picks the container); its folder must exist.
    fourcc : str
        The codec's four characters, e.g. ``"mp4v"``.
    fps : float
        Frames per second.
    shape : (int, int)
        Frame shape ``(H, W)``.

    Returns
    -------
    cv2.VideoWriter
        Opened; the caller releases it.

    Raises
    ------
    RenderError
        OpenCV cannot open the writer (the message says whether for this size only).
    """
    h, w = int(shape[0]), int(shape[1])
    level = cv2.utils.logging.getLogLevel()
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)  # its reason is ours to tell
    try:
        with quiet_stderr():
            writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), float(fps), (w, h))
        if writer.isOpened():
            return writer
        writer.release()
        p = Path(path)
        fd, probe = tempfile.mkstemp(prefix=".morphkit-probe-", suffix=p.suffix, dir=p.parent)
        os.close(fd)
        try:
            with quiet_stderr():
                small = cv2.VideoWriter(probe, cv2.VideoWriter_fourcc(*fourcc), float(fps), (16, 16))
            opens_small = small.isOpened()
            small.release()
        finally:
            os.unlink(probe)
    finally:
        cv2.utils.logging.setLogLevel(level)
    got = (f"a refusal for {w} x {h} frames (it opens for 16 x 16: frames this size need more memory "
           "than this process may use, or pass the codec's limits)" if opens_small
           else "none in this OpenCV build")
    raise RenderError(expected_got("video writer", f"OpenCV's {fourcc} writer for {p.suffix} files", got))


def append_lines(path: str | os.PathLike[str], lines: Sequence[str]) -> Path:
    """Append lines (a newline added to each) to ``path``, creating it; one write, flushed and
    ``fsync``-ed once (a group commit: many records cost one disk sync).

    A write that fails (a full disk) is cut back off: the file is left as it was. A file
    whose last line a crash cut short gets a newline first, so the new lines stay whole.

    Parameters
    ----------
    path : path-like
        The log file; its folder must exist.
    lines : sequence of str
        Lines of text, each without a newline.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValidationError
        A line contains a newline (nothing is written).
    OSError
        The file cannot be written (nothing of ``lines`` is left in it).
    """
    for line in lines:
        if "\n" in line or "\r" in line:
            raise ValidationError(expected_got("log line", "one line without newlines",
                                               f"{len(line.splitlines())} lines"))
    p = Path(path)
    data = "".join(f"{line}\n" for line in lines).encode("utf-8")
    fd = os.open(p, os.O_RDWR | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        start = os.fstat(fd).st_size
        if start and os.pread(fd, 1, start - 1) != b"\n":  # a line cut short (a crash): ours start anew
            data = b"\n" + data
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view):]
            os.fsync(fd)
        except BaseException:  # e.g. a full disk: no half line of ours is left behind
            with suppress(OSError):
                os.ftruncate(fd, start)
            raise
    finally:
        os.close(fd)
    return p


def array_digest(a: np.ndarray) -> str:
    """SHA-256 (hex) of an array's bytes in C order: the checksum the ``.npz`` formats of
    morphkit (shadow atlas, billboard and dome assets) store per array and check on load.

    Parameters
    ----------
    a : numpy.ndarray
        Any array.

    Returns
    -------
    str
        64 hex digits.
    """
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()


def write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (:func:`atomic_write`).

    Parameters
    ----------
    path : str or os.PathLike
        File to write; its folder must exist.
    data : bytes
        The whole content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return atomic_write(path, lambda f: f.write(data))


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically (:func:`atomic_write`).

    Parameters
    ----------
    path : str or os.PathLike
        File to write; its folder must exist.
    text : str
        The whole content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return write_bytes(path, text.encode("utf-8"))


def write_json(path: str | os.PathLike[str], obj: Any, *, indent: int | None = 2) -> Path:
    """Write ``obj`` as JSON (no NaN/inf: they are not JSON) to ``path`` atomically.

    Parameters
    ----------
    path : str or os.PathLike
        File to write; its folder must exist.
    obj : Any
        A JSON-serialisable object (finite numbers only).
    indent : int or None
        Indentation passed to ``json.dumps`` (None: one line).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return write_text(path, json.dumps(obj, indent=indent, allow_nan=False) + "\n")


def encode_image(path: str | os.PathLike[str], image: np.ndarray) -> bytes:
    """Encode ``image`` (RGB/RGBA, morphkit's order) in the format named by ``path``'s extension.

    Parameters
    ----------
    path : str or os.PathLike
        File name whose extension (``.png``, ``.jpg``, ...) names the format;
        nothing is written.
    image : (H, W), (H, W, 3) or (H, W, 4) array
        Grey, RGB or RGBA (straight alpha) image, in a dtype the format supports
        (uint8, or uint16 for PNG). It is swapped to OpenCV's BGR/BGRA here.

    Returns
    -------
    bytes
        The encoded file content.

    Raises
    ------
    ValidationError
        The extension is missing or unknown to OpenCV, or OpenCV cannot encode
        this image in it.
    """
    ext = Path(path).suffix.lower()
    if not ext:
        raise ValidationError(expected_got("image file name", "an extension such as .png or .jpg",
                                           f"{Path(path).name!r}"))
    img = np.asarray(image)
    try:
        ok, buf = cv2.imencode(ext, _swap_red_blue(img))
    except cv2.error as exc:
        raise ValidationError(expected_got(f"image for {ext}", "an image OpenCV can encode in that format",
                                           f"{img.dtype} {img.shape}: "
                                           f"{str(exc).strip().splitlines()[-1]}")) from exc
    if not ok:
        raise ValidationError(expected_got(f"image for {ext}", "an image OpenCV can encode in that format",
                                           f"{img.dtype} {img.shape}"))
    return buf.tobytes()


def write_image(path: str | os.PathLike[str], image: np.ndarray) -> Path:
    """Encode ``image`` (grey, RGB or RGBA) and write it to ``path`` atomically.

    Parameters
    ----------
    path : str or os.PathLike
        File to write; its extension names the format (see :func:`encode_image`).
    image : (H, W), (H, W, 3) or (H, W, 4) array
        Grey, RGB or RGBA (straight alpha) image, morphkit's channel order
        (:mod:`morphkit.conventions`); uint8, or uint16 for PNG.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> red = np.zeros((2, 3, 3), np.uint8); red[..., 0] = 255
    >>> path = write_image(Path(tempfile.mkdtemp()) / "red.png", red)
    >>> read_image(path)[0, 0].tolist()        # RGB in, RGB out
    [255, 0, 0]
    >>> cv2.imread(str(path))[0, 0].tolist()   # BGR in the file's OpenCV reading
    [0, 0, 255]
    """
    return write_bytes(path, encode_image(path, image))


def file_kind(mode: int) -> str:
    """What a file that is not a regular file is, from its ``st_mode``, for a message.

    Parameters
    ----------
    mode : int
        ``os.stat(path).st_mode``.

    Returns
    -------
    str
        ``"a FIFO (named pipe)"``, ``"a character device"``, ``"a block device"``, ``"a socket"``,
        ``"a directory"``, or ``"not a regular file"``.
    """
    for test, name in ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"),
                       (stat.S_ISDIR, "a directory")):
        if test(mode):
            return name
    return "not a regular file"


@contextmanager
def open_regular(path: str | os.PathLike[str], what: str,
                 error: type[MorphkitError] = FileFormatError) -> Iterator[IO[bytes]]:
    """``path`` open for reading, only if it is a regular file.

    It is opened without blocking (opening a FIFO that no process writes to would wait forever) and
    checked on the open descriptor (a file swapped for a FIFO or a folder after a check by name is
    refused too); a regular file is then read as usual.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    what : str
        What the file is, for the error message.
    error : type of MorphkitError
        The error raised (default :class:`~morphkit.errors.FileFormatError`).

    Yields
    ------
    file object
        Binary, blocking, closed on leaving the block.

    Raises
    ------
    MorphkitError
        ``error``: nothing at ``path``, a file that cannot be opened, or one that is not a regular
        file (a FIFO, a folder, a device, a socket; :func:`file_kind`).
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except FileNotFoundError as exc:
        raise error(expected_got(what, "an existing file", f"nothing at {str(path)!r}")) from exc
    except OSError as exc:
        raise error(expected_got(what, "a readable file", f"{str(path)!r} ({exc.strerror or exc})")) from exc
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise error(expected_got(what, "a regular file", f"{str(path)!r}: {file_kind(mode)}"))
        os.set_blocking(fd, True)
        f = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    with f:
        yield f


def read_json(path: str | os.PathLike[str], what: str) -> Any:
    """The JSON document in the regular file ``path`` (:func:`open_regular`), UTF-8.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    what : str
        What the file is, for the error message (``"scene file"``, ``"plan file"``).

    Returns
    -------
    object
        The decoded document.

    Raises
    ------
    FileFormatError
        No regular file there, or one that is not UTF-8 JSON (the decoder's message named).
    """
    with open_regular(path, what) as fh:
        data = fh.read()
    try:
        return json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise FileFormatError(expected_got(f"{what} {path}", "JSON", f"{type(exc).__name__}: {exc}")) from exc


def read_image(path: str | os.PathLike[str]) -> np.ndarray:
    """Read an image file into morphkit's channel order.

    Parameters
    ----------
    path : str or os.PathLike
        An image file OpenCV can decode (PNG, JPEG, TIFF, BMP, ...).

    Returns
    -------
    numpy.ndarray
        The image as stored, unconverted except for the channel order: ``(H, W)``
        grey, ``(H, W, 3)`` RGB or ``(H, W, 4)`` RGBA (straight alpha); dtype
        uint8, or uint16 for 16-bit PNG/TIFF.

    Raises
    ------
    FileFormatError
        Nothing at ``path``, a folder, an unreadable file, or content OpenCV
        cannot decode.
    """
    p = Path(path)
    # decoded from bytes: cv2.imread prints its own warning for a missing file
    if p.is_dir() or not p.exists():  # a FIFO, a device: refused by open_regular, never waited on
        raise FileFormatError(expected_got(f"image {str(path)!r}", "an existing file",
                                           "a folder" if p.is_dir() else "nothing there"))
    with open_regular(p, f"image {str(path)!r}") as f:
        try:
            data = f.read()
        except OSError as exc:
            raise FileFormatError(expected_got(f"image {str(path)!r}", "a readable file",
                                               exc.strerror or exc)) from exc
    return decode_image(data, f"image {str(path)!r}")


def decode_image(data: bytes, what: str = "image") -> np.ndarray:
    """Decode an image file's content (what :func:`encode_image` gives) into morphkit's channel order.

    Parameters
    ----------
    data : bytes
        The encoded image (PNG, JPEG, TIFF, BMP, ...).
    what : str, optional
        What it is, for the error.

    Returns
    -------
    numpy.ndarray
        As :func:`read_image`.

    Raises
    ------
    FileFormatError
        Content OpenCV cannot decode.
    """
    buf = np.frombuffer(data, dtype=np.uint8)
    try:
        img = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED) if buf.size else None
    except cv2.error as exc:  # e.g. a damaged header's size past OpenCV's limit
        raise FileFormatError(expected_got(what, "an image file OpenCV can decode",
                                           f"{buf.size} bytes it refuses: "
                                           f"{str(exc).strip().splitlines()[-1]}"[:300])) from exc
    if img is None:
        raise FileFormatError(expected_got(what, "an image file OpenCV can decode",
                                           f"{buf.size} bytes it cannot"))
    return np.ascontiguousarray(_swap_red_blue(img))


def check_writable(folder: str | os.PathLike[str]) -> Path:
    """Create ``folder`` if needed and prove it writable by creating and removing a probe file.

    Parameters
    ----------
    folder : str or os.PathLike
        The output folder.

    Returns
    -------
    pathlib.Path
        ``folder``, resolved to an absolute path.

    Raises
    ------
    ValidationError
        The folder cannot be created or written (a file in the way, no permission, read-only).
    """
    p = Path(folder)
    try:
        p.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".morphkit-probe-", dir=p)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise ValidationError(expected_got("output folder", "a folder morphkit can create and write",
                                           f"{str(p)!r} ({type(exc).__name__}: {exc.strerror or exc})")
                              ) from exc
    return p.resolve()
