"""A scene's camera: a named path fitted to the field, or keyframes.

Both are :class:`SceneCamera`: given the number of frames, the image shape and the field's half
size they give one camera per frame (world frame, :mod:`morphkit.conventions`). A scene file
writes a camera as one JSON object (:meth:`SceneCamera.to_json`, read back by
:func:`camera_from_json`):

* ``{"path": NAME}`` -- one of morphkit's paths (:data:`morphkit.billboard.frames.paths.PATHS`:
  the paper's pan, an orbit, a fly-through, a fly-over, a top-down pan), fitted to the field;
* ``{"keyframes": [{"eye": [x, y, z], "target": [x, y, z]}, ...], "yfov_deg": 50, "znear": 0.1,
  "zfar": 500}`` -- the eye and the point looked at, linearly between keys spaced evenly over the
  frames (one key: a still camera, as a glTF scene's camera is).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..billboard.frames.paths import PATHS, make_path
from ..camera import CameraModel, look_at, perspective
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array, as_int, as_positive, as_shape

__all__ = ["SceneCamera", "NamedPath", "Keyframes", "camera_from_json"]


@runtime_checkable
class SceneCamera(Protocol):
    """What a scene's camera gives: a camera per frame, and its JSON form.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def cameras(self, frames: int, shape: tuple[int, int], half_size: float) -> list[CameraModel]:
        """The cameras of ``frames`` frames of ``shape (H, W)`` over a field of ``half_size``.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.
        shape : (H, W)
            Image shape in pixels.
        half_size : float
            Half side of the field the instances stand on, scene units (paths are fitted to it).

        Returns
        -------
        list of CameraModel
            Perspective cameras, world frame.
        """
        ...

    def to_json(self) -> dict[str, Any]:
        """The camera as a scene file writes it (:func:`camera_from_json` reads it back).

        Returns
        -------
        dict
            JSON-ready.
        """
        ...


@dataclass(frozen=True)
class NamedPath:
    """One of morphkit's camera paths, fitted to the field
    (:func:`~morphkit.billboard.frames.paths.make_path`).

    Parameters
    ----------
    name : str
        A key of :data:`~morphkit.billboard.frames.paths.PATHS`.

    Raises
    ------
    ValidationError
        An unknown name.

    Examples
    --------
    >>> from morphkit.scenes.camerapaths import NamedPath
    >>> cams = NamedPath("orbit").cameras(3, (48, 64), half_size=5.0)
    >>> len(cams), cams[0].shape
    (3, (48, 64))
    """

    name: str

    def __post_init__(self) -> None:
        if self.name not in PATHS:
            raise ValidationError(expected_got("camera path", f"one of {sorted(PATHS)}", repr(self.name)))

    def cameras(self, frames: int, shape: tuple[int, int], half_size: float) -> list[CameraModel]:
        """See :class:`SceneCamera`.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.
        shape : (H, W)
            Image shape in pixels.
        half_size : float
            Half side of the field, scene units (at least 1 is used).

        Returns
        -------
        list of CameraModel
            Perspective cameras, world frame.
        """
        return make_path(self.name, max(float(half_size), 1.0)).cameras(frames, shape)

    def to_json(self) -> dict[str, Any]:
        """See :class:`SceneCamera`.

        Returns
        -------
        dict
            ``{"path": name}``.
        """
        return {"path": self.name}


@dataclass(frozen=True, eq=False)
class Keyframes:
    """A camera through keys ``(eye, target)`` spaced evenly over the frames, linear between them.

    Parameters
    ----------
    eyes, targets : (K, 3) float
        Eye positions and the points looked at, world frame, ``K >= 1``; an eye may not be its
        target (:func:`morphkit.camera.look_at`: the image's up is world ``+z``).
    yfov_deg : float, optional
        Vertical field of view, degrees in ``(0, 180)``.
    znear, zfar : float, optional
        Depth range, ``0 < znear < zfar``.

    Raises
    ------
    ValidationError
        Shapes, non-finite values, a bad field of view or depth range, a key whose eye is its
        target.

    Examples
    --------
    One key is a still camera: every frame the same.

    >>> from morphkit.scenes.camerapaths import Keyframes
    >>> cam = Keyframes([[0.0, -10.0, 2.0]], [[0.0, 0.0, 1.0]])
    >>> a, b = cam.cameras(2, (48, 64), half_size=5.0)
    >>> bool((a.cam2world == b.cam2world).all())
    True
    """

    eyes: np.ndarray
    targets: np.ndarray
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def __post_init__(self) -> None:
        eyes = np.atleast_2d(as_finite_array(self.eyes, "camera eyes"))
        if eyes.ndim != 2 or eyes.shape[1] != 3 or len(eyes) < 1:
            raise ValidationError(
                expected_got("camera eyes", "(K, 3) positions, K >= 1", f"shape {eyes.shape}")
            )
        targets = as_finite_array(self.targets, "camera targets", shape=eyes.shape)
        fov = float(self.yfov_deg)
        if not 0.0 < fov < 180.0:
            raise ValidationError(expected_got("yfov_deg", "degrees in (0, 180)", self.yfov_deg))
        znear = as_positive(self.znear, "znear")
        zfar = as_positive(self.zfar, "zfar")
        if not zfar > znear:
            raise ValidationError(expected_got("zfar", f"> znear = {znear:g}", zfar))
        for k in range(len(eyes)):
            look_at(eyes[k], targets[k])  # refuses a degenerate key now, not at its frame
        object.__setattr__(self, "eyes", eyes)
        object.__setattr__(self, "targets", targets)
        object.__setattr__(self, "yfov_deg", fov)
        object.__setattr__(self, "znear", znear)
        object.__setattr__(self, "zfar", zfar)

    def camera_at(self, t: float, shape: tuple[int, int]) -> CameraModel:
        """The camera at ``t`` in ``[0, 1]`` (key ``k`` of ``K`` at ``t = k / (K - 1)``).

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W)
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.

        Raises
        ------
        ValidationError
            ``t`` outside ``[0, 1]``; between two keys, an eye that meets its target.
        """
        tt = float(t)
        if not 0.0 <= tt <= 1.0:
            raise ValidationError(expected_got("t", "a number in [0, 1]", t))
        k = len(self.eyes) - 1
        u = tt * k
        i = min(int(np.floor(u)), max(k - 1, 0))
        f = u - i if k else 0.0
        j = min(i + 1, k)
        eye = (1.0 - f) * self.eyes[i] + f * self.eyes[j]
        target = (1.0 - f) * self.targets[i] + f * self.targets[j]
        return perspective(
            np.radians(self.yfov_deg),
            as_shape(shape, "shape"),
            look_at(eye, target),
            znear=self.znear,
            zfar=self.zfar,
        )

    def cameras(self, frames: int, shape: tuple[int, int], half_size: float) -> list[CameraModel]:
        """See :class:`SceneCamera` (``half_size`` is not used: keys are where they are).

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.
        shape : (H, W)
            Image shape in pixels.
        half_size : float
            Not used.

        Returns
        -------
        list of CameraModel
            Perspective cameras, world frame.
        """
        n = as_int(frames, "frames", lo=1)
        ts = np.linspace(0.0, 1.0, n) if n > 1 else np.zeros(1)
        return [self.camera_at(float(t), shape) for t in ts]

    def to_json(self) -> dict[str, Any]:
        """See :class:`SceneCamera`.

        Returns
        -------
        dict
            ``{"keyframes": [{"eye": ..., "target": ...}, ...], "yfov_deg": ..., "znear": ..., "zfar": ...}``.
        """
        keys = [
            {"eye": [float(v) for v in e], "target": [float(v) for v in t]}
            for e, t in zip(self.eyes, self.targets, strict=True)
        ]
        return {"keyframes": keys, "yfov_deg": self.yfov_deg, "znear": self.znear, "zfar": self.zfar}


def camera_from_json(obj: Mapping[str, Any]) -> NamedPath | Keyframes:
    """The camera a scene file's ``"camera"`` object describes (the module notes).

    Parameters
    ----------
    obj : mapping
        ``{"path": NAME}`` or ``{"keyframes": [...], ...}`` (checked by the scene schema first).

    Returns
    -------
    NamedPath or Keyframes

    Raises
    ------
    ValidationError
        Neither form, or bad values.
    """
    if "path" in obj:
        return NamedPath(str(obj["path"]))
    if "keyframes" in obj:
        keys: Sequence[Mapping[str, Any]] = obj["keyframes"]
        return Keyframes(
            np.array([k["eye"] for k in keys], np.float64).reshape(-1, 3),
            np.array([k["target"] for k in keys], np.float64).reshape(-1, 3),
            yfov_deg=obj.get("yfov_deg", 50.0),
            znear=obj.get("znear", 0.1),
            zfar=obj.get("zfar", 500.0),
        )
    raise ValidationError(expected_got("camera", '{"path": NAME} or {"keyframes": [...]}', sorted(obj)))
