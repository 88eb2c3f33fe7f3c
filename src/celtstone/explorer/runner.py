"""Runs for the explorer: one at a time, the newest wins, a stale result is never shown.

Each :meth:`Runner.submit` validates its inputs first (a refused input starts nothing and
leaves the run in flight, of the last good inputs, alone), numbers them with a new
*generation*, asks the run in flight to stop and starts the new one on a daemon thread.
A finished run is kept only if its generation is still the newest, so the page never
draws a figure of inputs it no longer shows.

A run is stopped inside its compiled loop. :func:`celtstone.simulate` hands the whole of
[0, t_end] to one call of the compiled loop (``solvers.driver.integrate``, or
``solvers.phases.run_phases`` for stick-slip) on a thread of its own, and calls its
``progress`` callback about ten times a second from the thread that waits for it. Once
a run is stopped or superseded the callback raises :class:`Cancelled`; ``simulate`` then
asks the loop to stop, the loop returns before its next step, and ``simulate`` waits for
its thread and raises :class:`Cancelled` again, which ends the run's worker thread with
nothing kept. A superseded run therefore costs at most one progress interval of
computing, except while its model is still being compiled (a model not yet in numba's
cache, on its first run): compiling cannot be interrupted, so the run ends when the
compiled loop starts, and :meth:`Runner.running` tells that phase apart (no progress
reported yet) for the page to say why it waits.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from celtstone.errors import CeltstoneError
from celtstone.explorer.inputs import Inputs, Prepared, prepare
from celtstone.simulation import plausibility
from celtstone.simulation.models import contact_settings

if TYPE_CHECKING:  # the run's modules are imported by the first run, not by the page
    from celtstone.simulation.trajectory import Trajectory

__all__ = ["Cancelled", "FinishedRun", "Progress", "Runner"]


class Cancelled(Exception):
    """Raised from the progress callback of a run that was stopped or superseded."""


@dataclass(frozen=True)
class FinishedRun:
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
        What ``celtstone.simulation.plausibility`` finds implausible in the inputs (the
        warnings ``simulate`` gives before a run).
    cautions : tuple of str
        What ``simulate`` warns of after the run (its friction beyond Coulomb's bound).
    seconds : float
        Wall time from submission to the result [s].
    """

    generation: int
    inputs: Inputs
    trajectory: Trajectory | None
    error: str = ""
    concerns: tuple[str, ...] = ()
    cautions: tuple[str, ...] = ()
    seconds: float = 0.0


@dataclass(frozen=True)
class Progress:
    """How far the run in flight has come.

    Parameters
    ----------
    generation : int
        Its inputs' number, as :attr:`FinishedRun.generation`.
    time_reached : float
        Simulated time of the last sample the compiled loop wrote [s].
    t_end : float
        The time the run goes to [s].
    looping : bool
        Whether the compiled loop has started (it has reported progress). Before that,
        the run is loading its model's compiled code, or compiling it on the first run
        of a model not yet in numba's cache.
    seconds : float
        Wall time since the inputs were submitted [s].
    """

    generation: int
    time_reached: float
    t_end: float
    looping: bool
    seconds: float


@dataclass
class _Job:
    generation: int
    inputs: Inputs
    prepared: Prepared
    started: float
    stop: threading.Event = field(default_factory=threading.Event)
    time_reached: float = 0.0
    looping: bool = False


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
        self._outcome: FinishedRun | None = None
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

    def running(self) -> Progress | None:
        """How far the run in flight has come; None when none is."""
        job = self._job
        if job is None:
            return None
        return Progress(
            generation=job.generation,
            time_reached=job.time_reached,
            t_end=job.prepared.t_end,
            looping=job.looping,
            seconds=time.perf_counter() - job.started,
        )

    def take(self) -> FinishedRun | None:
        """The newest finished outcome not taken yet, or None."""
        with self._lock:
            outcome, self._outcome = self._outcome, None
        return outcome

    def wait(self, generation: int, timeout: float = 60.0) -> FinishedRun | None:
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
            job.looping = True
            if job.stop.is_set():
                raise Cancelled

        if job.stop.is_set():  # superseded before it started (a slider dragged on)
            return
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
        outcome = FinishedRun(
            generation=job.generation,
            inputs=job.inputs,
            trajectory=trajectory,
            error=error,
            concerns=tuple(str(c) for c in concerns(job.prepared)),
            cautions=cautions(trajectory),
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


def cautions(trajectory: Trajectory | None) -> tuple[str, ...]:
    """What ``simulate`` warned of after running ``trajectory`` (none for no run)."""
    from celtstone.simulation.integrate import friction_bound_warning

    if trajectory is None:
        return ()
    warning = friction_bound_warning(trajectory)
    return () if warning is None else (str(warning),)


def _simulate(prepared: Prepared, progress: Callable[[float], None]) -> Trajectory:
    # imported by the first run, once a served page is shown: not on the way to it
    from celtstone.simulation.integrate import simulate

    return simulate(
        prepared.model,
        prepared.body,
        prepared.initial_state,
        prepared.t_end,
        progress=progress,
    )
