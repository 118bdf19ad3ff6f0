"""The README's Layout names every folder of src/, every WGSL module of shaders/, every module
and folder of python/pomkit/, every Rust file of the core's folders and every page of docs/, so
that a newcomer's map of the tree is the tree."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _layout() -> str:
    text = (ROOT / "README.md").read_text()
    m = re.search(r"## Layout\n\n```\n(.*?)```", text, re.S)
    assert m, "README.md has no Layout block"
    return m.group(1)


def _named(layout: str, name: str) -> bool:
    return re.search(rf"(?<![\w.]){re.escape(name)}(?![\w])", layout) is not None


def test_the_layout_names_every_folder_and_module():
    layout = _layout()
    missing = []
    for d in sorted(p for p in (ROOT / "src").iterdir() if p.is_dir()):
        missing += [] if _named(layout, d.name + "/") else [f"src/{d.name}/"]
    for d in sorted(p for p in (ROOT / "src" / "methods").iterdir() if p.is_dir()):
        missing += [] if _named(layout, d.name + "/") else [f"src/methods/{d.name}/"]
    for f in sorted((ROOT / "shaders").glob("*.wgsl")):
        missing += [] if _named(layout, f.stem) else [f"shaders/{f.name}"]
    for p in sorted((ROOT / "python" / "pomkit").iterdir()):
        if p.name.startswith("__") or p.suffix in (".so", ".typed") or p.name == "_core.pyi":
            continue
        stem = p.name + "/" if p.is_dir() else p.stem
        if not (_named(layout, stem) or _named(layout, stem.lstrip("_"))):
            missing.append(f"python/pomkit/{p.name}")
    for top in ("src", "shaders", "python/pomkit", "tools", "scripts", "notebooks", "tests", "docs"):
        missing += [] if _named(layout, top + "/") else [top + "/"]
    assert not missing, f"README.md's Layout does not name: {', '.join(missing)}"


def test_the_layout_names_every_source_file():
    """Every Rust file of the core's folders (src/methods/ is covered by its `<name>.rs` line and
    its folders), every page of docs/ and every app is named by its file name or its stem."""
    layout = _layout()
    missing = []
    for d in ("src", "src/gpu", "src/render", "src/python", "src/mesh", "src/oracle", "src/assets", "src/heightmap",
              "src/scene"):
        for f in sorted((ROOT / d).glob("*.rs")):
            if f.stem in ("mod", "lib", "tests"):
                continue
            if not (_named(layout, f.name) or _named(layout, f.stem)):
                missing.append(f"{d}/{f.name}")
    for f in sorted((ROOT / "docs").glob("*.md")):
        missing += [] if _named(layout, f.name) else [f"docs/{f.name}"]
    for f in sorted((ROOT / "python" / "pomkit" / "apps").glob("*.py")):
        missing += [] if f.stem == "__init__" or _named(layout, f.stem) else [f"python/pomkit/apps/{f.name}"]
    assert not missing, f"README.md's Layout does not name: {', '.join(missing)}"


def test_reference_pages_are_short():
    """Every page of docs/ but the journals is a reference page, kept under 400 lines: what is,
    not how it came to be (issue 67). Dated measurements and tries go to a journal, a file whose
    name says so (docs/cost_journal_2026.md)."""
    long = []
    for f in sorted((ROOT / "docs").glob("*.md")):
        if "journal" in f.name:
            continue
        n = len(f.read_text().splitlines())
        if n >= 400:
            long.append(f"docs/{f.name} ({n} lines)")
    assert not long, f"reference pages of 400 lines or more: {', '.join(long)}"


#: what names an adapter in a provenance line: a vendor, a backend, or the CPU alone
ADAPTER = re.compile(r"llvmpipe|lavapipe|NVIDIA|AMD|Intel|Apple|\b(vulkan|gl|metal|dx12)\b|the CPU")
COMMIT = re.compile(r"commit [0-9a-f]{7,}")


def test_every_table_states_its_commit_and_adapter():
    """Every table of docs/tables says, on one line, the commit and the adapter it came from
    (tools/provenance.py writes that line; a JSON table carries it under "provenance", a chart is
    shown by a table that states it), and the
    Makefile's tables comments name every file, so that `make tables-all` (or the device run it
    names) regenerates each (issue 67 §6)."""
    tables = ROOT / "docs" / "tables"
    makefile = (ROOT / "Makefile").read_text()
    files = sorted(p for p in tables.rglob("*") if p.is_file())
    assert files
    bad, unnamed = [], []
    for p in files:
        rel = p.relative_to(tables).as_posix()
        if not re.search(rf"(?<![\w./-]){re.escape(rel)}(?![\w.-])", makefile):
            unnamed.append(rel)
        if p.suffix == ".png":
            # a chart: it takes the provenance of the table that shows it
            lines = [ln for t in tables.rglob("*.md") if p.name in t.read_text() for ln in t.read_text().splitlines()]
        elif p.suffix == ".json":
            prov = json.loads(p.read_text()).get("provenance") or ""
            # {"commit": ..., "adapter": ..., "line": ...} as tools/provenance.py's record, or a line
            lines = [f"commit {prov.get('commit', '')} {prov.get('adapter', '')}"] if isinstance(prov, dict) else [str(prov)]
        else:
            lines = p.read_text().splitlines()
        if not any(COMMIT.search(ln) and ADAPTER.search(ln) for ln in lines):
            bad.append(rel)
    assert not bad, f"tables without a line naming their commit and adapter: {', '.join(bad)}"
    assert not unnamed, f"tables the Makefile's `tables` comments do not name: {', '.join(unnamed)}"
