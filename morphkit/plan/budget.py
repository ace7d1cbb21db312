"""An error budget: how close to the truth a scene's frames must be, and in how many of them.

A budget is a few ``KEY=VALUE`` pairs (``morphkit plan SCENE --budget billboard-psnr=28 ...``):

* ``billboard-psnr`` -- dB, the frame's PSNR against the real meshes' frame, at least;
* ``billboard-iou`` -- the IoU of the billboards' silhouettes against the real meshes', at least;
* ``shadow-iou`` -- the frame's shadow against the ray cast: the IoU of the ground pixels the
  shadows darken, where both frames show ground (the shadows the instances cast;
  :func:`~morphkit.sunlit.shadowing.darkened_iou`), at least;
* ``frames`` -- the fraction of frames that must meet every key above (default
  :data:`DEFAULT_FRAMES`);
* ``time-ms`` -- a frame's median time, at most: with it, the least error within that time.

A frame with nothing to measure for a key (no billboard on screen, no shadow) meets that key. How
a frame's figures are measured is the caller's: a budget only checks them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

from ..errors import UsageError, expected_got

__all__ = ["Budget", "BUDGET_KEYS", "DEFAULT_FRAMES", "ERROR_KEYS", "reached_by"]

#: The fraction of frames that must meet a budget when it does not say.
DEFAULT_FRAMES = 0.95
#: The keys of error a frame is measured by, and whether higher is better (all of them are).
ERROR_KEYS: tuple[str, ...] = ("billboard-psnr", "billboard-iou", "shadow-iou")
#: Every key a budget takes.
BUDGET_KEYS: tuple[str, ...] = (*ERROR_KEYS, "frames", "time-ms")


def _value(key: str, text: str) -> float:
    """``text`` as the value of ``key``, in its range (a usage error naming both otherwise)."""
    ranges = {"billboard-psnr": ("dB > 0", lambda v: v > 0.0),
              "billboard-iou": ("a number in (0, 1]", lambda v: 0.0 < v <= 1.0),
              "shadow-iou": ("a number in (0, 1]", lambda v: 0.0 < v <= 1.0),
              "frames": ("a fraction in (0, 1]", lambda v: 0.0 < v <= 1.0),
              "time-ms": ("milliseconds > 0", lambda v: v > 0.0)}
    what, ok = ranges[key]
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v) or not ok(v):
        raise UsageError(expected_got(f"--budget {key}", what, repr(text)))
    return v


def reached_by(values: Iterable[float | None], fraction: float) -> float | None:
    """The figure ``fraction`` of the values reach (higher is better): the quantile at least that
    fraction of them meets or beats; None values (nothing measured) left out, None when all are.

    Parameters
    ----------
    values : iterable of float or None
        One frame's figure each.
    fraction : float
        In ``(0, 1]``.

    Returns
    -------
    float or None

    Examples
    --------
    >>> from morphkit.plan.budget import reached_by
    >>> reached_by([0.9, 0.5, None, 0.7], 0.6), reached_by([0.9, 0.5, 0.7], 1.0), reached_by([None], 0.5)
    (0.7, 0.5, None)
    """
    vals = sorted((float(v) for v in values if v is not None), reverse=True)
    if not vals:
        return None
    return vals[min(len(vals) - 1, max(0, math.ceil(fraction * len(vals)) - 1))]


@dataclass(frozen=True)
class Budget:
    """An error budget (the module notes); None: the key is not in the budget.

    Parameters
    ----------
    billboard_psnr : float or None
        dB, > 0.
    billboard_iou : float or None
        In ``(0, 1]``.
    shadow_iou : float or None
        In ``(0, 1]``.
    frames : float
        The fraction of frames that must meet the budget, in ``(0, 1]``.
    time_ms : float or None
        A frame's median time at most, > 0.

    Examples
    --------
    >>> from morphkit.plan.budget import Budget
    >>> b = Budget.parse(["billboard-psnr=28", "shadow-iou=0.8"])
    >>> b.to_json()
    {'billboard-psnr': 28.0, 'shadow-iou': 0.8, 'frames': 0.95}
    >>> b.meets({"billboard-psnr": 29.1, "shadow-iou": 0.79})
    False
    """

    billboard_psnr: float | None = None
    billboard_iou: float | None = None
    shadow_iou: float | None = None
    frames: float = DEFAULT_FRAMES
    time_ms: float | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if v is not None:
                object.__setattr__(self, f.name, _value(f.name.replace("_", "-"), str(v)))
        if all(getattr(self, k.replace("-", "_")) is None for k in (*ERROR_KEYS, "time-ms")):
            raise UsageError(expected_got("--budget", f"at least one of {', '.join(ERROR_KEYS)}, time-ms",
                                          "none"))

    @classmethod
    def parse(cls, items: Iterable[str]) -> Budget:
        """A budget from ``KEY=VALUE`` strings (``--budget``, repeated).

        Parameters
        ----------
        items : iterable of str
            Each ``KEY=VALUE``; a key at most once.

        Returns
        -------
        Budget

        Raises
        ------
        UsageError
            A malformed pair, an unknown or repeated key, a value out of its range (NaN, a PSNR
            <= 0, an IoU > 1, ...), or no key of error nor time.
        """
        got: dict[str, float] = {}
        for item in items:
            key, sep, text = str(item).partition("=")
            key = key.strip().lower()
            if not sep:
                raise UsageError(expected_got("--budget", "KEY=VALUE", repr(item)))
            if key not in BUDGET_KEYS:
                raise UsageError(expected_got("--budget key", f"one of {', '.join(BUDGET_KEYS)}", repr(key)))
            if key in got:
                raise UsageError(expected_got(f"--budget {key}", "once", "twice"))
            got[key] = _value(key, text.strip())
        return cls(**{k.replace("-", "_"): v for k, v in got.items()})

    def to_json(self) -> dict[str, float]:
        """The budget as ``plan.json`` holds it: the keys given, and ``frames``.

        Returns
        -------
        dict
        """
        out = {k: getattr(self, k.replace("-", "_")) for k in BUDGET_KEYS}
        return {k: v for k, v in out.items() if v is not None}

    def error_keys(self) -> list[tuple[str, float]]:
        """The error keys the budget holds, each with its value, in :data:`ERROR_KEYS`' order.

        Returns
        -------
        list of (str, float)
        """
        keys = [(k, getattr(self, k.replace("-", "_"))) for k in ERROR_KEYS]
        return [(k, float(v)) for k, v in keys if v is not None]

    def meets(self, errors: Mapping[str, float | None]) -> bool:
        """Whether one frame's errors meet every error key of the budget.

        Parameters
        ----------
        errors : mapping
            The frame's value of each key of :data:`ERROR_KEYS` (None or absent: nothing to
            measure, which meets the key).

        Returns
        -------
        bool
        """
        for key in ERROR_KEYS:
            want = getattr(self, key.replace("-", "_"))
            got = errors.get(key)
            if want is not None and got is not None and not got >= want:
                return False
        return True

    def verdict(self, per_frame: Sequence[Mapping[str, float | None]]) -> dict[str, Any]:
        """How many of the frames meet the budget: ``{"frames", "within", "fraction", "met"}``.

        Parameters
        ----------
        per_frame : sequence of mapping
            Each frame's errors (:meth:`meets`).

        Returns
        -------
        dict
            ``met``: the fraction within is at least :attr:`frames` (no frames: not met).
        """
        n = len(per_frame)
        within = sum(self.meets(e) for e in per_frame)
        fraction = within / n if n else 0.0
        met = bool(n) and fraction >= self.frames
        return {"frames": n, "within": within, "fraction": fraction, "met": met}
