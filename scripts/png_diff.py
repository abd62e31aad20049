#!/usr/bin/env python3
"""Pixel comparison of two PNG files, standard library only (zlib), for
scripts/pictures_unchanged.sh: no Pillow or numpy needed.

    png_diff.py BEFORE.png AFTER.png [--diff-out DIFF.png] [--opaque]

prints one line `PIXELS_DIFFERING MAX_DIFF WxH` (WxH of BEFORE; `WxH->W2xH2` when the sizes
differ, then every pixel counts as differing and MAX_DIFF is 255) and exits 0 when every
pixel's RGBA is equal, 1 when some differ, 2 when a file cannot be read (the reason on stderr).
Pixels are compared as RGBA: grey, grey+alpha, RGB and palette images are expanded (alpha 255
where the file has none), so the same picture stored in another colour type still compares
equal; 16-bit channels compare at 16 bits and MAX_DIFF is then given on the 0..255 scale
(rounded up). Text chunks (glview.command, ...) and other metadata are ignored.

With --opaque, only RGB is compared, and only where BEFORE's alpha is full: a window's
screenshot (opaque) against a headless PNG that keeps the glass's alpha
(scripts/test_windows.sh).

With --diff-out, a picture that differs is written there (RGBA, 8-bit): every differing
pixel red, brighter the larger its largest channel difference (at least half bright, so a
difference of 1/255 stands out), every equal pixel the AFTER picture in grey at a quarter of
its brightness.

Decoder scope: every colour type (0, 2, 3, 4, 6) at bit depth 8 (and 16 for 0, 2, 4, 6; 1, 2, 4
for grey and palette), non-interlaced, filter types 0-4, IDAT split over any number of chunks,
CRCs checked. An interlaced or otherwise unsupported file is an error, never a guess.
"""

import struct
import sys
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}
DEPTHS = {0: (1, 2, 4, 8, 16), 2: (8, 16), 3: (1, 2, 4, 8), 4: (8, 16), 6: (8, 16)}


class PngError(Exception):
    pass


def read_chunks(data, path):
    if not data.startswith(SIGNATURE):
        raise PngError(f"{path}: not a PNG file (signature)")
    pos = len(SIGNATURE)
    while pos < len(data):
        if pos + 8 > len(data):
            raise PngError(f"{path}: truncated chunk header at byte {pos}")
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        end = pos + 8 + length
        if end + 4 > len(data):
            raise PngError(f"{path}: chunk {kind!r} truncated at byte {pos}")
        body = data[pos + 8:end]
        (crc,) = struct.unpack(">I", data[end:end + 4])
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            raise PngError(f"{path}: CRC mismatch in chunk {kind!r} at byte {pos}")
        yield kind, body
        if kind == b"IEND":
            return
        pos = end + 4
    raise PngError(f"{path}: no IEND chunk")


class Png:
    """A decoded PNG: width, height, 16-bit flag, header tuple, the raw (filtered,
    decompressed) stream and, once decoded, rows of RGBA samples."""

    def __init__(self, path):
        self.path = path
        with open(path, "rb") as f:
            data = f.read()
        header = None
        palette = None
        trns = None
        idat = []
        for kind, body in read_chunks(data, path):
            if kind == b"IHDR":
                if len(body) != 13:
                    raise PngError(f"{path}: IHDR of {len(body)} bytes")
                header = struct.unpack(">IIBBBBB", body)
            elif kind == b"PLTE":
                palette = body
            elif kind == b"tRNS":
                trns = body
            elif kind == b"IDAT":
                idat.append(body)
        if header is None:
            raise PngError(f"{path}: no IHDR chunk")
        w, h, depth, ctype, comp, filt, interlace = header
        if ctype not in CHANNELS or depth not in DEPTHS[ctype]:
            raise PngError(f"{path}: unsupported colour type {ctype} at bit depth {depth}")
        if comp != 0 or filt != 0:
            raise PngError(f"{path}: unknown compression {comp} or filter method {filt}")
        if interlace != 0:
            raise PngError(f"{path}: interlaced PNG (Adam7) is not supported")
        if w == 0 or h == 0:
            raise PngError(f"{path}: empty image {w}x{h}")
        if not idat:
            raise PngError(f"{path}: no IDAT chunk")
        if ctype == 3 and palette is None:
            raise PngError(f"{path}: palette image without PLTE")
        try:
            raw = zlib.decompress(b"".join(idat))
        except zlib.error as e:
            raise PngError(f"{path}: bad zlib stream: {e}") from None
        self.width, self.height, self.depth, self.ctype = w, h, depth, ctype
        self.header = header
        self.palette, self.trns = palette, trns
        self.bits_per_pixel = CHANNELS[ctype] * depth
        self.bpp = max(1, self.bits_per_pixel // 8)  # filter byte distance
        self.stride = (w * self.bits_per_pixel + 7) // 8
        if len(raw) < h * (self.stride + 1):
            raise PngError(f"{path}: image data too short ({len(raw)} bytes for "
                           f"{h} rows of {self.stride + 1})")
        self.raw = raw[:h * (self.stride + 1)]
        self.wide = depth == 16
        self._rows = None

    def rows(self):
        """RGBA rows, each a list of 4*width ints (0..255, or 0..65535 when 16-bit)."""
        if self._rows is None:
            self._rows = [self._to_rgba(r) for r in self._unfilter()]
        return self._rows

    def _unfilter(self):
        stride, bpp, raw = self.stride, self.bpp, self.raw
        prev = bytearray(stride)
        out = []
        for y in range(self.height):
            start = y * (stride + 1)
            ftype = raw[start]
            line = bytearray(raw[start + 1:start + 1 + stride])
            if ftype == 0:
                pass
            elif ftype == 1:  # Sub
                for i in range(bpp, stride):
                    line[i] = (line[i] + line[i - bpp]) & 0xFF
            elif ftype == 2:  # Up
                for i in range(stride):
                    line[i] = (line[i] + prev[i]) & 0xFF
            elif ftype == 3:  # Average
                for i in range(stride):
                    left = line[i - bpp] if i >= bpp else 0
                    line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xFF
            elif ftype == 4:  # Paeth
                for i in range(stride):
                    if i >= bpp:
                        a, c = line[i - bpp], prev[i - bpp]
                    else:
                        a = c = 0
                    b = prev[i]
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    if pa <= pb and pa <= pc:
                        pred = a
                    elif pb <= pc:
                        pred = b
                    else:
                        pred = c
                    line[i] = (line[i] + pred) & 0xFF
            else:
                raise PngError(f"{self.path}: row {y} has unknown filter type {ftype}")
            out.append(line)
            prev = line
        return out

    def _samples(self, line):
        d, n = self.depth, self.width * CHANNELS[self.ctype]
        if d == 8:
            return list(line[:n])
        if d == 16:
            return list(struct.unpack(f">{n}H", bytes(line[:2 * n])))
        per = 8 // d
        mask = (1 << d) - 1
        out = []
        for byte in line:
            for k in range(per):
                out.append((byte >> (8 - d * (k + 1))) & mask)
        return out[:n]

    def _to_rgba(self, line):
        s = self._samples(line)
        ct, d = self.ctype, self.depth
        full = 65535 if d == 16 else 255
        if ct == 6:
            return s
        out = []
        if ct == 2:
            key = struct.unpack(">3H", self.trns) if self.trns and len(self.trns) == 6 else None
            for i in range(0, len(s), 3):
                px = s[i:i + 3]
                out += px + [0 if key is not None and tuple(px) == key else full]
        elif ct == 0 or ct == 4:
            scale = 255 // ((1 << d) - 1) if d < 8 else 1
            key = struct.unpack(">H", self.trns)[0] if ct == 0 and self.trns and len(self.trns) == 2 else None
            step = 1 if ct == 0 else 2
            for i in range(0, len(s), step):
                g = s[i]
                a = s[i + 1] if ct == 4 else (0 if key is not None and g == key else full)
                g *= scale
                out += [g, g, g, a]
        else:  # palette
            pal, trns = self.palette, self.trns or b""
            for idx in s:
                if 3 * idx + 3 > len(pal):
                    raise PngError(f"{self.path}: palette index {idx} out of range")
                out += [pal[3 * idx], pal[3 * idx + 1], pal[3 * idx + 2],
                        trns[idx] if idx < len(trns) else 255]
        return out


def compare(before, after, opaque=False):
    """(pixels differing, max channel difference on the 0..255 scale, per-pixel max list or None).
    `opaque`: RGB only, where BEFORE's alpha is full."""
    if (before.width, before.height) != (after.width, after.height):
        return before.width * before.height, 255, None
    # Same header and same filtered stream: the same pixels, no need to decode.
    if before.header == after.header and before.raw == after.raw and \
            before.palette == after.palette and before.trns == after.trns:
        return 0, 0, None
    wide_b, wide_a = before.wide, after.wide
    count, worst = 0, 0
    per_pixel = []
    for rb, ra in zip(before.rows(), after.rows()):
        if wide_b != wide_a:  # compare at 16 bits
            rb = [v * 257 for v in rb] if not wide_b else rb
            ra = [v * 257 for v in ra] if not wide_a else ra
        if rb == ra:
            per_pixel.append(None)
            continue
        row = []
        full = 65535 if (wide_b or wide_a) else 255
        for i in range(0, len(rb), 4):
            if opaque and rb[i + 3] != full:
                row.append(0)
                continue
            m = max(abs(rb[i] - ra[i]), abs(rb[i + 1] - ra[i + 1]),
                    abs(rb[i + 2] - ra[i + 2]), 0 if opaque else abs(rb[i + 3] - ra[i + 3]))
            if m:
                count += 1
                worst = max(worst, m)
            row.append(m)
        per_pixel.append(row)
    if wide_b or wide_a:
        worst = -(-worst // 257)
    return count, worst, per_pixel


def write_png(path, width, height, rows):
    """8-bit RGBA PNG, filter type 0."""
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + \
            struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(SIGNATURE)
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def diff_picture(after, per_pixel, wide):
    rows = []
    for y, (ra, diffs) in enumerate(zip(after.rows(), per_pixel)):
        if after.wide:
            ra = [v >> 8 for v in ra]
        out = bytearray(4 * after.width)
        for x in range(after.width):
            m = diffs[x] if diffs is not None else 0
            if wide:
                m = -(-m // 257)
            if m:
                out[4 * x:4 * x + 4] = bytes((min(255, 128 + m * 127 // 32 if m < 32 else 255), 0, 0, 255))
            else:
                r, g, b = ra[4 * x:4 * x + 3]
                grey = (r * 299 + g * 587 + b * 114) // 4000
                out[4 * x:4 * x + 4] = bytes((grey, grey, grey, 255))
        rows.append(out)
    return rows


def main(argv):
    args = list(argv)
    opaque = "--opaque" in args
    args = [a for a in args if a != "--opaque"]
    diff_out = None
    if "--diff-out" in args:
        i = args.index("--diff-out")
        if i + 1 >= len(args):
            print("png_diff.py: --diff-out needs a path", file=sys.stderr)
            return 2
        diff_out = args[i + 1]
        del args[i:i + 2]
    if len(args) != 2 or any(a.startswith("-") for a in args):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        before, after = Png(args[0]), Png(args[1])
        count, worst, per_pixel = compare(before, after, opaque)
    except (OSError, PngError) as e:
        print(f"png_diff.py: {e}", file=sys.stderr)
        return 2
    size = f"{before.width}x{before.height}"
    if (before.width, before.height) != (after.width, after.height):
        size += f"->{after.width}x{after.height}"
    print(f"{count} {worst} {size}")
    if count and diff_out and per_pixel is not None:
        write_png(diff_out, after.width, after.height,
                  diff_picture(after, per_pixel, before.wide or after.wide))
    return 1 if count else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
