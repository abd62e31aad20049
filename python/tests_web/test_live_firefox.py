"""`glview export --live`'s page in Firefox ESR (Debian's `firefox-esr`: WebGL 2 on Mesa's
llvmpipe), over WebDriver BiDi as python/tests_browser/test_serve_firefox.py speaks it: the
page from disk draws live, and its canvas equals `glview -o` with the same options (the
Phong and PBR tiers, ArrowRight ×2) within test_viewer.py's bounds. Firefox runs on an Xvfb
display, not --headless: headless Firefox gives a page no WebGL context here (the page then
shows its pictures, as it should), on Xvfb it gets WebGL 2 on llvmpipe through GLX."""
import asyncio
import base64
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import pytest

from test_live_export import SIZE, lesson, words  # noqa: F401 (a fixture)
from test_viewer import ROOT, check, native

sys.path.insert(0, str(ROOT / "python" / "tests_browser"))
from test_serve_firefox import FIREFOX, Bidi, start_firefox, stop  # noqa: E402

DEADLINE = 120.0
# Firefox draws with the same llvmpipe as `glview -o`: measured Phong identical, PBR mean
# 0.06 with no pixel over 1/255 (the float IBL lookups' last bit). Bound: at most 1/255
# anywhere.
SAME_RASTERISER = (0.1, 1, 0.0)

PIXELS = """(async () => {
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  const px = glviewLive.viewer.pixels();
  let s = "";
  for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
  return btoa(s);
})()"""


def start_xvfb():
    """An Xvfb server on a free display: (process, ':N')."""
    read, write = os.pipe()
    proc = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1280x1024x24",
                             "-nolisten", "tcp"], pass_fds=(write,), stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as f:
        number = f.readline().strip()
    if not number:
        proc.kill()
        pytest.fail("Xvfb printed no display number")
    return proc, ":" + number


def image(b64):
    return np.frombuffer(base64.b64decode(b64), np.uint8).reshape(SIZE[1], SIZE[0], 4)


async def opened(b, url):
    """A BiDi session's first browsing context, at `url`."""
    await b.call("session.new", capabilities={"alwaysMatch": {}})
    context = (await b.call("browsingContext.getTree"))["contexts"][0]["context"]
    await b.call("browsingContext.navigate", context=context, url=url, wait="complete")
    return context


async def right_twice(b, context):
    right = "\ue014"  # WebDriver's ArrowRight, pressed twice on the focused element
    await b.call("input.performActions", context=context, actions=[{
        "type": "key", "id": "keyboard", "actions": [
            {"type": "keyDown", "value": right}, {"type": "keyUp", "value": right},
            {"type": "keyDown", "value": right}, {"type": "keyUp", "value": right}]}])


async def run(address, url):
    import websockets

    until = time.monotonic() + DEADLINE
    async with websockets.connect(address + "/session", max_size=None) as ws:
        b = Bidi(ws)
        context = await opened(b, url)
        mode = await b.wait_for(context, "(() => { const m = document.getElementById('view')"
                                ".getAttribute('data-mode'); return ['live', 'images'].includes(m)"
                                " && m; })()", until)
        why = await b.eval(context, "document.getElementById('view').getAttribute('data-why')")
        assert mode == "live", f"Firefox did not draw live: {why}"
        out = {"info": await b.eval(context, "JSON.stringify(glviewLive.info)"),
               "mode": await b.eval(context, "document.getElementById('mode').textContent"),
               "phong": await b.eval(context, PIXELS)}
        await b.eval(context, "(document.getElementById('tier-pbr').click(), true)")
        out["pbr"] = await b.eval(context, PIXELS)
        await b.eval(context, "(document.getElementById('tier-phong').click(),"
                     " document.getElementById('view').focus(), true)")
        await right_twice(b, context)
        await b.wait_for(context, "document.getElementById('view').getAttribute('data-yaw')"
                         " === '40.00'", until)
        out["keys"] = await b.eval(context, PIXELS)
        await b.call("session.end")
        return out


def test_firefox_esr_draws_the_live_page_as_glview(lesson):  # noqa: F811 (the fixture)
    if not os.path.exists(FIREFOX):
        if os.environ.get("CI") == "true":
            pytest.fail(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
        pytest.skip(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
    profile = tempfile.mkdtemp(prefix="glview-firefox-")
    xvfb, display = start_xvfb()
    firefox = None
    try:
        firefox, address = start_firefox(profile, display)
        url = lesson["page"].as_uri() + "?glview=live"
        got = asyncio.run(asyncio.wait_for(run(address, url), DEADLINE))
    finally:
        if firefox is not None:
            stop(firefox)
        stop(xvfb)
        shutil.rmtree(profile, ignore_errors=True)
    print(f"firefox: {got['info']}; {got['mode']}")
    check("firefox-phong", image(got["phong"]), native(words()), SAME_RASTERISER)
    check("firefox-pbr", image(got["pbr"]), native(words("--shading", "pbr")), SAME_RASTERISER)
    turned = [w if w != "30" else "40" for w in words()]
    check("firefox-keys", image(got["keys"]), native(turned), SAME_RASTERISER)


async def run_serve(address, url):
    """glview serve's page in local mode: its canvas before and after ArrowRight ×2."""
    import websockets

    until = time.monotonic() + DEADLINE
    pixels = PIXELS.replace("glviewLive.viewer", "glview.local.viewer")
    async with websockets.connect(address + "/session", max_size=None) as ws:
        b = Bidi(ws)
        context = await opened(b, url)
        mode = await b.wait_for(context, "(() => { const m = document.getElementById('mode')"
                                ".dataset.mode; return ['local', 'stream'].includes(m) && m; })()",
                                until)
        why = await b.eval(context, "document.getElementById('mode').dataset.why")
        assert mode == "local", f"Firefox did not draw the served view: {why}"
        out = {"mode": await b.eval(context, "document.getElementById('mode').title"),
               "phong": await b.eval(context, pixels)}
        await b.eval(context, "(document.getElementById('local-view').focus(), true)")
        await right_twice(b, context)
        await b.wait_for(context, "glview.sent >= 2 && glview.shown >= glview.sent", until)
        out["keys"] = await b.eval(context, pixels)
        out["drawn_by_server"] = await b.eval(context, "String(glview.last.format)")
        await b.call("session.end")
        return out


def test_firefox_esr_draws_glview_serve_in_local_mode():
    from test_serve_local import MODEL, SIZE as SERVE_SIZE, VIEW, serve_process

    if not os.path.exists(FIREFOX):
        if os.environ.get("CI") == "true":
            pytest.fail(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
        pytest.skip(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
    assert SERVE_SIZE == SIZE
    profile = tempfile.mkdtemp(prefix="glview-firefox-")
    server, urls = serve_process()
    xvfb, display = start_xvfb()
    firefox = None
    try:
        firefox, address = start_firefox(profile, display)
        got = asyncio.run(asyncio.wait_for(run_serve(address, urls["open"] + "&glview=local"),
                                           DEADLINE))
    finally:
        if firefox is not None:
            stop(firefox)
        stop(xvfb)
        stop(server)
        shutil.rmtree(profile, ignore_errors=True)
    print(f"firefox serve: {got['mode']}")
    assert got["drawn_by_server"] == "none", "the server sent Firefox's local page pictures"
    served = [str(MODEL), "--size", f"{SIZE[0]}x{SIZE[1]}", *VIEW]
    check("firefox-serve-local", image(got["phong"]), native(served), SAME_RASTERISER)
    turned = [w if w != "30" else "40" for w in served]
    check("firefox-serve-local-keys", image(got["keys"]), native(turned), SAME_RASTERISER)
