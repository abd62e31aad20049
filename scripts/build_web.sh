#!/usr/bin/env bash
# Builds the browser viewer (web/, the glview-web crate) into target/web/: glview_web_bg.wasm
# and glview_web.js (wasm-bindgen's plain ES module, no bundler), the page (web/page/) beside
# them. Prints each step's time and the sizes (raw, after wasm-opt where it ran, gzipped).
#
#   bash scripts/build_web.sh [--debug | --profile NAME]
#
# CI builds with --profile wine-test (unoptimised, as glview.exe's test build, in the same
# target folder: the host's build scripts and proc macros are made once for both; 32 MB of
# wasm that draws the same pictures, ~70 s instead of ~145 s). Cargo's CARGO_TARGET_DIR is
# followed.
# The compiler: rustup's wasm32-unknown-unknown target where it is installed, else Debian's
# rustc-web from ../shared/tools/cross-toolchain.sh with std built from source (-Zbuild-std),
# as scripts/check_wasm.sh; GLVIEW_CROSS=1 takes the second path even where rustup has it.
# wasm-bindgen-cli must be the version of the `wasm-bindgen` crate in Cargo.lock (its schema
# changes between versions): `cargo install`ed into GLVIEW_WEB_TOOLS (default
# target/web-tools) when missing there (~3 min once, 7 min on a loaded machine). wasm-opt runs
# where a working binaryen is in the tools folder (npm's), on PATH, or GLVIEW_WASM_OPT names
# one (-Oz: ~80 s, 7.1 -> 5.7 MB; Debian's binaryen 108 corrupts wasm-bindgen
# modules unless they are built for the MVP, so the build is MVP then: -Ctarget-cpu=mvp);
# without one the step is skipped and said so.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=release
case "${1:-}" in
  --debug) profile=debug ;;
  --profile) profile=${2:?--profile needs a name} ;;
  "") ;;
  *) echo "usage: bash scripts/build_web.sh [--debug | --profile NAME]" >&2; exit 2 ;;
esac
target_dir=${CARGO_TARGET_DIR:-target}
target=wasm32-unknown-unknown
out=target/web
tools=${GLVIEW_WEB_TOOLS:-$PWD/target/web-tools}
t() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(t)" 'BEGIN { printf "%.1f", b - a }'; }

bindgen_version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
[ -n "$bindgen_version" ] || { echo "error: no wasm-bindgen in Cargo.lock" >&2; exit 2; }
bindgen=$tools/bin/wasm-bindgen
if ! { [ -x "$bindgen" ] && "$bindgen" --version | grep -q " $bindgen_version\$"; }; then
  t0=$(t)
  echo "build_web: installing wasm-bindgen-cli $bindgen_version into $tools"
  # --locked fails here (the CLI's own lock names a yanked version): a plain install.
  # --debug: an unoptimised CLI compiles in ~80 s of CPU instead of ~380 s (measured on this
  # machine) and still binds the 7 MB module in a few seconds; it runs once per build.
  cargo install --quiet --debug --root "$tools" --version "=$bindgen_version" wasm-bindgen-cli
  echo "build_web: wasm-bindgen-cli installed in $(since "$t0") s"
fi
# GLVIEW_WEB_TOOLS_ONLY=1: only the tools (CI installs them before the cross toolchain is
# unpacked, which the build needs and they do not).
[ "${GLVIEW_WEB_TOOLS_ONLY:-}" = 1 ] && exit 0

# npm's binaryen in the tools folder (`npm install --prefix target/web-tools binaryen@132`,
# ~2 s) before one on PATH.
npm_opt=$tools/node_modules/.bin/wasm-opt
[ -x "$npm_opt" ] || npm_opt=""
wasm_opt=${GLVIEW_WASM_OPT:-${npm_opt:-$(command -v wasm-opt || true)}}
# GLVIEW_WASM_OPT=none skips it (a quick rebuild while developing: -Oz takes ~80 s).
[ "$wasm_opt" = none ] && wasm_opt=
mvp=0
if [ -n "$wasm_opt" ] && "$wasm_opt" --version 2>/dev/null | grep -qE 'version (1[01][0-9]|[0-9]{1,2})([^0-9]|$)'; then
  # binaryen <= 119 (Debian 12 has 108): only MVP modules survive it (see the notes).
  mvp=1
fi
flags=(--cfg 'getrandom_backend="wasm_js"')
[ "$mvp" = 1 ] && flags+=(-Ctarget-cpu=mvp)
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS="${flags[*]}"
build=(cargo build --quiet --target "$target" -p glview-web --profile "$profile")
[ "$profile" = debug ] && build=(cargo build --quiet --target "$target" -p glview-web)
t0=$(t)
if [ "${GLVIEW_CROSS:-}" != 1 ] && rustup target list --installed 2>/dev/null | grep -qx "$target"; then
  "${build[@]}"
else
  env_lines=$(bash scripts/cross_env.sh)
  (eval "$env_lines" && "${build[@]}" -Zbuild-std=std,panic_abort)
fi
echo "build_web: cargo build ($profile, $target) $(since "$t0") s"
wasm=$target_dir/$target/$profile/glview_web.wasm

t0=$(t)
rm -rf "$out"
mkdir -p "$out"
"$bindgen" --target web --no-typescript --out-dir "$out" "$wasm"
# The same module's glue as a classic script (a global `wasm_bindgen`), for the lesson page of
# `glview export --live`, which inlines it: an inline module script cannot import its wasm.
# Both glues name the same functions of the same .wasm, so the page takes the one optimised
# below (wasm-bindgen writes identical .wasm files for both targets).
"$bindgen" --target no-modules --no-typescript --out-dir "$out/no-modules" "$wasm"
rm -f "$out/no-modules/glview_web_bg.wasm"
echo "build_web: wasm-bindgen $(since "$t0") s"
bg=$out/glview_web_bg.wasm
raw=$(stat -c %s "$bg")
opt=""
if [ -n "$wasm_opt" ]; then
  t0=$(t)
  "$wasm_opt" -Oz --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
    $([ "$mvp" = 1 ] || echo --enable-reference-types --enable-multivalue) \
    "$bg" -o "$bg.opt" && mv "$bg.opt" "$bg"
  opt=$(stat -c %s "$bg")
  echo "build_web: wasm-opt -Oz $(since "$t0") s ($("$wasm_opt" --version))"
else
  echo "build_web: wasm-opt skipped: no binaryen on PATH (GLVIEW_WASM_OPT names one; Debian's 108 needs the MVP build it makes then)"
fi
cp web/page/* "$out/"
# What must never be in the browser build (scripts/check_wasm.sh's guard: CI's wasm32 check is
# this build, which compiles everything that check checks).
bad=$(cargo tree --target "$target" -p glview-web -e normal --prefix none 2>/dev/null |
  awk '{print $1}' | grep -xE 'glutin|libloading|winit|meshopt|khronos-egl|glview|tokio' | sort -u || true)
[ -z "$bad" ] || { echo "error: the wasm32 build of glview-web depends on: $bad" >&2; exit 1; }
gz=$(gzip -9 -c "$bg" | wc -c)
echo "build_web: $bg: raw $raw bytes${opt:+, after wasm-opt $opt}, gzipped $gz"
echo "build_web: serve $out over HTTP (a module cannot load from file://) and open index.html"
