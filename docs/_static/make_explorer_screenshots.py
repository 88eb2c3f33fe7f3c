"""Screenshots of the live explorer for its guide page (``docs/guide/explorer.md``).

``celtstone serve`` is started, headless Chromium (at /usr/bin/chromium, driven by
Playwright, which never downloads a browser of its own) opens the page, and two pictures
are taken at 1400 × 1000 pixels:

- ``explorer/first_run.png``: the page as it opens, Kane & Levinson's stone spun the
  wrong way on the rolling model, with its first run drawn;
- ``explorer/compare.png``: the sliding model at f = 0.35 pinned, then f = 0.15: the
  paper's Figure 2 by hand.

The docs build calls :func:`take` and publishes its pictures in place of the committed
ones (``docs/_ext/celtstone_docs.py``); without Chromium, Playwright or Panel it keeps
the committed ones. ``python docs/_static/make_explorer_screenshots.py`` renews those.
"""

from __future__ import annotations

import importlib.util
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

CHROMIUM = Path("/usr/bin/chromium")
FOLDER = Path(__file__).with_name("explorer")
NAMES = ("first_run.png", "compare.png")
VIEWPORT = {"width": 1400, "height": 1000}  # pixels
WAIT = 180.0  # s; a bound on waiting for the page, not a speed requirement


def missing() -> str:
    """What the screenshots need and this machine lacks ("" when nothing)."""
    if not CHROMIUM.exists():
        return f"no Chromium at {CHROMIUM}"
    for module in ("panel", "playwright"):
        if importlib.util.find_spec(module) is None:
            return f"{module} is not installed"
    return ""


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _listening(port: int) -> None:
    deadline = time.monotonic() + WAIT
    while time.monotonic() < deadline:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=5):
                return
        except OSError:
            time.sleep(0.1)
    raise RuntimeError("celtstone serve did not start listening")


#: the points of the spin plot's line in the page's Bokeh document (-1: not there yet)
SPIN_POINTS = """() => {
    for (const doc of Bokeh.documents) {
        const line = doc.get_model_by_name("spin");
        if (line) return line.data_source.data.value.length;
    }
    return -1;
}"""


def _verdict_after(page: Any, before: str) -> str:
    """The verdict once it names a run and differs from ``before``, its plots drawn."""
    verdict = page.locator(".cs-verdict p")
    deadline = time.monotonic() + WAIT
    while time.monotonic() < deadline:
        text = str(verdict.inner_text()) if verdict.count() else ""
        if "rever" in text and text != before and page.evaluate(SPIN_POINTS) > 0:
            page.wait_for_timeout(2000)  # the canvases paint after their data arrives
            return text
        page.wait_for_timeout(50)
    raise RuntimeError("the explorer showed no verdict")


def take(folder: Path = FOLDER) -> dict[str, str]:
    """Serve the explorer, take the screenshots into ``folder``; each picture's verdict.

    Raises
    ------
    RuntimeError
        When :func:`missing` names something, or the page does not answer.
    """
    lacking = missing()
    if lacking:
        raise RuntimeError(f"cannot take the explorer's screenshots: {lacking}")
    from playwright.sync_api import sync_playwright

    folder.mkdir(parents=True, exist_ok=True)
    port = _free_port()
    command = [sys.executable, "-m", "celtstone", "serve", "--no-browser", "--port", str(port)]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    verdicts: dict[str, str] = {}
    try:
        _listening(port)
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(
                executable_path=str(CHROMIUM),
                args=["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run"],
                headless=True,
            )
            try:
                page = browser.new_page(viewport=VIEWPORT)
                page.goto(f"http://127.0.0.1:{port}/", wait_until="load")
                first = _verdict_after(page, "")
                page.screenshot(path=str(folder / NAMES[0]))
                verdicts[NAMES[0]] = first
                page.get_by_role("button", name="sliding", exact=True).click()
                pinned = _verdict_after(page, first)
                page.get_by_role("button", name="pin this run").click()
                box = page.locator(".cs-friction_coefficient input").first
                box.fill("0.15")
                box.press("Enter")
                verdicts[NAMES[1]] = _verdict_after(page, pinned)
                page.screenshot(path=str(folder / NAMES[1]))
            finally:
                browser.close()
    finally:
        process.terminate()
        process.wait(30)
    return verdicts


if __name__ == "__main__":
    for name, verdict in take().items():
        print(f"{FOLDER / name}: {verdict}")
