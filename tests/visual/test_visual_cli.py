"""``celtstone animate`` and ``celtstone view`` in-process: files, messages, exit statuses."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import imageio.v3 as iio
import pytest
import xarray as xr

from celtstone.cli.main import main
from celtstone.files.export import write


@pytest.fixture
def run_file(sliding_run: xr.Dataset, tmp_path: Path) -> Path:
    return write(sliding_run, tmp_path / "run.nc")


def _call(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


def test_view_writes_the_page(run_file: Path, tmp_path: Path) -> None:
    status, out, _ = _call(["view", str(run_file), "--out", str(tmp_path / "run.html")])
    assert status == 0
    assert "61 frames" in out
    assert (tmp_path / "run.html").read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_animate_writes_the_video(run_file: Path, tmp_path: Path) -> None:
    target = tmp_path / "run.gif"
    argv = ["animate", str(run_file), "--out", str(target), "--speed", "4", "--size", "160x120"]
    status, out, _ = _call(argv)
    assert status == 0
    # 2 s at 4 x real time, 20 fps: 0.5 s of playback, 11 frames
    assert "11 frames at 20 fps (4 × real time)" in out
    assert iio.imread(target, index=None).shape[:3] == (11, 120, 160)


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["animate", "{run}", "--out", "{tmp}/run.avi"], "out"),
        (["animate", "{run}", "--out", "{tmp}/run.mp4", "--speed", "-1"], "speed"),
        (["animate", "{run}", "--out", "{tmp}/run.mp4", "--speed", "fast"], "speed"),
        (["animate", "{run}", "--out", "{tmp}/run.gif", "--fps", "60"], "fps"),
        (["animate", "{run}", "--out", "{tmp}/run.mp4", "--size", "big"], "size"),
        (["animate", "{tmp}/none.nc", "--out", "{tmp}/run.mp4"], "run"),
        (["view", "{run}", "--out", "{tmp}/run.pdf"], "out"),
        (["view", "{tmp}/none.nc", "--out", "{tmp}/run.html"], "run"),
        (["view", "{tmp}/not_a_run.nc", "--out", "{tmp}/run.html"], "run"),
    ],
)
def test_bad_input_is_one_line_naming_the_parameter(
    argv: list[str], name: str, run_file: Path, tmp_path: Path
) -> None:
    xr.Dataset({"x": ("t", [1.0, 2.0])}).to_netcdf(tmp_path / "not_a_run.nc")
    before = set(tmp_path.iterdir())
    args = [a.format(run=run_file, tmp=tmp_path) for a in argv]
    status, _, err = _call(args)
    assert status == 2
    assert err.startswith(f"celtstone: error: {name} = ")
    assert err.count("\n") == 1
    assert set(tmp_path.iterdir()) == before  # nothing written
