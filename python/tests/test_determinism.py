"""A picture is a function of the model and the options (issue #41): glview.render of a
sphere above the level-of-detail threshold and of one below it is `glview -o`'s picture,
pixel for pixel, with the mesh cache cold, warm and off and with 1 or 2 threads."""
import math
import os
import subprocess

import numpy as np
import pytest

import glview
from glview import _glview as _native
from glview._glview import decode_png

SIZE = (200, 150)
# The mesh cache's size threshold (scene::cache::MIN_SIZE): smaller files get no entry.
MIN_SIZE = 4 << 20


def sphere_obj(path, rings: int, segments: int) -> str:
    """The Rust tests' UV sphere (tests/suite/culling.rs): 2·segments·(rings − 1) triangles,
    padded with comment lines to the cache's threshold so its first load writes an entry."""
    lines = ["o sphere"]

    def vertex(p):
        xyz = " ".join(f"{c:.6f}" for c in p)
        lines.append(f"v {xyz}\nvn {xyz}")

    vertex((0.0, 1.0, 0.0))
    for j in range(1, rings):
        th = math.pi * j / rings
        for i in range(segments):
            ph = math.tau * i / segments
            vertex((math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph)))
    vertex((0.0, -1.0, 0.0))

    def at(j, i):
        return 2 + (j - 1) * segments + i % segments

    south = 2 + (rings - 1) * segments

    def face(a, b, c):
        lines.append(f"f {a}//{a} {b}//{b} {c}//{c}")

    for i in range(segments):
        face(1, at(1, i), at(1, i + 1))
        face(south, at(rings - 1, i + 1), at(rings - 1, i))
    for j in range(1, rings - 1):
        for i in range(segments):
            face(at(j, i), at(j + 1, i), at(j + 1, i + 1))
            face(at(j, i), at(j + 1, i + 1), at(j, i + 1))
    text = "\n".join(lines) + "\n"
    pad = "# padding: large enough for a mesh cache entry\n"
    if len(text) < MIN_SIZE:
        text += pad * ((MIN_SIZE - len(text)) // len(pad) + 1)
    path.write_text(text)
    return str(path)


# 65,536 triangles (more than the 30,000 pixels: `--lod auto` draws levels) and 20,480
# (clustered, but fewer than the pixels: every triangle).
@pytest.mark.parametrize("rings,segments", [(129, 256), (65, 160)], ids=["above", "below"])
def test_cache_cold_warm_off_threads_and_the_cli_give_one_picture(
    tmp_path, monkeypatch, glview_bin, rings, segments
):
    model = sphere_obj(tmp_path / "sphere.obj", rings, segments)
    # Read by this process's loads and inherited by the command lines below.
    monkeypatch.setenv("GLVIEW_CACHE_DIR", str(tmp_path / "cache"))
    glview.release()
    pictures = {"cold": glview.render(model, size=SIZE).color}
    _native.wait_for_cache_writes()
    # A new context and renderer: the scene comes from the entry just written.
    glview.release()
    pictures["warm"] = glview.render(model, size=SIZE).color
    pictures["no cache"] = glview.render(model, size=SIZE, no_cache=True).color
    for threads in ("1", "2"):
        out = tmp_path / f"cli-{threads}.png"
        env = {**os.environ, "RAYON_NUM_THREADS": threads}
        p = subprocess.run(
            [glview_bin, model, "--size", "200x150", "-o", str(out)],
            capture_output=True, text=True, env=env,
        )
        assert p.returncode == 0, p.stderr
        pictures[f"cli, {threads} thread(s)"] = decode_png(str(out))
    first = pictures["cold"]
    for name, img in pictures.items():
        assert np.array_equal(img, first), f"{name}: differs from the cold picture"
    # Above the threshold the levels take part (every triangle is another picture); below
    # it every triangle is what auto draws.
    every = glview.render(model, size=SIZE, lod="off").color
    glview.release()
    triangles = 2 * segments * (rings - 1)
    assert np.array_equal(every, first) == (triangles <= SIZE[0] * SIZE[1])


def test_every_combination_of_read_backs_leaves_the_colour_the_clis(tmp_path, glview_bin):
    """Issue 50: depth, normals, ids and the linear colour come from the geometry the colour
    is drawn with, so asking for any of them never changes the picture (on the sphere above
    the level-of-detail threshold, where `depth=True` used to draw every triangle)."""
    model = sphere_obj(tmp_path / "sphere.obj", 129, 256)
    out = tmp_path / "cli.png"
    p = subprocess.run([glview_bin, model, "--size", "200x150", "-o", str(out)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    want = decode_png(str(out))
    for k in range(16):
        flags = dict(depth=bool(k & 1), normals=bool(k & 2), ids=bool(k & 4), linear=bool(k & 8))
        img = glview.render(model, size=SIZE, **flags)
        assert np.array_equal(img.color, want), f"{flags}: the colour differs from glview -o"
        if flags["depth"]:
            assert np.isfinite(img.depth).any()
    glview.release()
