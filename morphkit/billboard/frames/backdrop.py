"""The backdrop of a billboard scene: a ground, a sky and distance fog, drawn in numpy.

Every camera pixel's ray (:meth:`CameraModel.rays`) either meets the ground
plane ``z = 0`` -- a checker of two colours (or one flat colour) -- or the sky, a
vertical gradient from a horizon colour to a zenith colour. Distance fog (like
the paper's Fig. 1) blends a colour in by ``1 - exp(-density * distance)``; the
ground gets it per pixel, billboards per instance (:meth:`Fog.factor` at the
pivot's distance). **One fog model for everything drawn** (:meth:`Fog.blend`):
the blend is made on the output-encoded colour (the frame's values, as the
ground's and the fog's colours are given), for the ground, the meshes, the ring
billboards and the relit ones alike (the relit ones are encoded before they are
fogged and composited, :mod:`.litmodes`). The image is drawn once per camera and reused while the
camera stays (:meth:`Backdrop.draw` keeps the last one).

**Shadows on the ground.** The ground's colours are its look in full sun. A
shadowed frame passes :meth:`Backdrop.draw` a ``ground_factor`` per ground pixel
(:meth:`Backdrop.ground_points` gives them in order): the share of the light the
shading model leaves there (:func:`morphkit.imaging.shading.sun_shadow_factor`, linear
light), applied to the colour as ``c f ^ (1/2.2)`` (the model's output encoding,
:data:`morphkit.imaging.shading.LIT_GAMMA`) before the fog.

Colours are RGB in ``[0, 1]``; images are float32 ``(H, W, 3)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ... import tol
from ...camera import CameraModel
from ...errors import ValidationError, expected_got
from ...imaging.composite import fade_towards
from ...imaging.shading import LIT_GAMMA
from ...memo import Memo
from ...validate import as_finite_array

__all__ = ["Fog", "Ground", "Sky", "Backdrop"]


def _rgb(c: object, name: str) -> tuple[float, float, float]:
    v = as_finite_array(c, name, shape=(3,))
    if v.min() < 0 or v.max() > 1:
        raise ValidationError(expected_got(name, "RGB values in [0, 1]", v.tolist()))
    return (float(v[0]), float(v[1]), float(v[2]))


@dataclass(frozen=True)
class Fog:
    """Exponential distance fog: a point at distance ``d`` keeps ``exp(-density d)`` of its colour.

    Parameters
    ----------
    color : RGB in [0, 1]
    density : float
        Per scene unit (>= 0; 0 is no fog).
        The fog's colour.
    density : float
        Per scene unit (>= 0; 0 is no fog).

    Examples
    --------
    With ``density = ln 2`` each unit of distance halves what is left of a
    point's colour:

    >>> import numpy as np
    >>> from morphkit.billboard.frames.backdrop import Fog
    >>> Fog(density=np.log(2.0)).factor(np.array([0.0, 1.0, 2.0]))
    array([0.  , 0.5 , 0.75])
    """

    color: tuple[float, float, float] = (0.78, 0.84, 0.90)
    density: float = 0.03

    def __post_init__(self) -> None:
        object.__setattr__(self, "color", _rgb(self.color, "fog color"))
        d = float(self.density)
        if not np.isfinite(d) or d < 0:
            raise ValidationError(expected_got("fog density", "a finite number >= 0", self.density))
        object.__setattr__(self, "density", d)

    def factor(self, distance: np.ndarray) -> np.ndarray:
        """Fraction of fog colour, ``1 - exp(-density * distance)``, same shape as ``distance``.

        Parameters
        ----------
        distance : ndarray of float
            Distance from the camera, scene units.

        Returns
        -------
        ndarray of float
            Fog fraction in ``[0, 1)``, shape of ``distance``.
        """
        return -np.expm1(-self.density * np.asarray(distance, dtype=np.float64))

    def blend(self, rgb: np.ndarray, alpha: np.ndarray | float, factor: np.ndarray | float) -> np.ndarray:
        """The fog model (module docstring): premultiplied output-encoded colour blended towards
        :attr:`color` by ``factor`` (:meth:`factor`), its alpha kept; in place.

        Parameters
        ----------
        rgb : (..., 3) float32
            Premultiplied colour in the output encoding; updated in place.
        alpha : float or (..., 1) float
            Its alpha (1: opaque).
        factor : float or (..., 1) float
            Fog fraction, :meth:`factor` of the distance.

        Returns
        -------
        (..., 3) float32
            ``rgb``.
        """
        return fade_towards(rgb, np.asarray(alpha, np.float32), factor, self.color)

    def blend_layer(self, layer: np.ndarray, depth: np.ndarray, camera: CameraModel) -> None:
        """Fog a frame's premultiplied layer in place, each pixel by its distance along its ray
        (camera depth ``Z`` times the ray's length per unit ``Z``): the meshes' layers.

        Parameters
        ----------
        layer : (H, W, 4) float32
            Premultiplied colour and alpha; its colour updated in place.
        depth : (H, W) float
            Camera depth ``Z`` of each pixel, ``+inf`` where nothing is drawn.
        camera : CameraModel
            The frame's camera.
        """
        alpha = layer[:, :, 3:]
        if not alpha.any():
            return
        x, y = camera.pixel_grid()
        ray = np.sqrt(((x - camera.cx) / camera.fx) ** 2 + ((y - camera.cy) / camera.fy) ** 2 + 1)
        d = np.where(np.isfinite(depth), depth, 0.0)
        self.blend(layer[:, :, :3], alpha, self.factor(d * ray).astype(np.float32)[:, :, None])


@dataclass(frozen=True)
class Ground:
    """The ground plane ``z = 0``: a checker of ``cell``-sized squares, or flat (``cell=None``).

    Parameters
    ----------
    color_a, color_b : tuple of 3 float, optional
        Checker RGB colours in ``[0, 1]`` (``color_a`` alone when flat).
    cell : float or None, optional
        Checker cell side, scene units; ``None`` for a flat ground.
    """

    color_a: tuple[float, float, float] = (0.42, 0.55, 0.32)
    color_b: tuple[float, float, float] = (0.36, 0.48, 0.27)
    cell: float | None = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "color_a", _rgb(self.color_a, "ground color_a"))
        object.__setattr__(self, "color_b", _rgb(self.color_b, "ground color_b"))
        if self.cell is not None and not (np.isfinite(self.cell) and self.cell > 0):
            raise ValidationError(expected_got("ground cell", "None or a finite number > 0", self.cell))


@dataclass(frozen=True)
class Sky:
    """A vertical gradient: ``horizon`` at elevation 0 to ``zenith`` straight up.

    Parameters
    ----------
    horizon : tuple of 3 float, optional
        RGB in ``[0, 1]`` at elevation 0.
    zenith : tuple of 3 float, optional
        RGB in ``[0, 1]`` straight up.
    """

    horizon: tuple[float, float, float] = (0.78, 0.84, 0.90)
    zenith: tuple[float, float, float] = (0.35, 0.55, 0.85)

    def __post_init__(self) -> None:
        object.__setattr__(self, "horizon", _rgb(self.horizon, "sky horizon"))
        object.__setattr__(self, "zenith", _rgb(self.zenith, "sky zenith"))


@dataclass
class Backdrop:
    """Ground + sky (+ fog) of a scene; :meth:`Backdrop.draw` renders them for a camera.

    Parameters
    ----------
    ground : Ground
    sky : Sky
    fog : Fog or None
    """

    ground: Ground = field(default_factory=Ground)
    sky: Sky = field(default_factory=Sky)
    fog: Fog | None = None
    # the last camera's layout (image, ground pixels): the modes of one frame draw it once
    _drawn: Memo[tuple[object, ...], _Layout] = field(default_factory=lambda: Memo(1), init=False,
                                                       repr=False, compare=False)

    def draw(self, camera: CameraModel, ground_factor: np.ndarray | None = None) -> np.ndarray:
        """The backdrop seen by ``camera``: float32 ``(H, W, 3)`` RGB in ``[0, 1]`` (read-only;
        the same array while the camera is unchanged and no factor is given).

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        ground_factor : (M,) float, optional
            The light kept at each ground pixel (module docstring, "Shadows on the ground"),
            in the order of :meth:`ground_points`; default 1 (full sun).

        Returns
        -------
        (H, W, 3) float32
            RGB in ``[0, 1]``, read-only.

        Raises
        ------
        ValidationError
            A factor not one per ground pixel.
        """
        lay = self._layout(camera)
        if ground_factor is None:
            return lay.image
        f = np.asarray(ground_factor, dtype=np.float32)
        if f.shape != (len(lay.color),):
            raise ValidationError(expected_got("ground_factor", f"one per ground pixel ({len(lay.color)},)",
                                               f.shape))
        col = lay.color * np.power(np.clip(f, 0.0, 1.0), np.float32(LIT_GAMMA))[:, None]
        if lay.fog is not None and self.fog is not None:
            self.fog.blend(col, 1.0, lay.fog)
        img = lay.image.copy()
        img[lay.hit] = col
        img.setflags(write=False)
        return img

    def ground_points(self, camera: CameraModel) -> tuple[np.ndarray, np.ndarray]:
        """The pixels of ``camera`` that see the ground, and their world points.

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.

        Returns
        -------
        hit : (H, W) bool
            True where the pixel's ray meets the ground plane (in front of the camera); read-only.
        points : (M, 3) float64
            Their points on ``z = 0``, row-major pixel order (``M = hit.sum()``); read-only.
        """
        lay = self._layout(camera)
        return lay.hit, lay.points

    def _layout(self, camera: CameraModel) -> _Layout:
        key = (camera.projection, camera.shape, camera.fx, camera.fy, camera.cx, camera.cy,
               camera.cam2world.tobytes())
        return self._drawn.get(key, lambda: self._draw(camera))

    def _draw(self, camera: CameraModel) -> _Layout:
        o, d = camera.rays()
        dz = d[..., 2]
        down = dz < -tol.BB_GROUND_RAY_DZ
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(down, -o[..., 2] / dz, np.inf)
        hit = down & (t > 0)
        img = np.empty(camera.shape + (3,), np.float32)
        elev = np.clip(dz, 0.0, 1.0)[..., None]
        sky_h, sky_z = np.asarray(self.sky.horizon), np.asarray(self.sky.zenith)
        img[:] = sky_h + np.sqrt(elev) * (sky_z - sky_h)
        p = o[hit] + t[hit, None] * d[hit]
        p[:, 2] = 0.0
        ca, cb = np.asarray(self.ground.color_a), np.asarray(self.ground.color_b)
        if self.ground.cell is None:
            col = np.broadcast_to(ca, p[:, :3].shape).astype(np.float32)
        else:
            parity = (np.floor(p[:, 0] / self.ground.cell) + np.floor(p[:, 1] / self.ground.cell)) % 2
            col = np.where(parity[:, None] > 0.5, cb, ca).astype(np.float32)
        fog = None
        shown = col
        if self.fog is not None:
            fog = self.fog.factor(t[hit])[:, None].astype(np.float32)
            shown = self.fog.blend(col.copy(), 1.0, fog)
        img[hit] = shown
        for a in (img, hit, p, col):
            a.setflags(write=False)
        return _Layout(img, hit, p, col, fog)


@dataclass(frozen=True, eq=False)
class _Layout:
    """One camera's backdrop: the image, its ground pixels, their points, unfogged colours, fog."""

    image: np.ndarray
    hit: np.ndarray
    points: np.ndarray
    color: np.ndarray
    fog: np.ndarray | None
