"""``celtstone export RUN.nc --csv``: a saved run as CSV, one column per component."""

from __future__ import annotations

import argparse
from pathlib import Path

from celtstone.errors import ParameterError
from celtstone.export import read_run, write

HELP = "convert a saved run (RUN.nc) to CSV"


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone export``."""
    parser.add_argument("run", metavar="RUN.nc", help="a run saved by `celtstone run --out`")
    parser.add_argument("--csv", action="store_true", help="write CSV (the one format so far)")
    parser.add_argument("--out", default=None, metavar="FILE.csv", help="default: RUN.csv")


def handle(args: argparse.Namespace) -> int:
    """Write the CSV whole or not at all."""
    if not args.csv:
        raise ParameterError("format", "none", "--csv")
    target = Path(args.out) if args.out else Path(args.run).with_suffix(".csv")
    if target.suffix.lower() != ".csv":
        raise ParameterError("out", str(target), "a file name ending in .csv")
    print(f"csv: {write(read_run(args.run), target)}")
    return 0
