"""Progress of a reproduction on standard error: a bar at a terminal, a line every
:data:`LINE_INTERVAL` seconds elsewhere (a log, ``make run`` in CI), or nothing.

Its lines start with the bar's description ("reproduce: ..."), not "celtstone:", the
start of the one line that says why a command stopped."""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from typing import Any, Protocol

from tqdm import tqdm

__all__ = ["LINE_INTERVAL", "Progress", "ReproductionProgress", "duration_words", "progress_bar"]

LINE_INTERVAL = 30.0
"""Seconds between two progress lines when standard error is not a terminal."""


class Progress(Protocol):
    """What the targets need of a progress bar (tqdm's bar has it).

    Attributes
    ----------
    total : float or None
        The runs in all, raised when a target adds runs (the threshold's bisections).
    """

    total: float | None

    def update(self, n: float = 1) -> bool | None:
        """Count ``n`` more runs done.

        Parameters
        ----------
        n : float, optional
            The runs just done.

        Returns
        -------
        bool or None
            Whatever the bar returns (tqdm: whether it was redrawn).
        """
        ...

    def set_description(self, desc: str | None = None, refresh: bool = True) -> None:
        """Say what is being done now.

        Parameters
        ----------
        desc : str, optional
            A few words (the target and its stage).
        refresh : bool, optional
            Whether to redraw at once.
        """
        ...

    def refresh(self) -> None:
        """Show a changed :attr:`total` (redraw)."""
        ...

    def close(self) -> None:
        """End the bar."""
        ...


class ReproductionProgress(Progress, Protocol):
    """A reproduction's progress: a :class:`Progress` that also says when a target is done."""

    def note(self, line: str) -> None:
        """Print ``line`` on standard error, unless silent.

        Parameters
        ----------
        line : str
            A target done and its time.
        """
        ...


def duration_words(seconds: float) -> str:
    """``41 s`` or ``3 min 05 s``."""
    whole = round(seconds)
    if whole < 60:
        return f"{whole} s"
    return f"{whole // 60} min {whole % 60:02d} s"


class _Bar(tqdm):
    """tqdm's bar of runs on standard error; notes are printed above it, after the bar's
    first description (later ones say the target)."""

    def __init__(self, total: int, description: str, enabled: bool) -> None:
        super().__init__(total=total, desc=description, unit="run", disable=not enabled)
        self.name = description

    def note(self, line: str) -> None:
        if not self.disable:
            self.write(f"{self.name}: {line}", file=sys.stderr)


class _Lines:
    """A bar's counts as plain lines on standard error: one when started, then one every
    ``interval`` seconds from a daemon thread (a run may take longer than a line's
    interval), the notes as they come, and one when closed."""

    def __init__(self, total: int, description: str, interval: float) -> None:
        self.total: float | None = total
        self.n = 0.0
        self._description = description
        self._what = ""
        self._started = time.monotonic()
        self._lock = threading.Lock()
        self._closed = threading.Event()
        self._say(f"{description}: {total} runs; a line every {interval:g} s")
        threading.Thread(
            target=self._tick, args=(interval,), name="celtstone-progress-lines", daemon=True
        ).start()

    def update(self, n: float = 1) -> None:
        with self._lock:
            self.n += n

    def set_description(self, desc: str | None = None, refresh: bool = True) -> None:
        with self._lock:
            self._what = desc or ""

    def refresh(self) -> None:
        """Nothing: the next line shows the new total."""

    def note(self, line: str) -> None:
        if not self._closed.is_set():
            self._say(f"{self._description}: {line}")

    def close(self) -> None:
        if not self._closed.is_set():
            self._closed.set()
            self._say(self._state())

    def _state(self) -> str:
        with self._lock:
            done, total, what = self.n, self.total, self._what
        count = f"{done:g}/{total:g} runs" if total is not None else f"{done:g} runs"
        elapsed = duration_words(time.monotonic() - self._started)
        return f"{self._description}: {count}, {elapsed}" + (f" ({what})" if what else "")

    def _tick(self, interval: float) -> None:
        while not self._closed.wait(interval):
            self._say(self._state())

    @staticmethod
    def _say(line: str) -> None:
        # a progress line is not worth stopping the work for: standard error may be full,
        # closed or a pipe whose reader has gone
        with contextlib.suppress(OSError, ValueError):
            print(line, file=sys.stderr, flush=True)


def progress_bar(
    total: int, description: str, enabled: bool, *, interval: float = LINE_INTERVAL
) -> ReproductionProgress:
    """Progress of ``total`` runs: a tqdm bar at a terminal, a line every ``interval``
    seconds elsewhere; disabled, it prints nothing."""
    if enabled and not sys.stderr.isatty():
        return _Lines(total, description, interval)
    bar: Any = _Bar(total, description, enabled)
    return bar
