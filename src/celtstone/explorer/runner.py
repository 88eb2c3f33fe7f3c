"""Runs for the explorer: one at a time, the newest wins, a stale result is never shown.

Each :meth:`Runner.submit` validates its inputs first (a refused input starts nothing and
leaves the run in flight, of the last good inputs, alone), numbers them with a new
*generation*, stops the run in flight and starts the new one on a daemon thread.
:func:`celtstone.simulate` calls its ``progress`` callback about ten times a second; the
callback raises :class:`Cancelled` once the run is stopped, which ends ``simulate`` at
once. A finished run is kept only if its generation is still the newest, so the page
never draws a figure of inputs it no longer shows.

A stopped run's computation is not interrupted, because a run is not made of chunks:
``simulate`` hands the whole of [0, t_end] to one call of the compiled loop
(``solvers.driver.integrate``, or ``solvers.phases.run_phases`` for stick-slip), which
``solvers._run`` starts on a thread of its own, and calls ``progress`` from the thread
that waits for it. Raising there ends the wait, not the loop: the loop reads no stop
request (it ends at t_end, at ``max_steps``, at a terminal event or on a failure), so it
finishes in the background and its result is dropped. Stopping it within a run needs a
stop flag that the compiled loop reads at each step, a change to the compiled solvers.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from celtstone.errors import CeltstoneError
from celtstone.explorer.inputs import Inputs, Prepared, prepare
from celtstone.simulation import plausibility
from celtstone.simulation.integrate import simulate
from celtstone.simulation.models import contact_settings
from celtstone.simulation.trajectory import Trajectory

__all__ = ["Cancelled", "Outcome", "Runner"]


class Cancelled(Exception):
    """Raised from the progress callback of a run that was stopped or superseded."""


@dataclass(frozen=True)
class Outcome:
    """A finished run of one generation of inputs.

    Parameters
    ----------
    generation : int
        The number :meth:`Runner.submit` gave its inputs.
    inputs : Inputs
        What was run.
    trajectory : Trajectory or None
        The run; None when it raised.
    error : str
        The one-line message of the error it raised ("" when none).
    concerns : tuple of str
        What ``celtstone.simulation.plausibility`` finds implausible in the inputs (the warnings
        ``simulate`` gives before a run).
    seconds : float
        Wall time from submission to the result [s].
    """

    generation: int
    inputs: Inputs
    trajectory: Trajectory | None
    error: str = ""
    concerns: tuple[str, ...] = ()
    seconds: float = 0.0


@dataclass
class _Job:
    generation: int
    inputs: Inputs
    prepared: Prepared
    started: float
    stop: threading.Event = field(default_factory=threading.Event)
    time_reached: float = 0.0


class Runner:
    """Runs the newest inputs on a worker thread; see the module docstring.

    Parameters
    ----------
    run : callable, optional
        ``run(prepared, progress) -> Trajectory``; default :func:`simulate`. Tests pass
        a slow stand-in to prove the cancel path.
    """

    def __init__(
        self, run: Callable[[Prepared, Callable[[float], None]], Trajectory] | None = None
    ):
        self._run = run or _simulate
        self._lock = threading.Lock()
        self._generation = 0
        self._job: _Job | None = None
        self._outcome: Outcome | None = None
        self._dropped = 0

    @property
    def generation(self) -> int:
        """The newest generation submitted."""
        return self._generation

    @property
    def dropped(self) -> int:
        """How many finished runs were dropped as stale (tests, diagnostics)."""
        return self._dropped

    def submit(self, inputs: Inputs) -> int:
        """Validate ``inputs``, stop the run in flight, start theirs; their generation.

        Raises
        ------
        ParameterError
            For an input out of range; the run in flight (of the last good inputs) goes on.
        """
        prepared = prepare(inputs)  # raises before anything is stopped or started
        with self._lock:
            self._generation += 1
            job = _Job(self._generation, inputs, prepared, time.perf_counter())
            if self._job is not None:
                self._job.stop.set()
            self._job = job
        threading.Thread(
            target=self._work, args=(job,), name=f"celtstone-explore-{job.generation}", daemon=True
        ).start()
        return job.generation

    def stop(self) -> bool:
        """Stop the run in flight (the Stop button); whether there was one."""
        with self._lock:
            job, self._job = self._job, None
        if job is None:
            return False
        job.stop.set()
        return True

    def running(self) -> tuple[int, float, float] | None:
        """(generation, simulated time reached [s], its t_end [s]) of the run in flight."""
        job = self._job
        if job is None:
            return None
        return job.generation, job.time_reached, job.prepared.t_end

    def elapsed(self) -> float:
        """Wall time since the run in flight was submitted [s]; 0 when none."""
        job = self._job
        return 0.0 if job is None else time.perf_counter() - job.started

    def take(self) -> Outcome | None:
        """The newest finished outcome not taken yet, or None."""
        with self._lock:
            outcome, self._outcome = self._outcome, None
        return outcome

    def wait(self, generation: int, timeout: float = 60.0) -> Outcome | None:
        """Block until the run of ``generation`` is done; its outcome (tests, notebooks)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self._lock:
                outcome = self._outcome
                if outcome is not None and outcome.generation == generation:
                    self._outcome = None
                    return outcome
                if self._generation != generation or (self._job is None and outcome is None):
                    return None
            time.sleep(0.01)
        return None

    def _work(self, job: _Job) -> None:
        def progress(time_reached: float) -> None:
            job.time_reached = time_reached
            if job.stop.is_set():
                raise Cancelled

        trajectory: Trajectory | None = None
        error = ""
        try:  # warnings go where the process sends them: catch_warnings is not thread-safe
            trajectory = self._run(job.prepared, progress)
        except Cancelled:
            return
        except CeltstoneError as failure:
            error = str(failure)
        except Exception as failure:  # shown on the page as one line, never a traceback
            error = f"{type(failure).__name__}: {failure}"
        outcome = Outcome(
            generation=job.generation,
            inputs=job.inputs,
            trajectory=trajectory,
            error=error,
            concerns=tuple(str(c) for c in concerns(job.prepared)),
            seconds=time.perf_counter() - job.started,
        )
        with self._lock:
            if job.generation != self._generation or job.stop.is_set():
                self._dropped += 1
                return
            self._outcome = outcome
            self._job = None


def concerns(prepared: Prepared) -> list[plausibility.Concern]:
    """What ``simulate`` would warn about before running ``prepared``."""
    return plausibility.concerns(prepared.body, contact_settings(prepared.model))


def _simulate(prepared: Prepared, progress: Callable[[float], None]) -> Trajectory:
    return simulate(
        prepared.model,
        prepared.body,
        prepared.initial_state,
        prepared.t_end,
        progress=progress,
    )
