"""The interactive page: self-contained, carries the run, stays small for long runs."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.visual import PAGE_FRAME_LIMIT, PAGE_SIZE_LIMIT, PLOT_BUCKETS, write_viewer
from celtstone.visual.frames import envelope, plan_frames
from celtstone.visual.viewer import render_page

DATA_ELEMENT = re.compile(
    r'<script type="application/json" id="celtstone-data">(.*?)</script>', re.DOTALL
)


def _data(page: str) -> dict:
    match = DATA_ELEMENT.search(page)
    assert match is not None
    return json.loads(match.group(1))


def test_page_loads_nothing_from_outside(sliding_run: xr.Dataset) -> None:
    page, _ = render_page(sliding_run)
    assert "http://" not in page and "https://" not in page
    for tag in re.findall(r"<[^>]+>", page):
        for link in re.findall(r'\b(?:src|href)\s*=\s*["\']?([^"\'\s>]*)', tag):
            assert link.startswith("data:"), tag
    assert not re.search(r"url\(|@import|\bfetch\(|XMLHttpRequest|\bimport\(", page)
    assert page.count("<script") == 2  # the data and the inline renderer


def test_page_carries_the_run(sliding_run: xr.Dataset) -> None:
    page, _ = render_page(sliding_run)
    data = _data(page)
    times = sliding_run["time"].values
    plan = plan_frames(times, max_frames=PAGE_FRAME_LIMIT)
    frames = data["frames"]
    assert len(frames["time"]) == 61  # 2 s at 30 frames per simulated second
    np.testing.assert_allclose(frames["time"], times[plan.indices], rtol=1e-6)
    quaternion = np.reshape(frames["quaternion"], (-1, 4))
    expected = sliding_run["quaternion"].values[plan.indices]
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    np.testing.assert_allclose(quaternion, expected, atol=1e-6)
    np.testing.assert_allclose(
        frames["slip_speed"], sliding_run["slip_speed"].values[plan.indices], rtol=1e-5
    )
    spin = next(p for p in data["plots"] if p["name"] == "spin")
    np.testing.assert_allclose(spin["value"], sliding_run["spin"].values, rtol=1e-5)
    assert {p["name"] for p in data["plots"]} == {"spin", "tilt", "energy", "slip_speed"}
    assert len(data["mesh"]["triangles"]) % 3 == 0
    assert max(data["mesh"]["triangles"]) == len(data["mesh"]["vertices"]) // 3 - 1


def test_title_is_escaped(sliding_run: xr.Dataset) -> None:
    page, _ = render_page(sliding_run, label="<script>alert(1)</script>")
    assert "<script>alert" not in page
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in page  # in <title> and <h1>
    assert _data(page)["label"] == "<script>alert(1)</script>"  # the data keeps it whole


@pytest.mark.parametrize(
    "text",
    [
        "__CELTSTONE_TITLE__",
        "/*__CELTSTONE_DATA__*/",
        "x __CELTSTONE_TITLE__ /*__CELTSTONE_DATA__*/",
        'a "quoted" back\\slash __CELTSTONE_TITLE__',
    ],
)
def test_data_is_never_read_as_template(sliding_run: xr.Dataset, text: str) -> None:
    """A label (body file name) or a title attribute holding the template's own markers is
    inlined as data: the page keeps exactly one data block and it parses."""
    run = sliding_run.assign_attrs(title=text, body=text)
    page, _ = render_page(run, label=text)
    data = _data(page)
    assert data["label"] == text
    assert data["title"] == text
    assert page.count('id="celtstone-data"') == 1
    assert f"<title>celtstone: {html.escape(text)}</title>" in page


def test_100_s_run_page_stays_within_the_limits(long_run: xr.Dataset, tmp_path: Path) -> None:
    info = write_viewer(long_run, tmp_path / "long.html")
    assert info.frames == PAGE_FRAME_LIMIT
    assert info.plot_points <= 2 * PLOT_BUCKETS
    assert info.bytes < PAGE_SIZE_LIMIT
    data = _data(info.path.read_text(encoding="utf-8"))
    tilt = next(p for p in data["plots"] if p["name"] == "tilt")
    # the envelope keeps the largest tilt of the 20 001 samples
    assert max(tilt["value"]) == pytest.approx(np.degrees(long_run["tilt"].values.max()), rel=1e-5)
    kept_t, _ = envelope(long_run["time"].values, long_run["tilt"].values)
    np.testing.assert_allclose(tilt["time"], kept_t, rtol=1e-6)


def test_bad_targets_are_refused(sliding_run: xr.Dataset, tmp_path: Path) -> None:
    with pytest.raises(cs.ParameterError, match="out"):
        write_viewer(sliding_run, tmp_path / "run.txt")
    with pytest.raises(cs.ParameterError, match="out"):
        write_viewer(sliding_run, tmp_path / "missing" / "run.html")
    assert list(tmp_path.iterdir()) == []
