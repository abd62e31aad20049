"""`glview serve`'s page in Firefox ESR (Debian's `firefox-esr`), driven over the WebDriver
BiDi protocol Firefox speaks itself (`--remote-debugging-port`): no geckodriver, no
Playwright browser. BiDi is JSON over a WebSocket, spoken here with the `websockets`
package (scripts/test_browser.sh pins it). The page loads, draws its first frame (a canvas
that is not blank) and turns on ArrowRight (the still after it shows another view, and the
canvas changes).
"""
import asyncio
import json
import os
import re
import shutil
import subprocess
import tempfile
import threading
import time

import pytest

from test_serve_page import Server, glview_bin  # noqa: F401 (a fixture)

FIREFOX = "/usr/bin/firefox-esr"
DEADLINE = 30.0  # seconds for the whole test; it takes about 5 here

# What the canvas shows, summed up: its size, how many distinct colours (of a sample) and a
# checksum of its pixels. A blank canvas has one colour.
CANVAS = """(() => {
  const c = document.getElementById('view');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  const colours = new Set();
  let sum = 0;
  for (let i = 0; i < d.length; i += 4) {
    sum = (sum * 31 + d[i] + 7 * d[i + 1] + 13 * d[i + 2]) % 1000000007;
    if (colours.size < 64) colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
  }
  return JSON.stringify([c.width, c.height, colours.size, sum]);
})()"""


class Bidi:
    """One WebDriver BiDi session over its WebSocket: commands by id, events skipped."""

    def __init__(self, ws):
        self.ws = ws
        self.next_id = 0

    async def call(self, method, **params):
        self.next_id += 1
        await self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            m = json.loads(await self.ws.recv())
            if m.get("id") != self.next_id:
                continue  # an event (none is subscribed to) or another reply
            if m.get("type") == "error":
                raise AssertionError(f"{method}: {m.get('error')}: {m.get('message')}")
            return m["result"]

    async def eval(self, context, expression):
        r = await self.call("script.evaluate", expression=expression, awaitPromise=True,
                            target={"context": context})
        if r.get("type") == "exception":
            raise AssertionError(f"{expression!r} threw: {r['exceptionDetails'].get('text')}")
        return r["result"].get("value")

    async def wait_for(self, context, expression, until):
        """Polls `expression` until it is truthy; `until` is a monotonic deadline."""
        while True:
            v = await self.eval(context, expression)
            if v:
                return v
            if time.monotonic() > until:
                raise AssertionError(f"timed out waiting for {expression!r}")
            await asyncio.sleep(0.05)


def start_firefox(profile, display=None):
    """Firefox with a fresh profile, headless or on X display `display`; returns it and its
    BiDi address (read from its stderr: port 0 makes it pick a free one)."""
    args = ["--headless"] if display is None else []
    env = dict(os.environ) if display is None else {**os.environ, "DISPLAY": display}
    proc = subprocess.Popen(
        [FIREFOX, *args, "--no-remote", "--profile", profile,
         "--remote-debugging-port", "0", "--width", "800", "--height", "600", "about:blank"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    until = time.monotonic() + 20
    lines = []
    while time.monotonic() < until:
        line = proc.stderr.readline()
        if not line:
            break
        lines.append(line)
        m = re.search(r"WebDriver BiDi listening on (ws://\S+)", line)
        if m:
            # The rest of its output is drained, so Firefox never blocks on a full pipe.
            threading.Thread(target=proc.stderr.read, daemon=True).start()
            return proc, m.group(1)
    proc.kill()
    proc.wait()
    pytest.fail("firefox-esr printed no BiDi address:\n" + "".join(lines))


def stop(proc):
    """Ends `proc` (Firefox, Xvfb): politely, then for certain."""
    proc.terminate()
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


async def smoke(address, url):
    import websockets

    until = time.monotonic() + DEADLINE
    async with websockets.connect(address + "/session", max_size=None) as ws:
        b = Bidi(ws)
        await b.call("session.new", capabilities={"alwaysMatch": {"acceptInsecureCerts": False}})
        context = (await b.call("browsingContext.getTree"))["contexts"][0]["context"]
        await b.call("browsingContext.navigate", context=context, url=url, wait="complete")
        await b.wait_for(context, "window.glview && window.glview.frames >= 1 && "
                         "window.glview.last && window.glview.last.still", until)
        first = json.loads(await b.eval(context, CANVAS))
        w, h, colours, _ = first
        assert (w, h) != (0, 0) and colours > 1, f"the first frame is blank: {first}"
        command = await b.eval(context, "window.glview.last.command")
        errors = await b.eval(context, "JSON.stringify(window.glview.errors)")
        assert errors == "[]", errors
        right = "\ue014"  # WebDriver's ArrowRight
        await b.call("input.performActions", context=context, actions=[{
            "type": "key", "id": "keyboard",
            "actions": [{"type": "keyDown", "value": right}, {"type": "keyUp", "value": right}],
        }])
        await b.wait_for(context, "window.glview.sent >= 1", until)
        await b.wait_for(context, "(() => { const g = window.glview, h = g.last;"
                         " return h && h.still && g.shown >= g.sent; })()", until)
        turned = await b.eval(context, "window.glview.last.command")
        assert turned != command, f"ArrowRight did not turn the view: {command}"
        after = json.loads(await b.eval(context, CANVAS))
        assert after[2] > 1 and after[3] != first[3], f"the canvas did not change: {first} {after}"
        await b.call("session.end")


def test_firefox_esr_loads_draws_and_turns(glview_bin):  # noqa: F811 (the fixture)
    if not os.path.exists(FIREFOX):
        # In CI a missing browser is a broken setup, never a reason to pass.
        if os.environ.get("CI") == "true":
            pytest.fail(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
        pytest.skip(f"{FIREFOX} is missing (scripts/deps.sh --browser installs it)")
    server = Server(glview_bin, "--size", "320x240")
    profile = tempfile.mkdtemp(prefix="glview-firefox-")
    firefox = None
    try:
        firefox, address = start_firefox(profile)
        asyncio.run(asyncio.wait_for(smoke(address, server.url), DEADLINE))
    finally:
        if firefox is not None:
            stop(firefox)
        server.stop()
        shutil.rmtree(profile, ignore_errors=True)
