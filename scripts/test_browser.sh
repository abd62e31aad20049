#!/usr/bin/env bash
# The browser tests of `glview serve` and `glview export` (python/tests_browser): Debian's
# Chromium driven by a pinned Playwright through executable_path, Firefox ESR over WebDriver
# BiDi. `playwright install` is never run (it downloads a browser, which these machines cannot
# reach and which we would not want to pin anyway). What they fetch (packages, the venv, the
# SCORM runtime and schemas) is scripts/prepare_tests.sh's, a no-op when already there.
# Needs target/debug/glview (built by `cargo build` or `cargo test --workspace` before).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/prepare_tests.sh
venv=target/pyvenv
echo "scripts/test_browser.sh: $(/usr/bin/chromium --version 2>/dev/null), $(/usr/bin/firefox-esr --version 2>/dev/null), playwright $("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("playwright"))')"
export SCORM_RUNTIME="$PWD/target/scorm-runtime/node_modules/scorm-again/dist/scorm12.js"
export SCORM_SCHEMAS="$PWD/target/scorm-schemas"

rc=0
GLVIEW_BIN="${GLVIEW_BIN:-$PWD/target/debug/glview}" \
  "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests_browser "$@" || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "error: pytest collected no tests in python/tests_browser" >&2
fi
exit "$rc"
