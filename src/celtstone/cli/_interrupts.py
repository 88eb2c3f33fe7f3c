"""Ctrl-C and SIGTERM in the command: exit 130 or 143 with one line, whatever the moment.

Three stretches of a command's life take a signal differently:

* while the command starts (``celtstone._early_signals``, the package's first import),
  nothing has been written yet: the process says so and exits at once (:func:`stop_at_once`);
* while :func:`celtstone.cli.main.main` runs, SIGINT raises ``KeyboardInterrupt`` and
  SIGTERM :class:`Terminated`, so that ``finally`` blocks remove temporaries before the
  one-line message (:func:`unwinding`);
* once ``main`` has returned, the command's work is done: the process exits at once again.

The first and last apply only when the process *is* the command (the ``celtstone`` script
or ``python -m celtstone``), never when a program or a test calls ``main`` in-process:
there the previous handlers are put back.
"""

from __future__ import annotations

import signal
import sys
import threading
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

from celtstone._early_signals import exit_now, is_the_command, stop_at_once
from celtstone._held_signals import defer

__all__ = [
    "Interruption",
    "Signals",
    "Terminated",
    "Termination",
    "is_the_command",
    "quiet_abandoned_writes",
    "stop_at_once",
    "unwinding",
]

_REDELIVERY_DELAY = 0.01  # s, for the hook to return before the signal comes again
_Handler = Callable[[int, FrameType | None], Any] | int | None  # what getsignal gives


def quiet_abandoned_writes() -> None:
    """From now on: no warning for a coroutine that was never awaited. Zarr writes
    through coroutines; one created just as Ctrl-C or SIGTERM arrived is collected
    while the command unwinds or at exit, and Python's warning would add lines after
    the one-line message (the store's completed blocks are unaffected). Called as the
    signal arrives and again after ``warnings.catch_warnings`` puts the filters back."""
    warnings.filterwarnings(
        "ignore", message="coroutine .* was never awaited", category=RuntimeWarning
    )


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that it unwinds like Ctrl-C.

    ``finally`` blocks remove temporaries, and every ``except KeyboardInterrupt``
    (the sweep's resume message) handles it as it handles Ctrl-C.
    """


class Interruption:
    """The SIGINT handler inside ``main``: raises ``KeyboardInterrupt``; in the command, a
    second Ctrl-C during the clean-up ends the process at once (one line, exit 130)
    instead of raising again wherever the clean-up is (a traceback)."""

    def __init__(self) -> None:
        self.received = False

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.received = True
        quiet_abandoned_writes()
        if is_the_command():
            signal.signal(signal.SIGINT, exit_now)
        if not defer(KeyboardInterrupt()):  # a child process starting: raised once it is held
            raise KeyboardInterrupt


class Termination:
    """The SIGTERM handler inside ``main``: raises :class:`Terminated` once and remembers
    that it came; a second SIGTERM is ignored so that it cannot cut the clean-up short
    (SIGKILL still ends the process)."""

    def __init__(self) -> None:
        self.received = False

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.received = True
        quiet_abandoned_writes()
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        if not defer(Terminated()):  # a child process starting: raised once it is held
            raise Terminated


def _redelivering(
    previous: Callable[[Any], object], interruption: Interruption, termination: Termination
) -> Callable[[Any], object]:
    """An unraisable hook that sends again a signal whose exception was swallowed.

    A signal's exception is raised in whatever Python code runs at that moment; in a
    finaliser or a weak reference's callback (the import system has some) Python only
    prints it ("Exception ignored in ...") and carries on: the command would print a
    traceback and not stop. The signal is sent again, to be raised in the next code.
    """

    def hook(unraisable: Any) -> object:
        kind = unraisable.exc_type
        if kind is None or not issubclass(kind, KeyboardInterrupt):
            return previous(unraisable)
        signum = signal.SIGINT
        signal.signal(signal.SIGINT, interruption)  # the first handler, once more
        if issubclass(kind, Terminated):
            signal.signal(signal.SIGTERM, termination)  # it ignores a second SIGTERM
            signum = signal.SIGTERM
        # sent from another thread a moment later: sent from here, its handler would run
        # at once, inside this hook, and be swallowed again
        threading.Timer(_REDELIVERY_DELAY, signal.raise_signal, (signum,)).start()
        return None

    return hook


class Signals:
    """The two handlers of one :func:`unwinding`, and what they saw."""

    def __init__(self) -> None:
        self.interruption = Interruption()
        self.termination = Termination()

    def lost(self) -> KeyboardInterrupt | None:
        """The stop that a received signal asked for, for a command that went on as if it
        had not come: C code may replace the exception a handler raised (an extension
        module imported while the signal lands reports an ``ImportError`` instead, which
        a library may even catch as "optional module missing"). None if none came."""
        if self.termination.received:
            return Terminated()
        if self.interruption.received:
            return KeyboardInterrupt()
        return None


@contextmanager
def unwinding() -> Iterator[Signals]:
    """Inside: SIGINT raises ``KeyboardInterrupt`` and SIGTERM :class:`Terminated` (main
    thread only; an ignored signal stays ignored). Afterwards: in the command, both end
    the process at once (:func:`stop_at_once`); in-process, the previous handlers are back."""
    signals = Signals()
    interruption, termination = signals.interruption, signals.termination
    handlers: dict[signal.Signals, _Handler] = {
        signal.SIGINT: interruption,
        signal.SIGTERM: termination,
    }
    previous: dict[signal.Signals, _Handler] = {}
    for number, handler in handlers.items():
        try:
            before = signal.getsignal(number)
            if before is not signal.SIG_IGN:
                signal.signal(number, handler)
                previous[number] = before
        except ValueError:  # not the main thread: signals stay as they are
            break
    hook = sys.unraisablehook
    sys.unraisablehook = _redelivering(hook, interruption, termination)
    try:
        yield signals
    finally:
        if not (is_the_command() and signals.lost() is not None):
            # a stopped command keeps its finalizers quiet (``main._stopped``)
            sys.unraisablehook = hook
        if is_the_command():
            stop_at_once()
        else:
            for signum, before in previous.items():
                signal.signal(signum, signal.SIG_DFL if before is None else before)
