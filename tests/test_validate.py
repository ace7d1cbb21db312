"""Validators of morphkit.validate: shapes (integral, positive, within the size limit), counts, arrays."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit import tol
from morphkit.errors import ValidationError
from morphkit.validate import as_array, as_bool_array, as_int, as_shape


def test_shapes_are_positive_integral_pairs():
    assert as_shape((32, 48), "s") == (32, 48)
    assert as_shape(np.array([32, 48]), "s") == (32, 48)
    assert as_shape((32.0, np.int64(48)), "s") == (32, 48)  # integral values of any numeric type
    assert all(type(v) is int for v in as_shape((np.int32(3), 4.0), "s"))


@pytest.mark.parametrize("shape, match", [
    ((32.5, 32), r"s: expected an \(H, W\) pair of integers, got \(32.5, 32\)"),
    ((32, float("nan")), r"s: expected an \(H, W\) pair of integers"),
    ((True, 32), r"s: expected an \(H, W\) pair of integers"),
    (("32", 32), r"s: expected an \(H, W\) pair of integers"),
    ((32,), r"s: expected an \(H, W\) pair"),
    (None, r"s: expected an \(H, W\) pair"),
    ((0, 32), r"s: expected positive \(H, W\), got \(0, 32\)"),
])
def test_bad_shapes_are_refused(shape, match):
    with pytest.raises(ValidationError, match=match):
        as_shape(shape, "s")


@pytest.mark.parametrize("shape", [(20000, 20000), (100000, 100000), (1, tol.MAX_IMAGE_PIXELS + 1)])
def test_shapes_beyond_the_size_limit_are_refused(shape):
    with pytest.raises(ValidationError, match=rf"s: expected at most {tol.MAX_IMAGE_PIXELS} pixels"):
        as_shape(shape, "s")


def test_the_largest_allowed_shape_passes():
    side = int(np.sqrt(tol.MAX_IMAGE_PIXELS))
    assert as_shape((side, side), "s") == (side, side)
    assert as_shape((1, tol.MAX_IMAGE_PIXELS), "s") == (1, tol.MAX_IMAGE_PIXELS)


def test_counts_are_integers_in_range():
    assert as_int(3, "k", lo=2) == 3 and as_int(np.int64(3), "k", lo=2, hi=3) == 3
    assert as_int(3.0, "k", lo=2) == 3
    for v, match in [(2.5, r"k: expected an integer >= 2, got 2.5"),
                     (True, r"k: expected an integer >= 2, got True"),
                     ("3", r"k: expected an integer >= 2, got '3'"),
                     (1, r"k: expected an integer >= 2, got 1")]:
        with pytest.raises(ValidationError, match=match):
            as_int(v, "k", lo=2)
    with pytest.raises(ValidationError, match=r"k: expected an integer in \[2, 3\], got 4"):
        as_int(4, "k", lo=2, hi=3)


def test_arrays_are_nonempty_numeric_numpy_arrays_returned_as_they_are():
    a = np.arange(6, dtype=np.uint8).reshape(2, 3)
    assert as_array(a, "a") is a and as_array(np.ones(4, bool), "m").dtype == np.bool_
    for v, match in [([1.0, 2.0], r"a: expected a numpy array, got list"),
                     (np.zeros((0, 3)), r"a: expected a non-empty array, got shape \(0, 3\)"),
                     (np.array(1.0), r"a: expected a non-empty array, got shape \(\)"),
                     (np.array(["x"]), r"a: expected a numeric or boolean dtype, got dtype <U1"),
                     (np.array([1.0, np.inf, np.nan]), r"a: expected finite values, got 2 NaN/inf entries")]:
        with pytest.raises(ValidationError, match=match):
            as_array(v, "a")


def test_bool_arrays_are_numpy_bool_only():
    m = np.zeros((2, 2), bool)
    assert as_bool_array(m, "mask") is m
    for v in (m.astype(np.uint8), [[True]]):
        with pytest.raises(ValidationError, match="mask: expected a boolean numpy array, got"):
            as_bool_array(v, "mask")
