"""CPU milliseconds a frame with lavapipe rasterising on the calling thread: a time that moves
little with the machine's load, for comparing two versions of a method when GPU timing on this
machine is too noisy (docs/cost_journal_2026.md, "Instructions are not time").

    python tools/cpu_time.py "sphere 64x32 spikes d0.1 x1" prism grid pom flat [--frames 9]

The scene is one of `tools/suite.py`'s held-out curved scenes (`heldout_curved_suite`), or a
planar one named "<map> <angle>" from `heldout_planar_suite` (e.g. "gravel 70°"). One child
process runs with LP_NUM_THREADS=0, renders each method twice to warm up, then `--frames` times
in interleaved rounds, and reports each method's median process CPU time a frame. Unlike
tools/jit_instructions.py's count, it sees what an instruction costs: a square root or a
division in a loop, a gather's latency. Only meaningful on lavapipe (llvmpipe).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

METHODS = ("prism", "prism_full", "prism_exact", "grid", "fan", "pom", "flat", "exact", "ncs")


def _child(scene_name: str, methods: list[str], frames: int) -> None:
    import time

    import numpy as np
    import pomkit as pk
    from suite import heldout_curved_suite, heldout_planar_suite

    scenes = dict(heldout_curved_suite(256))
    if scene_name not in scenes:
        scenes = dict(heldout_planar_suite(256))
    sc = scenes[scene_name]
    make = {"prism": lambda: pk.Prism(shadows="none"), "prism_full": lambda: pk.Prism(shadows="none", tight=False),
            "prism_exact": lambda: pk.Prism(shadows="none", exact=True),
            "grid": lambda: pk.Tessellated(1.0, shadows="none", pattern="grid"),
            "fan": lambda: pk.Tessellated(1.0, shadows="none", pattern="fan"), "pom": lambda: pk.POM(shadows="none"),
            "flat": pk.Flat, "exact": pk.Exact, "ncs": lambda: pk.NCS(shadows="none")}
    ms = {n: make[n]() for n in methods}
    r = pk.Renderer()
    for m in ms.values():
        for _ in range(2):
            r.render(sc, m, aovs=("color",))
    times: dict[str, list[float]] = {n: [] for n in ms}
    for _ in range(frames):
        for n, m in ms.items():
            t0 = time.process_time()
            r.render(sc, m, aovs=("color",))
            times[n].append((time.process_time() - t0) * 1000.0)
    print(json.dumps({n: float(np.median(t)) for n, t in times.items()}))


def cpu_ms(scene_name: str, methods: list[str], frames: int) -> dict[str, float]:
    """Median CPU ms a frame of each method, in one child process with LP_NUM_THREADS=0."""
    env = dict(os.environ, LP_NUM_THREADS="0")
    out = subprocess.run([sys.executable, __file__, "--child", scene_name, *methods, "--frames", str(frames)],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("methods", nargs="+", choices=METHODS)
    ap.add_argument("--frames", type=int, default=9)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        _child(a.scene, a.methods, a.frames)
        return
    t = cpu_ms(a.scene, a.methods, a.frames)
    for n, v in t.items():
        print(f"{a.scene}  {n:12s} {v:8.2f} ms CPU a frame")
    if len(t) > 1:
        first = a.methods[0]
        print("  " + ", ".join(f"{first}/{n} {t[first] / t[n]:.3f}" for n in a.methods[1:]))


if __name__ == "__main__":
    main()
