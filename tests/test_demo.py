"""The demo page: it renders, every method appears on both scenes, the shipped Mitsuba references
match their scenes (scripts/make_demo_refs.py re-makes them when a scene changes), and the page
holds a pk.choose answer and the LOD legend."""

import html

import numpy as np
import pytest

import pomkit as pk
from pomkit.apps import page

pytestmark = pytest.mark.slow


def test_the_shipped_references_are_the_demo_scenes():
    for name, make in (("planar", page.planar_scene), ("curved", page.curved_scene), ("asset", page.asset_scene)):
        ref = page.reference(name, make())
        assert ref is not None, f"{name}: the shipped reference is stale: run scripts/make_demo_refs.py"
        assert ref.shape == (256, 256, 3) and ref.mean() > 10


def test_the_planar_scene_is_framed_on_the_surface():
    f = pk.Renderer().render(page.planar_scene(64), pk.Flat(), aovs=("mask",))
    assert f.mask.mean() > 0.95


def test_the_page(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path / "cache"))
    out = page.run_page(tmp_path / "out", size=256)  # the shipped references are 256²
    text = out.read_text()
    for name in list(page.PLANAR) + list(page.CURVED):
        assert f"<th>{name}<br>" in text, name
    # both scenes' FLIP maps against the noise-free oracle image (on the torus too), shaded as each
    # method is (shadows and AO or none), the shipped Mitsuba render beside them; each time says
    # what its method computed
    assert text.count("vs pk.oracle.image (noise-free), shaded as the method is") == 2
    assert text.count("exact hits, exact shadows") == 2
    assert "exact shadows, AO 64 directions)" in text and "ConeStep<br>" in text
    assert text.count("against the unshadowed oracle image") >= 4 and text.count("against the shadowed oracle image") >= 2
    assert "pk.choose" in text and "lod_legend.png" in text
    # the command that opens the widget on the page's scenes is on the page, and it runs
    assert html.escape(page.EXPLORE_COMMAND) in text
    pytest.importorskip("anywidget")
    w = {}
    exec(page.EXPLORE_COMMAND.replace("pk.explore(planar_scene())", "w['x'] = pk.explore(planar_scene(64), size=64)"),
         {"w": w})
    assert w["x"].image[:4] == b"\x89PNG" and w["x"].stats
    # the chart: plotly, its script beside the page (no CDN), a point per method of both scenes
    assert 'src="plotly.min.js"' in text and (tmp_path / "out" / "plotly.min.js").stat().st_size > 1e6
    assert "cdn" not in text.lower()
    for png in ("lod.png", "planar_Exact.png", "planar_Exact_uv.png", "curved_Prism.png", "curved_exact.png",
                "curved_mitsuba.png", "asset_NCS.png", "asset_mitsuba.png"):
        assert (tmp_path / "out" / png).exists(), png
    assert np.asarray(page.lod_legend(8.0)).shape[1] == 256
    # the asset section: the glTF rock, its report, its shipped Mitsuba render
    assert "<h2>asset</h2>" in text and "pk.check_asset" in text and "7 chart(s)" in text
