"""A headless Chromium for the tests of the web views (:mod:`dhlb.render.web`), with the network off.

Not a test module: ``tests/test_web_browser.py`` and ``benchmarks/bench_web.py`` use it.
:func:`chromium_driver` starts Chromium through chromedriver (WebGL by SwiftShader, no GPU needed),
turns the network off (Chrome DevTools ``Network.emulateNetworkConditions``, checked by a probe that
must fail with ``net::ERR_INTERNET_DISCONNECTED``) and yields a :class:`Browser`, which records
every request the pages make (the DevTools performance log) and their console errors. The
JavaScript helpers work on the plotly graph div ``div.dhlb-web-view`` of the current frame:
:meth:`Browser.wait_ready`, :meth:`Browser.project` (3-D data coordinates to pixels of the div),
:meth:`Browser.rotate` (turn the camera about its up vector), :meth:`Browser.screenshot` (an element
as an RGB array) and :func:`ink` (the pixels that are not background).

Without chromium, chromedriver or selenium, :func:`chromium_driver` skips the test (pytest) and
:func:`missing` says what is missing.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import pathlib
import shutil
import time
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from collections.abc import Iterator

__all__ = ["INSTALL", "Browser", "chromium_driver", "ink", "missing", "parse_rgb"]

INSTALL = "apt-get install chromium chromium-driver; pip install selenium"
"""How to get what the browser tests need (Debian)."""
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
OPTIONS = ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--enable-unsafe-swiftshader",
           "--use-angle=swiftshader", "--force-device-scale-factor=1", "--hide-scrollbars")
PROBE = "http://dhlb-offline-probe.invalid/"
"""A URL the network-off probe fetches (``.invalid`` never resolves, so even a failed switch sends nothing)."""
OFFLINE_ERROR = "net::ERR_INTERNET_DISCONNECTED"

_READY = ("var e = document.querySelector('div.dhlb-web-view');"
          " return !!e && e.getAttribute('data-ready') === '1';")
_FRAMES = ("var done = arguments[arguments.length - 1], n = arguments[0];"
           " (function next() { if (n-- <= 0) { done(true); } else { requestAnimationFrame(next); } })();")
_PROJECT = """
var gd = document.querySelector('div.dhlb-web-view'), sc = gd._fullLayout.scene._scene;
var cp = sc.glplot.cameraParams, ds = sc.dataScale;
function mul(m, v) {  // a column-major 4x4 matrix times a vector
  var r = [0, 0, 0, 0];
  for (var i = 0; i < 4; i++) { for (var j = 0; j < 4; j++) { r[i] += m[4 * j + i] * v[j]; } }
  return r;
}
var c = sc.glplot.canvas.getBoundingClientRect(), g = gd.getBoundingClientRect();
return arguments[0].map(function (p) {
  var q = mul(cp.projection, mul(cp.view, mul(cp.model, [p[0] * ds[0], p[1] * ds[1], p[2] * ds[2], 1])));
  return [c.left - g.left + (q[0] / q[3] + 1) / 2 * c.width, c.top - g.top + (1 - q[1] / q[3]) / 2 * c.height,
          q[2] / q[3]];
});
"""
_BOUNDS = """
var gd = document.querySelector('div.dhlb-web-view'), lo = [Infinity, Infinity, Infinity];
var hi = [-Infinity, -Infinity, -Infinity];
gd._fullData.forEach(function (t) {
  ['x', 'y', 'z'].forEach(function (a, i) {
    var v = t[a] || [];
    for (var k = 0; k < v.length; k++) {
      var q = +v[k];
      if (isFinite(q)) { lo[i] = Math.min(lo[i], q); hi[i] = Math.max(hi[i], q); }
    }
  });
});
return [lo, hi];
"""
_TRACES = """
var gd = document.querySelector('div.dhlb-web-view');
return gd._fullData.map(function (t) {
  var xyz = ['x', 'y', 'z'].map(function (a) { return Array.from(t[a] || []); });
  var m = t.marker || {}, l = t.line || {};
  return {name: t.name, type: t.type, x: xyz[0], y: xyz[1], z: xyz[2],
          hovertext: t.hovertext === undefined ? null : t.hovertext, hoverinfo: t.hoverinfo,
          marker_color: m.color === undefined ? null : m.color, line_color: l.color === undefined ? null : l.color};
});
"""
_ROTATE = """
var done = arguments[arguments.length - 1], a = arguments[0] * Math.PI / 180;
var gd = document.querySelector('div.dhlb-web-view'), cam = gd._fullLayout.scene.camera;
var e = [cam.eye.x, cam.eye.y, cam.eye.z], u = [cam.up.x, cam.up.y, cam.up.z];
var n = Math.hypot(u[0], u[1], u[2]); u = u.map(function (x) { return x / n; });
var ue = u[0] * e[0] + u[1] * e[1] + u[2] * e[2];
var ux = [u[1] * e[2] - u[2] * e[1], u[2] * e[0] - u[0] * e[2], u[0] * e[1] - u[1] * e[0]];
var r = [0, 1, 2].map(function (i) {  // Rodrigues: e turned by a about u
  return e[i] * Math.cos(a) + ux[i] * Math.sin(a) + u[i] * ue * (1 - Math.cos(a));
});
Plotly.relayout(gd, {'scene.camera.eye': {x: r[0], y: r[1], z: r[2]}}).then(function () {
  requestAnimationFrame(function () { requestAnimationFrame(function () { done(r); }); });
}, function (err) { done('error: ' + err); });
"""
_HOVER = ("return Array.from(document.querySelectorAll('g.hovertext text'))"
          ".map(function (e) { return e.textContent; }).join(' ');")


def _browser_path() -> str | None:
    return next((p for p in map(shutil.which, BROWSERS) if p), None)


def missing() -> str | None:
    """Why a headless Chromium cannot run the browser tests here; None when everything is there.

    Returns
    -------
    str or None
        Names what is missing (chromium, chromedriver, selenium) and how to install it.
    """
    lacks = []
    if _browser_path() is None:
        lacks.append("chromium")
    if shutil.which("chromedriver") is None:
        lacks.append("chromedriver")
    try:
        import selenium  # noqa: F401
    except ImportError:
        lacks.append("selenium")
    if not lacks:
        return None
    return f"the browser tests need {', '.join(lacks)} (missing): {INSTALL}"


def parse_rgb(text: str) -> np.ndarray:
    """The colour ``"rgb(r,g,b)"`` (or ``"#rrggbb"``) as a float array in [0, 1].

    Parameters
    ----------
    text : str

    Returns
    -------
    (3,) float array

    Examples
    --------
    >>> parse_rgb("rgb(255, 0, 51)").tolist(), parse_rgb("#ff0033").tolist()
    ([1.0, 0.0, 0.2], [1.0, 0.0, 0.2])
    """
    s = text.strip()
    if s.startswith("#"):
        return np.array([int(s[i:i + 2], 16) for i in (1, 3, 5)], dtype=np.float64) / 255.0
    inner = s[s.index("(") + 1:s.rindex(")")]
    return np.array([float(c) for c in inner.split(",")[:3]], dtype=np.float64) / 255.0


def ink(image: np.ndarray, background=(1.0, 1.0, 1.0), tol: float = 8 / 255) -> np.ndarray:
    """The pixels of an RGB image that differ from the background by more than ``tol`` in some channel.

    Parameters
    ----------
    image : (H, W, 3) float array
        Values in [0, 1].
    background : (3,) float array
    tol : float

    Returns
    -------
    (H, W) bool array

    Examples
    --------
    >>> img = np.ones((2, 2, 3)); img[0, 1] = (0.5, 0.5, 0.5); img[1, 1, 2] = 1 - 4 / 255
    >>> ink(img).tolist()
    [[False, True], [False, False]]
    """
    diff = np.abs(np.asarray(image, dtype=np.float64)[..., :3] - np.asarray(background, dtype=np.float64))
    return diff.max(axis=-1) > tol


class Browser:
    """A selenium Chromium driver and what its pages did: requests, console errors.

    Parameters
    ----------
    driver : selenium.webdriver.Chrome
        Started with the ``goog:loggingPrefs`` browser and performance logs (:func:`chromium_driver`).
    """

    def __init__(self, driver):
        self.driver = driver
        self.requested: list[str] = []
        self.failed: dict[str, str] = {}
        self._ids: dict[str, str] = {}

    # ---------------------------------------------------------------- what the pages did
    def _drain(self) -> None:
        for entry in self.driver.get_log("performance"):
            msg = json.loads(entry["message"])["message"]
            params = msg.get("params", {})
            if msg["method"] == "Network.requestWillBeSent":
                self.requested.append(params["request"]["url"])
                self._ids[params["requestId"]] = params["request"]["url"]
            elif msg["method"] == "Network.loadingFailed":
                self.failed[self._ids.get(params["requestId"], params["requestId"])] = params["errorText"]

    def requests(self) -> list[str]:
        """Every URL requested since the browser started (documents, frames, scripts, images, fetches)."""
        self._drain()
        return [u for u in self.requested if u != PROBE]

    def assert_local(self) -> None:
        """Assert that every request, every resource timing entry and this document have ``file:`` URLs."""
        urls = self.requests() + self.driver.execute_script(
            "return performance.getEntriesByType('resource').map(function (e) { return e.name; })"
            ".concat([document.URL]);")
        remote = sorted({u for u in urls if not u.startswith("file:")})
        assert not remote, f"the page loaded non-local resources: {remote}"

    def console_errors(self) -> list[str]:
        """The console messages of level SEVERE since the last call (of every frame of the page)."""
        return [e["message"] for e in self.driver.get_log("browser")
                if e["level"] == "SEVERE" and PROBE not in e["message"]]

    def check_offline(self) -> None:
        """Fetch :data:`PROBE` from the current frame; raise unless it failed as offline."""
        self.driver.execute_async_script(
            "var done = arguments[arguments.length - 1];"
            f" fetch('{PROBE}', {{mode: 'no-cors'}}).then(function () {{ done(1); }}, function () {{ done(0); }});")
        deadline = time.monotonic() + 10
        while PROBE not in self.failed and time.monotonic() < deadline:
            self._drain()
            time.sleep(0.05)
        error = self.failed.pop(PROBE, "no failure recorded")
        if error != OFFLINE_ERROR:
            raise RuntimeError(f"the network is not off in the browser: the probe {PROBE} gave {error!r}")
        self.console_errors()  # the probe's own "Failed to load resource" message

    # ---------------------------------------------------------------- pages and views
    def open(self, path) -> None:
        """Navigate to a local file."""
        self.driver.get(pathlib.Path(path).resolve().as_uri())

    def frames(self, n: int = 2) -> None:
        """Let the page render ``n`` animation frames."""
        self.driver.execute_async_script(_FRAMES, int(n))

    def wait_ready(self, timeout: float = 30.0) -> None:
        """Wait until the view of the current frame says ``data-ready="1"`` (``Plotly.newPlot`` resolved), then render.

        Raises
        ------
        AssertionError
            Not ready within ``timeout`` seconds (with the console errors).
        """
        deadline = time.monotonic() + timeout
        while not self.driver.execute_script(_READY):
            if time.monotonic() > deadline:
                raise AssertionError(f"the view was not ready within {timeout} s; console errors: "
                                     f"{self.console_errors()}")
            time.sleep(0.05)
        self.frames(2)

    def view(self):
        """The graph div ``div.dhlb-web-view`` of the current frame (a selenium element)."""
        from selenium.webdriver.common.by import By

        return self.driver.find_element(By.CSS_SELECTOR, "div.dhlb-web-view")

    def traces(self) -> list[dict]:
        """The traces of the view as plotly drew them: name, type, x, y, z, hovertext, colours."""
        return self.driver.execute_script(_TRACES)

    def bounds(self) -> np.ndarray:
        """The (2, 3) lower and upper corners of every finite coordinate of every trace."""
        return np.asarray(self.driver.execute_script(_BOUNDS), dtype=np.float64)

    def project(self, points) -> np.ndarray:
        """Pixels of 3-D data points in the view (from plotly's camera matrices).

        Parameters
        ----------
        points : (k, 3) float array

        Returns
        -------
        (k, 3) float array
            Column, row (CSS pixels from the top left of the graph div) and the depth in [-1, 1]
            (smaller is nearer the camera).
        """
        P = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return np.asarray(self.driver.execute_script(_PROJECT, P.tolist()), dtype=np.float64).reshape(-1, 3)

    def projected_box(self) -> tuple[int, int, int, int]:
        """The pixel box ``(col0, row0, col1, row1)`` of the projected corners of :meth:`bounds`."""
        lo, hi = self.bounds()
        corners = np.array([[(lo, hi)[(k >> d) & 1][d] for d in range(3)] for k in range(8)])
        q = self.project(corners)
        return (int(np.floor(q[:, 0].min())), int(np.floor(q[:, 1].min())),
                int(np.ceil(q[:, 0].max())), int(np.ceil(q[:, 1].max())))

    def rotate(self, degrees: float) -> np.ndarray:
        """Turn the camera by ``degrees`` about its up vector (``Plotly.relayout`` of the eye), then render.

        Returns
        -------
        (3,) float array
            The new eye.
        """
        eye = self.driver.execute_async_script(_ROTATE, float(degrees))
        if isinstance(eye, str):
            raise AssertionError(f"Plotly.relayout failed: {eye}")
        return np.asarray(eye, dtype=np.float64)

    def hover_text(self) -> str:
        """The text of the hover label of the view (empty when none is shown)."""
        return self.driver.execute_script(_HOVER)

    def screenshot(self, element=None) -> np.ndarray:
        """An element (default: the view) as it is on screen, (H, W, 3) float array in [0, 1]."""
        import matplotlib.image

        png = (self.view() if element is None else element).screenshot_as_png
        return np.asarray(matplotlib.image.imread(io.BytesIO(png), format="png"))[..., :3]

    def settled_screenshot(self, element=None, tries: int = 10) -> np.ndarray:
        """:meth:`screenshot` once two in a row, a few animation frames apart, are identical.

        After a change of the camera, WebGL and plotly's SVG layers may take a few frames to
        settle; with SwiftShader two screenshots of a settled page are equal pixel for pixel.

        Raises
        ------
        AssertionError
            Still changing after ``tries`` screenshots.
        """
        last = self.screenshot(element)
        for _ in range(tries):
            self.frames(3)
            shot = self.screenshot(element)
            if shot.shape == last.shape and np.array_equal(shot, last):
                return shot
            last = shot
        raise AssertionError(f"the view kept changing over {tries} screenshots")


@contextlib.contextmanager
def chromium_driver(width: int = 1000, height: int = 1000) -> Iterator[Browser]:
    """A headless Chromium with the network off, as a :class:`Browser`; skips the test when it cannot start.

    Parameters
    ----------
    width, height : int
        The window (the viewport is a little lower).

    Yields
    ------
    Browser

    Raises
    ------
    RuntimeError
        The network could not be turned off.
    """
    reason = missing()
    if reason is not None:
        import pytest

        pytest.skip(reason)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = _browser_path()
    for arg in (*OPTIONS, f"--window-size={int(width)},{int(height)}"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    # an explicit chromedriver: otherwise Selenium Manager looks for one on the network
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver"), log_output=os.devnull), options=options)
    try:
        driver.set_script_timeout(60)
        driver.execute_cdp_cmd("Network.enable", {})
        driver.execute_cdp_cmd("Network.emulateNetworkConditions", {
            "offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1})
        browser = Browser(driver)
        driver.get("data:text/html,<title>probe</title>")
        browser.check_offline()
        browser.requested.clear()
        yield browser
    finally:
        driver.quit()
