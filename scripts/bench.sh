#!/usr/bin/env bash
# Runs glview's benchmarks and writes their results into docs/bench/:
#   quality (run time against error for every shadow/shading knob): quality.csv/.json/.png
#   load (parse, upload, time to PNG, peak memory against f3d):     load.csv/.json
#   frame (the 1M-triangle sphere's and the dragon's frame, culled or not): printed
# Installs what they need first (Debian: Mesa for headless GL, f3d and Xvfb for the peer,
# GNU time for peak memory, a font for the plot). Options after the script's own are passed
# to every run, e.g. `scripts/bench.sh --quick`. `--quality`, `--load` or `--frame` runs one only.
# About 10 minutes on a 2-core machine (1 with --quick); other load on the machine skews times.
set -euo pipefail
cd "$(dirname "$0")/.."

which=both
if [ "${1:-}" = "--quality" ] || [ "${1:-}" = "--load" ] || [ "${1:-}" = "--frame" ]; then
  which=${1#--}
  shift
fi

bash scripts/deps.sh
pkgs=(f3d xvfb time fonts-dejavu-core)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if command -v apt-get >/dev/null; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "bench: installing ${missing[*]}" >&2
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
  else
    echo "bench: please install ${missing[*]} (the load bench runs without f3d otherwise)" >&2
  fi
fi
if [ ! -f ../shared/MANIFEST.md ]; then
  echo "error: ../shared (the shared test models) is missing beside the repository" >&2
  exit 1
fi

cargo build --release --quiet
glview=target/release/glview
if [ "$which" = both ] || [ "$which" = quality ]; then
  "$glview" bench "$@"
fi
if [ "$which" = both ] || [ "$which" = load ]; then
  "$glview" bench --load "$@"
fi
if [ "$which" = both ] || [ "$which" = frame ]; then
  "$glview" bench --frame "$@"
fi
