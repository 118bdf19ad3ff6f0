#!/usr/bin/env bash
# pomkit on this machine's GPU, in one command (headless: Vulkan through the vendor's driver):
# the adapter, the tests that hold frames to the oracle and to pinned frames, and the speed of
# every method at 512² and 1920x1080 in both pipelines with the cost model fitted there, written to
# docs/tables/gpu/<adapter>.md. Needs a Python with the pomkit wheel and the `test` and `bench`
# extras (pytest, trimesh, xatlas and flip-evaluator for the tests; scipy for the fit); no Rust toolchain.
# Usage: scripts/gpu_check.sh [python]   (default: .venv/bin/python, else python3)
set -uo pipefail
cd "$(dirname "$0")/.."
PY=${1:-$( [ -x .venv/bin/python ] && echo .venv/bin/python || echo python3 )}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp/pomkit-xdg-$(id -u)}
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
status=0
echo "== python -m pomkit info"
"$PY" -m pomkit info || exit 1
echo "== tests on this adapter: methods, differential, golden, the two pipelines, references"
# -rs lists every skipped test with its reason
"$PY" -m pytest -q -rs -p no:cacheprovider tests/test_methods.py tests/test_differential.py tests/test_golden.py tests/test_pipelines.py \
  tests/test_reference_exact.py tests/test_oracle_curved.py || status=1
echo "== speed: methods, ratios and the cost model at 512² and 1920x1080"
"$PY" scripts/gpu_check.py || status=1
exit $status
