"""Instructions a frame runs in lavapipe's JIT-compiled shaders, counted by valgrind's callgrind:
a cost that does not move with the machine's load, for comparing two versions of a shader when
timing on this machine is too noisy to tell them apart (docs/cost_journal_2026.md, "The children as unorm8
codes").

    python tools/jit_instructions.py gravel exact pom flat [--angle 70] [--size 256] [--frames 2]

Each method runs in its own process under `valgrind --tool=callgrind --smc-check=all` with
LP_NUM_THREADS=0 (lavapipe rasterises on the calling thread); the instructions of the code that
has no file (the shaders LLVM compiled at run time) are summed and divided by the frames
rendered. The count is deterministic for a build, a scene and a CPU's vector width, and it is
instructions, not cycles: a gather or a spill counts one. It also holds the compute passes that
build the map's pyramids (once a process, spread over the frames), so compare methods by their
count above Flat's in the same build. Needs valgrind (Debian's `valgrind`)
and the installed package; the map is one of `pk.textures.real`'s, or "cobblestones".
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile


def _child(map_name: str, method: str, angle: float, size: int, frames: int) -> None:
    import pomkit as pk
    from pomkit.bench import plane_scene
    h = pk.textures.cobblestones(512, cells=8) if map_name == "cobblestones" else pk.textures.real(map_name, 512)
    m = {"pom": pk.POM(shadows="none"), "exact": pk.Exact(), "flat": pk.Flat(), "cone_step": pk.ConeStep(),
         "relief": pk.Relief()}[method]
    sc = plane_scene(h, angle, size)
    r = pk.Renderer()
    for _ in range(frames):
        r.render(sc, m, aovs=("color",))


def count(map_name: str, method: str, angle: float, size: int, frames: int) -> float:
    """JIT instructions per frame (millions)."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cg.out")
        env = dict(os.environ, LP_NUM_THREADS="0")
        subprocess.run(["valgrind", "--tool=callgrind", "--smc-check=all", f"--callgrind-out-file={out}",
                        sys.executable, __file__, "--child", map_name, method, "--angle", str(angle),
                        "--size", str(size), "--frames", str(frames)],
                       env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        text = subprocess.run(["callgrind_annotate", "--threshold=100", out], check=True, capture_output=True,
                              text=True).stdout
    total = sum(int(m.group(1).replace(",", "")) for m in re.finditer(r"^\s*([\d,]+) .*\[\?\?\?\]\s*$", text, re.M))
    return total / frames / 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("map")
    ap.add_argument("methods", nargs="+")
    ap.add_argument("--angle", type=float, default=70.0)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--frames", type=int, default=2)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        _child(a.map, a.methods[0], a.angle, a.size, a.frames)
        return
    got = {m: count(a.map, m, a.angle, a.size, a.frames) for m in a.methods}
    for m, v in got.items():
        print(f"{a.map} {a.angle:g}° {a.size}²: {m} {v:.1f} M instructions a frame")
    if "flat" in got:
        for m, v in got.items():
            if m != "flat":
                print(f"  {m} above flat: {v - got['flat']:.1f} M")


if __name__ == "__main__":
    main()
