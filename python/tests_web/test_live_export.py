"""`glview export --live`'s lesson page (src/export/page/live.js): glview's renderer, a model's
files (the Khronos Avocado: a .gltf, its .bin and three PNG textures) and the environment maps
inside one HTML file, opened from disk in Debian's Chromium with every request that is not the
file aborted. The canvas is held to `glview -o` with the same options (test_viewer.py's
bounds and measure), and the page falls back to its pictures where it cannot draw.
Run by scripts/test_web.sh."""
import base64
import json
import os
import re
import subprocess

import numpy as np
import pytest

from test_viewer import CHROMIUM, FLAGS, GL21, GLVIEW, PBR, PHONG, ROOT, WEB, check, native, stats

MODEL = ROOT.parent / "shared" / "gltf-samples" / "Avocado" / "Avocado.gltf"
SIZE = (320, 240)
YAWS = 8
VIEW = ["--yaw", "30", "--pitch", "15", "--shadow-size", "1024"]


@pytest.fixture(scope="module")
def lesson(tmp_path_factory):
    assert MODEL.exists(), f"{MODEL} is missing (../shared)"
    d = tmp_path_factory.mktemp("live")
    page = d / "lesson.html"
    r = subprocess.run([GLVIEW, "export", str(MODEL), "-o", str(page), "--live", "--png",
                        "--web-dir", str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}",
                        "--yaw-steps", str(YAWS), "--pitch-steps", "1", "--", *VIEW],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    print(r.stderr.strip())
    html = page.read_text(encoding="utf-8")
    m = re.search(r'<script type="application/json" id="glview-data">(.*?)</script>', html, re.S)
    return {"page": page, "data": json.loads(m.group(1)), "size": len(html)}


def launch(playwright, extra=()):
    return playwright.chromium.launch(executable_path=CHROMIUM, headless=True,
                                      args=[*FLAGS, *extra])


def open_page(browser, lesson, query="", init=None):
    """The page from disk, offline: (page, context, errors); `init`: a script run before the
    page's own."""
    context = browser.new_context(viewport={"width": 1000, "height": 900})
    context.requests = []
    if init:
        context.add_init_script(init)

    def route(r):
        context.requests.append(r.request.url)
        r.continue_() if r.request.url.startswith("file:") else r.abort()

    context.route("**/*", route)
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.goto(lesson["page"].as_uri() + query)
    page.wait_for_function("() => ['live', 'images'].includes(document.getElementById('view')"
                           ".getAttribute('data-mode'))", timeout=120_000)
    return page, context, errors


def close(page, context, errors):
    outside = [u for u in context.requests if not u.startswith(("file:", "data:"))]
    context.close()
    assert not outside, f"the page asked for {outside}"
    assert not errors, f"the page reported: {errors}"


def canvas(page):
    b64 = page.evaluate("""async () => {
        await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
        const px = glviewLive.viewer.pixels();
        let s = "";
        for (let i = 0; i < px.length; i += 0x8000) {
            s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
        }
        return [btoa(s), document.getElementById('live-canvas').width];
    }""")
    w = b64[1]
    return np.frombuffer(base64.b64decode(b64[0]), np.uint8).reshape(SIZE[1], w, 4)


def words(*more):
    return [str(MODEL), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW, *more]


@pytest.fixture(scope="module")
def chromium():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        yield p


def test_live_page_draws_both_tiers_the_compare_and_the_keys_as_glview(chromium, lesson):
    b = launch(chromium)
    page, context, errors = open_page(b, lesson, "?glview=live")
    view = page.locator("#view")
    assert view.get_attribute("data-mode") == "live", view.get_attribute("data-why")
    timings = page.evaluate("glviewLive.timings")
    print(f"live page ({lesson['size'] / 1e6:.2f} MB): renderer ready {timings['ready_ms']:.0f} ms,"
          f" first frame {timings['first_frame_ms']:.0f} ms, then {timings['frame_ms']:.0f} ms"
          f" a frame; {page.locator('#mode').inner_text()}")
    check("live-phong", canvas(page), native(words()), PHONG)
    page.get_by_role("button", name="PBR").click()
    pbr = canvas(page)
    assert view.get_attribute("data-tier") == "pbr"
    check("live-pbr", pbr, native(words("--shading", "pbr")), PBR)
    # Side by side: each half is its tier's picture at the page's size (split view framing).
    page.get_by_role("button", name="Compare side by side").click()
    both = canvas(page)
    assert both.shape[1] == 2 * SIZE[0]
    check("live-compare-phong", np.ascontiguousarray(both[:, :SIZE[0]]), native(words()), PHONG)
    check("live-compare-pbr", np.ascontiguousarray(both[:, SIZE[0]:]),
          native(words("--shading", "pbr")), PBR)
    # The difference numbers, computed in the page over the model's pixels, against the
    # export's own (`--diff phong,pbr`'s, view 0): the two rasterisers' pictures differ by
    # ~0.13/255 on average, so the numbers agree to a fraction of that.
    page.wait_for_function("() => window.glviewLive.numbers !== undefined", timeout=20_000)
    got, ref = page.evaluate("glviewLive.numbers"), lesson["data"]["numbers"][0]
    print(f"live compare numbers: {got}; export's: {ref}")
    assert abs(got["mean"] - ref["mean"]) <= 0.3 and abs(got["p99"] - ref["p99"]) <= 2
    assert abs(got["over_8"] - ref["over_8"]) <= 0.005
    assert abs(got["pixels"] - ref["pixels"]) <= 0.01 * ref["pixels"]
    assert page.locator("#numbers").is_visible()
    page.get_by_role("button", name="Phong").click()
    view.focus()
    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowRight")
    turned = canvas(page)
    assert view.get_attribute("data-yaw") == "40.00"
    ref = native([w if w != "30" else "40" for w in words()])
    check("live-keys", turned, ref, PHONG)
    assert stats(turned, native(words()))[0] > 2 * PHONG[0], "the keys turned nothing"
    close(page, context, errors)
    b.close()


def test_live_page_on_webgl1_draws_the_legacy_tier_as_gl21(chromium, lesson):
    b = launch(chromium)
    page, context, errors = open_page(b, lesson, "?glview=live&webgl=1")
    assert page.locator("#view").get_attribute("data-mode") == "live"
    assert page.evaluate("glviewLive.info.dialect") == "GLSL ES 1.00"
    check("live-webgl1", canvas(page), native([*words(), "--gl", "2.1"], GL21), PHONG)
    close(page, context, errors)
    b.close()


def test_live_scorm_progress_is_a_full_turn_and_both_tiers(chromium, lesson):
    b = launch(chromium)
    page, context, errors = open_page(b, lesson, "?glview=live")
    view = page.locator("#view")
    view.focus()
    # 5 degrees a key: a full turn is 72 presses; every 45-degree column is passed.
    for _ in range(71):
        page.keyboard.press("ArrowRight")
    page.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert view.get_attribute("data-seen") == f"{YAWS}/{YAWS},1/2"
    assert view.get_attribute("data-complete") == "false"
    page.get_by_role("button", name="PBR").click()
    page.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    assert view.get_attribute("data-complete") == "true"
    close(page, context, errors)
    b.close()


def test_without_webgl_or_on_a_software_context_the_page_shows_its_pictures(chromium, lesson):
    # Frames slower than the rule's bound (here made 0 ms) keep the turntable, and so does
    # a browser without WebGL; the page says which. Both still turn and complete. (This
    # Chromium's SwiftShader is not refused by failIfMajorPerformanceCaveat: the page draws
    # on it, and the speed rule is what judges it; a refusal is the next test's.)
    for extra, query, why in [((), "?slow-ms=0", "a frame took"),
                              (("--disable-3d-apis",), "", "no WebGL context")]:
        b = launch(chromium, extra)
        page, context, errors = open_page(b, lesson, query)
        view = page.locator("#view")
        assert view.get_attribute("data-mode") == "images"
        assert why in view.get_attribute("data-why"), view.get_attribute("data-why")
        assert page.locator("#pic-a").is_visible()
        assert why in page.locator("#mode").inner_text()
        view.focus()
        for _ in range(YAWS - 1):
            page.keyboard.press("ArrowRight")
        page.get_by_role("button", name="PBR").click()
        assert view.get_attribute("data-complete") == "true"
        close(page, context, errors)
        b.close()


# A browser that refuses a slow context: what Chrome does on a blocklisted GPU or a
# software rasteriser when failIfMajorPerformanceCaveat is asked (this Chromium does not, on
# SwiftShader): getContext answers null to the caveat's request.
REFUSES_SLOW = """(() => {
  const get = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (kind, attrs) {
    if (attrs && attrs.failIfMajorPerformanceCaveat) return null;
    return get.call(this, kind, attrs);
  };
})()"""


def test_a_context_refused_as_slow_shows_the_pictures_unless_asked_for_live(chromium, lesson):
    b = launch(chromium)
    page, context, errors = open_page(b, lesson, "", REFUSES_SLOW)
    view = page.locator("#view")
    assert view.get_attribute("data-mode") == "images"
    assert "major performance caveat" in view.get_attribute("data-why")
    assert page.locator("#pic-a").is_visible()
    close(page, context, errors)
    page, context, errors = open_page(b, lesson, "?glview=live", REFUSES_SLOW)
    assert page.locator("#view").get_attribute("data-mode") == "live"
    close(page, context, errors)
    b.close()


def test_a_live_only_page_is_smaller_and_names_what_it_lacks(chromium, lesson, tmp_path):
    page_file = tmp_path / "only.html"
    r = subprocess.run([GLVIEW, "export", str(MODEL), "-o", str(page_file), "--live-only",
                        "--web-dir", str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}",
                        "--yaw-steps", str(YAWS), "--pitch-steps", "1", "--", *VIEW],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    size = page_file.stat().st_size
    print(f"live-only page {size / 1e6:.2f} MB, live page {lesson['size'] / 1e6:.2f} MB")
    assert size < lesson["size"]
    b = launch(chromium, ("--disable-3d-apis",))
    page, context, errors = open_page(b, {"page": page_file})
    assert "cannot here" in page.locator("#mode").inner_text()
    close(page, context, errors)
    b.close()


def test_export_live_without_the_browser_build_is_one_line(tmp_path):
    r = subprocess.run([GLVIEW, "export", "-o", str(tmp_path / "x.html"), "--live",
                        "--web-dir", str(tmp_path), "--yaw-steps", "2", "--pitch-steps", "1",
                        "--size", "32x24"], capture_output=True, text=True)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "scripts/build_web.sh" in lines[0], r.stderr


def animated_avocado(folder):
    """The Avocado with an animation of its one node: a turn about +Y, a quarter each second
    for two seconds (LINEAR rotation keys), its keys in a second buffer (a data URI)."""
    import shutil
    import struct

    src = MODEL.parent
    for name in ["Avocado.bin", "Avocado_baseColor.png", "Avocado_normal.png",
                 "Avocado_roughnessMetallic.png"]:
        shutil.copy(src / name, folder / name)
    doc = json.loads(MODEL.read_text())
    times = [0.0, 1.0, 2.0]
    half = [0.0, 0.25, 0.5]  # turns: 0, 90, 180 degrees; a quaternion's half angle
    import math
    quats = [(0.0, math.sin(math.pi * h), 0.0, math.cos(math.pi * h)) for h in half]
    data = struct.pack("<3f", *times) + b"".join(struct.pack("<4f", *q) for q in quats)
    doc["buffers"].append({"uri": "data:application/octet-stream;base64," +
                           base64.b64encode(data).decode(), "byteLength": len(data)})
    b = len(doc["buffers"]) - 1
    views = len(doc["bufferViews"])
    doc["bufferViews"] += [{"buffer": b, "byteOffset": 0, "byteLength": 12},
                           {"buffer": b, "byteOffset": 12, "byteLength": 48}]
    acc = len(doc["accessors"])
    doc["accessors"] += [
        {"bufferView": views, "componentType": 5126, "count": 3, "type": "SCALAR",
         "min": [0.0], "max": [2.0]},
        {"bufferView": views + 1, "componentType": 5126, "count": 3, "type": "VEC4"}]
    doc["nodes"][0].pop("rotation", None)
    doc["animations"] = [{"name": "Turn", "channels": [
        {"sampler": 0, "target": {"node": 0, "path": "rotation"}}],
        "samplers": [{"input": acc, "output": acc + 1, "interpolation": "LINEAR"}]}]
    path = folder / "Turning.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_a_moment_and_playing_in_the_live_page(chromium, tmp_path):
    # --time 0.5 given to the export is the page's first picture, as glview -o --time 0.5;
    # Space plays it: the time runs on with the page's clock and the picture follows.
    model = animated_avocado(tmp_path)
    page_file = tmp_path / "turning.html"
    r = subprocess.run([GLVIEW, "export", str(model), "-o", str(page_file), "--live-only",
                        "--web-dir", str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}",
                        "--yaw-steps", "2", "--pitch-steps", "1", "--", *VIEW, "--time", "0.5"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    b = launch(chromium)
    page, context, errors = open_page(b, {"page": page_file}, "?glview=live")
    view = page.locator("#view")
    assert view.get_attribute("data-mode") == "live", view.get_attribute("data-why")
    at = [str(model), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW]
    still = canvas(page)
    check("live-time-0.5", still, native([*at, "--time", "0.5"]), PHONG)
    assert stats(still, native([*at, "--time", "0"]))[0] > 2 * PHONG[0], "--time posed nothing"
    view.focus()
    page.keyboard.press("Space")
    page.wait_for_function("() => Number(document.getElementById('view').getAttribute('data-time')) > 0.9",
                           timeout=20_000)
    page.keyboard.press("Space")
    paused = canvas(page)
    t = float(view.get_attribute("data-time"))
    check(f"live-paused-at-{t}", paused, native([*at, "--time", f"{t}"]), PHONG)
    close(page, context, errors)
    b.close()


def test_an_environment_file_travels_with_the_page(chromium, tmp_path):
    # --env's HDR goes into the page (/environment/NAME) beside its maps: the PBR tier over
    # the studio HDR equals glview -o's. Bound: PBR's, with the share over 8/255 at 0.5 %:
    # the HDR's background has sharp bright lights whose edges the rasterisers filter apart
    # (measured 0.18, p99 2, 0.26 %).
    hdr = ROOT.parent / "shared" / "hdr" / "studio_small_03_1k.hdr"
    page_file = tmp_path / "env.html"
    r = subprocess.run([GLVIEW, "export", "-o", str(page_file), "--live-only", "--web-dir",
                        str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}", "--yaw-steps", "2",
                        "--pitch-steps", "1", "--", "--env", str(hdr)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    b = launch(chromium)
    page, context, errors = open_page(b, {"page": page_file}, "?glview=live")
    assert page.locator("#view").get_attribute("data-mode") == "live"
    page.get_by_role("button", name="PBR").click()
    web = canvas(page)
    ref = native(["--size", f"{SIZE[0]}x{SIZE[1]}", "--env", str(hdr), "--shading", "pbr"])
    check("live-env-pbr", web, ref, (PBR[0], PBR[1], 0.005))
    close(page, context, errors)
    b.close()


def viewed_avocado(folder):
    """The Avocado with a camera (a node 0.2 m out on +Z, looking at it along -Z) and a
    KHR_materials_variants variant "Red" (a plain red material)."""
    import shutil

    for name in ["Avocado.bin", "Avocado_baseColor.png", "Avocado_normal.png",
                 "Avocado_roughnessMetallic.png"]:
        shutil.copy(MODEL.parent / name, folder / name)
    doc = json.loads(MODEL.read_text())
    doc["cameras"] = [{"type": "perspective", "name": "Front",
                       "perspective": {"yfov": 0.5, "znear": 0.01, "zfar": 10.0}}]
    doc["nodes"].append({"name": "FrontNode", "camera": 0, "translation": [0.0, 0.03, 0.2]})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    doc["materials"].append({"name": "Red", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.05, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5}})
    doc["extensionsUsed"] = ["KHR_materials_variants"]
    doc["extensions"] = {"KHR_materials_variants": {"variants": [{"name": "Red"}]}}
    doc["meshes"][0]["primitives"][0]["extensions"] = {
        "KHR_materials_variants": {"mappings": [{"material": 1, "variants": [0]}]}}
    path = folder / "Viewed.gltf"
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize("choice", [["--camera", "Front"], ["--variant", "Red"]])
def test_a_file_camera_and_a_variant_in_the_live_page(chromium, tmp_path, choice):
    # The file's camera and material variant, given to the export, are the page's first
    # picture, as glview -o --camera / --variant draws them.
    model = viewed_avocado(tmp_path)
    page_file = tmp_path / "viewed.html"
    r = subprocess.run([GLVIEW, "export", str(model), "-o", str(page_file), "--live-only",
                        "--web-dir", str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}",
                        "--yaw-steps", "2", "--pitch-steps", "1", "--", *VIEW, *choice],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    b = launch(chromium)
    page, context, errors = open_page(b, {"page": page_file}, "?glview=live")
    assert page.locator("#view").get_attribute("data-mode") == "live"
    web = canvas(page)
    at = [str(model), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW]
    check(f"live{choice[0]}", web, native([*at, *choice]), PHONG)
    assert stats(web, native(at))[0] > 2 * PHONG[0], f"{choice} changed nothing"
    close(page, context, errors)
    b.close()


def test_v_draws_the_files_next_variant_in_the_live_page(chromium, tmp_path):
    # V (the window's next variant) is a load option: the page's renderer loads the scene
    # again from the page's files, and draws what glview -o --variant 0 draws.
    model = viewed_avocado(tmp_path)
    page_file = tmp_path / "variants.html"
    r = subprocess.run([GLVIEW, "export", str(model), "-o", str(page_file), "--live-only",
                        "--web-dir", str(WEB), "--size", f"{SIZE[0]}x{SIZE[1]}",
                        "--yaw-steps", "2", "--pitch-steps", "1", "--", *VIEW],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    b = launch(chromium)
    page, context, errors = open_page(b, {"page": page_file}, "?glview=live")
    page.locator("#view").focus()
    page.keyboard.press("v")
    web = canvas(page)
    at = [str(model), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW]
    check("live-key-v", web, native([*at, "--variant", "0"]), PHONG)
    assert stats(web, native(at))[0] > 2 * PHONG[0], "V changed nothing"
    close(page, context, errors)
    b.close()
