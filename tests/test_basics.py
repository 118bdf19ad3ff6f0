"""The package, meshes, frames, adapters and the shared device."""

import os

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene


def test_version_and_adapters():
    assert isinstance(pk.__version__, str) and pk.__version__
    a = pk.adapters()
    assert a and {"name", "backend", "device_type"} <= set(a[0])


def test_one_device_per_process():
    r1, r2 = pk.Renderer(), pk.Renderer()
    assert r1.info == r2.info


@pytest.mark.parametrize("mesh", ["plane", "sphere", "torus", "cylinder", "cube"])
@pytest.mark.parametrize("method", [pk.Flat(), pk.Bump(), pk.POM(), pk.POM(shadows="hard")])
def test_every_mesh_renders_finite_aovs(renderer, mesh, method):
    m = getattr(pk.Mesh, mesh)()
    scene = pk.Scene(
        mesh=m, material=pk.Material(pk.textures.cobblestones(64, cells=4), depth=0.05),
        camera=pk.Camera.look_at((1.8, 1.6, 2.6), width=64, height=64),
        lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0, 1.0)], ambient=0.1,
    )
    f = renderer.render(scene, method)
    assert 0.05 < f.mask.mean() < 0.95
    for a in (f.color[f.mask], f.uv[f.mask], f.depth[f.mask], f.lod[f.mask]):
        assert np.all(np.isfinite(a))
    assert np.all(np.isnan(f.uv[~f.mask])) and np.all(np.isnan(f.depth[~f.mask]))
    assert f.color.dtype == np.float32 and f.steps.dtype == np.uint32 and f.mask.dtype == bool
    assert f.time_ms is not None and f.time_ms > 0


def test_tangent_frames_are_orthonormal_with_handedness():
    for m in (pk.Mesh.sphere(), pk.Mesh.torus(), pk.Mesh.cylinder(), pk.Mesh.cube(), pk.Mesh.plane()):
        t = m.tangents
        assert np.allclose(np.linalg.norm(t[:, :3], axis=1), 1, atol=1e-5)
        assert set(np.unique(t[:, 3])) <= {-1.0, 1.0}
        n = m.normals / np.linalg.norm(m.normals, axis=1, keepdims=True)
        assert np.abs((t[:, :3] * n).sum(1)).max() < 1e-4
        assert np.all(m.uv_scale > 0)


def test_frame_srgb_and_save(renderer, tmp_path):
    f = renderer.render(plane_scene(pk.textures.bricks(64), size=32, lights=[pk.DirectionalLight((0, -1, 0), 1.0)]), pk.Bump())
    s = f.to_srgb8()
    assert s.dtype == np.uint8 and s.shape == (32, 32, 3)
    p = f.save(tmp_path / "f.png")
    assert p.stat().st_size > 100
    q = f.save(tmp_path / "f.npz")
    with np.load(q) as z:
        assert set(z.files) >= {"color", "uv", "depth", "mask", "steps", "lod"}


def test_lambert_irradiance_units(renderer):
    # Flat shading of a grey plane lit head-on: L = albedo/pi * E * cos + albedo * ambient
    E, amb = 2.0, 0.25
    scene = plane_scene(pk.textures.constant(8, 1.0), size=16, theta_deg=20,
                        lights=[pk.DirectionalLight((0, -1, 0), E)], ambient=amb)
    f = renderer.render(scene, pk.Flat())
    expect = 0.5 / np.pi * E + 0.5 * amb
    assert np.allclose(f.color[f.mask], expect, rtol=1e-3)


def test_sphere_light_inverse_square(renderer):
    I = 4.0
    scene = plane_scene(pk.textures.constant(8, 1.0), size=16, theta_deg=20,
                        lights=[pk.SphereLight((0, 2.0, 0), 0.01, I)])
    f = renderer.render(scene, pk.Flat())
    # at the plane point p: E = I / r^2 * cos = I * 2 / r^3
    cam = scene.camera
    d = cam.rays()
    eye = np.asarray(cam.eye)
    p = eye + d * (-eye[1] / d[..., 1])[..., None]
    r = np.linalg.norm(p - [0, 2.0, 0], axis=-1)
    expect = 0.5 / np.pi * I * 2.0 / r ** 3
    m = f.mask
    assert np.allclose(f.color[m][:, 0], expect[m], rtol=2e-3)


def test_uv_orientation_plane(renderer):
    # u grows with +x, v with +z: camera on +z looking down, row 0 (top of the image) is the far edge
    scene = plane_scene(pk.textures.bricks(32), theta_deg=30, size=32)
    f = renderer.render(scene, pk.Flat())
    col = f.uv[:, 16, 1]
    ok = np.isfinite(col)
    assert np.all(np.diff(col[ok]) > 0)  # v grows downward in the image (toward the camera)
    row = f.uv[24, :, 0]
    ok = np.isfinite(row)
    assert np.all(np.diff(row[ok]) > 0)


def test_textures_are_deterministic_and_in_range():
    for name, fn in pk.textures.ALL.items():
        a, b = fn(64), fn(64)
        assert a.shape == (64, 64) and a.dtype == np.float32, name
        assert np.array_equal(a, b), name
        assert 0.0 <= a.min() and a.max() <= 1.0 and a.max() - a.min() > 0.2, name


def test_info_names_the_adapter_features_and_fallbacks():
    """`python -m pomkit info` on this install: adapter, backend, driver, every feature with its
    fallback, limits and versions; on GL the float32 filtering fallback is reported."""
    import subprocess
    import sys
    for backend in ("vulkan", "gl"):
        env = dict(os.environ, POMKIT_BACKEND=backend)
        out = subprocess.run([sys.executable, "-m", "pomkit", "info"], env=env, capture_output=True, text=True, check=True).stdout
        assert f"({backend}," in out and "driver" in out and "wgpu 30" in out, out
        assert "float32 filtering" in out and "max_texture_dimension_2d" in out, out
        if backend == "gl":
            assert "NO  float32 filtering  -> fallback" in out, out
    d = pk.info()
    assert d["pomkit"] == pk.__version__ and d["features"] and d["adapters"]
