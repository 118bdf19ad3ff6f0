"""pk.choose: the cheapest setting that meets a bound on every case it was given."""

import numpy as np
import pytest

import pomkit as pk
from pomkit import metrics
from pomkit._choose import parse_angles

KW = dict(angles=(40.0, 72.0), resolution=48, rounds=2)


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    return tmp_path


def test_the_choice_meets_the_bound_on_every_case(cache):
    hs = [pk.textures.bricks(64), pk.textures.real("gravel", 64)]
    ch = pk.choose(heights=hs, max_uv_error=0.5, methods=["SteepParallax", "POM", "Exact"], **KW)
    assert ch.met and ch.method is not None, str(ch)
    # rendered again, on every case
    from pomkit.bench import plane_scene
    r = pk.Renderer()
    for h in hs:
        for a in KW["angles"]:
            sc = plane_scene(h, a, KW["resolution"])
            e = metrics.uv_error(r.render(sc, ch.method), pk.oracle.hits(sc), sc)
            assert e["p95"] <= 0.5, (ch.method, h.shape, a, e["p95"])
    # the cheapest that meets it: nothing in the table that meets it is cheaper
    best = next(r for r in ch.table if r["method"] is ch.method)
    assert all(r["gpu_ms"] >= best["gpu_ms"] for r in ch.table if r["meets"])
    # bisection, not a grid: a handful of step counts per family
    assert sum(r["family"] == "SteepParallax" for r in ch.table) <= 9
    assert "runner-up" in str(ch) or ch.runner_up is None
    # a uv bound measures no FLIP: the answer says nothing of it (it read "worst FLIP nan")
    assert "nan" not in str(ch) and "nan" not in ch.markdown()


def test_a_looser_bound_is_answered_from_the_cache(cache, monkeypatch):
    renders = []
    real = pk.Renderer.render

    def counting(self, *a, **k):
        renders.append(1)
        return real(self, *a, **k)

    monkeypatch.setattr(pk.Renderer, "render", counting)
    h = pk.textures.bricks(64)
    tight = pk.choose(heights=h, max_uv_error=0.3, methods=["SteepParallax", "Exact"], **KW)
    n_tight = len(renders)
    again = pk.choose(heights=h, max_uv_error=0.3, methods=["SteepParallax", "Exact"], **KW)
    n_again = len(renders) - n_tight
    loose = pk.choose(heights=h, max_uv_error=3.0, methods=["SteepParallax", "Exact"], **KW)
    n_loose = len(renders) - n_tight - n_again
    assert tight.met and loose.met and repr(again.method) == repr(tight.method)
    assert n_tight > 0 and n_again == 0 and n_loose < n_tight / 2, (n_tight, n_again, n_loose)
    # a looser bound needs no more steps of any family (costs at 48² are within timing noise of
    # each other, so the check is on the knob, not on the ms)
    for fam in ("SteepParallax",):
        need = [min((r["knob"] for r in c.table if r["family"] == fam and r["meets"]), default=None) for c in (tight, loose)]
        assert need[0] is not None and need[1] is not None and need[1] <= need[0], need


def test_no_method_meets_it_and_the_closest_is_named(cache):
    ch = pk.choose(heights=pk.textures.bricks(64), max_uv_error=1e-9, methods=["Parallax", "SteepParallax"], **KW)
    assert not ch.met and ch.method is None and ch.closest is not None
    from pomkit.bench import label
    assert "no method meets" in str(ch) and label(ch.closest) in str(ch) and "nan" not in str(ch)


def test_bad_arguments_name_the_fix():
    with pytest.raises(ValueError, match="max_uv_error or max_flip"):
        pk.choose(heights=pk.textures.bricks(32))
    with pytest.raises(ValueError, match="methods"):
        pk.choose(heights=pk.textures.bricks(32), max_uv_error=1.0, methods=["Nope"])
    with pytest.raises(ValueError, match="heights or scenes"):
        pk.choose(max_uv_error=1.0)
    assert parse_angles("30:80") == [30.0, 55.0, 80.0] and parse_angles("10,20") == [10.0, 20.0]
    with pytest.raises(ValueError, match="angles"):
        parse_angles("a:b")


def test_the_command_line_writes_a_report(cache, tmp_path):
    from pomkit.__main__ import main
    from PIL import Image
    path = tmp_path / "h.png"
    Image.fromarray((pk.textures.bricks(64) * 65535).astype(np.uint16)).save(path)
    out = tmp_path / "out"
    assert main(["choose", str(path), "--angles", "40:70:2", "--resolution", "48", "--max-uv-error", "1.0",
                 "--methods", "SteepParallax,Exact", "--out", str(out)]) == 0
    assert (out / "choice.md").read_text().startswith("# pk.choose")
    assert (out / "choice.json").exists()


def test_the_cache_tells_backends_apart(cache, monkeypatch):
    """GL's adapter has the same name as Vulkan's here, and samples differently (exact filtering:
    four fetches a sample): a measurement is keyed by adapter, backend and driver."""
    from pomkit import _choose
    from pomkit._cache import scene_hash
    seen = []
    real = scene_hash

    def spy(scene, **kw):
        seen.append(kw)
        return real(scene, **kw)

    monkeypatch.setattr("pomkit._cache.scene_hash", spy)
    pk.choose(heights=pk.textures.bricks(32), max_uv_error=5.0, methods=["Parallax"], angles=(40.0,), resolution=32, rounds=1)
    info = _choose._renderer().info
    keys = [k for k in seen if k.get("kind") == "choose"]
    assert keys and all(info["backend"] in k["adapter"] and info["name"] in k["adapter"] for k in keys)
