"""The live explorer's response: a control change to the redrawn result, and start-up.

1. A control change to the new run drawn on the page, for a rolling and a sliding run
   of 10 s (Padé law, disk contact): the explorer's Python side (no browser), polled as
   the served page polls, ``app.POLL_MS``; the median over repeats, warm cache.
2. ``celtstone serve`` to the first page usable: the command started, headless Chromium
   (at /usr/bin/chromium, driven by Playwright) opens the page as soon as the server
   listens; usable is its controls shown, and the first run's verdict follows. Without
   Chromium or Playwright this part says so and measures the page's HTML answer only.

Run with ``python benchmarks/bench_explore.py`` (needs the ``explore`` extra).
"""

from __future__ import annotations

import socket
import statistics
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

from celtstone.explorer import Inputs
from celtstone.explorer.app import POLL_MS, Explorer

CHROMIUM = Path("/usr/bin/chromium")
TARGETS = {"rolling": 0.5, "sliding": 1.5, "serve": 5.0}  # s, issue 42's targets


def _settle(explorer: Explorer) -> None:
    while True:
        explorer.poll()
        shown = explorer.outcome
        if shown is not None and shown.generation == explorer.runner.generation:
            return
        time.sleep(POLL_MS / 1000)


def change_to_redraw(kind: str, repeats: int = 7) -> list[float]:
    """Seconds from a control change to the new run shown, ``repeats`` times."""
    explorer = Explorer(Inputs(kind=kind, t_end=10.0))
    _settle(explorer)  # first run: loads the compiled kernels
    seconds = []
    for index in range(repeats):
        start = time.perf_counter()
        if kind == "rolling":  # the rolling model has no friction: nudge the spin
            explorer.omega[2].value = -5.0 - 0.01 * (index % 2 + 1)
        else:
            explorer.settings["friction_coefficient"].value = 0.35 - 0.01 * (index % 2 + 1)
        _settle(explorer)
        seconds.append(time.perf_counter() - start)
    return seconds


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _start(port: int) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [sys.executable, "-m", "celtstone", "serve", "--no-browser", "--port", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def _listening(port: int, start: float) -> float:
    """Seconds from ``start`` until the server accepts connections (a TCP connect: a GET
    of the page would build a page, and its first run, that no browser shows)."""
    while True:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=5):
                return time.perf_counter() - start
        except OSError:
            time.sleep(0.05)


def serve_to_usable() -> tuple[float, float, float, str]:
    """Seconds from ``celtstone serve`` to the server listening, to the first page usable
    (its controls shown: they answer from then on) and to the first run's verdict on it
    (the browser is started before the clock), and what the last two measure."""
    port = _free_port()
    url = f"http://127.0.0.1:{port}/"
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
    if sync_playwright is None or not CHROMIUM.exists():
        start = time.perf_counter()
        process = _start(port)
        try:
            listening = _listening(port, start)
            with urllib.request.urlopen(url, timeout=60):
                answered = time.perf_counter() - start
        finally:
            process.terminate()
            process.wait(30)
        return listening, answered, answered, "the page's HTML only (no Playwright or Chromium)"
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=str(CHROMIUM), args=["--headless", "--no-sandbox"], headless=True
        )
        page = browser.new_page()
        start = time.perf_counter()
        process = _start(port)
        try:
            listening = _listening(port, start)
            page.goto(url, wait_until="load")
            page.get_by_text("spin it the wrong way").wait_for(timeout=120_000)
            usable = time.perf_counter() - start
            verdict = page.locator(".cs-verdict p")
            while "rever" not in (verdict.inner_text() if verdict.count() else ""):
                page.wait_for_timeout(20)
            shown = time.perf_counter() - start
        finally:
            browser.close()
            process.terminate()
            process.wait(30)
    return listening, usable, shown, "controls shown in Chromium; the first run's verdict"


def main() -> None:
    for kind in ("rolling", "sliding"):
        seconds = change_to_redraw(kind)
        median = statistics.median(seconds)
        print(
            f"change -> redrawn, {kind} 10 s: median {median:.3f} s "
            f"(min {min(seconds):.3f}, max {max(seconds):.3f}; target {TARGETS[kind]} s)"
        )
    listening, usable, shown, what = serve_to_usable()
    print(
        f"celtstone serve -> listening {listening:.2f} s; first page usable {usable:.2f} s "
        f"(target {TARGETS['serve']} s); first verdict {shown:.2f} s ({what})"
    )


if __name__ == "__main__":
    main()
