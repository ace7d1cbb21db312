"""A billboard scene along a camera path, written to files: frames, a video, Fig. 5 strips.

:func:`write_sequence` renders every camera in the view-morphed mode and
writes, into an output folder:

* ``frames/frame_NNNN.png`` -- the frame sequence;
* ``billboards.webm`` -- the same frames as a video (:class:`morphkit.programs.video.VideoFile`,
  written under a temporary name and renamed when complete);
* ``compare_NNNN.png`` -- for a few frames, classic | view-morphed | real meshes
  side by side (the paper's Fig. 5), when a mesh mode is given;
* ``billboards.json`` -- per-frame counts, cache hits and misses and times, and
  the per-billboard errors of each compared frame.

Every file goes through :mod:`morphkit.files.fileio` (atomic).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from ..billboard.compare import compare_modes
from ..billboard.frames.field import BillboardScene, FrameMode
from ..billboard.modes import ClassicMode, MorphMode
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..files.fileio import write_image, write_json
from ..files.outfolder import FRAMES_FOLDER, frame_name
from ..imaging.shading import Lighting
from ..sunlit.litmodes import Relit
from .video import VideoFile

__all__ = ["write_sequence", "compare_indices"]


def compare_indices(frames: int, count: int = 3) -> list[int]:
    """``count`` frame indices spread over ``frames`` (first, ..., last), without repeats.

    Parameters
    ----------
    frames : int
        Number of frames.
    count : int, optional
        Number of indices wanted.

    Returns
    -------
    list of int
        Sorted distinct frame indices.
    """
    if frames <= 0 or count <= 0:
        return []
    if count == 1 or frames == 1:
        return [0]
    return sorted({round(k * (frames - 1) / (count - 1)) for k in range(count)})


def write_sequence(scene: BillboardScene, cameras: Sequence[CameraModel], out: str | Path, *,
                   mode: FrameMode | None = None, truth: FrameMode | None = None, compare: int = 3,
                   fps: float = 24.0, video: bool = True, progress: bool = False,
                   classic: FrameMode | None = None, lighting: Sequence[Lighting] | None = None,
                   stem: str = "billboards", extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """Render ``cameras`` and write the frames, the video, the comparison strips and a summary.

    Parameters
    ----------
    scene : BillboardScene
    cameras : sequence of CameraModel
        The path (all the same shape).
    out : path-like
        Output folder (created).
    mode : FrameMode, optional
        The mode of the sequence; default :class:`~.modes.MorphMode`.
    truth : FrameMode, optional
        The mesh mode: with it, ``compare`` frames are also drawn classic | mode | mesh.
    compare : int
        How many frames to compare (spread over the path).
    fps : float
        Video frame rate.
    video : bool
        Write ``billboards.webm``.
    progress : bool
        A progress bar over the frames.
    classic : FrameMode, optional
        The classic billboard of the comparison strips (default :class:`~.modes.ClassicMode`;
        relit scenes: ``LitMode(ClassicSurface())``).
    lighting : sequence of Lighting, optional
        One per camera (a sun path): set on every relit mode (:class:`~.litmodes.Relit`:
        the mode, the classic and the truth) before its frame is drawn.
    stem : str, optional
        The name of the video and the summary, ``STEM.webm`` and ``STEM.json`` (``billboards``;
        ``render`` for ``morphkit render``), whose marker key is ``"morphkit_STEM"``.
    extra : dict, optional
        More entries of the summary (``render``: the scene's assets and notes).

    Returns
    -------
    dict
        The summary written to ``STEM.json`` (``files`` lists every file written,
        relative to ``out``).
    """
    out = Path(out)
    (out / FRAMES_FOLDER).mkdir(parents=True, exist_ok=True)
    mode = MorphMode() if mode is None else mode
    picks = set(compare_indices(len(cameras), compare)) if truth is not None else set()
    classic = ClassicMode() if classic is None else classic
    if lighting is not None and len(lighting) != len(cameras):
        raise ValidationError(expected_got("lighting", f"one Lighting per camera ({len(cameras)})",
                                           len(lighting)))

    def lit(cams: Sequence[CameraModel]) -> Iterator[CameraModel]:
        for k, cam in enumerate(cams):
            if lighting is not None:
                for m in (mode, classic, truth):
                    if isinstance(m, Relit):
                        m.lighting = lighting[k]
            yield cam
    files: list[str] = []
    per_frame: list[dict[str, Any]] = []
    compared: list[dict[str, Any]] = []
    sink = VideoFile(out / f"{stem}.webm", fps, cameras[0].shape) if video and cameras else None
    try:
        for k, frame in enumerate(scene.render_path(lit(cameras), mode, progress=progress,
                                                    total=len(cameras))):
            name = frame_name(k)
            write_image(out / name, frame.rgb)
            files.append(name)
            if sink is not None:
                sink.write(frame.rgb)
            st = frame.stats
            per_frame.append({"frame": k, "drawn": st.n_drawn, "culled": st.n_frustum_culled,
                              "small": st.n_small, "near_clipped": st.n_near_clipped, "hits": st.hits,
                              "misses": st.misses, "cache_entries": st.cache_entries,
                              "max_outside_deg": st.max_outside_deg, "ms": st.ms})
            if k in picks and truth is not None:
                cmp = compare_modes(scene, cameras[k], {classic.name: classic, mode.name: mode}, truth)
                cname = f"compare_{k:04d}.png"
                write_image(out / cname, cmp.strip)
                files.append(cname)
                compared.append({"frame": k, "file": cname, "errors": cmp.errors})
    except BaseException:
        if sink is not None:
            sink.abort()
        raise
    if sink is not None:
        sink.close()
        files.append(f"{stem}.webm")
    hits = sum(f["hits"] for f in per_frame)
    misses = sum(f["misses"] for f in per_frame)
    summary = {f"morphkit_{stem}": 1, "mode": mode.name, "frames": len(cameras),
               "instances": len(scene), "hit_rate": hits / max(hits + misses, 1), **(extra or {}),
               "per_frame": per_frame, "compared": compared, "files": files + [f"{stem}.json"]}
    write_json(out / f"{stem}.json", _finite(summary))
    return summary


def _finite(obj: Any) -> Any:
    """JSON has no NaN: None in its place (means of no billboards)."""
    if isinstance(obj, float) and obj != obj:
        return None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_finite(v) for v in obj]
    return obj
