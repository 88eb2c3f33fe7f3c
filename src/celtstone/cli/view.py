"""``celtstone view RUN.nc --out run.html``: one self-contained interactive page."""

from __future__ import annotations

import argparse

from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.visual import load_run, write_viewer
from celtstone.visual.viewer import check_page_target


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone view``."""
    parser.add_argument("run", metavar="RUN.nc", help="a run saved by `celtstone run --out`")
    parser.add_argument("--out", required=True, metavar="FILE.html", help="the page")
    add_overwrite_arg(parser, "the page")


def handle(args: argparse.Namespace) -> int:
    """Write the page and say how big it is."""
    check_page_target(args.out, overwrite=args.overwrite)
    info = write_viewer(load_run(args.run), args.out, overwrite=args.overwrite)
    print(
        f"wrote {info.path}: {info.frames} frames, {info.plot_points} points per plot, "
        f"{info.bytes / 1e6:.2f} MB; open it in a browser (works offline)"
    )
    return 0
