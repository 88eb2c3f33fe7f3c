"""``celtstone compile``: compile the solvers into numba's on-disk cache now.

About 3 minutes of one core once per install (``celtstone.compile_solvers``), before a
batch of parallel jobs that would otherwise each compile the same drivers at once.
"""

from __future__ import annotations

import argparse
import json

from celtstone import compile_solvers


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone compile``."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def handle(args: argparse.Namespace) -> int:
    """Compile (or load from the cache) every driver; say which and how long it took."""
    report = compile_solvers()
    if args.json:
        print(
            json.dumps(
                {
                    "compiled_functions": report.compiled_functions,
                    "seconds": round(report.seconds, 2),
                }
            )
        )
    elif report.compiled_functions:
        print(
            f"compiled {report.compiled_functions} functions into numba's cache"
            f" in {report.seconds:.1f} s"
        )
    else:
        print(f"already compiled: loaded from numba's cache in {report.seconds:.1f} s")
    return 0
