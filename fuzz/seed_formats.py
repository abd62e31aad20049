#!/usr/bin/env python3
"""Seeds the stl, ply and gltf fuzz targets (corpus/{stl,ply,gltf}/) at run time: small
generated STL and PLY files in every encoding the loaders read, and the glTF sample models
of ../shared/gltf-samples up to 64 KiB plus a one-triangle glTF with its buffer as a data: URI,
and the Draco samples of tests/data/khronos/draco as GLBs.
Usage: fuzz/seed_formats.py [SHARED_DIR]"""
import base64, json, os, struct, sys

here = os.path.dirname(os.path.abspath(__file__))
shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "shared")
def out(target, name, data):
    d = os.path.join(here, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)

tris = [((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (0, 1, 0))]
ascii_stl = "solid s\n" + "".join(
    "facet normal 0 0 1\nouter loop\n" + "".join("vertex %g %g %g\n" % v for v in t)
    + "endloop\nendfacet\n" for t in tris) + "endsolid s\n"
out("stl", "ascii.stl", ascii_stl.encode())
out("stl", "crlf.stl", ascii_stl.replace("\n", "\r\n").encode())
def binary(header):
    b = header.ljust(80, b" ") + struct.pack("<I", len(tris))
    for t in tris:
        b += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in t) + b"\0\0"
    return b
out("stl", "binary.stl", binary(b"binary"))
out("stl", "solid-header.stl", binary(b"solid but binary"))

verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
head = ("ply\nformat %s 1.0\ncomment c\nobj_info o\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
        "property uchar blue\nelement face 1\nproperty list uchar int %s\nend_header\n")
out("ply", "ascii.ply", (head % ("ascii", "vertex_indices")).encode() + b"".join(
    b"%g %g %g 255 0 0\n" % v for v in verts) + b"4 0 1 2 3\n")
for fmt, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
    body = b"".join(struct.pack(e + "3f3B", *v, 255, 128, 0) for v in verts)
    body += struct.pack(e + "B4i", 4, 0, 1, 2, 3)
    out("ply", fmt + ".ply", (head % (fmt, "vertex_index")).encode() + body)

samples = os.path.join(shared, "gltf-samples")
for root, _, files in os.walk(samples):
    for f in files:
        p = os.path.join(root, f)
        if f.endswith((".gltf", ".glb")) and os.path.getsize(p) <= 65536:
            out("gltf", f, open(p, "rb").read())
buf = b"".join(struct.pack("<3f", *v) for v in verts[:3]) + struct.pack("<3H", 0, 1, 2) + b"\0\0"
out("gltf", "tri.gltf", json.dumps({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"children": [1], "scale": [1, 1, -1]}, {"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode(),
                 "byteLength": len(buf)}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}).encode())
# The Draco samples of tests/data (KHR_draco_mesh_compression), each made one GLB with its
# buffer as the binary chunk, so the target reaches the Draco decoder with a valid stream.
def glb(doc, binary):
    doc["buffers"][0].pop("uri", None)
    binary += b"\0" * (-len(binary) % 4)
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    chunks = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks
draco = os.path.join(here, "..", "tests", "data", "khronos", "draco")
for model in ("Box", "Duck", "Avocado", "RiggedSimple"):
    d = os.path.join(draco, model)
    gltf = json.load(open(os.path.join(d, model + ".gltf")))
    binary = open(os.path.join(d, gltf["buffers"][0]["uri"]), "rb").read()
    out("gltf", model + "-draco.glb", glb(gltf, binary))
    # The tolerated Draco counts (issue 50): accessors saying fewer points and indices than
    # the stream decodes, so the target reaches the decoded-count path.
    for a in gltf["accessors"]:
        a["count"] = max(1, a["count"] - 4)
    out("gltf", model + "-draco-counts.glb", glb(gltf, binary))
# AVIF (issue 50): the avif target's corpus, and BoxTextured with an EXT_texture_avif image
# beside its PNG, so the gltf target reaches the AVIF decoder and the fallback.
avif = os.path.join(here, "..", "tests", "data", "avif")
for f in sorted(os.listdir(avif)):
    if f.endswith(".avif"):
        out("avif", f, open(os.path.join(avif, f), "rb").read())
box = open(os.path.join(samples, "BoxTextured", "BoxTextured.glb"), "rb").read()
n = struct.unpack("<I", box[12:16])[0]
doc = json.loads(box[20:20 + n])
binary = box[28 + n:28 + n + struct.unpack("<I", box[20 + n:24 + n])[0]]
binary += b"\0" * (-len(binary) % 4)
img = open(os.path.join(avif, "opaque-420-limited.avif"), "rb").read()
doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(img)})
doc["images"].append({"bufferView": len(doc["bufferViews"]) - 1, "mimeType": "image/avif"})
doc["textures"][0]["extensions"] = {"EXT_texture_avif": {"source": len(doc["images"]) - 1}}
doc["extensionsUsed"] = ["EXT_texture_avif"]
binary += img
doc["buffers"][0]["byteLength"] = len(binary)
out("gltf", "BoxTextured-avif.glb", glb(doc, binary))
print("seed_formats.py: corpus/stl, corpus/ply, corpus/gltf, corpus/avif written")
