"""The page in a real browser: headless Chromium plays it, the slider moves it, the
3-D view and the plots change, and nothing is loaded from outside or logged as an error.

Runs when Chromium is at /usr/bin/chromium (``apt-get install chromium``; ``.ci/run``
installs it); Playwright drives it and never downloads a browser of its own.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import numpy as np
import pytest

import celtstone as cs
from celtstone.visual import write_viewer

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
T_END = 10.0  # s; 301 frames at 30 per simulated second

pytestmark = pytest.mark.skipif(
    not CHROMIUM.exists(),
    reason="browser tests need Chromium at /usr/bin/chromium (apt-get install chromium)",
)


@pytest.fixture(scope="module")
def page_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Page of a 10 s rolling run of the Kane & Levinson body (spin reverses at 2.7 s)."""
    state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
    body = cs.load_body("kane_levinson_1982")
    run = cs.simulate(cs.RollingModel(), body, state, T_END).raise_for_status()
    return write_viewer(run.dataset, tmp_path_factory.mktemp("page") / "run.html").path


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        chromium = playwright.chromium.launch(
            executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True
        )
        yield chromium
        chromium.close()


def _changed_pixels(before: bytes, after: bytes) -> int:
    """Pixels whose colour differs by more than 30 (of 255) in some channel."""
    a = iio.imread(before, extension=".png").astype(int)
    b = iio.imread(after, extension=".png").astype(int)
    assert a.shape == b.shape
    return int(np.count_nonzero(np.max(np.abs(a - b), axis=-1) > 30))


class _Viewer:
    """The opened page, with what the browser logged and requested."""

    def __init__(self, browser: Any, page_file: Path) -> None:
        self.errors: list[str] = []
        self.outside: list[str] = []
        self.page = browser.new_page(viewport={"width": 1320, "height": 760})
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda error: self.errors.append(str(error)))
        self.page.on("request", self._request)
        self.page.goto(page_file.as_uri())
        self.page.wait_for_function("window.celtstoneViewer !== undefined")

    def _request(self, request: Any) -> None:
        if not request.url.startswith(("file://", "data:")):
            self.outside.append(request.url)

    def frame(self) -> int:
        return int(self.page.evaluate("window.celtstoneViewer.currentFrame()"))

    def shots(self) -> tuple[bytes, bytes]:
        return (
            self.page.locator("#scene").screenshot(),
            self.page.locator("#plots").screenshot(),
        )


def test_play_pause_slider_and_linked_plots(browser: Any, page_file: Path) -> None:
    viewer = _Viewer(browser, page_file)
    page = viewer.page
    count = int(page.evaluate("window.celtstoneViewer.frameCount"))
    assert count == 301
    assert page.locator("#plots canvas").count() == 4
    assert page.locator("#readout").inner_text().startswith("t = 0.00 s")
    scene0, plots0 = viewer.shots()

    # play for at least half a simulated second, then pause
    page.click("#play")
    assert page.locator("#play").inner_text() == "Pause"
    page.wait_for_function("window.celtstoneViewer.currentFrame() >= 15", timeout=10_000)
    page.click("#play")
    assert not page.evaluate("window.celtstoneViewer.isPlaying()")
    paused = viewer.frame()
    assert 15 <= paused < count
    assert int(page.locator("#time-slider").input_value()) == paused
    scene1, plots1 = viewer.shots()
    assert _changed_pixels(scene0, scene1) > 500  # the body turned and rocked
    assert _changed_pixels(plots0, plots1) > 50  # the four cursors moved

    # the keyboard on the slider: End goes to the last frame
    page.locator("#time-slider").focus()
    page.keyboard.press("End")
    assert viewer.frame() == count - 1
    assert page.locator("#readout").inner_text().startswith(f"t = {T_END:.2f} s")
    scene2, plots2 = viewer.shots()
    assert _changed_pixels(scene1, scene2) > 500
    assert _changed_pixels(plots1, plots2) > 50

    # the mouse on the slider: a click at its middle goes to the middle frame
    box = page.locator("#time-slider").bounding_box()
    page.mouse.click(box["x"] + 0.5 * box["width"], box["y"] + 0.5 * box["height"])
    assert math.isclose(viewer.frame(), (count - 1) / 2, abs_tol=0.05 * count)

    # a click on a plot seeks to its time: 2.5 s on the spin plot's time axis
    spin_plot = page.locator("#plot-spin")
    plot_box = spin_plot.bounding_box()
    left, right = 64, 520 - 12  # plot area of the 520 px canvas (viewer.html)
    x = left + 2.5 / T_END * (right - left)
    spin_plot.click(position={"x": x * plot_box["width"] / 520, "y": 60})
    assert math.isclose(viewer.frame(), 75, abs_tol=2)  # 2.5 s x 30 frames/s

    # playing from the end starts again from the beginning
    page.locator("#time-slider").focus()
    page.keyboard.press("End")
    page.click("#play")
    page.wait_for_function("window.celtstoneViewer.currentFrame() < 100", timeout=5_000)
    page.click("#play")

    assert viewer.errors == []
    assert viewer.outside == []
    page.close()


def test_dragging_turns_the_view(browser: Any, page_file: Path) -> None:
    viewer = _Viewer(browser, page_file)
    page = viewer.page
    before, plots_before = viewer.shots()
    box = page.locator("#scene").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 120, y - 40, steps=6)
    page.mouse.up()
    after, plots_after = viewer.shots()
    assert _changed_pixels(before, after) > 500
    assert _changed_pixels(plots_before, plots_after) == 0  # same time, same cursors
    assert viewer.frame() == 0
    assert viewer.errors == []
    page.close()
