"""A run whose progress callback raises stops its compiled loop (``solvers._stop``).

The loop runs in a thread of its own while the caller's thread reports progress; when
the callback raises (the live explorer's ``Cancelled``), the loop must return at its
next step with ``Status.STOPPED``, not run on to t_end in the background.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.solvers import run as solver_run
from tests.conftest import LITERATURE_EULER_ANGLES

T_END = 1.0e5  # s: far longer than the test lets the run go
CANCEL_AFTER = 0.3  # s of progress reports before the callback raises
THREAD_END_WAIT = 10.0  # s: generous; the loop returns within one step of the request


class Cancelled(Exception):
    """What the test's progress callback raises."""


def _cancelling_progress(reached: list[float]) -> Any:
    first_call: list[float] = []

    def progress(t: float) -> None:
        reached.append(t)
        if not first_call:
            first_call.append(time.monotonic())
        if time.monotonic() - first_call[0] > CANCEL_AFTER:
            raise Cancelled

    return progress


def _recording(function: Any, ends: list[Any]) -> Any:
    """``function``, keeping what it returns (in the loop's thread) in ``ends``."""

    def record(*arguments: Any) -> Any:
        result = function(*arguments)
        ends.append(result)
        return result

    return record


def _run_threads() -> list[threading.Thread]:
    return [thread for thread in threading.enumerate() if thread.name == "celtstone-run"]


def _wait_for_run_threads() -> list[threading.Thread]:
    deadline = time.monotonic() + THREAD_END_WAIT
    while _run_threads() and time.monotonic() < deadline:
        time.sleep(0.01)
    return _run_threads()


@pytest.mark.parametrize(
    ("model", "loop"),
    [(cs.SlidingModel(), "integrate_at"), (cs.HybridModel(), "run_phases")],
    ids=["sliding", "stick-slip"],
)
def test_a_raising_progress_callback_stops_the_compiled_loop(
    kane_levinson: cs.Body, model: Any, loop: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    state = cs.InitialState((0.0, 0.0, -5.0), LITERATURE_EULER_ANGLES)
    cs.simulate(model, kane_levinson, state, 0.01, n_samples=2)  # compiled before: the
    # cancel below reaches a loop that runs, whatever the machine's load
    ends: list[Any] = []
    monkeypatch.setattr(solver_run, loop, _recording(getattr(solver_run, loop), ends))
    reached: list[float] = []
    assert not _run_threads()
    with pytest.raises(Cancelled):
        cs.simulate(
            model,
            kane_levinson,
            state,
            T_END,
            sample_times=np.linspace(0.0, T_END, 11),
            progress=_cancelling_progress(reached),
        )
    assert not _wait_for_run_threads(), "the compiled loop ran on after the cancel"
    assert len(ends) == 1, "the loop's thread returned"
    end = ends[0] if loop == "integrate_at" else ends[0][0]  # run_phases: (RunEnd, ...)
    assert end.status == solvers.Status.STOPPED
    assert 0.0 <= end.t_stop < T_END
