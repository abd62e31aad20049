#!/usr/bin/env python3
"""docs/export.png: the lesson page of `glview export` in Chromium, compare view on, one
step right of the first view (the pinned Playwright of scripts/test_browser.sh).

    target/pyvenv/bin/python scripts/export_screenshot.py PAGE.html docs/export.png
"""
import pathlib
import sys

from playwright.sync_api import sync_playwright

page_path, out = pathlib.Path(sys.argv[1]).resolve(), sys.argv[2]
with sync_playwright() as p:
    b = p.chromium.launch(executable_path="/usr/bin/chromium", headless=True,
                          args=["--no-sandbox", "--disable-gpu"])
    page = b.new_page(viewport={"width": 720, "height": 560}, device_scale_factor=1)
    page.route("**/*", lambda r: r.continue_() if r.request.url.startswith("file:") else r.abort())
    page.goto(page_path.as_uri())
    page.get_by_role("button", name="Compare side by side").click()
    page.locator("#view").focus()
    page.keyboard.press("ArrowRight")
    page.locator("#view").blur()
    page.screenshot(path=out, full_page=True)
    b.close()
