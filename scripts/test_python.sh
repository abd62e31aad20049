#!/usr/bin/env bash
# The Python package's tests (python/tests), run by scripts/test.sh after the Rust tests:
# a venv in target/pyvenv, `pip install ./python` built with the dev profile (pyproject's is
# release, for users; MATURIN_PEP517_ARGS overrides it here) into the
# repository's target/ (so only pyo3, numpy and the binding compile on top of the test
# build, whose workspace features match), then pytest. pytest's exit code 5 (no tests
# collected) fails like any other.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/pyvenv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet maturin numpy pytest trimesh distributed
t=$(date +%s)
MATURIN_PEP517_ARGS="--profile dev" CARGO_TARGET_DIR="$PWD/target" "$venv/bin/pip" install --quiet --force-reinstall --no-deps ./python
echo "scripts/test_python.sh: pip install ./python: $(( $(date +%s) - t )) s"
# The tests compare with target/debug/glview, built by `cargo test --workspace` just before.
rc=0
GLVIEW_BIN="$PWD/target/debug/glview" "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "error: pytest collected no tests in python/tests" >&2
fi
exit "$rc"
