"""A target's runs on threads (``reproduce.parallel``): order, errors, stopping."""

from __future__ import annotations

import threading
import time

import pytest

from celtstone.reproduce import parallel
from celtstone.reproduce.parallel import map_in_threads


@pytest.fixture
def two_threads(monkeypatch: pytest.MonkeyPatch) -> None:
    """Two threads whatever the machine has, so the threaded path is the one tested."""
    monkeypatch.setattr(parallel, "thread_count", lambda jobs: min(2, jobs))


def test_results_come_in_the_items_order(two_threads: None) -> None:
    def slow_for_small(value: int) -> int:
        time.sleep(0.02 * (5 - value))  # the first items finish last
        return value * value

    assert list(map_in_threads(slow_for_small, range(5))) == [0, 1, 4, 9, 16]


def test_the_calls_run_side_by_side(two_threads: None) -> None:
    both = threading.Barrier(2, timeout=5.0)  # broken (an error) unless two wait at once

    def meet(value: int) -> int:
        both.wait()
        return value

    assert list(map_in_threads(meet, [1, 2])) == [1, 2]


def test_an_error_is_raised_in_its_turn(two_threads: None) -> None:
    def fail_at_two(value: int) -> int:
        if value == 2:
            raise ValueError("two")
        return value

    results = map_in_threads(fail_at_two, range(4))
    assert [next(results), next(results)] == [0, 1]
    with pytest.raises(ValueError, match="two"):
        next(results)


def test_no_new_call_starts_once_the_reader_stops(two_threads: None) -> None:
    started: list[int] = []

    def record(value: int) -> int:
        started.append(value)
        time.sleep(0.05)
        return value

    results = map_in_threads(record, range(40))
    assert next(results) == 0
    results.close()  # as an exception or a signal in the reader does
    time.sleep(0.3)
    assert len(started) <= 4  # the two running and at most one more each


def test_one_core_or_one_item_runs_in_the_callers_thread() -> None:
    names = list(map_in_threads(lambda _: threading.current_thread().name, [None]))
    assert names == [threading.current_thread().name]
    assert parallel.thread_count(1) == 1 and parallel.thread_count(0) == 1
