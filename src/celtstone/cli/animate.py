"""``celtstone animate RUN.nc --out run.mp4|run.gif``: the run in 3-D as a video."""

from __future__ import annotations

import argparse

from celtstone import ParameterError
from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.cli._progress import progress_bar
from celtstone.visual import VIDEO_FPS_LIMITS, VIDEO_FRAME_LIMITS, animate, load_run
from celtstone.visual.animation import check_video_target

# frames from which the command says what it does when not at a terminal (several
# seconds of drawing)
ANNOUNCED_FRAME_COUNT = 300


def _size(text: str) -> tuple[int, int]:
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise ParameterError("size", text, "WIDTHxHEIGHT in pixels, e.g. 768x576") from None
    if not (16 <= width <= 4096 and 16 <= height <= 4096):
        raise ParameterError("size", text, "WIDTHxHEIGHT, each in [16, 4096] pixels")
    return width, height


def _float(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ParameterError(name, text, "a number > 0") from None


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone animate``."""
    mp4, gif = (
        f"{VIDEO_FPS_LIMITS[s]:g} fps, {VIDEO_FRAME_LIMITS[s]} frames" for s in (".mp4", ".gif")
    )
    parser.add_argument("run", metavar="RUN.nc", help="a run saved by `celtstone run --out`")
    parser.add_argument("--out", required=True, metavar="FILE.mp4|FILE.gif", help="the video")
    add_overwrite_arg(parser, "the video")
    parser.add_argument(
        "--speed",
        default="1",
        help="simulated seconds per second of playback (1 = real time; 0.1 = slow motion)",
    )
    parser.add_argument(
        "--fps", default=None, help=f"frames per second (at most: mp4 {mp4}; gif {gif})"
    )
    parser.add_argument("--size", default=None, metavar="WxH", help="pixels (mp4: multiples of 16)")
    parser.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (at a terminal, shown once the frames take over a second)",
    )


def handle(args: argparse.Namespace) -> int:
    """Write the video and say how many frames at which rate."""
    check_video_target(args.out, overwrite=args.overwrite)
    speed = _float("speed", args.speed)
    fps = _float("fps", args.fps) if args.fps is not None else None
    size = _size(args.size) if args.size is not None else None
    run = load_run(args.run)
    with progress_bar(
        "animate",
        "frame",
        enabled=not args.no_progress,
        announcement=f"drawing {{total}} frames into {args.out}",
        announce_from=ANNOUNCED_FRAME_COUNT,
    ) as progress:
        info = animate(
            run, args.out, speed=speed, fps=fps, size=size, overwrite=args.overwrite,
            progress=progress,
        )  # fmt: skip
    pace = "real time" if info.speed == 1.0 else f"{info.speed:.3g} × real time"
    print(
        f"wrote {info.path}: {info.frames} frames at {info.fps:.3g} fps ({pace}), "
        f"{info.size[0]}x{info.size[1]} px, {info.bytes / 1e6:.2f} MB"
    )
    return 0
