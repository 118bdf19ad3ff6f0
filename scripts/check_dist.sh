#!/usr/bin/env bash
# The distributions, checked as a user gets them (make test runs this):
#   1. the wheel setup.sh built (target/wheels): auditwheel says it is manylinux_2_17
#      (manylinux2014: glibc 2.17 and later, CentOS 7 / RHEL 7 onwards);
#   2. the sdist (maturin sdist): `pip install` builds it where Rust is present;
#   3. each installed into its own new venv renders a POM frame.
set -euo pipefail
cd "$(dirname "$0")/.."
. .venv/bin/activate
pip install -q auditwheel
WHEEL=$(ls target/wheels/pomkit-*-abi3-*.whl | head -n 1)
echo "[dist] $WHEEL"
auditwheel show "$WHEEL" > target/auditwheel.txt
grep -q '"manylinux_2_17_x86_64"' target/auditwheel.txt \
  || { cat target/auditwheel.txt; echo "[dist] the wheel is not manylinux_2_17 (manylinux2014)" >&2; exit 1; }
echo "[dist] auditwheel: manylinux_2_17_x86_64"
rm -rf target/sdist && maturin sdist -o target/sdist >/dev/null
SDIST=$(ls target/sdist/pomkit-*.tar.gz)
echo "[dist] $SDIST: $(tar tzf "$SDIST" | wc -l) files"
smoke='
import numpy as np, pomkit as pk
s = pk.Scene(mesh=pk.Mesh.plane(2.0), material=pk.Material(pk.textures.bricks(64), depth=0.05),
             camera=pk.Camera.look_at((0, 1.2, 1.6), width=32, height=32))
f = pk.Renderer().render(s, pk.POM())
assert f.color.shape == (32, 32, 3) and f.mask.mean() > 0.5 and np.isfinite(f.color).all()
print("[dist] renders:", pk.__file__)'
# the sdist compiles from its own files, in a target directory of its own per sdist content:
# its files carry the tarball's fixed timestamps, so cargo cannot tell a changed source from an
# old build by time (kept for the same sources). It compiles unoptimised (opt-level 0: about
# 1 minute cold here, against 3.5 at opt-level 3): what it checks is that pip builds a working
# module from the sdist's files alone; the optimised build of the same sources is the wheel's
BUILD="$PWD/target/sdist-build-$(sha256sum "$SDIST" | cut -c1-12)"
find target -maxdepth 1 -name 'sdist-build*' ! -path "$BUILD" -exec rm -rf {} +
for what in "$WHEEL" "$SDIST"; do
  d=$(mktemp -d /tmp/pomkit-dist-XXXX)
  python -m venv "$d"
  CARGO_TARGET_DIR="$BUILD" CARGO_PROFILE_RELEASE_OPT_LEVEL=0 "$d/bin/pip" install -q --no-cache-dir "$what"
  (cd "$d" && "$d/bin/python" -c "$smoke")
  if [ "$what" = "$SDIST" ]; then
    # what pip builds for a user holds what users call: no test hooks, no pytest plugin entry
    # point, no cost-model fitting
    (cd "$d" && "$d/bin/python" -c '
import importlib.metadata as md, pomkit as pk, pomkit.bench as b
assert not hasattr(pk._core.Renderer, "_provoke_validation_error"), "test hooks in a user build"
assert not [e for e in md.entry_points(group="pytest11") if e.value.startswith("pomkit")], "a pytest11 entry point"
assert not hasattr(b, "fit_model") and not hasattr(b, "cost_rows"), "cost fitting in the package"
print("[dist] the sdist build holds no test hooks, no pytest plugin, no fitting code")')
  fi
  rm -rf "$d"
done
