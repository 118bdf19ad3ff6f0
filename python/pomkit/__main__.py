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
    i = sub.add_parser("info", help="adapters, backend, driver, features and fallbacks, limits, versions (paste it into a bug report)")
    i.add_argument("--adapter", default=None, help="an adapter index, name or backend (default: the best)")
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
        from ._info import format_info, info
        print(format_info(info(a.adapter)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
