"""Browser tests of `glview serve`'s page (cli/src/serve/page/) against the real server:
Debian's Chromium, headless, driven by a pinned Playwright (scripts/test_browser.sh). The
server is started as `$GLVIEW_BIN serve --bind 127.0.0.1:0 --size 320x240` and draws the
built-in scene; every test opens its own page, so its own socket and view.

What is checked is what a user sees and keeps: the first frame, keys and drags that change
the view, the lossless still equal to `glview -o` of the same view, the compare panes with
their numbers, Save PNG giving exactly the still's bytes, and the token.
"""
import base64
import io
import os
import pathlib
import queue
import shutil
import subprocess
import threading
import time
import urllib.parse

import pytest
from PIL import Image

REPO = pathlib.Path(__file__).resolve().parents[2]
from conftest import CHROMIUM  # noqa: F401 (test_serve_proxy imports it from here)
SIZE = (320, 240)
FLAGS = ["--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", "--disable-quic"]

# Every message the page sends, recorded before the page's script runs (to check what went
# over the socket, e.g. that a drag's pixels add up).
RECORD_SENT = """
window.__sent = [];
const send = WebSocket.prototype.send;
WebSocket.prototype.send = function (d) {
  if (typeof d === 'string') window.__sent.push(JSON.parse(d));
  return send.call(this, d);
};
"""

# The last still's bytes as base64 (a plain array of numbers would be ten times larger).
LAST_STILL_B64 = """() => {
  const b = window.glview.lastStill;
  if (!b) return null;
  let s = '';
  for (let i = 0; i < b.length; i += 0x8000) s += String.fromCharCode.apply(null, b.subarray(i, i + 0x8000));
  return btoa(s);
}"""


@pytest.fixture(scope="session")
def glview_bin() -> str:
    exe = os.environ.get("GLVIEW_BIN") or str(REPO / "target" / "debug" / "glview")
    assert os.path.exists(exe), f"{exe} is missing: build glview first (cargo build)"
    return exe


class Server:
    """`glview serve` as a subprocess; its stdout is drained by a thread (so it never blocks).
    The stream's (`--stream-only`): local mode is python/tests_web/test_serve_local.py's."""

    def __init__(self, glview_bin, *args):
        self.proc = subprocess.Popen(
            [glview_bin, "serve", "--bind", "127.0.0.1:0", "--stream-only", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.lines = queue.Queue()
        self.output = []
        for stream in (self.proc.stdout, self.proc.stderr):
            threading.Thread(target=self._drain, args=(stream,), daemon=True).start()
        self.url = self.presenter_url = None
        deadline = time.monotonic() + 30
        while self.url is None or self.presenter_url is None:
            try:
                line = self.lines.get(timeout=max(0.01, deadline - time.monotonic()))
            except queue.Empty:
                self.stop()
                pytest.fail("glview serve printed no address in 30 s:\n" + "".join(self.output))
            if line.startswith("glview serve: open "):
                self.url = line.split()[-1]
            elif line.startswith("glview serve: presenter "):
                self.presenter_url = line.split()[-1]
        parts = urllib.parse.urlsplit(self.url)
        self.origin = f"{parts.scheme}://{parts.netloc}"
        self.token = urllib.parse.parse_qs(parts.query)["token"][0]

    def _drain(self, stream):
        for line in stream:
            self.output.append(line)
            self.lines.put(line)

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


@pytest.fixture(scope="module")
def server(glview_bin):
    s = Server(glview_bin, "--size", f"{SIZE[0]}x{SIZE[1]}")
    yield s
    s.stop()


def open_page(browser, url):
    """A fresh context (no cookie) with the page loaded and its first frame drawn."""
    context = browser.new_context(viewport={"width": 800, "height": 600}, accept_downloads=True)
    page = context.new_page()
    page.errors = []
    page.on("pageerror", lambda e: page.errors.append(str(e)))
    page.add_init_script(RECORD_SENT)
    response = page.goto(url)
    assert response.status == 200, response.status
    page.wait_for_function("window.glview && window.glview.frames >= 1", timeout=15000)
    return page


@pytest.fixture
def page(browser, server):
    page = open_page(browser, server.url)
    yield page
    errors = page.errors
    page.context.close()
    assert not errors, f"the page threw: {errors}"


def wait_still(page, seq=0, compare=None, timeout=15000):
    """Waits for a still showing every input up to `seq`; returns its header. (`shown` is
    the page's highest seq of its own frames: a presenter's frame on a follower's page
    carries the presenter's seq.)"""
    page.wait_for_function(
        """([seq, compare]) => {
          const g = window.glview, h = g.last;
          return h && h.still && h.seq >= seq && g.shown >= seq &&
            (compare === null || h.compare === compare);
        }""", arg=[seq, compare], timeout=timeout)
    return page.evaluate("window.glview.last")


def last_still(page) -> bytes:
    return base64.b64decode(page.evaluate(LAST_STILL_B64))


def pixels(png: bytes) -> Image.Image:
    return Image.open(io.BytesIO(png)).convert("RGBA")


def test_first_frame_fills_the_canvas_one_pixel_per_css_pixel(page):
    box = page.evaluate("""() => {
      const c = document.getElementById('view'), r = c.getBoundingClientRect();
      return [c.width, c.height, r.width, r.height];
    }""")
    assert box == [SIZE[0], SIZE[1], SIZE[0], SIZE[1]]
    h = page.evaluate("window.glview.last")
    assert h["view"] == list(SIZE), h
    # One model (the built-in scene): no picker.
    assert page.locator("#model").is_hidden()


def test_arrow_keys_still_equals_the_command_line(page, glview_bin, tmp_path):
    first = wait_still(page)
    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowRight")
    seq = page.evaluate("window.glview.sent")
    assert [m["key"] for m in page.evaluate("window.__sent") if m["type"] == "key"] == ["Right", "Right"]
    h = wait_still(page, seq)
    assert h["command"] != first["command"], h["command"]
    got = last_still(page)
    # Default yaw 30, two presses of Right: +10 degrees.
    out = tmp_path / "out.png"
    p = subprocess.run([glview_bin, "-o", str(out), "--size", f"{SIZE[0]}x{SIZE[1]}", "--yaw", "40"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    a, b = pixels(got), pixels(out.read_bytes())
    assert a.size == b.size == SIZE
    assert a.tobytes() == b.tobytes(), f"the still ({h['command']}) differs from glview -o --yaw 40; first {first['command']}; sent {page.evaluate('window.__sent')}"


def test_mouse_drag_orbits(page):
    first = wait_still(page)
    before = last_still(page)
    box = page.locator("#view").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 60, y + 20, steps=10)
    page.mouse.up()
    page.wait_for_function("window.__sent.some(m => m.type === 'drag')")
    page.wait_for_timeout(100)  # the last animation frame's remainder
    drags = [m for m in page.evaluate("window.__sent") if m["type"] == "drag"]
    # Coalesced per animation frame, but not a pixel lost.
    assert (sum(m["dx"] for m in drags), sum(m["dy"] for m in drags)) == (60, 20), drags
    h = wait_still(page, page.evaluate("window.glview.sent"))
    assert h["command"] != first["command"]
    assert pixels(last_still(page)).tobytes() != pixels(before).tobytes()


def test_compare_shows_both_panes_and_the_numbers(page):
    wait_still(page)
    page.get_by_role("button", name="Compare Phong | PBR").click()
    assert page.evaluate("window.__sent.filter(m => m.type === 'key').map(m => m.key)") == ["C"]
    h = wait_still(page, page.evaluate("window.glview.sent"), compare=True)
    assert h["diff"], h
    assert h["diff"].get("model_pixels", 0) > 0, f"docs/serve.md's diff has model_pixels: {h['diff']}"
    img = pixels(last_still(page))
    w, hh = img.size
    left, right = img.crop((0, 0, w // 2, hh)), img.crop((w // 2, 0, w // 2 * 2, hh))
    assert left.tobytes() != right.tobytes()
    text = page.locator("#diff").inner_text()
    assert page.locator("#diff").is_visible()
    assert "/255" in text and "SSIM" in text and str(h["diff"]["model_pixels"]) in text, text


def test_touch_drag_and_pinch(browser, server):
    context = browser.new_context(viewport={"width": 800, "height": 600}, has_touch=True)
    try:
        page = context.new_page()
        page.add_init_script(RECORD_SENT)
        page.goto(server.url)
        first = wait_still(page)
        box = page.locator("#view").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        cdp = context.new_cdp_session(page)

        def touch(kind, *points):
            cdp.send("Input.dispatchTouchEvent", {
                "type": kind, "touchPoints": [{"x": px, "y": py, "id": i} for i, (px, py) in points]})
            page.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")

        # One finger: a drag of 40 px to the left.
        touch("touchStart", (0, (x, y)))
        for k in range(1, 5):
            touch("touchMove", (0, (x - 10 * k, y)))
        touch("touchEnd")
        # Two fingers from 40 to 80 px apart: a factor 2, log(2)/log(1.1) = 7.27 notches in.
        touch("touchStart", (0, (x - 20, y)), (1, (x + 20, y)))
        for k in range(1, 5):
            touch("touchMove", (0, (x - 20 - 5 * k, y)), (1, (x + 20 + 5 * k, y)))
        touch("touchEnd")
        sent = page.evaluate("window.__sent")
        drags = [m for m in sent if m["type"] == "drag"]
        notches = sum(m["notches"] for m in sent if m["type"] == "wheel")
        assert (sum(m["dx"] for m in drags), sum(m["dy"] for m in drags)) == (-40, 0), drags
        assert abs(notches - 7.27) < 0.05, sent
        h = wait_still(page, page.evaluate("window.glview.sent"))
        assert h["command"] != first["command"]
    finally:
        context.close()


def test_wheel_zooms_and_errors_show(page):
    first = wait_still(page)
    box = page.locator("#view").bounding_box()
    page.mouse.move(box["x"] + 100, box["y"] + 100)
    page.mouse.wheel(0, -100)  # away from the user: zoom in, one notch
    page.wait_for_function("window.__sent.some(m => m.type === 'wheel')")
    wheels = [m["notches"] for m in page.evaluate("window.__sent") if m["type"] == "wheel"]
    assert wheels == [1], wheels
    h = wait_still(page, page.evaluate("window.glview.sent"))
    assert h["command"] != first["command"]
    # The page did not scroll (the wheel is the view's).
    assert page.evaluate("window.scrollY") == 0
    # An error from the server is shown, and the socket stays open.
    page.evaluate("window.glview.send({type: 'key', key: 'NoSuchKey', seq: 1000})")
    page.wait_for_function("document.getElementById('status').textContent.includes('NoSuchKey')")
    assert "error" in page.locator("#status").inner_text()


def test_presenter_and_follower(browser, server):
    presenter = open_page(browser, server.presenter_url)
    follower = open_page(browser, server.url + "&follow=1")
    try:
        assert presenter.locator("#presenting").is_visible()
        assert "present=" not in presenter.url and "token" not in presenter.url, presenter.url
        assert presenter.locator("#follow-label").is_hidden()
        box = follower.locator("#follow")
        assert box.is_checked() and box.is_enabled()
        assert {"type": "follow", "on": True} in follower.evaluate("window.__sent")
        wait_still(presenter)
        presenter.keyboard.press("ArrowLeft")
        h = wait_still(presenter, presenter.evaluate("window.glview.sent"))
        # One render for the class: the follower is shown the presenter's still.
        follower.wait_for_function("c => window.glview.last.still && window.glview.last.command === c",
                                   arg=h["command"])
        assert last_still(follower) == last_still(presenter)
        # Save PNG on the follower: the presenter's still as it is, no new render.
        with follower.expect_download() as d:
            follower.get_by_role("button", name="Save PNG").click()
        assert pathlib.Path(d.value.path()).read_bytes() == last_still(presenter)
        # The follower's own input leaves follow mode (and the box says so at once).
        follower.keyboard.press("ArrowDown")
        assert not box.is_checked()
        g = wait_still(follower, follower.evaluate("window.glview.sent"))
        assert g["command"] != h["command"]
        presenter.context.close()
        follower.wait_for_function("document.getElementById('follow').disabled")
        assert not presenter.errors and not follower.errors, (presenter.errors, follower.errors)
    finally:
        follower.context.close()
        if not presenter.is_closed():
            presenter.context.close()


def test_model_picker(browser, glview_bin, tmp_path):
    shared = REPO.parent / "shared" / "models"
    for name in ("bunny-small/bunny.obj", "teapot-small/teapot.obj"):
        shutil.copy(shared / name, tmp_path)
    s = Server(glview_bin, "--size", f"{SIZE[0]}x{SIZE[1]}", str(tmp_path))
    try:
        page = open_page(browser, s.url)
        picker = page.locator("#model")
        assert picker.is_visible()
        assert picker.locator("option").all_inner_texts() == ["bunny.obj", "teapot.obj"]
        first = wait_still(page)
        assert first["model"] == picker.input_value()
        picker.select_option("teapot.obj")
        h = wait_still(page, page.evaluate("window.glview.sent"))
        assert h["model"] == "teapot.obj", h
        out = tmp_path / "teapot.png"
        p = subprocess.run([glview_bin, str(tmp_path / "teapot.obj"), "-o", str(out),
                            "--size", f"{SIZE[0]}x{SIZE[1]}"], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        assert pixels(last_still(page)).tobytes() == pixels(out.read_bytes()).tobytes(), h["command"]
        # Keys go to the view again after a pick (the picker gave its focus back).
        page.keyboard.press("s")
        assert page.evaluate("window.__sent.filter(m => m.type === 'key').at(-1).key") == "S"
        s.stop()
        page.wait_for_function("document.getElementById('status').textContent === 'disconnected'")
        assert not page.errors, page.errors
        page.context.close()
    finally:
        s.stop()


def test_save_png_downloads_exactly_the_still(page):
    wait_still(page)
    # The still on screen is current: saved without asking.
    with page.expect_download() as d:
        page.get_by_role("button", name="Save PNG").click()
    assert pathlib.Path(d.value.path()).read_bytes() == last_still(page)
    assert d.value.suggested_filename.startswith("glview-") and d.value.suggested_filename.endswith(".png")
    assert not any(m["type"] == "still" for m in page.evaluate("window.__sent"))
    # Just after a key: the page asks for the still and saves it when it comes.
    # (Both in one script, so the still cannot come between the key and the click.)
    with page.expect_download() as d:
        page.evaluate("""() => {
          document.dispatchEvent(new KeyboardEvent('keydown', {key: 'ArrowUp', bubbles: true}));
          document.getElementById('save').click();
        }""")
    saved = pathlib.Path(d.value.path()).read_bytes()
    assert any(m["type"] == "still" for m in page.evaluate("window.__sent"))
    assert saved == last_still(page)
    assert page.evaluate("window.glview.last.still")
    assert saved.startswith(b"\x89PNG\r\n\x1a\n")


def test_screenshot_for_the_docs(browser, glview_bin):
    """The page in compare mode, a larger view than the other tests': into target/ (its
    overlay shows timings, so it differs every run), and into docs/serve.png with
    GLVIEW_UPDATE_SCREENSHOT=1."""
    s = Server(glview_bin, "--size", "640x400")
    try:
        page = open_page(browser, s.url)
        wait_still(page)
        page.keyboard.press("c")
        wait_still(page, page.evaluate("window.glview.sent"), compare=True)
        page.wait_for_function("!document.getElementById('diff').hidden")
        out = REPO / "target" / "serve-page.png"
        out.parent.mkdir(exist_ok=True)
        page.screenshot(path=str(out))
        if os.environ.get("GLVIEW_UPDATE_SCREENSHOT") == "1":
            page.screenshot(path=str(REPO / "docs" / "serve.png"))
        assert not page.errors, page.errors
        page.context.close()
    finally:
        s.stop()


def test_token_is_required(browser, server):
    context = browser.new_context()
    try:
        page = context.new_page()
        assert page.goto(server.origin + "/").status == 401
        assert page.goto(server.origin + "/?token=" + "0" * len(server.token)).status == 403
        assert context.request.get(server.origin + "/app.js").status == 401
        assert context.request.get(server.origin + "/models").status == 401
    finally:
        context.close()
    # Once the page was opened with the token, its cookie lets the address without it work
    # (a reload after the query was cut off), socket included.
    page = open_page(browser, server.url)
    try:
        # The address bar no longer shows the token (a projected tab shows no secret).
        assert "token" not in page.url and page.url.startswith(server.origin), page.url
        page.goto(server.origin + "/")
        page.wait_for_function("window.glview && window.glview.frames >= 1", timeout=15000)
        assert not page.errors, page.errors
    finally:
        page.context.close()


FITS = """() => {
  if (!window.glview) return false;
  const h = window.glview.last, c = document.getElementById('view').getBoundingClientRect();
  const root = document.documentElement;
  return h && h.still && h.view[0] === c.width && h.view[1] === c.height &&
    c.top >= 0 && c.bottom <= window.innerHeight && c.right <= root.clientWidth &&
    root.scrollWidth <= root.clientWidth;
}"""


def test_the_view_fits_a_laptop_window(browser, glview_bin):
    """A 1366×768 screen leaves Firefox ESR 1366×682 of page: with the default --size
    (1024x768) the view takes the room below the bar, all of it visible without scrolling
    (the help line below it may need a scroll), and its still is one image pixel per CSS
    pixel at that size."""
    s = Server(glview_bin)
    try:
        context = browser.new_context(viewport={"width": 1366, "height": 682})
        page = context.new_page()
        page.goto(s.url)
        page.wait_for_function(FITS, timeout=20000)
        h = page.evaluate("window.glview.last")
        assert h["view"][0] == 1024 and 600 <= h["view"][1] < 682, h["view"]
        assert (h["width"], h["height"]) == tuple(h["view"]), h
        # A resize asks again: a smaller window, a smaller view.
        page.set_viewport_size({"width": 900, "height": 500})
        page.wait_for_function("(" + FITS + ")() && window.glview.last.view[0] < 900", timeout=20000)
        context.close()
    finally:
        s.stop()


class CoursePage:
    """A page of another site framing `url` in 480×360, as a learning platform's lesson
    would: served by this test on another loopback port (a public address would be refused
    by Chromium's local network access rules, whatever the viewer's headers)."""

    def __init__(self, url):
        import http.server
        self.url = url
        course = self

        class Handler(http.server.BaseHTTPRequestHandler):
            def do_GET(self):
                html = (f'<p>Lesson 3</p><iframe src="{course.url}" width="480" height="360" '
                        'style="border:0"></iframe>').encode()
                self.send_response(200)
                self.send_header("Content-Type", "text/html")
                self.send_header("Content-Length", str(len(html)))
                self.end_headers()
                self.wfile.write(html)

            def log_message(self, *args):
                pass

        self.httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.origin = f"http://127.0.0.1:{self.httpd.server_address[1]}"
        threading.Thread(target=self.httpd.serve_forever, daemon=True).start()

    def open(self, browser):
        page = browser.new_context(viewport={"width": 800, "height": 600}).new_page()
        page.goto(self.origin + "/")
        return page

    def stop(self):
        self.httpd.shutdown()


def test_the_view_fits_a_480x360_iframe(browser, glview_bin):
    """A course page of an --embed-origin frames the viewer in 480×360: the whole view is
    visible inside it. The server prints the iframe snippet."""
    course = CoursePage(None)
    s = Server(glview_bin, "--embed-origin", course.origin)
    try:
        course.url = s.url
        page = course.open(browser)
        page.frame_locator("iframe").locator("#view").wait_for(timeout=20000)
        inner = page.frames[1]
        inner.wait_for_function(FITS, timeout=20000)
        h = inner.evaluate("window.glview.last")
        assert h["view"][0] <= 480 and h["view"][1] < 360, h["view"]
        snippet = next(line for line in s.output if "<iframe" in line)
        assert f'src="{s.url}"' in snippet, snippet
        page.context.close()
    finally:
        s.stop()
        course.stop()


def test_other_sites_cannot_frame_the_viewer(browser, server):
    """Without --embed-origin only the server itself may frame the page (CSP
    frame-ancestors): another site's frame stays empty."""
    course = CoursePage(server.url)
    page = course.open(browser)
    try:
        page.wait_for_timeout(2000)
        inner = page.frames[1]
        assert not inner.evaluate("() => { try { return !!window.glview; } catch (e) { return false; } }")
    finally:
        page.context.close()
        course.stop()


def test_a_link_opens_a_model_and_a_view(browser, glview_bin, tmp_path):
    """A course page's link carries a model and a view (keys of the window's table): the
    page opens there, and the still is the command line's picture of that view."""
    shared = REPO.parent / "shared" / "models"
    for name in ("bunny-small/bunny.obj", "teapot-small/teapot.obj"):
        shutil.copy(shared / name, tmp_path)
    s = Server(glview_bin, "--size", f"{SIZE[0]}x{SIZE[1]}", str(tmp_path))
    try:
        page = open_page(browser, s.url + "&model=teapot.obj&keys=Right,Right,P,P,nonsense")
        h = wait_still(page, 5)
        assert h["model"] == "teapot.obj" and h["tier"] == "pbr", h
        assert "--yaw 40" in h["command"] and "teapot.obj" in h["command"], h["command"]
        assert page.locator("#model").input_value() == "teapot.obj"
        assert not page.errors, page.errors
        page.context.close()
    finally:
        s.stop()


def test_copy_link_opens_the_same_view(browser, server):
    """"Copy link" writes the model, the camera absolutely and the state keys (never the
    presenter's key): a fresh page opened with that link draws the same still, byte for byte."""
    page = open_page(browser, server.url)
    try:
        wait_still(page)
        box = page.locator("#view").bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + 45, y - 15, steps=5)
        page.mouse.up()
        page.mouse.wheel(0, -240)
        page.keyboard.press("s")  # shadows off: a state key
        page.wait_for_timeout(100)  # the last animation frame's remainder
        h = wait_still(page, page.evaluate("window.glview.sent"))
        want = last_still(page)
        link = page.evaluate("window.glview.viewLink()")
        assert "yaw=" in link and "distance=" in link and "keys=S" in link, link
        assert "present" not in link, link
        other = open_page(browser, link)
        try:
            h2 = wait_still(other, 2)  # the link's camera, then its key
            assert h2["camera"] == h["camera"] and h2["shadows"] is False, (h2, h)
            assert pixels(last_still(other)).tobytes() == pixels(want).tobytes(), link
            assert not other.errors, other.errors
        finally:
            other.context.close()
        assert not page.errors, page.errors
    finally:
        page.context.close()

