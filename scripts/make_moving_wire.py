#!/usr/bin/env python3
"""Writes tests/data/motion/MovingWire.glb and its still twin MovingWireStill.glb (issue #39:
lines, points and instances of a moving node move with it).

MovingWire: node 0 holds a unit cube (triangles), a square frame of LINES in front of it
(z = 0.8, not on a face: no depth ties) and its four corners as POINTS; one animation moves
node 0 (STEP: at 1 s translation (1.5, 0.5, 0) and a turn of 30 degrees about Y) and turns
joint node 4 of a skinned rope of LINES (two joints; STEP: at 1 s 45 degrees about Z);
node 1's square of LINES never moves; node 5, a child of node 0, draws a small cube three
times in a row above it (EXT_mesh_gpu_instancing). A second animation turns node 5 alone
(90 degrees about Y at 1 s, STEP): it moves no line or point. STEP keys make the pose at 1 s the key values
exactly. MovingWireStill is the same file with those values written into the nodes and
no animation: its static pose is the animated file's pose at 1 s. Run from the repository
root; only the standard library.
"""
import math

import glb


def quat(axis, deg):
    h = math.radians(deg) / 2
    s = math.sin(h)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(h)]


class Glb(glb.Glb):
    """Float accessors of positions and key times carry min and max."""

    def floats(self, data, kind):
        n = len(data) // glb.COMPONENTS[kind]
        return self.add("f", data, kind, glb.FLOAT, n, kind in ("VEC3", "SCALAR"))

    def u16(self, data, kind="SCALAR"):
        return self.add("H", data, kind, glb.U16, len(data) // glb.COMPONENTS[kind])


def cube(g):
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u, v = [(axis + 1) % 3, (axis + 2) % 3]
            base = len(pos) // 3
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = 0.5 * sign, 0.5 * a, 0.5 * b
                pos += p
                nrm += n
            quad = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]
            idx += [base + k for k in quad]
    return {"attributes": {"POSITION": g.floats(pos, "VEC3"), "NORMAL": g.floats(nrm, "VEC3")},
            "indices": g.u16(idx)}


def square(g, x, z, half):
    pos = []
    for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        pos += [x + half * a, half * b, z]
    return g.floats(pos, "VEC3")


def build(animated):
    g = Glb()
    frame = square(g, 0.0, 0.8, 0.7)
    loop = g.u16([0, 1, 1, 2, 2, 3, 3, 0])
    far = square(g, -2.5, 0.0, 0.5)
    # The rope: 9 positions up Y from 0 to 2, weights moving from joint 3 to joint 4.
    rope_p, rope_j, rope_w = [], [], []
    for k in range(9):
        y = 2.0 * k / 8
        w1 = min(1.0, max(0.0, y - 0.5))
        rope_p += [2.5, y, 0.0]
        rope_j += [0, 1, 0, 0]
        rope_w += [1.0 - w1, w1, 0.0, 0.0]
    rope = g.floats(rope_p, "VEC3")
    rope_joints = g.u16(rope_j, "VEC4")
    rope_weights = g.floats(rope_w, "VEC4")
    strip = g.u16([k for i in range(8) for k in (i, i + 1)])
    ibm = g.floats([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2.5, 0, 0, 1,
                    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2.5, -1, 0, 1], "MAT4")
    move_t, move_r = [1.5, 0.5, 0.0], quat((0, 1, 0), 30)
    bend_r = quat((0, 0, 1), 45)
    meshes = [
        {"primitives": [cube(g),
                        {"attributes": {"POSITION": frame}, "indices": loop, "mode": 1},
                        {"attributes": {"POSITION": frame}, "mode": 0}]},
        {"primitives": [{"attributes": {"POSITION": far}, "indices": loop, "mode": 1}]},
        {"primitives": [{"attributes": {"POSITION": rope, "JOINTS_0": rope_joints,
                                        "WEIGHTS_0": rope_weights},
                         "indices": strip, "mode": 1}]},
        {"primitives": [cube(g)]},
    ]
    rows = g.floats([-0.8, 0.0, 0.0, 0.0, 0.0, 0.0, 0.8, 0.0, 0.0], "VEC3")
    small = g.floats([0.3] * 9, "VEC3")
    nodes = [{"mesh": 0, "children": [5]}, {"mesh": 1}, {"mesh": 2, "skin": 0},
             {"translation": [2.5, 0, 0], "children": [4]},
             {"translation": [0, 1, 0]},
             {"mesh": 3, "translation": [0, 0.9, 0],
              "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": rows,
                                                                       "SCALE": small}}}}]
    gltf = {"scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}], "nodes": nodes, "meshes": meshes,
            "skins": [{"joints": [3, 4], "inverseBindMatrices": ibm}],
            "extensionsUsed": ["EXT_mesh_gpu_instancing"]}
    if animated:
        times = g.floats([0.0, 1.0], "SCALAR")
        tv = g.floats([0.0, 0.0, 0.0] + move_t, "VEC3")
        rv = g.floats([0.0, 0.0, 0.0, 1.0] + move_r, "VEC4")
        bv = g.floats([0.0, 0.0, 0.0, 1.0] + bend_r, "VEC4")
        sv = g.floats([0.0, 0.0, 0.0, 1.0] + quat((0, 1, 0), 90), "VEC4")
        gltf["animations"] = [{
            "name": "Move",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                         {"sampler": 1, "target": {"node": 0, "path": "rotation"}},
                         {"sampler": 2, "target": {"node": 4, "path": "rotation"}}],
            "samplers": [{"input": times, "output": o, "interpolation": "STEP"}
                         for o in (tv, rv, bv)]}, {
            "name": "Spin",
            "channels": [{"sampler": 0, "target": {"node": 5, "path": "rotation"}}],
            "samplers": [{"input": times, "output": sv, "interpolation": "STEP"}]}]
    else:
        nodes[0].update(translation=move_t, rotation=move_r)
        nodes[4]["rotation"] = bend_r
    return g, gltf


for animated, path in ((True, "tests/data/motion/MovingWire.glb"),
                       (False, "tests/data/motion/MovingWireStill.glb")):
    g, gltf = build(animated)
    g.write(path, gltf)
