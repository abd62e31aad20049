#!/usr/bin/env bash
# The browser build's benchmark (python/bench/bench_web.py): time to the first live frame of
# `glview export --live-only` pages (built-in scene, 200k dragon), frames/s dragging in
# Chromium against native glview on the same machine, page and wasm sizes. Builds target/web
# when missing (release, wasm-opt where a binaryen is found: scripts/build_web.sh) and needs
# target/debug/glview. BENCH_WEB_RUNS (5), BENCH_WEB_SIZE (640x480).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f target/web/glview_web_bg.wasm ] || bash scripts/build_web.sh
bash scripts/prepare_tests.sh >/dev/null
exec target/pyvenv/bin/python python/bench/bench_web.py "$@"
