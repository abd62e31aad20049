#!/usr/bin/env bash
# Contact sheet for issue #32: the Khronos extension samples in the PBR tier (GPU), the CPU
# reference of the same frame (Monte Carlo, --reference-samples 256) and the Khronos
# screenshot, one row per model; and the GPU-against-reference numbers (share of the model's
# pixels more than 8/255 apart, mean, 1 − SSIM) from `--diff pbr,reference-pbr`.
# Arguments: model folders in the glTF-Sample-Assets layout (NAME/glTF/NAME.gltf,
# NAME/screenshot/screenshot.jpg). Writes docs/gltf/khr_sheet.jpg and prints a Markdown
# table. Needs ImageMagick (montage, convert) and glview ($GLVIEW_BIN, else target/debug).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${GLVIEW_BIN:-target/debug/glview}
out=docs/gltf; tmp=$(mktemp -d); mkdir -p "$out"
size=${SIZE:-256}
tiles=()
echo "| model | pixels > 8/255 | mean (1/255) | 1 − SSIM |"
echo "|---|---|---|---|"
for d in "$@"; do
  n=$(basename "$d"); m=$(ls "$d"/glTF/*.gltf | head -1)
  r=$(ls "$d"/screenshot/screenshot.* | head -1)
  if "$bin" "$m" --shading pbr --size ${size}x${size} --yaw 0 --pitch 0 \
      --diff pbr,reference-pbr --reference-samples 256 -o "$tmp/$n.png" >"$tmp/$n.log" 2>&1; then
    json=$(tail -1 "$tmp/$n.log")
    echo "| $n | $(echo "$json" | python3 -c 'import json,sys; d=json.load(sys.stdin)["model"]; print("%.1f %% | %.2f | %.3f" % (100*d["over_8"], d["mean"], d["one_minus_ssim"]))') |"
  else
    echo "| $n | error: $(grep -m1 error "$tmp/$n.log") | | |"
    convert -size ${size}x${size} xc:gray20 "$tmp/$n-pbr.png"
    cp "$tmp/$n-pbr.png" "$tmp/$n-reference-pbr.png"
  fi
  convert "$r" -resize ${size}x${size} -background gray20 -gravity center -extent ${size}x${size} "$tmp/$n-ref.png"
  tiles+=(-label "$n: PBR" "$tmp/$n-pbr.png" -label "reference" "$tmp/$n-reference-pbr.png"
    -label "Khronos" "$tmp/$n-ref.png")
done
montage "${tiles[@]}" -tile 6x -geometry +4+4 -pointsize 12 -background gray12 -fill white "$tmp/sheet.png"
convert "$tmp/sheet.png" -quality 85 "$out/khr_sheet.jpg"
cp "$tmp/sheet.png" /tmp/khr_sheet.png 2>/dev/null || true
echo "wrote $out/khr_sheet.jpg" >&2
