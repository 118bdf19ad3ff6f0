"""The Rust core's module graph has no cycle (issue 24): for each top-level module of src/
(a file or a folder), the modules it names through `crate::` paths (and `use super::` in a
folder's nested files stays inside the folder). The pyo3 layer (src/python) sits on top and
may use anything; nothing may use it."""

import re
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"


def graph() -> dict[str, set[str]]:
    g: dict[str, set[str]] = {}
    for f in SRC.rglob("*.rs"):
        rel = f.relative_to(SRC)
        top = rel.parts[0].removesuffix(".rs")
        if top in ("lib", "main"):
            continue
        text = "\n".join(l for l in f.read_text().splitlines() if not l.lstrip().startswith("//"))
        deps = set(re.findall(r"\bcrate::([a-z_][a-z0-9_]*)", text)) - {top}
        g.setdefault(top, set()).update(deps)
    return g


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in list(g):
        if v not in index:
            visit(v)
    return out


def test_no_module_cycle():
    g = graph()
    assert "contract" in g and "render" in g and "methods" in g
    assert cycles(g) == [], f"module cycles: {cycles(g)}; graph: { {k: sorted(v) for k, v in g.items()} }"


def test_contract_is_at_the_bottom_and_python_on_top():
    g = graph()
    assert g["contract"] <= {"error", "fields", "gpu", "scene", "mesh", "heightmap"}, g["contract"]
    for m, deps in g.items():
        if m != "python":
            assert "python" not in deps, f"{m} uses the pyo3 layer"
    for m in ("shaders", "render", "methods"):
        assert "contract" in g[m], f"{m} does not build on the contract"


PY = SRC.parent / "python" / "pomkit"


def python_graph() -> dict[str, set[str]]:
    """pomkit's Python modules and the pomkit modules each imports, at any depth of the file
    (function-local imports too): relative imports, `import pomkit.x` and `from pomkit[.x]
    import y`. `pomkit` itself (the package's __init__) is a node like the others."""
    import ast
    g: dict[str, set[str]] = {}
    mods = {str(f.relative_to(PY.parent).with_suffix("")).replace("/", ".").removesuffix(".__init__")
            for f in PY.rglob("*.py")} | {"pomkit._core"}
    for f in PY.rglob("*.py"):
        name = str(f.relative_to(PY.parent).with_suffix("")).replace("/", ".")
        pkg = name.rsplit(".", 1)[0] if not name.endswith("__init__") else name.removesuffix(".__init__")
        name = name.removesuffix(".__init__")
        deps: set[str] = set()
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = pkg.split(".")
                    base = base[:len(base) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if not target.startswith("pomkit"):
                    continue
                for a in node.names:  # `from . import x` names a module when x is one
                    sub = f"{target}.{a.name}"
                    deps.add(sub if sub in mods else target)
            elif isinstance(node, ast.Import):
                deps |= {a.name for a in node.names if a.name.startswith("pomkit")}
        g[name] = deps - {name}
    return g


def test_no_python_module_cycle():
    g = python_graph()
    assert "pomkit._scene" in g and "pomkit.apps.page" in g
    assert cycles(g) == [], f"Python module cycles: {cycles(g)}"


def nested_graph() -> dict[str, set[str]]:
    """Inside each folder of src/: its files (and subfolders) and the siblings each names, by
    `super::x` or `crate::folder::x`."""
    g: dict[str, set[str]] = {}
    for d in [p for p in SRC.iterdir() if p.is_dir()]:
        for f in d.rglob("*.rs"):
            parts = f.relative_to(d).parts
            me = parts[0].removesuffix(".rs")
            if me == "mod":
                continue
            text = "\n".join(l for l in f.read_text().splitlines() if not l.lstrip().startswith("//"))
            sib = set(re.findall(rf"\bcrate::{d.name}::([a-z_][a-z0-9_]*)", text))
            if len(parts) == 1:  # a file directly in the folder: super:: is the folder
                sib |= set(re.findall(r"\bsuper::([a-z_][a-z0-9_]*)", text))
            names = {p.name.removesuffix(".rs") for p in d.iterdir() if p.suffix == ".rs" or p.is_dir()} - {"mod"}
            g.setdefault(f"{d.name}::{me}", set()).update(f"{d.name}::{s}" for s in sib & names if s != me)
    return g


def test_no_cycle_inside_a_folder():
    g = nested_graph()
    assert "render::uniforms" in g and "render::shadow_map" in g
    assert cycles(g) == [], f"module cycles inside a folder: {cycles(g)}"
