"""Facing: how each billboard quad turns towards the camera, and from which azimuth it is seen.

Three rules, one object each (:class:`Facing`):

* :class:`AxialFacing` -- the quad turns about the world up axis (``+z``) only,
  the paper's billboard for objects symmetric about the vertical (trees,
  people): its normal is the horizontal direction from the billboard to the eye.
  The paper writes the turn from the quad's rest normal ``B_n`` as
  ``theta = pi - acos(dot(L_os, B_n))`` with ``L_os`` the unit direction from the
  eye to the billboard (horizontal); :func:`paper_angle` is that formula, and
  the quad orientation here equals it (tested).
* :class:`ScreenFacing` -- the quad lies parallel to the image plane (the
  paper's OpenGL variant: undo the rotation part of the model-view matrix); its
  right and up axes are the camera's.
* :class:`ViewpointFacing` -- the quad is perpendicular to the direction from the
  pivot to the eye, in elevation too (billboards seen from any height): the quad of
  the camera rule of :mod:`morphkit.views.domecameras` for the instance's viewing azimuth and
  elevation, turned into the world. With ``t`` the unit horizontal direction
  towards the eye (:attr:`ViewDirections.toward_eye`, world) and ``e`` the
  elevation, ``up = -sin(e) t + cos(e) z`` and ``right = (-t_y, t_x, 0)``; the
  direction to the eye ``d = cos(e) t + sin(e) z`` completes the orthonormal
  triple (``right = up x d``). At ``e = 0`` it is :class:`AxialFacing`.

The **viewing azimuth** of an instance (:func:`view_directions`) is the
direction from its pivot to the eye in the asset's object frame (the instance's
yaw removed), degrees counter-clockwise from the asset's front (object ``+x``),
in ``[-180, 180)``: what :meth:`ViewPairing.pair` takes.

Directly above (fallback)
-------------------------
When the eye is (within :data:`morphkit.tol.BB_ABOVE_RATIO`) straight above a
pivot, the horizontal direction is undefined. Then the instance keeps its own
yaw: the azimuth is ``0`` (the asset is seen from its front) and an axial quad
faces the asset's front direction ``(cos yaw, sin yaw, 0)``, i.e. the quad a
viewer in front of it would see. It is the limit of neither side, but it is
stable (no spin) and consistent with the image chosen for azimuth 0. A
:class:`ViewpointFacing` quad straight above lies flat (``d = +z``) with
``up = -t = -(cos yaw, sin yaw, 0)`` and ``right = (-sin yaw, cos yaw, 0)``: the
quad of the dome rule's direction ``(azimuth 0, elevation 90)``, i.e. the top view
with the asset's front at the image's bottom edge, whatever the camera's roll.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ... import tol
from ...camera import CameraModel
from ...validate import as_finite_array

__all__ = ["ViewDirections", "view_directions", "Facing", "AxialFacing", "ScreenFacing", "ViewpointFacing",
           "paper_angle"]


@dataclass(frozen=True)
class ViewDirections:
    """How ``N`` instances are seen from one eye.

    Parameters
    ----------
    azimuth_deg : (N,) float64
        Viewing azimuth in each instance's object frame, degrees in ``[-180, 180)``.
    elevation_deg : (N,) float64
        Elevation of the eye above each pivot's horizontal plane, degrees.
    toward_eye : (N, 2) float64
        Unit horizontal direction (world x, y) from each pivot to the eye; the
        instance's front direction where ``above``.
    above : (N,) bool
        The eye is directly above the pivot (see the module's fallback).
    """

    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    toward_eye: np.ndarray
    above: np.ndarray


def view_directions(eye: np.ndarray, pivots: np.ndarray, yaw_deg: np.ndarray) -> ViewDirections:
    """Viewing azimuths and elevations of ``N`` pivots seen from ``eye``.

    Parameters
    ----------
    eye : (3,) float
        Camera centre, world frame.
    pivots : (N, 3) float
        Billboard pivots, world frame.
    yaw_deg : (N,) float
        Instance yaws, degrees.

    Returns
    -------
    ViewDirections
        The instances' viewing azimuths, elevations and directions towards the eye.

    Examples
    --------
    An eye 10 units along ``-y`` at pivot height: the unturned instance at the
    origin is seen from azimuth -90 (its right side, object ``-y``); the one at
    ``(5, -5)`` turned 90 degrees is seen from 135 degrees in its own frame
    (world heading -135, less its yaw 90, wrapped into ``[-180, 180)``).

    >>> import numpy as np
    >>> from morphkit.billboard.frames.facing import view_directions
    >>> views = view_directions(np.array([0.0, -10.0, 0.5]),
    ...                         np.array([[0.0, 0.0, 0.5], [5.0, -5.0, 0.5]]), np.array([0.0, 90.0]))
    >>> views.azimuth_deg, views.elevation_deg
    (array([-90., 135.]), array([0., 0.]))
    """
    eye = as_finite_array(eye, "eye", shape=(3,))
    d = eye[None, :] - np.asarray(pivots, dtype=np.float64).reshape(-1, 3)
    yaw = np.asarray(yaw_deg, dtype=np.float64).reshape(-1)
    horiz = np.hypot(d[:, 0], d[:, 1])
    full = np.linalg.norm(d, axis=1)
    above = horiz <= tol.BB_ABOVE_RATIO * full
    a = np.radians(yaw)
    front = np.stack([np.cos(a), np.sin(a)], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        toward = np.where(above[:, None], front, d[:, :2] / horiz[:, None])
    az = np.degrees(np.arctan2(d[:, 1], d[:, 0])) - yaw
    az = np.where(above, 0.0, (az + 180.0) % 360.0 - 180.0)
    elev = np.degrees(np.arctan2(d[:, 2], horiz))
    return ViewDirections(az, elev, toward, above)


@runtime_checkable
class Facing(Protocol):
    """A facing rule: the world axes of ``N`` billboard quads for one camera.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def axes(self, camera: CameraModel, views: ViewDirections) -> tuple[np.ndarray, np.ndarray]:
        """``(right, up)``, each ``(N, 3)`` unit vectors (world): the quad's image ``+x``
        direction and its up direction (image ``-y``).

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        views : ViewDirections
            How each of the ``N`` instances is seen.

        Returns
        -------
        right, up : (N, 3) float64
            Unit vectors, world frame.
        """
        ...


@dataclass(frozen=True)
class AxialFacing:
    """Turn each quad about the world up axis to face the eye (the paper's rule)."""

    def axes(self, camera: CameraModel, views: ViewDirections) -> tuple[np.ndarray, np.ndarray]:
        """Right ``= z x n`` (``n`` the horizontal direction to the eye), up ``= +z``; see
        :class:`Facing`.

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        views : ViewDirections
            How each of the ``N`` instances is seen.

        Returns
        -------
        right, up : (N, 3) float64
            Unit vectors, world frame.
        """
        n = views.toward_eye
        right = np.zeros((len(n), 3))
        right[:, 0], right[:, 1] = -n[:, 1], n[:, 0]
        up = np.zeros((len(n), 3))
        up[:, 2] = 1.0
        return right, up


@dataclass(frozen=True)
class ScreenFacing:
    """Quads parallel to the image plane: right and up are the camera's."""

    def axes(self, camera: CameraModel, views: ViewDirections) -> tuple[np.ndarray, np.ndarray]:
        """Right ``=`` camera ``+x``, up ``=`` camera ``-y`` (world); see :class:`Facing`.

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        views : ViewDirections
            How each of the ``N`` instances is seen.

        Returns
        -------
        right, up : (N, 3) float64
            Unit vectors, world frame.
        """
        n = len(views.azimuth_deg)
        R = camera.cam2world[:3, :3]
        return np.repeat(R[None, :, 0], n, axis=0), np.repeat(-R[None, :, 1], n, axis=0)


@dataclass(frozen=True)
class ViewpointFacing:
    """Quads perpendicular to the direction from the pivot to the eye (module docstring): the
    quads of :mod:`morphkit.views.domecameras` for each instance's viewing azimuth and elevation."""

    def axes(self, camera: CameraModel, views: ViewDirections) -> tuple[np.ndarray, np.ndarray]:
        """Right ``= (-t_y, t_x, 0)``, up ``= -sin(e) t + cos(e) z`` (``t`` the horizontal
        direction to the eye, ``e`` the elevation); see :class:`Facing`. Directly above,
        ``t`` is the instance's front (the module's fallback).

        Parameters
        ----------
        camera : CameraModel
            The view, world frame (not used: ``views`` holds the directions).
        views : ViewDirections
            How each of the ``N`` instances is seen.

        Returns
        -------
        right, up : (N, 3) float64
            Unit vectors, world frame.

        Examples
        --------
        Seen from 90 degrees above (straight down) along world ``+x``: the quad lies flat,
        its up pointing back along ``-x``.

        >>> import numpy as np
        >>> from morphkit.billboard.frames.facing import ViewDirections, ViewpointFacing
        >>> views = ViewDirections(np.zeros(1), np.array([90.0]), np.array([[1.0, 0.0]]),
        ...                        np.array([True]))
        >>> right, up = ViewpointFacing().axes(None, views)
        >>> right.round(12) + 0.0, up.round(12) + 0.0
        (array([[0., 1., 0.]]), array([[-1.,  0.,  0.]]))
        """
        t = np.asarray(views.toward_eye, dtype=np.float64).reshape(-1, 2)
        e = np.radians(np.asarray(views.elevation_deg, dtype=np.float64).reshape(-1))
        se, ce = np.sin(e), np.cos(e)
        right = np.zeros((len(t), 3))
        right[:, 0], right[:, 1] = -t[:, 1], t[:, 0]
        up = np.empty((len(t), 3))
        up[:, 0], up[:, 1], up[:, 2] = -se * t[:, 0], -se * t[:, 1], ce
        return right, up


def paper_angle(l_os: np.ndarray, b_n: np.ndarray) -> float:
    """The paper's billboard turn ``theta = pi - acos(dot(L_os, B_n))`` (radians, in ``[0, pi]``).

    Parameters
    ----------
    l_os : (3,) float
        Direction from the eye to the billboard (normalised here).
    b_n : (3,) float
        The quad's rest normal (normalised here).

    Returns
    -------
    float
        The angle between the rest normal and the direction towards the eye:
        how far the quad turns (its sign follows from ``L_os x B_n``).

    References
    ----------
    .. [1] S. Kim, J. Song and O. Gwon, "A Billboarding Technique dependent on View Direction using View
       Morphing", KIISE conference paper (digest: ``docs/papers.md``).

    Examples
    --------
    A quad whose rest normal already points at the eye does not turn; seen
    from the side it turns a quarter turn.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.facing import paper_angle
    >>> paper_angle(np.array([0.0, 1.0, 0.0]), np.array([0.0, -1.0, 0.0]))
    0.0
    >>> round(paper_angle(np.array([1.0, 0.0, 0.0]), np.array([0.0, -1.0, 0.0])) / np.pi, 12)
    0.5
    """
    lv = as_finite_array(l_os, "L_os", shape=(3,))
    bv = as_finite_array(b_n, "B_n", shape=(3,))
    c = float(lv @ bv / (np.linalg.norm(lv) * np.linalg.norm(bv)))
    return float(np.pi - np.arccos(np.clip(c, -1.0, 1.0)))
