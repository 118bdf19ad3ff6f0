"""The sweep's table and the Pareto front (speed itself is measured in benchmarks, not here)."""

import numpy as np
import pytest

import pomkit as pk
from pomkit.bench import SweepSettings, pareto_front, sweep, variants


def test_pareto_front():
    pts = [(1, 10), (2, 5), (3, 7), (4, 1), (5, 1), (0.5, 20)]
    assert sorted(pareto_front(pts)) == [0, 1, 3, 5]


def test_sweep_rows(tmp_path):
    methods = variants(pk.POM, max_steps=[8, 16], shadows=["none"]) + [pk.Exact()]
    rows = sweep(methods, maps=["pyramids"], angles=[30.0, 70.0], settings=SweepSettings(size=32), repeats=2,
                 csv_path=str(tmp_path / "t.csv"), progress=False)
    assert len(rows) == 6
    need = {"method", "label", "safety", "scene", "angle", "gpu_ms", "gpu_ms_p25", "gpu_ms_p75", "march_ms", "call_ms",
            "repeats", "ms_per_mpix", "mean_steps", "fetches_mean", "fetches_p99", "bytes_mean", "uv_p50", "uv_p95", "uv_p99", "mask_iou", "flip"}
    assert need <= set(rows[0])
    for x in rows:
        # every row is labelled, without stray spaces (the quick bench once wrote '' and 'Exact ')
        assert x["method"] and x["method"] == x["method"].strip() and x["label"] == x["label"].strip()
        assert x["gpu_ms_p25"] <= x["gpu_ms"] <= x["gpu_ms_p75"] and x["repeats"] >= 1
    assert {x["label"] for x in rows} == {"POM(shadows='none', max_steps=8)", "POM(shadows='none', max_steps=16)", "Exact()"}
    assert {x["safety"] for x in rows if x["method"] == "Exact"} == {"safe"}
    assert {x["safety"] for x in rows if x["method"] == "POM"} == {"approximate"}
    exact = [x for x in rows if x["method"] == "Exact"]
    assert all(x["uv_p99"] < 0.1 for x in exact)
    assert (tmp_path / "t.csv").read_text().count("\n") == 7
    # the fetch counts follow the settings: twice the layers, more fetches (same scene and angle)
    for a in (30.0, 70.0):
        f8, f16 = (next(x["fetches_mean"] for x in rows if x["angle"] == a and f"max_steps={n})" in x["label"]) for n in (8, 16))
        assert 0 < f8 < f16
        assert all(x["bytes_mean"] >= 4 * x["fetches_mean"] for x in rows)


def test_sweep_settings_are_checked_by_field():
    assert SweepSettings() == SweepSettings(size=256, depth=0.08, tiling=1.0, spp=64, frame_spp=1, flip=True)
    s = SweepSettings(size=np.int64(32), depth=np.float32(0.5), flip=np.bool_(False))
    assert type(s.size) is int and type(s.depth) is float and s.flip is False
    for kw, err, field in [(dict(size=0), pk.ArgumentError, "size"), (dict(size="32"), pk.ArgumentTypeError, "size"),
                           (dict(depth=-0.1), pk.ArgumentError, "depth"), (dict(tiling=0.0), pk.ArgumentError, "tiling"),
                           (dict(spp=8), pk.ArgumentError, "spp"), (dict(frame_spp=2), pk.ArgumentError, "frame_spp"),
                           (dict(frame_spp=4.0), pk.ArgumentTypeError, "frame_spp"), (dict(flip=1), pk.ArgumentTypeError, "flip")]:
        with pytest.raises(err, match=f"^{field}:"):
            SweepSettings(**kw)
    with pytest.raises(pk.ArgumentTypeError, match="settings: expected a pomkit.bench.SweepSettings"):
        sweep([pk.Exact()], settings=[("size", 32)], progress=False)
    with pytest.raises(pk.ArgumentTypeError, match=r"settings: .*write pk.bench.SweepSettings\(\*\*\{'size': 32\}\)"):
        sweep([pk.Exact()], settings=dict(size=32), progress=False)
    with pytest.raises(pk.ArgumentError, match="reference: must be 'oracle', 'tessellated' or 'mitsuba', got 'exact'"):
        sweep([pk.Exact()], reference="exact", progress=False)
    with pytest.raises(TypeError, match="scenes"):
        sweep([pk.Exact()], scenes=["bricks"], progress=False)  # type: ignore[call-arg]
    with pytest.raises(pk.ArgumentTypeError, match="methods: .*\\(name, method\\) pairs"):
        sweep(["POM"], progress=False)
    with pytest.raises(pk.ArgumentError, match="name must be a non-empty string"):
        sweep([("", pk.POM())], progress=False)


def test_sweep_names_rows_by_pairs():
    """A (name, method) pair's name is its rows' method and label."""
    bevy = pk.presets.bevy_pom()
    rows = sweep([("bevy_pom", bevy), bevy], maps=["pyramids"], angles=[60.0], settings=SweepSettings(size=16, flip=False),
                 repeats=1, progress=False)
    assert [(x["method"], x["label"]) for x in rows] == [("bevy_pom", "bevy_pom"), ("POM", pk.bench.label(bevy))]
    assert rows[0]["size"] == 16 and rows[0]["uv_p95"] == rows[1]["uv_p95"]


def test_presets_are_valid_methods():
    r = pk.Renderer()
    from conftest import plane_scene
    s = plane_scene(pk.textures.bricks(64), size=32)
    for name, fn in pk.presets.ALL_PRESETS.items():
        assert r.render(s, fn()).mask.any(), name


def _deterministic(rows):
    from pomkit.bench import TIMING_COLUMNS
    return [{k: v for k, v in r.items() if k not in TIMING_COLUMNS} for r in rows]


def test_sweep_on_a_dask_cluster_equals_the_local_sweep():
    """Any concurrent.futures.Executor runs the sweep; here Dask's LocalCluster with two worker
    processes, each opening its own device. The rows equal a local sweep's, timings aside."""
    import math

    distributed = __import__("pytest").importorskip("distributed", reason="the [distributed] extra")
    methods = [pk.POM(shadows="none", max_steps=16), pk.Relief(), pk.Exact(), pk.Custom(
        wgsl=(__import__("pathlib").Path(pk.__file__).parent / "wgsl" / "steep_custom.wgsl").read_text(),
        name="steep_custom", params={"steps": 16.0})]
    kw = dict(maps=["bricks", "spikes"], angles=[40.0, 75.0], settings=SweepSettings(size=32, flip=False), repeats=1,
              progress=False)
    local = _deterministic(sweep(methods, **kw))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
            distributed.Client(cl) as client:
        remote = _deterministic(sweep(methods, executor=client.get_executor(), **kw))
        assert len(client.scheduler_info()["workers"]) == 2
    assert len(local) == len(remote) == 16
    for a, b in zip(local, remote):
        assert a.keys() == b.keys()
        for k in a:
            same = (a[k] == b[k]) or (isinstance(a[k], float) and math.isnan(a[k]) and math.isnan(b[k]))
            assert same, (k, a[k], b[k])


def test_bench_without_its_extra_names_the_extra():
    """`python -m pomkit bench` without matplotlib/pandas/tqdm: one line naming the extra, exit 2."""
    import subprocess
    import sys
    code = (
        "import sys, importlib.abc\n"
        "class Block(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name.split('.')[0] in ('matplotlib', 'pandas', 'tqdm'): raise ImportError(name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "import importlib.util\n"
        "importlib.util.find_spec = lambda n, *a: None if n in ('matplotlib', 'pandas', 'tqdm') else 1\n"
        "from pomkit.__main__ import main\n"
        "sys.exit(main(['bench', '--quick']))\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "pip install pomkit[bench]" in lines[0], p.stderr


def test_sweep_shadow_columns():
    """The shadow error against the oracle's visibility is a column: NaN without shadows, the
    exact light walk's IoU near 1 with them."""
    rows = sweep([pk.Exact(), pk.Exact(shadows="exact"), pk.POM(shadows="hard")], maps=["cobblestones"],
                 angles=[60.0], settings=SweepSettings(size=64), repeats=1, progress=False)
    by = {x["label"]: x for x in rows}
    assert np.isnan(by["Exact()"]["shadow_iou"])
    assert by["Exact(shadows='exact')"]["shadow_iou"] > 0.95
    assert 0.5 < by["POM(shadows='hard')"]["shadow_iou"] <= 1.0
    assert by["POM(shadows='hard')"]["shadow_vis_error"] >= 0.0


def test_regions_split_interior_and_outline():
    from pomkit import metrics
    mask = np.zeros((20, 30), bool)
    mask[5:15, 0:20] = True  # the left edge is the frame's border, not an outline
    f = pk.Frame._of({"mask": mask})
    reg = metrics.regions(f, f, band=2)
    assert not (reg["interior"] & reg["silhouette"]).any()
    assert reg["interior"][10, 1] and reg["interior"][10, 16] and not reg["interior"][10, 18]
    assert reg["silhouette"][4, 10] and reg["silhouette"][10, 21] and not reg["silhouette"][10, 25]
    assert not reg["silhouette"][10, 0] and reg["interior"].sum() == 4 * 17
