"""Shared fixtures. GL tests are marked ``gl``; run the numpy/OpenCV core alone
with ``pytest -m "not gl"`` (no GL context, pyrender never imported)."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def renderer():
    from morphkit.render import Renderer

    r = Renderer()
    yield r
    r.close()
