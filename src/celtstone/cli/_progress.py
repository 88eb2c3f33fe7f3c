"""Progress of a long command on standard error: a bar at a terminal, one line elsewhere."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["Progress", "progress_bar"]

Progress = Callable[[int, int], None]  # (items done, items in all)


@contextmanager
def progress_bar(
    description: str,
    unit: str,
    *,
    enabled: bool,
    announcement: str | None,
    announce_from: int = 0,
) -> Iterator[Progress]:
    """A progress callback ``(done, total)`` for the duration of the block.

    At a terminal: a tqdm bar on standard error, drawn once the work has taken a second.
    Elsewhere (a log, a pipe): ``announcement``, if any, as one line at the first call
    when the total is at least ``announce_from`` (a long wait), ``{total}`` in it replaced
    by the total; then nothing. ``enabled`` False: silence.
    """
    if not enabled:
        yield _silent
        return
    if not sys.stderr.isatty():
        said = False

        def announce(done: int, total: int) -> None:
            nonlocal said
            if not said and announcement is not None and total >= announce_from:
                line = announcement.replace("{total}", str(total))
                print(f"celtstone: {line}", file=sys.stderr, flush=True)
            said = True

        yield announce
        return
    from tqdm import tqdm

    bar: Any = None
    try:

        def update(done: int, total: int) -> None:
            nonlocal bar
            if bar is None:
                bar = tqdm(total=total, desc=description, unit=unit, file=sys.stderr, delay=1.0)
            bar.update(done - bar.n)

        yield update
    finally:
        if bar is not None:
            bar.close()


def _silent(done: int, total: int) -> None:
    """The callback of a disabled bar."""
