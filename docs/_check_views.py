"""Check in headless Chromium, with the network off, that built pages draw their views and their mathematics.

Usage::

    python docs/_check_views.py BUILD_DIR [PAGE ...]

``PAGE`` is a page of the build relative to ``BUILD_DIR`` (default: the pages of notebooks 06 and 08).
Every ``.dhlb-web-view`` of each page must get ``data-ready="1"`` (plotly drew it), its WebGL canvas must
have non-white pixels (the page's text and plotly's SVG layers hidden while it is captured), plotly must
come from the page (``window.Plotly``) with no AMD loader (``window.define``) to swallow it, and the
browser console must show no SEVERE message. The pages of ``MATH_PAGES`` must typeset every formula
(each ``.math`` element holds MathJax's SVG output, none shows its TeX source). Chromium resolves no
host name (``--host-resolver-rules``): a page that needs the network fails here. Prints one line per
page or view and exits 1 on any failure.

Needs selenium, Pillow, Chromium and chromedriver (``CHROMIUM``, ``CHROMEDRIVER``: their paths, default
``/usr/bin/chromium``, ``/usr/bin/chromedriver``); software WebGL (SwiftShader) is enough.
"""

import io
import os
import sys
import time
from pathlib import Path

PAGES = ["notebooks/06_direction_fields.html", "notebooks/08_vortex_filaments.html"]
MATH_PAGES = ["fem.html", "theory.html", "bundles.html", "notebooks/05_line_bundle_laplacian_landau_levels.html"]
TIMEOUT = 120.0  # seconds for the views of one page to be drawn


def _driver():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = os.environ.get("CHROMIUM", "/usr/bin/chromium")
    for arg in ("--headless=new", "--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
                "--window-size=1200,1000", "--allow-file-access-from-files",
                "--host-resolver-rules=MAP * ~NOTFOUND"):   # no network: what a page needs must be in the build
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(os.environ.get("CHROMEDRIVER", "/usr/bin/chromedriver")),
                            options=options)


def _ink(png: bytes) -> float:
    """The fraction of pixels of a PNG that are not (nearly) white."""
    from PIL import Image

    img = Image.open(io.BytesIO(png)).convert("L")
    hist = img.histogram()
    return 1.0 - sum(hist[245:]) / max(1, img.width * img.height)


def check_page(driver, path: Path) -> list[str]:
    """Load ``path``, wait for its views, print one line per view; return the failures."""
    from selenium.webdriver.common.by import By

    driver.get_log("browser")  # drop the messages of earlier pages
    driver.get(path.resolve().as_uri())
    failures = []
    deadline = time.monotonic() + TIMEOUT
    while True:
        views = driver.find_elements(By.CSS_SELECTOR, ".dhlb-web-view")
        ready = [v.get_attribute("data-ready") == "1" for v in views]
        if (views and all(ready)) or time.monotonic() > deadline:
            break
        time.sleep(0.5)
    if not views:
        return [f"{path.name}: no interactive view on the page"]
    plotly, amd = driver.execute_script("return [typeof window.Plotly, typeof window.define];")
    if plotly != "object" or amd != "undefined":
        failures.append(f"{path.name}: window.Plotly is {plotly}, window.define is {amd} (expected object, undefined)")
    # only the WebGL drawing is captured: plotly's SVG layers (title, colour bar) and the page around are hidden
    driver.execute_script("document.body.style.visibility = 'hidden';"
                          "document.querySelectorAll('.dhlb-web-view .gl-container')"
                          ".forEach(function (e) { e.style.visibility = 'visible'; });")
    for k, (view, ok) in enumerate(zip(views, ready)):
        canvases = view.find_elements(By.CSS_SELECTOR, ".gl-container canvas")
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'});", view)
        time.sleep(0.3)
        ink = _ink(view.screenshot_as_png) if canvases else 0.0
        print(f"{path.name} view {k}: data-ready={'1' if ok else 'missing'}, {len(canvases)} canvas, "
              f"non-white {100 * ink:.1f}% of the view")
        if not ok:
            failures.append(f"{path.name} view {k}: not drawn within {TIMEOUT:.0f} s")
        if ink < 0.005:
            failures.append(f"{path.name} view {k}: the canvas is blank")
    driver.execute_script("document.body.style.visibility = '';")
    severe = [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]
    print(f"{path.name}: {len(views)} view(s), {len(severe)} SEVERE console message(s)")
    failures += [f"{path.name}: console: {m}" for m in severe]
    return failures


def check_math(driver, path: Path) -> list[str]:
    """Load ``path`` and wait for MathJax; every ``.math`` element must hold its SVG output; return the failures."""
    driver.get(path.resolve().as_uri())
    deadline = time.monotonic() + TIMEOUT
    state = None
    while time.monotonic() < deadline:
        state = driver.execute_script(
            "var m = document.querySelectorAll('.math');"
            "var done = document.querySelectorAll('.math mjx-container svg').length;"
            "var raw = Array.prototype.filter.call(m, function (e) {"
            "  return !e.querySelector('mjx-container') && /\\\\[(\\[]/.test(e.textContent); }).length;"
            "return [m.length, done, raw, typeof window.MathJax];")
        if state[0] and not state[2]:
            break
        time.sleep(0.5)
    total, svgs, raw, mathjax = state
    print(f"{path.name}: {total} formulas, {svgs} typeset as SVG, {raw} left as TeX (MathJax: {mathjax})")
    if not total:
        return [f"{path.name}: no formula on the page"]
    return [f"{path.name}: {raw} of {total} formulas show their TeX source"] if raw or not svgs else []


def main(argv: list[str]) -> int:
    """Check the pages; 0 when every view is drawn, 1 otherwise, 2 on a usage error."""
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 2
    build = Path(argv[0])
    pages = [build / p for p in (argv[1:] or PAGES)]
    math = [build / p for p in ([] if argv[1:] else MATH_PAGES)]
    missing = [str(p) for p in pages + math if not p.is_file()]
    if missing:
        print("no such page:", *missing)
        return 2
    driver = _driver()
    try:
        failures = [f for p in pages for f in check_page(driver, p)] + [f for p in math for f in check_math(driver, p)]
    finally:
        driver.quit()
    for f in failures:
        print("FAIL", f)
    print("OK" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
