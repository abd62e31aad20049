#!/usr/bin/env bash
# Installs what the tests need on a fresh Debian machine, then runs every check:
# formatting, clippy (warnings are errors) and the whole test suite on llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# Printed on success and on failure, so CI logs always show how long the suite took.
# Background steps (below) still running when a foreground step fails are stopped, with
# their children (an orphaned rustdoc would hold cargo's build lock, an orphaned pytest use
# binaries a re-run rebuilds), and their logs shown.
bg_pids=()
bg_logs=()
bg_names=()
kill_tree() {
  local c
  for c in $(pgrep -P "$1" || true); do kill_tree "$c"; done
  kill "$1" 2>/dev/null || true
}
finish() {
  local rc=$? k
  for k in "${!bg_pids[@]}"; do
    [ -n "${bg_pids[$k]}" ] || continue
    kill_tree "${bg_pids[$k]}"
    wait "${bg_pids[$k]}" 2>/dev/null || true
    echo "scripts/test.sh: step '${bg_names[$k]}' (in the background) stopped; its log:"
    cat "${bg_logs[$k]}"
    rm -f "${bg_logs[$k]}"
  done
  [ -z "${prep_done:-}" ] || rm -f "$prep_done"
  echo "scripts/test.sh: $(( $(date +%s) - start )) s (exit $rc)"
}
trap finish EXIT
# Each step prints its own duration, so a slow CI run says which step to look at.
step() {
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  echo "scripts/test.sh: step '$name' $(( $(date +%s) - t0 )) s"
}
# A step in the background at nice 19, its log printed when it is collected.
background() {
  local name=$1 log
  shift
  log=$(mktemp)
  (
    t0=$(date +%s)
    nice -n 19 "$@"
    echo "scripts/test.sh: step '$name' (in the background) $(($(date +%s) - t0)) s"
  ) >"$log" 2>&1 &
  bg_pids+=("$!")
  bg_logs+=("$log")
  bg_names+=("$name")
}
# Waits for background step $1 (its index), prints its log, and fails if it failed.
collect() {
  local k=$1 rc=0
  wait "${bg_pids[$k]}" || rc=$?
  bg_pids[k]=""
  cat "${bg_logs[$k]}"
  rm -f "${bg_logs[$k]}"
  [ "$rc" -eq 0 ] || { echo "error: step '${bg_names[$k]}' failed (above)" >&2; exit "$rc"; }
}
step deps bash scripts/deps.sh --tests
if [ ! -f ../shared/MANIFEST.md ]; then
  echo "error: ../shared (test models and conformance files) is missing beside the repository" >&2
  exit 1
fi
step fmt cargo fmt --all --check
# The library is what Python, Dask and the server hold: none of the command line's, the
# window's or the tools' crates may reach it (cli/ has them).
lib_deps() {
  local bad
  bad=$(cargo tree -p glview -e normal --prefix none | awk '{print $1}' |
    grep -xE 'clap|winit|glutin-winit|indicatif|plotters|shlex|env_logger' | sort -u || true)
  if [ -n "$bad" ]; then
    echo "error: the glview library depends on: $bad" >&2
    return 1
  fi
  echo "glview library: $(cargo tree -p glview -e normal --prefix none | sort -u | wc -l) crates, none of clap/winit/indicatif/plotters/shlex"
  # The crate boundaries are the platform boundaries (docs/design.md, "Layout"): the renderer
  # holds no context, window or loaded library, the scene crate without `native` no C++.
  bad=$(cargo tree -p glview-render -e normal --prefix none | awk '{print $1}' |
    grep -xE 'glview|glutin|glutin-winit|winit|libloading|khronos-egl|meshopt|tokio' | sort -u || true)
  if [ -n "$bad" ]; then
    echo "error: glview-render depends on: $bad" >&2
    return 1
  fi
  bad=$(cargo tree -p glview-scene --no-default-features -e normal --prefix none | awk '{print $1}' |
    grep -xE 'glview|glview-render|glow|glutin|winit|libloading|meshopt' | sort -u || true)
  if [ -n "$bad" ]; then
    echo "error: glview-scene without its native feature depends on: $bad" >&2
    return 1
  fi
  echo "glview-render: no glutin/winit/libloading/meshopt; glview-scene (no native): no GL, contexts or C++ (rayon runs on the calling thread in wasm32)"
}
step "library dependencies" lib_deps
# The Python and browser steps' downloads (system packages, the venv's pinned packages, the
# SCORM runtime and schemas: scripts/prepare_tests.sh) run in the background beside the Rust
# build, whose cores they barely use; the test step waits for them.
prep_log=$(mktemp)
# Written when prepare has the cross toolchain ready, or when it ends, failed or not (a
# finished but unreaped process still answers `kill -0`, so the platforms job below waits
# for this file instead).
prep_done=$(mktemp -u)
(
  t0=$(date +%s)
  rc=0
  GLVIEW_CROSS_READY=$prep_done bash scripts/prepare_tests.sh || rc=$?
  touch "$prep_done"
  echo "scripts/test.sh: step 'prepare' (in the background) $(($(date +%s) - t0)) s"
  exit "$rc"
) >"$prep_log" 2>&1 &
prep_pid=$!
# The platforms the labs have: glview.exe built (unoptimised: the Wine tests compare
# pictures, not speed; scripts/build_windows.sh; the wasm32 build is the `web` job's below). ~7.7 min of CPU on a fresh machine (the cross compiler builds
# std for both targets and its own host build scripts), which at nice 19 takes what the Linux
# build's serial stretches (one crate's front end at a time), the tests and the browser step
# leave idle. It starts once `prepare` has unpacked the cross toolchain and installed MinGW
# (that holds apt's lock; the browser's packages come after, and the job needs no apt); in its own target folder, so its cargo holds no lock the build's, the tests' or
# rustdoc's waits on; without the clippy-driver wrapper (rustup's, with no std source).
background platforms bash -c 'for _ in $(seq 600); do [ -e '"$prep_done"' ] && break; sleep 1; done
  unset RUSTC_WORKSPACE_WRAPPER CLIPPY_ARGS; export CARGO_TARGET_DIR=target/cross
  bash scripts/build_windows.sh --profile wine-test'
# The browser build (scripts/build_web.sh, docs/web.md): wasm-bindgen-cli installed unoptimised
# (~80 s of CPU) at once (it needs no cross toolchain), then glview-web for wasm32 in the same unoptimised profile and target folder
# as glview.exe (~120 s of CPU; the host's build scripts are shared), bound without wasm-opt.
# It is also CI's wasm32 check: it compiles the scene (without `native`) and render crates
# that scripts/check_wasm.sh checks, and guards the same dependency tree; check_wasm.sh's
# rustdoc pass (-D warnings) is left to developers, as the library's `cargo doc` is (the
# check it needs was ~2 min of CPU this job could not spare). Beside the platforms job at
# the same nice level, for the same idle cycles.
background web bash -c 'unset RUSTC_WORKSPACE_WRAPPER CLIPPY_ARGS; export CARGO_TARGET_DIR=target/cross
  GLVIEW_WEB_TOOLS_ONLY=1 bash scripts/build_web.sh
  for _ in $(seq 600); do [ -e '"$prep_done"' ] && break; sleep 1; done
  GLVIEW_CROSS=1 GLVIEW_WASM_OPT=none bash scripts/build_web.sh --profile wine-test'
# Clippy runs inside the test build instead of as `cargo clippy` before it: clippy-driver as
# the workspace wrapper lints every target `cargo clippy --all-targets` lints (lib, bins, tests,
# their test builds; the crate has no examples or benches) while compiling them for real, so the
# tree is compiled once instead of twice (a check build, then the test build) — the clean CI
# run's longest step. This is what `cargo clippy` itself does, with `check` instead of `build`.
# `build --workspace --all-targets` rather than `test --no-run`: it builds the same test
# binaries (`cargo test` below finds them fresh) and also the Python binding's extension
# (python/ has no test target, so `test --no-run` skipped it), with the workspace's unified
# features, so scripts/test_python.sh installs that file instead of compiling the library a
# second time under maturin's per-package features (~110 s of a clean run).
# A clean CI build gains nothing from incremental compilation's caches and pays for writing
# them; a developer's runs keep them (the flag is part of cargo's fingerprint).
if [ "${CI:-}" = true ]; then
  export CARGO_INCREMENTAL=0
fi
clippy_driver=$(rustup which clippy-driver 2>/dev/null || command -v clippy-driver)
export RUSTC_WORKSPACE_WRAPPER=$clippy_driver
export CLIPPY_ARGS="-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__"
step "build + clippy -D warnings" cargo build --workspace --all-targets --quiet
# The downloads are waited for here (long done: they take ~25 s, the build ~5 min): the
# three.js poses test (tests/suite/gltf_motion_threejs.rs) runs node with its pinned three.js.
prep_rc=0
wait "$prep_pid" || prep_rc=$?
cat "$prep_log"
# prep_done stays until the end (finish): the web job looks for it after installing its tools,
# which can end after this point.
rm -f "$prep_log"
[ "$prep_rc" -eq 0 ] || { echo "error: scripts/prepare_tests.sh failed (above)" >&2; exit "$prep_rc"; }
# The Python package's tests, in the background beside the Rust tests, niced so that the tests
# come first: the Rust tests keep about a quarter of the two cores idle (tests waiting on
# sockets, timeouts and child processes). Docs with -D warnings (scripts/check_wasm.sh for the
# scene and render crates, `cargo doc -p glview` for the library) each re-check every
# dependency (~2 min of CPU) and are left to developers (docs/testing.md), to keep CI within
# its 15 minutes.
background python bash scripts/test_python.sh
step test cargo test --workspace --no-fail-fast 2>&1
# The before/after picture checker of refactors (scripts/pictures_unchanged.sh) still tells
# equal, different and failed renders apart.
step "pictures checker self-test" bash scripts/pictures_unchanged.sh --self-test --after-bin target/debug/glview
collect 2
# The page of `glview serve` in Debian's Chromium, driven by a pinned Playwright: alone, as
# its pages wait on frames with timeouts.
step browser bash scripts/test_browser.sh
collect 0
# glview.exe, built in the background above, held to the Linux binary under Wine: alone, as
# its window test waits on frames.
step "windows (Wine)" bash scripts/test_windows.sh target/cross/x86_64-pc-windows-gnu/wine-test/glview.exe target/debug/glview
# glview's renderer in the browser, built in the background above: the viewer page and the
# live lesson page of `glview export --live` in Chromium against `glview -o` (python/tests_web).
# Nothing else runs by then: two pytest workers (pytest-xdist), each with its own browser and
# server, keep both cores busy (the every-program compiles are single-threaded): 210 s → 131 s
# here on an idle machine.
collect 1
step "web (Chromium)" bash scripts/test_web.sh -n 2
