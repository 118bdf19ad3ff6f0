"""The README's Layout names every folder of src/, every WGSL module of shaders/, every module
and folder of python/pomkit/, every Rust file of the core's folders and every page of docs/, so
that a newcomer's map of the tree is the tree."""

from __future__ import annotations

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
