#!/usr/bin/env python3
"""Writes tests/data/motion/TwoJointSets.glb: a skin with up to six joints per vertex, in two
JOINTS_n/WEIGHTS_n sets (issue #39: "up to 4 joints per vertex; more sets where the file has
them"), as exporters write when a vertex has more than four influences; and
tests/data/motion/TwoJointSets.expected.json: its posed positions at 1 s, computed here,
apart from glview's code, for the test to hold glview's pose to.

An open 8-sided tube along Y (11 rings, y = 0 to 4), skinned to a chain of six joints at
y = 0, 0.8, ..., 4 (inverse binds T(0, -y_j, 0)). A vertex at height y weighs joint j by
max(0, 1 - |y - y_j| / 2.1), normalised: up to six influences (the middle rings have six).
Even rings put joints 0-3 in set 0 and 4-5 in set 1; odd rings put 2-5 in set 0 and 0-1 in
set 1, so neither set alone is the skin. One animation, LINEAR, keys 0 / 1 / 2 s: joints 1-5
turn about Z by 0 / 15 / 0 degrees, so at 1 s the tube bends into an arc. Run from
the repository root; only the standard library.

`make_two_joint_sets.py SIDES RINGS OUT` writes the same tube finer (e.g. 64 200
/tmp/sets.glb: 12,800 vertices) and no positions, for `glview bench --motion
--motion-model OUT`.
"""
import json
import math
import struct
import sys

import glb

SIDES, RINGS, JOINTS, SPACING, REACH = 8, 11, 6, 0.8, 2.1
OUT = "tests/data/motion/TwoJointSets.glb"
EXPECTED = "tests/data/motion/TwoJointSets.expected.json"
if len(sys.argv) == 4:
    SIDES, RINGS, OUT, EXPECTED = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], None


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


joint_y = [SPACING * j for j in range(JOINTS)]
positions, normals, sets = [], [], ([], [], [], [])
for r in range(RINGS):
    y = 4.0 * r / (RINGS - 1)
    raw = [max(0.0, 1.0 - abs(y - jy) / REACH) for jy in joint_y]
    total = sum(raw)
    w = [x / total for x in raw]
    first, second = ([0, 1, 2, 3], [4, 5]) if r % 2 == 0 else ([2, 3, 4, 5], [0, 1])
    for s in range(SIDES):
        a = 2 * math.pi * s / SIDES
        c, k = math.cos(a), math.sin(a)
        positions += [0.5 * c, y, 0.5 * k]
        normals += [c, 0.0, k]
        sets[0].extend(first)
        sets[1].extend(w[j] for j in first)
        sets[2].extend(second + [0, 0])
        sets[3].extend([w[j] for j in second] + [0.0, 0.0])

indices = []
for r in range(RINGS - 1):
    for s in range(SIDES):
        a, b = r * SIDES + s, r * SIDES + (s + 1) % SIDES
        indices += [a, a + SIDES, b, b, a + SIDES, b + SIDES]

g = glb.Glb()
add = g.add


n = len(positions) // 3
F, U16 = glb.FLOAT, glb.U16
attributes = {
    "POSITION": add("f", positions, "VEC3", F, n, True),
    "NORMAL": add("f", normals, "VEC3", F, n),
    "JOINTS_0": add("H", sets[0], "VEC4", U16, n),
    "WEIGHTS_0": add("f", sets[1], "VEC4", F, n),
    "JOINTS_1": add("H", sets[2], "VEC4", U16, n),
    "WEIGHTS_1": add("f", sets[3], "VEC4", F, n),
}
idx = add("H", indices, "SCALAR", U16, len(indices))
ibm_values = []
for jy in joint_y:
    ibm_values += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -jy, 0, 1]
ibm = add("f", ibm_values, "MAT4", F, JOINTS)
times = add("f", [0.0, 1.0, 2.0], "SCALAR", F, 3)
angles = [0.0] + [math.radians(15)] * (JOINTS - 1)
samplers, channels = [], []
for j in range(1, JOINTS):
    h = angles[j] / 2
    out = add("f", [0, 0, 0, 1, 0, 0, math.sin(h), math.cos(h), 0, 0, 0, 1], "VEC4", F, 3)
    samplers.append({"input": times, "output": out})
    channels.append({"sampler": j - 1, "target": {"node": 1 + j, "path": "rotation"}})

# Joint nodes 1..6: the root at the origin, each next one 0.8 above its parent.
nodes = [{"name": "tube", "mesh": 0, "skin": 0}]
for j in range(JOINTS):
    node = {"name": "joint%d" % j}
    if j > 0:
        node["translation"] = [0, SPACING, 0]
    if j + 1 < JOINTS:
        node["children"] = [2 + j]
    nodes.append(node)

gltf = {
    "asset": {"version": "2.0", "generator": "glview scripts/make_two_joint_sets.py"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": nodes,
    "skins": [{"joints": list(range(1, 1 + JOINTS)), "inverseBindMatrices": ibm}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.6, 0.85, 1],
                                            "metallicFactor": 0, "roughnessFactor": 0.6},
                   "doubleSided": True}],
    "meshes": [{"primitives": [{"attributes": attributes, "indices": idx, "material": 0}]}],
    "animations": [{"name": "Bend", "channels": channels, "samplers": samplers}],
    "buffers": None,  # these three set by Glb.write, in these places
    "bufferViews": None,
    "accessors": None,
}
g.write(OUT, gltf)
if EXPECTED is None:
    sys.exit(0)


# The pose at 1 s (the middle key exactly), from the values as stored (f32), in 2D: every
# joint turns about Z and stays at z = 0, so a joint's world transform is a turn by the sum
# of the angles above the root and a translation.
def turn(a):
    h = f32(math.sin(a / 2)), f32(math.cos(a / 2))
    norm = math.hypot(*h)
    s, c = h[0] / norm, h[1] / norm
    return 2 * s * c, c * c - s * s  # sin and cos of the stored quaternion's angle


worlds = []  # (sin, cos, x, y) per joint
for j in range(JOINTS):
    sn, cs = turn(angles[j]) if j else (0.0, 1.0)
    if j == 0:
        worlds.append((sn, cs, 0.0, 0.0))
        continue
    ps, pc, px, py = worlds[-1]
    # parent * T(0, SPACING) * R(own): the offset turned by the parent, the angles added.
    x, y = px - ps * f32(SPACING), py + pc * f32(SPACING)
    worlds.append((ps * cs + pc * sn, pc * cs - ps * sn, x, y))
expected = []
for v in range(n):
    p = [f32(c) for c in positions[3 * v:3 * v + 3]]
    out = [0.0, 0.0, 0.0]
    for js, ws in ((sets[0], sets[1]), (sets[2], sets[3])):
        for k in range(4):
            j, w = js[4 * v + k], f32(ws[4 * v + k])
            sn, cs, x, y = worlds[j]
            by = p[1] - f32(joint_y[j])  # the inverse bind
            out[0] += w * (cs * p[0] - sn * by + x)
            out[1] += w * (sn * p[0] + cs * by + y)
            out[2] += w * p[2]
    expected.append(out)
with open(EXPECTED, "w") as f:
    json.dump({"time": 1.0, "animation": 0, "positions": expected}, f, indent=0)
    f.write("\n")
