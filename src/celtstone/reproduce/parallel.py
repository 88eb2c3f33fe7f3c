"""The runs of a reproduction on the cores.

:func:`map_in_threads` runs one target's independent runs side by side, results in order,
stoppable at once (``celtstone._threads``, which a fit's runs share).

:class:`SharedRuns` runs ahead: every run a reproduction will ask for is planned when it
starts, computed on the cores in the order the targets ask for them, and handed over when
asked, so that a core does not wait while another target's figures, video and files are
written, nor at the end of a target whose last run is long, and a run that two targets ask
for (Figure 2's sliding runs are also rows of the one-at-a-time table) is computed once.
A run is deterministic: the one computed ahead is the one that would have been computed
when asked.
"""

from __future__ import annotations

import contextlib
import sys
import threading
from collections import deque
from collections.abc import Callable, Hashable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import Any, TypeVar

from celtstone import _threads
from celtstone._threads import POLL_INTERVAL as POLL_INTERVAL
from celtstone._threads import thread_count as thread_count

__all__ = ["SharedRuns", "map_in_threads", "shared_run", "sharing_runs", "thread_count"]

Item = TypeVar("Item")
Result = TypeVar("Result")

RESULTS_AHEAD = 256
"""Most finished runs held before the targets ask for them (a 20 s run's samples are
0.87 MB: about 220 MB at most). The targets' figures and videos are one thread's work,
a quarter of a reproduction's CPU: while the Figure 2 targets draw, the workers go on
with the later targets' runs rather than leave a core idle."""


def map_in_threads(function: Callable[[Item], Result], items: Iterable[Item]) -> Iterator[Result]:
    """``function(item)`` for every item on :func:`thread_count` daemon threads, in the
    items' order (:func:`celtstone._threads.map_in_threads`)."""
    work = list(items)
    return _threads.map_in_threads(function, work, workers=thread_count(len(work)))


@dataclass
class _Run:
    """One planned run: its computation, how many more times it will be asked for, and
    how often it was handed over, and its result once computed (state "planned",
    "running", "done")."""

    compute: Callable[[], Any]
    asked: int
    handed: int = 0
    state: str = "planned"
    result: Any = None
    error: BaseException | None = None
    done: threading.Event = field(default_factory=threading.Event)


class SharedRuns:
    """Runs planned ahead and computed on ``workers`` daemon threads, each once.

    :meth:`plan` queues a run under a key (its settings); :meth:`take` hands it over: at
    once if computed, after it ends if under way, computed in the caller's thread if not
    yet started (a target never waits behind runs queued for later ones). A run asked for
    more often than planned, or never planned, is computed by the caller. A result is
    let go once asked for as often as planned; a run's error is raised to the caller that
    asks for it, as if computed there. :meth:`stop` (or leaving :func:`sharing_runs`)
    starts no new run; runs under way are abandoned, as in :func:`map_in_threads`.
    """

    def __init__(self, workers: int) -> None:
        self._runs: dict[Hashable, _Run] = {}
        self._queue: deque[Hashable] = deque()
        self._held = 0  # finished runs not yet asked for as often as planned
        self._changed = threading.Condition()
        self._stopped = False
        self.computed = 0
        """Runs computed (by a worker or a caller), shared or not."""
        self.shared = 0
        """Runs handed over that had been computed for another caller before."""
        self.unclaimed = 0
        """Planned runs not asked for as often as planned when :meth:`stop` was called."""
        for number in range(workers):
            name = f"celtstone-ahead-{number}"
            threading.Thread(target=self._serve, name=name, daemon=True).start()

    def plan(self, key: Hashable, compute: Callable[[], Any]) -> None:
        """Queue ``compute`` under ``key``; a key planned before is asked for once more."""
        with self._changed:
            run = self._runs.get(key)
            if run is not None:
                run.asked += 1
                return
            self._runs[key] = _Run(compute, asked=1)
            self._queue.append(key)
            self._changed.notify_all()

    def take(self, key: Hashable, compute: Callable[[], Any]) -> Any:
        """The result of the run planned under ``key`` (``compute()`` if none is)."""
        with self._changed:
            run = self._runs.get(key)
            mine = run is not None and run.state == "planned"  # not started: computed here
            if run is None:
                self.computed += 1
            elif mine:
                run.state = "running"
                self._queue.remove(key)
        if run is None:
            return compute()
        if mine:
            self._compute(run)
        else:
            while not run.done.wait(POLL_INTERVAL):  # wakes to take a signal
                pass
        return self._hand_over(key, run)

    def stop(self) -> None:
        """Start no new run; let go of every result."""
        with self._changed:
            self._stopped = True
            self.unclaimed = len(self._runs)
            self._queue.clear()
            self._runs.clear()
            self._changed.notify_all()

    def _hand_over(self, key: Hashable, run: _Run) -> Any:
        with self._changed:
            self.shared += 1 if run.handed else 0
            run.handed += 1
            run.asked -= 1
            if run.asked <= 0:  # asked for as often as planned: let it go
                self._runs.pop(key, None)
                self._held -= 1
                self._changed.notify_all()
            result, error = run.result, run.error
            if run.asked <= 0:
                run.result = run.error = None
        if error is not None:
            raise error
        return result

    def _compute(self, run: _Run) -> None:
        try:
            run.result = run.compute()
        except BaseException as error:  # raised to whoever asks for the run
            run.error = error
        with self._changed:
            run.state = "done"
            self._held += 1
            self.computed += 1
        run.done.set()

    def _serve(self) -> None:
        while True:
            with self._changed:
                while not self._stopped and (not self._queue or self._held >= RESULTS_AHEAD):
                    self._changed.wait()
                if self._stopped:
                    return
                key = self._queue.popleft()
                run = self._runs[key]
                run.state = "running"
            self._compute(run)


_active: list[SharedRuns] = []  # the reproduction's runs while one is under way


@contextlib.contextmanager
def sharing_runs(workers: int | None = None) -> Iterator[SharedRuns]:
    """Within the block, :func:`shared_run` takes its runs from one :class:`SharedRuns` of
    ``workers`` threads (default one per core); leaving it stops them."""
    runs = SharedRuns(thread_count(sys.maxsize) if workers is None else workers)
    _active.append(runs)
    try:
        yield runs
    finally:
        runs.stop()
        _active.remove(runs)


def shared_run(key: Hashable, compute: Callable[[], Result]) -> Result:
    """``compute()``, or the run planned under ``key`` within :func:`sharing_runs`."""
    if not _active:
        return compute()
    result: Result = _active[-1].take(key, compute)
    return result
