"""The explorer's guide page and its screenshots: the pictures the page shows are the
ones the screenshot script takes (the docs build replaces exactly those when it has
Chromium), and the committed ones, kept for builds without Chromium, are whole PNGs of
the script's size."""

from __future__ import annotations

import importlib.util
import re
import struct
from pathlib import Path
from types import ModuleType

DOCS = Path(__file__).parents[1] / "docs"
GUIDE = DOCS / "guide" / "explorer.md"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"  # the PNG specification, section 5.2


def _script() -> ModuleType:
    path = DOCS / "_static" / "make_explorer_screenshots.py"
    spec = importlib.util.spec_from_file_location("make_explorer_screenshots", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def png_size(path: Path) -> tuple[int, int]:
    """(width, height) in pixels from a PNG's IHDR chunk, which must come first (PNG
    specification, section 11.2.2), after checking that the file ends with IEND."""
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    length, kind = struct.unpack(">I4s", data[8:16])
    assert kind == b"IHDR" and length == 13
    assert data[-12:] == b"\x00\x00\x00\x00IEND\xaeB`\x82", f"{path} is cut short"
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def test_the_guide_shows_the_screenshots_the_script_takes() -> None:
    script = _script()
    shown = re.findall(r'src="\.\./_static/explorer/([^"]+)"', GUIDE.read_text())
    assert sorted(shown) == sorted(script.NAMES)


def test_the_committed_screenshots_are_whole_pngs_of_the_scripts_size() -> None:
    script = _script()
    size = (script.VIEWPORT["width"], script.VIEWPORT["height"])
    for name in script.NAMES:
        assert png_size(script.FOLDER / name) == size
