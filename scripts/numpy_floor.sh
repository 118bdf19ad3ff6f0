#!/usr/bin/env bash
# The digest tests (tests/test_hashes.py) under the oldest numpy that pyproject.toml allows, in a
# venv of their own (.venv-floor: that numpy, Pillow, and the wheel setup.sh built), so that a map
# or a hash that depends on numpy's version is caught. Run by `make test` after setup.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3.11}
command -v "$PY" >/dev/null || PY=python3
FLOOR=$(sed -n 's/.*"numpy>=\([0-9.]*\)".*/\1/p' pyproject.toml | head -n 1)
[ -n "$FLOOR" ] || { echo "[numpy-floor] no numpy>= floor in pyproject.toml" >&2; exit 1; }
WHEEL=$(ls target/wheels/pomkit-*-abi3-*.whl dist/pomkit-*-abi3-*.whl 2>/dev/null | head -n 1 || true)
[ -n "$WHEEL" ] || { echo "[numpy-floor] no pomkit wheel: run scripts/setup.sh first" >&2; exit 1; }
[ -x .venv-floor/bin/python ] || "$PY" -m venv .venv-floor
.venv-floor/bin/pip install -q "numpy==$FLOOR.*" "pillow>=9"
.venv-floor/bin/pip install -q --force-reinstall --no-deps "$WHEEL"
# run from outside the repository, so that the installed package (not ./python) is imported
(cd /tmp && "$OLDPWD/.venv-floor/bin/python" "$OLDPWD/tests/test_hashes.py" --check-floor)
