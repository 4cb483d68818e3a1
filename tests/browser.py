"""Headless Chromium for the tests of pages (Debian's chromium and chromedriver, driven by
selenium; `.ci/run` installs them when missing). Nothing is downloaded and no window
opens: Chromium runs --headless with software WebGL (SwiftShader).

Without a browser the tests that need one are skipped, unless CLEARANCE_REQUIRE_BROWSER is
set (`.ci/run` sets it), when they fail.
"""

from __future__ import annotations

import io
import os
import shutil
import time

import numpy as np
import pytest

CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
FLAGS = (
    "--headless=new",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--window-size=1280,800",
    "--force-device-scale-factor=1",
)


def _find(names) -> str | None:
    for n in names:
        p = shutil.which(n)
        if p:
            return p
    return None


def chrome():
    """A selenium Chrome driver on headless Chromium, or pytest.skip / fail (module
    docstring)."""
    binary, driver = _find(CHROMIUM), _find(("chromedriver",))
    missing = None
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        missing = "selenium is not installed (pip install -e '.[test]')"
    if missing is None and (binary is None or driver is None):
        missing = (
            "Chromium and chromedriver are not installed (apt-get install chromium chromium-driver)"
        )
    if missing is not None:
        if os.environ.get("CLEARANCE_REQUIRE_BROWSER"):
            pytest.fail(missing)
        pytest.skip(missing)
    opts = webdriver.ChromeOptions()
    opts.binary_location = binary
    for f in FLAGS:
        opts.add_argument(f)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(driver), options=opts)


def wait_for(driver, script: str, timeout: float = 20.0):
    """Poll a JavaScript expression until it is truthy; its value (fails after timeout)."""
    end = time.monotonic() + timeout
    while True:
        v = driver.execute_script(f"return ({script});")
        if v:
            return v
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout} s waiting for {script}")
        time.sleep(0.05)


def screenshot(driver) -> np.ndarray:
    """The viewport as an (h, w, 3) uint8 array."""
    from PIL import Image

    png = driver.get_screenshot_as_png()
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def severe_logs(driver) -> list[str]:
    """Console messages of level SEVERE (JavaScript errors) since the last call."""
    return [e["message"] for e in driver.get_log("browser") if e.get("level") == "SEVERE"]


def project(point, position, target, fov_deg: float, width: float, height: float, up=(0, 0, 1)):
    """Pixel (x, y) of a world point seen by a perspective camera at `position` looking at
    `target` (three.js lookAt: the camera looks along -z, y up), vertical field of view
    fov_deg, in a canvas of width x height. Written from the pinhole model, not from
    three.js."""
    p, c, t = (np.asarray(v, dtype=float) for v in (point, position, target))
    z = c - t
    z /= np.linalg.norm(z)
    x = np.cross(np.asarray(up, dtype=float), z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    d = p - c
    xc, yc, zc = d @ x, d @ y, d @ z
    f = 1.0 / np.tan(np.radians(fov_deg) / 2)
    xn = f * xc / (-zc) / (width / height)
    yn = f * yc / (-zc)
    return (xn + 1) / 2 * width, (1 - yn) / 2 * height
