"""Independent runs on threads: results in order, stoppable at once (a reproduction's
targets, a fit's residuals and Jacobian columns).

The compiled loop releases the GIL, so runs on threads run side by side. The threads are
daemons and take no new run once the caller stops reading (an error, Ctrl-C, SIGTERM);
the runs under way are abandoned, since the process does not wait for daemon threads:
the command stops within a tenth of a second, as a single run does (``cases.simulate_case``),
instead of waiting for the runs in flight and the queued ones (what ``concurrent.futures``'
pools do on shutdown and at exit).
"""

from __future__ import annotations

import os
import queue
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import TypeVar

Item = TypeVar("Item")
Result = TypeVar("Result")

POLL_INTERVAL = 0.1  # s, how often the waiting thread wakes to take a signal


def thread_count(jobs: int) -> int:
    """Threads for ``jobs`` runs: one per core this process may use, at most ``jobs``."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return max(1, min(jobs, cores or 1))


def map_in_threads(
    function: Callable[[Item], Result], items: Iterable[Item], workers: int | None = None
) -> Iterator[Result]:
    """``function(item)`` for every item, computed on ``workers`` daemon threads (default
    :func:`thread_count`), yielded in the items' order; an exception of a call is raised
    when its turn comes.

    ``function`` must be safe to call from several threads at once (``simulate`` is) and
    must not change the process's warning filters: set them around the whole map
    (``warnings.catch_warnings`` is not thread-safe).
    """
    work = list(items)
    workers = thread_count(len(work)) if workers is None else max(1, min(workers, len(work)))
    if workers == 1:
        yield from map(function, work)
        return
    results: list[Result | None] = [None] * len(work)
    errors: list[BaseException | None] = [None] * len(work)
    done = [False] * len(work)
    todo: queue.SimpleQueue[int] = queue.SimpleQueue()
    for index in range(len(work)):
        todo.put(index)
    stop = threading.Event()
    ready = threading.Condition()

    def serve() -> None:
        while not stop.is_set():
            try:
                index = todo.get_nowait()
            except queue.Empty:
                return
            value: Result | None = None
            error: BaseException | None = None
            try:
                value = function(work[index])
            except BaseException as exception:  # handed to the reader, raised there
                error = exception
            with ready:
                results[index], errors[index], done[index] = value, error, True
                ready.notify_all()

    try:  # a signal while the threads start stops those already started too
        for number in range(workers):
            threading.Thread(target=serve, name=f"celtstone-run-{number}", daemon=True).start()
        for index in range(len(work)):
            with ready:
                while not done[index]:
                    ready.wait(POLL_INTERVAL)
            error = errors[index]
            if error is not None:
                raise error
            yield results[index]  # type: ignore[misc]
    finally:
        stop.set()
