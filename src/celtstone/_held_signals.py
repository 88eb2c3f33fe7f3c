"""Ctrl-C and SIGTERM held back while a child process starts, so that it is never orphaned.

A signal's exception is raised in whatever Python code runs when it lands. Landing inside
``subprocess.Popen`` after the fork, it leaves a child that no one holds: an ffmpeg that
then creates its output after the clean-up removed it. Inside :func:`held_signals` the
celtstone command's handlers (``cli._interrupts``) and Python's own Ctrl-C handler record
the signal instead, and its exception is raised as the block ends, where the caller holds
the child and can stop it.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["defer", "held_signals"]

_depth = 0  # nesting of held_signals in the main thread
_pending: BaseException | None = None  # the first signal's exception while held


def defer(exception: BaseException) -> bool:
    """Keep ``exception`` (a signal handler's) for the end of the held block, if one runs;
    whether it was kept (the handler then returns instead of raising)."""
    global _pending
    if _depth == 0:
        return False
    if _pending is None:
        _pending = exception
    return True


def _held_interrupt(signum: int, frame: FrameType | None) -> None:
    """Python's Ctrl-C handler while held: KeyboardInterrupt at the block's end."""
    defer(KeyboardInterrupt())


@contextmanager
def held_signals() -> Iterator[None]:
    """Inside, a Ctrl-C or SIGTERM (celtstone's handlers, or Python's default Ctrl-C in the
    main thread) is raised only as the block ends, after whatever it was doing is done."""
    global _depth, _pending
    swapped = None
    main = threading.current_thread() is threading.main_thread()
    if main and _depth == 0 and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        swapped = signal.signal(signal.SIGINT, _held_interrupt)
    _depth += 1
    try:
        yield
    finally:
        _depth -= 1
        if swapped is not None:
            signal.signal(signal.SIGINT, swapped)
        if _depth == 0 and _pending is not None:
            pending, _pending = _pending, None
            raise pending
