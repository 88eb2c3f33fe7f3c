"""A target's independent runs on the cores: results in order, stoppable at once
(``celtstone._threads``, which a fit's runs share)."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import TypeVar

from celtstone import _threads
from celtstone._threads import POLL_INTERVAL as POLL_INTERVAL
from celtstone._threads import thread_count as thread_count

Item = TypeVar("Item")
Result = TypeVar("Result")


def map_in_threads(function: Callable[[Item], Result], items: Iterable[Item]) -> Iterator[Result]:
    """``function(item)`` for every item on :func:`thread_count` daemon threads, in the
    items' order (:func:`celtstone._threads.map_in_threads`)."""
    work = list(items)
    return _threads.map_in_threads(function, work, workers=thread_count(len(work)))
