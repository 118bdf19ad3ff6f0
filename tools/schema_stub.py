#!/usr/bin/env python
"""Writes python/pomkit/_schema_classes.pyi, the static types of the classes the core declares
(the scene classes of src/scene/schema.rs, built at import by pomkit._schema; the asset report
of src/assets/report.rs, built by pomkit._assets), from the same tables:

    .venv/bin/python tools/schema_stub.py          # write it (make stubs)
    .venv/bin/python tools/schema_stub.py --check  # exit 1 where it differs

tests/test_contracts.py runs the check."""

from __future__ import annotations

import sys
from pathlib import Path

from pomkit import _core, _schema

OUT = Path(__file__).resolve().parent.parent / "python" / "pomkit" / "_schema_classes.pyi"
BASES = {"Camera": "_CameraBase", "Material": "_MaterialBase", "DirectionalLight": "_DirectionalBase", "SphereLight": "_LightBase"}


def stub() -> str:
    lines = ['"""Static types of the classes the core declares (src/scene/schema.rs, src/assets/report.rs),',
             "which pomkit builds at import. Written by tools/schema_stub.py (make stubs); do not edit.\"\"\"",
             "", "from dataclasses import dataclass", "from typing import Any, Optional", "", "import numpy as np", "",
             "from ._assets import _AssetReportBase",
             "from ._scene import _CameraBase, _DirectionalBase, _LightBase, _MaterialBase", ""]
    for name in _core.SCHEMA:
        eq = "" if _schema.by_value(name) else ", eq=False"
        lines += ["", f"@dataclass(frozen=True{eq})", f"class {name}({BASES[name]}):"]
        for f, kind, default, _lo, _hi, doc in _schema.fields(name):
            lines.append(f"    #: {' '.join(doc.split())}")
            lines.append(f"    {f}: {_schema.PY_TYPES[kind]}" + (" = ..." if default is not None else ""))
    from pomkit._assets import _AssetReportBase
    lines += ["", "@dataclass(frozen=True)", "class AssetReport(_AssetReportBase):"]
    for f, py_type, doc in _core.ASSET_REPORT_FIELDS:
        if doc:
            lines.append(f"    #: {' '.join(doc.split())}")
        lines.append(f"    {f}: {py_type}")
    for f, py_type, doc, _default in _AssetReportBase._PYTHON_FIELDS:
        lines.append(f"    #: {doc}")
        lines.append(f"    {f}: {py_type} = ...")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    text = stub()
    if "--check" in sys.argv:
        if not OUT.exists() or OUT.read_text() != text:
            print(f"{OUT} differs from the core's schema: run tools/schema_stub.py", file=sys.stderr)
            sys.exit(1)
    else:
        OUT.write_text(text)
