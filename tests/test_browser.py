"""The demo page and the explore widget in a real browser (issue 32): headless Chromium (Debian's
`chromium`, which setup.sh installs for the `browser` extra) driven by Playwright through
`executable_path`.

- The page loads with no console error, no failed request and no broken image; its chart is
  interactive (hovering a point shows its method and settings) and needs no CDN; the choose
  answer has no "nan"; its motion loops play (each video loads and its time moves on).
- The widget, served with a kernel by Voilà, turns a drag on its frame into a new frame.
"""

from __future__ import annotations

import contextlib
import functools
import http.server
import os
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

sync_api = pytest.importorskip("playwright.sync_api", reason="the [browser] extra installs Playwright")

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no system Chromium: scripts/setup.sh browser installs it")]


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        yield b
        b.close()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def _serve(root: Path):
    """An HTTP server over `root` on a free loopback port, for the test's lifetime."""
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    handler = functools.partial(Quiet, directory=str(root))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    t = threading.Thread(target=httpd.serve_forever, daemon=True)
    t.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()


class _Watch:
    """What a page reports while it loads: console errors, failed requests, error responses, and
    requests to anything but the page's own server."""

    def __init__(self, page, origin: str):
        self.errors: list[str] = []
        page.on("console", lambda m: self.errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
        page.on("pageerror", lambda e: self.errors.append(f"page error: {e}"))
        page.on("requestfailed", lambda r: self.errors.append(f"failed: {r.url} {r.failure}"))
        page.on("response", lambda r: self.errors.append(f"HTTP {r.status}: {r.url}") if r.status >= 400 else None)
        page.on("request", lambda r: None if r.url.startswith((origin, "data:", "blob:")) else
                self.errors.append(f"off-site request: {r.url}"))


@pytest.fixture(scope="module")
def demo_page(tmp_path_factory):
    from pomkit.apps import page
    out = tmp_path_factory.mktemp("demo")
    # a cache of its own for this page, restored after (set for good, it reached the notebooks
    # that run after the tests)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("POMKIT_CACHE", str(tmp_path_factory.mktemp("cache")))
        page.run_page(out, size=256)
    return out


def test_the_demo_page_loads_whole(browser, demo_page):
    with _serve(demo_page) as url:
        pg = browser.new_page(viewport={"width": 1400, "height": 1000})
        watch = _Watch(pg, url)
        pg.goto(url + "/index.html", wait_until="networkidle")
        assert not watch.errors, watch.errors
        broken = pg.evaluate("Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0)"
                             ".map(i => i.getAttribute('src'))")
        n_img = pg.evaluate("document.images.length")
        assert n_img > 35 and not broken, (n_img, broken)
        text = pg.inner_text("body")
        answer = text[text.index("Which method should I ship?"):]
        assert "nan" not in answer.lower().split(), answer[:400]
        assert "pk.explore(" in text
        # it fits the 1400-pixel window (no sideways scroll), says nothing meant for maintainers,
        # and keeps its legend in view
        width = pg.evaluate("document.documentElement.scrollWidth")
        assert width <= 1400, width
        assert "scripts/" not in text and "make_demo_refs" not in text
        pg.evaluate("window.scrollTo(0, document.body.scrollHeight / 2)")
        top = pg.locator("div.maplegend").bounding_box()
        assert top is not None and abs(top["y"]) < 2, top
        # a card opens its method's page; on every one the frame and maps load, within the window
        cards = pg.locator("a.card")
        assert cards.count() >= 30, cards.count()
        cards.nth(3).click()
        pg.wait_for_load_state("networkidle")
        pg.go_back(wait_until="networkidle")
        hrefs = pg.evaluate("Array.from(document.querySelectorAll('a.card')).map(a => a.getAttribute('href'))")
        for h in hrefs:
            pg.goto(url + "/" + h, wait_until="networkidle")
            n = pg.evaluate("document.images.length")
            bad = pg.evaluate("Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0).length")
            assert n >= 2 and not bad, (h, n, bad)
            assert pg.evaluate("document.documentElement.scrollWidth") <= 1400, h
        assert not watch.errors, watch.errors


def test_the_chart_is_readable_and_tells_each_point(browser, demo_page):
    from pomkit.apps import page
    with _serve(demo_page) as url:
        pg = browser.new_page(viewport={"width": 1400, "height": 1000})
        watch = _Watch(pg, url)
        pg.goto(url + "/index.html", wait_until="networkidle")
        pg.wait_for_selector("#pareto .scatterlayer .point")
        box = pg.locator("#pareto .main-svg").first.bounding_box()
        assert box["width"] >= 800, box  # not a thumbnail
        points = pg.locator("#pareto .scatterlayer .point")
        assert points.count() == len(page.PLANAR) + len(page.CURVED) + len(page.ASSET_METHODS) + len(page.HYBRID_METHODS)
        # hover each of a few points: its label names the method and its settings
        seen = []
        pg.locator("#pareto").scroll_into_view_if_needed()
        for i in (0, points.count() // 2, points.count() - 1):
            b = points.nth(i).bounding_box()
            pg.mouse.move(b["x"] + b["width"] / 2, b["y"] + b["height"] / 2)
            label = pg.locator("#pareto .hoverlayer .hovertext")
            label.first.wait_for(timeout=5000)
            t = label.first.text_content() or ""
            assert "GPU ms" in t and "uv p95" in t and "(" in t, t
            seen.append(t.split("(")[0].strip())
            pg.mouse.move(5, 5)
        assert len(set(seen)) == 3, seen
        assert not watch.errors, watch.errors


def test_the_motion_loops_play(browser, demo_page):
    """Each loop of the "In motion" section loads and advances once it is in view (Chromium
    holds muted autoplay videos off screen): a <video> (WebM) whose time moves on, in headless
    Chromium."""
    with _serve(demo_page) as url:
        pg = browser.new_page(viewport={"width": 1400, "height": 1000})
        watch = _Watch(pg, url)
        pg.goto(url + "/index.html", wait_until="networkidle")
        videos = pg.locator("video")
        assert videos.count() == 3, videos.count()
        for i in range(videos.count()):
            v = videos.nth(i)
            v.scroll_into_view_if_needed()
            # bounded: a video that has not loaded its first frame after 30 s fails the test
            # instead of hanging it (a stalled load is asked once more, with load())
            ready = v.evaluate("v => new Promise(ok => { if (v.readyState >= 2) return ok(true);"
                               " v.addEventListener('loadeddata', () => ok(true));"
                               " setTimeout(() => { if (v.readyState < 2) v.load(); }, 10000);"
                               " setTimeout(() => ok(v.readyState >= 2), 30000); })")
            assert ready, (i, "the loop did not load its first frame in 30 s")
            t0 = v.evaluate("v => v.currentTime")
            pg.wait_for_timeout(700)
            t1, paused, w, h = v.evaluate("v => [v.currentTime, v.paused, v.videoWidth, v.videoHeight]")
            assert t1 != t0 and not paused, (i, t0, t1, paused)
            assert w == 3 * h and h > 0, (w, h)
        assert not watch.errors, watch.errors


NOTEBOOK = """{"cells": [{"cell_type": "code", "execution_count": null, "metadata": {}, "outputs": [], "source": [
 "import pomkit as pk\\n", "from pomkit.apps.page import planar_scene\\n",
 "w = pk.explore(planar_scene(64), methods=['POM', 'Exact'], size=96)\\n", "w"]}],
 "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"}},
 "nbformat": 4, "nbformat_minor": 5}"""


@pytest.fixture(scope="module")
def voila(tmp_path_factory):
    """Voilà serving a notebook that shows pk.explore, with this interpreter's kernel."""
    pytest.importorskip("voila", reason="the [browser] extra installs Voilà")
    d = tmp_path_factory.mktemp("voila")
    (d / "explore.ipynb").write_text(NOTEBOOK)
    port = _free_port()
    log = open(d / "voila.log", "w")
    env = dict(os.environ, JUPYTER_PLATFORM_DIRS="1")
    proc = subprocess.Popen([sys.executable, "-m", "voila", "explore.ipynb", "--no-browser", f"--port={port}",
                             "--Voila.ip=127.0.0.1", "--ServerApp.token=", "--show_tracebacks=True"],
                            cwd=d, stdout=log, stderr=subprocess.STDOUT, env=env)
    url = f"http://127.0.0.1:{port}"
    deadline = time.time() + 60
    while time.time() < deadline:
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=1):
            break
        if proc.poll() is not None:
            break
        time.sleep(0.3)
    try:
        yield url, d / "voila.log"
    finally:
        proc.terminate()
        with contextlib.suppress(subprocess.TimeoutExpired):
            proc.wait(10)
        proc.kill()
        log.close()


def test_a_drag_on_the_widget_renders_a_new_frame(browser, voila):
    url, log = voila
    pg = browser.new_page(viewport={"width": 1200, "height": 900})
    watch = _Watch(pg, url)
    # offline: nothing but the local server answers (the widget must need no CDN)
    pg.route("**/*", lambda r: r.continue_() if r.request.url.startswith((url, "data:", "blob:")) else r.abort())
    pg.goto(url, wait_until="domcontentloaded", timeout=60_000)
    img = pg.locator(".pomkit-explore img")
    try:
        img.wait_for(timeout=90_000)
        pg.wait_for_function("() => { const i = document.querySelector('.pomkit-explore img');"
                             " return i && i.src.startsWith('blob:') && i.complete && i.naturalWidth > 0; }",
                             timeout=90_000)
    except Exception:
        raise AssertionError(f"the widget did not show a frame; Voilà's log:\n{log.read_text()[-3000:]}\n{watch.errors}")
    first = img.evaluate("i => i.src")
    stats0 = pg.locator(".pomkit-explore pre").inner_text()
    b = img.bounding_box()
    x, y = b["x"] + b["width"] / 2, b["y"] + b["height"] / 2
    pg.mouse.move(x, y)
    pg.mouse.down()
    for k in range(1, 6):
        pg.mouse.move(x + 12 * k, y + 3 * k)
        time.sleep(0.05)
    pg.mouse.up()
    pg.wait_for_function("s => { const i = document.querySelector('.pomkit-explore img'); return i.src !== s"
                         " && i.complete && i.naturalWidth > 0; }", arg=first, timeout=30_000)
    # the orbit moved: the stats the kernel sent back changed with it
    pg.wait_for_function("s => document.querySelector('.pomkit-explore pre').innerText !== s", arg=stats0,
                         timeout=30_000)
    # the one thing fetched from elsewhere is Voilà's own template's icon font (fontawesome from
    # a CDN), which the page does without; pomkit's widget asks for nothing off-site
    offsite = [e for e in watch.errors if e.startswith(("off-site", "failed")) and url not in e]
    assert all("fontawesome" in e for e in offsite), offsite
    # and every request to the server (the notebook, the kernel, the widget's module) succeeds.
    # A frame is shown from a blob: URL of the page's own origin, not a request to the server; a
    # frame's load is aborted when the next one replaces it mid-drag (net::ERR_ABORTED, seen once
    # in CI), and that is the widget keeping up, not a failure: the frames that stay are checked
    # above (loaded, with a width).
    server = [e for e in watch.errors if e.startswith(("failed", "HTTP")) and url in e
              and not e.startswith("failed: blob:")]
    assert not server, watch.errors
