"""Shared fixtures. GL tests are marked ``gl``; run the numpy/OpenCV core alone
with ``pytest -m "not gl"`` (no GL context, pyrender never imported)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# Hypothesis profiles of the property-based tests (tests/test_prop_*.py). "ci" (the default) is
# derandomised (a fixed seed per test: the same cases on every run) with few examples, so the
# generated suite stays well under 2 minutes on 2 cores; "long" tries 10x as many, on demand:
# MORPHKIT_HYPOTHESIS=long pytest tests/test_prop_*.py
_HYPOTHESIS_BASE = dict(derandomize=True, deadline=None, database=None, print_blob=True,
                        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                               HealthCheck.function_scoped_fixture,
                                               HealthCheck.filter_too_much])
settings.register_profile("ci", max_examples=100, **_HYPOTHESIS_BASE)
settings.register_profile("long", max_examples=1000, **_HYPOTHESIS_BASE)
settings.load_profile(os.environ.get("MORPHKIT_HYPOTHESIS", "ci"))


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def renderer():
    from morphkit.render import Renderer

    r = Renderer()
    yield r
    r.close()


@pytest.fixture(autouse=True)
def _cache_in_a_temporary_folder(tmp_path_factory, monkeypatch):
    """What morphkit keeps between runs (a plan's error tables) goes to one folder of the session's
    temporary tree, never to the user's cache."""
    import morphkit.settings

    cache = tmp_path_factory.getbasetemp() / "morphkit-cache"
    monkeypatch.setattr(morphkit.settings, "CACHE_DIR", str(cache))
