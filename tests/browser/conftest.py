"""A headless Chromium driven by Selenium, for the workbench's tests.

The browser is the system's (Debian's ``chromium`` and ``chromium-driver``), named by path
through ``Service(executable_path=...)``, and Selenium Manager is kept offline
(``SE_OFFLINE``): nothing is ever downloaded. Where no browser is installed the tests skip
with the reason, unless ``MORPHSERVE_REQUIRE_BROWSER=1`` (CI sets it), where that is a
failure. One browser serves a whole test module.

Screenshots go to ``test-artifacts/browser/`` (``MORPHSERVE_TEST_ARTIFACTS`` overrides it),
which git ignores.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.live import REPO

CHROMIUM = os.environ.get("MORPHSERVE_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("MORPHSERVE_CHROMEDRIVER", "/usr/bin/chromedriver")
REQUIRED = os.environ.get("MORPHSERVE_REQUIRE_BROWSER", "") not in ("", "0")
ARTIFACTS = Path(os.environ.get("MORPHSERVE_TEST_ARTIFACTS", REPO / "test-artifacts")) / "browser"


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:  # `-m "not browser"` leaves out every test that drives the browser
        if "browser" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.browser)


def _missing() -> str | None:
    """Why the browser tests cannot run here, or None."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install -e '.[test]')"
    for path, package in ((CHROMIUM, "chromium"), (CHROMEDRIVER, "chromium-driver")):
        if not (Path(path).is_file() and os.access(path, os.X_OK)) and not shutil.which(path):
            return f"no {path}: install Debian's {package} (apt-get install chromium chromium-driver)"
    return None


@pytest.fixture(scope="session")
def chromium() -> str:
    """The browser's path, once it is known to be there: a skip (or, in CI, a failure) with
    the reason otherwise. Session-scoped, so that it is decided before the live server
    starts."""
    reason = _missing()
    if reason is not None:
        if REQUIRED:
            pytest.fail(f"MORPHSERVE_REQUIRE_BROWSER is set but {reason}")
        pytest.skip(reason)
    return CHROMIUM


@pytest.fixture(scope="module")
def browser(chromium: str) -> Iterator[Any]:
    """A headless Chromium of the system, 1400x900, WebGL on SwiftShader (no GPU needed)."""
    os.environ["SE_OFFLINE"] = "true"  # Selenium Manager: never look for or fetch a driver
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                "--window-size=1400,900", "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
                "--disable-extensions", "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-default-apps", "--disable-sync"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    driver.set_script_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()


@pytest.fixture
def shot(browser: Any, request: pytest.FixtureRequest) -> Iterator[Any]:
    """``shot(name)`` saves a screenshot as a test artifact; a test that took none gets one
    at its end, passed or failed."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    base = request.node.name.replace("/", "_").replace("[", "-").replace("]", "")
    taken: list[Path] = []

    def take(name: str = "") -> Path:
        path = ARTIFACTS / f"{base}{'-' + name if name else ''}.png"
        browser.save_screenshot(str(path))
        taken.append(path)
        return path

    yield take
    if not taken:
        take("end")
