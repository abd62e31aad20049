"""What the browser tests share: Debian's Chromium driven by the pinned Playwright
(scripts/test_browser.sh), launched with the test module's own FLAGS."""
import os

import pytest

CHROMIUM = "/usr/bin/chromium"


@pytest.fixture(scope="module")
def browser(request):
    if not os.path.exists(CHROMIUM):
        # In CI a missing browser is a broken setup, never a reason to pass.
        if os.environ.get("CI") == "true":
            pytest.fail(f"{CHROMIUM} is missing (scripts/test_browser.sh installs it)")
        pytest.skip(f"{CHROMIUM} is missing (scripts/test_browser.sh installs it)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=request.module.FLAGS)
        yield b
        b.close()
