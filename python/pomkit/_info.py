"""What a user pastes into a bug report, and what every bench record carries so that results
from different machines can be pooled: the adapters, the one in use, its backend and driver,
the features pomkit detected and the fallback taken for each missing one, the limits that matter,
and pomkit's, wgpu's, Python's and numpy's versions (`python -m pomkit info`)."""

from __future__ import annotations

import platform
import sys
from typing import Any, Optional

__all__ = ["info", "machine", "format_info"]


def info(adapter: Optional[str | int] = None, probe: bool = False) -> dict[str, Any]:
    """Everything `python -m pomkit info` prints, as a dict. `probe`: also time "auto"'s probe
    (POM on a plane at 512² in both pipelines: a second or two) and report its medians."""
    import numpy as np

    from ._core import __version__
    from ._render import Renderer, adapters
    r = Renderer(adapter)
    i = r.info
    return dict(
        pomkit=__version__, wgpu=i["wgpu_version"], python=sys.version.split()[0], numpy=np.__version__,
        os=f"{platform.system()} {platform.release()} {platform.machine()}",
        adapters=adapters(), adapter=i["name"], backend=i["backend"], device_type=i["device_type"],
        driver=i["driver"], features=[dict(feature=f, present=p, fallback=fb) for f, p, fb in i["features"]],
        limits=dict(max_texture_dimension_2d=i["max_texture_dimension_2d"], max_buffer_size=i["max_buffer_size"],
                    max_storage_buffer_binding_size=i["max_storage_buffer_binding_size"],
                    max_storage_buffers_per_shader_stage=i["max_storage_buffers_per_shader_stage"]),
        pipeline=dict(auto=i["auto_pipeline"], probe_ms=_probe(r) if probe else None),
    )


def _probe(r: Any) -> Optional[dict[str, float]]:
    """The probe's medians, or None where the adapter has no compute pipeline."""
    try:
        raster, compute = r._r.pipeline_probe()
    except ValueError:
        return None
    return dict(raster=raster, compute=compute)


def machine() -> dict[str, str]:
    """The fields every bench CSV row and goals.txt records: adapter, backend, driver and versions."""
    i = info()
    return {"adapter": i["adapter"], "backend": i["backend"], "driver": i["driver"], "pomkit": i["pomkit"],
            "wgpu": i["wgpu"], "os": i["os"]}


def format_info(d: dict[str, Any]) -> str:
    lines = [f"pomkit {d['pomkit']} (wgpu {d['wgpu']}), Python {d['python']}, numpy {d['numpy']}, {d['os']}", "",
             "adapters:"]
    for k, a in enumerate(d["adapters"]):
        lines.append(f"  {k}: {a['name']} ({a['backend']}, {a['device_type']}), driver {a['driver']}")
    lines += ["", f"using: {d['adapter']} ({d['backend']}, {d['device_type']}), driver {d['driver']}", "", "features:"]
    for f in d["features"]:
        mark = "yes" if f["present"] else "NO "
        lines.append(f"  {mark} {f['feature']}" + ("" if f["present"] else f"  -> fallback: {f['fallback']}"))
    lines += ["", "limits:"] + [f"  {k}: {v}" for k, v in d["limits"].items()]
    p = d["pipeline"]
    lines += ["", f"pipeline: \"auto\" draws the per-pixel methods with the {p['auto']} pipeline"]
    if p["probe_ms"]:
        t = p["probe_ms"]
        lines.append(f"  probe (POM, plane, 512²): raster {t['raster']:.3f} ms, compute {t['compute']:.3f} ms")
    return "\n".join(lines)
