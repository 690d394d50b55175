"""Headless Chromium for the browser tests: the distribution's Chromium and chromedriver,
driven by Selenium (nothing downloaded). Locally the tests skip without them; in CI (CI
set) they run, and a missing browser is a failure (.ci/run installs it)."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager

import pytest

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
DRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"


def have_browser() -> bool:
    try:
        import selenium  # noqa: F401
    except ImportError:
        return False
    return os.path.exists(CHROMIUM) and os.path.exists(DRIVER)


def skip_without_browser() -> None:
    """At a browser test module's top: skip it here without a browser, never in CI."""
    if not have_browser() and not os.environ.get("CI"):
        pytest.skip("no Chromium, chromedriver or selenium here (CI installs them)",
                    allow_module_level=True)


@contextmanager
def chromium(*flags: str, size: str = "1400,1000") -> Iterator[object]:
    """A headless Chromium with its own profile, quit and removed afterwards."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="maxk-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless", "--no-sandbox", "--disable-gpu",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
                 f"--user-data-dir={profile}", f"--window-size={size}", *flags):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(executable_path=DRIVER), options=options)
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)
