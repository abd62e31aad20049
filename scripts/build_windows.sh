#!/usr/bin/env bash
# glview.exe for x86_64-pc-windows-gnu: target/x86_64-pc-windows-gnu/<profile>/glview.exe.
#
#   bash scripts/build_windows.sh            # release (what a lab PC gets)
#   bash scripts/build_windows.sh --profile wine-test   # CI's quicker, unoptimised build for the Wine tests
#
# Uses rustup's target where it is installed (`rustup target add x86_64-pc-windows-gnu`), and
# otherwise Debian's rustc-web unpacked by ../shared/tools/cross-toolchain.sh, whose std is
# cross-built with -Zbuild-std (docs/windows.md; the recipe and its snags are measured in
# ../shared/notes/cross-builds.md). Either way the linker is Debian's MinGW gcc, and the .exe
# needs no MinGW DLL (checked here). Prints the .exe's path last. GLVIEW_CROSS=1 takes the
# cross toolchain even where rustup has the target.
set -euo pipefail
cd "$(dirname "$0")/.."
profile=release
while [ $# -gt 0 ]; do
  case $1 in
    --profile) profile=$2; shift 2 ;;
    *) echo "usage: $0 [--profile NAME]" >&2; exit 2 ;;
  esac
done
target=x86_64-pc-windows-gnu
sudo=; [ "$(id -u)" = 0 ] || sudo=sudo
if ! command -v x86_64-w64-mingw32-g++ >/dev/null; then
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64
fi
export CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=x86_64-w64-mingw32-gcc
# meshoptimizer is C++ and its build script links libstdc++ as a DLL, which a lab PC does not
# have. A folder that holds only the static archives, searched first, makes the MinGW linker
# take libstdc++.a (and the winpthread it needs) instead: the .exe imports system DLLs only.
static=$PWD/target/mingw-static
mkdir -p "$static"
ln -sf "$(x86_64-w64-mingw32-g++ -print-file-name=libstdc++.a)" "$static/libstdc++.a"
ln -sf "$(x86_64-w64-mingw32-gcc -print-file-name=libwinpthread.a)" "$static/libwinpthread.a"
ln -sf "$(x86_64-w64-mingw32-gcc -print-file-name=libwinpthread.a)" "$static/libpthread.a"
# `cargo rustc` gives the search path to the final link only (RUSTFLAGS would rebuild all).
build=(cargo rustc -p glview-cli --bin glview --target "$target" --profile "$profile")
link=(-- -L "native=$static")
if [ "${GLVIEW_CROSS:-}" != 1 ] && rustup target list --installed 2>/dev/null | grep -qx "$target"; then
  echo "build_windows: rustup's $target" >&2
  "${build[@]}" "${link[@]}"
else
  shared=${GLVIEW_SHARED:-../shared}
  cross_dir=${GLVIEW_CROSS_DIR:-/opt/glview-cross}
  echo "build_windows: no rustup target; Debian's rustc-web through $shared/tools/cross-toolchain.sh" >&2
  env_lines=$(GLVIEW_SHARED=$shared GLVIEW_CROSS_DIR=$cross_dir bash scripts/cross_env.sh)
  # The exports replace the compiler for this subshell only (the host build keeps rustup's).
  (eval "$env_lines" && "${build[@]}" -Zbuild-std=std,panic_abort "${link[@]}")
fi
dir=$profile; [ "$profile" = dev ] && dir=debug
exe=${CARGO_TARGET_DIR:-target}/$target/$dir/glview.exe
[ -f "$exe" ] || { echo "error: $exe was not built" >&2; exit 1; }
if dlls=$(x86_64-w64-mingw32-objdump -p "$exe" | grep -iE "DLL Name: (libstdc|libgcc|libwinpthread)"); then
  echo "error: $exe needs MinGW's DLLs: $dlls" >&2
  exit 1
fi
echo "$exe"
