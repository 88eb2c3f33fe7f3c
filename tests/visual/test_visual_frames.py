"""Frame decimation: counts and rates worked by hand from the stated caps."""

from __future__ import annotations

import numpy as np
import pytest

import celtstone as cs
from celtstone.visual.frames import (
    FPS_MIN,
    PAGE_FRAME_LIMIT,
    VIDEO_FPS_LIMITS,
    VIDEO_FRAME_LIMITS,
    VIDEO_TICKS,
    FramePlan,
    envelope,
    plan_frames,
)

MP4, GIF = VIDEO_FRAME_LIMITS[".mp4"], VIDEO_FRAME_LIMITS[".gif"]


def _samples(t_end: float, per_second: int = 200) -> np.ndarray:
    return np.linspace(0.0, t_end, round(t_end * per_second) + 1)


def test_real_time_at_30_fps() -> None:
    # 10 s at 30 fps: frames at 0, 1/30, ..., 10 s -> 301 frames
    plan = plan_frames(_samples(10.0), max_frames=MP4)
    assert (plan.count, plan.fps, plan.speed) == (301, 30.0, 1.0)
    # each frame shows the sample nearest k/30 s: within half the 1/200 s sample spacing
    assert np.max(np.abs(plan.times - np.arange(301) / 30)) <= 0.5 / 200 + 1e-12
    assert plan.times[-1] == 10.0


def test_slow_motion_and_fast_forward() -> None:
    assert plan_frames(_samples(10.0), max_frames=MP4, speed=0.5).count == 601
    assert plan_frames(_samples(10.0), max_frames=MP4, speed=4.0).count == 76  # 2.5 s x 30 + 1


def test_100_s_run_mp4_keeps_real_time_at_a_lower_rate() -> None:
    # 100 s at 30 fps would be 3001 frames > 1800: fps = 1799 / 100 s = 17.99
    plan = plan_frames(_samples(100.0), max_frames=MP4)
    assert plan.count == MP4
    assert plan.fps == pytest.approx(17.99)
    assert plan.speed == 1.0
    assert plan.times[-1] == pytest.approx(100.0, abs=0.01)


def _gif_plan(t_end: float) -> FramePlan:
    rate = VIDEO_FPS_LIMITS[".gif"]
    return plan_frames(
        _samples(t_end), max_frames=GIF, fps=rate, max_fps=rate, tick=VIDEO_TICKS[".gif"]
    )


def test_gif_at_20_fps_real_time() -> None:
    plan = _gif_plan(10.0)  # 10 s x 20 fps + 1
    assert (plan.count, plan.fps, plan.speed) == (201, 20.0, 1.0)


def test_gif_frame_delay_is_whole_centiseconds() -> None:
    # 20 s at 20 fps = 401 frames > 300: 299 / 20 s = 14.95 fps, a 66.9 ms delay,
    # rounded up to 70 ms (14.29 fps): floor(20 / 0.07) + 1 = 286 frames
    plan = _gif_plan(20.0)
    assert plan.fps == pytest.approx(1 / 0.07)
    assert plan.count == 286
    assert plan.speed == 1.0


def test_100_s_run_gif_plays_faster_than_real_time() -> None:
    # real time would need 299 / 100 s = 2.99 fps < FPS_MIN: 10 fps and
    # speed = 100 s / (299 / 10 fps) = 3.344
    plan = _gif_plan(100.0)
    assert plan.count == GIF
    assert plan.fps == FPS_MIN
    assert plan.speed == pytest.approx(100.0 / (299 / 10.0))


def test_page_frames_are_capped() -> None:
    assert plan_frames(_samples(10.0), max_frames=PAGE_FRAME_LIMIT).count == 301
    assert plan_frames(_samples(100.0), max_frames=PAGE_FRAME_LIMIT).count == PAGE_FRAME_LIMIT
    assert plan_frames(_samples(1000.0, 20), max_frames=PAGE_FRAME_LIMIT).count == 3000


def test_coarse_samples_repeat_rather_than_invent() -> None:
    times = np.linspace(0.0, 1.0, 3)  # samples every 0.5 s
    plan = plan_frames(times, max_frames=MP4)
    assert plan.count == 31
    assert set(plan.times) == {0.0, 0.5, 1.0}


@pytest.mark.parametrize(("name", "value"), [("speed", 0.0), ("speed", -1.0), ("fps", 31.0)])
def test_bad_playback_settings_are_refused(name: str, value: float) -> None:
    with pytest.raises(cs.ParameterError, match=name):
        plan_frames(_samples(1.0), max_frames=MP4, **{name: value})


def test_gif_rate_is_capped_at_20() -> None:
    with pytest.raises(cs.ParameterError, match="fps"):
        plan_frames(_samples(1.0), max_frames=GIF, fps=25.0, max_fps=VIDEO_FPS_LIMITS[".gif"])


def test_envelope_keeps_the_extremes_of_a_fast_oscillation() -> None:
    # 20 Hz oscillation (like the Kane & Levinson pitching, 17 Hz) with a slow amplitude
    t = np.linspace(0.0, 100.0, 20_001)
    amplitude = 1.0 + 0.5 * np.sin(2 * np.pi * t / 100.0)
    values = amplitude * np.cos(2 * np.pi * 20.0 * t)
    kept_t, kept_v = envelope(t, values, buckets=1000)
    assert kept_t.size <= 2000
    assert np.all(np.diff(kept_t) > 0)
    # every 0.1 s bucket holds two periods: its max and min are the amplitude's
    assert kept_v.max() == values.max() and kept_v.min() == values.min()
    upper = np.interp(t, kept_t[kept_v > 0], kept_v[kept_v > 0])
    assert np.max(np.abs(upper - amplitude)[500:-500]) < 0.02


def test_envelope_returns_short_series_whole() -> None:
    t = np.arange(5.0)
    kept_t, kept_v = envelope(t, t**2, buckets=10)
    np.testing.assert_array_equal(kept_t, t)
    np.testing.assert_array_equal(kept_v, t**2)
