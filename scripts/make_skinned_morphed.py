#!/usr/bin/env python3
"""Writes tests/data/motion/SkinnedMorphed.glb: a mesh both skinned and morphed (issue #39),
as characters with a skeleton and shape keys are, small enough for tests (40 vertices).

An open 8-sided tube along Y (rings at y = 0, 0.5, 1, 1.5, 2), skinned to two joints: the
root at the origin and a child at y = 1 (inverse bind: identity and T(0,-1,0)); rings below
0.5 follow the root, rings above 1.5 the child, ring 1 half each. Two morph targets with
position and normal deltas (four delta attributes, the GPU's budget on 16 attributes):
"bulge" pushes the middle rings out, "lean" shears the tube along X. One animation, LINEAR,
keys 0 / 1 / 2 s: the child turns about Z 0 / 40 / 0 degrees and the weights go
[0, 0] / [1, 0.5] / [0, 0], so at any moment inside (0, 2) s both the joints and the
weights are away from rest. Run from the repository root; only the standard library.

`make_skinned_morphed.py SIDES RINGS OUT` writes the same shape finer (e.g. 64 100
/tmp/big.glb: 6,400 vertices), for `glview bench --motion --motion-model OUT`.

`make_skinned_morphed.py --mapped` writes tests/data/motion/SkinnedMorphedMapped.glb: the
tube with UVs (a seam column of its own), TANGENTs and an 8x8 bumpy normal map, and the
"bulge" target only, with position, normal and tangent deltas (three delta attributes: a
normal-mapped material needs the tangents' deltas too).
"""
import math
import struct
import sys
import zlib

import glb

SIDES, RINGS, OUT = 8, 5, "tests/data/motion/SkinnedMorphed.glb"
MAPPED = sys.argv[1:] == ["--mapped"]
if MAPPED:
    OUT = "tests/data/motion/SkinnedMorphedMapped.glb"
if len(sys.argv) == 4:
    SIDES, RINGS, OUT = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
COLS = SIDES + 1 if MAPPED else SIDES


def ring_y(r):
    return 2.0 * r / (RINGS - 1)


positions, normals, joints, weights, uvs, tangents = [], [], [], [], [], []
bulge_p, bulge_n, bulge_t, lean_p, lean_n = [], [], [], [], []
for r in range(RINGS):
    y = ring_y(r)
    w1 = min(1.0, max(0.0, y - 0.5))  # 0 up to 0.5, 1 from 1.5
    push = 0.4 * max(0.0, 1.0 - abs(y - 1.0))
    tilt = 0.4 * math.sin(math.pi * (y - 1.0))
    for s in range(COLS):
        a = 2 * math.pi * s / SIDES
        c, k = math.cos(a), math.sin(a)
        positions += [0.5 * c, y, 0.5 * k]
        normals += [c, 0.0, k]
        joints += [0, 1, 0, 0]
        weights += [1.0 - w1, w1, 0.0, 0.0]
        bulge_p += [push * c, 0.0, push * k]
        bulge_n += [0.0, tilt, 0.0]
        lean_p += [0.3 * y, 0.0, 0.0]
        lean_n += [-0.15 * c * c, 0.15 * c, 0.0]
        uvs += [s / SIDES, y / 2.0]
        tangents += [-k, 0.0, c, 1.0]
        bulge_t += [0.0, 0.5 * tilt, 0.0]

indices = []
for r in range(RINGS - 1):
    for s in range(SIDES):
        a, b = r * COLS + s, r * COLS + (s + 1) % COLS
        c, d = a + COLS, b + COLS
        indices += [a, c, b, b, c, d]

g = glb.Glb()
add = g.add


n = len(positions) // 3
F, U16 = glb.FLOAT, glb.U16
pos = add("f", positions, "VEC3", F, n, True)
nrm = add("f", normals, "VEC3", F, n)
jnt = add("H", joints, "VEC4", U16, n)
wgt = add("f", weights, "VEC4", F, n)
idx = add("H", indices, "SCALAR", U16, len(indices))
bp = add("f", bulge_p, "VEC3", F, n, True)
bn = add("f", bulge_n, "VEC3", F, n)
attributes = {"POSITION": pos, "NORMAL": nrm, "JOINTS_0": jnt, "WEIGHTS_0": wgt}
material = {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.45, 0.2, 1],
                                     "metallicFactor": 0, "roughnessFactor": 0.6},
            "doubleSided": True}
extra = {}
if MAPPED:
    attributes["TEXCOORD_0"] = add("f", uvs, "VEC2", F, n)
    attributes["TANGENT"] = add("f", tangents, "VEC4", F, n)
    targets = [{"POSITION": bp, "NORMAL": bn,
                "TANGENT": add("f", bulge_t, "VEC3", F, n)}]
    names = ["bulge"]
    # An 8x8 normal map of bumps: tangent-space normals tilted by a sine in u and in v.
    rows = b""
    for j in range(8):
        rows += b"\0"
        for i in range(8):
            x, y = 0.5 * math.sin(2 * math.pi * i / 8), 0.5 * math.sin(2 * math.pi * j / 8)
            z = math.sqrt(max(0.0, 1 - x * x - y * y))
            rows += bytes(round((v * 0.5 + 0.5) * 255) for v in (x, y, z))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 8, 8, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")
    extra["images"] = [{"bufferView": g.view(png), "mimeType": "image/png"}]
    extra["textures"] = [{"source": 0}]
    material["normalTexture"] = {"index": 0}
    weight_keys = [0, 1, 0]
else:
    lp = add("f", lean_p, "VEC3", F, n, True)
    ln = add("f", lean_n, "VEC3", F, n)
    targets = [{"POSITION": bp, "NORMAL": bn}, {"POSITION": lp, "NORMAL": ln}]
    names = ["bulge", "lean"]
    weight_keys = [0, 0, 1, 0.5, 0, 0]
ibm = add("f", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1], "MAT4", F, 2)
times = add("f", [0.0, 1.0, 2.0], "SCALAR", F, 3)
h = math.radians(40) / 2
turns = add("f", [0, 0, 0, 1, 0, 0, math.sin(h), math.cos(h), 0, 0, 0, 1], "VEC4", F, 3)
morphs = add("f", weight_keys, "SCALAR", F, len(weight_keys))

gltf = {
    "asset": {"version": "2.0", "generator": "glview scripts/make_skinned_morphed.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [
        {"name": "tube", "mesh": 0, "skin": 0},
        {"name": "root", "children": [2]},
        {"name": "upper", "translation": [0, 1, 0]},
    ],
    "skins": [{"joints": [1, 2], "inverseBindMatrices": ibm, "skeleton": 1}],
    "materials": [material],
    "meshes": [{
        "primitives": [{
            "attributes": attributes,
            "indices": idx, "material": 0,
            "targets": targets,
        }],
        "weights": [0] * len(names),
        "extras": {"targetNames": names},
    }],
    "animations": [{
        "name": "BendAndBulge",
        "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}},
                     {"sampler": 1, "target": {"node": 0, "path": "weights"}}],
        "samplers": [{"input": times, "output": turns}, {"input": times, "output": morphs}],
    }],
    "buffers": None,  # these three set by Glb.write, in these places
    "bufferViews": None,
    "accessors": None,
    **extra,
}
g.write(OUT, gltf)
