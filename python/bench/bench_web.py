"""Benchmark of the browser build (issue 52), run by scripts/bench_web.sh: for the built-in
scene and the 200k-triangle dragon, a `glview export --live-only` page opened from disk in
Debian's Chromium (SwiftShader) RUNS times: time to the renderer being ready and to the first
live frame after page load (medians), then frames/s dragging (each frame: a drag step, a draw
and a one-pixel read so the frame is really done) against native `glview -o --frames` on the
same machine (llvmpipe; the median of frames 2 onwards, the shadow map reused as in a drag).
Prints the page and wasm sizes."""
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
GLVIEW = os.environ.get("GLVIEW_BIN", str(ROOT / "target" / "debug" / "glview"))
WEB = Path(os.environ.get("GLVIEW_WEB", ROOT / "target" / "web"))
CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run"]
SIZE = os.environ.get("BENCH_WEB_SIZE", "640x480")
RUNS = int(os.environ.get("BENCH_WEB_RUNS", "5"))
DRAG_S = 3.0
MODELS = [("built-in scene", None),
          ("dragon 200k", ROOT.parent / "shared" / "models" / "dragon-200k" / "dragon_vrip_res2.obj")]


def export(model, out):
    cmd = [GLVIEW, "export", *([str(model)] if model else []), "-o", str(out), "--live-only",
           "--web-dir", str(WEB), "--size", SIZE, "--yaw-steps", "8", "--pitch-steps", "1"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"bench_web: {' '.join(cmd)} failed: {r.stderr.strip()}")
    return r.stderr.strip()


def open_live(browser, page_file):
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    context.route("**/*", lambda r: r.continue_() if r.request.url.startswith("file:") else r.abort())
    page = context.new_page()
    page.goto(page_file.as_uri() + "?glview=live")
    page.wait_for_function("() => ['live', 'images'].includes(document.getElementById('view')"
                           ".getAttribute('data-mode'))", timeout=300_000)
    mode = page.locator("#view").get_attribute("data-mode")
    if mode != "live":
        sys.exit(f"bench_web: {page_file} did not draw: {page.locator('#view').get_attribute('data-why')}")
    return context, page


def drag_fps(page):
    return page.evaluate("""(seconds) => new Promise((done) => {
        const v = glviewLive.viewer;
        let frames = 0;
        const t0 = performance.now();
        const step = () => {
            v.drag(4, 0);
            v.draw();
            v.finish();
            frames++;
            const t = performance.now() - t0;
            if (t < seconds * 1000) requestAnimationFrame(step); else done(frames * 1000 / t);
        };
        requestAnimationFrame(step);
    })""", DRAG_S)


def native_fps(model):
    with tempfile.TemporaryDirectory() as d:
        cmd = [GLVIEW, *([str(model)] if model else []), "-o", f"{d}/n.png", "--size", SIZE,
               "--frames", "20", "--stats", "--no-cache"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"bench_web: {' '.join(cmd)} failed: {r.stderr.strip()}")
        last = [json.loads(l) for l in (r.stdout + r.stderr).splitlines() if l.startswith("{")][-1]
        frames = last["profile"]["frames_ms"][1:]
        return 1000 / statistics.median(frames)


def main():
    from playwright.sync_api import sync_playwright

    wasm = WEB / "glview_web_bg.wasm"
    print(f"bench_web: {wasm}: {wasm.stat().st_size} bytes; {RUNS} loads each at {SIZE}, "
          f"Chromium {subprocess.run([CHROMIUM, '--version'], capture_output=True, text=True).stdout.strip()}")
    with tempfile.TemporaryDirectory() as d, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=FLAGS)
        for name, model in MODELS:
            page_file = Path(d) / "page.html"
            summary = export(model, page_file)
            ready, first, fps = [], [], []
            for _ in range(RUNS):
                context, page = open_live(browser, page_file)
                t = page.evaluate("glviewLive.timings")
                ready.append(t["ready_ms"])
                first.append(t["first_frame_ms"])
                fps.append(drag_fps(page))
                context.close()
            nat = native_fps(model)
            web = statistics.median(fps)
            print(f"{name}: page {page_file.stat().st_size / 1e6:.2f} MB ({summary.split('drawn live')[1].split(')')[0].strip(' (')}); "
                  f"renderer ready {statistics.median(ready):.0f} ms, first live frame "
                  f"{statistics.median(first):.0f} ms after load (medians, range {min(first):.0f}–{max(first):.0f}); "
                  f"dragging {web:.1f} frames/s in Chromium against {nat:.1f} natively (glview -o --frames, llvmpipe): "
                  f"{web / nat:.2f}x")
        browser.close()


if __name__ == "__main__":
    main()
