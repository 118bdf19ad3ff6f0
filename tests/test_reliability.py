"""Reliability: fuzzed inputs, threads, determinism, device faults, resource limits."""

import hashlib
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import pomkit as pk
from conftest import plane_scene

FUZZ_EXAMPLES = int(os.environ.get("POMKIT_FUZZ_EXAMPLES", "150"))

finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
anyfloat = st.one_of(finite, st.just(float("nan")), st.just(float("inf")), st.just(-float("inf")),
                     st.floats(-1e30, 1e30))
shapes = st.one_of(st.tuples(st.integers(0, 40), st.integers(0, 40)), st.tuples(st.integers(1, 8)),
                   st.tuples(st.integers(1, 6), st.integers(1, 6), st.integers(1, 4)))
dtypes = st.sampled_from([np.float32, np.float64, np.uint8, np.uint16, np.int32, np.bool_, np.float16])


@st.composite
def valid_heights(draw):
    h = draw(st.integers(1, 40))
    w = draw(st.integers(1, 40))
    seed = draw(st.integers(0, 2**16))
    return np.random.default_rng(seed).random((h, w)).astype(draw(st.sampled_from([np.float32, np.float64])))


@st.composite
def junk_arrays(draw):
    shape = draw(shapes)
    dt = draw(dtypes)
    n = int(np.prod(shape)) if shape else 1
    if dt in (np.uint8, np.uint16, np.int32):
        data = draw(st.lists(st.integers(0, 255), min_size=n, max_size=n))
    elif dt == np.bool_:
        data = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    else:
        data = draw(st.lists(st.one_of(st.floats(0, 1), anyfloat), min_size=n, max_size=n))
    with np.errstate(over="ignore"):
        return np.array(data, dtype=dt).reshape(shape)


def method_strategy():
    steps = st.one_of(st.integers(-2, 300), st.floats(-1, 300), st.just(float("nan")), st.just(1.5))
    shadows = st.sampled_from(["none", "hard", "soft", "horizon", "exact", "bogus"])
    return st.one_of(
        st.just(pk.Flat()).map(lambda m: lambda: m),
        st.builds(lambda f: lambda: pk.Bump(filtering=f), st.sampled_from(["hardware", "exact", "x"])),
        st.builds(lambda a, b, s, l, f: lambda: pk.POM(min_steps=a, max_steps=b, shadows=s, lod_threshold=l, filtering=f),
                  steps, steps, shadows, anyfloat, st.sampled_from(["hardware", "exact"])),
        st.builds(lambda n, s: lambda: pk.SteepParallax(steps=n, shadows=s), steps, shadows),
        st.builds(lambda n, b, d: lambda: pk.Relief(linear_steps=n, binary_steps=b, depth_bias=d), steps, steps, st.booleans()),
        st.builds(lambda k, s, a: lambda: pk.Exact(max_iterations=k, shadows=s, ao_directions=a), st.integers(-1, 5000), shadows,
                  st.integers(-1, 9)),
        st.builds(lambda sc, b, o: lambda: pk.Parallax(scale=sc, bias=b, offset_limiting=o), anyfloat, anyfloat, st.booleans()),
        st.builds(lambda t, s: lambda: pk.Tessellated(texels_per_vertex=t, shadows=s), st.one_of(st.floats(0.4, 8), anyfloat), shadows),
    )


def _named(e: Exception) -> bool:
    """The message names an argument (starts with 'name:')."""
    msg = str(e)
    head = msg.split(":", 1)[0]
    return ":" in msg and head.strip().replace("_", "").isalnum()


def mostly(valid, junk, one_in=10):
    """`valid`, and `junk` once in `one_in` draws: the fuzz must reach the GPU often."""
    return st.integers(0, one_in - 1).flatmap(lambda k: junk if k == 0 else valid)


heights = mostly(valid_heights(), junk_arrays())
depths = mostly(st.floats(0, 1), anyfloat)
tilings = mostly(st.floats(0.01, 100), anyfloat)
eyes = mostly(st.tuples(st.floats(-5, 5), st.floats(0.1, 5), st.floats(-5, 5)), st.tuples(anyfloat, anyfloat, anyfloat))
fovs = mostly(st.floats(1, 170), anyfloat)
sizes = mostly(st.tuples(st.integers(1, 48), st.integers(1, 48)), st.tuples(st.integers(-2, 70000), st.integers(-2, 70000)))


@settings(max_examples=FUZZ_EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(height=heights, depth=depths, tiling=tilings, eye=eyes, fov=fovs, size=sizes,
       method=method_strategy(), ambient=mostly(st.floats(0, 2), anyfloat))
def test_fuzzed_api_never_crashes(renderer, height, depth, tiling, eye, fov, size, method, ambient):
    try:
        mat = pk.Material(height, depth=depth, tiling=tiling)
        cam = pk.Camera.look_at(eye, fov_y=fov, width=size[0], height=size[1])
        m = method()
        scene = pk.Scene(mesh=pk.Mesh.plane(), material=mat, camera=cam,
                         lights=[pk.DirectionalLight((-0.3, -1, -0.2), 2.0, 1.0)], ambient=ambient)
        f = renderer.render(scene, m)
    except (ValueError, TypeError) as e:
        assert _named(e), repr(e)
        event(f"raised {type(e).__name__} naming {str(e).split(':', 1)[0]}")
        return
    event("rendered")
    for name in ("color", "uv", "depth", "lod"):
        assert np.isfinite(getattr(f, name)[f.mask]).all(), name


@settings(max_examples=max(FUZZ_EXAMPLES // 3, 20), deadline=None, suppress_health_check=list(HealthCheck))
@given(n=st.integers(0, 12), pos=st.lists(mostly(st.floats(-3, 3), anyfloat, 200), min_size=36, max_size=36),
       uvs=st.lists(mostly(st.floats(-2, 2), anyfloat, 200), min_size=24, max_size=24),
       idx=mostly(st.lists(st.integers(0, 11), min_size=3, max_size=18).map(lambda l: l[: len(l) // 3 * 3]),
                  st.lists(st.integers(-2, 14), min_size=0, max_size=18), 5))
def test_fuzzed_meshes(renderer, n, pos, uvs, idx):
    n = max(n, max(idx, default=-1) + 1) if all(i >= 0 for i in idx) and max(idx, default=0) < 12 else n
    p = np.array(pos[: 3 * n], np.float64).reshape(n, 3)
    u = np.array(uvs[: 2 * n], np.float64).reshape(n, 2)
    normals = np.tile([0.0, 1.0, 0.0], (n, 1))
    try:
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = pk.Mesh.from_arrays(p, normals, u, np.array(idx, np.int64))
        scene = pk.Scene(mesh=mesh, material=pk.Material(pk.textures.bricks(16)), camera=pk.Camera.look_at((0, 2, 2), width=16, height=16))
        f = renderer.render(scene, pk.POM())
    except (ValueError, TypeError) as e:
        assert _named(e), repr(e)
        event(f"mesh raised {type(e).__name__} naming {str(e).split(':', 1)[0]}")
        return
    event("mesh rendered")
    assert np.isfinite(f.color[f.mask]).all()


def _scenes():
    out = []
    for i, tex in enumerate(["bricks", "spikes", "noise", "pyramids"]):
        out.append(plane_scene(pk.textures.ALL[tex](64), theta_deg=20 + 15 * i, size=64,
                               lights=[pk.DirectionalLight((-0.4, -1, -0.3), 2.0, 2.0)], ambient=0.1))
    return out


def _digest(f):
    h = hashlib.sha256()
    for a in (f.color, f.uv, f.depth, f.mask, f.steps, f.lod):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def test_threads_render_alone_bit_for_bit(renderer):
    scenes = _scenes()
    methods = [pk.POM(), pk.Exact(shadows="exact"), pk.Relief(shadows="soft"), pk.Tessellated()]
    alone = [_digest(renderer.render(s, m)) for s, m in zip(scenes, methods)]
    results = [None] * 4
    errors = []

    def work(k):
        try:
            for _ in range(5):
                results[k] = _digest(renderer.render(scenes[k], methods[k]))
                assert results[k] == alone[k]
        except Exception as e:  # surfaced below
            errors.append(e)

    ts = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert not errors, errors
    assert results == alone


def test_deterministic_across_calls_and_processes(renderer):
    s = _scenes()[1]
    a = _digest(renderer.render(s, pk.POM()))
    assert a == _digest(renderer.render(s, pk.POM()))
    code = (
        "import sys; sys.path.insert(0, 'tests')\n"
        "import pomkit as pk\n"
        "from test_reliability import _scenes, _digest\n"
        "print(_digest(pk.Renderer().render(_scenes()[1], pk.POM())))\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                       cwd=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == a


def test_device_lost_then_a_new_renderer_works():
    # in a subprocess: destroying the shared device must not disturb the other tests
    code = (
        "import pomkit as pk, numpy as np\n"
        "s = pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(pk.textures.bricks(32)), camera=pk.Camera.look_at((0,1,1.5), width=32, height=32))\n"
        "r = pk.Renderer(); r.render(s, pk.POM())\n"
        "r._r._destroy_device()\n"
        "try:\n    r.render(s, pk.POM())\n    print('NO ERROR')\n"
        "except pk.DeviceLostError as e:\n    print('LOST', 'new pomkit.Renderer' in str(e))\n"
        "r2 = pk.Renderer(); f = r2.render(s, pk.POM()); print('OK', bool(f.mask.any()))\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["LOST", "True", "OK", "True"], p.stdout + p.stderr


def test_huge_requests_are_refused_before_the_gpu(renderer):
    lim = renderer.info["max_texture_dimension_2d"]
    # a 16k+ map: refused with the limit named, without allocating it on the GPU
    h = np.zeros((lim + 1, 2), np.float32)
    with pytest.raises(ValueError, match=f"max_texture_dimension_2d = {lim}"):
        renderer.render(plane_scene(h, size=8), pk.Exact())
    # a tessellation that would need more vertices than the core allows
    with pytest.raises(ValueError, match="texels_per_vertex|resolution"):
        renderer.render(plane_scene(np.zeros((4096, 4096), np.uint8), size=8), pk.Tessellated(texels_per_vertex=1 / 8))


def test_renderer_survives_a_shader_error_message():
    # a validation error is a GpuError with wgpu's message; the next call works
    r = pk.Renderer()
    with pytest.raises(pk.GpuError):
        r._r._provoke_validation_error()
    assert r.render(_scenes()[0], pk.Exact()).mask.any()
