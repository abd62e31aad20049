"""A binary glTF (GLB) written from Python, for the scripts that make test files
(make_*.py): accessors added one after another into one buffer, then the file. Only the
standard library."""
import json
import struct

FLOAT, U16 = 5126, 5123
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


class Glb:
    def __init__(self):
        self.bin, self.views, self.accessors = bytearray(), [], []

    def view(self, raw):
        """A buffer view of bytes `raw` (4-byte aligned); its index."""
        while len(self.bin) % 4:
            self.bin.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(raw)})
        self.bin += raw
        return len(self.views) - 1

    def add(self, fmt, data, kind, ctype, count, minmax=False):
        """An accessor of `count` `kind`s packed as struct format `fmt` (componentType
        `ctype`), with per-component min and max when `minmax`; its index."""
        raw = struct.pack("<%d%s" % (len(data), fmt), *data)
        acc = {"bufferView": self.view(raw), "componentType": ctype, "count": count,
               "type": kind}
        if minmax:
            per = COMPONENTS[kind]
            acc["min"] = [min(data[i::per]) for i in range(per)]
            acc["max"] = [max(data[i::per]) for i in range(per)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def write(self, path, gltf):
        """Writes `gltf` with this buffer to `path`: its `buffers`, `bufferViews` and
        `accessors` set (in their places when the dict has them), `asset` added if absent."""
        while len(self.bin) % 4:
            self.bin.append(0)
        gltf.setdefault("asset", {"version": "2.0"})
        gltf.update(buffers=[{"byteLength": len(self.bin)}], bufferViews=self.views,
                    accessors=self.accessors)
        js = json.dumps(gltf, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        out = b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js) + 8 + len(self.bin))
        out += struct.pack("<I", len(js)) + b"JSON" + js
        out += struct.pack("<I", len(self.bin)) + b"BIN\0" + bytes(self.bin)
        with open(path, "wb") as f:
            f.write(out)
