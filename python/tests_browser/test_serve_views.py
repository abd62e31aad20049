"""The server page's camera and variant pickers (issue 37): on a generated glTF with two
cameras and two KHR_materials_variants, K and V change the picture on the page, and a
choice in a picker gives the still `glview -o --camera NAME` / `--variant NAME` draws, byte
for byte (the picker's index goes into the view's options as K's and V's do).
"""
import base64
import json
import math
import struct
import subprocess

import pytest

from test_serve_page import (  # noqa: F401 (FLAGS: the browser fixture reads it here)
    FLAGS, SIZE, Server, glview_bin, last_still, open_page, pixels, wait_still)

CAMERAS = ["Front", "Side"]
# The second variant's name is markup: the picker must show it as text (the names are the
# file author's).
BLUE = '<b>Blue</b> & "sky"'
VARIANTS = ["Red", BLUE]


def box_gltf() -> dict:
    """A unit box at the origin (grey; variant Red and Blue map it to red and blue) and two
    perspective cameras: Front on +Z, Side on +X at 45° above, both looking at the box."""
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for s in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = s
            u = [0.0, 0.0, 0.0]
            u[(axis + 1) % 3] = 1.0
            v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append([(n[k] + u[k] * a + v[k] * b) * 0.5 for k in range(3)])
                nrm.append(n)
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    blob = b"".join(struct.pack("<3f", *p) for p in pos + nrm) + struct.pack(f"<{len(idx)}I", *idx)
    nv = len(pos)
    view = lambda off, length: {"buffer": 0, "byteOffset": off, "byteLength": length}  # noqa: E731
    material = lambda name, rgb: {"name": name, "pbrMetallicRoughness": {  # noqa: E731
        "baseColorFactor": [*rgb, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}}
    # Side: yaw +90° about Y, then pitched down 45° about its own X.
    y, p = math.radians(90) / 2, math.radians(-45) / 2
    qy, qx = (0, math.sin(y), 0, math.cos(y)), (math.sin(p), 0, 0, math.cos(p))
    side = (qy[3] * qx[0], qy[1] * qx[3], -qy[1] * qx[0], qy[3] * qx[3])
    return {
        "asset": {"version": "2.0"}, "scene": 0,
        "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [{"name": n} for n in VARIANTS]}},
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 0, 4]},
            {"camera": 1, "translation": [3, 3, 0], "rotation": list(side)},
        ],
        "cameras": [{"name": n, "type": "perspective",
                     "perspective": {"yfov": 0.7, "znear": 0.1}} for n in CAMERAS],
        "materials": [material("grey", (0.5, 0.5, 0.5)), material("red", (0.9, 0.1, 0.1)),
                      material("blue", (0.1, 0.1, 0.9))],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0,
            "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]}}}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
             "min": [-0.5] * 3, "max": [0.5] * 3},
            {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "bufferViews": [view(0, nv * 12), view(nv * 12, nv * 12), view(nv * 24, len(idx) * 4)],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }


@pytest.fixture(scope="module")
def views_server(glview_bin, tmp_path_factory):
    folder = tmp_path_factory.mktemp("views")
    (folder / "box.gltf").write_text(json.dumps(box_gltf()))
    s = Server(glview_bin, "--size", f"{SIZE[0]}x{SIZE[1]}", str(folder))
    s.model = folder / "box.gltf"
    yield s
    s.stop()


@pytest.fixture
def page(browser, views_server):
    page = open_page(browser, views_server.url)
    yield page
    errors = page.errors
    page.context.close()
    assert not errors, f"the page threw: {errors}"


def still_after(page, *, key=None, pick=None):
    """Presses `key` or chooses `pick` = (picker id, option label); returns the header and
    PNG of the still that shows it."""
    if key:
        page.keyboard.press(key)
    else:
        page.locator("#" + pick[0]).select_option(label=pick[1])
    h = wait_still(page, page.evaluate("window.glview.sent"))
    return h, last_still(page)


def test_k_and_v_change_the_picture(page):
    first = wait_still(page)
    assert first["views"] == {"cameras": CAMERAS, "camera": None, "variants": VARIANTS, "variant": None}
    before = pixels(last_still(page)).tobytes()
    h, png = still_after(page, key="k")
    assert h["views"]["camera"] == 0, h["views"]
    through = pixels(png).tobytes()
    assert through != before
    assert page.locator("#camera").input_value() == "0"
    h, png = still_after(page, key="v")
    assert h["views"]["variant"] == 0, h["views"]
    assert pixels(png).tobytes() != through
    assert page.locator("#variant").input_value() == "0"


def test_pickers_draw_what_the_command_line_draws(page, views_server, glview_bin, tmp_path):
    wait_still(page)
    for sel, labels in (("camera", ["orbit camera", *CAMERAS]), ("variant", ["own materials", *VARIANTS])):
        assert page.locator("#" + sel).is_visible()
        assert page.locator(f"#{sel} option").all_inner_texts() == labels
    args = []
    for pick, flag in ((("variant", BLUE), "--variant"), (("camera", "Side"), "--camera")):
        h, png = still_after(page, pick=pick)
        args += [flag, pick[1]]
        out = tmp_path / "out.png"
        w, hh = h["view"]
        p = subprocess.run([glview_bin, "-o", str(out), "--size", f"{w}x{hh}", *args, str(views_server.model)],
                           capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        a, b = pixels(png), pixels(out.read_bytes())
        assert a.size == b.size == (w, hh)
        assert a.tobytes() == b.tobytes(), f"the still ({h['command']}) differs from glview -o {' '.join(args)}"
    assert h["views"] == {"cameras": CAMERAS, "camera": 1, "variants": VARIANTS, "variant": 1}
    # The view's link carries both choices: opened, it draws the same still.
    link = page.evaluate("window.glview.viewLink()")
    assert "camera=1" in link and "variant=1" in link and "keys=" not in link, link
    other = open_page(page.context.browser, link)
    try:
        wait_still(other, other.evaluate("window.glview.sent"))
        assert last_still(other) == png
        assert other.locator("#camera").input_value() == other.locator("#variant").input_value() == "1"
    finally:
        other.context.close()
    # A choice the file lacks is a one-line error naming what it has; the view stays.
    page.evaluate("window.glview.send({type: 'pick', what: 'camera', index: 7, seq: 1000})")
    page.wait_for_function("document.getElementById('status').textContent.includes('no camera')")
    assert '1 "Side"' in page.locator("#status").inner_text()
