"""``celtstone plot RUN.nc``: spin, tilt, energy, slip, normal force and contact track."""

from __future__ import annotations

import argparse

from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.files.export import output_beside
from celtstone.plotting.save import check_figure_target
from celtstone.simulation.schema import check, parse_number


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone plot``."""
    parser.add_argument("run", metavar="RUN.nc", help="a run saved by `celtstone run --out`")
    parser.add_argument(
        "--out", default=None, metavar="FILE.png|FILE.svg", help="figure file (default: RUN.png)"
    )
    add_overwrite_arg(parser, "the figure file")
    parser.add_argument(
        "--band",
        type=str,
        default=None,
        help="hysteresis band of a reversal [rad/s], > 0 (default: 4 %% of the initial spin)",
    )


def handle(args: argparse.Namespace) -> int:
    """Draw the run and write the figure."""
    from celtstone.plotting import plot_run, save_figure
    from celtstone.visual import load_run  # the one check of a run file for drawing

    out = args.out if args.out is not None else output_beside(args.run, ".png")
    target = check_figure_target(out, overwrite=args.overwrite)
    band = None if args.band is None else check("reversal_band", parse_number("band", args.band))
    figure = plot_run(load_run(args.run), threshold=band)
    print(f"figure: {save_figure(figure, target, overwrite=args.overwrite)}")
    return 0
