"""Bad input raises ValueError/TypeError naming the argument; the process survives."""

import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene


def good_height():
    return pk.textures.bricks(32)


@pytest.mark.parametrize(
    "height, exc, word",
    [
        (np.full((8, 8), np.nan, np.float32), ValueError, "height"),
        (np.array([[0.1, np.inf]], np.float32), ValueError, "height"),
        (np.zeros((4, 4, 4), np.float32), ValueError, "height"),
        (np.zeros(16, np.float32), ValueError, "height"),
        (np.zeros((4, 4), np.int32), TypeError, "height"),
        (np.zeros((4, 4), bool), TypeError, "height"),
        (np.zeros((0, 4), np.float32), ValueError, "height"),
        (np.full((4, 4), 2.0, np.float32), ValueError, "height"),
    ],
)
def test_bad_heights(height, exc, word):
    with pytest.raises(exc, match=word):
        pk.Material(height)


def test_height_dtypes_normalised():
    assert pk.Material(np.full((2, 2), 255, np.uint8)).height.max() == 1.0
    assert abs(pk.Material(np.full((2, 2), 32768, np.uint16)).height.max() - 32768 / 65535) < 1e-7
    assert pk.Material(np.full((2, 2), 0.25)).height.dtype == np.float32


def test_non_contiguous_arrays_accepted(renderer):
    h = pk.textures.bricks(64)[:, ::2].T  # strided and transposed
    assert not h.flags.c_contiguous
    f = renderer.render(plane_scene(h, size=32), pk.POM())
    assert f.mask.any()


def test_map_larger_than_device_limit(renderer):
    lim = renderer.info["max_texture_dimension_2d"]
    scene = plane_scene(np.zeros((1, lim + 1), np.float32), size=16)
    with pytest.raises(ValueError, match="max_texture_dimension_2d") as e:
        renderer.render(scene, pk.Flat())
    assert str(lim) in str(e.value)


def test_frame_larger_than_device_limit(renderer):
    lim = renderer.info["max_texture_dimension_2d"]
    scene = plane_scene(good_height(), size=16).replace(
        camera=pk.Camera.look_at((0, 1, 1), width=lim + 1, height=4))
    with pytest.raises(ValueError, match="width.*max_texture_dimension_2d"):
        renderer.render(scene, pk.Flat())


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(eye=(1, 1, 1), target=(1, 1, 1)), "eye"),
        (dict(eye=(0, 2, 0), target=(0, 0, 0), up=(0, 1, 0)), "up"),
        (dict(eye=(0, 0, 2), up=(0, 0, 0)), "up"),
        (dict(eye=(0, 1, 2), fov_y=0.0), "fov_y"),
        (dict(eye=(0, 1, 2), fov_y=180.0), "fov_y"),
        (dict(eye=(0, 1, 2), fov_y=-5.0), "fov_y"),
        (dict(eye=(0, 1, 2), width=0), "width"),
        (dict(eye=(0, 1, 2), height=-3), "height"),
        (dict(eye=(0, np.nan, 2)), "eye"),
    ],
)
def test_bad_cameras(kwargs, word):
    with pytest.raises(ValueError, match=word):
        pk.Camera.look_at(**kwargs)


def test_bad_camera_types():
    with pytest.raises(TypeError, match="width"):
        pk.Camera.look_at((0, 1, 2), width=12.5)
    with pytest.raises(TypeError, match="eye"):
        pk.Camera.look_at("abc")


@pytest.mark.parametrize("depth, exc", [(-0.1, ValueError), (float("nan"), ValueError), ("deep", TypeError)])
def test_bad_depth(depth, exc):
    with pytest.raises(exc, match="depth"):
        pk.Material(good_height(), depth=depth)


def test_bad_tiling():
    with pytest.raises(ValueError, match="tiling"):
        pk.Material(good_height(), tiling=0)


def _tri():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1]], np.float32)
    n = np.array([[0, 1, 0]] * 3, np.float32)
    uv = np.array([[0, 0], [1, 0], [0, 1]], np.float32)
    return p, n, uv


def test_index_out_of_range():
    p, n, uv = _tri()
    with pytest.raises(ValueError, match="indices"):
        pk.Mesh.from_arrays(p, n, uv, np.array([0, 1, 3]))
    with pytest.raises(ValueError, match="indices"):
        pk.Mesh.from_arrays(p, n, uv, np.array([0, 1, -1]))
    with pytest.raises(TypeError, match="indices"):
        pk.Mesh.from_arrays(p, n, uv, np.array([0.0, 1.0, 2.0]))


def test_mesh_without_usable_uvs():
    p, n, _ = _tri()
    with pytest.raises(ValueError, match="uvs"):
        pk.Mesh.from_arrays(p, n, np.full((3, 2), 0.5, np.float32), np.array([0, 1, 2]))


def test_mesh_shape_errors():
    p, n, uv = _tri()
    with pytest.raises(ValueError, match="normals"):
        pk.Mesh.from_arrays(p, n[:2], uv, np.array([0, 1, 2]))
    with pytest.raises(ValueError, match="positions"):
        pk.Mesh.from_arrays(p[:, :2], n, uv, np.array([0, 1, 2]))
    with pytest.raises(ValueError, match="positions"):
        pk.Mesh.from_arrays(np.full((3, 3), np.nan), n, uv, np.array([0, 1, 2]))


def test_single_degenerate_uv_triangle_warns(renderer):
    p, n, uv = _tri()
    p = np.concatenate([p, p + [2, 0, 0]])
    n = np.concatenate([n, n])
    uv = np.concatenate([uv, np.full((3, 2), 0.3, np.float32)])
    with pytest.warns(RuntimeWarning, match="degenerate"):
        m = pk.Mesh.from_arrays(p, n, uv, np.array([0, 1, 2, 3, 4, 5]))
    assert np.all(np.isfinite(m.tangents))
    scene = pk.Scene(mesh=m, material=pk.Material(good_height()), camera=pk.Camera.look_at((1.5, 2, 2), target=(1.5, 0, 0.3), width=32, height=32))
    f = renderer.render(scene, pk.POM())
    assert np.all(np.isfinite(f.color))


@pytest.mark.parametrize(
    "make, word",
    [
        (lambda: pk.POM(min_steps=0), "min_steps"),
        (lambda: pk.POM(min_steps=60, max_steps=50), "min_steps"),
        (lambda: pk.POM(max_steps=1.5), "max_steps"),
        (lambda: pk.POM(shadows="fuzzy"), "shadows"),
        (lambda: pk.POM(filtering="cubic"), "filtering"),
        (lambda: pk.POM(lod_threshold=float("nan")), "lod_threshold"),
        (lambda: pk.DirectionalLight((0, 0, 0)), "direction"),
        (lambda: pk.DirectionalLight((0, -1, 0), irradiance=-1), "irradiance"),
        (lambda: pk.SphereLight((0, 1, 0), radius=-1), "radius"),
    ],
)
def test_bad_method_and_light_parameters(make, word):
    with pytest.raises((ValueError, TypeError), match=word):
        make()


def test_bad_scene_types():
    cam = pk.Camera.look_at((0, 1, 2))
    with pytest.raises(TypeError, match="mesh"):
        pk.Scene(mesh="plane", material=pk.Material(good_height()), camera=cam)
    with pytest.raises(TypeError, match="lights"):
        pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(good_height()), camera=cam, lights=["sun"])
    with pytest.raises(ValueError, match="lights"):
        pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(good_height()), camera=cam,
                 lights=[pk.DirectionalLight((0, -1, 0))] * 5)


def test_validation_error_becomes_exception_and_renderer_survives(renderer):
    with pytest.raises(RuntimeError, match="(?i)map_read|usage|usages") as e:
        renderer._r._provoke_validation_error()
    assert isinstance(e.value, pk.GpuError)
    f = renderer.render(plane_scene(good_height(), size=16), pk.POM())
    assert f.mask.any()


def test_unknown_adapter_names_the_choices():
    with pytest.raises(ValueError, match="adapter.*available"):
        pk.Renderer(adapter="no-such-gpu")


def _run(code, **env):
    import os
    e = dict(os.environ, **env)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=e, timeout=300)


def test_backend_env_forces_gl_and_falls_back_without_float32_filtering():
    code = (
        "import pomkit as pk, numpy as np\n"
        "r = pk.Renderer(); print(r.info['backend'], r.info['float32_filterable'])\n"
        "s = pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(pk.textures.bricks(32)), camera=pk.Camera.look_at((0,1,1.5), width=32, height=32))\n"
        "ms = [pk.Flat(), pk.Bump(), pk.Parallax(), pk.SteepParallax(), pk.POM(), pk.Relief(), pk.Exact(shadows='exact'),\n"
        "      pk.POM(shadows='horizon', ao_directions=4), pk.NCS(), pk.Prism(), pk.Tessellated()]\n"
        "s = s.replace(mesh=pk.Mesh.torus(segments=24, tube_segments=12), camera=pk.Camera.look_at((0,1.2,2.4), width=32, height=32))\n"
        "print(all(bool(f.mask.any()) and bool(np.isfinite(f.color).all()) for f in (r.render(s, m) for m in ms)))\n"
    )
    p = _run(code, POMKIT_BACKEND="gl")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.split()
    assert lines[0] == "gl"
    # every method renders on GL too (storage buffers, uint targets, fragment depth)
    assert lines[2:] == ["True"], p.stdout


def test_bad_backend_env():
    p = _run("import pomkit as pk\ntry:\n    pk.Renderer()\nexcept ValueError as e:\n    print('VE', e)\n", POMKIT_BACKEND="metal2")
    assert p.returncode == 0 and "POMKIT_BACKEND" in p.stdout, p.stdout + p.stderr


def test_gil_released_during_render(renderer):
    scene = plane_scene(pk.textures.bricks(256), size=384, theta_deg=75)
    method = pk.POM(max_steps=256)
    renderer.render(scene, method)  # warm the pipeline
    count = 0
    stop = False

    def spin():
        nonlocal count
        while not stop:
            count += 1
            time.sleep(0)

    t = threading.Thread(target=spin)
    t.start()
    before = count
    f = renderer.render(scene, method)
    during = count - before
    stop = True
    t.join()
    # the spinning thread ran while the render (tens of ms on this adapter) was in flight
    assert f.wall_ms > 5
    assert during > 10, during


def test_missing_adapter_names_the_package():
    # no Vulkan driver visible and only the Vulkan backend allowed: a clear error, no crash
    code = (
        "import pomkit as pk\n"
        "print(len(pk.adapters()))\n"
        "try:\n    pk.Renderer()\nexcept pk.NoAdapterError as e:\n    print('NoAdapterError', e)\n"
    )
    p = _run(code, POMKIT_BACKEND="vulkan", VK_ICD_FILENAMES="/nonexistent.json", VK_DRIVER_FILES="/nonexistent.json")
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("0\nNoAdapterError") and "mesa-vulkan-drivers" in p.stdout, p.stdout


def test_numpy_scalars_accepted_everywhere():
    """Arguments from NumPy (sweeps build them with np.arange/np.linspace) are accepted by the
    scene and by every method, and stored as plain Python numbers (pomkit/_validate.py)."""
    i, f, b = np.int64(16), np.float32(0.25), np.bool_(True)
    methods = [
        pk.SteepParallax(steps=i), pk.POM(min_steps=np.int32(4), max_steps=i, lod_threshold=f, adaptive=b),
        pk.Relief(linear_steps=i, binary_steps=np.uint8(3), depth_bias=b), pk.Exact(max_iterations=i),
        pk.Parallax(scale=f, offset_limiting=b), pk.NCS(step_scale=np.float64(2.0), max_steps=i),
        pk.Prism(min_steps=i, max_steps=i, outward=np.bool_(False)), pk.Tessellated(texels_per_vertex=f * 4),
        pk.POM(shadow_steps=i, ao_directions=np.int16(4), horizon_samples=np.int64(6)),
    ]
    for m in methods:
        for k, v in vars(m).items():
            assert not isinstance(v, np.generic), (type(m).__name__, k, type(v))
    cam = pk.Camera.look_at(np.array([0, 1.0, 1.5]), fov_y=np.float32(40), width=np.int64(24), height=np.uint16(24))
    scene = pk.Scene(mesh=pk.Mesh.plane(size=np.float64(2.0), segments=np.int32(2)),
                     material=pk.Material(pk.textures.bricks(32), depth=np.float32(0.05), tiling=np.int64(2)),
                     camera=cam, lights=[pk.DirectionalLight((0, -1, 0), irradiance=np.float32(2.0))])
    frame = pk.Renderer().render(scene, methods[1])
    assert frame.color.shape == (24, 24, 3) and frame.mask.any()


@pytest.mark.parametrize("make, word", [
    (lambda: pk.SteepParallax(steps=np.float64(2.5)), "steps"),
    (lambda: pk.POM(adaptive=np.int64(1)), "adaptive"),
    (lambda: pk.Camera.look_at((0, 1, 1), width=np.float32(10.5)), "width"),
    (lambda: pk.Relief(binary_steps=np.int64(-1)), "binary_steps"),
])
def test_numpy_scalars_checked_like_python_ones(make, word):
    with pytest.raises((TypeError, ValueError), match=word):
        make()
