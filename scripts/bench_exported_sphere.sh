#!/usr/bin/env bash
# Issue #22's model: a 1M-triangle UV sphere as exporters write it (seam column twice, off by
# sin 2π; poles repeated per segment), timed to a 1280x720 PNG: glview cold (--no-cache),
# glview with its mesh cache warm, f3d 1.3.1 (under one Xvfb); medians of 3, interleaved.
# Needs a release build, python3, f3d and Xvfb. Usage: scripts/bench_exported_sphere.sh [MODEL]
set -euo pipefail
cd "$(dirname "$0")/.."
work=${TMPDIR:-/tmp}/glview-exported-sphere
mkdir -p "$work"
model=${1:-$work/exported_sphere_1m.obj}
if [ ! -f "$model" ]; then
  python3 - "$model" <<'PY'
import math, sys
R, S = 500, 1000
with open(sys.argv[1], "w") as f:
    for j in range(R + 1):
        th = math.pi * j / R
        f.write("".join(
            f"v {x!r} {y!r} {z!r}\nvn {x!r} {y!r} {z!r}\n"
            for x, y, z in ((math.sin(th) * math.sin(2 * math.pi * i / S), math.cos(th),
                             math.sin(th) * math.cos(2 * math.pi * i / S)) for i in range(S + 1))))
    at = lambda j, i: 1 + j * (S + 1) + i
    for j in range(R):
        f.write("".join(
            f"f {a}//{a} {b}//{b} {c}//{c}\nf {a}//{a} {c}//{c} {d}//{d}\n"
            for a, b, c, d in ((at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i + 1))
                               for i in range(S))))
PY
fi
glview=target/release/glview
export GLVIEW_CACHE_DIR=$work/cache
Xvfb :97 -screen 0 1920x1080x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb' EXIT
seconds() { local s; s=$(date +%s.%N); "$@" >/dev/null 2>&1; echo "$(date +%s.%N) - $s" | bc; }
"$glview" "$model" -o "$work/warm.png" --size 1280x720 >/dev/null 2>&1
for _ in 1 2 3; do
  echo "cold $(seconds "$glview" "$model" -o "$work/c.png" --size 1280x720 --no-cache)"
  echo "cached $(seconds "$glview" "$model" -o "$work/h.png" --size 1280x720)"
  echo "f3d $(seconds env DISPLAY=:97 f3d --output "$work/f.png" --resolution 1280,720 "$model")"
done >"$work/runs.txt"
for w in cold cached f3d; do
  echo "$w $(grep "^$w " "$work/runs.txt" | cut -d' ' -f2 | sort -n | sed -n 2p) s (median of 3)"
done
"$glview" "$model" -o "$work/s.png" --size 1280x720 --stats | tail -1
