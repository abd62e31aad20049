#!/usr/bin/env bash
# The browser build against the native binary (python/tests_web): glview's renderer compiled
# to wasm32 (scripts/build_web.sh, target/web) in Debian's Chromium on SwiftShader, driven by
# the pinned Playwright of scripts/prepare_tests.sh, its canvas held to `glview -o` of the
# same options (WebGL 2 both tiers, the window's keys, WebGL 1's legacy tier against the GL
# 2.1 override). Builds target/web when it is missing (GLVIEW_WEB_REBUILD=1: always).
# Needs target/debug/glview (cargo build).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${GLVIEW_WEB_REBUILD:-}" = 1 ] || [ ! -f target/web/glview_web_bg.wasm ]; then
  bash scripts/build_web.sh
fi
bash scripts/prepare_tests.sh
venv=target/pyvenv
echo "scripts/test_web.sh: $(/usr/bin/chromium --version 2>/dev/null), playwright $("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("playwright"))')"
GLVIEW_BIN="${GLVIEW_BIN:-$PWD/target/debug/glview}" \
  "$venv/bin/python" -m pytest -q -s -p no:cacheprovider --durations=8 python/tests_web "$@"
