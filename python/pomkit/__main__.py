"""Command line: `python -m pomkit demo [--out DIR]`, `bench [--quick]`, `choose HEIGHTS... --max-uv-error E`
and `info`."""

from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m pomkit", description=__doc__)
    sub = p.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("demo", help="render the gallery and the comparison report into a folder")
    d.add_argument("--out", default="pomkit-out", help="output folder (default ./pomkit-out)")
    d.add_argument("--size", type=int, default=256, help="image size in pixels")
    b = sub.add_parser("bench", help="speed-versus-accuracy sweep: table and charts")
    b.add_argument("--out", default="pomkit-out/bench")
    b.add_argument("--quick", action="store_true", help="a small sweep (minutes)")
    b.add_argument("--spp", type=int, default=1, help="samples per pixel of the Pareto sweep's frames (a square: 1, 4, 16...)")
    i = sub.add_parser("info", help="adapters, backend, driver, features and fallbacks, limits, versions (paste it into a bug report)")
    i.add_argument("--adapter", default=None, help="an adapter index, name or backend (default: the best)")
    c = sub.add_parser("choose", help="the cheapest method and settings within an error bound, for your height maps and angles")
    c.add_argument("heights", nargs="+", help="height map files (PNG/TIFF/EXR/.npy)")
    c.add_argument("--angles", default="30:80", help="view angles in degrees: 'a:b' (3 angles from a to b), 'a:b:n' or 'a,b,c'")
    c.add_argument("--resolution", type=int, default=256)
    c.add_argument("--max-uv-error", type=float, default=None, help="bound on the worst uv p95 (texels)")
    c.add_argument("--max-flip", type=float, default=None, help="bound on the worst FLIP (against the mesh)")
    c.add_argument("--cost", choices=("gpu_ms", "fetches"), default="gpu_ms")
    c.add_argument("--methods", default=None, help="comma-separated families (default: all)")
    c.add_argument("--out", default="pomkit-out/choose")
    a = p.parse_args(argv)
    if a.cmd == "demo":
        from .apps.demo import run_demo
        run_demo(a.out, a.size)
    elif a.cmd == "bench":
        from .apps import pareto
        missing = pareto.missing_extra()
        if missing:
            print(f"python -m pomkit bench needs {', '.join(missing)}: pip install pomkit[bench]", file=sys.stderr)
            return 2
        pareto.run_bench(a.out, quick=a.quick, spp=a.spp)
    elif a.cmd == "choose":
        from ._choose import choose, report, parse_angles
        try:
            ch = choose(a.heights, angles=parse_angles(a.angles), resolution=a.resolution, max_uv_error=a.max_uv_error,
                        max_flip=a.max_flip, cost=a.cost, methods=a.methods.split(",") if a.methods else None)
        except (ValueError, TypeError, OSError) as e:
            print(f"python -m pomkit choose: {e}", file=sys.stderr)
            return 2
        print(ch)
        report(ch, a.out)
        print(f"wrote {a.out}/choice.md, choice.png, choice.json ({ch.seconds:.1f} s)")
    elif a.cmd == "info":
        from ._info import format_info, info
        print(format_info(info(a.adapter, probe=True)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
