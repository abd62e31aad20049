"""The server page's controls of a glTF file's own views, with one browser between them.

Cameras and variants (issue 37): on a generated glTF with two cameras and two
KHR_materials_variants, K and V change the picture on the page, and a choice in a picker
gives the still `glview -o --camera NAME` / `--variant NAME` draws, byte for byte (the
picker's index goes into the view's options as K's and V's do).

Animations (issue 39), driven as a user drives them on the committed Khronos
BoxAnimated.glb: open it in the model picker, Play, Space on the view to pause, the
frame-step buttons; a follower's page shows the presenter's time. Checked is what the user
sees: frames arrive and the time shown (`#clock`'s `data-time`, the header's number as it
is) moves on while playing; paused, neither the time nor the picture moves; a step lands on
the `--fps` grid and the next one moves by exactly one frame (the time is an f32, so
"exactly" is k/fps rounded to f32, as `--time` parses it); the still at a stepped time is
`glview -o --animation 0 --time T`, byte for byte. The server's side of this (the play and
time messages, frames at most `--fps` a second) is tests/suite/play.rs.
"""
import base64
import json
import math
import shutil
import struct
import subprocess

import pytest

from test_serve_page import (  # noqa: F401 (FLAGS: the browser fixture reads it here)
    FLAGS, REPO, SIZE, Server, glview_bin, last_still, open_page, pixels, wait_still)

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


MOTION = REPO / "tests" / "data" / "khronos" / "motion"
ANIMATED = "BoxAnimated.glb"


def f32(x: float) -> float:
    """`x` rounded to f32, as glview holds a time. (A quotient of two small integers rounded
    to f64 and then to f32 is the f32 quotient: f64 has more than twice f32's bits.)"""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def shown_time(page):
    """The time the page shows: None for the static pose."""
    t = page.locator("#clock").get_attribute("data-time")
    return None if t in (None, "") else float(t)


def wait_time(page, above):
    """Waits until the page shows a time above `above`; returns it, checked against the
    clock's text in the same instant (frames keep coming while it plays)."""
    page.wait_for_function(
        "t => { const d = document.getElementById('clock').dataset.time;"
        " return d !== undefined && d !== '' && Number(d) > t; }", arg=above, timeout=15000)
    t, text = page.evaluate("() => { const c = document.getElementById('clock');"
                            " return [c.dataset.time, c.textContent]; }")
    # The text is rounded to hundredths for the eye.
    assert abs(float(text.split(" / ")[0]) - float(t)) <= 0.005 + 1e-9, (t, text)
    return float(t)


def press(page, button):
    """Clicks one of the play controls; returns the header of the still that shows it."""
    page.locator("#" + button).click()
    return wait_still(page, page.evaluate("window.glview.sent"))


def test_play_pause_step_and_follow(browser, glview_bin, tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    # Two models, so the user opens the animated one in the picker.
    for name in ("AnimatedMorphCube.glb", ANIMATED):
        shutil.copy(MOTION / name, folder)
    s = Server(glview_bin, "--size", f"{SIZE[0]}x{SIZE[1]}", str(folder))
    presenter = follower = None
    try:
        presenter = open_page(browser, s.presenter_url)
        follower = open_page(browser, s.url + "&follow=1")
        presenter.locator("#model").select_option(ANIMATED)
        h = wait_still(presenter, presenter.evaluate("window.glview.sent"))
        assert h["model"] == ANIMATED, h
        assert presenter.locator("#motion").is_visible()
        assert shown_time(presenter) is None
        assert presenter.locator("#clock").inner_text() == "static pose"
        fps = h["motion"]["fps"]
        duration = h["motion"]["animations"][0]["duration"]

        # Play: preview frames come with a time that moves on; the follower shows it too.
        frames = presenter.evaluate("window.glview.frames")
        presenter.locator("#play").click()
        t1 = wait_time(presenter, 0)
        t2 = wait_time(presenter, t1)
        assert presenter.evaluate("window.glview.frames") >= frames + 2
        assert presenter.locator("#play").inner_text() == "Pause"
        assert wait_time(follower, 0) > 0

        # Space on the view pauses: the still comes, then nothing for half a second (seven
        # frames' time at --fps 15; tests/suite/play.rs waits a whole second on the server).
        presenter.locator("#view").press("Space")
        h = wait_still(presenter, presenter.evaluate("window.glview.sent"))
        assert h["motion"]["playing"] is False, h["motion"]
        assert presenter.locator("#play").inner_text() == "Play"
        paused = shown_time(presenter)
        assert t2 <= paused < duration, (t2, paused)
        frames = presenter.evaluate("window.glview.frames")
        presenter.wait_for_timeout(500)
        assert presenter.evaluate("window.glview.frames") == frames
        assert shown_time(presenter) == paused

        # A step forward lands on the next frame of the grid; the next moves by one frame,
        # a step back returns: k/fps, (k+1)/fps, k/fps.
        press(presenter, "step-fwd")
        k = math.floor(paused * fps + 1e-3) + 1
        assert shown_time(presenter) == f32(k / fps), (paused, shown_time(presenter), k)
        press(presenter, "step-fwd")
        assert shown_time(presenter) == f32((k + 1) / fps)
        ahead = pixels(last_still(presenter))
        h = press(presenter, "step-back")
        assert shown_time(presenter) == f32(k / fps)
        assert h["motion"]["playing"] is False and h["motion"]["animation"] == 0, h["motion"]
        still = last_still(presenter)
        assert pixels(still).tobytes() != ahead.tobytes(), "a frame's step changed nothing"

        # The still at that time is the command line's picture of it.
        t = presenter.locator("#clock").get_attribute("data-time")
        out = tmp_path / "moment.png"
        w, hh = h["view"]
        p = subprocess.run([glview_bin, str(folder / ANIMATED), "-o", str(out), "--size", f"{w}x{hh}",
                            "--animation", "0", "--time", t], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        a, b = pixels(still), pixels(out.read_bytes())
        assert a.size == b.size == (w, hh)
        assert a.tobytes() == b.tobytes(), f"the still ({h['command']}) differs from glview -o --time {t}"

        # Teacher mode: the follower shows the presenter's moment and its very still.
        follower.wait_for_function(
            "t => window.glview.last.still && document.getElementById('clock').dataset.time === t",
            arg=t)
        assert last_still(follower) == still
        assert not presenter.errors and not follower.errors, (presenter.errors, follower.errors)
    finally:
        for page in (presenter, follower):
            if page is not None:
                page.context.close()
        s.stop()
