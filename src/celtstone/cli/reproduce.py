"""``celtstone reproduce``: the paper's Figures 2 and 3, the friction threshold, a report."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from celtstone.reproduce.study import STUDIES, TARGETS, reduced, study_for


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone reproduce``."""
    parser.add_argument(
        "targets",
        nargs="*",
        default=["all"],
        metavar="TARGET",
        help=f"one or more of {', '.join(TARGETS)}, all (default: all)",
    )
    parser.add_argument("--out", default="results", help="output directory (default: results)")
    parser.add_argument(
        "--body",
        action="append",
        default=None,
        help="body to use (repeatable; default: "
        + ", ".join(s.body for s in STUDIES)
        + ") — shipped name or .toml path",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="shortened runs and a 6-point f grid: a smoke test, not the reproduction",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def handle(args: argparse.Namespace) -> int:
    """Run the targets; print where the report is."""
    from celtstone.reproduce.targets import reproduce

    studies = [study_for(name) for name in args.body] if args.body else list(STUDIES)
    for study in studies:
        study.load_body()  # an unknown body fails before any run
    if args.quick:
        studies = [reduced(study) for study in studies]
    show = not args.no_progress and sys.stderr.isatty()
    report = reproduce(args.targets, Path(args.out), studies, progress=show)
    print(f"report: {report}")
    return 0
