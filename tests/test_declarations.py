"""Every field the core declares reaches everything that must know it (issue 67): by reflection
over `_core.SCHEMA`, each field of Camera, Material and the lights is a field of the Python class
and of its stub, changes the reference caches' key (`scene_hash`) unless it is one of pomkit's
own renderer's settings (`@ setting` in the core), and is kept by `Renderer.update_height`. A
field added to a `schema!` struct is checked here with no edit to this file."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

import pomkit as pk
from pomkit import _core, _schema
from pomkit._cache import scene_hash

STUB = Path(pk.__file__).parent / "_schema_classes.pyi"


def _other(kind: str, v, lo, hi):
    """A valid value of `kind` other than `v`."""
    if kind == "vec3":
        return tuple(float(x) + 0.25 * (k + 1) for k, x in enumerate(v))
    if kind == "rgb":
        return (0.5, 0.25, 0.75)
    if kind == "real":
        step = 0.01 * (hi - lo) if np.isfinite(hi - lo) else 0.5
        return float(v) + step if float(v) + step <= hi else float(v) - step
    if kind == "integer":
        return int(v) + 1 if int(v) + 1 <= hi else int(v) - 1
    if kind == "bool":
        return not v
    if kind == "height":
        h = np.array(v, np.float32)
        h[0, 0] = 1.0 - h[0, 0]
        return h
    if kind == "albedo":
        return np.full((8, 8, 3), 0.5, np.float32)
    raise AssertionError(f"a kind this test does not know: {kind}")


def _scene(**replace) -> pk.Scene:
    mat = pk.Material(pk.textures.bricks(16), depth=0.05)
    cam = pk.Camera(eye=(0.0, 1.0, 1.5), target=(0.0, 0.0, 0.0), width=16, height=16)
    lights = [pk.DirectionalLight(direction=(-0.3, -1.0, -0.2)), pk.SphereLight(position=(0.0, 2.0, 0.0))]
    objs = dict(Camera=cam, Material=mat, DirectionalLight=lights[0], SphereLight=lights[1])
    for cls, (name, value) in replace.items():
        objs[cls] = dataclasses.replace(objs[cls], **{name: value})
    return pk.Scene(mesh=pk.Mesh.plane(), material=objs["Material"], camera=objs["Camera"],
                    lights=[objs["DirectionalLight"], objs["SphereLight"]])


FIELDS = [(cls, f) for cls in _core.SCHEMA for f in _schema.fields(cls)]


def test_every_class_is_checked():
    assert {"Camera", "Material", "DirectionalLight", "SphereLight"} <= set(_core.SCHEMA)
    assert _schema.settings("DirectionalLight") == {"cast_shadows", "shadow_map_size"}


@pytest.mark.parametrize("cls,field", FIELDS, ids=[f"{c}.{f[0]}" for c, f in FIELDS])
def test_a_declared_field_reaches_the_class_the_stub_and_the_cache_key(cls, field):
    name, kind, _default, lo, hi, _doc = field
    py = getattr(pk, cls)
    assert name in [f.name for f in dataclasses.fields(py)], f"{cls}.{name} is not a field of pk.{cls}"
    stub = next(n for n in ast.parse(STUB.read_text()).body if isinstance(n, ast.ClassDef) and n.name == cls)
    assert name in [n.target.id for n in stub.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)], \
        f"{cls}.{name} is not in the stub: make stubs"
    base = _scene()
    obj = {"Camera": base.camera, "Material": base.material, "DirectionalLight": base.lights[0], "SphereLight": base.lights[1]}[cls]
    changed = _scene(**{cls: (name, _other(kind, getattr(obj, name), lo, hi))})
    moved = scene_hash(changed, kind="t") != scene_hash(base, kind="t")
    if name in _schema.settings(cls):
        assert not moved, f"{cls}.{name} is pomkit's own setting: it must not change a reference's key"
    else:
        assert moved, f"{cls}.{name} does not change the reference caches' key"


def test_update_height_keeps_every_other_declared_field(renderer):
    mat = pk.Material(pk.textures.bricks(16), depth=0.05)
    for name, kind, _d, lo, hi, _doc in _schema.fields("Material"):
        if name != "height":
            mat = dataclasses.replace(mat, **{name: _other(kind, getattr(mat, name), lo, hi)})
    new = renderer.update_height(mat, pk.textures.pyramids(16))
    for name, *_ in _schema.fields("Material"):
        if name != "height":
            a, b = getattr(new, name), getattr(mat, name)
            assert np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b, name
    assert not np.array_equal(new.height, mat.height)


def _stub_class(name: str) -> dict[str, str]:
    cls = next(n for n in ast.parse(STUB.read_text()).body if isinstance(n, ast.ClassDef) and n.name == name)
    return {n.target.id: ast.unparse(n.annotation) for n in cls.body
            if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}


def test_every_declared_report_field_reaches_the_report_the_stub_and_check_asset():
    """src/assets/report.rs's `report!` declares the report once: each field is a field of
    pk.AssetReport, in the stub with the declared type, and in what check_asset returns."""
    declared = [(n, t) for n, t, _doc in _core.ASSET_REPORT_FIELDS]
    assert len(declared) >= 20
    names = [f.name for f in dataclasses.fields(pk.AssetReport)]
    stub = _stub_class("AssetReport")
    report = pk.check_asset(pk.Mesh.sphere(), pk.Material(pk.textures.bricks(32), depth=0.05))
    for name, py_type in declared:
        assert name in names, f"AssetReport.{name} is not a field of pk.AssetReport"
        assert stub.get(name) == py_type, f"AssetReport.{name}: the stub says {stub.get(name)}, the core {py_type}: make stubs"
        assert hasattr(report, name)
    assert names[:len(declared)] == [n for n, _ in declared]


def test_every_method_parameter_the_core_reads_is_a_field_of_its_class():
    """The core reads each method's parameters by name from its dataclass (`params!`): every
    name it reads is a field of the Python class of that `_kind`, and every field of the class
    is read."""
    classes = {c._kind: c for c in vars(pk).values()
               if isinstance(c, type) and issubclass(c, pk.Method) and dataclasses.is_dataclass(c) and getattr(c, "_kind", None)}
    core = dict(_core.METHOD_FIELDS)
    assert set(core) == set(classes), f"core methods {sorted(core)} against Python's {sorted(classes)}"
    for kind, read in core.items():
        fields = {f.name for f in dataclasses.fields(classes[kind])}
        assert set(read) == fields, f"{kind}: the core reads {sorted(read)}, the class has {sorted(fields)}"
