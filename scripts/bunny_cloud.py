#!/usr/bin/env python3
"""A point cloud from an OBJ mesh, for pictures and comparisons with other viewers (the
points picture of docs/guide.md beside f3d's): every vertex with its area-weighted normal
and a colour by height (orange at the top, blue at the bottom), as a binary PLY.

    python3 scripts/bunny_cloud.py ../shared/models/stanford-bunny/stanford-bunny.obj bunny-cloud.ply
"""
import struct
import sys


def main(src, dst):
    vs, faces = [], []
    with open(src) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                vs.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = [int(c.split("/")[0]) for c in w[1:]]
                idx = [i - 1 if i > 0 else len(vs) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    ns = [[0.0, 0.0, 0.0] for _ in vs]
    for a, b, c in faces:
        pa, pb, pc = vs[a], vs[b], vs[c]
        u = [pb[i] - pa[i] for i in range(3)]
        v = [pc[i] - pa[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        for k in (a, b, c):
            for i in range(3):
                ns[k][i] += n[i]
    ys = [p[1] for p in vs]
    lo, hi = min(ys), max(ys)
    out = bytearray()
    for p, n in zip(vs, ns):
        length = sum(x * x for x in n) ** 0.5 or 1.0
        t = (p[1] - lo) / (hi - lo or 1.0)
        rgb = [int(round(255 * (c0 + (c1 - c0) * t))) for c0, c1 in zip((0.2, 0.6, 0.9), (0.9, 0.45, 0.2))]
        out += struct.pack("<6f3B", *p, *(x / length for x in n), *rgb)
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment made by glview scripts/bunny_cloud.py\n"
        f"element vertex {len(vs)}\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
    )
    with open(dst, "wb") as f:
        f.write(header.encode() + out)
    print(f"{dst}: {len(vs)} points")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
