"""Browser tests of `glview export`'s lesson page (src/export/page/): Debian's Chromium,
headless, driven by the pinned Playwright (scripts/test_browser.sh), with every request that
is not the page's own file aborted. A tiny grid (8 yaw × 3 pitch at 96×72, PNG pictures so
the screen can be compared pixel for pixel) of the repository's box_on_floor model.

The SCORM package runs in a harness page that loads a real SCORM 1.2 runtime (scorm-again,
pinned in scorm/package-lock.json; $SCORM_RUNTIME) as window.API with the lesson in an
iframe, both served from one made-up LMS origin by Playwright's router (no network).
"""
import base64
import io
import json
import os
import pathlib
import re
import shutil
import subprocess
import zipfile

import pytest
from PIL import Image

REPO = pathlib.Path(__file__).resolve().parents[2]
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]
YAWS, PITCHES, SIZE = 8, 3, (96, 72)
LMS = "http://lms.invalid/"


@pytest.fixture(scope="module")
def lesson(tmp_path_factory):
    exe = os.environ.get("GLVIEW_BIN") or str(REPO / "target" / "debug" / "glview")
    assert os.path.exists(exe), f"{exe} is missing: build glview first (cargo build)"
    d = tmp_path_factory.mktemp("export")
    page, package = d / "lesson.html", d / "lesson.zip"
    subprocess.run([exe, "export", "models/box_on_floor.obj", "-o", str(page), "--png",
                    "--size", f"{SIZE[0]}x{SIZE[1]}", "--yaw-steps", str(YAWS),
                    "--pitch-steps", str(PITCHES), "--scorm", str(package),
                    "--title", "Box on a floor", "--caption", "Turn it all the way round."],
                   check=True, cwd=REPO)
    html = page.read_text(encoding="utf-8")
    m = re.search(r'<script type="application/json" id="glview-data">(.*?)</script>', html, re.S)
    return {"page": page, "package": package, "data": json.loads(m.group(1))}


def offline_context(browser, allow):
    """A context whose every request is aborted unless `allow(url)`; the requests made are
    recorded in `context.requests`."""
    context = browser.new_context(viewport={"width": 900, "height": 800}, device_scale_factor=1)
    context.requests = []

    def route(r):
        context.requests.append(r.request.url)
        if allow(r.request.url):
            r.continue_()
        else:
            r.abort()

    context.route("**/*", route)
    return context


@pytest.fixture
def page(browser, lesson):
    context = offline_context(browser, lambda url: url.startswith("file:"))
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(lesson["page"].as_uri())
    page.wait_for_function("document.getElementById('pic-a').complete")
    yield page
    outside = [u for u in context.requests if not u.startswith(("file:", "data:"))]
    context.close()
    assert not errors, f"the page threw: {errors}"
    assert not outside, f"the page asked for {outside}"


def view(page):
    v = page.locator("#view")
    return {k: v.get_attribute("data-" + k) for k in ("view", "yaw", "pitch", "tier", "compare", "zoom")}


def decoded(uri):
    return Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1]))).convert("RGB")


def shown(page, selector="#pic-a"):
    return page.locator(selector).get_attribute("src")


def test_opens_offline_on_the_default_view_one_pixel_per_css_pixel(page, lesson):
    data = lesson["data"]
    start = data["start"]
    assert int(view(page)["view"]) == start == (PITCHES - 1) // 2 * YAWS
    assert (float(view(page)["yaw"]), float(view(page)["pitch"])) == (30.0, 25.0)
    assert shown(page) == data["phong"][start]
    box = page.locator("#pic-a").bounding_box()
    assert (box["width"], box["height"]) == SIZE
    # The layout may place the picture at a fractional offset; Chromium paints it snapped to
    # the nearest device pixel, unscaled.
    x, y = round(box["x"]), round(box["y"])
    shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")
    shot = shot.crop((x, y, x + SIZE[0], y + SIZE[1]))
    assert shot.tobytes() == decoded(data["phong"][start]).tobytes()
    assert page.locator("h1").inner_text() == "Box on a floor"
    assert "glview export models/box_on_floor.obj" in page.locator("#command").text_content()


def test_arrow_keys_and_drags_step_the_grid(page, lesson):
    data = lesson["data"]
    start = data["start"]
    page.locator("#view").focus()
    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowRight")
    # ArrowRight increases yaw, as in the window: two grid steps of 45°.
    assert int(view(page)["view"]) == start + 2
    assert float(view(page)["yaw"]) == data["yaws"][2] == 120.0
    assert shown(page) == data["phong"][start + 2]
    page.keyboard.press("ArrowUp")
    assert int(view(page)["view"]) == start + YAWS + 2
    page.keyboard.press("ArrowLeft")
    page.keyboard.press("ArrowLeft")
    page.keyboard.press("ArrowLeft")
    assert int(view(page)["view"]) == start + YAWS + YAWS - 1  # wraps round
    page.keyboard.press("ArrowDown")
    # A drag as the window's: dragging right turns the model right (yaw decreases by
    # 0.4° per pixel): 120 px is one 45° step.
    box = page.locator("#view").bounding_box()
    x, y = box["x"] + 40, box["y"] + 30
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 120, y, steps=6)
    page.mouse.up()
    assert int(view(page)["view"]) == start + YAWS - 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x - 240, y, steps=12)
    page.mouse.up()
    assert int(view(page)["view"]) == start
    assert shown(page) == data["phong"][start]


def test_touch_drag_steps_the_grid(browser, lesson):
    """A finger's drag (real touch input through the DevTools protocol, as a phone sends it)
    moves between views as a mouse drag does."""
    context = browser.new_context(viewport={"width": 900, "height": 800}, has_touch=True)
    context.route("**/*", lambda r: r.continue_() if r.request.url.startswith("file:") else r.abort())
    page = context.new_page()
    page.goto(lesson["page"].as_uri())
    start = lesson["data"]["start"]
    box = page.locator("#pic-a").bounding_box()
    x, y = box["x"] + 80, box["y"] + 30
    cdp = context.new_cdp_session(page)
    cdp.send("Input.dispatchTouchEvent", {"type": "touchStart", "touchPoints": [{"x": x, "y": y}]})
    for i in range(1, 7):
        cdp.send("Input.dispatchTouchEvent",
                 {"type": "touchMove", "touchPoints": [{"x": x - 20 * i, "y": y}]})
    cdp.send("Input.dispatchTouchEvent", {"type": "touchEnd", "touchPoints": []})
    # 120 px to the left: one 45° step, yaw up (the model turns left).
    assert int(view(page)["view"]) == start + 1
    context.close()


def test_tier_switch_compare_numbers_and_wheel(page, lesson):
    data = lesson["data"]
    v = data["start"]
    page.get_by_role("button", name="PBR").click()
    assert view(page)["tier"] == "pbr" and shown(page) == data["pbr"][v]
    assert page.locator("#pane-b").is_hidden() and page.locator("#numbers").is_hidden()
    page.get_by_role("button", name="Compare side by side").click()
    assert view(page)["compare"] == "true"
    assert shown(page) == data["phong"][v] and shown(page, "#pic-b") == data["pbr"][v]
    n = data["numbers"][v]
    assert page.locator("#n-mean").inner_text() == f"{n['mean']:.2f}/255"
    assert page.locator("#n-p99").inner_text() == f"{n['p99']:.0f}/255"
    assert page.locator("#n-over").inner_text().startswith(f"{100 * n['over_8']:.1f} %")
    page.locator("#view").focus()
    page.keyboard.press("ArrowRight")
    assert shown(page, "#pic-b") == data["pbr"][v + 1]
    assert page.locator("#n-mean").inner_text() == f"{data['numbers'][v + 1]['mean']:.2f}/255"
    # The wheel scales the picture (the grid has one distance).
    box = page.locator("#view").bounding_box()
    page.mouse.move(box["x"] + 10, box["y"] + 10)
    page.mouse.wheel(0, -100)
    assert float(view(page)["zoom"]) > 1
    assert page.get_by_role("button", name="Zoom out").is_visible()


def serve_lms(lesson, tmp_path, runtime, preset=""):
    """The package unzipped under the LMS origin, with the harness page that makes the
    runtime's window.API and opens the lesson in an iframe."""
    root = tmp_path / "lms"
    with zipfile.ZipFile(lesson["package"]) as z:
        z.extractall(root / "course")
    (root / "scorm12.js").write_bytes(pathlib.Path(runtime).read_bytes())
    (root / "harness.html").write_text(
        "<!DOCTYPE html><html><head><script src='scorm12.js'></script><script>"
        "window.API = new Scorm12API({autocommit: false, logLevel: 5});" + preset +
        "</script></head><body><iframe id='lesson' src='course/index.html' "
        "width='880' height='760'></iframe></body></html>")
    return root


def open_in_lms(browser, root):
    def fulfil(r):
        context.requests.append(r.request.url)
        path = root / r.request.url[len(LMS):].split("?")[0]
        if r.request.url.startswith(LMS) and path.is_file():
            r.fulfill(path=str(path))
        else:
            r.abort()

    context = browser.new_context(viewport={"width": 900, "height": 800})
    context.requests = []
    context.route("**/*", fulfil)
    page = context.new_page()
    page.goto(LMS + "harness.html")
    frame = page.frame_locator("#lesson")
    frame.locator("#view").wait_for()
    return page, frame


def scorm_runtime():
    runtime = os.environ.get("SCORM_RUNTIME")
    if not runtime or not os.path.exists(runtime):
        if os.environ.get("CI") == "true":
            pytest.fail("SCORM_RUNTIME is missing (scripts/test_browser.sh installs it)")
        pytest.skip("SCORM_RUNTIME is missing (scripts/test_browser.sh installs it)")
    return runtime


@pytest.mark.parametrize("order", ["turn first", "tiers first"])
def test_scorm_package_completes_after_a_full_turn_and_both_tiers(browser, lesson, tmp_path, order):
    page, frame = open_in_lms(browser, serve_lms(lesson, tmp_path, scorm_runtime()))
    status = lambda: page.evaluate("window.API.cmi.core.lesson_status")
    assert page.evaluate("window.API.isInitialized()")
    assert status() == "incomplete"
    frame.locator("#view").focus()
    if order == "turn first":
        for _ in range(YAWS - 1):
            page.keyboard.press("ArrowRight")
        assert frame.locator("#view").get_attribute("data-seen") == f"{YAWS}/{YAWS},1/2"
        assert status() == "incomplete", "a full turn in one tier is not the lesson"
        frame.get_by_role("button", name="PBR").click()
    else:
        frame.get_by_role("button", name="Compare side by side").click()
        frame.locator("#view").focus()
        for _ in range(YAWS - 2):
            page.keyboard.press("ArrowLeft")
        assert status() == "incomplete", "both tiers but one direction unseen"
        page.keyboard.press("ArrowLeft")
    assert status() == "completed"
    assert page.evaluate("window.API.cmi.core.lesson_location") == frame.locator("#view").get_attribute("data-view")
    assert page.evaluate("window.API.cmi.suspend_data") == "yaws:" + "1" * YAWS + ";tiers:phong,pbr"
    outside = [u for u in page.context.requests if not u.startswith(LMS)]
    page.context.close()
    assert not outside, outside


def test_scorm_progress_is_restored_from_suspend_data(browser, lesson, tmp_path):
    # A student who saw every direction but the last (yaw step 7) in both tiers comes back.
    saved = "yaws:" + "1" * (YAWS - 1) + "0;tiers:phong,pbr"
    preset = f"window.API.cmi.suspend_data = '{saved}';"
    page, frame = open_in_lms(browser, serve_lms(lesson, tmp_path, scorm_runtime(), preset))
    status = lambda: page.evaluate("window.API.cmi.core.lesson_status")
    assert status() == "incomplete"
    assert frame.locator("#view").get_attribute("data-seen") == f"{YAWS - 1}/{YAWS},2/2"
    frame.locator("#view").focus()
    page.keyboard.press("ArrowLeft")
    assert status() == "completed"
    page.context.close()


def test_scorm_manifest_validates_against_the_scorm_12_schemas(lesson, tmp_path):
    """ADL's SCORM 1.2 schema files ($SCORM_SCHEMAS, fetched and hash-checked by
    scripts/test_browser.sh) with xmllint; a manifest with a wrong SCO type must fail, so the
    validator is known to bite."""
    schemas = os.environ.get("SCORM_SCHEMAS")
    missing = not schemas or not os.path.exists(os.path.join(schemas, "imscp_rootv1p1p2.xsd"))
    if missing or not shutil.which("xmllint"):
        if os.environ.get("CI") == "true":
            pytest.fail("SCORM_SCHEMAS or xmllint is missing (scripts/test_browser.sh)")
        pytest.skip("SCORM_SCHEMAS or xmllint is missing (scripts/test_browser.sh)")
    imports = "".join(
        f'<xsd:import namespace="{ns}" schemaLocation="{pathlib.Path(schemas, f).as_uri()}"/>'
        for ns, f in [("http://www.imsproject.org/xsd/imscp_rootv1p1p2", "imscp_rootv1p1p2.xsd"),
                      ("http://www.adlnet.org/xsd/adlcp_rootv1p2", "adlcp_rootv1p2.xsd"),
                      ("http://www.imsglobal.org/xsd/imsmd_rootv1p2p1", "imsmd_rootv1p2p1.xsd")])
    driver = tmp_path / "scorm12.xsd"
    driver.write_text('<?xml version="1.0"?><xsd:schema '
                      f'xmlns:xsd="http://www.w3.org/2001/XMLSchema">{imports}</xsd:schema>')
    with zipfile.ZipFile(lesson["package"]) as z:
        manifest = z.read("imsmanifest.xml").decode()
    good, bad = tmp_path / "imsmanifest.xml", tmp_path / "bad.xml"
    good.write_text(manifest)
    bad.write_text(manifest.replace('adlcp:scormtype="sco"', 'adlcp:scormtype="lesson"'))
    run = lambda f: subprocess.run(["xmllint", "--noout", "--schema", str(driver), str(f)],
                                   capture_output=True, text=True)
    ok = run(good)
    assert ok.returncode == 0 and "validates" in ok.stderr, ok.stderr
    assert run(bad).returncode != 0
