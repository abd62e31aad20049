#!/usr/bin/env bash
# Writes the AVIF test files in tests/data/avif (committed; run again only to change them):
# two 64x64 patterns (opaque; soft alpha) and BoxTextured's own texture, encoded by libavif's
# avifenc (Debian's libavif-bin, 0.11.1 with libaom 3.6) in the forms the decoder must read
# (lossless identity 4:4:4, 4:2:0 limited range, 10-bit 4:4:4 with alpha, 4:0:0,
# premultiplied alpha), and avifdec's 8-bit decodes of the lossy ones as references.
set -euo pipefail
cd "$(dirname "$0")/../tests/data/avif"
command -v avifenc >/dev/null || { echo "needs avifenc (apt-get install libavif-bin)" >&2; exit 1; }
python3 - <<'PY'
import math, struct, zlib
def png(path, w, h, px):
    raw = b"".join(b"\0" + b"".join(bytes(px(x, y)) for x in range(w)) for y in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
png("alpha.png", 64, 64, lambda x, y: (255 * x // 63, 255 * y // 63, (x * y) % 256, 64 + 191 * ((x + y) % 32) // 31))
png("opaque.png", 64, 64, lambda x, y: (255 * x // 63, 255 * y // 63, 128 + int(127 * math.sin(x / 5)), 255))
PY
box=$(mktemp --suffix .png)
trap 'rm -f "$box"' EXIT
python3 - "$box" <<'PY'
import json, struct, sys
b = open("../../../../shared/gltf-samples/BoxTextured/BoxTextured.glb", "rb").read()
n = struct.unpack("<I", b[12:16])[0]
j = json.loads(b[20:20 + n])
v = j["bufferViews"][j["images"][0]["bufferView"]]
start = 28 + n + v["byteOffset"]
open(sys.argv[1], "wb").write(b[start:start + v["byteLength"]])
PY
e() { avifenc -j 1 "$@" >/dev/null; }
e -l opaque.png opaque-lossless.avif
e -l alpha.png alpha-lossless.avif
e -l "$box" box-lossless.avif
e -y 420 -r limited --min 20 --max 30 opaque.png opaque-420-limited.avif
e -y 444 -d 10 --min 10 --max 20 --minalpha 0 --maxalpha 0 alpha.png alpha-444-10bit.avif
e -y 400 --min 10 --max 20 opaque.png grey-400.avif
e -y 420 --premultiply --min 10 --max 20 alpha.png alpha-premultiplied.avif
for f in opaque-420-limited alpha-444-10bit grey-400 alpha-premultiplied; do
  avifdec -d 8 "$f.avif" "ref-$f.png" >/dev/null
done
