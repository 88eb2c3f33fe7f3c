"""``celtstone export RUN.nc --csv``: a saved run as CSV, one column per component."""

from __future__ import annotations

import argparse

from celtstone.cli._overwrite import add_overwrite_arg
from celtstone.errors import ParameterError
from celtstone.files.export import check_target, output_beside, read_run, write
from celtstone.files.ownership import check_inputs_outside


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone export``."""
    parser.add_argument("run", metavar="RUN.nc", help="a run saved by `celtstone run --out`")
    parser.add_argument("--csv", action="store_true", help="write CSV (the one format so far)")
    parser.add_argument("--out", default=None, metavar="FILE.csv", help="default: RUN.csv")
    add_overwrite_arg(parser, "the CSV")


def handle(args: argparse.Namespace) -> int:
    """Write the CSV whole or not at all."""
    if not args.csv:
        raise ParameterError("format", "none", "--csv")
    out = args.out if args.out is not None else output_beside(args.run, ".csv")
    check_inputs_outside(out, [args.run])  # RUN.nc is never its own output
    target = check_target(out, (".csv",), overwrite=args.overwrite)
    print(f"csv: {write(read_run(args.run), target, overwrite=args.overwrite)}")
    return 0
