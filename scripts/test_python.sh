#!/usr/bin/env bash
# The Python package's tests (python/tests), run by scripts/test.sh after the Rust tests:
# a venv in target/pyvenv holding the package as the test build made it, then pytest.
#
# The extension is the one `cargo test --workspace` (scripts/test.sh, just before) already
# compiled and linted: target/debug/lib_glview.so, placed as glview/_glview.abi3.so beside
# python/glview's modules in the venv (what `maturin develop` does). Building it again with
# `pip install ./python` cost ~110 s of a clean CI run: maturin builds the binding with
# `cargo rustc` on python/Cargo.toml alone, whose features differ from the workspace's
# unified ones (log, bitflags, ... come with the window's crates), so the library and half
# its dependencies compiled twice — and pip downloads maturin into an isolated env each time.
# `--pip-install` runs the user's install instead (release profile), for checking packaging.
# pytest's exit code 5 (no tests collected) fails like any other.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/pyvenv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet -r python/tests/requirements.txt
if [ "${1:-}" = "--pip-install" ]; then
  shift
  "$venv/bin/pip" install --quiet maturin
  CARGO_TARGET_DIR="$PWD/target" "$venv/bin/pip" install --quiet --force-reinstall --no-deps ./python
else
  so=target/debug/lib_glview.so
  [ -f "$so" ] || { echo "error: $so is missing: run cargo build --workspace --all-targets first (scripts/test.sh does)" >&2; exit 1; }
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  "$venv/bin/pip" uninstall --quiet --yes glview >/dev/null 2>&1 || true
  rm -rf "$site/glview"
  cp -r python/glview "$site/glview"
  cp "$so" "$site/glview/_glview.abi3.so"
fi
# The tests compare with target/debug/glview, built by `cargo test --workspace` just before.
rc=0
GLVIEW_BIN="$PWD/target/debug/glview" "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests "$@" || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "error: pytest collected no tests in python/tests" >&2
fi
exit "$rc"
