#!/usr/bin/env bash
# `cargo test` for `make test`, built on the test wheel's build: scripts/setup.sh builds that wheel
# with zig (maturin --zig, for x86_64-unknown-linux-gnu, linked by cargo-zigbuild's wrapper), and
# this builds the tests for the same target with the same linker, profile (Cargo.toml's
# profile.release) and dependency features (the test-hooks feature turns on the naga backends the
# tests use), so that only pomkit itself compiles: 38 s here, against 4 min 15 s for a
# build of its own. Without that build (POMKIT_NO_ZIG, another OS), a plain cargo test. Arguments are
# cargo test's.
set -euo pipefail
cd "$(dirname "$0")/.."
ARGS=(--release --features test-hooks)
# the wrapper this checkout's maturin wrote (each checkout's venv has its own; another's may be gone)
WRAPPER=$(grep -lF "\"$PWD/.venv/bin/maturin\"" "$HOME"/.cache/cargo-zigbuild/*/wrappers/*/zigcc-x86_64-unknown-linux-gnu.2.17-*.sh 2>/dev/null | head -n 1 || true)
if [ -z "${POMKIT_NO_ZIG:-}" ] && [ -n "$WRAPPER" ] && [ -d target/x86_64-unknown-linux-gnu/release ]; then
  export CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_LINKER="$WRAPPER"
  ARGS+=(--target x86_64-unknown-linux-gnu)
fi
exec cargo test "${ARGS[@]}" "$@"
