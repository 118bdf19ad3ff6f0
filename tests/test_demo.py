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
    # a card per method on both scenes, each opening its own page with its frame and maps
    for scene, methods in (("planar", page.PLANAR), ("curved", page.CURVED)):
        for name in methods:
            detail = f"{scene}_{name}.html".replace(" ", "_")
            assert f'href="{html.escape(detail)}"' in text, (scene, name)
            d = (tmp_path / "out" / detail).read_text()
            assert f'src="{html.escape(scene + "_" + name)}_uv.png"' in d, detail
    details = "".join(p.read_text() for p in (tmp_path / "out").glob("*.html") if p.name != "index.html")
    # both scenes' FLIP maps against the noise-free oracle image (on the torus too), shaded as each
    # method is (shadows and AO or none), the shipped Mitsuba render beside them; each time says
    # what its method computed
    assert text.count("vs pk.oracle.image (noise-free), shaded as the method is") == 2
    assert text.count("exact hits, exact shadows") == 2
    assert "exact shadows, AO 64 directions)" in details and "ConeStep</b>" in text
    assert details.count("against the unshadowed oracle image") >= 4 and details.count("against the shadowed oracle image") >= 2
    assert "pk.choose" in text and "lod_legend.png" in text
    # the page says nothing meant for maintainers, and its chart comes first
    assert "scripts/" not in text and "make_demo_refs" not in text
    assert text.index('id="pareto"') < text.index('id="planar"')
    # the corpus table's summary, from the checkout the tests run in
    assert "On models other people made" in text and "converted files from" in text
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
    assert '<h2 id="asset">asset</h2>' in text and "pk.check_asset" in text and "7 chart(s)" in text
