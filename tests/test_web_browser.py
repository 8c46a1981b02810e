"""The interactive 3-D views (:mod:`dhlb.render.web`) in a real browser: headless Chromium, network off.

``dhlb demo`` runs once for the module; its ``index.html`` is opened from the file system and
every "rotate in 3-D" button is clicked: each view must load from local files only, draw the
model without console errors, and turn when the camera turns. Hovering a singularity must show
its index, the linked filaments must show in their colours, and a self-contained page (plotly
inline) must open too. Skipped without chromium, chromedriver or selenium (tests/browser.py).

Thresholds come from measurements in headless Chromium 150 with SwiftShader (window 1000 × 1000;
a view in the demo page is 472 × 472 pixels):

- ink (pixels more than 8/255 away from white) inside the projected bounding box of the data:
  0.12 (the octopus) to 0.81 (the vortex box) of the box; with the WebGL canvas hidden it is 0
  in every view, so every counted pixel is drawn by WebGL. Threshold :data:`MIN_INK` = 0.05.
- two screenshots of a settled view differ in 0 pixels; a quarter turn about the up vector
  changes 1.0 % (the vortex ring: the cube maps to itself, only the ring moves) to 22 % of the
  view's pixels. Threshold :data:`MIN_TURN` = 0.4 %.
- a filament seen through the 25 %-opaque domain is drawn within 31–35/255 of its trace colour
  (each channel); the nearest other colours on the canvas (the box's greys, the outline
  rgb(90,98,112)) are more than 60/255 away. Tolerance :data:`FILAMENT_TOL` = 48/255; each filament
  of vortex-linked covers about 1000 such pixels, threshold :data:`MIN_FILAMENT_PIXELS` = 300.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from tests.browser import chromium_driver, ink, missing, parse_rgb

pytest.importorskip("plotly")
pytest.importorskip("matplotlib")

MIN_INK = 0.05
"""Least fraction of the projected bounding box of the model that WebGL must draw on."""
MIN_TURN = 0.004
"""Least fraction of the view's pixels that a quarter turn of the camera must change."""
FILAMENT_TOL = 48 / 255
MIN_FILAMENT_PIXELS = 300
MARKER_TOL = 12 / 255
"""A singularity marker's pixels are within this of its colour (flat-shaded markers, no outline)."""


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """The output folder of ``dhlb demo`` (made once for the module)."""
    reason = missing()
    if reason is not None:   # do not spend the demo's 15 s when the browser cannot run
        pytest.skip(reason)
    from dhlb.cli import main

    out = tmp_path_factory.mktemp("web-demo")
    assert main(["demo", "-o", str(out), "-q"]) == 0
    return out


@pytest.fixture
def browser():
    with chromium_driver() as b:
        yield b


def _changed(a: np.ndarray, b: np.ndarray) -> float:
    """Fraction of pixels of two same-size screenshots that differ by more than 8/255 in some channel."""
    assert a.shape == b.shape
    return float((np.abs(a - b).max(axis=2) > 8 / 255).mean())


def _box_ink(browser, image) -> float:
    c0, r0, c1, r1 = browser.projected_box()
    H, W = image.shape[:2]
    box = ink(image)[max(r0, 0):min(r1, H), max(c0, 0):min(c1, W)]
    assert box.size > 0.05 * H * W, f"the projected model box {(c0, r0, c1, r1)} is (nearly) outside the view"
    return float(box.mean())


def test_every_view_of_the_demo_page_opens_offline_draws_and_turns(demo, browser):
    from selenium.webdriver.common.by import By

    from dhlb.render.gallery import LIVE_VIEWS

    driver = browser.driver
    browser.open(demo / "index.html")
    buttons = driver.find_elements(By.CSS_SELECTOR, "div.frame > button.dhlb-rotate")
    views = [b.get_attribute("data-view") for b in buttons]
    written = sorted(p.name for p in demo.glob("*.html")
                     if p.name != "index.html" and not p.name.endswith("-views.html"))
    assert sorted(views) == written and len(views) > LIVE_VIEWS     # one button per interactive view
    cards = [b.find_element(By.XPATH, "..") for b in buttons]
    for k, (button, view) in enumerate(zip(buttons, views)):
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'});", button)
        button.click()
        live = driver.find_elements(By.CSS_SELECTOR, "iframe.dhlb-web-frame")
        assert len(live) == min(k + 1, LIVE_VIEWS), f"{view}: {len(live)} live views"
        if k >= LIVE_VIEWS:                                          # the oldest went back to its picture
            old = cards[k - LIVE_VIEWS]
            assert not old.find_elements(By.TAG_NAME, "iframe")
            assert old.find_element(By.TAG_NAME, "img").is_displayed()
        frame = cards[k].find_element(By.CSS_SELECTOR, "iframe.dhlb-web-frame")
        assert frame.get_attribute("src").endswith("/" + view)
        driver.switch_to.frame(frame)
        try:
            if k == 0:
                browser.check_offline()                             # the network is off inside the frames too
            browser.wait_ready()
            assert browser.console_errors() == [], view
            before = browser.screenshot()                           # settled once ready (measured)
            frac = _box_ink(browser, before)
            assert frac >= MIN_INK, f"{view}: only {frac:.3f} of the model's box is drawn"
            browser.rotate(90.0)
            after = browser.settled_screenshot()
            turned = _changed(before, after)
            assert turned >= MIN_TURN, f"{view}: a quarter turn changed only {turned:.4f} of the pixels"
            assert browser.console_errors() == [], view
        finally:
            driver.switch_to.default_content()
    assert len(driver.find_elements(By.CSS_SELECTOR, "iframe.dhlb-web-frame")) == LIVE_VIEWS
    browser.assert_local()
    requested = {u.rsplit("/", 1)[-1] for u in browser.requests()}
    assert {"index.html", "plotly.min.js", *views} <= requested


def _nearest_marker_pixels(image, at, color, radius: int = 4, count: int = 4) -> list:
    """Up to ``count`` pixels of ``color`` within ``radius`` of ``at`` (column, row), nearest first."""
    x, y = int(np.rint(at[0])), int(np.rint(at[1]))
    H, W = image.shape[:2]
    r0, c0 = max(y - radius, 0), max(x - radius, 0)
    patch = image[r0:min(y + radius + 1, H), c0:min(x + radius + 1, W)]
    rows, cols = np.nonzero(np.abs(patch - color).max(axis=2) <= MARKER_TOL)
    order = np.argsort((rows + r0 - y) ** 2 + (cols + c0 - x) ** 2)
    return [(int(cols[i] + c0), int(rows[i] + r0)) for i in order[:count]]


def _hover(browser, element, x: int, y: int, timeout: float = 1.0) -> str:
    from selenium.webdriver.common.action_chains import ActionChains

    rect = element.rect
    ActionChains(browser.driver).move_to_element_with_offset(
        element, int(np.rint(x + 0.5 - rect["width"] / 2)), int(np.rint(y + 0.5 - rect["height"] / 2))).perform()
    deadline = time.monotonic() + timeout
    while True:
        text = browser.hover_text()
        if text or time.monotonic() > deadline:
            return text
        time.sleep(0.05)


def test_hovering_a_singularity_shows_its_index(demo, browser):
    browser.open(demo / "field-n4-s+0.html")
    browser.wait_ready()
    sing = next(t for t in browser.traces() if t["name"] == "singularities")
    labels = list(sing["hovertext"])
    assert all("index" in s for s in labels) and sing["hoverinfo"] == "text"
    P = np.array([sing["x"], sing["y"], sing["z"]], dtype=np.float64).T
    at = browser.project(P)[:, :2]
    image = browser.screenshot()
    colors = [parse_rgb(c) for c in sing["marker_color"]]
    assert any(np.allclose(c * 255, (217, 31, 26)) for c in colors)
    visible = [k for k in range(len(P)) if _nearest_marker_pixels(image, at[k], colors[k])]
    assert len(visible) >= 5, f"only {len(visible)} of {len(P)} singularity markers found where projected"
    view, matched, shown = browser.view(), [], []
    for k in visible[:12]:
        for x, y in _nearest_marker_pixels(image, at[k], colors[k]):
            text = _hover(browser, view, x, y)
            if text:
                shown.append(text)
                near = {labels[j] for j in np.nonzero(np.hypot(*(at - (x, y)).T) <= 6)[0]}
                if text in near:
                    matched.append(k)
                break
        if len(matched) >= 3:
            break
    assert all("index" in s and s in labels for s in shown), shown
    assert len(matched) >= 3, f"hover labels {shown} for {len(visible[:12])} visible singularities"
    assert browser.console_errors() == []


def test_the_linked_filaments_show_in_their_colours(demo, browser):
    browser.open(demo / "vortex-linked.html")
    browser.wait_ready()
    filaments = [t for t in browser.traces() if t["name"].startswith("filament")]
    colors = [parse_rgb(t["line_color"]) for t in filaments]
    assert len(filaments) == 2 and not np.allclose(*colors)
    image = browser.settled_screenshot()
    for t, c in zip(filaments, colors):
        near = np.abs(image - c).max(axis=2) <= FILAMENT_TOL
        assert near.sum() >= MIN_FILAMENT_PIXELS, f"{t['name']} {t['line_color']}: {near.sum()} pixels"
        P = np.array([t["x"], t["y"], t["z"]], dtype=np.float64).T
        q = np.round(browser.project(P[np.isfinite(P).all(axis=1)])[:, :2]).astype(np.int64)
        inside = (q[:, 0] >= 0) & (q[:, 1] >= 0) & (q[:, 0] < image.shape[1]) & (q[:, 1] < image.shape[0])
        assert inside.all()
        on = near[q[:, 1], q[:, 0]]                                  # its colour where its nodes project
        assert on.mean() >= 0.5, f"{t['name']}: its colour at {on.mean():.2f} of its nodes"
    assert browser.console_errors() == []


def test_a_self_contained_page_opens_offline(tmp_path, browser):
    from dhlb.fields import direction_field
    from dhlb.io import example_path, read_surface
    from dhlb.render.web import to_html

    page = to_html(direction_field(*read_surface(example_path("torus.obj")), n=4), tmp_path / "torus.html",
                   plotlyjs="inline")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["torus.html"]
    browser.open(page)
    browser.wait_ready()
    assert browser.console_errors() == []
    browser.assert_local()
    assert [u.rsplit("/", 1)[-1] for u in browser.requests()] == ["torus.html"]   # nothing but the page
    assert {t["name"] for t in browser.traces()} == {"mesh", "mesh: glyphs", "singularities"}
    assert _box_ink(browser, browser.settled_screenshot()) >= MIN_INK
