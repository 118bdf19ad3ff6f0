"""The sweep's table and the Pareto front (speed itself is measured in benchmarks, not here)."""

import pomkit as pk
from pomkit.bench import pareto_front, sweep, variants


def test_pareto_front():
    pts = [(1, 10), (2, 5), (3, 7), (4, 1), (5, 1), (0.5, 20)]
    assert sorted(pareto_front(pts)) == [0, 1, 3, 5]


def test_sweep_rows(tmp_path):
    methods = variants(pk.POM, max_steps=[8, 16], shadows=["none"]) + [pk.Exact()]
    rows = sweep(methods, scenes=["pyramids"], angles=[30.0, 70.0], settings=dict(size=32), repeats=1,
                 csv_path=str(tmp_path / "t.csv"), progress=False)
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    assert len(rows) == 6
    need = {"method", "params", "scene", "angle", "gpu_ms", "gpu_ms_min", "gpu_ms_max", "ms_per_mpix", "mean_steps",
            "uv_p50", "uv_p95", "uv_p99", "mask_iou", "flip"}
    assert need <= set(rows[0])
    exact = [x for x in rows if x["method"] == "Exact"]
    assert all(x["uv_p99"] < 0.1 for x in exact)
    assert (tmp_path / "t.csv").read_text().count("\n") == 7


def test_presets_are_valid_methods():
    r = pk.Renderer()
    from conftest import plane_scene
    s = plane_scene(pk.textures.bricks(64), size=32)
    for name, fn in pk.presets.ALL_PRESETS.items():
        assert r.render(s, fn()).mask.any(), name
