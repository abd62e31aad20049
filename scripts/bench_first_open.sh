#!/usr/bin/env bash
# Issue #30's targets: the 2M-triangle sphere (glview bench --lod writes it) to a 1280x720
# PNG, each round interleaved: a first open with an empty mesh cache (time to the PNG and to
# the process's end), a cold --no-cache run, a cached run, a cold run without levels of detail
# (--lod off), and f3d under Xvfb; medians of 3 and their ratios to f3d's.
# Needs a release build, f3d and Xvfb. Usage: scripts/bench_first_open.sh [MODEL]
set -euo pipefail
cd "$(dirname "$0")/.."
model=${1:-${XDG_CACHE_HOME:-$HOME/.cache}/glview/bench/sphere_1999396.obj}
[ -f "$model" ] || { echo "no $model: run glview bench --lod --quick first" >&2; exit 1; }
glview=$PWD/target/release/glview
work=$(mktemp -d)
export GLVIEW_CACHE_DIR=$work/cache
Xvfb :97 -screen 0 1920x1080x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb; rm -rf "$work"' EXIT
t() { local s; s=$(date +%s.%N); "$@" >/dev/null 2>&1; echo "$(date +%s.%N) - $s" | bc; }
for _ in 1 2 3; do
  rm -rf "$work/cache"
  s=$(date +%s.%N)
  "$glview" "$model" -o "$work/first.png" --size 1280x720 >/dev/null 2>&1
  e=$(date +%s.%N)
  echo "first_png $(echo "$(stat -c %.Y "$work/first.png") - $s" | bc)"
  echo "first_exit $(echo "$e - $s" | bc)"
  echo "cold $(t "$glview" "$model" -o "$work/c.png" --size 1280x720 --no-cache)"
  echo "cached $(t "$glview" "$model" -o "$work/h.png" --size 1280x720)"
  echo "cold_lod_off $(t "$glview" "$model" -o "$work/n.png" --size 1280x720 --no-cache --lod off)"
  echo "f3d $(t env DISPLAY=:97 f3d --output "$work/f.png" --resolution 1280,720 "$model")"
done >"$work/runs.txt"
median() { grep "^$1 " "$work/runs.txt" | cut -d' ' -f2 | sort -n | sed -n 2p; }
f3d=$(median f3d)
for w in first_png first_exit cold cold_lod_off cached f3d; do
  m=$(median "$w")
  echo "$w $m s (median of 3), $(echo "scale=3; $m / $f3d" | bc)x f3d"
done
