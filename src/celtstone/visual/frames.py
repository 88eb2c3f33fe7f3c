"""Which samples become frames, and how long series are thinned for plots.

Limits (docs/benchmarks.md, "Videos and the viewer", measures them)
-------------------------------------------------------------------
Video: at most ``VIDEO_FPS_LIMITS`` frames per second of playback (30 for mp4,
20 for gif, whose frame delays are whole centiseconds) and at most
``VIDEO_FRAME_LIMITS`` frames (1800 for mp4, 300 for gif). Real time by default;
a run too long for the cap at real time plays at a lower frame rate, down to
``FPS_MIN`` = 10 fps, and beyond that faster than real time (the read-out says so).
Page: at most 30 frames per simulated second and at most ``PAGE_FRAME_LIMIT`` =
3000 frames; each plotted series keeps at most 2 × ``PLOT_BUCKETS`` points
(the minimum and maximum of each bucket, so fast oscillations keep their envelope).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from celtstone.errors import ParameterError

__all__ = [
    "FPS_MAX",
    "FPS_MIN",
    "PAGE_FRAME_LIMIT",
    "PLOT_BUCKETS",
    "VIDEO_FPS_LIMITS",
    "VIDEO_FRAME_LIMITS",
    "VIDEO_TICKS",
    "FramePlan",
    "envelope",
    "nearest_samples",
    "plan_frames",
]

FPS_MAX = 30.0
FPS_MIN = 10.0
VIDEO_FPS_LIMITS = {".mp4": FPS_MAX, ".gif": 20.0}
"""Video suffix -> most frames per second of playback (gif delays are whole centiseconds)."""
# frame delays a format can store [s]: gif counts in centiseconds
VIDEO_TICKS = {".mp4": 0.0, ".gif": 0.01}
VIDEO_FRAME_LIMITS = {".mp4": 1800, ".gif": 300}
"""Video suffix -> most frames of a video."""
PAGE_FRAME_LIMIT = 3000
"""Most frames of the interactive page (at most 30 per simulated second)."""
PLOT_BUCKETS = 1000
"""Buckets of a thinned plot series: each keeps its minimum and maximum (2 points)."""


@dataclass(frozen=True)
class FramePlan:
    """Frames of a playback.

    indices : sample index shown in each frame, shape (k,)
    times : simulated time of each frame [s], shape (k,)
    fps : frames per second of playback [1/s]
    speed : simulated seconds per second of playback [1]
    """

    indices: np.ndarray
    times: np.ndarray
    fps: float
    speed: float

    @property
    def count(self) -> int:
        """Number of frames."""
        return int(self.indices.size)


def _positive(name: str, value: float, upper: float = math.inf) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, f"a number in (0, {upper:g}]") from None
    if not (math.isfinite(number) and 0.0 < number <= upper):
        raise ParameterError(name, value, f"a number in (0, {upper:g}]")
    return number


def plan_frames(
    times: np.ndarray,
    *,
    max_frames: int,
    speed: float = 1.0,
    fps: float = FPS_MAX,
    max_fps: float = FPS_MAX,
    tick: float = 0.0,
) -> FramePlan:
    """Frames for playing samples at ``times`` [s] at ``speed`` × real time and ``fps``.

    Frames are equally spaced in simulated time, ``speed / fps`` apart, each showing
    the nearest sample. With more than ``max_frames`` frames the frame rate drops
    (real time kept) down to ``FPS_MIN``; below that, ``speed`` rises instead.
    ``fps`` may not exceed ``max_fps``. With ``tick`` > 0 [s] the frame delay is
    rounded up to a whole number of ticks (gif: 0.01 s).
    """
    speed = _positive("speed", speed, 1e6)
    fps = _positive("fps", fps, min(max_fps, FPS_MAX))
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or times.size == 0:
        raise ParameterError("run", "no samples", "a run with at least one time sample")
    span = float(times[-1] - times[0])
    if span <= 0.0:
        return FramePlan(np.array([0]), times[:1].copy(), fps, speed)
    if max_frames < 2:
        raise ParameterError("max_frames", max_frames, "an integer >= 2")
    playback = span / speed
    if math.floor(playback * fps) + 1 > max_frames:
        fps = (max_frames - 1) / playback
        if fps < FPS_MIN:
            fps = min(FPS_MIN, FPS_MAX)
            speed = span * fps / (max_frames - 1)
    if tick > 0.0:
        fps = 1.0 / (tick * math.ceil(round(1.0 / (fps * tick), 9)))
    step = speed / fps
    count = min(max_frames, math.floor(span / step * (1 + 1e-12)) + 1)
    nearest = nearest_samples(times, times[0] + step * np.arange(count))
    return FramePlan(nearest, times[nearest], fps, speed)


def nearest_samples(times: np.ndarray, wanted: np.ndarray) -> np.ndarray:
    """Index of the sample of increasing ``times`` nearest each of ``wanted`` [s]."""
    times = np.asarray(times, dtype=float)
    wanted = np.asarray(wanted, dtype=float)
    if times.size == 1:
        return np.zeros(wanted.shape, dtype=np.int64)
    right = np.clip(np.searchsorted(times, wanted), 1, times.size - 1)
    left = right - 1
    return np.where(wanted - times[left] <= times[right] - wanted, left, right).astype(np.int64)


def envelope(
    times: np.ndarray, values: np.ndarray, buckets: int = PLOT_BUCKETS
) -> tuple[np.ndarray, np.ndarray]:
    """At most 2 × ``buckets`` points of a series that keep its envelope.

    The samples are split into ``buckets`` runs of consecutive samples; each run
    keeps its minimum and its maximum, in time order. Shorter series are returned
    whole. NaN samples are dropped.
    """
    times = np.asarray(times, dtype=float)
    values = np.asarray(values, dtype=float)
    finite = np.isfinite(values)
    times, values = times[finite], values[finite]
    if values.size <= 2 * buckets:
        return times, values
    edges = np.linspace(0, values.size, buckets + 1).astype(int)
    keep = []
    for start, stop in itertools.pairwise(edges):
        chunk = values[start:stop]
        pair = sorted({start + int(np.argmin(chunk)), start + int(np.argmax(chunk))})
        keep.extend(pair)
    index = np.asarray(keep)
    return times[index], values[index]
