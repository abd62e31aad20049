#!/usr/bin/env bash
# Installs what the tests need on a fresh Debian machine, then runs every check:
# formatting, clippy (warnings are errors) and the whole test suite on llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# Printed on success and on failure, so CI logs always show how long the suite took.
trap 'rc=$?; echo "scripts/test.sh: $(( $(date +%s) - start )) s (exit $rc)"' EXIT
bash scripts/deps.sh --tests
if [ ! -f ../shared/MANIFEST.md ]; then
  echo "error: ../shared (test models and conformance files) is missing beside the repository" >&2
  exit 1
fi
cargo fmt --check
cargo clippy --workspace --all-targets --quiet -- -D warnings
# --workspace: the Python binding's features are resolved with the tests', so building it
# afterwards (scripts/test_python.sh) reuses this build's dependencies.
cargo test --workspace --no-fail-fast 2>&1
bash scripts/test_python.sh
