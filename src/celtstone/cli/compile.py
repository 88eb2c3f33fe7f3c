"""``celtstone compile``: compile the solvers into numba's on-disk cache now.

About a minute of one core once per install (``celtstone.compile_solvers``), before a
batch of parallel jobs that would otherwise each compile the same drivers at once; a
progress bar on standard error while it compiles.
"""

from __future__ import annotations

import argparse
import json
import sys

from celtstone import compile_solvers


def add_args(parser: argparse.ArgumentParser) -> None:
    """Options of ``celtstone compile``."""
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def handle(args: argparse.Namespace) -> int:
    """Compile (or load from the cache) every driver; say which and how long it took."""
    from tqdm import tqdm

    with tqdm(total=1, desc="compile", unit=" run", file=sys.stderr, delay=1.0) as bar:

        def progress(done: int, total: int, label: str) -> None:
            bar.total = total
            bar.n = done
            bar.set_postfix_str(label, refresh=False)
            bar.refresh()

        report = compile_solvers(progress)
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
