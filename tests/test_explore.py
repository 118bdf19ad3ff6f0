"""pk.explore: the notebook widget, driven from Python as its front-end drives it (trait by
trait). The browser side (a drag turning into a new frame) is issue 32's next step."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

import pomkit as pk

pytest.importorskip("anywidget", reason="the notebooks and test extras install anywidget")


def _scene(mesh=None, size=96):
    return pk.Scene(mesh=mesh or pk.Mesh.plane(2.0), material=pk.Material(pk.textures.bricks(64), depth=0.08),
                    camera=pk.Camera.look_at((0.0, 1.2, 1.4), fov_y=40, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.3, -1.0, -0.2), 3.0, angular_diameter=2.0)], ambient=0.1)


def _png(w) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(w.image)).convert("RGB"))


def test_the_widget_starts_at_the_scenes_camera_and_orbits(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _scene()
    w = pk.explore(s, methods=["POM", "Exact"], size=96)
    # the first frame is the scene's own view
    want = pk.Renderer().render(s, pk.POM(), aovs=("color",)).to_srgb8()
    assert np.array_equal(_png(w), want)
    assert np.isclose(w.distance, np.linalg.norm(np.subtract(s.camera.eye, s.camera.target)))
    for k in ("gpu_ms", "fetches", "uv_p95", "flip", "ms"):
        assert k in w.stats, k
    a = _png(w)
    w.azimuth += 25.0
    assert not np.array_equal(a, _png(w))
    w.dragging = True  # while dragging: half the resolution, no reference
    w.azimuth += 5.0
    assert _png(w).shape == (48, 48, 3) and "flip" not in w.stats
    w.dragging = False
    assert _png(w).shape == (96, 96, 3) and "flip" in w.stats


def test_every_view_and_comparison(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    w = pk.explore(_scene(), methods=["POM", "Exact"], size=64)
    seen = {}
    for v in pk._explore.VIEWS:
        w.view = v
        seen[v] = _png(w)
        assert seen[v].shape == (64, 64, 3)
    assert len({img.tobytes() for img in seen.values()}) == len(seen)  # each view shows something else
    w.view = "color"
    w.compare = "reference"
    ref = _png(w)
    w.compare = "split"
    split = _png(w)
    assert np.array_equal(split[:, 40:], ref[:, 40:])
    # Exact follows the reference shading but for its shadows and AO: closer than POM with 4 steps
    w.compare = "off"
    w.method, w.steps = "POM", 4
    pom4 = w.stats["flip"]
    w.method = "Exact"
    assert w.stats["flip"] < pom4


def test_a_curved_scene_is_measured_against_the_mesh(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    w = pk.explore(_scene(pk.Mesh.torus(segments=32, tube_segments=16), 64), methods=["NCS", "Prism"], size=64)
    assert w.method == "NCS" and np.isfinite(w.stats["uv_p95"])


def test_bad_arguments_say_what_is_wrong():
    with pytest.raises(ValueError, match="methods: 'Nope'"):
        pk.explore(_scene(), methods=["Nope"])
    with pytest.raises(ValueError, match="reference"):
        pk.explore(_scene(), reference="mitsuba")
    with pytest.raises(TypeError, match="scene"):
        pk.explore("a scene")


def test_configured_methods_are_explored_as_configured():
    pytest.importorskip("anywidget")
    tuned = pk.POM(min_steps=12, max_steps=40)
    w = pk.explore(_scene(), methods=[tuned, "Exact"], size=48)
    assert w.methods == [repr(tuned), "Exact"]
    w.method = repr(tuned)
    assert w._method() == tuned
    w.steps = 20  # POM's one rule for its knob (Method.with_steps): min_steps a quarter of max_steps
    assert w._method() == pk.POM(min_steps=5, max_steps=20)
    assert w.image
    with pytest.raises(TypeError, match="methods"):
        pk.explore(_scene(), methods=[3])
