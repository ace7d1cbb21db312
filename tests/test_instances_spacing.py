"""Scatter with a minimum spacing: instances.separate and footprint_radius (no GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.billboard.frames.instances import (
    Instances,
    field_half_size,
    footprint_radius,
    place_random,
    separate,
)
from morphkit.errors import ValidationError
from morphkit.scene import Item


def _gaps(inst: Instances, radius: dict[str, float]) -> np.ndarray:
    """Distance between each pair's positions less the sum of their scaled footprints."""
    r = np.array([radius[nm] for nm in inst.names])[inst.asset] * inst.scale
    d = np.hypot(*(inst.xy[:, None, :] - inst.xy[None, :, :]).transpose(2, 0, 1))
    gap = d - (r[:, None] + r[None, :])
    return gap[np.triu_indices(len(inst), 1)]


def test_separated_footprints_do_not_overlap_and_the_free_ones_stay():
    radius = {"tree": 0.35, "person": 0.15}
    first = place_random(["tree", "person"], 300, np.random.default_rng(0))
    assert (_gaps(first, radius) < 0).sum() > 20  # the uniform scatter puts instances inside others
    out = separate(first, radius, np.random.default_rng(1), half_size=field_half_size(300))
    assert out.crowded == 0 and out.moved > 0
    assert _gaps(out.instances, radius).min() >= 0
    same = np.all(out.instances.xy == first.xy, axis=1)
    assert same.sum() == 300 - out.moved  # only the moved ones changed
    assert np.abs(out.instances.xy).max() <= field_half_size(300)
    for a in ("asset", "yaw_deg", "scale"):
        np.testing.assert_array_equal(getattr(out.instances, a), getattr(first, a))
    again = separate(first, radius, np.random.default_rng(1), half_size=field_half_size(300))
    np.testing.assert_array_equal(again.instances.xy, out.instances.xy)  # the seed fixes it


def test_a_field_too_small_counts_the_crowded_ones():
    """Ten discs of radius 1 cannot lie apart in a 2 x 2 field (one fits): nine stay crowded."""
    inst = Instances.from_records([("ball", 0.0, 0.0)] * 10)
    out = separate(inst, {"ball": 1.0}, np.random.default_rng(0), half_size=1.0)
    assert out.crowded == 9 and out.moved == 0


def test_footprint_radius_of_posed_parts():
    """A unit box centred at (2, 0) (by its pose) reaches hypot(2.5, 0.5) from the axis."""
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    pose = np.eye(4)
    pose[0, 3] = 2.0
    assert footprint_radius([Item(box, pose)]) == pytest.approx(np.hypot(2.5, 0.5))


def test_bad_arguments_are_refused():
    inst = Instances.from_records([("tree", 0.0, 0.0)])
    with pytest.raises(ValidationError, match="one for each asset"):
        separate(inst, {"person": 1.0}, np.random.default_rng(0), half_size=2.0)
    with pytest.raises(ValidationError, match="finite values >= 0"):
        separate(inst, {"tree": -1.0}, np.random.default_rng(0), half_size=2.0)
    with pytest.raises(ValidationError, match="numpy Generator"):
        separate(inst, {"tree": 1.0}, 0, half_size=2.0)  # type: ignore[arg-type]
    with pytest.raises(ValidationError, match="half_size"):
        separate(inst, {"tree": 1.0}, np.random.default_rng(0), half_size=0.0)
    with pytest.raises(ValidationError, match="at least one vertex"):
        footprint_radius([])
