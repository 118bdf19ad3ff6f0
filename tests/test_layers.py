"""The Rust core's module graph has no circle: between the top-level modules of src/ (a file or
a folder, by the `crate::` paths each names), and between its files (`file_graph`: every `use`
and path, nested `super::` resolved). A folder's mod.rs is its face: it may use its files,
its files never use it. The pyo3 layer (src/python) sits on top and may use anything; nothing
may use it. pomkit's Python modules have no circle either."""

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


def _strip(text: str) -> str:
    """Rust source without comments and string contents."""
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return re.sub(r'"(?:\\.|[^"\\])*"', '""', text)


def _use_paths(tree: str) -> list[str]:
    """The paths of one `use` tree: `a::{b, c::{d, e}}` -> a::b, a::c::d, a::c::e."""
    tree = re.sub(r"\s+", "", tree)
    out: list[str] = []

    def walk(prefix: str, t: str) -> None:
        parts, depth, cur = [], 0, ""
        for ch in t:
            depth += (ch == "{") - (ch == "}")
            if ch == "," and depth == 0:
                parts.append(cur)
                cur = ""
            else:
                cur += ch
        parts.append(cur)
        for part in filter(None, parts):
            i = part.find("{")
            if i < 0:
                out.append(prefix + re.sub(r"as\w+$", "", part))
            else:
                walk(prefix + part[:i], part[i + 1:part.rfind("}")])

    walk("", tree)
    return out


def _inline_modules(text: str) -> tuple[str, list[tuple[str, str]]]:
    """A file's text outside its inline `mod name { ... }` blocks, and each block's (name, text)."""
    blocks, outer, i = [], "", 0
    for m in re.finditer(r"\bmod\s+([a-z_][a-z0-9_]*)\s*\{", text):
        if m.start() < i:
            continue
        depth, j = 0, m.end() - 1
        while True:
            depth += (text[j] == "{") - (text[j] == "}")
            if depth == 0:
                break
            j += 1
        outer += text[i:m.start()]
        blocks.append((m.group(1), text[m.end():j]))
        i = j + 1
    return outer + text[i:], blocks


def file_graph(src: Path = SRC) -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    """Every file of src/ as its module path (src/render/mod.rs is ("render",)), and the files
    whose items it names: each `use` path and each path written in code (`crate::x::y`,
    `super::super::x`, `self::x`, `child::x`), resolved through nested `super::` to the deepest
    module that is a file, and on through that file's `pub use` to where the item is defined.
    A `pub use` is a use of its file only where the file's own code names what it brings in.
    An inline module (`mod tests { use super::*; }`) resolves from its own place. A method
    called on a type whose impl is split over files is not a named path and is not seen."""
    def modpath(f: Path) -> tuple[str, ...]:
        parts = list(f.relative_to(src).with_suffix("").parts)
        if parts[-1] == "mod":
            parts = parts[:-1]
        return () if parts in (["lib"], ["main"]) else tuple(parts)

    files = {modpath(f): f for f in src.rglob("*.rs")}
    texts = {m: _inline_modules(_strip(f.read_text())) for m, f in files.items()}
    pub_use = r"\bpub(?:\([a-z]+\))?\s+use\s+([^;]+);"

    def walk(me: tuple[str, ...], path: str) -> tuple[tuple[str, ...], list[str]] | None:
        segs = [s for s in path.split("::") if s]
        if not segs:
            return None
        if segs[0] == "crate":
            base, segs = (), segs[1:]
        elif segs[0] in ("super", "self"):
            base = me
            while segs and segs[0] in ("super", "self"):
                base = base[:-1] if segs[0] == "super" else base
                segs = segs[1:]
        elif me + (segs[0],) in files:
            base = me
        else:
            return None
        while segs and base + (segs[0],) in files:
            base, segs = base + (segs[0],), segs[1:]
        return base, segs

    def exports(m: tuple[str, ...]) -> dict[str, str]:
        """What file m re-exports: name -> the path it stands for."""
        out = {}
        for u in re.findall(pub_use, texts[m][0]):
            for p in _use_paths(u):
                alias = re.search(r"as(\w+)$", p)
                name = alias.group(1) if alias else p.split("::")[-1]
                out[name] = re.sub(r"as\w+$", "", p)
        return out

    reexports = {m: exports(m) for m in files}

    def resolve(me: tuple[str, ...], path: str):
        for _ in range(8):
            w = walk(me, path)
            if w is None:
                return None
            base, rest = w
            if not rest or rest[0] not in reexports.get(base, {}):
                return base
            me, path = base, reexports[base][rest[0]]
        return base

    def deps(me: tuple[str, ...], text: str) -> set:
        code = re.sub(r"\buse\s+[^;]+;", "", text)
        named = set(re.findall(r"\w+", code))
        paths = []
        for m in re.finditer(r"(\bpub(?:\([a-z]+\))?\s+)?\buse\s+([^;]+);", text):
            for p in _use_paths(m.group(2)):
                alias = re.search(r"as(\w+)$", p)
                name = alias.group(1) if alias else p.split("::")[-1]
                if not m.group(1) or name in named:
                    paths.append(re.sub(r"as\w+$", "", p))
        paths += re.findall(r"\b((?:crate|super|self)(?:::[A-Za-z_]\w*)+)", code)
        paths += re.findall(r"(?<![:\w])([a-z_]\w*(?:::[A-Za-z_]\w*)+)", code)
        return {r for r in (resolve(me, p) for p in paths) if r is not None}

    g: dict[tuple[str, ...], set[tuple[str, ...]]] = {}
    for me in files:
        outer, blocks = texts[me]
        d = deps(me, outer)
        for name, inner in blocks:
            d |= deps(me + (name,), inner)
        g[me] = d - {me}
    return g


def test_no_circle_between_files():
    g = file_graph()
    assert ("render", "targets") in g and ("methods", "pom") in g[("methods",)]
    found = [["::".join(m) for m in c] for c in cycles(g)]
    assert found == [], f"circles between files of src/: {found}"


def test_the_file_graph_sees_a_planted_circle(tmp_path):
    """A method that takes its contract from the registry that lists it, and a file that names
    its parent through a nested super::, are circles."""
    import shutil
    shutil.copytree(SRC, tmp_path / "src")
    assert cycles(file_graph(tmp_path / "src")) == []
    pom = tmp_path / "src" / "methods" / "pom.rs"
    pom.write_text(pom.read_text() + "\nfn planted() -> Option<super::Method> { None }\n")
    assert any({("methods",), ("methods", "pom")} <= set(c) for c in cycles(file_graph(tmp_path / "src")))
    pom.write_text(pom.read_text().replace("super::Method", "crate::methods::Method"))
    assert cycles(file_graph(tmp_path / "src")) != []
    shutil.copy(SRC / "methods" / "pom.rs", pom)
    targets = tmp_path / "src" / "render" / "targets.rs"
    targets.write_text(targets.read_text() + "\nmod inner { fn f() { let _ = super::super::Renderer::new; } }\n")
    assert any({("render",), ("render", "targets")} <= set(c) for c in cycles(file_graph(tmp_path / "src")))


def test_methods_build_on_the_contract_not_on_their_registry():
    g = file_graph()
    for m, deps in g.items():
        if m[:1] == ("methods",) and len(m) > 1:
            assert ("methods",) not in deps, f"{'::'.join(m)} uses the registry (src/methods/mod.rs)"
