"""Shared pieces of the property-based tests (tests/test_prop_*.py).

The property every generated case checks: the entry point returns valid output
(checked by the test) or raises a :class:`~morphkit.errors.MorphkitError`
subclass -- never another exception, a hang (a case over :data:`HANG_S` seconds
fails) or NaN output. :func:`outcome` runs one call and tags it with a
Hypothesis ``event`` (``<function>: valid`` or ``<function>: refused: <ErrorType>``), so
``pytest --hypothesis-show-statistics`` prints the outcomes per entry point.
"""

from __future__ import annotations

import io
import json
import signal
import zipfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from hypothesis import event
from hypothesis import strategies as st

from morphkit.errors import MorphkitError

#: A single generated case taking longer than this is a hang (seconds).
HANG_S = 20


class Hang(Exception):
    """A generated case ran past :data:`HANG_S`."""


def _alarm(signum: int, frame: Any) -> None:
    raise Hang(f"a generated case ran over {HANG_S} s")


def outcome(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> tuple[bool, Any]:
    """Run ``fn(*args, **kwargs)``: ``(True, result)``, or ``(False, error)`` for a MorphkitError.

    Any other exception propagates (the test fails with it: a crash).
    """
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_S)
    try:
        result = fn(*args, **kwargs)
    except MorphkitError as exc:
        event(f"{_name(fn)}: refused: {type(exc).__name__}")
        return False, exc
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    event(f"{_name(fn)}: valid")
    return True, result


@contextmanager
def hang_limit() -> Iterator[None]:
    """The block fails with :class:`Hang` past :data:`HANG_S` seconds (a blocking ``open`` of a FIFO
    no process writes to is interrupted too)."""
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_S)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _name(fn: Callable[..., Any]) -> str:
    return getattr(fn, "__qualname__", None) or type(fn).__name__


# ------------------------------------------------------------------ byte mutations
@st.composite
def damaged(draw: st.DrawFn, valid: bytes) -> bytes:
    """``valid`` truncated, with bits flipped or bytes overwritten, or random bytes instead."""
    how = draw(st.sampled_from(["truncate", "flip", "overwrite", "random", "empty-ish"]))
    if how == "truncate":
        return valid[:draw(st.integers(0, max(0, len(valid) - 1)))]
    if how == "random":
        return draw(st.binary(max_size=512))
    if how == "empty-ish":
        return draw(st.sampled_from([b"", b"\0", b"PK\x03\x04", b"PK\x05\x06" + b"\0" * 18, b"\xef\xbb\xbf"]))
    data = bytearray(valid)
    if how == "flip":
        for pos, bit in draw(st.lists(st.tuples(st.integers(0, len(data) - 1), st.integers(0, 7)),
                                      min_size=1, max_size=8)):
            data[pos] ^= 1 << bit
    else:
        pos = draw(st.integers(0, len(data) - 1))
        chunk = draw(st.binary(min_size=1, max_size=64))
        data[pos:pos + len(chunk)] = chunk
    event(f"damage: {how}")
    return bytes(data)


# ------------------------------------------------------------------ JSON mutations
#: JSON values a mutated field may take (NaN and infinities too: Python's json writes them).
json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70)
    | st.sampled_from([0, -1, 1, 2, 3, 1e308, -1e308, float("nan"), float("inf"), float("-inf"), -0.0, 0.5])
    | st.floats() | st.text(max_size=6),
    lambda c: st.lists(c, max_size=4) | st.dictionaries(st.text(max_size=4), c, max_size=3),
    max_leaves=6)


def json_paths(obj: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key/index path into nested dicts and lists (the root excluded)."""
    out: list[tuple] = []
    items = obj.items() if isinstance(obj, dict) else enumerate(obj) if isinstance(obj, list) else ()
    for k, v in items:
        out.append(prefix + (k,))
        out.extend(json_paths(v, prefix + (k,)))
    return out


@st.composite
def mutated_json(draw: st.DrawFn, obj: Any, keep: tuple[str, ...] = ()) -> Any:
    """A deep copy of ``obj`` with 1-3 fields deleted or replaced by random JSON values
    (top-level keys in ``keep`` are left alone, e.g. checksums that are recomputed)."""
    obj = json.loads(json.dumps(obj))
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in json_paths(obj) if p[0] not in keep]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = obj
        for k in path[:-1]:
            parent = parent[k]
        if draw(st.booleans()) and isinstance(parent, dict):
            del parent[path[-1]]
            event("json: delete")
        else:
            parent[path[-1]] = draw(json_values)
            event("json: replace")
    return obj


# ------------------------------------------------------------------ array mutations
SPECIAL = [np.nan, np.inf, -np.inf, 1e38, -1e38, 0.0, -1.0, 2**31, -(2**31)]


@st.composite
def mutated_array(draw: st.DrawFn, a: np.ndarray) -> np.ndarray:
    """``a`` with a special value written somewhere, another dtype or another shape."""
    how = draw(st.sampled_from(["value", "value", "dtype", "shape", "empty"]))
    event(f"array: {how}")
    if how == "value" and a.size:
        b = a.copy()
        flat = b.reshape(-1)
        v = draw(st.sampled_from(SPECIAL))
        idx = draw(st.lists(st.integers(0, flat.size - 1), min_size=1, max_size=4))
        with np.errstate(invalid="ignore", over="ignore"):
            try:
                flat[idx] = np.asarray(v).astype(b.dtype)
            except (OverflowError, ValueError):
                flat[idx] = 0
        return b
    if how == "dtype":
        dt = draw(st.sampled_from(["uint8", "int64", "float16", "float32", "float64", "bool", "int32"]))
        with np.errstate(invalid="ignore", over="ignore"):
            return a.astype(dt)
    if how == "shape" and a.size:
        return a.reshape(-1)[: draw(st.integers(0, a.size - 1))]
    return np.zeros((0,) * max(a.ndim, 1), a.dtype)


def npz_bytes(arrays: dict[str, np.ndarray], *, compressed: bool = False) -> bytes:
    buf = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buf, **arrays)
    return buf.getvalue()


def read_npz(data: bytes) -> dict[str, np.ndarray]:
    with np.load(io.BytesIO(data), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def meta_array(meta: Any) -> np.ndarray:
    return np.frombuffer(json.dumps(meta).encode(), np.uint8)


def zip_members(data: bytes) -> list[str]:
    with zipfile.ZipFile(io.BytesIO(data)) as z:
        return z.namelist()
