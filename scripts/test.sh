#!/usr/bin/env bash
# Installs what the tests need on a fresh Debian machine, then runs every check:
# formatting, clippy (warnings are errors) and the whole test suite on llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# Printed on success and on failure, so CI logs always show how long the suite took.
trap 'rc=$?; echo "scripts/test.sh: $(( $(date +%s) - start )) s (exit $rc)"' EXIT
# Each step prints its own duration, so a slow CI run says which step to look at.
step() {
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  echo "scripts/test.sh: step '$name' $(( $(date +%s) - t0 )) s"
}
step deps bash scripts/deps.sh --tests
if [ ! -f ../shared/MANIFEST.md ]; then
  echo "error: ../shared (test models and conformance files) is missing beside the repository" >&2
  exit 1
fi
step fmt cargo fmt --check
# Clippy runs inside the test build instead of as `cargo clippy` before it: clippy-driver as
# the workspace wrapper lints every target `cargo clippy --all-targets` lints (lib, bins, tests,
# their test builds; the crate has no examples or benches) while compiling them for real, so the
# tree is compiled once instead of twice (a check build, then the test build) — the clean CI
# run's longest step. This is what `cargo clippy` itself does, with `check` instead of `test`.
# --workspace: the Python binding is linted too, and its features are resolved with the
# tests', so building it afterwards (scripts/test_python.sh, same wrapper) reuses this build.
clippy_driver=$(rustup which clippy-driver 2>/dev/null || command -v clippy-driver)
export RUSTC_WORKSPACE_WRAPPER=$clippy_driver
export CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"
step "build + clippy -D warnings" cargo test --workspace --no-run --quiet
step test cargo test --workspace --no-fail-fast 2>&1
step python bash scripts/test_python.sh
