"""Maps of any size up to the device's max_texture_dimension_2d render with every method, and
past a limit a ValueError names the limit, the size asked for and the way out; supersampling has
no size ceiling (issue 31).

Each size case renders a small frame (the map's size is what is tested). Hypothesis draws sizes
from 1 to the limit on each axis, up to 2^22 texels (so that a case takes seconds); the explicit
cases reach the limit on one axis, and 8192² with the oracle. tools/large_maps.py measures
8192² and 16384² with every method (time, peak RSS).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pomkit as pk
from pomkit._methods import ALL_METHODS

pytestmark = pytest.mark.slow

R = pk.Renderer()
LIMIT = R.info["max_texture_dimension_2d"]
# the words a clear error holds: a limit's name, and a way out
WAYS_OUT = ("pk.textures.fit", "crop", "texels_per_vertex", "resample", "lower")


def _scene(h: np.ndarray, size: int = 12, mesh=None) -> pk.Scene:
    return pk.Scene(mesh=mesh or pk.Mesh.plane(2.0), material=pk.Material(h, depth=0.08),
                    camera=pk.Camera.look_at((0.0, 1.2, 1.2), fov_y=30.0, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.3, -1.0, -0.2), 3.0)])


def _map(w: int, h: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.random((h, w), dtype=np.float32)


def _renders_or_says_why(scene: pk.Scene, method: pk.Method) -> str:
    try:
        f = R.render(scene, method, aovs=("color", "mask"))
    except ValueError as e:
        msg = str(e)
        assert "max_" in msg or "limit" in msg, f"{method!r}: a ValueError that names no limit: {msg}"
        assert any(w in msg for w in WAYS_OUT), f"{method!r}: a ValueError with no way out: {msg}"
        return "refused"
    assert f.mask.any(), f"{method!r}: nothing hit"
    assert np.isfinite(f.color).all() and (f.color >= 0).all(), f"{method!r}: colour not finite"
    return "rendered"


@st.composite
def _sizes(draw):
    w = draw(st.integers(1, LIMIT))
    h = draw(st.integers(1, min(LIMIT, (1 << 22) // w)))
    return (h, w) if draw(st.booleans()) else (w, h)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(size=_sizes(), method=st.sampled_from(ALL_METHODS))
def test_any_size_renders_with_any_method(size, method):
    w, h = size
    outcome = _renders_or_says_why(_scene(_map(w, h)), method())
    # only an odd-sized map's distance volume may be refused (its level-0 volume)
    if outcome == "refused":
        assert method is pk.DistanceMapping and (w % 2 or h % 2), (w, h, method)


@pytest.mark.parametrize("shape", [(LIMIT, 1), (1, LIMIT), (37, LIMIT), (LIMIT, 3)])
@pytest.mark.parametrize("method", ALL_METHODS, ids=lambda m: m.__name__)
def test_the_limit_on_one_axis(shape, method):
    w, h = shape
    outcome = _renders_or_says_why(_scene(_map(w, h)), method())
    if outcome == "refused":
        assert method is pk.DistanceMapping and (w % 2 or h % 2)


def test_one_past_the_limit_is_a_clear_error():
    for shape in ((1, LIMIT + 1), (LIMIT + 1, 8)):
        with pytest.raises(ValueError, match=r"height: height map .* exceeds the device's max_texture_dimension_2d") as e:
            R.render(_scene(np.zeros(shape, np.float32)), pk.POM())
        assert "pk.textures.fit" in str(e.value) and "crop" in str(e.value)


def test_8192_exact_meets_the_oracle():
    """Issue 31's check: Exact within 0.01 texel p99 of the oracle on an 8192² map."""
    h = pk.textures.fit(pk.textures.noise(512), None)
    big = np.kron(h, np.ones((16, 16), np.float32))  # 8192², plateaus 16 texels wide
    big = np.clip(big + 0.02 * _map(8192, 8192), 0, 1)
    scene = _scene(big, size=48)
    f = R.render(scene, pk.Exact(), aovs=("uv", "mask"))
    o = pk.oracle.hits(scene)
    err = pk.metrics.uv_error(f, o, scene)
    assert err["mask_iou"] > 0.99 and err["p99"] < 0.01, err


def test_tessellated_names_the_texels_per_vertex_that_fits():
    with pytest.raises(ValueError, match=r"texels_per_vertex: .* use at least ([0-9.]+) texels per vertex") as e:
        R.render(_scene(np.zeros((8192, 8192), np.float32)), pk.Tessellated(1.0), aovs=("mask",))
    fit = float(str(e.value).split("use at least ")[1].split()[0])
    assert 1.0 < fit < 2.0


def test_supersampling_at_any_size():
    """spp=256 at 600² (a 9600² sample grid, rendered in 3 x 3 tiles of at most 4096² samples, the
    last row and column partial) gives one frame, its colour finite and its coverage a fraction
    (tests/rust/core_render.rs holds tiles equal to one pass). At 1024² it took 52 s here."""
    h = pk.textures.bricks(128)
    big = R.render(_scene(h, size=600), pk.POM(), spp=256, aovs=("color", "coverage"))
    assert big.color.shape == (600, 600, 3) and np.isfinite(big.color).all()
    assert 0.9 < big.coverage.mean() <= 1.0


CONE_CASE = r"""
import hashlib, sys
import numpy as np
import pomkit as pk
from pomkit import _core
sys.path.insert(0, sys.argv[1])
from test_sizes import _map, _scene
r = pk.Renderer()
seen = []
_core.set_progress_hook(lambda label, done, total: seen.append(label))
f = r.render(_scene(_map(4096, 4096, seed=5), size=32), pk.ConeStep(), aovs=("uv", "mask"))
print(hashlib.sha256(np.nan_to_num(f.uv).tobytes()).hexdigest(), seen.count("cone map"))
"""


def test_a_long_cone_map_build_reports_progress_and_is_kept(tmp_path):
    """A 4096² cone map (3 s here): the build reports its rows (the first process) and is kept on
    disk by content; a second process reads it (no build, so no report) and renders the
    same frame; a damaged file is built again."""
    import os
    import subprocess
    import sys
    # keep every build: a faster machine may build 4096² in under the default second
    env = dict(os.environ, POMKIT_CACHE=str(tmp_path), POMKIT_KEEP_BUILDS_AFTER_MS="0")
    run = lambda: subprocess.run([sys.executable, "-c", CONE_CASE, os.path.dirname(__file__)], env=env,
                                 capture_output=True, text=True, timeout=600)
    a = run()
    assert a.returncode == 0, a.stderr[-2000:]
    digest, reports = a.stdout.split()
    assert int(reports) >= 2  # the start and the bands
    kept = list(tmp_path.glob("cone-map-*.bin"))
    assert len(kept) == 1 and kept[0].stat().st_size == 16 + 4096 * 4096 * 8
    b = run()
    assert b.returncode == 0 and b.stdout.split() == [digest, "0"], b.stdout + b.stderr[-2000:]
    kept[0].write_bytes(kept[0].read_bytes()[:1000])  # damaged: removed and built again
    c = run()
    assert c.returncode == 0 and c.stdout.split()[0] == digest and int(c.stdout.split()[1]) >= 2


def test_a_bar_only_after_two_seconds(monkeypatch):
    from pomkit import _progress
    made = []

    class Bar:
        n = 0

        def __init__(self, total, initial, **kw):
            self.total, self.n = total, initial
            made.append(self)

        def update(self, k):
            self.n += k

        def close(self):
            self.closed = True

    clock = iter([0.0, 0.5, 1.0, 2.5, 3.0, 4.0])
    monkeypatch.setattr(_progress.time, "monotonic", lambda: next(clock))
    monkeypatch.setattr(_progress, "_bar", lambda label, total, done: Bar(total, done))
    for done in (0, 10, 20, 30, 40):
        _progress.report("cone map", done, 50)
    assert len(made) == 1 and made[0].n == 40  # made at 2.5 s (30 rows), updated after
    _progress.report("cone map", 50, 50)
    assert made[0].closed and "cone map" not in _progress._builds
