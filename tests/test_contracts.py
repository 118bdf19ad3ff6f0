"""Contracts have one source, the core: the values Python checks against come from `_core`, and
the Literals that type them (for mypy and editors) must equal them."""

from typing import get_args

import numpy as np
import pytest

import pomkit as pk
from pomkit import _core, _frame, _methods
from conftest import plane_scene


@pytest.mark.parametrize("literal,core", [
    (_methods.ShadowKind, _core.SHADOW_KINDS),
    (_methods.FilteringKind, _core.FILTERING_KINDS),
    (_methods.ConeKind, _core.CONE_KINDS),
    (_methods.RefineKind, _core.REFINE_KINDS),
    (_methods.PatternKind, _core.PATTERN_KINDS),
    (_frame.AovName, _core.AOV_NAMES),
])
def test_literals_equal_the_core(literal, core):
    assert list(get_args(literal)) == list(core)


def test_checks_use_the_core_values():
    assert pk.AOV_NAMES == tuple(_core.AOV_NAMES)
    for bad in ("bogus", "Hard"):
        with pytest.raises(ValueError, match="shadows"):
            pk.POM(shadows=bad)


def test_max_lights_is_the_cores_and_the_shaders(renderer):
    """The light array of the shaders has MAX_LIGHTS entries (a shader def from the core): a
    scene with that many lights renders each of them; one more is refused."""
    n = _core.MAX_LIGHTS
    lights = [pk.DirectionalLight((0.3 * np.cos(k), -1.0, 0.3 * np.sin(k)), 1.0) for k in range(n)]
    sc = plane_scene(pk.textures.constant(16, 1.0), lights=lights, size=16)
    full = renderer.render(sc, pk.Flat(), aovs=("color",)).color
    fewer = renderer.render(sc.replace(lights=lights[:-1]), pk.Flat(), aovs=("color",)).color
    assert full.mean() > fewer.mean()  # the last light in the array is lit
    with pytest.raises(ValueError, match="lights"):
        sc.replace(lights=lights + lights[:1])
