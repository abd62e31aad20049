#!/usr/bin/env bash
# Issue #22's batch row: 100 pictures of real models (the 25 models of ../shared/models and
# ../shared/gltf-samples, 4 views each, 640x480) rendered by `glview batch` in one process,
# by glview one process per picture (`--compare-processes`), and by f3d 1.3.1 one process
# per picture (it has no batch mode; under one Xvfb). Medians of 3, interleaved. A benchmark,
# not a test. Needs a release build, f3d and Xvfb. Usage: scripts/bench_batch_vs_f3d.sh
set -euo pipefail
cd "$(dirname "$0")/.."
shared=$(cd .. && pwd)/shared
work=${TMPDIR:-/tmp}/glview-batch-bench
rm -rf "$work" && mkdir -p "$work/out" "$work/f3d"
models=()
for f in "$shared"/models/*/*.obj "$shared"/gltf-samples/*/*.gl[tb]*; do models+=("$f"); done
jobs=$work/jobs.txt
: >"$jobs"
n=0
for m in "${models[@]}"; do
  for yaw in 0 90 180 270; do
    echo "\"$m\" --size 640x480 --yaw $yaw -o $work/out/$n.png" >>"$jobs"
    n=$((n + 1))
  done
done
echo "$n pictures of ${#models[@]} models" >&2
glview=target/release/glview
Xvfb :98 -screen 0 1920x1080x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb' EXIT
seconds() { local s; s=$(date +%s.%N); "$@" >/dev/null 2>&1 || true; echo "$(date +%s.%N) - $s" | bc; }
f3d_all() {
  local i=0
  for m in "${models[@]}"; do
    for _ in 0 90 180 270; do
      DISPLAY=:98 f3d --output "$work/f3d/$i.png" --resolution 640,480 "$m" >/dev/null 2>&1 || true
      i=$((i + 1))
    done
  done
}
processes() {
  # One glview process per job line, as a shell script would run them.
  while IFS= read -r line; do eval "$glview $line" >/dev/null 2>&1 || true; done <"$jobs"
}
"$glview" batch "$jobs" >/dev/null 2>&1 || true # warm: mesh and environment caches
for _ in 1 2 3; do
  echo "batch $(seconds "$glview" batch "$jobs")"
  echo "processes $(seconds processes)"
  echo "f3d $(seconds f3d_all)"
done >"$work/runs.txt"
for w in batch processes f3d; do
  t=$(grep "^$w " "$work/runs.txt" | cut -d' ' -f2 | sort -n | sed -n 2p)
  echo "$w $t s (median of 3), $(echo "scale=1; $n / $t" | bc) pictures/s"
done
