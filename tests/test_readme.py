"""The README's python blocks, run in order in one namespace, as a newcomer pastes them one after
another into a notebook, in a folder holding the files they name: height.png and albedo.exr
(tests/readme_fixtures/: pk.textures.bricks(64) as 16-bit PNG, its brick albedo as linear half
float OpenEXR), rock.glb (the demo's rock, shipped in pomkit/data/demo) and scene.glb (that
rock's mesh under two nodes, the second moved). Each block is one test; a block run alone first
runs the blocks above it. A block that defines a `test_*` function has it called, with pytest's
fixtures, as the README says to use it."""

from __future__ import annotations

import inspect
import json
import re
import shutil
import struct
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
FIXTURES = Path(__file__).parent / "readme_fixtures"

#: blocks not run here, each keyed by a string only that block holds, and why
SKIP = {
    'Client("tcp://scheduler:8786")': "needs a Dask scheduler at that address (tests/test_bench.py runs the sweep "
                                      "on a LocalCluster)",
    "pk.reference.render_cycles(": "needs Mitsuba and Blender's Cycles, heavy optional references "
                                   "(tests/test_reference.py, tests/test_cycles.py)",
}


def _blocks() -> list[tuple[int, str]]:
    """Each ```python block of the README: (the line its code starts on, its code)."""
    text = README.read_text()
    return [(text.count("\n", 0, m.start(1)) + 1, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)]


BLOCKS = _blocks()


def _two_rocks(src: Path, dst: Path) -> None:
    """A .glb of two mesh nodes, both `src`'s first mesh, the second translated: `src`'s own
    binary chunk under a rewritten JSON chunk."""
    b = src.read_bytes()
    n = struct.unpack("<I", b[12:16])[0]
    doc, binary = json.loads(b[20:20 + n]), b[20 + n:]
    doc["nodes"] = [{"name": "rock", "mesh": 0}, {"name": "rock moved", "mesh": 0, "translation": [2.5, 0.0, 0.0]}]
    doc["scenes"] = [{"nodes": [0, 1]}]
    doc["scene"] = 0
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    dst.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + len(binary))
                    + struct.pack("<I4s", len(js), b"JSON") + js + binary)


@pytest.fixture(scope="module")
def notebook(tmp_path_factory):
    folder = tmp_path_factory.mktemp("readme")
    for f in FIXTURES.iterdir():
        shutil.copy(f, folder / f.name)
    import pomkit

    rock = Path(pomkit.__file__).parent / "data" / "demo" / "rock.glb"
    shutil.copy(rock, folder / "rock.glb")
    _two_rocks(rock, folder / "scene.glb")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(folder)
        mp.setenv("POMKIT_CACHE", str(folder / "cache"))  # every reference computed afresh
        yield {"namespace": {"__name__": "__readme__"}, "next": 0, "failed": None}


def _skip_reason(code: str) -> str | None:
    return next((why for key, why in SKIP.items() if key in code), None)


def _run(notebook, i: int, request) -> None:
    line, code = BLOCKS[i]
    ns = notebook["namespace"]
    before = set(ns)
    # padded so that a traceback names the README's own line
    exec(compile("\n" * (line - 1) + code, str(README), "exec"), ns)
    for name in sorted(set(ns) - before):
        if name.startswith("test_") and callable(ns[name]):
            f = ns[name]
            f(**{p: request.getfixturevalue(p) for p in inspect.signature(f).parameters})


def test_each_skip_names_one_block():
    for key in SKIP:
        assert sum(key in code for _, code in BLOCKS) == 1, f"SKIP key {key!r} matches no block or several"


@pytest.mark.parametrize("i", range(len(BLOCKS)), ids=[f"line{line}" for line, _ in BLOCKS])
def test_readme_block(i, notebook, request):
    while notebook["next"] <= i:
        k = notebook["next"]
        notebook["next"] += 1
        if notebook["failed"] is not None:
            pytest.fail(f"not run: the block at README.md line {notebook['failed']} failed, and the blocks "
                        "below it read its names")
        if _skip_reason(BLOCKS[k][1]) is not None:
            continue
        try:
            _run(notebook, k, request)
        except Exception:
            notebook["failed"] = BLOCKS[k][0]
            raise
    why = _skip_reason(BLOCKS[i][1])
    if why is not None:
        pytest.skip(f"README.md line {BLOCKS[i][0]}: {why}")
