"""The demo's page (`python -m pomkit demo` writes pomkit-out/index.html, a page per card and
their PNGs): a gallery of every method on a planar and on a curved scene and of the curved methods
on an asset (a glTF rock with a UV atlas, its report from `pk.check_asset`), framed on the
surface, each card a thumbnail and its figures that opens the method's frame, uv-error and FLIP
maps and settings; the Mitsuba reference beside each scene (renders shipped with the package,
made by scripts/make_demo_refs.py, so the demo needs no Mitsuba); a sticky legend of the maps'
scales; the speed/accuracy chart of the methods shown at the top; the corpus table's summary
where the checkout holds it; a `pk.choose` answer for one built-in map, loops in motion beside
their motion tables (loops.py), and the LOD as a false-colour overlay with its legend. One
column of at most 1360 pixels (a 1400-pixel window shows it without scrolling sideways).
"""

from __future__ import annotations

import functools
import html
import json
import textwrap
import time
from pathlib import Path
from typing import Callable, Optional

import numpy as np

import pomkit as pk
from pomkit._heatmap import heat, ramp

REFS = Path(__file__).resolve().parent.parent / "data" / "demo"
UV_MAX = 2.0  # texels: the uv heat map's scale
#: the table of the corpus of other people's models (relative to a checkout), whose summary the
#: page quotes where it is made in a checkout that holds it (`make demo` runs in one) or from an
#: editable install of one
WILD_TABLE = Path("docs") / "tables" / "wild.md"
#: the page's style: one column of at most 1360 pixels, the legend kept in view
CSS = ("body{font-family:system-ui,sans-serif;font-size:15px;line-height:1.4;background:#fafafa;color:#222;"
       "margin:0 auto;padding:0 1em 2em;max-width:1360px;box-sizing:border-box}"
       "img{image-rendering:pixelated;max-width:100%}h2{margin-top:1.6em;border-bottom:1px solid #ddd}"
       ".maplegend{position:sticky;top:0;z-index:5;background:#fafafaee;border-bottom:1px solid #ddd;padding:6px 0;"
       "display:flex;flex-wrap:wrap;gap:18px;align-items:center;font-size:13px}.maplegend img{height:14px;width:160px;"
       "vertical-align:middle}.gallery{display:grid;grid-template-columns:repeat(auto-fill,minmax(180px,1fr));gap:10px}"
       ".card{display:block;background:#fff;border:1px solid #ddd;border-radius:6px;padding:6px;color:inherit;"
       "text-decoration:none;font-size:13px}.card:hover{border-color:#888}.card img{width:100%;display:block;"
       "margin-bottom:4px}.card .more{display:none}.refs,.maps{display:flex;flex-wrap:wrap;gap:12px}"
       "figure{margin:0;max-width:420px}figcaption{font-size:13px;color:#555}small{color:#555}"
       "pre{white-space:pre-wrap;overflow-wrap:anywhere;background:#fff;border:1px solid #eee;padding:8px}"
       "td,th{padding:3px;vertical-align:top}")


#: what the page prints to open `pk.explore` on its own two scenes (tests/test_demo.py runs it)
EXPLORE_COMMAND = ("import pomkit as pk\n"
                   "from pomkit.apps.page import planar_scene, curved_scene\n"
                   "pk.explore(planar_scene())   # or curved_scene()")


def planar_scene(size: int = 256) -> pk.Scene:
    """Bricks with an albedo on a plane at 62° from the normal, framed on the surface (no sky)."""
    h = pk.textures.bricks(256)
    t = np.radians(62.0)
    return pk.Scene(mesh=pk.Mesh.plane(size=6.0),
                    material=pk.Material(height=h, depth=0.06, tiling=6.0, albedo=pk.textures.brick_albedo(h)),
                    camera=pk.Camera.look_at(eye=(0.0, 1.1 * np.cos(t), 1.1 * np.sin(t)), target=(0.0, 0.0, -0.15),
                                             up=(0, 1, 0), fov_y=36.0, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.6, -0.55, -0.3), 3.0)], ambient=0.08)


def curved_scene(size: int = 256) -> pk.Scene:
    """Cobblestones on a torus, seen from above the rim: silhouettes against the black."""
    return pk.Scene(mesh=pk.Mesh.torus(segments=48, tube_segments=24),
                    material=pk.Material(pk.textures.cobblestones(256, cells=8), depth=0.12, tiling=1.0),
                    camera=pk.Camera.look_at((0.0, 1.6, 2.2), target=(0.0, -0.1, 0.0), fov_y=38, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.08)


ASSET = REFS / "rock.glb"
ASSET_HEIGHT = REFS / "rock_height.png"


def asset_scene(size: int = 256) -> pk.Scene:
    """A low-poly rock as a user brings it: a glTF (1280 triangles, an xatlas atlas of several
    charts, MikkTSpace tangents) with a height map baked over its atlas (scripts/make_demo_refs.py
    made both from tests/zoo.py's rock)."""
    mesh = pk.load_mesh(ASSET)
    return pk.Scene(mesh=mesh, material=pk.Material(pk.load_height(ASSET_HEIGHT), depth=0.05),
                    camera=pk.Camera.look_at((1.9, 1.5, 2.4), target=(0.0, 0.0, 0.0), fov_y=38, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.08)


PLANAR: dict[str, Callable[[], pk.Method]] = {
    "Flat": pk.Flat, "Bump": pk.Bump, "Parallax": pk.Parallax, "SteepParallax": pk.SteepParallax,
    "POM": lambda: pk.POM(shadows="soft"), "Relief": pk.Relief, "ConeStep": pk.ConeStep,
    "Exact": lambda: pk.Exact(shadows="exact", ao_directions=64, mip_filtering=False), "DistanceMapping": pk.DistanceMapping,
    "Prism": pk.Prism, "Tessellated(1)": lambda: pk.Tessellated(1.0, shadows="exact")}
CURVED: dict[str, Callable[[], pk.Method]] = {
    "Flat": pk.Flat, "POM": pk.POM, "NCS": pk.NCS, "CurvedRelief": pk.CurvedRelief, "Prism": pk.Prism,
    "Prism (exact)": lambda: pk.Prism(exact=True), "Tessellated(1)": lambda: pk.Tessellated(1.0)}
ASSET_METHODS: dict[str, Callable[[], pk.Method]] = {
    "Flat": pk.Flat, "POM": pk.POM, "NCS": pk.NCS, "CurvedRelief": pk.CurvedRelief, "Prism": pk.Prism,
    "Prism (exact)": lambda: pk.Prism(exact=True), "Tessellated(1)": lambda: pk.Tessellated(1.0)}

#: coarse + fine (pk.Hybrid) on the asset: three densities of the coarse mesh, Exact marching the rest
def _hybrid(tpv: float) -> Callable[[], pk.Method]:
    return lambda: pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=tpv), fine=pk.Exact())


HYBRID_METHODS: dict[str, Callable[[], pk.Method]] = {
    "Exact": pk.Exact, **{f"Hybrid({tpv:g}, Exact)": _hybrid(tpv) for tpv in (16.0, 4.0, 1.0)},
    "Tessellated(1)": lambda: pk.Tessellated(1.0)}


def reference(name: str, scene: pk.Scene) -> Optional[np.ndarray]:
    """The shipped Mitsuba render (sRGB8) of the demo scene `name`, if it is this scene's."""
    from PIL import Image
    from .._cache import scene_hash
    meta = REFS / f"{name}.json"
    if not meta.exists():
        return None
    m = json.loads(meta.read_text())
    if m.get("hash") != scene_hash(scene, kind="mitsuba", spp=m["spp"], seed=0, variant=None, resolution=2.0):
        return None
    return np.asarray(Image.open(REFS / f"{name}.png").convert("RGB"))


def lod_overlay(frame: pk.Frame, levels: float) -> np.ndarray:
    """The mip level as a false colour (level 0 blue, rising through green and yellow to red at
    `levels`) over the frame's luminance: it reads at a glance, whatever the albedo."""
    base = frame.to_srgb8().astype(np.float32) / 255.0
    lum = base.mean(-1, keepdims=True)
    stops = np.array([[0.15, 0.35, 1.0], [0.1, 0.85, 0.4], [1.0, 0.9, 0.1], [1.0, 0.2, 0.15]])
    col = ramp(np.nan_to_num(frame.lod, nan=0.0) / max(levels, 1e-6), stops)
    out = np.where(frame.mask[..., None], col * (0.35 + 0.65 * lum), base)
    return (np.clip(out, 0, 1) * 255).astype(np.uint8)


def lod_legend(levels: float, width: int = 256) -> np.ndarray:
    from PIL import Image, ImageDraw
    fake = pk.Frame._of({"color": np.ones((1, width, 3), np.float32) * 0.8,
                         "lod": np.linspace(0, levels, width, dtype=np.float32)[None, :],
                         "mask": np.ones((1, width), bool)})
    bar = np.repeat(lod_overlay(fake, levels), 14, axis=0)
    im = Image.new("RGB", (width, 30), (255, 255, 255))
    im.paste(Image.fromarray(bar), (0, 0))
    d = ImageDraw.Draw(im)
    for k in range(int(levels) + 1):
        x = int(k / levels * (width - 1))
        d.text((min(x, width - 10), 16), str(k), fill=(0, 0, 0))
    return np.asarray(im)


def _save(img: np.ndarray, path: Path) -> str:
    from PIL import Image
    Image.fromarray(img).save(path)
    return path.name


def _have_flip() -> bool:
    """Whether FLIP (flip-evaluator) is installed: the colour error maps are FLIP's, else the mean
    absolute sRGB difference (`_flip_map`)."""
    try:
        import flip_evaluator  # noqa: F401
    except ImportError:
        return False
    return True


def _flip_map(frame: pk.Frame, ref: pk.Frame) -> tuple[float, np.ndarray]:
    """FLIP (flip-evaluator, when installed) or, without it, the mean absolute sRGB difference."""
    ref8 = ref.to_srgb8()
    try:
        m, e = pk.metrics.flip(frame, ref, image=True)
        e = np.asarray(e)
        return m, e.reshape(e.shape[:2])
    except ImportError:
        d = np.abs(frame.to_srgb8().astype(np.float32) - ref8.astype(np.float32)).mean(-1) / 255.0
        return float(d.mean()), d


def computed(m: pk.Method) -> str:
    """What a method's frame computed beyond its hit: its self-shadows and ambient occlusion."""
    sh = getattr(m, "shadows", "none")
    ao = getattr(m, "ao_directions", 0)
    return ("no shadows" if sh == "none" else f"{sh} shadows") + (f", AO {ao} directions" if ao else "")


def _detail_page(outdir: Path, name: str, label: str, imgs: list[str], heads: list[str], figures: str,
                 settings: str) -> str:
    """One card's page: the method's frame and error maps at full size, its figures and settings."""
    page_name = f"{name}_{label}.html".replace(" ", "_")
    cells = "".join(f"<figure><img src=\"{html.escape(i)}\"><figcaption>{html.escape(h)}</figcaption></figure>"
                    for i, h in zip(imgs, heads))
    (outdir / page_name).write_text(
        f"<!doctype html><meta charset=utf-8><title>{html.escape(label)} on {name}</title><link rel=icon href='data:,'>"
        f"<style>{CSS}</style><p><a href=\"index.html#{name}\">back to the gallery</a></p>"
        f"<h1>{html.escape(label)} <small>on the {name} scene</small></h1><div class=maps>{cells}</div>"
        f"<p>{html.escape(figures)}</p><pre>{html.escape(settings)}</pre>", encoding="utf-8")
    return page_name


def section(r: pk.Renderer, outdir: Path, name: str, scene: pk.Scene, methods: dict, uv_ref: pk.Frame,
            uv_ref_label: str, colour_ref: Optional[dict[bool, pk.Frame]] = None) -> tuple[str, list[dict]]:
    """One scene of the gallery: its references, and a card per method (its frame as a
    thumbnail, its figures) that opens the method's page (its frame, uv-error map, FLIP map,
    figures and settings), with what the method computed beside its time. The FLIP is against
    `colour_ref` when given, the noise-free `pk.oracle.image` shaded as the method is ({True:
    with shadows and AO, False: without}, by whether the method shadows itself), else against
    the shipped Mitsuba render."""
    ref8 = reference(name, scene)
    flip_refs: dict[bool, pk.Frame] = {}
    if colour_ref is not None:
        flip_refs, flip_label = colour_ref, "pk.oracle.image (noise-free), shaded as the method is"
        flip_ref: Optional[pk.Frame] = colour_ref[True]
    elif ref8 is not None:
        flip_ref = pk.Frame._of({"color": pk.srgb_to_linear(ref8).astype(np.float32), "mask": np.ones(ref8.shape[:2], bool)})
        flip_label = "Mitsuba"
    else:
        flip_ref, flip_label = None, ""
    rows, cards = [], []
    have_flip = _have_flip()
    flip_name = "FLIP" if have_flip else "|Δ sRGB|"
    for label, make in methods.items():
        m = make()
        f = r.render(scene, m, spp=4)
        e = pk.metrics.uv_error(f, uv_ref, scene)
        row = dict(scene=name, method=label, gpu_ms=f.time_ms or float("nan"), uv_p95=e["p95"], mask_iou=e["mask_iou"],
                   safety=m.safety, settings=repr(m))
        imgs = [_save(f.to_srgb8(), outdir / f"{name}_{label}.png"),
                _save(heat(e["image"], UV_MAX, f.mask | uv_ref.mask), outdir / f"{name}_{label}_uv.png")]
        heads = ["frame (4 spp)", f"uv error vs {uv_ref_label} (0–{UV_MAX:g} texels)"]
        if flip_ref is not None:
            shaded = getattr(m, "shadows", "none") != "none"
            fl, emap = _flip_map(f, flip_refs.get(shaded, flip_ref))
            row["flip"] = fl
            row["flip_against"] = ("the shadowed" if shaded else "the unshadowed") if flip_refs else "Mitsuba"
            imgs.append(_save(heat(emap, 0.5 if have_flip else 0.25, np.ones(emap.shape, bool)),
                              outdir / f"{name}_{label}_flip.png"))
            heads.append(f"{flip_name} vs {flip_label}")
        rows.append(row)
        row["computed"] = computed(m)
        figures = (f"{row['gpu_ms']:.1f} ms (2 passes, spp 4; {row['computed']}) · uv p95 {row['uv_p95']:.2f} tx · "
                   f"IoU {row['mask_iou']:.3f}")
        if "flip" in row:
            figures += f" · {flip_name} {row['flip']:.3f}"
            if flip_refs:
                figures += f" against {row['flip_against']} oracle image"
        detail = _detail_page(outdir, name, label, imgs, heads, figures, row["settings"])
        short = f"{row['gpu_ms']:.1f} ms · uv p95 {row['uv_p95']:.2f} · IoU {row['mask_iou']:.3f}" + (
            f" · {flip_name} {row['flip']:.3f}" if "flip" in row else "")
        cards.append(f'<a class=card href="{html.escape(detail)}"><img src="{html.escape(imgs[0])}" alt="{html.escape(label)}">'
                     f"<b>{html.escape(label)}</b> <small>{m.safety}</small><br><small>{html.escape(short)}</small></a>")
    refs = []
    if ref8 is not None:
        _save(ref8, outdir / f"{name}_mitsuba.png")
        refs.append(f'<figure><img src="{name}_mitsuba.png"><figcaption>Mitsuba 3 (the displaced mesh, box filter)</figcaption></figure>')
    if colour_ref is not None:
        _save(colour_ref[True].to_srgb8(), outdir / f"{name}_exact.png")
        refs.append(f'<figure><img src="{name}_exact.png"><figcaption><code>pk.oracle.image</code> (exact hits, exact '
                    f'shadows and AO, float64; noise-free): the FLIP maps\' reference for the methods that shadow themselves, '
                    f'and the same without shadows or AO for those that do not</figcaption></figure>')
    against = f"uv error vs {html.escape(uv_ref_label)}" + (f", {flip_name} vs {html.escape(flip_label)}" if flip_ref is not None else "")
    return (f'<h2 id="{name}">{name}</h2><div class=refs>{"".join(refs)}</div><p><small>Each card opens the '
            f"method's frame and maps ({against}).</small></p><div class=gallery>{''.join(cards)}</div>"), rows


def chart(rows: list[dict], outdir: Path) -> str:
    """The speed/accuracy chart of `rows` (section's) as HTML: plotly, its script written beside
    the page as plotly.min.js (no CDN), each point's hover its scene, method, settings and
    figures. Without plotly (the demo extra), a note."""
    try:
        import plotly.graph_objects as go
        from plotly.offline import get_plotlyjs
    except ImportError:
        return "<h2 id=chart>Speed against accuracy</h2><p>(plotly not installed: no chart; <code>pip install pomkit[demo]</code>)</p>"
    fig = go.Figure()
    esc = functools.partial(html.escape, quote=False)
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for safety, symbol in (("safe", "diamond"), ("approximate", "circle")):
            pts = [r for r in rows if r["scene"] == scene and (r["safety"] == "safe") == (safety == "safe")]
            if not pts:
                continue
            hover = [f"<b>{esc(r['method'])}</b> ({esc(scene)}, {esc(r['safety'])})<br>"
                     f"{'<br>'.join(esc(x) for x in textwrap.wrap(r['settings'], 70))}<br>"
                     f"{r['gpu_ms']:.2f} GPU ms · uv p95 {r['uv_p95']:.3f} texel"
                     + (f" · FLIP {r['flip']:.4f}" if "flip" in r else "") for r in pts]
            fig.add_trace(go.Scatter(
                x=[r["gpu_ms"] for r in pts], y=[max(r["uv_p95"], 1e-3) for r in pts], mode="markers+text",
                text=[r["method"] for r in pts], textposition="top center", hovertext=hover, hoverinfo="text",
                marker=dict(symbol=symbol, size=10), name=f"{scene}, {safety}"))
    fig.update_layout(width=900, height=560, template="plotly_white",
                      title="Speed against accuracy (hover a point for its settings; diamonds: safe methods)",
                      xaxis=dict(type="log", title="GPU ms (4 spp + 1 spp passes, this adapter)"),
                      yaxis=dict(type="log", title="uv p95 against the reference geometry (texels; 0 shown at 0.001)"))
    (outdir / "plotly.min.js").write_text(get_plotlyjs(), encoding="utf-8")
    div = fig.to_html(full_html=False, include_plotlyjs="directory", div_id="pareto")
    return ("<h2 id=chart>Speed against accuracy</h2>" + div + "<p>The full sweep: <code>python -m pomkit bench</code>.</p>")


def legend(outdir: Path, have_flip: bool) -> str:
    """The sticky legend: what the error maps' colours mean, the markers, and the sections."""
    bar = np.linspace(0.0, 1.0, 160)[None, :].repeat(14, 0)
    _save(heat(bar * UV_MAX, UV_MAX, np.ones(bar.shape, bool)), outdir / "legend_uv.png")
    vmax = 0.5 if have_flip else 0.25
    _save(heat(bar * vmax, vmax, np.ones(bar.shape, bool)), outdir / "legend_flip.png")
    links = " · ".join(f'<a href="#{k}">{v}</a>' for k, v in (("chart", "speed/accuracy"), ("planar", "plane"),
                                                             ("curved", "torus"), ("asset", "asset"), ("hybrid", "coarse + fine"),
                                                             ("choose", "choose"), ("motion", "in motion")))
    return (f'<div class=maplegend><span>uv error 0 <img src="legend_uv.png" alt="uv error scale"> {UV_MAX:g} texels</span>'
            f'<span>{"FLIP" if have_flip else "|Δ sRGB|"} 0 <img src="legend_flip.png" alt="FLIP scale"> {vmax:g}</span>'
            "<span>grey: neither hits · safe: never misses a feature of the field</span>"
            f"<span>{links}</span></div>")


def wild_summary() -> str:
    """The corpus table's summary line, where the page is made from a checkout that holds it."""
    roots = (Path.cwd(), Path(__file__).resolve().parents[3])
    table = next((r / WILD_TABLE for r in roots if (r / WILD_TABLE).exists()), None)
    if table is None:
        return ""
    lines = [ln for ln in table.read_text().splitlines() if "converted files from" in ln]
    if not lines:
        return ""
    return ("<h2 id=corpus>On models other people made</h2><p>" + html.escape(lines[0]) +
            " (docs/tables/wild.md: every file, method and view against the oracle).</p>")


def run_page(out: str | Path = "pomkit-out", size: int = 256) -> Path:
    t0 = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    have_flip = _have_flip()
    head = [f"<h1>pomkit {pk.__version__}</h1><p>{html.escape(r.info['name'])} ({r.info['backend']}). "
            "Every method of the field on a plane and on a torus, and the curved methods on an asset, each against "
            "the float64 oracle; GPU times of this adapter. Each card opens its frame, error maps and figures.</p>",
            legend(outdir, have_flip)]
    planar = planar_scene(size)
    oracle = pk.oracle.hits(planar)
    exact = {sh: pk.oracle.image(planar, spp=4, shadows=sh) for sh in (True, False)}
    s1, rows = section(r, outdir, "planar", planar, PLANAR, oracle, "the float64 oracle", exact)
    curved = curved_scene(size)
    curved_ref = {sh: pk.oracle.image(curved, spp=4, shadows=sh) for sh in (True, False)}
    s2, rows2 = section(r, outdir, "curved", curved, CURVED, pk.oracle.hits(curved), "the float64 oracle", curved_ref)
    # a user's asset: a glTF with an atlas, checked, every curved method against the mesh
    asset = asset_scene(size)
    obj = asset.objects[0]
    report = pk.check_asset(obj.mesh, obj.material)
    s3, rows3 = section(r, outdir, "asset", asset, ASSET_METHODS, r.render(asset, pk.Tessellated(0.5)), "Tessellated(0.5)")
    s3 = s3.replace("</h2>", "</h2><p><code>pk.load_mesh(\"rock.glb\")</code>, then <code>pk.check_asset(mesh, material)</code>:</p><pre>"
                    + html.escape(str(report)) + "</pre>", 1)
    # coarse + fine: the asset under a coarse mesh displaced at its vertices, at three densities
    s4, rows4 = section(r, outdir, "hybrid", asset, HYBRID_METHODS, pk.oracle.hits(asset), "the float64 oracle")
    s4 = s4.replace(">hybrid</h2>", ">coarse + fine</h2><p>A coarse mesh displaced at its vertices (16, 4 and 1 texels a vertex) "
                    "and Exact marching the rest: <code>pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=4), "
                    "fine=pk.Exact())</code> (docs/hybrid.md; the full sweep with JOD in motion: "
                    "docs/tables/hybrid.md). Its points are in the chart above.</p>", 1)
    # speed against accuracy, every scene's methods, at the top: plotly.js beside the page
    parts = head + [chart(rows + rows2 + rows3 + rows4, outdir), wild_summary(), s1, s2, s3, s4]
    # pk.choose on one built-in map (cached after the first run)
    ch = pk.choose(heights=pk.textures.bricks(128), angles=(40.0, 75.0), resolution=96, max_uv_error=0.5, rounds=3,
                   methods=["SteepParallax", "POM", "Relief", "ConeStep", "Exact"])
    parts.append("<h2 id=choose>Which method should I ship?</h2><p><code>pk.choose(heights=pk.textures.bricks(128), "
                 "angles=(40, 75), resolution=96, max_uv_error=0.5)</code></p><pre>" + html.escape(str(ch)) + "</pre>")
    # the same scenes, live: the notebook widget
    parts.append("<h2>Explore these scenes live</h2><p>In a notebook (JupyterLab, Notebook 7, VS Code, Colab; the "
                 "<code>notebooks</code> extra), orbit either scene, switch methods and views, and compare with the "
                 "reference:</p><pre>" + html.escape(EXPLORE_COMMAND) + "</pre>")
    # in motion: loops of the plane, the torus and a pull-back into minification, each beside
    # its motion table
    from . import loops
    small = 96
    parts.append(loops.section(r, outdir, [
        ("plane", planar_scene(small), "orbit", [pk.POM(), pk.Exact(), pk.presets.playcanvas_pom()]),
        ("torus", curved_scene(small), "orbit", [pk.Prism(), pk.NCS(), pk.Prism(exact=True)]),
        ("plane", planar_scene(small), "pullback", [pk.POM(mip_filtering=True), pk.POM(), pk.Exact()]),
    ]).replace("<h2>", "<h2 id=motion>", 1))
    # the LOD, at a glance
    pom = r.render(planar, pk.POM(mip_filtering=True))
    levels = float(np.log2(256))
    _save(lod_overlay(pom, levels), outdir / "lod.png")
    _save(lod_legend(levels), outdir / "lod_legend.png")
    parts.append('<h2>Level of detail</h2><p>POM(mip_filtering=True): the mip level each pixel marched '
                 '(blue: level 0, red: the coarsest).</p><img src="lod.png"><br><img src="lod_legend.png">')
    (outdir / "index.html").write_text(f"<!doctype html><meta charset=utf-8><title>pomkit demo</title><link rel=icon href='data:,'><style>{CSS}</style>"
                                       + "".join(parts) + f"<p><small>made in {time.perf_counter() - t0:.1f} s</small></p>")
    return outdir / "index.html"
