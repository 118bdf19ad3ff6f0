"""Instructions the float64 oracle runs for a frame, counted by valgrind's callgrind: the cost of
tools/oracle_time.py's cases (the sphere and the torus against the plane, 4096² bricks) that does
not move with the machine's load, for comparing two builds when timing here is too noisy to
tell them apart (runs vary by up to 30%).

    python tools/oracle_instructions.py [hits|img|sharp|disk] [--spp 4] [--size 64] [plane sphere torus]

Each scene renders in its own process under `valgrind --tool=callgrind`, once at `size`² and
once at 4²; the difference is the frame's own cost (the map's pyramid, the scene's hash and the
process's start are in both). It is instructions, not cycles: a cache miss or a division counts
one, so the planar oracle, whose cost lies more in reading the map, runs faster beside the
curved one than these counts say. The map is written once to a temporary .npy, so that the
children do not build it under valgrind. The children run on one thread (rayon's and numpy's),
so that spinning idle threads add nothing. Needs valgrind (Debian's `valgrind`) and the installed
package.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def _child(case: str, name: str, spp: int, size: int, path: str) -> None:
    import numpy as np

    import oracle_time as ot
    import pomkit as pk
    ot._HM.append(np.load(path))
    s = ot.scene(name, ot.DISK if case == "disk" else ot.SHARP, 0.0 if case in ("hits", "img") else 0.1, size)
    if case == "hits":
        pk.oracle.hits(s)
    else:
        pk.oracle.image(s, spp=spp, shadows=case != "img", cache=False)


def count(case: str, name: str, spp: int, size: int, path: str) -> int:
    cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", sys.executable, __file__,
           "--child", case, name, str(spp), str(size), path]
    # one thread each for rayon and numpy: idle threads' spinning would add instructions that
    # vary from run to run (by 1-3%); with one, runs of one build count the same to 0.1%
    env = dict(os.environ, RAYON_NUM_THREADS="1", OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env).stderr
    m = re.search(r"Collected : (\d+)", out)
    if not m:
        raise RuntimeError(f"no count in valgrind's output:\n{out[-2000:]}")
    return int(m.group(1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", nargs="?", default="sharp", choices=["hits", "img", "sharp", "disk"])
    ap.add_argument("names", nargs="*", default=["plane", "sphere", "torus"])
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--size", type=int, default=64)
    a = ap.parse_args()
    import numpy as np

    import oracle_time as ot
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "bricks4096.npy")
        np.save(path, np.asarray(ot.height(), dtype=np.float32))
        net = {n: count(a.case, n, a.spp, a.size, path) - count(a.case, n, a.spp, 4, path) for n in a.names}
    row = "  ".join(f"{n} {v / 1e6:.0f}M" for n, v in net.items())
    ratios = "  ".join(f"{n}/plane {net[n] / net['plane']:.2f}" for n in net if n != "plane" and "plane" in net)
    print(f"{a.case} spp {a.spp} {a.size}²: {row}  {ratios}", flush=True)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        _child(sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6])
    else:
        main()
