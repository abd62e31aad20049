"""`glview serve`'s local mode in Debian's Chromium (cli/src/serve/page/local.js): the page
downloads the renderer and the model's scene once and draws the view itself; the server sends
only the view's state. A presenter's page and a follower's page both draw the Khronos Avocado
(a textured glTF); the follower's canvas, after the presenter's keys, is `glview -o` of the
presenter's view within test_viewer.py's bounds, and the server draws no picture meanwhile.
Without WebGL the page keeps the stream and says why. Run by scripts/test_web.sh."""
import base64
import subprocess

import numpy as np
import pytest

from test_live_export import launch
from test_viewer import GL21, GLVIEW, PBR, PHONG, ROOT, WEB, check, native, stats

MODEL = ROOT.parent / "shared" / "gltf-samples" / "Avocado" / "Avocado.gltf"
SIZE = (320, 240)
VIEW = ["--yaw", "30", "--pitch", "15", "--shadow-size", "1024"]


def serve_process():
    """`glview serve MODEL` with the browser build: (process, {"open": url, "presenter": url})."""
    assert MODEL.exists(), f"{MODEL} is missing (../shared)"
    p = subprocess.Popen([GLVIEW, "serve", str(MODEL), "--bind", "127.0.0.1:0", "--web-dir",
                          str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW],
                         stdout=subprocess.PIPE, text=True)
    urls = {}
    for line in p.stdout:
        for what in ("open", "presenter"):
            if line.startswith(f"glview serve: {what} "):
                urls[what] = line.split(" ", 3)[3].strip()
        if "presenter" in urls:
            break
    assert "presenter" in urls, "glview serve printed no address"
    return p, urls


@pytest.fixture(scope="module")
def server():
    p, urls = serve_process()
    yield urls
    p.kill()
    p.wait()


@pytest.fixture(scope="module")
def chromium():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        yield p


def open_page(browser, url):
    """`url` in a new page of `browser` (or of a browser context): (page, errors)."""
    if hasattr(browser, "add_init_script"):
        page = browser.new_page()
        page.set_viewport_size({"width": 1000, "height": 900})
    else:
        page = browser.new_page(viewport={"width": 1000, "height": 900})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.goto(url)
    page.wait_for_function("() => ['local', 'stream'].includes(document.getElementById('mode')"
                           ".dataset.mode)", timeout=120_000)
    return page, errors


def settled(page):
    """Waits until the page's last input is in a state from the server and drawn."""
    page.wait_for_function("() => glview.shown >= glview.sent && glview.local", timeout=30_000)


def canvas(page):
    b64 = page.evaluate("""async () => {
        await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
        const px = glview.local.viewer.pixels();
        let s = "";
        for (let i = 0; i < px.length; i += 0x8000) {
            s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
        }
        return btoa(s);
    }""")
    return np.frombuffer(base64.b64decode(b64), np.uint8).reshape(SIZE[1], SIZE[0], 4)


def words(*more):
    return [str(MODEL), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW, *more]


def test_pages_draw_the_class_themselves_and_the_server_draws_nothing(chromium, server):
    b = launch(chromium)
    presenter, p_errors = open_page(b, server["presenter"] + "&glview=local")
    follower, f_errors = open_page(b, server["open"] + "&glview=local&follow=1")
    for page in (presenter, follower):
        mode = page.locator("#mode")
        assert mode.get_attribute("data-mode") == "local", mode.get_attribute("data-why")
    print(f"serve local: {presenter.locator('#mode').get_attribute('title')}; timings "
          f"{presenter.evaluate('glview.local.timings')}")
    check("serve-local-phong", canvas(follower), native(words()), PHONG)
    # Its frames are states now (the ones before, while its renderer started, pictures).
    follower.wait_for_function("() => glview.localFrames > 0", timeout=30_000)
    drawn = follower.evaluate("glview.last.drawn")
    # The presenter's keys: drawn at once on its page, then its state on the follower's.
    presenter.locator("#local-view").focus()
    presenter.keyboard.press("ArrowRight")
    presenter.keyboard.press("ArrowRight")
    presenter.keyboard.press("p")  # Phong → Gouraud → PBR
    presenter.keyboard.press("p")
    settled(presenter)
    turned = words("--shading", "pbr")
    turned[turned.index("30")] = "40"
    follower.wait_for_function("() => glview.last.seq >= 4 && glview.last.presenter")
    got = canvas(follower)
    check("serve-local-presenter-keys-follower", got, native(turned), PBR)
    check("serve-local-presenter-keys-presenter", canvas(presenter), native(turned), PBR)
    assert stats(got, native(words()))[0] > 2 * PHONG[0], "the follower did not follow"
    assert follower.evaluate("glview.last.drawn") == drawn, "the server drew for local pages"
    assert follower.evaluate("glview.last.state.options.render.shading") == "pbr"
    # The follower's own drag leaves the class and is drawn on its page at once.
    box = follower.locator("#local-view").bounding_box()
    follower.mouse.move(box["x"] + 100, box["y"] + 100)
    follower.mouse.down()
    follower.mouse.move(box["x"] + 140, box["y"] + 100, steps=4)
    follower.mouse.up()
    settled(follower)
    assert not follower.locator("#follow").is_checked()
    state = follower.evaluate("glview.last.state.options.camera")
    assert state["yaw"] != 40.0, state
    assert follower.evaluate("glview.last.drawn") == drawn
    assert not p_errors and not f_errors, (p_errors, f_errors)
    b.close()


def test_a_context_refused_as_slow_keeps_the_stream(chromium, server):
    from test_live_export import REFUSES_SLOW

    b = launch(chromium)
    context = b.new_context(viewport={"width": 1000, "height": 900})
    context.add_init_script(REFUSES_SLOW)
    page, errors = open_page(context, server["open"])
    mode = page.locator("#mode")
    assert mode.get_attribute("data-mode") == "stream"
    assert "major performance caveat" in mode.get_attribute("data-why")
    page.wait_for_function("() => glview.frames > 0")
    page, errors = open_page(context, server["open"] + "&glview=local")
    assert page.locator("#mode").get_attribute("data-mode") == "local"
    b.close()


def test_without_webgl_the_page_keeps_the_stream(chromium, server):
    b = launch(chromium, ["--disable-3d-apis"])
    page, errors = open_page(b, server["open"])
    mode = page.locator("#mode")
    assert mode.get_attribute("data-mode") == "stream"
    assert "WebGL" in mode.get_attribute("data-why"), mode.get_attribute("data-why")
    page.wait_for_function("() => glview.frames > 0 && glview.last.format === 'png'")
    assert page.locator("#view").is_visible()
    assert not errors, errors
    b.close()


def test_webgl1_pages_draw_the_legacy_tier_locally(chromium, server):
    b = launch(chromium)
    page, errors = open_page(b, server["open"] + "&glview=local&webgl=1")
    mode = page.locator("#mode")
    assert mode.get_attribute("data-mode") == "local", mode.get_attribute("data-why")
    assert page.evaluate("glview.local.info.webgl") == 1
    check("serve-local-webgl1", canvas(page), native(words(), GL21), PHONG)
    assert not errors, errors
    b.close()
