"""Mitsuba matched to the reference shading (issue 30): `render_mitsuba(integrator="cast")`, the
default, casts every sample's ray and every light and ambient ray with Mitsuba against the
displaced mesh and shades the hits by docs/conventions.md. These tests hold it to pk.oracle.image
(the float64 oracle: an independent ray caster on the same definition), to the analytic sphere,
and the mesh the GPU rasterises (Tessellated) to it on curved meshes, where pk.oracle.image is this
render. Measured tables: docs/tables/reference_agreement.md.
"""

from __future__ import annotations


import numpy as np
import pytest

import pomkit as pk
from pomkit import reference as R

pytestmark = pytest.mark.reference  # Mitsuba

RENDERER = pk.Renderer()


def _suite_scene(name: str, theta: float, ambient: float, size: int = 96) -> pk.Scene:
    """The agreement suite's planar scenes (tools/reference_agreement.py): 30° with the light
    overhead, 70° with it grazing (19° above the plane); a 2° light."""
    h = pk.textures.real(name, 128) if name in pk.textures.REAL else getattr(pk.textures, name)(128)
    light = (-1.0, -0.35, -0.2) if theta > 45 else (-0.3, -1.0, -0.2)
    return pk.scenes.tilted_plane(h, theta, size, fov=30.0, ambient=ambient,
                                  lights=[pk.DirectionalLight(light, 3.0, angular_diameter=2.0)])


@pytest.mark.parametrize("name", ["bricks", "cobblestones", "terrain", "gravel"])
@pytest.mark.parametrize("theta", [30.0, 70.0])
@pytest.mark.parametrize("ambient", [0.0, 0.15])
def test_matched_mitsuba_meets_the_oracle_image_on_planes(tmp_path, monkeypatch, name, theta, ambient):
    """Mitsuba's hits on the mesh and the oracle's on the bilinear field, shaded alike: interior
    FLIP <= 0.005 (issue 30's bound) at Mitsuba's defaults (8 lattice vertices per texel, each
    quad cut in four about its centre). Measured at 144²: at most 0.0039, on the gravel
    photograph at 70° under the grazing light, where the mesh's chords decide grazing light rays
    (the two-triangle grid left 0.0064 there and needed 16 per texel)."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene(name, theta, ambient)
    ref = pk.oracle.image(s, spp=16)
    mi = R.render_mitsuba(s)
    assert mi.noise_floor == 0.0
    fl = pk.metrics.compare(mi, ref, s)["flip_interior"]
    assert fl <= 0.005, fl


def test_matched_mitsuba_is_deterministic_and_refuses_a_seed(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene("bricks", 30.0, 0.15, size=32)
    a = R.render_mitsuba(s, spp=4, cache=False)
    b = R.render_mitsuba(s, spp=4, cache=False)
    assert np.array_equal(a.color, b.color)
    with pytest.raises(ValueError, match="seed"):
        R.render_mitsuba(s, seed=1)
    with pytest.raises(ValueError, match="square"):
        R.render_mitsuba(s, spp=8)


@pytest.mark.parametrize("mesh", ["torus", "sphere"])
def test_the_mesh_meets_the_exact_reference_on_curved_meshes(tmp_path, monkeypatch, mesh):
    """On a curved mesh pk.oracle.image is the float64 oracle's shell walk. The mesh the GPU
    rasterises (Tessellated(0.5), spp 16) against it without shadows: interior FLIP <= 0.006
    (issue 30's bound), held at 0.003 (against Mitsuba's ray casts on the finer mesh it was
    0.0007-0.0012).
    With shadows the GPU's own estimates on a curved mesh are far (its exact shadows trace a flat
    shell: 0.043-0.054; its shadow map 0.036-0.11): docs/tables/reference_agreement.md."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    m = pk.Mesh.torus(segments=48, tube_segments=24) if mesh == "torus" else pk.Mesh.sphere(segments=48, rings=24)
    s = pk.Scene(mesh=m, material=pk.Material(pk.textures.cobblestones(128, cells=8), depth=0.08, tiling=2.0),
                 camera=pk.Camera.look_at((0.4, 1.6, 2.8), fov_y=40, width=96, height=96),
                 lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0, angular_diameter=2.0)], ambient=0.15)
    ref = pk.oracle.image(s, spp=16, shadows=False)
    f = RENDERER.render(s, pk.Tessellated(0.5, shadows="none"), spp=16)
    c = pk.metrics.compare(f, ref, s)
    assert c["flip_interior"] <= 0.003 and c["uv_p95_interior"] < 0.02, c


def test_matched_mitsuba_traces_a_sphere_lights_disk(tmp_path, monkeypatch):
    """A sphere light's disk seen from each hit (apparent radius from Mitsuba's distance) and
    its irradiance I / r² from Mitsuba's point emitter: on a flat field, against the oracle's."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene("cobblestones", 45.0, 0.0, size=48).replace(
        lights=[pk.SphereLight((0.3, 0.5, 0.2), radius=0.05, intensity=0.8)])
    fl = pk.metrics.compare(R.render_mitsuba(s), pk.oracle.image(s, spp=16), s)["flip_interior"]
    assert fl <= 0.005, fl
