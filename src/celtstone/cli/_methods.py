"""The integrator options that ``run`` and ``sweep`` share: ``--method`` and ``--stick-method``,
their names and words from the method registry (``solvers.METHOD_ENTRIES``)."""

from __future__ import annotations

import argparse

from celtstone.simulation.integrate import STICK_METHOD, method_words
from celtstone.simulation.models import RollingModel, SlidingModel


def _choices() -> str:
    return "; ".join(f"{name}: {words}" for name, words in method_words().items())


def add_method_args(parser: argparse.ArgumentParser, hybrid_words: str) -> None:
    """Add ``--method`` and ``--stick-method`` to ``parser``; ``hybrid_words`` says how
    the command chooses the stick–slip contact (empty where it is the default)."""
    parser.add_argument(
        "--method",
        default=None,
        help=f"the integrator ({_choices()}); default: {RollingModel.default_method} "
        f"rolling, {SlidingModel.default_method} sliding",
    )
    parser.add_argument(
        "--stick-method",
        default=None,
        help=f"the integrator of the stick–slip contact's stick phases{hybrid_words}: "
        f"{', '.join(method_words())} (default: --method if given, else {STICK_METHOD})",
    )
