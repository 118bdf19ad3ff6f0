"""The scene's classes declared once (src/scene/schema.rs): Camera and the lights are built from
the core's table, their stub is written from it, they cross the boundary by attribute (a wrong
value names the field), and a field added there (a light's `color`) reaches the GPU, the oracle
and the references with no other edit."""

from __future__ import annotations

import dataclasses
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pomkit as pk
from pomkit import _core
from conftest import plane_scene

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("cls", [pk.Camera, pk.DirectionalLight, pk.SphereLight])
def test_classes_are_the_core_table(cls):
    doc, fields = _core.SCHEMA[cls.__name__]
    assert [f.name for f in dataclasses.fields(cls)] == [f[0] for f in fields]
    assert doc.split()[0] in cls.__doc__
    for name, kind, default, lo, hi, fdoc in fields:
        assert name in cls.__doc__ and fdoc.split()[0] in cls.__doc__


def test_the_stub_is_written_from_the_table():
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "schema_stub.py"), "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_ranges_and_kinds_come_from_the_table():
    with pytest.raises(ValueError, match="shadow_map_size"):
        pk.DirectionalLight((0, -1, 0), shadow_map_size=8)
    with pytest.raises(ValueError, match="angular_diameter"):
        pk.DirectionalLight((0, -1, 0), angular_diameter=180.0)
    with pytest.raises(TypeError, match="fov_y"):
        pk.Camera.look_at((0, 1, 2), fov_y="wide")
    with pytest.raises(ValueError, match="color"):
        pk.SphereLight((0, 1, 0), color=(1, -1, 0))
    c = pk.Camera.look_at((0, 1, 2), width=8, height=4)
    assert pickle.loads(pickle.dumps(c)) == c and dataclasses.replace(c, width=16).width == 16


def test_a_wrong_value_that_crosses_the_boundary_names_its_field():
    """A value that skipped Python's checks (set after construction) is refused by the core's
    reader with the field's name, not a generic cast error: a wrong type is pomkit's
    ArgumentTypeError (a TypeError)."""
    s = plane_scene(pk.textures.bricks(32), size=16)
    cam = s.camera
    object.__setattr__(cam, "fov_y", "wide")
    with pytest.raises(pk.ArgumentTypeError, match="fov_y: expected a number"):
        pk.Renderer().render(s, pk.Flat())
    light = pk.DirectionalLight((0, -1, 0))
    object.__setattr__(light, "irradiance", "bright")
    with pytest.raises(TypeError, match="irradiance: expected three numbers"):
        pk.Renderer().render(plane_scene(pk.textures.bricks(32), size=16, lights=[light]), pk.Flat())


@pytest.mark.parametrize("kind", ["directional", "sphere"])
def test_a_light_colour_multiplies_its_power_on_the_gpu_and_in_the_oracle(kind):
    """The colour field, added to the core's table alone: the GPU frame and the oracle's image of
    a tinted light equal those of the untinted light with its power multiplied, channel by
    channel (to float32 rounding)."""
    tint = (1.0, 0.5, 0.25)
    if kind == "directional":
        tinted = pk.DirectionalLight((-0.3, -1, -0.2), 2.0, color=tint)
        plain = pk.DirectionalLight((-0.3, -1, -0.2), np.multiply(2.0, tint))
    else:
        tinted = pk.SphereLight((0.3, 1.5, 0.5), 0.05, 3.0, color=tint)
        plain = pk.SphereLight((0.3, 1.5, 0.5), 0.05, np.multiply(3.0, tint))
    assert tinted.power == pytest.approx(plain.power)
    h = pk.textures.bricks(32)
    a, b = (plane_scene(h, size=32, lights=[l], ambient=0.05) for l in (tinted, plain))
    r = pk.Renderer()
    fa, fb = r.render(a, pk.POM()), r.render(b, pk.POM())
    np.testing.assert_allclose(fa.color, fb.color, atol=1e-6)
    assert fa.color[..., 2].mean() < 0.5 * fa.color[..., 0].mean()
    ea, eb = pk.oracle.image(a, spp=1, cache=False), pk.oracle.image(b, spp=1, cache=False)
    np.testing.assert_allclose(ea.color, eb.color, atol=1e-6)
