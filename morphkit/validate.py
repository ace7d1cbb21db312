"""Validators: convert and return their input, or raise a morphkit error that
names what was expected and what was got. See :mod:`morphkit.conventions`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from . import tol
from .errors import ValidationError, expected_got

__all__ = [
    "as_points",
    "as_image",
    "as_finite_array",
    "as_array",
    "as_bool_array",
    "as_shape",
    "as_int",
    "as_flag",
    "as_pose",
    "as_positive",
    "as_unit_interval",
]


def _describe(a: Any) -> str:
    if isinstance(a, np.ndarray):
        return f"array of shape {a.shape} and dtype {a.dtype}"
    return f"{type(a).__name__} {a!r}"[:120]


def as_finite_array(
    a: Any, name: str, *, shape: Sequence[int | None] | None = None, dtype: Any = np.float64
) -> np.ndarray:
    """Return ``a`` as a finite array of ``dtype``; ``None`` in ``shape`` matches any size.

    Parameters
    ----------
    a : array_like
        The value to check.
    name : str
        Its name in the error message.
    shape : sequence of int or None, optional
        Required shape; None entries match any size (None: any shape).
    dtype : dtype
        Dtype to convert to.

    Returns
    -------
    numpy.ndarray
        ``a`` as an array of ``dtype`` (no copy when it already is one).

    Raises
    ------
    ValidationError
        Not numeric, wrong shape, or NaN/inf entries.
    """
    try:
        arr = np.asarray(a, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got(name, "a numeric array", _describe(a))) from exc
    if shape is not None:
        ok = arr.ndim == len(shape) and all(
            s is None or s == n for s, n in zip(shape, arr.shape, strict=False)
        )
        if not ok:
            want = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ")"
            raise ValidationError(expected_got(name, f"shape {want}", f"shape {arr.shape}"))
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise ValidationError(expected_got(name, "finite values", f"{bad} NaN/inf entries"))
    return arr


def as_array(a: Any, name: str) -> np.ndarray:
    """Return ``a`` itself if it is a non-empty numpy array of a boolean or numeric dtype, finite.

    Any number of dimensions (>= 1); nothing is converted or copied, so a list
    is refused rather than read (compare :func:`as_finite_array`, which converts).

    Parameters
    ----------
    a : numpy.ndarray
        The array.
    name : str
        Its name in the error message.

    Returns
    -------
    numpy.ndarray
        ``a``.

    Raises
    ------
    ValidationError
        Not a numpy array, empty (or 0-d), not boolean/integer/float, or NaN/inf entries.
    """
    if not isinstance(a, np.ndarray):
        raise ValidationError(expected_got(name, "a numpy array", _describe(a)))
    if a.size == 0 or a.ndim == 0:
        raise ValidationError(expected_got(name, "a non-empty array", f"shape {a.shape}"))
    if a.dtype.kind not in "buif":
        raise ValidationError(expected_got(name, "a numeric or boolean dtype", f"dtype {a.dtype}"))
    if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
        bad = int(np.count_nonzero(~np.isfinite(a)))
        raise ValidationError(expected_got(name, "finite values", f"{bad} NaN/inf entries"))
    return a


def as_bool_array(a: Any, name: str) -> np.ndarray:
    """Return ``a`` itself if it is a numpy array of dtype bool (a mask), of any shape.

    Parameters
    ----------
    a : numpy.ndarray
        The mask.
    name : str
        Its name in the error message.

    Returns
    -------
    numpy.ndarray
        ``a``.
    """
    if not isinstance(a, np.ndarray) or a.dtype != np.bool_:
        raise ValidationError(expected_got(name, "a boolean numpy array", _describe(a)))
    return a


def as_points(a: Any, name: str, *, dim: int = 2, min_count: int = 0) -> np.ndarray:
    """Return ``a`` as a finite float64 ``(N, dim)`` array with ``N >= min_count``.

    Parameters
    ----------
    a : array_like
        The points.
    name : str
        Their name in the error message.
    dim : int
        Coordinates per point.
    min_count : int
        Fewest points accepted.

    Returns
    -------
    (N, dim) float64
        The points.
    """
    arr = as_finite_array(a, name, shape=(None, dim))
    if arr.shape[0] < min_count:
        raise ValidationError(
            expected_got(name, f"at least {min_count} points", f"{arr.shape[0]}")
        )
    return arr


def as_image(
    img: Any, name: str, *, channels: Sequence[int] | None = None, allow_nonfinite: bool = False
) -> np.ndarray:
    """Return ``img`` as a non-empty ``(H, W)`` or ``(H, W, C)`` numeric array.

    ``channels`` restricts ``C`` (use 1 for 2-D images). Float images must be
    finite unless ``allow_nonfinite`` (depth maps hold ``+inf`` background).

    Parameters
    ----------
    img : numpy.ndarray
        The image.
    name : str
        Its name in the error message.
    channels : sequence of int, optional
        Accepted channel counts (None: any).
    allow_nonfinite : bool
        Accept NaN/inf in float images.

    Returns
    -------
    (H, W) or (H, W, C) numpy.ndarray
        ``img`` itself (not copied or converted).
    """
    if not isinstance(img, np.ndarray):
        raise ValidationError(expected_got(name, "a numpy array", _describe(img)))
    if img.ndim not in (2, 3) or img.size == 0 or min(img.shape[:2]) < 1:
        raise ValidationError(
            expected_got(name, "a non-empty (H, W) or (H, W, C) image", f"shape {img.shape}")
        )
    if img.dtype.kind not in "uif" and img.dtype != np.bool_:
        raise ValidationError(expected_got(name, "a numeric dtype", f"dtype {img.dtype}"))
    c = 1 if img.ndim == 2 else img.shape[2]
    if channels is not None and c not in channels:
        raise ValidationError(expected_got(name, f"{list(channels)} channels", f"{c}"))
    if img.dtype.kind == "f" and not allow_nonfinite and not np.all(np.isfinite(img)):
        raise ValidationError(expected_got(name, "finite pixel values", "NaN/inf pixels"))
    return img


def as_shape(shape: Any, name: str) -> tuple[int, int]:
    """Return ``shape`` as a positive ``(H, W)`` tuple of ints.

    Each value must be an integer (``int``, a numpy integer, or an integral
    float such as ``32.0``); ``32.5`` is refused, not truncated. ``H * W`` may
    be at most :data:`morphkit.tol.MAX_IMAGE_PIXELS`, checked here before any
    buffer of that shape is allocated.

    Parameters
    ----------
    shape : Any
        The value to check, a pair ``(H, W)``.
    name : str
        Its name in the error message.

    Returns
    -------
    tuple of int
        ``(H, W)``.

    Raises
    ------
    ValidationError
        Not a pair of integers, not positive, or more pixels than the limit.
    """
    want = "an (H, W) pair of integers"
    try:
        vals = tuple(shape)
    except TypeError as exc:
        raise ValidationError(expected_got(name, want, _describe(shape))) from exc
    if len(vals) != 2:
        raise ValidationError(expected_got(name, want, repr(shape)[:120]))
    out = []
    for v in vals:
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.integer | np.floating):
            raise ValidationError(expected_got(name, want, repr(shape)[:120]))
        if not (np.isfinite(v) and float(v) == int(v)):
            raise ValidationError(expected_got(name, want, f"({vals[0]}, {vals[1]})"))
        out.append(int(v))
    h, w = out
    if h < 1 or w < 1:
        raise ValidationError(expected_got(name, "positive (H, W)", f"({h}, {w})"))
    if h * w > tol.MAX_IMAGE_PIXELS:
        raise ValidationError(expected_got(
            name, f"at most {tol.MAX_IMAGE_PIXELS} pixels (morphkit.tol.MAX_IMAGE_PIXELS)",
            f"({h}, {w}) = {h * w} pixels"))
    return h, w


def as_int(v: Any, name: str, *, lo: int | None = None, hi: int | None = None) -> int:
    """Return ``v`` as an int in ``[lo, hi]`` (a bound that is None is not checked).

    ``v`` must be an integer (``int``, a numpy integer, or an integral float
    such as ``3.0``); ``2.5`` is refused, not truncated, and so are ``bool``
    and strings.

    Parameters
    ----------
    v : Any
        The value to check.
    name : str
        Its name in the error message.
    lo, hi : int or None
        Inclusive bounds (None: unbounded on that side).

    Returns
    -------
    int
        ``v`` as an int.
    """
    if lo is not None and hi is not None:
        want = f"an integer in [{lo}, {hi}]"
    elif lo is not None:
        want = f"an integer >= {lo}"
    else:
        want = "an integer" if hi is None else f"an integer <= {hi}"
    ok = not isinstance(v, bool | np.bool_) and isinstance(v, int | float | np.integer | np.floating)
    integral = isinstance(v, int | np.integer)  # any size (np.isfinite overflows on a huge int)
    if not ok or not (integral or (np.isfinite(v) and float(v) == int(v))):
        raise ValidationError(expected_got(name, want, repr(v)[:120]))
    n = int(v)
    if (lo is not None and n < lo) or (hi is not None and n > hi):
        raise ValidationError(expected_got(name, want, n))
    return n


def as_flag(v: Any, name: str) -> bool:
    """Return ``v`` as a bool; only ``bool`` and ``numpy.bool_`` are flags.

    ``0``/``1``, strings such as ``"yes"`` and ``None`` are refused rather than
    read by truthiness, so a misplaced positional argument is caught.

    Parameters
    ----------
    v : Any
        The value to check.
    name : str
        Its name in the error message.

    Returns
    -------
    bool
        ``v`` as a Python bool.

    Examples
    --------
    >>> as_flag(True, "interpolate")
    True
    >>> as_flag(1, "interpolate")
    Traceback (most recent call last):
    ...
    morphkit.errors.ValidationError: interpolate: expected a bool (True or False), got 1
    """
    if not isinstance(v, bool | np.bool_):
        raise ValidationError(expected_got(name, "a bool (True or False)", repr(v)[:120]))
    return bool(v)


def as_pose(T: Any, name: str) -> np.ndarray:
    """Return ``T`` as a finite rigid 4x4 float64 transform (rotation + translation).

    Parameters
    ----------
    T : array_like
        The transform, ``(4, 4)``.
    name : str
        Its name in the error message (a transform name with its frames, e.g.
        ``cam2world``).

    Returns
    -------
    (4, 4) float64
        ``T``, checked rigid with a proper rotation (tolerance ``morphkit.tol.POSE_ORTHO``).
    """
    arr = as_finite_array(T, name, shape=(4, 4))
    R = arr[:3, :3]
    if not np.allclose(arr[3], [0, 0, 0, 1], atol=tol.POSE_ORTHO) or not np.allclose(
        R.T @ R, np.eye(3), atol=tol.POSE_ORTHO
    ):
        raise ValidationError(
            expected_got(name, "a rigid 4x4 transform (orthonormal rotation, last row 0 0 0 1)",
                         "a non-rigid matrix")
        )
    if np.linalg.det(R) < 0:
        raise ValidationError(expected_got(name, "a proper rotation (det +1)", "a reflection"))
    return arr


def as_positive(v: Any, name: str) -> float:
    """Return ``v`` as a finite float > 0.

    Parameters
    ----------
    v : Any
        The value to check.
    name : str
        Its name in the error message.

    Returns
    -------
    float
        ``v`` as a float.
    """
    try:
        f = float(v)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got(name, "a positive number", repr(v))) from exc
    if not np.isfinite(f) or f <= 0:
        raise ValidationError(expected_got(name, "a finite number > 0", repr(v)))
    return f


def as_direction(v: Any, name: str) -> np.ndarray:
    """Return ``v``, a non-zero finite 3-vector, scaled to unit length.

    Parameters
    ----------
    v : Any
        The direction (any length > :data:`~morphkit.tol.MIN_EXTENT`).
    name : str
        Its name in the error message.

    Returns
    -------
    (3,) float64
        The unit vector.
    """
    d = as_finite_array(v, name, shape=(3,))
    n = float(np.linalg.norm(d))
    if not n > tol.MIN_EXTENT:
        raise ValidationError(expected_got(name, "a non-zero direction (3-vector)", d.tolist()))
    return d / n


def as_unit_interval(v: Any, name: str) -> float:
    """Return ``v`` as a float in ``[0, 1]``.

    Parameters
    ----------
    v : Any
        The value to check.
    name : str
        Its name in the error message.

    Returns
    -------
    float
        ``v`` as a float.
    """
    try:
        f = float(v)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got(name, "a number in [0, 1]", repr(v))) from exc
    if not (0.0 <= f <= 1.0):
        raise ValidationError(expected_got(name, "a number in [0, 1]", repr(v)))
    return f
