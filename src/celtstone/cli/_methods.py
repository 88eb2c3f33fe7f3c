"""The integrator options that ``run`` and ``sweep`` share: ``--method`` and ``--stick-method``."""

from __future__ import annotations

import argparse


def add_method_args(parser: argparse.ArgumentParser, hybrid_words: str) -> None:
    """Add ``--method`` and ``--stick-method`` to ``parser``; ``hybrid_words`` says how
    the command chooses the stick–slip contact (empty where it is the default)."""
    parser.add_argument(
        "--method",
        default=None,
        help="vern9, dop853, radau5 or auto (default: vern9 rolling, auto sliding)",
    )
    parser.add_argument(
        "--stick-method",
        default=None,
        help=f"the integrator of the stick–slip contact's stick phases{hybrid_words}: "
        "vern9, dop853, radau5 or auto (default: --method if given, else dop853)",
    )
