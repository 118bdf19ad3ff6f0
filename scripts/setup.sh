#!/usr/bin/env bash
# Set up pomkit from a fresh Debian machine with Rust and Python 3.11:
#   system packages (Mesa's software Vulkan/GL drivers where no adapter is found; Debian's
#   libllvm19 for Mitsuba's LLVM variant, OSMesa/EGL for pyrender and Chromium for the browser
#   tests when those extras are asked for),
#   a venv in .venv, and a release build of the extension installed into it.
# Usage: scripts/setup.sh [extra ...]   e.g. scripts/setup.sh test reference
set -euo pipefail
cd "$(dirname "$0")/.."
EXTRAS=("$@")
PY=${PYTHON:-python3.11}
command -v "$PY" >/dev/null || PY=python3

export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp/pomkit-xdg-$(id -u)}
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"

SUDO=""
[ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null && SUDO="sudo"
apt_install() {
  local missing=()
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "[setup] apt-get install ${missing[*]}"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

# A GPU adapter: if no Vulkan ICD is present, install Mesa's software drivers (lavapipe + EGL/GL).
if ! ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ! ls /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
  apt_install mesa-vulkan-drivers libegl1 libegl-mesa0 libgl1-mesa-dri
fi
for e in "${EXTRAS[@]}"; do
  if [ "$e" = "reference" ]; then
    # Mitsuba's llvm_ad_rgb needs LLVM >= 16 (Debian's 15 crashes); pyrender renders headless
    # through EGL or OSMesa.
    apt_install libllvm19 libegl1 libegl-mesa0 libgl1-mesa-dri libosmesa6
  fi
  if [ "$e" = "browser" ]; then
    # a real browser for tests/test_browser.py: Debian's Chromium (Playwright cannot download its
    # own here; it drives this one through executable_path)
    apt_install chromium
  fi
done

if [ ! -x .venv/bin/python ]; then
  echo "[setup] creating .venv with $PY"
  "$PY" -m venv .venv
fi
. .venv/bin/activate
pip install -q --upgrade pip >/dev/null
pip install -q "maturin>=1.16,<2" numpy pillow

# The extension: one abi3 wheel (CPython 3.10+). Rebuilt only when the sources changed since the
# wheel in target/wheels was built (their hash is kept beside it); without a Rust toolchain, a
# wheel already in target/wheels or dist/ is installed as it is.
src_hash() {
  { git ls-files -s Cargo.toml Cargo.lock pyproject.toml src shaders python 2>/dev/null || true
    git diff HEAD -- Cargo.toml Cargo.lock pyproject.toml src shaders python 2>/dev/null || true; } | sha256sum | cut -c1-16
}
# the test builds carry the test hooks (Cargo feature test-hooks); a user's wheel does not
FEATURES=()
for e in "${EXTRAS[@]}"; do if [ "$e" = "test" ]; then FEATURES=(--features python,test-hooks); fi; done
HASH=$( { src_hash; echo "${FEATURES[*]:-}"; } | sha256sum | cut -c1-16)
WHEEL=$(ls target/wheels/pomkit-*-abi3-*.whl 2>/dev/null | head -n 1 || true)
if [ -n "$WHEEL" ] && [ "$(cat target/wheels/.source-hash 2>/dev/null)" = "$HASH" ]; then
  echo "[setup] $WHEEL matches the sources: not rebuilding"
elif ! command -v cargo >/dev/null; then
  WHEEL=$(ls target/wheels/pomkit-*-abi3-*.whl dist/pomkit-*-abi3-*.whl 2>/dev/null | head -n 1 || true)
  [ -n "$WHEEL" ] || { echo "[setup] no Rust toolchain and no wheel in target/wheels or dist/: install Rust (https://rustup.rs) or put a pomkit abi3 wheel in dist/" >&2; exit 1; }
  echo "[setup] no Rust toolchain: installing $WHEEL"
else
  rm -rf target/wheels
  if [ "$(uname -s)" = Linux ] && [ "${POMKIT_NO_ZIG:-}" = "" ]; then
    # linked by zig against glibc 2.17's symbols: a manylinux2014 wheel, which installs on any
    # Linux since CentOS 7 / RHEL 7 (glibc 2.17), not only on this machine's glibc
    echo "[setup] building the extension (release, abi3, manylinux2014 by zig)"
    pip install -q "ziglang>=0.13"
    maturin build --release --quiet ${FEATURES[@]+"${FEATURES[@]}"} --zig --compatibility manylinux2014 -o target/wheels
  else
    echo "[setup] building the extension (release, abi3)"
    maturin build --release --quiet ${FEATURES[@]+"${FEATURES[@]}"} -o target/wheels
  fi
  WHEEL=$(ls target/wheels/pomkit-*.whl | head -n 1)
  echo "$HASH" > target/wheels/.source-hash
fi
# the `blender` extra lives in a venv of its own (.venv-blender): bpy 5.0.1 is built for CPython
# 3.11 and wants numpy < 2; pk.reference.render_cycles runs it as a subprocess
PIP_EXTRAS=()
for e in "${EXTRAS[@]}"; do
  if [ "$e" = "blender" ]; then
    if [ ! -x .venv-blender/bin/python ] || ! .venv-blender/bin/python -c "import bpy" 2>/dev/null; then
      echo "[setup] creating .venv-blender with bpy 5.0.1 (Blender as a module, for pk.reference.render_cycles)"
      "$PY" -m venv .venv-blender
      .venv-blender/bin/pip install -q --upgrade pip >/dev/null
      .venv-blender/bin/pip install -q "bpy==5.0.1"
    fi
  else
    PIP_EXTRAS+=("$e")
  fi
done
spec="$WHEEL"
if [ ${#PIP_EXTRAS[@]} -gt 0 ]; then spec="$WHEEL[$(IFS=,; echo "${PIP_EXTRAS[*]}")]"; fi
pip install -q --force-reinstall --no-deps "$WHEEL"
pip install -q "$spec"
for e in "${EXTRAS[@]}"; do
  # pyrender 0.1.45 pins PyOpenGL 3.1.0, whose OSMesa binding is broken; 3.1.10 works with it
  # (EGL and OSMesa) and is what the headless fallback needs.
  [ "$e" = "reference" ] && pip install -q --no-deps "PyOpenGL>=3.1.10" 2>/dev/null
done
python -c "import pomkit, sys; print('[setup] pomkit', pomkit.__version__, 'on', pomkit.adapters()[0]['name'] if pomkit.adapters() else 'NO ADAPTER')"
