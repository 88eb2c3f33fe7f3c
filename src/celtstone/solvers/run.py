"""Running the compiled loops from Python: :func:`solve` (one model, ``driver.integrate``),
:func:`solve_phases` (the stick–slip contact, ``phases.run_phases``), :func:`capture`,
and what they return, trimmed to what the loops filled (SI units).

A stick–slip run's phases stay one record from the compiled loop to the user: the phase
log's arrays (kind, start, end, energy jump), its kind a :class:`codes.PhaseKind`, kept
as such in the run's Dataset and named by the enum's label in its summary.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from celtstone.errors import ParameterError
from celtstone.solvers import phases
from celtstone.solvers._events import event_table
from celtstone.solvers._linking import compile_for
from celtstone.solvers._stop import request_stop
from celtstone.solvers._structures import (
    Controls,
    HybridSettings,
    Output,
    PhaseLog,
    RunEnd,
    new_output,
    new_phase_log,
)
from celtstone.solvers.codes import (
    DEFAULT_MAX_PHASES,
    STAT_ACCEPTED,
    STAT_NFEV,
    STAT_NJEV,
    STAT_NLU,
    STAT_RADAU_STEPS,
    STAT_REJECTED,
    STAT_SAMPLES_WRITTEN,
    STAT_SWITCHES,
)
from celtstone.solvers.codes import (
    METHOD_DOP853 as METHOD_DOP853,
)
from celtstone.solvers.codes import (
    METHOD_RADAU5 as METHOD_RADAU5,
)
from celtstone.solvers.codes import (
    METHOD_VERN9 as METHOD_VERN9,
)
from celtstone.solvers.codes import (
    METHODS as METHODS,
)
from celtstone.solvers.codes import (
    STATUS_LIFT_OFF as STATUS_LIFT_OFF,
)
from celtstone.solvers.codes import (
    STATUS_MAX_PHASES as STATUS_MAX_PHASES,
)
from celtstone.solvers.codes import (
    STATUS_MAX_STEPS as STATUS_MAX_STEPS,
)
from celtstone.solvers.codes import (
    STATUS_MESSAGES as STATUS_MESSAGES,
)
from celtstone.solvers.codes import (
    STATUS_NON_CONVEX as STATUS_NON_CONVEX,
)
from celtstone.solvers.codes import (
    STATUS_NOT_FINITE as STATUS_NOT_FINITE,
)
from celtstone.solvers.codes import (
    STATUS_OFF_SHAPE as STATUS_OFF_SHAPE,
)
from celtstone.solvers.codes import (
    STATUS_PHASE_CHANGE as STATUS_PHASE_CHANGE,
)
from celtstone.solvers.codes import (
    STATUS_SINGULAR as STATUS_SINGULAR,
)
from celtstone.solvers.codes import (
    STATUS_STEP_TOO_SMALL as STATUS_STEP_TOO_SMALL,
)
from celtstone.solvers.codes import (
    STATUS_STOPPED as STATUS_STOPPED,
)
from celtstone.solvers.codes import (
    STATUS_SUCCESS as STATUS_SUCCESS,
)
from celtstone.solvers.codes import (
    STATUS_UNKNOWN_CODE as STATUS_UNKNOWN_CODE,
)
from celtstone.solvers.codes import Status as Status
from celtstone.solvers.codes import status_label as status_label
from celtstone.solvers.codes import stop_message as stop_message
from celtstone.solvers.driver import integrate as integrate
from celtstone.solvers.driver import integrate_at, integrate_link
from celtstone.solvers.phases import integrate_links, run_phases

# the solver counts of a run, fields of :class:`RawSolution`: a run's ``statistics``
STATISTICS = (
    "nfev",
    "njev",
    "nlu",
    "n_accepted",
    "n_rejected",
    "n_switches",
    "n_radau_steps",
)


@dataclass(frozen=True)
class RawSolution:
    """What the compiled loop returns, trimmed to what it filled (SI units)."""

    status: int
    t_stop: float
    sample_times: np.ndarray
    samples: np.ndarray
    crossings: np.ndarray
    n_crossings_total: int
    min_normal_force: float
    t_min_normal_force: float
    nfev: int
    njev: int
    nlu: int
    n_accepted: int
    n_rejected: int
    n_switches: int  # between DOP853 and Radau (method auto; 0 for the others)
    n_radau_steps: int  # accepted steps that Radau took
    final_state: np.ndarray


@dataclass(frozen=True)
class RawPhases(RawSolution):
    """What the compiled stick–slip loop returns: a :class:`RawSolution` of the whole
    run (its sample times as the phases report them) plus the phases.

    ``sample_phase`` holds each sample's phase (a ``PhaseKind`` code); ``phase_kind``,
    ``phase_start``, ``phase_end`` [s] and ``phase_energy_jump`` [J] one entry per phase.
    """

    sample_phase: np.ndarray
    phase_kind: np.ndarray  # PhaseKind codes
    phase_start: np.ndarray
    phase_end: np.ndarray
    phase_energy_jump: np.ndarray
    rejected_captures: int


def _method_code(name: str) -> int:
    if name not in METHODS:
        raise ParameterError("method", name, "one of: " + ", ".join(METHODS))
    return METHODS[name]


def _trimmed(end: RunEnd, output: Output) -> dict[str, Any]:
    """The fields of :class:`RawSolution` from a run's end and its output arrays."""
    stored = min(int(end.n_crossings), output.crossings.shape[0])
    stats = output.stats
    return {
        "status": int(end.status),
        "t_stop": float(end.t_stop),
        "sample_times": output.sample_times[: end.n_samples].copy(),
        "samples": output.samples[: end.n_samples].copy(),
        "crossings": output.crossings[:stored].copy(),
        "n_crossings_total": int(end.n_crossings),
        "min_normal_force": float(end.min_normal_force),
        "t_min_normal_force": float(end.t_min_normal_force),
        "nfev": int(stats[STAT_NFEV]),
        "njev": int(stats[STAT_NJEV]),
        "nlu": int(stats[STAT_NLU]),
        "n_accepted": int(stats[STAT_ACCEPTED]),
        "n_rejected": int(stats[STAT_REJECTED]),
        "n_switches": int(stats[STAT_SWITCHES]),
        "n_radau_steps": int(stats[STAT_RADAU_STEPS]),
        "final_state": output.final_state,
    }


def raw_solution(end: RunEnd, output: Output) -> RawSolution:
    """The :class:`RawSolution` of a run of ``driver.run_loop`` that ended with ``end``
    into ``output``: :func:`solve`'s, and a GPU thread's (``batch_cuda.run_whole``)."""
    return RawSolution(**_trimmed(end, output))


def raw_phases(
    ended: tuple[RunEnd, int, int], output: Output, log: PhaseLog, max_crossings: int
) -> RawPhases:
    """The :class:`RawPhases` of a run of ``phases.phase_loop`` that ended with ``ended``
    (its ``RunEnd``, phases logged, rejected captures) into ``output`` and ``log``, at
    most ``max_crossings`` crossings kept: :func:`solve_phases`'s, and a GPU thread's
    (``batch_cuda.run_whole``)."""
    end, n_phases, rejected = ended
    n_phases = int(n_phases)
    fields = _trimmed(end, output)
    fields["sample_times"] = log.sample_times[: end.n_samples].copy()
    fields["crossings"] = fields["crossings"][:max_crossings]
    return RawPhases(
        **fields,
        sample_phase=log.sample_phase[: end.n_samples].copy(),
        phase_kind=log.kind[:n_phases].copy(),
        phase_start=log.start[:n_phases].copy(),
        phase_end=log.end[:n_phases].copy(),
        phase_energy_jump=log.energy_jump[:n_phases].copy(),
        rejected_captures=int(rejected),
    )


def solve(
    model: int,
    method_name: str,
    params: Any,
    y0: np.ndarray,
    t_end: float,
    *,
    rtol: float,
    atol: float,
    sample_times: np.ndarray,
    max_crossings: int = 10_000,
    first_step: float = 0.0,
    max_step: float = 0.0,
    max_steps: int = 10_000_000,
    adaptive: bool = True,
    capture_speed: float = 0.0,
    progress: Callable[[float], None] | None = None,
) -> RawSolution:
    """Integrate the kernel system ``model`` from t = 0 to ``t_end`` with ``method_name``.

    ``params`` is the kernel parameter record, passed to the kernels unread.
    ``capture_speed`` [m/s] > 0 stops a sliding run (status ``STATUS_PHASE_CHANGE``)
    when sqrt(|V1|² + ε²(ω·n)²) falls below it; a stick run (``MODEL_STICK``) always
    stops when its stick margin falls below zero. ``final_state`` is the state at
    ``t_stop``. ``progress``, if given, is called about ten times a second from this
    thread with the time [s] reached, while the compiled loop runs in another; if it
    raises, the loop stops at its next step and the exception is raised here.
    """
    method = _method_code(method_name)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    output = new_output(sample_times, y0.shape[0], max_crossings)
    controls = Controls(
        float(rtol), float(atol), float(first_step), float(max_step), int(max_steps), bool(adaptive)
    )
    table = event_table(int(model), float(capture_speed))
    arguments = (int(model), method, params, y0, float(t_end), controls, table, output)
    link, to_rhs = integrate_link(arguments)  # compiled for this model and method
    end = _run(integrate_at, (link, (*arguments, to_rhs)), output, progress)
    return raw_solution(end, output)


def solve_phases(
    params: Any,
    y0: np.ndarray,
    t_end: float,
    *,
    slip_method: str,
    stick_method: str,
    rtol: float,
    atol: float,
    capture_speed: float,
    sample_times: np.ndarray,
    max_crossings: int,
    max_steps: int,
    max_phases: int = DEFAULT_MAX_PHASES,
    progress: Callable[[float], None] | None = None,
) -> RawPhases:
    """Integrate the hybrid (stick–slip) contact over [0, t_end] with the compiled phase
    loop ``phases.run_phases``; ``max_phases`` is the capacity of its phase log.

    ``progress`` is called as in :func:`solve`, with the time reached over all phases.
    """
    hybrid = HybridSettings(
        _method_code(slip_method), _method_code(stick_method), float(capture_speed)
    )
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    output = new_output(sample_times, y0.shape[0], max_crossings)
    log = new_phase_log(output.sample_times.shape[0], max_phases)
    controls = Controls(float(rtol), float(atol), 0.0, 0.0, int(max_steps), True)
    links = integrate_links(params, hybrid, controls, output)
    arguments = (params, y0, float(t_end), hybrid, controls, output, log, links)
    end, n_phases, rejected = _run(run_phases, arguments, output, progress)
    return raw_phases((end, n_phases, rejected), output, log, max_crossings)


_POLL_INTERVAL = 0.1  # s between progress reports
# s to wait for a stopped loop's thread: it returns before its next step, but a loop that
# is still compiling (a first stick–slip run) finishes that first, then stops at once
_STOP_WAIT = 5.0


def _run(
    function: Callable[..., Any],
    arguments: tuple[Any, ...],
    output: Output,
    progress: Callable[[float], None] | None,
) -> Any:
    """``function(*arguments)``; with ``progress``, compiled (or loaded) in this thread,
    then run in a daemon thread (the compiled loops release the GIL) while this thread
    reports the last sample time written, read from ``output.stats``.

    When ``progress`` raises, or Ctrl-C arrives while this thread waits, the compiled
    loop is asked to stop (``_stop.request_stop``: it returns before its next step with
    ``STATUS_STOPPED``), its thread is waited for, and the exception is raised again.
    """
    if progress is None:
        return function(*arguments)
    # compiled here, first: a stop request reaches a loop that runs, not one that compiles
    compile_for(function, arguments)
    outcome: dict[str, Any] = {}

    def work() -> None:
        try:
            outcome["returned"] = function(*arguments)
        except BaseException as error:  # re-raised in the caller's thread
            outcome["error"] = error

    thread = threading.Thread(target=work, name="celtstone-run", daemon=True)
    thread.start()
    times, stats = output.sample_times, output.stats
    try:
        while thread.is_alive():
            thread.join(_POLL_INTERVAL)
            written = int(stats[STAT_SAMPLES_WRITTEN])
            progress(float(times[written - 1]) if written > 0 else 0.0)
    except BaseException:
        request_stop(stats)
        thread.join(_STOP_WAIT)
        raise
    if "error" in outcome:
        raise outcome["error"]
    return outcome["returned"]


def capture(params: Any, y: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The state after the capture impulse, its energy jump [J] and its stick margin [1].

    The energy removed by the impulse is added to the dissipated work, so that
    E + W stays E(0) across the switch (``phases.capture``).
    """
    captured = np.empty_like(y)
    jump, margin = phases.capture(params, np.ascontiguousarray(y, dtype=np.float64), captured)
    return captured, float(jump), float(margin)
