"""The explorer in a real browser: ``celtstone serve`` is started, headless Chromium opens
the page, moves the friction coefficient, types a value out of range, pins a run and
downloads the NetCDF file.

Runs when Chromium is at /usr/bin/chromium and Panel is installed; Playwright drives it
and never downloads a browser of its own.
"""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from celtstone.cli.main import main

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run"]
WAIT_MS = 120_000  # a bound on waiting for the page, not a speed requirement
SLOW_T_END = 2000.0  # s of sliding: minutes of computing, a run a student would stop

pytestmark = pytest.mark.skipif(
    not CHROMIUM.exists(),
    reason="browser tests need Chromium at /usr/bin/chromium (apt-get install chromium)",
)


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    pytest.importorskip("panel")
    port = _free_port()
    process = subprocess.Popen(
        [sys.executable, "-m", "celtstone", "serve", "--no-browser", "--port", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    url = f"http://127.0.0.1:{port}/"
    try:
        deadline = time.monotonic() + WAIT_MS / 1000
        while time.monotonic() < deadline:
            try:
                with urllib.request.urlopen(url, timeout=5) as answer:
                    if answer.status == 200:
                        break
            except OSError:
                time.sleep(0.2)
        else:
            raise AssertionError("celtstone serve did not answer")
        yield url
    finally:
        process.terminate()
        process.wait(30)


@pytest.fixture()
def tab(server: str) -> Iterator[Any]:
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True
        )
        try:
            page = browser.new_page(viewport={"width": 1400, "height": 1000}, accept_downloads=True)
            page.errors = []  # console errors and uncaught exceptions of the page
            page.outside = []  # requests that leave the server: none expected
            page.on("console", lambda m: page.errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda error: page.errors.append(str(error)))
            page.on(
                "request",
                lambda r: (
                    None
                    if r.url.startswith((server, "data:", "blob:"))
                    else page.outside.append(r.url)
                ),
            )
            page.goto(server, wait_until="load")
            yield page
        finally:
            browser.close()


def _verdict(page: Any) -> str:
    """The verdict's text; "" before the first run's (an empty verdict has no paragraph)."""
    shown = page.locator(".cs-verdict p")
    return str(shown.inner_text()) if shown.count() else ""


def _wait_verdict(page: Any, different_from: str) -> str:
    """The verdict once it names a run and differs from ``different_from``."""
    deadline = time.monotonic() + WAIT_MS / 1000
    while time.monotonic() < deadline:
        text = _verdict(page)
        if "rever" in text and text != different_from:
            return text
        page.wait_for_timeout(50)
    raise AssertionError(f"the verdict stayed {_verdict(page)!r}")


def _set_friction(page: Any, text: str) -> None:
    box = page.locator(".cs-friction_coefficient input").first
    box.fill(text)
    box.press("Enter")


def _curves(page: Any, name: str) -> int:
    """Points of the spin plot's renderer ``name``, read from the page's Bokeh document."""
    return int(
        page.evaluate(
            """(name) => {
                for (const doc of Bokeh.documents) {
                    const r = doc.get_model_by_name(name);
                    if (r) return r.data_source.data.value.length;
                }
                return -1;
            }""",
            name,
        )
    )


def _cli_words(friction: str, capsys: pytest.CaptureFixture[str]) -> str:
    """What the verdict must say of the first reversal: ``celtstone run``'s own answer."""
    argv = ["run", "--model", "sliding", "--friction-coefficient", friction, "--json"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    first = summary["first_reversal_time"]
    if first is None:  # f = 0.15 on this start: no reversal in the default 10 s
        return f"no reversal in {summary['t_stop']:g} s"
    return f"reverses at {first:.3g} s"


def test_the_explorer_in_chromium(
    tab: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tab
    first = _wait_verdict(page, "")
    page.get_by_role("button", name="sliding", exact=True).click()
    sliding = _wait_verdict(page, first)
    assert _cli_words("0.35", capsys) in sliding

    page.get_by_role("button", name="pin this run").click()
    _set_friction(page, "0.15")
    moved = _wait_verdict(page, sliding)
    assert _cli_words("0.15", capsys) in moved
    # the pinned f = 0.35 run and the f = 0.15 run: two curves on the spin plot
    assert _curves(page, "spin") > 0 and _curves(page, "pinned_spin") == _curves(page, "spin")

    _set_friction(page, "-1")
    message = page.locator(".cs-message div").first
    message.wait_for(state="visible", timeout=WAIT_MS)
    assert "friction_coefficient = -1.0 is not allowed: expected a number >= 0" in (
        message.inner_text()
    )
    assert _verdict(page) == moved and _curves(page, "spin") > 0

    with page.expect_download(timeout=WAIT_MS) as download:
        page.get_by_role("button", name="run (NetCDF)").click()
    path = tmp_path / "run.nc"
    download.value.save_as(path)
    assert main(["plot", str(path), "--out", str(tmp_path / "run.png")]) == 0
    capsys.readouterr()

    # a slow run shows how far it has come (t / t_end) and its stop button; stopped, the
    # page keeps the last finished run
    _set_friction(page, "0.15")
    _wait_verdict(page, "")
    box = page.locator(".cs-t_end input").first
    box.fill(str(SLOW_T_END))
    box.press("Enter")
    page.get_by_text(f"of {SLOW_T_END:g} s").wait_for(timeout=WAIT_MS)
    stop = page.get_by_role("button", name="stop", exact=True)
    assert stop.is_visible()
    kept = _verdict(page)
    stop.click()
    page.get_by_text("stopped; the plots show the last finished run").wait_for(timeout=WAIT_MS)
    assert _verdict(page) == kept and _curves(page, "spin") > 0
    page.screenshot(path=str(tmp_path / "explorer.png"))
    assert page.errors == [] and page.outside == []
