#!/usr/bin/env python
"""The cost of the same frames at two commits, built side by side, in one command:

    .venv/bin/python tools/cost_history.py c29048d HEAD [--size 512] [--runs 3] [--rounds 7]

Each commit is checked out into target/history/<sha>/src (a `git worktree`), built there with
maturin into target/history/<sha>/wheel (the cargo target dir is this clone's `target/`, so
dependencies built once are reused), and unpacked into target/history/<sha>/py. The timing runs
in child processes, alternating A, B, A, B... (`--runs` each), so that drift of a noisy machine
falls on both. Each child times, interleaved after a warm-up, the default frame (every AOV) of
Flat, Parallax, POM, Relief (level 0 where the commit has `mip_filtering`) and Exact on 512²
bricks at 60°, and Flat with colour alone where the commit can ask for it (`aovs=`). GPU ms
come from timestamp queries (`Frame.time_ms`). The table (markdown) goes to stdout and to
target/history/<A>-<B>.md: per method the range of the runs' medians and the change of the
medians' median.

Only the public API both commits share is used, so any two commits since the first round work.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, sys, inspect
import numpy as np
import pomkit as pk
size, rounds = int(sys.argv[1]), int(sys.argv[2])
t = np.radians(60.0)
try:
    from pomkit.textures import bricks
except ImportError:
    bricks = pk.textures.bricks
sc = pk.Scene(mesh=pk.Mesh.plane(2.0), material=pk.Material(bricks(512), depth=0.08, tiling=1.0),
              camera=pk.Camera.look_at(eye=(0.0, 1.6 * np.cos(t), 1.6 * np.sin(t)), target=(0, 0, 0), up=(0, 0, -1),
                                       fov_y=40.0, width=size, height=size),
              lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0)])
def make(cls, **kw):
    try:
        return cls(mip_filtering=False, **kw)
    except TypeError:
        return cls(**kw)
methods = {"Flat": pk.Flat(), "Parallax (level 0)": make(pk.Parallax), "POM (level 0, no shadows)": make(pk.POM, shadows="none"),
           "Relief (level 0)": make(pk.Relief), "Exact": pk.Exact()}
r = pk.Renderer()
runs = [(k, m, None) for k, m in methods.items()]
if "aovs" in inspect.signature(r.render).parameters:
    runs.append(("Flat, colour alone", pk.Flat(), ("color",)))
def one(m, aovs):
    f = r.render(sc, m) if aovs is None else r.render(sc, m, aovs=aovs)
    return f.time_ms
for k, m, a in runs:
    one(m, a); one(m, a)
out = {k: [] for k, _, _ in runs}
for _ in range(rounds):
    for k, m, a in runs:
        out[k].append(one(m, a))
print(json.dumps({k: float(np.median(v)) for k, v in out.items()}))
"""


def sh(cmd: list[str], **kw) -> str:
    return subprocess.run(cmd, check=True, text=True, capture_output=True, **kw).stdout.strip()


def build(rev: str, python: str) -> tuple[str, Path]:
    sha = sh(["git", "-C", str(ROOT), "rev-parse", "--short", rev])
    home = ROOT / "target" / "history" / sha
    py = home / "py"
    if (py / ".built").exists():
        print(f"{rev} ({sha}): built before, {py}", file=sys.stderr)
        return sha, py
    src = home / "src"
    if not src.exists():
        home.mkdir(parents=True, exist_ok=True)
        sh(["git", "-C", str(ROOT), "worktree", "add", "--force", "--detach", str(src), sha])
    print(f"{rev} ({sha}): building (maturin, release) ...", file=sys.stderr)
    wheels = home / "wheel"
    shutil.rmtree(wheels, ignore_errors=True)
    env = dict(os.environ, CARGO_TARGET_DIR=str(ROOT / "target"))
    subprocess.run([python, "-m", "maturin", "build", "--release", "--quiet", "-o", str(wheels)], cwd=src, env=env, check=True)
    shutil.rmtree(py, ignore_errors=True)
    whl = sorted(wheels.glob("*.whl"))[-1]
    subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", "--target", str(py), str(whl)], check=True)
    (py / ".built").write_text(sha)
    return sha, py


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a", help="the older commit (any git revision)")
    ap.add_argument("b", nargs="?", default="HEAD", help="the newer commit (default HEAD)")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--runs", type=int, default=3, help="child processes per commit, alternating")
    ap.add_argument("--rounds", type=int, default=7, help="interleaved rounds per child")
    args = ap.parse_args()
    python = sys.executable
    builds = [build(args.a, python), build(args.b, python)]
    env = dict(os.environ)
    env.setdefault("XDG_RUNTIME_DIR", f"/tmp/pomkit-xdg-{os.getuid()}")
    Path(env["XDG_RUNTIME_DIR"]).mkdir(mode=0o700, exist_ok=True)
    results: dict[str, list[dict]] = {sha: [] for sha, _ in builds}
    for i in range(args.runs):
        for sha, py in builds:
            e = dict(env, PYTHONPATH=str(py))
            out = subprocess.run([python, "-c", CHILD, str(args.size), str(args.rounds)], env=e, check=True, text=True,
                                 capture_output=True, cwd="/").stdout
            results[sha].append(json.loads(out.strip().splitlines()[-1]))
            print(f"  run {i + 1}/{args.runs} {sha} done", file=sys.stderr)
    (a, _), (b, _) = builds
    keys = list(results[b][0]) + [k for k in results[a][0] if k not in results[b][0]]
    lines = [f"GPU ms per {args.size}² frame, bricks 60°, default AOVs (every one) unless named; "
             f"range of {args.runs} runs' medians ({args.rounds} interleaved rounds each)", "",
             f"| | {a} | {b} | change |", "|---|---|---|---|"]

    def cell(sha: str, k: str) -> tuple[str, float | None]:
        v = [r[k] for r in results[sha] if k in r]
        if not v:
            return "-", None
        return f"{min(v):.2f}–{max(v):.2f}", sorted(v)[len(v) // 2]

    for k in keys:
        ca, ma = cell(a, k)
        cb, mb = cell(b, k)
        change = f"{(mb / ma - 1) * 100:+.0f} %" if ma and mb else "-"
        lines.append(f"| {k} | {ca} | {cb} | {change} |")
    text = "\n".join(lines)
    print(text)
    (ROOT / "target" / "history" / f"{a}-{b}.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
