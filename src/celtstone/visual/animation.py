"""3-D animation of runs: matplotlib (Agg) frames, encoded by ffmpeg or imageio.

A frame redraws only what moves on the static scene (blitting), the read-out's glyphs
rasterised once each (``_glyphs``). mp4: the canvas's raw RGBA frames go through one
pipe into the ffmpeg binary bundled by imageio-ffmpeg (H.264, yuv420p); gif: imageio's
pillow plugin. No system ffmpeg is needed. Files are
written whole or not at all (``export.atomic_path``).
"""

from __future__ import annotations

import contextlib
import errno
import io
import itertools
import math
import os
import re
import subprocess
import tempfile
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone._held_signals import held_signals
from celtstone.errors import OutputError, ParameterError
from celtstone.files.export import atomic_path, check_target
from celtstone.files.ownership import video_mark
from celtstone.visual import scene
from celtstone.visual._glyphs import reuse_glyphs
from celtstone.visual.frames import (
    VIDEO_FPS_LIMITS,
    VIDEO_FRAME_LIMITS,
    VIDEO_TICKS,
    FramePlan,
    nearest_samples,
    plan_frames,
)
from celtstone.visual.runs import check_run, default_label

if TYPE_CHECKING:
    import xarray as xr


__all__ = [
    "VIDEO_FORMATS",
    "VIDEO_SIZES",
    "VideoInfo",
    "animate",
    "animate_comparison",
    "check_video_target",
]

VIDEO_FORMATS = (".mp4", ".gif")
# pixel size (width, height) of one panel; panels sit side by side.
# mp4 sizes are multiples of 16 (H.264 macro blocks).
VIDEO_SIZES = {".mp4": (768, 576), ".gif": (480, 360)}
_PANEL_WIDTH_COMPARISON = {".mp4": 640, ".gif": 400}
_DPI = 100.0
_BODY_COLOUR = np.array([0.56, 0.60, 0.70])
_LIGHT = np.array([-0.35, -0.55, 1.0]) / np.linalg.norm([-0.35, -0.55, 1.0])
_AMBIENT = 0.3
_ELEVATION, _AZIMUTH = 24.0, -58.0  # camera [deg]
# raw frames ffmpeg reads, by colour channels: the canvas's RGBA goes in as it is
_PIXEL_FORMATS = {3: "rgb24", 4: "rgba"}
# FreeType's hinting of each glyph is half the cost of the read-out drawn every frame;
# unhinted glyphs at the video's 8-10 pt read as well
_TEXT_HINTING = "no_hinting"
# x264's veryfast preset at crf 22 keeps the picture of its default (medium) at crf 25,
# frame by frame (SSIM to the drawn frames 0.992 both, worst frame 0.990), at about half
# the encoder's CPU, for a file about a third larger
_MP4_PRESET = "veryfast"
_MP4_CRF = 22


@dataclass(frozen=True)
class VideoInfo:
    """What was written.

    Parameters
    ----------
    path : pathlib.Path
        The video file.
    frames : int
        Number of frames.
    fps : float
        Frames per second of playback [1/s].
    speed : float
        Simulated seconds per second of playback.
    size : tuple of int
        (width, height) [px].
    bytes : int
        The file's size [bytes].
    """

    path: Path
    frames: int
    fps: float
    speed: float
    size: tuple[int, int]
    bytes: int


def check_video_target(path: str | Path, *, overwrite: bool = False) -> Path:
    """``path`` if it ends in .mp4 or .gif, its directory exists and it is not in use
    (unless ``overwrite``; never a directory), else ParameterError."""
    return check_target(path, VIDEO_FORMATS, overwrite=overwrite)


class _Panel:
    """One body on its plane in one 3-D axes, updated frame by frame."""

    def __init__(
        self, figure: Any, position: int, count: int, dataset: xr.Dataset, label: str, font: float
    ):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        from celtstone.visual.shading import FlatShadedTriangles

        self.dataset = dataset
        self.geometry = scene.body_geometry(dataset)
        self.mesh = scene.surface_mesh(self.geometry, along=40, around=24)
        self.marks = scene.axis_marks(self.geometry)
        self.times = np.asarray(dataset["time"].values, dtype=float)
        self.rotations = scene.rotation_matrices(dataset["quaternion"].values)
        self.centres = scene.centre_positions(dataset)
        self.contacts = np.asarray(dataset["contact_position"].values, dtype=float)
        self.is_sliding = dataset.attrs.get("model") == "sliding"
        # the read-out's series as arrays, read once (an xarray lookup per frame costs more
        # than the numbers it gives)
        self.readout_series = {
            name: np.asarray(dataset[name].values, dtype=float)
            for name in ("spin", "tilt", *(("slip_speed",) if self.is_sliding else ()))
        }
        ax = figure.add_subplot(1, count, position + 1, projection="3d", computed_zorder=False)
        self.ax = ax
        self._limits()
        self._plane(Poly3DCollection)
        ax.plot(*self._track(self.contacts), color="0.75", lw=0.8, zorder=1)
        # drawn piece by piece onto the background as the frames go (``grow_trail``)
        (self.trail,) = ax.plot([], [], [], color="tab:red", lw=1.2, zorder=2)
        self.trail_end = 0  # the last sample of the trail on the background
        self.body = FlatShadedTriangles(ax, zorder=3)
        self.long_axis = _projected_line(ax, color="black", lw=1.8, zorder=4)
        self.principal = _projected_line(ax, color="tab:orange", lw=1.2, ls="--", zorder=4)
        self.contact = _projected_line(ax, marker="o", ls="", color="tab:red", ms=4, zorder=5)
        ax.set_title(label, fontsize=font + 1 if font > 8.0 else font)  # a gif: 360 px tall
        self.readout = ax.text2D(0.03, 0.03, "", transform=ax.transAxes, fontsize=font)
        # what changes from frame to frame, in drawing order
        self.moving = [
            self.body,
            self.long_axis,
            self.principal,
            self.contact,
            self.readout,
        ]
        self._legend(font)

    def _legend(self, font: float) -> None:
        """The key to the lines, at the reader's font size, in the panel's top left corner
        (the body is drawn at the centre)."""
        from matplotlib.lines import Line2D

        delta = math.degrees(self.geometry.misalignment_angle)
        keys = [
            (self.long_axis, "long axis"),
            (self.principal, f"principal axis (δ = {delta:.2f}°)"),
            (self.trail, "contact track"),
        ]
        handles = [
            Line2D([], [], color=line.get_color(), linestyle=line.get_linestyle(), label=label)
            for line, label in keys
        ]
        self.ax.legend(
            handles=handles,
            loc="upper left",
            bbox_to_anchor=(0.0, 0.95),
            fontsize=font,
            frameon=False,
            handlelength=1.8,
            borderaxespad=0.2,
            labelspacing=0.25,
        )

    @staticmethod
    def _track(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return points[:, 0], points[:, 1], np.zeros(points.shape[0])

    def _limits(self) -> None:
        centre, reach, top = scene.extent(
            self.geometry, self.mesh, self.rotations, self.centres, self.contacts
        )
        self.centre, self.reach, self.top = centre, reach, top
        ax = self.ax
        ax.set_xlim(centre[0] - reach, centre[0] + reach)
        ax.set_ylim(centre[1] - reach, centre[1] + reach)
        ax.set_zlim(0.0, self.top)
        ax.set_box_aspect((2 * reach, 2 * reach, self.top), zoom=1.8)
        ax.view_init(elev=_ELEVATION, azim=_AZIMUTH)
        elevation, azimuth = math.radians(_ELEVATION), math.radians(_AZIMUTH)
        # towards the camera; the box aspect equals the data ranges, so the scale is equal
        self.eye = np.array(
            [
                math.cos(elevation) * math.cos(azimuth),
                math.cos(elevation) * math.sin(azimuth),
                math.sin(elevation),
            ]
        )
        ax.set_axis_off()

    def _plane(self, poly3d: Any) -> None:
        (x0, x1), (y0, y1) = self.ax.get_xlim(), self.ax.get_ylim()
        square = [[(x0, y0, 0.0), (x1, y0, 0.0), (x1, y1, 0.0), (x0, y1, 0.0)]]
        self.ax.add_collection3d(poly3d(square, facecolor="0.93", edgecolor="0.7", zorder=0))
        spacing = _grid_spacing(x1 - x0)
        for x in np.arange(math.ceil(x0 / spacing), math.floor(x1 / spacing) + 1) * spacing:
            self.ax.plot([x, x], [y0, y1], [0, 0], color="0.85", lw=0.5, zorder=0.5)
        for y in np.arange(math.ceil(y0 / spacing), math.floor(y1 / spacing) + 1) * spacing:
            self.ax.plot([x0, x1], [y, y], [0, 0], color="0.85", lw=0.5, zorder=0.5)

    def sample(self, time: float) -> int:
        """Index of the sample nearest ``time`` [s]."""
        return int(nearest_samples(self.times, np.array([time]))[0])

    def grow_trail(self, i: int) -> bool:
        """Draw the contact track from the last sample drawn to sample ``i``; True if it
        grew.

        The trail only grows, so each piece is drawn once onto the background rather than
        the whole track every frame (its cost would grow with the run)."""
        if i <= self.trail_end:
            return False
        self.trail.set_data_3d(*self._track(self.contacts[self.trail_end : i + 1]))
        self.ax.draw_artist(self.trail)
        self.trail_end = i
        return True

    def show(self, i: int, speed: float) -> None:
        """Set the moving artists to sample ``i`` (once the figure has been drawn: the
        camera is the axes' projection)."""
        rotation, centre = self.rotations[i], self.centres[i]
        vertices = scene.place(self.mesh.vertices, rotation, centre)
        faces = vertices[self.mesh.triangles]
        normals = np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0])
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        front = normals @ self.eye > 0.0  # the body is convex: back faces are hidden
        light = _AMBIENT + (1 - _AMBIENT) * np.clip(normals[front] @ _LIGHT, 0.0, None)
        colours = np.clip(light[:, None] * _BODY_COLOUR, 0.0, 1.0)
        self.body.set_faces(vertices, self.mesh.triangles[front], colours)
        for line, name in ((self.long_axis, "long_axis"), (self.principal, "principal_axis")):
            points = scene.place(self.marks[name], rotation, centre)
            _set_projected(line, points[:, 0], points[:, 1], points[:, 2])
        x, y = self.contacts[i]
        _set_projected(self.contact, np.array([x]), np.array([y]), np.zeros(1))
        series = self.readout_series
        lines = [
            f"t = {self.times[i]:.2f} s"
            + ("" if speed == 1.0 else f"  (playback {speed:.3g} × real time)"),
            f"spin = {float(series['spin'][i]):+.2f} rad/s"
            f"  tilt = {math.degrees(float(series['tilt'][i])):.2f}°",
        ]
        if self.is_sliding:
            lines.append(f"slip speed = {1e3 * float(series['slip_speed'][i]):.2f} mm/s")
        text = "\n".join(lines)
        self.readout.set_text(text)


def _projected_line(ax: Any, **style: Any) -> Any:
    """An empty 2-D line of the 3-D axes ``ax``, for :func:`_set_projected`: what
    ``ax.plot(x, y, z)`` draws, without re-projecting through masked arrays each frame."""
    from matplotlib.lines import Line2D

    line = Line2D([], [], **style)
    ax.add_line(line)
    return line


def _set_projected(line: Any, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> None:
    """Set ``line`` (:func:`_projected_line`) to the points (x, y, z) [m] as the axes'
    camera sees them (``proj3d.proj_transform`` by the projection set when the figure was
    drawn), a point out of the perspective's view hidden, as a 3-D line hides it."""
    from mpl_toolkits.mplot3d import proj3d

    ax = line.axes
    px, py, pz = proj3d.proj_transform(x, y, z, ax.M)
    hidden = ~((px >= -1.0) & (px <= 1.0) & (py >= -1.0) & (py <= 1.0) & (pz <= 0.0))
    if hidden.any():
        px, py = np.where(hidden, np.nan, px), np.where(hidden, np.nan, py)
    line.set_data(px, py)


def _grid_spacing(width: float) -> float:
    """A round grid spacing (1, 2 or 5 × 10^k m) giving about 8 lines across ``width``."""
    raw = width / 8.0
    power = 10.0 ** math.floor(math.log10(raw))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= raw)


def _frames(
    figure: Any,
    panels: list[_Panel],
    plan: FramePlan,
    progress: Callable[[int, int], None] | None = None,
) -> Iterator[np.ndarray]:
    """RGBA frames; the static scene (plane, grid, whole track, titles) is drawn once.

    Each frame restores that background and draws only the moving artists on it, in
    their z-order (blitting); the contact trail, which only grows, is added to the
    background piece by piece. A frame is the canvas's own buffer (height, width, 4):
    use it before asking for the next. ``progress(frames drawn, frames in all)`` is
    called after each.
    """
    canvas = figure.canvas
    for panel in panels:
        for artist in panel.moving:
            artist.set_visible(False)
    canvas.draw()
    background = canvas.copy_from_bbox(figure.bbox)
    reuse_glyphs(canvas.get_renderer())  # the read-outs' glyphs, rasterised once each
    for panel in panels:
        for artist in panel.moving:
            artist.set_visible(True)
    for index, time in enumerate(plan.times):
        canvas.restore_region(background)
        samples = [panel.sample(float(time)) for panel in panels]
        grown = [panel.grow_trail(i) for panel, i in zip(panels, samples, strict=True)]
        if any(grown):
            background = canvas.copy_from_bbox(figure.bbox)
        for panel, i in zip(panels, samples, strict=True):
            panel.show(i, plan.speed)
            for artist in panel.moving:
                if hasattr(artist, "do_3d_projection"):
                    artist.do_3d_projection()
                panel.ax.draw_artist(artist)
        yield np.asarray(canvas.buffer_rgba())
        if progress is not None:
            progress(index + 1, plan.count)


def _write(
    path: Path, suffix: str, frames: Iterator[np.ndarray], fps: float, *, overwrite: bool = False
) -> None:
    """Encode ``frames`` to ``path`` whole or not at all; a failure raises OutputError."""
    with atomic_path(path, overwrite=overwrite) as temporary:
        if suffix == ".mp4":
            _write_mp4(temporary, path, frames, fps)
        else:
            _write_gif(temporary, frames, fps)


def _write_gif(temporary: Path, frames: Iterator[np.ndarray], fps: float) -> None:
    """Encode in memory, then write the bytes: a write error is one plain OSError (the
    encoder never meets it, so nothing is left to fail again when it is collected)."""
    import imageio.v3 as iio

    opener: Any = iio.imopen  # plugin-specific keywords are beyond imageio's type stubs
    buffer = io.BytesIO()
    duration_ms = 1000.0 / fps
    with opener(buffer, "w", extension=".gif", plugin="pillow") as file:
        for frame in frames:
            rgb = np.ascontiguousarray(frame[..., :3])  # a copy: the canvas draws on
            # the comment marks the file as celtstone's: --overwrite may replace it later
            file.write(rgb, duration=duration_ms, loop=0, is_batch=False, comment=video_mark())
    temporary.write_bytes(buffer.getvalue())


def _ffmpeg_cause(log: bytes, status: int) -> str:
    """Why ffmpeg failed, in a few words, from its error log."""
    text = log.decode("utf-8", errors="replace")
    if "No space left on device" in text:
        return os.strerror(errno.ENOSPC)
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    detail = lines[-1][:200] if lines else f"exit status {status}"
    return f"ffmpeg failed: {detail}"


def _write_mp4(temporary: Path, target: Path, frames: Iterator[np.ndarray], fps: float) -> None:
    """H.264 (yuv420p) by the ffmpeg bundled with imageio-ffmpeg, checked before it is kept.

    ffmpeg reports a failed write (e.g. "Error writing trailer: No space left on
    device") only in its log and exit status: both are read, and the finished file
    must read back with every frame, or :class:`OutputError` is raised.
    """
    import imageio_ffmpeg

    first = next(frames)
    height, width, channels = first.shape
    command = [
        imageio_ffmpeg.get_ffmpeg_exe(),
        "-nostdin",
        "-y",
        "-v",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        _PIXEL_FORMATS[channels],
        "-s",
        f"{width}x{height}",
        "-r",
        str(Fraction(fps).limit_denominator()),
        "-i",
        "-",
        "-an",
        "-vcodec",
        "libx264",
        "-pix_fmt",
        "yuv420p",
        "-preset",
        _MP4_PRESET,
        "-crf",
        str(_MP4_CRF),
        "-metadata",  # marks the file as celtstone's: --overwrite may replace it later
        f"comment={video_mark().decode()}",
        "-f",
        "mp4",
        str(temporary),
    ]
    count = 0
    with tempfile.TemporaryFile() as log:
        process: subprocess.Popen[bytes] | None = None
        try:
            # a signal while ffmpeg starts is raised once it is held here, to be stopped
            # below: landing inside Popen it left an ffmpeg that made the temporary again
            # after the clean-up; its own session: Ctrl-C reaches celtstone, which stops it
            with held_signals():
                process = subprocess.Popen(
                    command,
                    stdin=subprocess.PIPE,
                    stdout=subprocess.DEVNULL,
                    stderr=log,
                    start_new_session=True,
                )
            stdin = process.stdin
            assert stdin is not None
            try:
                for frame in itertools.chain([first], frames):
                    # the frame's own memory: no copy on the way into the pipe
                    stdin.write(np.ascontiguousarray(frame, dtype=np.uint8).data)
                    count += 1
                stdin.close()
            except BrokenPipeError:
                pass  # ffmpeg stopped early: its status and log say why
        except BaseException:
            if process is not None:
                process.kill()  # interrupted or failed: no ffmpeg left writing the temporary
            raise
        finally:
            if process is not None:
                with contextlib.suppress(OSError):  # data left in the pipe's buffer is dropped
                    if process.stdin is not None:
                        process.stdin.close()
                process.wait()
        status = process.returncode
        if status != 0:
            log.seek(0)
            raise OutputError(str(target), _ffmpeg_cause(log.read(), status))
    frames_read = _count_frames(temporary)
    if frames_read != count:
        raise OutputError(
            str(target),
            f"the encoded video reads back with {frames_read} of its {count} frames",
        )


def _count_frames(path: Path) -> int:
    """Frames of the first video stream of ``path``, read by ffmpeg without decoding;
    -1 if ffmpeg cannot read the file."""
    import imageio_ffmpeg

    command = [
        imageio_ffmpeg.get_ffmpeg_exe(),
        "-nostdin",
        "-v",
        "error",
        "-nostats",
        "-i",
        str(path),
        "-map",
        "0:v:0",
        "-c",
        "copy",
        "-f",
        "null",
        "-progress",
        "pipe:1",
        "-",
    ]
    result = subprocess.run(command, capture_output=True, check=False)
    counts = re.findall(rb"^frame=(\d+)", result.stdout, flags=re.MULTILINE)
    if result.returncode != 0 or not counts:
        return -1
    return int(counts[-1])


def animate_comparison(
    datasets: Sequence[xr.Dataset],
    labels: Sequence[str],
    path: str | Path,
    *,
    speed: float = 1.0,
    fps: float | None = None,
    size: tuple[int, int] | None = None,
    overwrite: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> VideoInfo:
    """Animate runs side by side on a common clock (e.g. rolling beside sliding, Figure 2).

    Parameters
    ----------
    datasets : sequence of xarray.Dataset
        The runs (``Trajectory.dataset`` or files read by :func:`load_run`).
    labels : sequence of str
        One panel title per run.
    path : str or pathlib.Path
        Output file, .mp4 or .gif.
    speed : float, optional
        Simulated seconds per second of playback (1 = real time), > 0.
    fps : float, optional
        Frames per second of playback, in (0, 30] for mp4 (default 30), (0, 20] for gif
        (default 20; rounded down to a whole-centisecond delay).
    size : tuple of int, optional
        (width, height) [px] of the whole video; default 768 × 576 for one run
        (480 × 360 for gif), 640 (400) px wide per panel for several.
    overwrite : bool, optional
        Replace ``path`` if it is a file (never a directory); without it an existing
        ``path`` is refused before any frame is drawn.
    progress : callable, optional
        Called with (frames drawn, frames in all) as the frames are drawn (a progress bar).

    Returns
    -------
    VideoInfo
        The frame count and rate actually used: see ``frames`` for the caps.

    Notes
    -----
    The clock runs over the shortest run; each panel shows its sample nearest to
    the frame's time.
    """
    target = check_video_target(path, overwrite=overwrite)
    suffix = target.suffix.lower()
    if len(datasets) == 0 or len(datasets) != len(labels):
        raise ParameterError("labels", list(labels), "one label per dataset, at least one")
    runs = [check_run(ds, "datasets") for ds in datasets]
    clock = min(runs, key=lambda ds: float(ds["time"].values[-1] - ds["time"].values[0]))
    plan = plan_frames(
        clock["time"].values,
        max_frames=VIDEO_FRAME_LIMITS[suffix],
        speed=speed,
        fps=VIDEO_FPS_LIMITS[suffix] if fps is None else fps,
        max_fps=VIDEO_FPS_LIMITS[suffix],
        tick=VIDEO_TICKS[suffix],
    )
    width, height = size if size is not None else _default_size(suffix, len(runs))
    if suffix == ".mp4" and (width % 16 or height % 16):
        raise ParameterError("size", (width, height), "multiples of 16 pixels for mp4")
    if progress is not None:  # before matplotlib's import and the first frame: a second
        progress(0, plan.count)

    from matplotlib import rc_context
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI)
    figure.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.95, wspace=0.0)
    font = 9.0 if width / len(runs) >= 600 else 8.0  # [pt]; 8 pt is 11 px at 100 dpi
    panels = [
        _Panel(figure, i, len(runs), ds, label, font)
        for i, (ds, label) in enumerate(zip(runs, labels, strict=True))
    ]
    FigureCanvasAgg(figure)
    frames = _frames(figure, panels, plan, progress)
    with rc_context({"text.hinting": _TEXT_HINTING}):  # read as the text is drawn, in _write
        _write(target, suffix, frames, plan.fps, overwrite=overwrite)
    return VideoInfo(
        path=target,
        frames=plan.count,
        fps=plan.fps,
        speed=plan.speed,
        size=(width, height),
        bytes=target.stat().st_size,
    )


def _default_size(suffix: str, panels: int) -> tuple[int, int]:
    width, height = VIDEO_SIZES[suffix]
    if panels > 1:
        width = panels * _PANEL_WIDTH_COMPARISON[suffix]
    return width, height


def animate(
    dataset: xr.Dataset,
    path: str | Path,
    *,
    speed: float = 1.0,
    fps: float | None = None,
    size: tuple[int, int] | None = None,
    label: str | None = None,
    overwrite: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> VideoInfo:
    """Animate one run in 3-D: shaded body, plane, contact track and read-out.

    Parameters
    ----------
    dataset : xarray.Dataset
        The run (``Trajectory.dataset`` or a file read by :func:`load_run`).
    path : str or pathlib.Path
        Output file, .mp4 or .gif.
    speed : float, optional
        Simulated seconds per second of playback (1 = real time), > 0.
    fps : float, optional
        Frames per second of playback, as in :func:`animate_comparison`.
    size : tuple of int, optional
        (width, height) [px]; default 768 × 576 (480 × 360 for gif).
    label : str, optional
        The title; default the model and body of the run.
    overwrite : bool, optional
        Replace ``path`` if it is a file (never a directory).
    progress : callable, optional
        Called with (frames drawn, frames in all) as the frames are drawn (a progress bar).

    Returns
    -------
    VideoInfo
        The frame count and rate actually used.
    """
    title = label if label is not None else default_label(dataset)
    return animate_comparison(
        [dataset],
        [title],
        path,
        speed=speed,
        fps=fps,
        size=size,
        overwrite=overwrite,
        progress=progress,
    )
