#!/usr/bin/env bash
# Prints the environment of the cross toolchain (Debian's rustc-web, unpacked by
# ../shared/tools/cross-toolchain.sh) for scripts/build_windows.sh and scripts/check_wasm.sh.
# That script checks its packages with apt-get update each time (~10 s); its output is kept
# beside the toolchain and asked for again only when the toolchain changed.
set -euo pipefail
cross_dir=${GLVIEW_CROSS_DIR:-/opt/glview-cross}
kept=$cross_dir/glview-env.sh
if [ ! -s "$kept" ] || [ ! -f "$cross_dir/.versions" ] || [ "$kept" -ot "$cross_dir/.versions" ]; then
  out=$(bash "${GLVIEW_SHARED:-$(dirname "$0")/../../shared}/tools/cross-toolchain.sh" "$cross_dir")
  printf '%s\n' "$out" >"$kept"
fi
cat "$kept"
