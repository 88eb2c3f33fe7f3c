"""A reproduction's runs on threads (``reproduce.parallel``): order, errors, stopping, the
runs computed ahead and shared; its progress in a log (``reproduce.progress``)."""

from __future__ import annotations

import threading
import time

import pytest

from celtstone.reproduce import parallel
from celtstone.reproduce.parallel import map_in_threads
from celtstone.reproduce.progress import duration_words, progress_bar


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


# Runs computed ahead for a whole reproduction (``parallel.SharedRuns``)


def _counting(calls: list[str], key: str, value: object, gate: threading.Event | None = None):
    """A run that records its key and the thread it ran in, waiting for ``gate`` if given."""

    def compute() -> object:
        calls.append(f"{key}@{threading.current_thread().name}")
        if gate is not None:
            assert gate.wait(5.0)
        return value

    return compute


def _unplanned() -> object:
    raise AssertionError("a planned run was computed by its caller's function")


def test_a_run_planned_twice_is_computed_once_and_handed_to_both() -> None:
    calls: list[str] = []
    value = object()
    runs = parallel.SharedRuns(workers=1)
    try:
        runs.plan("a", _counting(calls, "a", value))
        runs.plan("a", _counting(calls, "a again", object()))
        assert runs.take("a", _unplanned) is value
        assert runs.take("a", _unplanned) is value
        # asked for as often as planned: let go, so a third ask computes afresh
        assert runs.take("a", lambda: "fresh") == "fresh"
    finally:
        runs.stop()
    assert [c.split("@")[0] for c in calls] == ["a"]
    assert (runs.computed, runs.shared, runs.unclaimed) == (2, 1, 0)


def test_planned_runs_are_computed_ahead_on_the_workers() -> None:
    calls: list[str] = []
    gate = threading.Event()
    runs = parallel.SharedRuns(workers=2)
    try:
        runs.plan("a", _counting(calls, "a", 1, gate))
        runs.plan("b", _counting(calls, "b", 2, gate))
        deadline = time.monotonic() + 5.0
        while len(calls) < 2 and time.monotonic() < deadline:  # both started, none asked for
            time.sleep(0.01)
        gate.set()
        assert [runs.take(k, _unplanned) for k in "ab"] == [1, 2]
    finally:
        runs.stop()
    assert sorted(c.split("@")[0] for c in calls) == ["a", "b"]
    assert all("celtstone-ahead" in c for c in calls)


def test_a_run_not_yet_started_is_computed_by_the_caller() -> None:
    calls: list[str] = []
    gate = threading.Event()
    runs = parallel.SharedRuns(workers=1)
    try:
        runs.plan("slow", _counting(calls, "slow", 1, gate))  # holds the only worker
        runs.plan("next", _counting(calls, "next", 2))
        while not calls:
            time.sleep(0.01)
        assert runs.take("next", _unplanned) == 2  # not behind "slow"
        gate.set()
        assert runs.take("slow", _unplanned) == 1
    finally:
        runs.stop()
    assert calls[1] == f"next@{threading.current_thread().name}"


def test_a_runs_error_is_raised_to_whoever_asks_for_it() -> None:
    def fail() -> None:
        raise ValueError("bad run")

    runs = parallel.SharedRuns(workers=2)
    try:
        runs.plan("bad", fail)
        with pytest.raises(ValueError, match="bad run"):
            runs.take("bad", _unplanned)
    finally:
        runs.stop()


def test_no_planned_run_starts_once_stopped() -> None:
    calls: list[str] = []
    gate = threading.Event()
    runs = parallel.SharedRuns(workers=1)
    runs.plan("first", _counting(calls, "first", 1, gate))
    for number in range(5):
        runs.plan(number, _counting(calls, str(number), number))
    while not calls:
        time.sleep(0.01)
    runs.stop()
    gate.set()
    time.sleep(0.2)
    assert [c.split("@")[0] for c in calls] == ["first"]
    assert runs.unclaimed == 6


def test_the_workers_wait_once_enough_results_are_held(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(parallel, "RESULTS_AHEAD", 2)
    calls: list[str] = []
    runs = parallel.SharedRuns(workers=2)
    try:
        for number in range(5):
            runs.plan(number, _counting(calls, str(number), number))
        time.sleep(0.3)  # long enough for the workers to compute all five, were they free to
        assert sorted(c.split("@")[0] for c in calls) == ["0", "1"]
        assert runs.take(0, _unplanned) == 0  # one result let go: one more run
        deadline = time.monotonic() + 5.0
        while len(calls) < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        time.sleep(0.1)
        assert sorted(c.split("@")[0] for c in calls) == ["0", "1", "2"]
        assert [runs.take(k, _unplanned) for k in range(1, 5)] == [1, 2, 3, 4]
    finally:
        runs.stop()


def test_outside_a_reproduction_a_run_is_computed_where_asked() -> None:
    assert parallel.shared_run("k", lambda: threading.current_thread().name) == (
        threading.current_thread().name
    )
    with parallel.sharing_runs(workers=1) as runs:
        runs.plan("k", lambda: "ahead")
        assert parallel.shared_run("k", _unplanned) == "ahead"
    assert parallel.shared_run("k", lambda: "after") == "after"


# A reproduction's progress where standard error is a log, not a terminal


def test_a_log_gets_a_line_every_interval_and_each_note(
    capsys: pytest.CaptureFixture[str],
) -> None:
    bar = progress_bar(10, "reproduce", enabled=True, interval=0.05)
    bar.set_description("fig2_x: runs")
    bar.update(3)
    time.sleep(0.3)  # several intervals, no update: still lines
    bar.note("fig2 x: 41 s (3 min 05 s in all)")
    bar.close()
    bar.note("after the end")  # nothing
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == "reproduce: 10 runs; a line every 0.05 s"
    ticks = [line for line in lines if line.startswith("reproduce: 3/10 runs, 0 s (fig2_x: runs)")]
    assert len(ticks) >= 3
    assert "reproduce: fig2 x: 41 s (3 min 05 s in all)" in lines
    assert "after the end" not in "".join(lines)


def test_a_disabled_bar_prints_nothing(capsys: pytest.CaptureFixture[str]) -> None:
    bar = progress_bar(10, "reproduce", enabled=False, interval=0.01)
    bar.update(1)
    bar.note("done")
    time.sleep(0.05)
    bar.close()
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(
    ("seconds", "words"), [(0.4, "0 s"), (41.2, "41 s"), (60, "1 min 00 s"), (185, "3 min 05 s")]
)
def test_duration_words(seconds: float, words: str) -> None:
    assert duration_words(seconds) == words
