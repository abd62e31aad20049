#!/usr/bin/env bash
# Contact sheet for issue #19: glview's renders of every glTF sample, legacy (Phong) and PBR
# tier, beside the Khronos glTF-Sample-Viewer's screenshot (default camera and light kit,
# built-in sky).
# Reads ../shared/gltf-samples (always) and any extra model folders given as arguments (NAME/glTF/NAME.gltf + NAME/screenshot/screenshot*.{png,jpg}, the
# glTF-Sample-Assets layout; a folder without a screenshot gets a "no reference" tile).
# Writes docs/gltf/sheet.jpg: per model, Phong (labelled with the name), PBR, the reference.
# Needs ImageMagick (montage, convert) and glview ($GLVIEW_BIN, else a release build).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${GLVIEW_BIN:-target/release/glview}
[ -x "$bin" ] || cargo build --release --quiet
out=docs/gltf; tmp=$(mktemp -d); mkdir -p "$out"
size=${SIZE:-200}
tiles=()
add() { # name model reference
  local name=$1 model=$2 ref=$3 log shading
  for shading in phong pbr; do
    if log=$("$bin" "$model" --shading $shading --size ${size}x${size} -o "$tmp/$name-$shading.png" 2>&1); then :; else
      convert -size ${size}x${size} xc:gray20 -fill white -annotate +10+20 "error" "$tmp/$name-$shading.png"; fi
    echo "$name $shading: ${log:-ok}" | head -3
  done
  if [ -n "$ref" ]; then
    convert "$ref" -resize ${size}x${size} -background gray20 -gravity center -extent ${size}x${size} "$tmp/$name-ref.png"
  else
    convert -size ${size}x${size} xc:gray20 -fill white -annotate +10+20 "no reference" "$tmp/$name-ref.png"
  fi
  # Labels stay shorter than a tile: the name under the Phong tile, the tier or source under
  # the others (a long name under every tile ran into its neighbours).
  tiles+=(-label "$name" "$tmp/$name-phong.png" -label "PBR" "$tmp/$name-pbr.png"
    -label "reference" "$tmp/$name-ref.png")
}
for d in ../shared/gltf-samples/*/; do
  n=$(basename "$d"); m=$(ls "$d"*.gl* | head -1); r=$(ls "$d"reference.* | head -1)
  add "$n" "$m" "$r"
done
for d in "$@"; do
  n=$(basename "$d"); m=$(ls "$d"/glTF/*.gltf 2>/dev/null | head -1) || true
  [ -n "$m" ] || m=$(ls "$d"/glTF-Binary/*.glb | head -1)
  r=$(ls "$d"/screenshot/screenshot.* "$d"/screenshot/*.{png,jpg} 2>/dev/null | head -1) || true
  add "$n" "$m" "$r"
done
montage "${tiles[@]}" -tile 9x -geometry +4+4 -pointsize 12 -background gray12 -fill white "$tmp/sheet.png"
convert "$tmp/sheet.png" -quality 85 "$out/sheet.jpg"
echo "wrote $out/sheet.jpg"
