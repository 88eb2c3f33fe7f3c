"""Videos read back with imageio: frame counts and sizes as planned, the body moves."""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest
import xarray as xr

import celtstone as cs
from celtstone.visual import VIDEO_FRAME_LIMITS, animate, animate_comparison, scene
from celtstone.visual import animation as animate_module

# the 100 s run's mp4 at the default 768 x 576 stays below this (README "See it move")
MP4_SIZE_LIMIT = 20e6  # bytes
RAW_RGB = ("-f", "rawvideo", "-pix_fmt", "rgb24", "-")


def _read_mp4(path: Path, width: int, height: int) -> tuple[np.ndarray, float]:
    """All frames (k, height, width, 3) decoded by the bundled ffmpeg, and the duration [s]."""
    decoded = subprocess.run(
        [imageio_ffmpeg.get_ffmpeg_exe(), "-v", "error", "-i", str(path), *RAW_RGB],
        capture_output=True,
        check=True,
    ).stdout
    frames = np.frombuffer(decoded, np.uint8).reshape(-1, height, width, 3)
    _, seconds = imageio_ffmpeg.count_frames_and_secs(str(path))
    return frames, seconds


def _read(path: Path, size: tuple[int, int]) -> np.ndarray:
    if path.suffix == ".mp4":
        return _read_mp4(path, *size)[0]
    return iio.imread(path, index=None)


def test_mp4_has_the_planned_frames_and_size(sliding_run: xr.Dataset, tmp_path: Path) -> None:
    # 2 s at real time, 30 fps: 61 frames
    info = animate(sliding_run, tmp_path / "run.mp4", size=(320, 240))
    frames, seconds = _read_mp4(info.path, 320, 240)
    assert info.frames == 61
    assert frames.shape == (61, 240, 320, 3)
    assert seconds == pytest.approx(61 / 30.0, abs=0.01)  # ffmpeg reports 0.01 s
    assert info.bytes == info.path.stat().st_size
    # the body turns: first and last frames differ
    assert np.mean(np.abs(frames[0].astype(float) - frames[-1].astype(float)) > 40) > 1e-3


def test_gif_slow_motion(rolling_runs: dict[str, xr.Dataset], tmp_path: Path) -> None:
    rolling_run = rolling_runs["kane_levinson_1982_paraboloid"]
    # first 4 s at speed 2 -> 2 s of playback at 20 fps: 41 frames of 50 ms
    info = animate(rolling_run, tmp_path / "run.gif", speed=2.0, size=(240, 180))
    frames = _read(info.path, info.size)
    assert (info.frames, info.fps, info.speed) == (41, 20.0, 2.0)
    assert frames.shape[:3] == (41, 180, 240)
    assert iio.immeta(info.path)["duration"] == 50
    # 12 fps asked: gif delays are whole centiseconds, so 90 ms (11.1 fps), 23 frames
    info = animate(
        rolling_run, tmp_path / "run.gif", speed=2.0, fps=12.0, size=(240, 180), overwrite=True
    )
    assert info.fps == pytest.approx(1 / 0.09)
    assert info.frames == 23  # floor(2 s / 0.09 s) + 1
    assert iio.immeta(info.path)["duration"] == 90


def test_comparison_side_by_side_on_the_shortest_clock(
    rolling_runs: dict[str, xr.Dataset], sliding_run: xr.Dataset, tmp_path: Path
) -> None:
    rolling_run = rolling_runs["kane_levinson_1982"]
    info = animate_comparison(
        [rolling_run, sliding_run],
        ["rolling", "sliding, f = 0.35"],
        tmp_path / "figure2.mp4",
        speed=2.0,
        size=(480, 192),
    )
    # clock: the 2 s sliding run, at speed 2 and 30 fps -> 31 frames
    assert _read(info.path, info.size).shape == (31, 192, 480, 3)


def test_bad_targets_and_sizes_are_refused(sliding_run: xr.Dataset, tmp_path: Path) -> None:
    with pytest.raises(cs.ParameterError, match="out"):
        animate(sliding_run, tmp_path / "run.avi")
    with pytest.raises(cs.ParameterError, match="out"):
        animate(sliding_run, tmp_path / "missing" / "run.mp4")
    with pytest.raises(cs.ParameterError, match="size"):
        animate(sliding_run, tmp_path / "run.mp4", size=(300, 200))
    with pytest.raises(cs.ParameterError, match="labels"):
        animate_comparison([sliding_run], [], tmp_path / "run.mp4")
    assert list(tmp_path.iterdir()) == []


def test_an_interrupted_video_leaves_no_file(
    sliding_run: xr.Dataset, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = []
    original = animate_module._Panel.show

    def failing(self: object, time: float, speed: float) -> None:
        calls.append(time)
        if len(calls) == 3:
            raise KeyboardInterrupt
        original(self, time, speed)  # type: ignore[arg-type]

    monkeypatch.setattr(animate_module._Panel, "show", failing)
    with pytest.raises(KeyboardInterrupt):
        animate(sliding_run, tmp_path / "run.mp4", size=(160, 128))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_100_s_run_video_stays_within_the_limits(long_run: xr.Dataset, tmp_path: Path) -> None:
    info = animate(long_run, tmp_path / "long.mp4")
    assert info.frames == VIDEO_FRAME_LIMITS[".mp4"]
    assert _read(info.path, info.size).shape[0] == info.frames
    assert info.bytes < MP4_SIZE_LIMIT


def _drawn_whole(figure: Any, panel: Any, time: float) -> tuple[np.ndarray, np.ndarray]:
    """The figure drawn from scratch at ``time`` [s] with matplotlib's own 3-D artists: the
    whole trail, and the body's front faces as a ``Poly3DCollection`` (shaded as the video
    shades them, each face stroked in its colour to hide the seams); then without the body.
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    i = panel.sample(time)
    vertices = scene.place(panel.mesh.vertices, panel.rotations[i], panel.centres[i])
    faces = vertices[panel.mesh.triangles]
    normals = np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    front = normals @ panel.eye > 0.0
    ambient = animate_module._AMBIENT
    light = ambient + (1 - ambient) * np.clip(normals[front] @ animate_module._LIGHT, 0, None)
    shade = np.clip(light[:, None] * animate_module._BODY_COLOUR, 0.0, 1.0)
    body = Poly3DCollection(faces[front], facecolor=shade, edgecolor=shade, lw=0.3, zorder=3)
    panel.ax.add_collection3d(body)
    contacts = panel.contacts[: i + 1]
    panel.trail.set_data_3d(contacts[:, 0], contacts[:, 1], np.zeros(i + 1))
    panel.body.set_visible(False)
    drawn = []
    for shown in (True, False):
        body.set_visible(shown)
        figure.canvas.draw()
        drawn.append(np.asarray(figure.canvas.buffer_rgba())[..., :3].astype(int))
    body.remove()
    panel.body.set_visible(True)
    return drawn[0], drawn[1]


def test_a_blitted_frame_matches_the_scene_drawn_whole(
    rolling_runs: dict[str, xr.Dataset], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A frame as the video draws it (the background restored, the trail grown piece by
    piece, the body's faces projected and drawn as one batch of flat triangles) is what
    matplotlib draws from scratch with its own 3-D artists: the two differ only along
    edges (the collection strokes each face), in a few of the body's pixels."""
    compared: list[tuple[int, int]] = []

    def compare(
        path: Path, suffix: str, frames: Iterator[np.ndarray], *args: Any, **kw: Any
    ) -> None:
        arguments = frames.gi_frame.f_locals  # type: ignore[attr-defined]
        figure, (panel,), plan = arguments["figure"], arguments["panels"], arguments["plan"]
        for index, frame in enumerate(frames):
            if index in (plan.count // 3, plan.count - 1):
                blitted = frame[..., :3].astype(int)
                whole, without_body = _drawn_whole(figure, panel, float(plan.times[index]))
                body = np.count_nonzero(np.abs(whole - without_body).max(axis=-1) > 64)
                differing = np.count_nonzero(np.abs(whole - blitted).max(axis=-1) > 64)
                compared.append((differing, body))
        path.write_bytes(b"")

    monkeypatch.setattr(animate_module, "_write", compare)
    # the rolling stone's contact wanders: its trail is long
    animate(rolling_runs["kane_levinson_1982"], tmp_path / "run.mp4", size=(640, 480))
    assert len(compared) == 2
    for differing, body in compared:
        assert body > 2000  # the body is drawn, a few thousand pixels
        assert differing < 0.05 * body


def _all_frames(
    dataset: xr.Dataset, path: Path, monkeypatch: pytest.MonkeyPatch
) -> list[np.ndarray]:
    """Every frame of a 640 x 480 video of ``dataset`` as drawn (before encoding)."""
    frames: list[np.ndarray] = []

    def keep(path: Path, suffix: str, drawn: Iterator[np.ndarray], *args: Any, **kw: Any) -> None:
        frames.extend(np.array(frame) for frame in drawn)
        path.write_bytes(b"")

    monkeypatch.setattr(animate_module, "_write", keep)
    animate(dataset, path, size=(640, 480))
    return frames


def test_reused_glyphs_draw_the_frames_that_matplotlib_draws(
    sliding_run: xr.Dataset, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The read-out's glyphs rasterised once each (``visual._glyphs``) give every frame
    to the bit as matplotlib's own renderer, which rasterises each glyph every time."""
    from matplotlib.backends.backend_agg import RendererAgg

    from celtstone.visual import _glyphs

    assert _glyphs.reuse_glyphs(RendererAgg(64, 64, 100.0)), (
        "this matplotlib no longer draws glyphs as visual._glyphs expects: videos are "
        "drawn without reusing glyphs (same frames, more CPU); update or remove _glyphs"
    )
    reused = _all_frames(sliding_run, tmp_path / "reused.mp4", monkeypatch)
    monkeypatch.setattr(animate_module, "reuse_glyphs", lambda renderer: False)
    drawn = _all_frames(sliding_run, tmp_path / "drawn.mp4", monkeypatch)
    assert len(reused) == len(drawn) == 61
    for frame, expected in zip(reused, drawn, strict=True):
        np.testing.assert_array_equal(frame, expected)
