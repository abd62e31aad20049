#!/usr/bin/env python3
"""Pixel comparison of two 8-bit PNGs with Python's standard library only (the Wine test runs
before any venv exists): `png_compare.py same A B` exits 0 when every pixel is equal, else
prints how many differ and by how much; `--opaque` compares RGB only where B's alpha is 255
(a window screenshot is opaque, a headless PNG keeps the glass's alpha); `differ A B` exits 0
when some pixel differs."""
import struct
import sys
import zlib


def decode(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"error: {path}: not a PNG")
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, colour, _, _, interlace = ihdr
    channels = {2: 3, 6: 4, 0: 1, 4: 2}.get(colour)
    if depth != 8 or channels is None or interlace:
        sys.exit(f"error: {path}: only 8-bit non-interlaced grey/RGB(A) PNGs are compared")
    raw, bpp, stride = zlib.decompress(idat), channels, w * channels
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    px = []
    for line in rows:
        for x in range(w):
            v = tuple(line[x * channels:(x + 1) * channels])
            if channels == 1:
                v = v * 3 + (255,)
            elif channels == 2:
                v = (v[0],) * 3 + (v[1],)
            elif channels == 3:
                v = v + (255,)
            px.append(v)
    return w, h, px


def main():
    args = sys.argv[1:]
    opaque = "--opaque" in args
    args = [a for a in args if a != "--opaque"]
    if len(args) != 3 or args[0] not in ("same", "differ"):
        sys.exit(__doc__)
    mode, a, b = args
    (wa, ha, pa), (wb, hb, pb) = decode(a), decode(b)
    if (wa, ha) != (wb, hb):
        print(f"{a} is {wa}x{ha}, {b} is {wb}x{hb}")
        sys.exit(1 if mode == "same" else 0)
    n, worst = 0, 0
    for p, q in zip(pa, pb):
        if opaque and q[3] != 255:
            continue
        d = max(abs(x - y) for x, y in zip(p[:3] if opaque else p, q[:3] if opaque else q))
        if d:
            n += 1
            worst = max(worst, d)
    print(f"{a} vs {b}: {n} of {wa * ha} pixels differ, by at most {worst}/255")
    sys.exit((n > 0) if mode == "same" else (n == 0))


if __name__ == "__main__":
    main()
