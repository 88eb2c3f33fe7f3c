"""The stick–slip phase loop of the hybrid contact, compiled (docs/decisions.md §16).

``run_phases`` alternates two phases, each integrated by ``driver.integrate`` until its
terminal phase event (``_events``):

* slip: the sliding model with the capture event, the slip–spin speed
  sqrt(|V1|² + ε²(ω · n)²) falling below the capture speed v_c. Stick starts there if
  the stick margin is >= 0 after the capture impulse (``kernels.stick.capture_state``,
  its energy jump moved into the dissipated work W so that E + W = E(0)); else sliding
  goes on from the same state (a rejected capture) and the phase log's slip phase grows.
* stick: rolling without sliding and without pivoting (``MODEL_STICK``) until the
  stick margin falls below zero; sliding restarts from that state.

Each phase runs from its own t = 0 (its sample times and t_end shifted by its start
t0, its crossings and times shifted back), exactly as the Python loop it replaces, so
the results are the same to the last bit. Samples, crossings and the counters of
``stats`` continue from phase to phase in the caller's arrays; phases are written to a
preallocated :class:`_structures.PhaseLog` whose length is the capacity: a run that
needs one more phase stops with ``STATUS_MAX_PHASES`` where that phase would start.
A stop request (``_stop``) ends the phase under way with ``STATUS_STOPPED``, and so
the run.
The function releases the GIL, so sweeps run it on threads and Dask workers.

The loop itself, ``phase_loop``, allocates nothing: ``run_phases`` allocates its
buffers (:class:`PhaseBuffers`) and calls it, as ``driver.integrate`` calls
``driver.run_loop``; a sweep's CUDA thread calls it on arrays of its own
(``batch_cuda``). Each phase is integrated by :func:`integrate_phase`: on the CPU,
``driver.integrate`` at its link (``solvers._linking``); on a thread, ``driver.run_loop``
on the thread's arrays, which ``batch_cuda`` puts in its place while the thread's code
compiles, as it puts the kernels' right-hand side in place of ``_system``'s.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import MODEL_SLIDING, MODEL_STICK, Y_WORK
from celtstone.kernels.stick import capture_state, slip_spin_speed
from celtstone.kernels.system import energy, phase_value
from celtstone.solvers._compile import inlined
from celtstone.solvers._events import event_table
from celtstone.solvers._structures import Controls, HybridSettings, Output, RunEnd
from celtstone.solvers.codes import DEFAULT_MAX_PHASES as DEFAULT_MAX_PHASES
from celtstone.solvers.codes import (
    STAT_ACCEPTED,
    STAT_REJECTED,
    STATUS_MAX_PHASES,
    STATUS_MAX_STEPS,
    STATUS_PHASE_CHANGE,
    STATUS_SUCCESS,
    PhaseKind,
)
from celtstone.solvers.driver import call_integrate, copy_into, integrate_link

# the compiled loop reads plain ints (a global folds to its integer)
SLIP = int(PhaseKind.SLIP)
STICK = int(PhaseKind.STICK)


def integrate_links(
    params: np.ndarray, hybrid: HybridSettings, controls: Controls, output: Output
) -> tuple[tuple[int, int], tuple[int, int], tuple[int, int]]:
    """The links to ``driver.integrate`` for slip (the sliding model, the slip method)
    and stick (the stick model, the stick method), for the arguments ``run_phase``
    passes it, from a run's parameter record, settings, controls and output, and the
    link to the right-hand side that both take (``rhs_link``; Python side; compiles or
    loads them). Both phases run the loop for every code, compiled once
    (``driver.integrate_link``)."""
    state = np.zeros(output.final_state.shape[0])
    links = []
    for model, method in (
        (MODEL_SLIDING, hybrid.slip_method),
        (MODEL_STICK, hybrid.stick_method),
    ):
        table = event_table(model, 1.0)
        arguments = (model, int(method), params, state, 0.0, controls, table, output)
        links.append(integrate_link(arguments, own_loop=False))
    return links[0][0], links[1][0], links[0][1]


@kernel
def capture(params, y, out):
    """``out`` = ``y`` after the capture impulse that starts stick.

    Returns (the kinetic-energy jump of the impulse [J], <= 0, which is also taken from
    ``out``'s dissipated work so that E + W is unchanged; the stick margin there [1]).
    """
    capture_state(y, params, out)
    # the codes as values: the versions for every code that the run's events and
    # summary compile serve them, where each constant compiled one more
    stick, sliding = np.int64(MODEL_STICK), np.int64(MODEL_SLIDING)
    jump = energy(stick, out, params) - energy(sliding, y, params)
    out[Y_WORK] -= jump
    return jump, phase_value(stick, out, params, 0.0)


@inlined
def first_phase(params, y, capture_speed, captured):
    """The phase a run starts in: stick if ``y`` neither slides nor pivots (slip–spin
    speed <= v_c) and stick is admissible after the capture impulse (then ``y`` becomes
    the captured state). Returns (kind, energy jump [J]).

    Inlined into the phase loop, which calls :func:`capture` too: compiled apart, it
    linked and optimised ``capture``'s code once more."""
    if slip_spin_speed(y, params) <= capture_speed:
        jump, margin = capture(params, y, captured)
        if margin >= 0.0:
            copy_into(y, captured)
            return STICK, jump
    return SLIP, 0.0


class PhaseBuffers(NamedTuple):
    """The arrays :func:`phase_loop` works in besides the run's output and phase log, its
    caller's (``run_phases`` allocates them; a GPU thread, which cannot, takes them from its
    local and global memory).

    Parameters
    ----------
    y : the state, shape (n,); holds the initial state when the loop starts
    captured : the state after a capture impulse, shape (n,)
    phase_times : a phase's sample times in its own time [s], shape (m,) (m samples)
    spare_crossings : a phase's crossings once the run's are full, shape (1,)
    slip_table, stick_table : the events of slip (the capture event at v_c) and of stick
        (``_events.event_table``)
    """

    y: np.ndarray
    captured: np.ndarray
    phase_times: np.ndarray
    spare_crossings: np.ndarray
    slip_table: np.ndarray
    stick_table: np.ndarray


@inlined
def integrate_phase(integrator, kind, model, method, params, y, t_end, controls, table, output):
    """Integrate a phase of ``kind`` (its ``model`` and ``method``) from ``y`` over
    [0, t_end] [s] into ``output`` with ``driver.integrate`` at its link: ``integrator``
    holds the links of :func:`integrate_links` (slip, stick, right-hand side). Returns
    the ``RunEnd``. (A GPU thread's twin calls ``driver.run_loop`` on its own arrays:
    ``batch_cuda``.)"""
    link = integrator[1] if kind == STICK else integrator[0]
    arguments = (model, method, params, y, t_end, controls, table, output, integrator[2])
    return call_integrate(link, arguments)


@kernel
def run_phase(
    params, y, t0, t_end, kind, hybrid, controls, output, first_sample, first_crossing, buffers,
    integrator,
):  # fmt: skip
    """Integrate one phase of ``kind`` from state ``y`` at t0 [s] in its own time from 0,
    with ``controls`` (the phase's: ``max_steps`` the steps left to the run), by
    :func:`integrate_phase` with ``integrator``; its samples go to ``output`` from
    ``first_sample``, its crossings from ``first_crossing`` (to ``buffers``' spare once
    ``output.crossings`` is full). Returns (``RunEnd``, its shifted sample times, its
    crossing buffer)."""
    model = MODEL_STICK if kind == STICK else MODEL_SLIDING
    method = hybrid.stick_method if kind == STICK else hybrid.slip_method
    n_times = output.sample_times.shape[0] - first_sample
    times = buffers.phase_times[:n_times]
    for i in range(n_times):
        times[i] = output.sample_times[first_sample + i] - t0
    crossings = buffers.spare_crossings  # the run's crossings are full
    if first_crossing < output.crossings.shape[0]:
        crossings = output.crossings[first_crossing:]
    phase_output = Output(
        times, output.samples[first_sample:], crossings, output.stats, output.final_state
    )
    table = buffers.stick_table if kind == STICK else buffers.slip_table
    end = integrate_phase(
        integrator, kind, model, method, params, y, t_end - t0, controls, table, phase_output
    )
    return end, times, crossings


@kernel
def run_phases(params, y0, t_end, hybrid, controls, output, log, integrate_links):
    """Integrate the hybrid contact over [0, t_end] [s]; see the module docstring.

    Parameters
    ----------
    params : kernel parameter record, passed on unread
    y0 : initial state, shape (N_STATE,)
    t_end : end time [s]
    hybrid : ``_structures.HybridSettings``: the methods of slip and stick, v_c [m/s] > 0
    controls : ``_structures.Controls``; ``max_steps`` bounds the steps of all phases
    output : ``_structures.Output`` over the whole run, filled
    log : ``_structures.PhaseLog``, filled
    integrate_links : the links to ``driver.integrate`` for slip and stick and its
        ``rhs_link`` that :func:`integrate_links` makes from the run's parameter
        record, settings, controls and output (``solvers._linking``)

    Returns
    -------
    (``RunEnd`` of the whole run, phases logged, rejected captures)
    """
    n = y0.shape[0]
    buffers = PhaseBuffers(
        y0.copy(),
        np.empty(n),
        np.empty(output.sample_times.shape[0]),
        np.empty(1),
        # the codes as values: the table for every code that ``integrate_links`` makes
        # serves both, where each constant compiled it once more
        event_table(np.int64(MODEL_SLIDING), hybrid.capture_speed),
        event_table(np.int64(MODEL_STICK), 0.0),
    )
    return phase_loop(params, t_end, hybrid, controls, output, log, buffers, integrate_links)


@inlined
def phase_loop(params, t_end, hybrid, controls, output, log, buffers, integrator):
    """The loop of :func:`run_phases` from the state ``buffers.y`` (overwritten) in the
    caller's ``buffers`` (:class:`PhaseBuffers`), which it does not allocate, each phase
    integrated by :func:`integrate_phase` with ``integrator``: a CUDA thread runs it too
    (``batch_cuda``). Returns (``RunEnd``, phases logged, rejected captures)."""
    stats = output.stats
    y = buffers.y
    captured = buffers.captured
    kind, jump = first_phase(params, y, hybrid.capture_speed, captured)
    t0 = 0.0
    t_stop = 0.0
    # counters typed int64 from the start: the literal 0 would compile ``run_phase`` once
    # more for the first phase's constant offsets (``Literal[int](0)``)
    n_samples = np.int64(0)
    n_crossings = 0
    n_stored = np.int64(0)
    n_phases = 0
    min_normal = np.inf
    t_min_normal = 0.0
    rejected = 0
    status = STATUS_SUCCESS
    while True:
        steps_left = controls.max_steps - stats[STAT_ACCEPTED] - stats[STAT_REJECTED]
        if steps_left <= 0:
            status = STATUS_MAX_STEPS
            break
        is_new = n_phases == 0 or log.kind[n_phases - 1] != kind
        if is_new and n_phases == log.kind.shape[0]:
            status = STATUS_MAX_PHASES
            break
        phase_controls = Controls(  # the run's, with the steps it has left
            controls.rtol,
            controls.atol,
            controls.first_step,
            controls.max_step,
            steps_left,
            controls.adaptive,
        )
        end, times, crossings = run_phase(
            params,
            y,
            t0,
            t_end,
            kind,
            hybrid,
            phase_controls,
            output,
            n_samples,
            n_stored,
            buffers,
            integrator,
        )
        for i in range(end.n_samples):
            log.sample_times[n_samples + i] = times[i] + t0
            log.sample_phase[n_samples + i] = kind
        n_samples += end.n_samples
        if n_stored < output.crossings.shape[0]:
            stored = min(end.n_crossings, crossings.shape[0])
            for k in range(stored):
                crossings[k] += t0
            n_stored += stored
        n_crossings += end.n_crossings
        if end.min_normal_force < min_normal:
            min_normal = end.min_normal_force
            t_min_normal = end.t_min_normal_force + t0
        t_stop = t0 + end.t_stop
        if is_new:
            log.kind[n_phases] = kind
            log.start[n_phases] = t0
            log.energy_jump[n_phases] = jump
            n_phases += 1
        else:  # sliding went on after a capture where stick was not admissible
            log.energy_jump[n_phases - 1] = 0.0
        log.end[n_phases - 1] = t_stop
        if end.status != STATUS_PHASE_CHANGE:
            status = end.status
            break
        t0 = t_stop
        copy_into(y, output.final_state)
        jump = 0.0
        if t0 >= t_end:
            break
        if kind == STICK:
            kind = SLIP
            continue
        capture_jump, margin = capture(params, y, captured)
        if margin >= 0.0:
            copy_into(y, captured)
            kind = STICK
            jump = capture_jump
        else:
            rejected += 1
    run = RunEnd(status, int(n_samples), n_crossings, t_stop, min_normal, t_min_normal)
    return run, n_phases, rejected
