"""Writing a frame sequence as a video file through OpenCV's writer, atomically.

:class:`VideoFile` opens ``cv2.VideoWriter`` on a temporary file beside the
target (same folder, same extension, so OpenCV picks the container from it) and
renames it over the target only when :meth:`VideoFile.close` is reached after
every frame was written -- a crash or an error mid-sequence leaves the old file
(or none), never half a video (as :mod:`morphkit.files.fileio` does for other files).
Use it as a context manager: leaving the ``with`` block by an exception removes
the temporary file.

Codecs (:data:`CODECS`): VP9 for ``.webm`` -- what morphkit's own commands write
(:data:`VIDEO_SUFFIX`), since browsers play it -- and, for callers who name them,
``mp4v`` (MPEG-4 Part 2, which browsers do not play) for ``.mp4`` and ``MJPG`` for
``.avi``. Frames of an odd width or height are padded by one repeated edge row or
column to even sides (4:2:0 chroma halves both; the encoder would otherwise drop
the last column).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from types import TracebackType

import cv2
import numpy as np

from .. import tol
from ..errors import RenderError, ValidationError, expected_got
from ..files.fileio import open_video_writer

__all__ = ["VideoFile", "CODECS", "VIDEO_SUFFIX"]

#: FourCC per file extension.
CODECS = {".webm": "VP90", ".mp4": "mp4v", ".avi": "MJPG"}
#: The extension of the videos morphkit's commands write (VP9 in WebM).
VIDEO_SUFFIX = ".webm"


class VideoFile:
    """A video written frame by frame, renamed into place on :meth:`VideoFile.close`.

    Parameters
    ----------
    path : path-like
        The target, ``.webm``, ``.mp4`` or ``.avi``; its folder must exist.
    fps : float
        Frames per second.
    shape : (H, W)
        Frame shape; every frame must have it.

    Raises
    ------
    ValidationError
        An unknown extension, a bad fps, or a frame side past
        :data:`morphkit.tol.MAX_VIDEO_SIDE`.
    RenderError
        OpenCV cannot open a writer for it (:func:`morphkit.files.fileio.open_video_writer`).
    """

    def __init__(self, path: str | os.PathLike[str], fps: float, shape: tuple[int, int]) -> None:
        self.path = Path(path)
        ext = self.path.suffix.lower()
        if ext not in CODECS:
            raise ValidationError(expected_got("video file", f"a name ending in one of {sorted(CODECS)}",
                                               repr(self.path.name)))
        if not (np.isfinite(fps) and fps > 0):
            raise ValidationError(expected_got("fps", "a finite number > 0", fps))
        self.shape = (int(shape[0]), int(shape[1]))
        if min(self.shape) < 1 or max(self.shape) > tol.MAX_VIDEO_SIDE:
            raise ValidationError(expected_got("video frame shape", f"sides of 1 to {tol.MAX_VIDEO_SIDE} "
                                               "pixels (tol.MAX_VIDEO_SIDE)", self.shape))
        self._pad = (self.shape[0] % 2, self.shape[1] % 2)  # to even sides (module notes)
        # named as morphkit.files.fileio.atomic_output's temporary files (.<stem>.<8 random>.part<suffix>): a
        # run killed mid-video leaves one that the next run into the folder knows as its own
        fd, tmp = tempfile.mkstemp(prefix=f".{self.path.stem}.", suffix=f".part{ext}", dir=self.path.parent)
        os.close(fd)
        self._tmp = Path(tmp)
        try:
            self._writer = open_video_writer(self._tmp, CODECS[ext], fps,
                                             (self.shape[0] + self._pad[0], self.shape[1] + self._pad[1]))
        except RenderError:
            self._tmp.unlink(missing_ok=True)
            raise
        self.frames = 0

    def write(self, rgb: np.ndarray) -> None:
        """Append one uint8 RGB frame ``(H, W, 3)``.

        Parameters
        ----------
        rgb : (H, W, 3) uint8
            The frame, RGB.
        """
        if rgb.shape != self.shape + (3,) or rgb.dtype != np.uint8:
            raise ValidationError(expected_got("video frame", f"uint8 {self.shape + (3,)}",
                                               f"{rgb.dtype} {rgb.shape}"))
        bgr = cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)
        if any(self._pad):
            bgr = cv2.copyMakeBorder(bgr, 0, self._pad[0], 0, self._pad[1], cv2.BORDER_REPLICATE)
        self._writer.write(bgr)
        self.frames += 1

    def close(self) -> Path:
        """Finish the file and rename it over the target; returns the target.

        Returns
        -------
        pathlib.Path
            The target file.
        """
        self._writer.release()
        os.chmod(self._tmp, 0o644)
        os.replace(self._tmp, self.path)
        return self.path

    def abort(self) -> None:
        """Drop the temporary file; the target is untouched."""
        self._writer.release()
        self._tmp.unlink(missing_ok=True)

    def __enter__(self) -> VideoFile:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()
