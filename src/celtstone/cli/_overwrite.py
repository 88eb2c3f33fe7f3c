"""The ``--overwrite`` option, said once for every command that writes."""

from __future__ import annotations

import argparse


def add_overwrite_arg(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--overwrite``: replace ``what`` only where celtstone wrote it.

    A file is replaced only if it carries celtstone's mark, a folder or store only if its
    manifest lists every file in it; anything else there is refused, with or without the
    option (``celtstone.files.ownership``)."""
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help=f"replace {what} if celtstone wrote it (its mark); never a file it did not write",
    )
