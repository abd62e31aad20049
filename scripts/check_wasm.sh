#!/usr/bin/env bash
# The scene and render crates build for wasm32-unknown-unknown (the browser build's next
# step): `cargo check` of both, the scene crate without its `native` feature (no mesh cache,
# threads or C++ meshoptimizer). rustup's target where it is installed, else Debian's
# rustc-web from ../shared/tools/cross-toolchain.sh with std checked from source
# (-Zbuild-std). GLVIEW_CROSS=1 takes the second path even where rustup has the target.
set -euo pipefail
cd "$(dirname "$0")/.."
target=wasm32-unknown-unknown
# The wine-test profile, as scripts/build_windows.sh's CI build: the build scripts and proc
# macros the cross compiler makes for the host are then made once for both.
check=(cargo check --quiet --profile wine-test --target "$target" -p glview-scene -p glview-render --no-default-features)
# Then their docs without a warning (broken links, bad code blocks), from the same check
# metadata: the rustdoc pass costs seconds, where the library's own `cargo doc` re-checked
# every dependency (~2 min of CPU in CI).
doc=(cargo doc --quiet --no-deps --profile wine-test --target "$target" -p glview-scene -p glview-render --no-default-features)
export RUSTDOCFLAGS="-D warnings"
if [ "${GLVIEW_CROSS:-}" != 1 ] && rustup target list --installed 2>/dev/null | grep -qx "$target"; then
  "${check[@]}" && "${doc[@]}"
else
  env_lines=$(bash scripts/cross_env.sh)
  (eval "$env_lines" && "${check[@]}" -Zbuild-std=std,panic_abort && "${doc[@]}" -Zbuild-std=std,panic_abort)
fi
# What must never be in the browser build: the native contexts and file-system crates.
bad=$(cargo tree --target "$target" -p glview-render -e normal --prefix none 2>/dev/null |
  awk '{print $1}' | grep -xE 'glutin|libloading|winit|meshopt|khronos-egl' | sort -u || true)
[ -z "$bad" ] || { echo "error: the wasm32 build of glview-render depends on: $bad" >&2; exit 1; }
echo "check_wasm: glview-scene and glview-render check and document for $target"
