"""Command line: `python -m pomkit demo [--out DIR]` and `python -m pomkit bench [--quick]`."""

from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m pomkit", description=__doc__)
    sub = p.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("demo", help="render the gallery and the comparison report into a folder")
    d.add_argument("--out", default="pomkit-out", help="output folder (default ./pomkit-out)")
    d.add_argument("--size", type=int, default=384, help="image size in pixels")
    b = sub.add_parser("bench", help="speed-versus-accuracy sweep: table and charts")
    b.add_argument("--out", default="pomkit-out/bench")
    b.add_argument("--quick", action="store_true", help="a small sweep (minutes)")
    sub.add_parser("info", help="print the adapters and the one pomkit would use")
    t = sub.add_parser("tables", help="regenerate the measured tables in docs/tables/")
    t.add_argument("--out", default="docs/tables")
    a = p.parse_args(argv)
    if a.cmd == "demo":
        from .apps.demo import run_demo
        run_demo(a.out, a.size)
    elif a.cmd == "bench":
        from .apps import bench
        missing = bench.missing_extra()
        if missing:
            print(f"python -m pomkit bench needs {', '.join(missing)}: pip install pomkit[bench]", file=sys.stderr)
            return 2
        bench.run_bench(a.out, quick=a.quick)
    elif a.cmd == "tables":
        from .apps.tables import run_tables
        run_tables(a.out)
    elif a.cmd == "info":
        import pomkit as pk
        for i, ad in enumerate(pk.adapters()):
            print(i, ad)
        print("using:", pk.Renderer())
    return 0


if __name__ == "__main__":
    sys.exit(main())
