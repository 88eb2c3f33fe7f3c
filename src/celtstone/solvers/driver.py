"""The compiled integration loop shared by every method: stepping, sampling, events, stopping.

``integrate`` runs entirely in numba: no Python per step. It asks the run's method
(``_methods``, the integrator contract) for one accepted step at a time, checks the
accepted state (finite, a right-hand side that applies, its normal force and spin),
locates the events of the run's table inside the step (``_events``: lift-off, phase
change of the hybrid contact, spin zero crossings), fills the output samples that fall
inside the step from the method's dense output, and stops at t_end, at a terminal
event, at a singular or off-shape right-hand side, on integrator failure, or when
another thread asks it to (``_stop``). Its loop, ``run_loop``, allocates nothing: a sweep's
CUDA thread runs the same loop on arrays of its own (``batch_cuda``).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple, cast

import numpy as np
from numba import types
from numba.core.typing.typeof import typeof
from numba.extending import overload

from celtstone.kernels._internals import internals_changed
from celtstone.kernels._jit import compiling, kernel, kernel_options
from celtstone.kernels.layout import (
    RHS_CONTACT_RANGE,
    RHS_NON_CONVEX,
    RHS_OFF_SHAPE,
    RHS_OK,
    RHS_SINGULAR,
    ModelCode,
)
from celtstone.solvers import _events as events
from celtstone.solvers import _methods as methods
from celtstone.solvers._compile import inlined
from celtstone.solvers._linking import NO_LINK, address_call, cached_link_to, link_to
from celtstone.solvers._step_control import initial_step
from celtstone.solvers._stop import stop_requested
from celtstone.solvers._structures import RunEnd
from celtstone.solvers._system import cached_rhs_link, rhs, rhs_link, spin_and_normal_force
from celtstone.solvers.codes import (
    METHOD_AUTO,
    METHOD_ENTRIES,
    METHOD_RADAU5,
    METHODS,
    STAT_ACCEPTED,
    STAT_NFEV,
    STAT_RADAU_STEPS,
    STAT_SAMPLES_WRITTEN,
    STATUS_CONTACT_RANGE,
    STATUS_LIFT_OFF,
    STATUS_MAX_STEPS,
    STATUS_NON_CONVEX,
    STATUS_NOT_FINITE,
    STATUS_OFF_SHAPE,
    STATUS_SINGULAR,
    STATUS_STOPPED,
    STATUS_SUCCESS,
    STATUS_UNKNOWN_CODE,
)


@kernel
def rhs_failure(code):
    """Run status for a right-hand-side status code other than ``RHS_OK``."""
    if code == RHS_SINGULAR:
        return STATUS_SINGULAR
    if code == RHS_OFF_SHAPE:
        return STATUS_OFF_SHAPE
    if code == RHS_NON_CONVEX:
        return STATUS_NON_CONVEX
    if code == RHS_CONTACT_RANGE:
        return STATUS_CONTACT_RANGE
    # RHS_UNKNOWN_CODE, and an rhs status this function does not know, which is one too
    return STATUS_UNKNOWN_CODE


@inlined
def all_finite(values):
    """Whether every entry of ``values`` is finite."""
    for j in range(values.shape[0]):
        if not math.isfinite(values[j]):
            return False
    return True


@inlined
def copy_into(target, source):
    """``target[:] = source`` for 1-d arrays, as a loop: numba's CUDA lowering copies no
    array into a slice, and a GPU thread runs this loop too (a slice copy on the CPU also
    compiles numba's shape checks and their messages, some 20 functions, for a first run)."""
    for j in range(source.shape[0]):
        target[j] = source[j]


@inlined
def copy_into_row(rows, row, source):
    """``rows[row, :] = source``, as :func:`copy_into` (a loop)."""
    for j in range(source.shape[0]):
        rows[row, j] = source[j]


@inlined
def fill_samples(step, t_limit, sample_times, samples, n_samples, y_end):
    """Fill the samples with times in (t_old, t_limit] from the step's interpolant, the
    accepted state ``y_end`` exactly at the step's end; returns the new count."""
    while n_samples < sample_times.shape[0] and sample_times[n_samples] <= t_limit:
        time = sample_times[n_samples]
        if time == step.t_old + step.h:
            copy_into_row(samples, n_samples, y_end)
        else:
            x = (time - step.t_old) / step.h
            methods.interpolate_apart(step.method, step.dense, step.y_old, x, samples[n_samples])
        n_samples += 1
    return n_samples


@inlined
def sample_inside(step, t_new, sample_times, n_samples):
    """Whether a sample waits in (t_old, t_new] [s] at another time than the step's end:
    ``fill_samples`` would read the step's interpolant."""
    while n_samples < sample_times.shape[0] and sample_times[n_samples] <= t_new:
        if sample_times[n_samples] != step.t_old + step.h:
            return True
        n_samples += 1
    return False


@inlined
def first_check(model, params, y, f, output):
    """The first state: f(0, y), samples at times <= 0, and why the run cannot start.

    Returns (status, samples written, normal force [N]). Inlined, as
    :func:`first_step` and :func:`stop_at` are: each runs once a run, and compiled apart
    each was a compile of its own that linked its callees' code again.
    """
    code, normal_force = rhs(model, 0.0, y, params, f)
    output.stats[STAT_NFEV] += 1
    copy_into(output.final_state, y)
    n_samples = 0
    times = output.sample_times
    while n_samples < times.shape[0] and times[n_samples] <= 0.0:
        copy_into_row(output.samples, n_samples, y)
        n_samples += 1
    status = STATUS_SUCCESS
    if not (all_finite(y) and all_finite(f)):
        status = STATUS_NOT_FINITE
    if code != RHS_OK:
        status = rhs_failure(code)
    elif normal_force < 0.0:
        status = STATUS_LIFT_OFF
    return status, n_samples, normal_force


@inlined
def first_step(method, model, params, y, f, controls, scratch, f_scratch, stats):
    """The first step size [s]: ``controls.first_step``, else Hairer's heuristic, at
    most ``controls.max_step``."""
    if controls.first_step > 0.0:
        h = controls.first_step
    else:
        order = methods.error_order(method)
        h = initial_step(
            model, params, y, f, order, controls.rtol, controls.atol, scratch, f_scratch
        )
        stats[STAT_NFEV] += 1
    if controls.max_step > 0.0:
        h = min(h, controls.max_step)
    return h


class LoopArrays(NamedTuple):
    """The arrays :func:`run_loop` works in besides the state, its caller's (``integrate``
    allocates them; a GPU thread, which cannot, takes them from its local memory).

    Parameters
    ----------
    f, y_new, f_new : dy/dt at the state, the step's new state and its dy/dt, shape (n,)
    point, scratch : a state on the interpolant and scratch, shape (n,)
    values : the event table's values at the state, shape (rows,)
    work : the methods' workspaces (``_methods.Workspaces``)
    dense_of : every method's interpolant coefficients by method code
        (``_methods.dense_arrays``), looked up once per run
    """

    f: np.ndarray
    y_new: np.ndarray
    f_new: np.ndarray
    point: np.ndarray
    scratch: np.ndarray
    values: np.ndarray
    work: Any
    dense_of: Any


def run_workspaces(method: int, n: int) -> Any:
    """The run loop's workspaces (``_methods.Workspaces``) for a run of ``method`` on
    states of length n: ``_methods.workspaces``; compiled for a method of
    ``OWN_LOOP_METHODS`` as a constant, its own workspace in every slot."""
    return methods.workspaces(method, n)


# compiled with a kernel's options, apart: inlined (numba's typed inlining of an
# overload), the loop for every code took other steps in a stick–slip run
@overload(run_workspaces, prefer_literal=True, jit_options=cast(Any, kernel_options()))
def _run_workspaces_typed(method, n):
    """:func:`run_workspaces` in compiled code, chosen by the type of ``method``.

    A loop compiled for an explicit method as a constant reads that method's workspace
    alone (the other methods' branches are removed before typing, ``kernels._pruning``),
    so the other slots hold it too: every method's empty workspace, Radau's complex and
    integer arrays and records and ``auto``'s record, compiled numba's allocation for
    five more types of array and the function that made them (about 1 s of a first
    rolling run's CPU)."""
    code = method.literal_value if isinstance(method, types.IntegerLiteral) else None
    if code not in OWN_LOOP_METHODS:  # ``_methods.workspaces``' own code, compiled here
        return cast(Any, methods.workspaces).py_func
    own_workspace = methods.MODULES[code].workspace

    def one_method(method, n):
        own = own_workspace(n)
        return methods.Workspaces(own, own, own, own)

    return one_method


@kernel
def integrate(model, method, params, y0, t_end, controls, table, output, rhs_link):
    """Integrate from t = 0 to ``t_end`` [s]; see the module docstring.

    Parameters
    ----------
    model : model code (``kernels.layout``)
    method : method code (``codes.METHODS``)
    params : kernel parameter record, passed to the kernels unread
    y0 : initial state, shape (N_STATE,)
    t_end : end time [s]
    controls : ``_structures.Controls``
    table : event table (``_events.event_table``)
    output : ``_structures.Output``, filled; ``output.stats`` is added to, its slot
        ``STAT_SAMPLES_WRITTEN`` after every step (read while the loop runs: progress);
        its slot ``STAT_STOP_REQUESTED`` read before every step (set from another
        thread, the run stops with ``STATUS_STOPPED`` at the state it reached)
    rhs_link : the link to the right-hand side compiled for ``params``
        (``_system.rhs_link``; for ``model`` as a constant where it is one)

    Returns
    -------
    ``_structures.RunEnd``
    """
    n = y0.shape[0]
    work = run_workspaces(method, n)
    # the interpolants' arrays looked up once, and the whole workspace handed only to
    # the helpers that need it: per step, those lookups and hand-overs cost about 10 %
    # of a rolling run (docs/decisions.md §43)
    arrays = LoopArrays(
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(n),
        np.zeros(table.shape[0]),
        work,
        methods.dense_arrays(work),
    )
    system = (params, rhs_link)  # as ``_system.rhs`` takes it: the methods' ``params``
    return run_loop(model, method, system, y0.copy(), t_end, controls, table, output, arrays)


@inlined
def run_loop(model, method, system, y, t_end, controls, table, output, arrays):
    """The loop of :func:`integrate` from ``y`` (overwritten) on the run's ``system``
    (as ``_system.rhs`` takes it) and ``arrays`` (:class:`LoopArrays`), which it does not
    allocate: a CUDA thread runs it too (``batch_cuda``). Returns the ``RunEnd``."""
    f, y_new, f_new, point, scratch, values, work, dense_of = arrays
    stats = output.stats
    samples_before = stats[STAT_SAMPLES_WRITTEN]
    status, n_samples, normal_old = first_check(model, system, y, f, output)
    if status == STATUS_SUCCESS and not methods.is_known(method):
        status = STATUS_UNKNOWN_CODE
    stats[STAT_SAMPLES_WRITTEN] = samples_before + n_samples
    if status != STATUS_SUCCESS:
        return RunEnd(status, n_samples, 0, 0.0, normal_old, 0.0)
    min_normal = normal_old
    t_min_normal = 0.0
    events.start_values(table, model, system, y, values, scratch)
    switching = work.auto
    rate = events.spin_rate(y, f)
    h = first_step(method, model, system, y, f, controls, scratch, f_new, stats)
    methods.start(method, model, system, 0.0, y, f, h, controls, work, stats)
    n_crossings = 0
    t = 0.0
    steps = 0
    stopped = False
    while t < t_end:
        if stop_requested(stats):  # another thread asked (``solvers._stop``)
            status = STATUS_STOPPED
            break
        if steps >= controls.max_steps:
            status = STATUS_MAX_STEPS
            break
        steps += 1
        stepper = methods.active(method, switching)  # the method that takes this step
        status, h_taken, h_next, code, normal_new = methods.attempt(
            method, stepper, model, system, t, y, f, h, t_end, controls, work, y_new, f_new, stats
        )
        if status != STATUS_SUCCESS:
            break
        if not all_finite(y_new):
            status = STATUS_NOT_FINITE
            break
        t_new = t_end if h_taken == t_end - t else t + h_taken
        stats[STAT_ACCEPTED] += 1
        if stepper == METHOD_RADAU5:
            stats[STAT_RADAU_STEPS] += 1
        spin_new = events.spin_of(y_new)
        rate_new = events.spin_rate(y_new, f_new)
        if code != RHS_OK:
            status = rhs_failure(code)
            break
        step = events.Step(stepper, dense_of[stepper], y, t, h_taken)
        all_decided = events.all_decided_by_ends(
            table, values, spin_new, normal_new, rate, rate_new, h_taken
        )
        # the interpolant only where a sample or an event reads it (contract item 7)
        if (
            methods.dense_every_step(stepper)
            or not all_decided
            or sample_inside(step, t_new, output.sample_times, n_samples)
        ):
            methods.dense(stepper, model, system, t, y, y_new, h_taken, work, stats)
        if all_decided:
            stop_row, x_limit, t_limit, n_crossings = events.take_ends(
                table, values, spin_new, normal_new, step, t_new, n_crossings
            )
        else:
            stop_row, x_limit, t_limit, n_crossings = events.scan_rows(
                table,
                values,
                spin_new,
                normal_new,
                model,
                system,
                step,
                t_new,
                output.crossings,
                n_crossings + 0,  # an int: the loop's count starts as the constant 0, for
                point,  # which numba would compile scan_rows once more
                scratch,
            )
        n_samples = fill_samples(
            step, t_limit, output.sample_times, output.samples, n_samples, y_new
        )
        stats[STAT_SAMPLES_WRITTEN] = samples_before + n_samples
        if stop_row >= 0:
            status = table[stop_row].status
            min_normal, t_min_normal = stop_at(
                table[stop_row],
                model,
                system,
                step,
                x_limit,
                t_limit,
                y_new,
                output,
                min_normal,
                t_min_normal,
                scratch,
            )
            t = t_limit
            stopped = True
            break
        if normal_new < min_normal:
            min_normal = normal_new
            t_min_normal = t_new
        copy_into(y, y_new)
        copy_into(f, f_new)
        rate = rate_new
        t = t_new
        h = h_next
        if controls.max_step > 0.0:
            h = min(h, controls.max_step)
        if method == METHOD_AUTO:  # only a switching run hands over its workspace here
            methods.after_step(method, model, system, t, y, f, h, controls, work, stats)
    if not stopped:
        copy_into(output.final_state, y)
    return RunEnd(status, n_samples, n_crossings, t, min_normal, t_min_normal)


@inlined
def stop_at(
    event, model, params, step, x_limit, t_limit, y_end, output, min_normal, t_min_normal, work
):
    """The state where a terminal ``event`` stops the run into ``output.final_state``;
    returns the smallest normal force [N] and its time [s] including that state (a
    lift-off root is N = 0). Once a run, inlined as :func:`first_check` is: it holds
    little code of its own (the interpolant and the right-hand side are calls), and
    compiled apart it linked and optimised theirs once more."""
    if x_limit >= 1.0:
        copy_into(output.final_state, y_end)
    else:
        methods.interpolate_apart(step.method, step.dense, step.y_old, x_limit, output.final_state)
    if event.value == events.VALUE_NORMAL_FORCE:
        return min(min_normal, 0.0), t_limit
    normal_force = spin_and_normal_force(model, output.final_state, params, work)[1]
    if normal_force < min_normal:
        return normal_force, t_limit
    return min_normal, t_min_normal


RUN_END_TYPE = typeof(RunEnd(0, 0, 0, 0.0, 0.0, 0.0))  # integrate's return type in numba
# integrate's arguments compiled as constants; none where numba's own compiler runs,
# which would compile every branch for each (``kernels._internals``)
MODEL_AND_METHOD = () if internals_changed() else (0, 1)
call_integrate = address_call(integrate, returns=RUN_END_TYPE)  # see ``solvers._linking``


# The methods whose run loops are compiled for a model and method as constants (a first
# rolling run with vern9: about 12 s of CPU on a 2-core machine, empty cache), taken
# wherever they are compiled, and compiled where the loop for every code is not. A loop
# of auto or radau5 holds most of the code of every method and compiles nearly as long
# as the model's loop with the method a value, which serves every method of that model:
# those runs compile that one (the sliding model: about 26 s; the loop for every code,
# with every model's branches and right-hand side, about 34 s). The registry's entries
# say which (``own_loop``).
OWN_LOOP_METHODS = tuple(entry.code for entry in METHOD_ENTRIES.values() if entry.own_loop)
# CPU seconds of a first compile on the 2-core machine (benchmarks/bench_cold_start.py)
OWN_LOOP_SECONDS = 13.0
MODEL_LOOP_SECONDS = 28.0
EVERY_CODE_SECONDS = 36.0
RHS_SECONDS = 3.0  # a right-hand side alone, for new codes: rolling 1 s, sliding 3 s


def integrate_link(
    arguments: tuple[Any, ...], own_loop: bool = True, codes_vary: bool = False
) -> tuple[tuple[int, int], tuple[int, int]]:
    """The link to ``integrate`` for ``arguments`` and its ``rhs_link`` argument, as
    ``integrate`` is called with ``(*arguments, rhs_link)`` (Python side; loads or
    compiles it, saying so on a terminal when it compiles).

    With ``own_loop``, the loop compiled for ``arguments``' model as a constant and,
    for a method of ``OWN_LOOP_METHODS``, its method too (``MODEL_AND_METHOD``), which
    holds only their branches, if it and its right-hand side are compiled (in this
    process or numba's cache); else the loop for every model and method code if it is
    compiled (``celtstone compile``, a stick–slip run); else, with ``own_loop``, the
    run's own loop, compiled now; else the loop for every code, compiled now (the
    stick–slip loop's two phases call one loop). Each calls the right-hand side at
    ``rhs_link`` (``_system``), compiled for the model as a constant in a loop for one
    model, and the record's codes (``_system.RUN_CODES``) too unless ``codes_vary`` (a
    sweep whose points differ in one).

    A run's own loop is faster than the loop for every code; where its right-hand side
    for the record's codes is not compiled (a body shape or law no run had), the loop
    for every code serves, compiling nothing, wherever it is compiled.
    """
    placeholder = (*arguments, NO_LINK)  # for the argument types
    model, method = int(arguments[0]), int(arguments[1])
    own = own_loop and bool(MODEL_AND_METHOD)
    constants = MODEL_AND_METHOD if method in OWN_LOOP_METHODS else MODEL_AND_METHOD[:1]
    own_link = None
    if own:
        own_link = cached_link_to(integrate, placeholder, constants)
        if own_link is not None:
            to_rhs = cached_rhs_link(arguments[2], model, codes=not codes_vary)
            if to_rhs is not None:
                return own_link, to_rhs
    every_code = cached_link_to(integrate, placeholder)
    if every_code is not None:
        return every_code, rhs_link(arguments[2])
    if own:
        seconds = RHS_SECONDS if own_link is not None else _own_loop_seconds(constants)
        with compiling(_own_loop_subject(model, method), seconds):
            to_rhs = rhs_link(arguments[2], model, codes=not codes_vary)
            return link_to(integrate, placeholder, constants), to_rhs
    with compiling("the run loop of every model and method", EVERY_CODE_SECONDS):
        to_rhs = rhs_link(arguments[2])
        return link_to(integrate, placeholder), to_rhs


def _own_loop_subject(model: int, method: int) -> str:
    """What a compile of the run's own loop says it compiles."""
    model_names = {int(code): code.name.lower() for code in ModelCode}
    method_names = {code: name for name, code in METHODS.items()}
    return f"the {model_names.get(model, model)} model with {method_names.get(method, method)}"


def _own_loop_seconds(constants: tuple[int, ...]) -> float:
    """About how long the loop for these constants compiles [s of CPU]."""
    return OWN_LOOP_SECONDS if constants == MODEL_AND_METHOD else MODEL_LOOP_SECONDS


@kernel
def integrate_at(link, arguments):
    """``integrate(*arguments)`` at ``link`` (:func:`integrate_link` of the same
    arguments, with its ``rhs_link`` last): the entry from Python."""
    return call_integrate(link, arguments)
