#!/usr/bin/env python
"""Writes python/pomkit/_schema_classes.pyi, the static types of the scene classes the core
declares (src/scene/schema.rs, built at import by pomkit._schema), from the same table:

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
    lines = ['"""Static types of the scene classes the core declares (src/scene/schema.rs), which',
             "pomkit._schema builds at import. Written by tools/schema_stub.py (make stubs); do not edit.\"\"\"",
             "", "from dataclasses import dataclass", "from typing import Any, Optional", "", "import numpy as np", "",
             "from ._scene import _CameraBase, _DirectionalBase, _LightBase, _MaterialBase", ""]
    for name in _core.SCHEMA:
        eq = "" if _schema.by_value(name) else ", eq=False"
        lines += ["", f"@dataclass(frozen=True{eq})", f"class {name}({BASES[name]}):"]
        for f, kind, default, _lo, _hi, doc in _schema.fields(name):
            lines.append(f"    #: {' '.join(doc.split())}")
            lines.append(f"    {f}: {_schema.PY_TYPES[kind]}" + (" = ..." if default is not None else ""))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    text = stub()
    if "--check" in sys.argv:
        if not OUT.exists() or OUT.read_text() != text:
            print(f"{OUT} differs from the core's schema: run tools/schema_stub.py", file=sys.stderr)
            sys.exit(1)
    else:
        OUT.write_text(text)
