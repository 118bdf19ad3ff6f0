"""Contracts have one source, the core: the values Python checks against come from `_core`, and
the Literals that type them (for mypy and editors) must equal them."""

from typing import get_args

import numpy as np
import pytest

import pomkit as pk
from pomkit import _core, _frame, _methods, _scene
from conftest import plane_scene


@pytest.mark.parametrize("literal,core", [
    (_methods.ShadowKind, _core.SHADOW_KINDS),
    (_methods.FilteringKind, _core.FILTERING_KINDS),
    (_methods.ConeKind, _core.CONE_KINDS),
    (_methods.RefineKind, _core.REFINE_KINDS),
    (_methods.PatternKind, _core.PATTERN_KINDS),
    (_frame.AovName, _core.AOV_NAMES),
    (_scene.NormalsMode, _core.NORMALS_MODES),
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


def test_the_frame_types_every_aov():
    assert set(_frame.Frame.__annotations__) >= set(_core.AOV_NAMES)


def test_a_misspelt_aov_fails_type_checking(tmp_path):
    """mypy reads Frame's AOVs as typed attributes: `frame.uv` checks, `frame.uvv` does not."""
    import subprocess
    import sys
    code = tmp_path / "typo.py"
    code.write_text("import pomkit as pk\n\ndef f(frame: pk.Frame) -> None:\n    frame.uv.sum()\n    frame.uvv.sum()\n")
    out = subprocess.run([sys.executable, "-m", "mypy", "--no-error-summary", "--cache-dir", str(tmp_path / "cache"),
                          "--follow-imports=silent", str(code)], capture_output=True, text=True)
    assert out.returncode == 1, out.stdout + out.stderr
    lines = [x for x in out.stdout.splitlines() if "error" in x]
    assert len(lines) == 1 and '"Frame" has no attribute "uvv"' in lines[0] and ":5:" in lines[0], out.stdout


def test_each_method_declares_its_step_knob_once():
    """choose, the bench and the explorer set a method's step count through `with_steps`, which
    reads the method's own `steps_knob`."""
    for cls in pk.ALL_METHODS:
        m = cls()
        if cls.steps_knob is None:
            assert m.with_steps(12) is m
        else:
            assert getattr(m.with_steps(12), cls.steps_knob) == 12, cls
    assert pk.POM().with_steps(32).min_steps == 8 and pk.ConeStep().with_steps(32).binary_steps == 8
