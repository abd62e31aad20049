#!/usr/bin/env bash
# Contact sheet for issue #39: Khronos samples with skins, morph targets and animations, each
# posed at one moment (--time) by the GPU and by the CPU reference renderer, beside the
# Khronos screenshot (an animated GIF's first frame: another moment, for what the model is).
# Reads the models from a bare clone of glTF-Sample-Assets ($ASSETS, default the
# DRx3D/glTF-Sample-Assets-OLD mirror of /work/.mirror), Models/NAME/glTF-Binary/NAME.glb.
# Writes docs/gltf/motion_sheet.jpg: per model, GPU (labelled with the name and time),
# reference, screenshot. Needs ImageMagick (montage, convert) and glview ($GLVIEW_BIN, else
# a release build).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${GLVIEW_BIN:-target/release/glview}
[ -x "$bin" ] || cargo build --release --quiet
assets=${ASSETS:-/work/.mirror/DRx3D+glTF-Sample-Assets-OLD/repo}
out=docs/gltf; tmp=$(mktemp -d); mkdir -p "$out"
size=${SIZE:-240}
tiles=()
add() { # name time [options...]
  local name=$1 t=$2 model="$tmp/$1.glb" shot
  shift 2
  git --git-dir="$assets" show "HEAD:Models/$name/glTF-Binary/$name.glb" >"$model"
  "$bin" "$model" --time "$t" --size ${size}x${size} "$@" -o "$tmp/$name-gpu.png"
  "$bin" "$model" --time "$t" --size ${size}x${size} "$@" --reference -o "$tmp/$name-ref.png"
  shot=$(git --git-dir="$assets" ls-tree --name-only HEAD "Models/$name/screenshot/" |
    grep -E '/screenshot\.(gif|png|jpg)$' | head -1)
  git --git-dir="$assets" show "HEAD:$shot" >"$tmp/$name-shot.${shot##*.}"
  convert "$tmp/$name-shot.${shot##*.}[0]" -resize ${size}x${size} -background gray20 \
    -gravity center -extent ${size}x${size} "$tmp/$name-khronos.png"
  tiles+=(-label "$name t=$t" "$tmp/$name-gpu.png" -label "reference" "$tmp/$name-ref.png"
    -label "Khronos" "$tmp/$name-khronos.png")
}
add CesiumMan 0.5
add RiggedSimple 1.25
add RiggedFigure 0.4
add AnimatedMorphCube 2.0
add BoxAnimated 1.5
add Fox 0.3 --animation Walk
montage "${tiles[@]}" -tile 6x -geometry +4+4 -pointsize 12 -background gray12 -fill white "$tmp/sheet.png"
convert "$tmp/sheet.png" -quality 85 "$out/motion_sheet.jpg"
echo "wrote $out/motion_sheet.jpg"
