"""The ``morphkit shadows`` scene without GL: the exposed light, the camera's view, its checks."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.errors import ValidationError
from morphkit.programs.playback import DEFAULT_VIEW, GROUND_PEAK, exposed
from morphkit.scene import AreaLight, DirectionalLight, PointLight, Receiver


def _peak(light, receiver: Receiver, ambient: float) -> float:
    """The brightest lit ground point's linear value in the receiver's brightest channel, by the
    shader's diffuse term (``albedo / pi * E cos + ambient * albedo``), computed here from the
    light's own geometry: a point light at its foot, a directional one anywhere."""
    a = max(receiver.color)
    if isinstance(light, DirectionalLight):
        d = light.direction / np.linalg.norm(light.direction)
        return a / np.pi * light.intensity * -d[2] + ambient * a
    c = light.center if isinstance(light, AreaLight) else light.position
    return a / np.pi * light.intensity / c[2] ** 2 + ambient * a


@pytest.mark.parametrize("light", [
    PointLight([0.25, -0.2, 2.4]),
    PointLight([3.0, 1.0, 0.7], intensity=500.0),
    DirectionalLight([0.3, 0.2, -1.0]),
    DirectionalLight([1.0, 0.0, -0.2], intensity=1.0),
    AreaLight([0.0, 0.0, 2.0], [0.2, 0, 0], [0, 0.2, 0]),
])
def test_an_exposed_light_puts_the_brightest_ground_at_the_peak(light):
    ground = Receiver()
    for ambient in (0.0, 0.3):
        lit = exposed(light, ground, ambient)
        assert type(lit) is type(light) and _peak(lit, ground, ambient) == pytest.approx(GROUND_PEAK)
        assert lit.intensity != light.intensity or _peak(light, ground, ambient) == pytest.approx(GROUND_PEAK)


def test_a_light_that_cannot_reach_the_ground_is_left_as_it_is():
    ground = Receiver()
    for light in (PointLight([0.0, 0.0, -1.0]), DirectionalLight([0.0, 1.0, 0.5])):
        assert exposed(light, ground, 0.3) is light


def test_the_view_is_checked():
    from morphkit.programs.playback import playback_scene

    with pytest.raises(ValidationError, match=r"view: expected an azimuth and an elevation in \[5, 89\]"):
        playback_scene(None, None, 64, view=(0.0, 90.0))  # type: ignore[arg-type]
    assert 5.0 <= DEFAULT_VIEW[1] <= 89.0
