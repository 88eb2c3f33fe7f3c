"""The batch driver on a CUDA GPU: one thread per point, the CPU driver's loop and fields.

``run_points`` is ``batch.run_batch`` with ``device="cuda"``: the same points and the
same result array (``batch.FIELDS`` columns, ``batch._reduce``'s numbers), for the
rolling model and the sliding model (``CUDA_MODELS``), the stick–slip contact
included, with every method (``CUDA_METHODS``). Each thread integrates one point with
the code the CPU runs, compiled by numba for CUDA from the same Python source, so no
equation, method, loop or reduction is written twice:

* the run loop ``driver.run_loop``, which ``driver.integrate`` runs on the CPU: the
  methods' dispatch (``_methods``), so ``auto`` switches between DOP853 and Radau on the
  thread as on the CPU; the events of ``_events``, spin zero crossings located inside
  each step on the method's interpolant, pairs of crossings inside one step included,
  so the reversal counts agree exactly; the samples, filled from the same interpolant;
* for the stick–slip contact, the phase loop ``phases.phase_loop``, which
  ``phases.run_phases`` runs on the CPU: its phase log (one per point, its capacity
  ``max_phases``, so ``STATUS_MAX_PHASES`` where the CPU has it), its capture impulses
  and rejected captures; each phase runs ``driver.run_loop`` on the thread's arrays
  (``_phase_on_thread``, in place of ``phases.integrate_phase``, which calls
  ``driver.integrate`` at a CPU address), its methods' workspaces set as
  ``driver.integrate`` makes them for a phase (``_fresh_workspaces``);
* the reduction ``batch._reduce`` (reversals with their band and rocking window, final
  spin, energy lost, tilt, normal force, energy budget).

``solve_runs`` (``run_whole``) is ``solvers.solve`` (``solve_phases`` for the stick–slip
contact) of many runs, one thread each, for ``simulation.integrate.simulate_many``: the
same launch with ``Run.keeps_runs`` set keeps each point's whole run instead of reducing
it, each point sampled at its own times (``Buffers.sample_times`` of a row per point; a
sweep's one row serves all), its crossings, phase log and how it ended (``RunEnds``: the
``RunEnd``, the counters, the final state, phases logged, rejected captures) in global
arrays, turned into the CPU's ``RawSolution`` or ``RawPhases`` on the host by the CPU's
own functions (``run.raw_solution``, ``run.raw_phases``). The flag is read at run time,
so one kernel of a model and method serves a sweep and a batch of runs.

``driver.run_loop`` allocates nothing: ``driver.integrate`` allocates its arrays, a thread takes
them from its local memory and from the launch's global arrays (``_thread_arrays``:
each point's samples, averaged spin and crossings, Radau's scalars and ``auto``'s
switching record, set on the host as ``_radau.workspace`` and ``_auto.workspace`` set
them). Radau's workspace (Jacobian, the real and the complex LU, about 8 kB) is the
thread's local memory.

On the CPU the solvers call the right-hand side at its address (``_system``: the run's
system is the parameter record and a link); a GPU cannot call a CPU address, so while
the kernel compiles for CUDA the solvers call the kernels' own right-hand side directly
on the record (``direct_rhs``); the loop's stop request, which no host thread can make
of a GPU thread, reads False, and its array copies are loops. numba's simulator runs the
CPU's compiled code, and there the thread passes the CPU's system, link included;
there the phase loop's integrator is replaced for the launch alone (``_phases_on_thread``).

The sliding model's kernels read the elliptic contact's spline table
(``kernels.friction_ellipse``, 396 kB) at the address in each point's parameter record
(``ellipse_table``): a launch on a GPU copies the table to the device once per process
and device (``_device_table``) and writes that copy's address into the records it sends
(``_with_device_table``); in the simulator the host's address stays, as the CPU's compiled
code reads it. No large array is frozen into a kernel, so the methods' small tableaux are
all that numba-cuda puts in constant memory.

numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``, no GPU) runs the thread's Python
with the kernels as their compiled CPU code: there the fields equal the CPU sweep's to the
last bit (``tests/test_sweep_cuda.py``). It hands a kernel's tuple arguments over as
they are, so the launch passes its arrays in tuples (``Run``, ``Buffers``), which a GPU
launch copies to the device as numba does any array argument.

The kernel of a model and method is compiled once per machine: ``cuda.jit(cache=True)``
keeps it in numba's cache, keyed on a hash of the sources it is built from
(``SOURCE_KEY``), since numba's cache looks only at the kernel's own file.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

try:  # numba's CUDA target: its own (numba-cuda) or the one built into numba
    from numba import complex128, cuda, float64, int64
except ImportError:  # pragma: no cover - a numba without one
    cuda = None  # type: ignore[assignment]

from celtstone.kernels.layout import N_STATE, ModelCode
from celtstone.solvers import _auto, _dop853, _radau, _stop, _system, _vern9, phases
from celtstone.solvers import _events as events
from celtstone.solvers import _methods as methods
from celtstone.solvers._compile import inlined
from celtstone.solvers._structures import Controls, HybridSettings, Output, PhaseLog, RunEnd
from celtstone.solvers.batch import N_FIELDS, Points, _reduce
from celtstone.solvers.codes import (
    DEFAULT_MAX_PHASES,
    METHOD_AUTO,
    METHOD_ENTRIES,
    METHOD_RADAU5,
    N_STATS,
)
from celtstone.solvers.driver import LoopArrays, copy_into, run_loop
from celtstone.solvers.run import RawSolution, raw_phases, raw_solution

__all__ = [
    "CUDA_METHODS",
    "CUDA_MODELS",
    "CUDA_MODEL_NAMES",
    "KEPT_CROSSINGS",
    "ONE_MODEL",
    "THREADS_PER_BLOCK",
    "Buffers",
    "Launch",
    "PhaseArrays",
    "Run",
    "RunEnds",
    "bytes_per_point",
    "cuda_unavailable_reason",
    "device_name",
    "in_simulator",
    "launch_inputs",
    "launch_points",
    "run_points",
    "run_whole",
    "solve_runs",
]

CUDA_MODELS = (int(ModelCode.ROLLING), int(ModelCode.SLIDING))
"""Model codes a GPU thread runs: rolling, and sliding, on its own or in the stick–slip
contact's slip phases (its stick phases run ``MODEL_STICK``)."""
CUDA_MODEL_NAMES = tuple(ModelCode(code).name.lower() for code in CUDA_MODELS)
"""Their names, as ``Sweep(model=...)`` takes them."""
CUDA_METHODS = {name: entry.code for name, entry in METHOD_ENTRIES.items() if entry.gpu}
"""Methods a GPU thread runs, by name: those of the registry marked ``gpu`` (every method
now), Radau's workspace (Jacobian and LU factors, 8 kB) in the thread's local memory."""
MAX_LAUNCH_POINTS = 262_144  # threads of one launch: more than fill a GPU (§44: 65 536 do)
SIMULATOR_LAUNCH_POINTS = 64  # numba's simulator runs a Python thread per GPU thread
MEMORY_FRACTION = 0.5  # of the GPU's free memory, for one launch's arrays
THREADS_PER_BLOCK = 64  # 32 to 256 made no difference (docs/decisions.md §44)
KEPT_CROSSINGS = 100_000  # crossing times a point keeps where they time reversals, as on the CPU
MAX_EVENT_ROWS = 3  # lift-off, phase change, spin crossing (``_events.event_table``)
ONE_MODEL = -1  # the stick method of a launch without stick phases (``_kernel``)
# the thread's workspace arrays, sized for the larger of the two methods
MAX_STAGES = max(_vern9.N_STAGES_EXTENDED, _dop853.N_STAGES_EXTENDED)
MAX_DENSE_ROWS = max(_vern9.DENSE_ROWS, _dop853.DENSE_ROWS)
RADAU_DENSE_ROWS = _radau.DENSE_ROWS  # a global of this module: a shape CUDA types as constant

# NumPy's name that numba-cuda 0.30 still overloads (by name: ruff's NumPy 2 rule rewrites it)
REMOVED_ALIAS = "row_stack"

_PACKAGE = Path(__file__).resolve().parents[1]


def _source_key() -> int:
    """A hash of every source the kernel is compiled from (``kernels`` and ``solvers``):
    numba's cache checks only the kernel's own file, and would load a kernel built from
    older kernels after an upgrade."""
    digest = hashlib.sha256()
    for folder in ("kernels", "solvers"):
        for path in sorted((_PACKAGE / folder).glob("*")):
            if path.suffix in (".py", ".json"):
                digest.update(path.name.encode())
                digest.update(path.read_bytes())
    return int(digest.hexdigest()[:15], 16)


SOURCE_KEY = _source_key()


class Run(NamedTuple):
    """What every thread of a launch shares: the duration [s], the controls
    (``_structures.Controls``: tolerances, step limit), in numba's simulator the
    right-hand side's link (``_system.rhs_link``; (0, 0) on a GPU, where the kernels are
    called directly), and whether each point's whole run is kept (``Buffers.ends``, for
    :func:`run_whole`) rather than reduced into its result fields (a sweep's)."""

    t_end: float
    controls: Controls
    rhs_link: tuple[int, int]
    keeps_runs: bool


class Buffers(NamedTuple):
    """A launch's arrays, k points (on the GPU: device arrays).

    Parameters
    ----------
    params : kernel parameter records, shape (k,)
    initial_states : shape (k, N_STATE)
    reversal_bands : each point's hysteresis half-width [rad/s], shape (k,)
    reversal_windows : each point's rocking window [s], shape (k,)
    table : the run's events (``_events.event_table``)
    sample_times : [s], shape (1, m): every point's (a sweep's), or (k, m): each point's
    samples : each point's states at the sample times, shape (k, m, N_STATE)
    spins, averaged, cumulative : each point's ``_reduce`` buffers, shape (k, m); one
        row, unread, where the runs are kept
    crossings : each point's spin zero crossing times [s], shape (k, capacity)
    results : each point's result fields (``batch.FIELDS``), shape (k, N_FIELDS); one
        row, unread, where the runs are kept
    radau_memory : each point's Radau scalars (``_radau.MEMORY``), shape (k, 1)
    radau_start : Radau's scalars as ``_radau.workspace`` sets them before a run or a
        phase, shape (1,)
    switching : each point's ``auto`` switching record (``_auto.RECORD``), shape (k, 1)
    phases : the stick–slip contact's arrays (:class:`PhaseArrays`; one row, unread,
        in a launch without stick phases)
    ends : how each point's run ended (:class:`RunEnds`; one row, unread, in a sweep's
        launch)
    """

    params: Any
    initial_states: Any
    reversal_bands: Any
    reversal_windows: Any
    table: Any
    sample_times: Any
    samples: Any
    spins: Any
    averaged: Any
    cumulative: Any
    crossings: Any
    results: Any
    radau_memory: Any
    radau_start: Any
    switching: Any
    phases: Any
    ends: Any


class RunEnds(NamedTuple):
    """How each of a launch's k runs ended, kept where the runs are (``Run.keeps_runs``):
    what ``solvers.solve`` and ``solve_phases`` read of a run besides its samples.

    Parameters
    ----------
    status, n_samples, n_crossings : each run's ``RunEnd`` fields of those names (int64),
        shape (k,)
    t_stop, min_normal_force, t_min_normal_force : its ``RunEnd`` fields [s], [N], [s],
        shape (k,)
    statistics : its counters (``codes.STAT_*``, int64), shape (k, N_STATS)
    final_states : the state where it stopped, shape (k, N_STATE)
    phases_logged, rejected_captures : the stick–slip contact's phases logged and
        captures rejected (int64; 0 without stick phases), shape (k,)
    """

    status: Any
    n_samples: Any
    n_crossings: Any
    t_stop: Any
    min_normal_force: Any
    t_min_normal_force: Any
    statistics: Any
    final_states: Any
    phases_logged: Any
    rejected_captures: Any


def _end_shapes(k: int) -> dict[str, tuple[tuple[int, ...], Any]]:
    """The shape and type of each array of :class:`RunEnds` for k runs."""
    counts = ("status", "n_samples", "n_crossings", "phases_logged", "rejected_captures")
    shapes: dict[str, tuple[tuple[int, ...], Any]] = {name: ((k,), np.int64) for name in counts}
    for name in ("t_stop", "min_normal_force", "t_min_normal_force"):
        shapes[name] = ((k,), np.float64)
    shapes["statistics"] = ((k, N_STATS), np.int64)
    shapes["final_states"] = ((k, N_STATE), np.float64)
    return shapes


class PhaseArrays(NamedTuple):
    """A launch's arrays of the stick–slip contact, k points of m samples, each with a
    phase log of capacity c (``_structures.PhaseLog``, ``phases.PhaseBuffers``).

    Parameters
    ----------
    capture_speeds : each point's v_c [m/s], shape (k,)
    slip_tables : each point's events of slip, the capture event at its v_c, shape
        (k, rows) (``_events.event_table``)
    stick_table : the events of stick, shape (rows,)
    phase_times : each point's sample times of a phase in its own time [s], shape (k, m)
    log_sample_times, log_sample_phase : each point's ``PhaseLog.sample_times`` [s] and
        ``sample_phase`` (int8), shape (k, m)
    log_kind, log_start, log_end, log_energy_jump : each point's ``PhaseLog.kind``
        (int8), ``start``, ``end`` [s] and ``energy_jump`` [J], shape (k, c)
    """

    capture_speeds: Any
    slip_tables: Any
    stick_table: Any
    phase_times: Any
    log_sample_times: Any
    log_sample_phase: Any
    log_kind: Any
    log_start: Any
    log_end: Any
    log_energy_jump: Any


class ThreadWorkspace(NamedTuple):
    """The workspace of either explicit method (the fields of ``_vern9.Workspace`` and
    ``_dop853.Workspace``, which read theirs by name), so that one compiled loop takes
    both."""

    stages: Any  # (MAX_STAGES, N_STATE)
    dense: Any  # (MAX_DENSE_ROWS, N_STATE)
    scratch: Any  # (N_STATE,)
    error_term: Any  # (N_STATE,): Verner's
    error_terms: Any  # (2, N_STATE): DOP853's


def _thread_arrays(memory, switching):
    """The ``driver.LoopArrays`` of a thread, in its local memory, as ``driver.integrate``
    makes them before a run: the explicit methods share one ``ThreadWorkspace``. Radau's
    scalars ``memory`` and ``auto``'s switching record ``switching`` (shape (1,) each)
    are the launch's. CUDA's local arrays start undefined: :func:`_fresh_workspaces` sets
    them before each run or phase."""
    loop = cuda.local.array((5, N_STATE), float64)  # f, y_new, f_new, point, scratch
    values = cuda.local.array(MAX_EVENT_ROWS, float64)
    stages = cuda.local.array((MAX_STAGES, N_STATE), float64)
    dense = cuda.local.array((MAX_DENSE_ROWS, N_STATE), float64)
    scratch = cuda.local.array(N_STATE, float64)
    errors = cuda.local.array((2, N_STATE), float64)
    explicit = ThreadWorkspace(stages, dense, scratch, errors[0], errors)
    jacobian = cuda.local.array((N_STATE, N_STATE), float64)
    lu_real = cuda.local.array((N_STATE, N_STATE), float64)
    lu_complex = cuda.local.array((N_STATE, N_STATE), complex128)
    pivots = cuda.local.array((2, N_STATE), int64)
    collocation = cuda.local.array((3, N_STATE), float64)
    transformed = cuda.local.array((3, N_STATE), float64)
    stage_rates = cuda.local.array((3, N_STATE), float64)
    vectors = cuda.local.array((6, N_STATE), float64)
    complex_rhs = cuda.local.array(N_STATE, complex128)
    radau_dense = cuda.local.array((RADAU_DENSE_ROWS, N_STATE), float64)
    radau = _radau.Workspace(
        jacobian, lu_real, lu_complex, pivots[0], pivots[1], collocation, transformed,
        stage_rates, vectors[0], complex_rhs, vectors[1], vectors[2], vectors[3], vectors[4],
        radau_dense, vectors[5], memory,
    )  # fmt: skip
    # the explicit methods read their workspace's fields by name, which ThreadWorkspace
    # has; by method code, as the registry's entries say (``gpu``)
    work = methods.thread_workspaces(explicit, radau, switching)
    dense_of = methods.thread_dense_arrays(dense, radau_dense)
    return LoopArrays(loop[0], loop[1], loop[2], loop[3], loop[4], values, work, dense_of)


@inlined
def _fresh_workspaces(method, work, radau_start):
    """Set a thread's workspaces ``work`` (:func:`_thread_arrays`) for a run or a phase of
    ``method`` as ``_methods.workspaces`` makes them for ``driver.integrate``: the arrays
    it zeroes zeroed, Radau's scalars from ``radau_start`` (``_radau.workspace``'s);
    ``auto``'s switching record is set by its ``start``."""
    if method != METHOD_RADAU5:  # DOP853 (auto's too) or Verner: one shared workspace
        explicit = work.dop853
        for j in range(explicit.stages.shape[1]):
            for k in range(explicit.stages.shape[0]):
                explicit.stages[k, j] = 0.0
            for k in range(explicit.dense.shape[0]):
                explicit.dense[k, j] = 0.0
    if method == METHOD_RADAU5 or method == METHOD_AUTO:
        radau = work.radau5
        for i in range(radau.jacobian.shape[0]):
            for j in range(radau.jacobian.shape[1]):
                radau.jacobian[i, j] = 0.0
                radau.lu_real[i, j] = 0.0
                radau.lu_complex[i, j] = 0.0
            radau.pivots_real[i] = 0
            radau.pivots_complex[i] = 0
            for k in range(3):
                radau.collocation[k, i] = 0.0
                radau.transformed[k, i] = 0.0
                radau.stage_rates[k, i] = 0.0
            for k in range(radau.dense.shape[0]):
                radau.dense[k, i] = 0.0
            radau.real_rhs[i] = 0.0
            radau.complex_rhs[i] = 0.0
        radau.memory[0] = radau_start[0]


@inlined
def _phase_on_thread(integrator, kind, model, method, params, y, t_end, controls, table, output):
    """``phases.integrate_phase`` on a thread: ``driver.run_loop`` from ``y`` (overwritten)
    on the thread's arrays, its workspaces set first as ``driver.integrate`` sets a
    phase's. ``integrator`` is (``driver.LoopArrays``, the run's system, Radau's
    scalars before a run); the record ``params`` is the system's own."""
    arrays, system, radau_start = integrator
    _fresh_workspaces(method, arrays.work, radau_start)
    return run_loop(model, method, system, y, t_end, controls, table, output, arrays)


def _thread(model, method, stick_method, point, run, buffers):
    """Integrate point ``point`` of the launch with the CPU's loops (``driver.run_loop``;
    with a ``stick_method``, the stick–slip contact's ``phases.phase_loop``) and reduce it
    into ``buffers.results[point]`` (``batch._reduce``), or, where the launch keeps the
    runs (``run.keeps_runs``), keep how it ended in ``buffers.ends`` (its samples and
    crossings are in place already) (a CUDA device function; ``model``, ``method`` and
    ``stick_method`` are compile-time constants, so only their branches are compiled)."""
    y = cuda.local.array(N_STATE, float64)
    final_state = cuda.local.array(N_STATE, float64)
    stats = cuda.local.array(N_STATS, int64)
    first_time = cuda.local.array(1, float64)
    for j in range(N_STATS):
        stats[j] = 0
    y0 = buffers.initial_states[point]
    copy_into(y, y0)
    params = buffers.params[point]
    times = buffers.sample_times[point if buffers.sample_times.shape[0] > 1 else 0]
    output = Output(times, buffers.samples[point], buffers.crossings[point], stats, final_state)
    arrays = _arrays_device(buffers.radau_memory[point], buffers.switching[point])
    system = _system_device(params, run)
    phases_logged = 0
    rejected = 0
    if stick_method == ONE_MODEL:
        _fresh_workspaces(method, arrays.work, buffers.radau_start)
        end = run_loop(
            model, method, system, y, run.t_end, run.controls, buffers.table, output, arrays
        )
    else:
        end, phases_logged, rejected = _phases_device(
            method, stick_method, point, params, system, y, run, buffers, output, arrays
        )
        times = buffers.phases.log_sample_times[point]
    if run.keeps_runs:
        _keep_end(buffers.ends, point, end, (phases_logged, rejected), stats, final_state)
        return
    reversal = (
        buffers.reversal_bands[point],
        buffers.reversal_windows[point],
        buffers.averaged[point],
        first_time,
        buffers.cumulative[point],
    )
    finished = (end, times, output.samples, output.crossings)
    _reduce(
        model,
        system,
        y0,
        finished,
        reversal,
        buffers.spins[point],
        arrays.scratch,
        buffers.results[point],
    )


@inlined
def _keep_end(ends, point, end, counts, stats, final_state):
    """How run ``point`` ended into its row of ``ends`` (:class:`RunEnds`): its ``RunEnd``
    ``end``, ``counts`` (phases logged, rejected captures), its counters ``stats`` and
    its ``final_state`` (inlined into the thread)."""
    ends.status[point] = end.status
    ends.n_samples[point] = end.n_samples
    ends.n_crossings[point] = end.n_crossings
    ends.t_stop[point] = end.t_stop
    ends.min_normal_force[point] = end.min_normal_force
    ends.t_min_normal_force[point] = end.t_min_normal_force
    ends.phases_logged[point] = counts[0]
    ends.rejected_captures[point] = counts[1]
    for j in range(stats.shape[0]):
        ends.statistics[point, j] = stats[j]
    for j in range(final_state.shape[0]):
        ends.final_states[point, j] = final_state[j]


def _phases(method, stick_method, point, params, system, y, run, buffers, output, arrays):
    """The stick–slip contact's run of point ``point`` from ``y`` (its initial state) by
    the CPU's phase loop ``phases.phase_loop``, slip with ``method``, stick with
    ``stick_method``, into ``output`` and the point's phase log; returns (the ``RunEnd``,
    phases logged, captures rejected) (a CUDA device function)."""
    captured = cuda.local.array(N_STATE, float64)
    spare_crossings = cuda.local.array(1, float64)
    arrays_of = buffers.phases
    hybrid = HybridSettings(method, stick_method, arrays_of.capture_speeds[point])
    log = PhaseLog(
        arrays_of.log_sample_times[point],
        arrays_of.log_sample_phase[point],
        arrays_of.log_kind[point],
        arrays_of.log_start[point],
        arrays_of.log_end[point],
        arrays_of.log_energy_jump[point],
    )
    phase_buffers = phases.PhaseBuffers(
        y,
        captured,
        arrays_of.phase_times[point],
        spare_crossings,
        arrays_of.slip_tables[point],
        arrays_of.stick_table,
    )
    integrator = (arrays, system, buffers.radau_start)
    return phases.phase_loop(
        params, run.t_end, hybrid, run.controls, output, log, phase_buffers, integrator
    )


def _system_in_simulator(params, run):
    """The run's system as the CPU driver's loop has it: the parameter record and the
    right-hand side's link (numba's simulator runs the CPU's compiled code)."""
    return (params, run.rhs_link)


def _system_on_gpu(params, run):
    """The run's system on a GPU: the parameter record itself, which the kernels'
    own right-hand side takes (``direct_rhs``); no CPU address can be called there."""
    return params


@inlined
def _record_itself(system):
    """``_system.parameters`` of a GPU thread's system, the record itself."""
    return system


@inlined
def _not_asked(stats):
    """``_stop.stop_requested`` on a GPU thread: no host thread can ask a thread to stop
    (its counters ``stats`` are its own local array), and the stop slot's atomic load
    is a CPU intrinsic."""
    return False


@contextlib.contextmanager
def direct_rhs() -> Iterator[None]:
    """While a CUDA kernel compiles: the solvers call the kernels' right-hand side
    directly (``kernels.system.rhs``, ``spin_and_normal_force``) with the parameter record
    as their ``params``, in place of ``_system``'s call at a CPU address; the loop's stop
    request reads False (``_not_asked``); the stick–slip phase loop integrates each
    phase with ``driver.run_loop`` on the thread's arrays (``_phase_on_thread``).

    numba compiles a CPU function for CUDA from its Python source, reading the globals of
    its module as it compiles: each solver module's reference to a ``_system`` function
    is replaced for that time (under numba's compiler lock, so that no CPU compile sees
    it) and restored after. The same arithmetic either way: ``_system`` calls
    ``kernels.system.evaluate``, which those call too.
    """
    from numba.core.compiler_lock import global_compiler_lock

    from celtstone.kernels import system as physics

    direct = {
        id(_system.rhs): physics.rhs,
        id(_system.spin_and_normal_force): physics.spin_and_normal_force,
        id(_system.parameters): _record_itself,
        id(_stop.stop_requested): _not_asked,
        id(phases.integrate_phase): _phase_on_thread,
    }
    with global_compiler_lock, _replaced(direct):
        yield


@contextlib.contextmanager
def _phases_on_thread() -> Iterator[None]:
    """In numba's simulator, for a launch of the stick–slip contact: the phase loop
    integrates its phases with ``driver.run_loop`` on the thread's arrays
    (``_phase_on_thread`` in place of ``phases.integrate_phase``), compiled for the CPU
    as the thread's code first calls it. The simulator runs each thread in a Python
    thread that compiles what it calls, so numba's compiler lock is not held here: a
    stick–slip run compiled for the first time in another thread of this process during
    the launch would see the replacement too, and fail to compile (its links are not
    the thread's arrays)."""
    with _replaced({id(phases.integrate_phase): _phase_on_thread}):
        yield


@contextlib.contextmanager
def _replaced(direct: dict[int, Any]) -> Iterator[None]:
    """Each solver module's reference to a function whose ``id`` is a key of ``direct``
    replaced by its value, and restored after."""
    modules = [m for n, m in sorted(sys.modules.items()) if n.startswith("celtstone.solvers")]
    replaced: list[tuple[Any, str, Any]] = []
    try:
        for module in modules:
            for name, value in list(vars(module).items()):
                if id(value) in direct:
                    replaced.append((module, name, value))
                    setattr(module, name, direct[id(value)])
        yield
    finally:
        for module, name, value in replaced:
            setattr(module, name, value)


def _ensemble_source(model, method, stick_method, key):  # pragma: no cover - the template
    """The kernel of ``model``, ``method`` and ``stick_method`` (``ONE_MODEL``: no stick
    phases) as a Python closure over four integers (numba's cache keys a closure on its
    cells, which must pickle the same in every process: ``key`` is ``SOURCE_KEY``)."""

    def ensemble(run, buffers):
        point: int = cuda.grid(1)  # type: ignore[call-arg]
        if key >= 0 and point < buffers.initial_states.shape[0]:
            _thread_device(model, method, stick_method, point, run, buffers)

    return ensemble


# ``_thread``, ``_thread_arrays``, ``_phases`` and the system's maker as CUDA device
# functions, made by ``_kernel`` (``declare_device_functions``)
_thread_device: Any = None
_arrays_device: Any = None
_system_device: Any = None
_phases_device: Any = None


@functools.cache
def _kernel(model: int, method: int, stick_method: int = ONE_MODEL) -> Any:
    """The CUDA kernel of ``model`` and ``method`` (with a ``stick_method``, the
    stick–slip contact's), compiled at its first launch or loaded from numba's cache."""
    declare_device_functions()
    return cuda.jit(cache=True)(_ensemble_source(model, method, stick_method, SOURCE_KEY))


def declare_device_functions() -> None:
    """``declare_for_cuda``, and the thread's device functions, once per process."""
    global _thread_device, _arrays_device, _system_device, _phases_device
    declare_for_cuda()
    if _thread_device is None:
        making_system = _system_in_simulator if in_simulator() else _system_on_gpu
        _system_device = cuda.jit(device=True)(making_system)
        _arrays_device = cuda.jit(device=True)(_thread_arrays)
        _phases_device = cuda.jit(device=True)(_phases)
        _thread_device = cuda.jit(device=True)(_thread)


@functools.cache
def declare_for_cuda() -> None:
    """What numba's CUDA targets lack for celtstone's kernels, for the CUDA target only:
    min/max of two numbers (numba 0.68's built-in target types the builtins' overloads
    for iterables and fails on ``max(a, b)``), ``np.nextafter(t, np.inf)`` for t >= 0
    (the step floor of ``_step_control.smallest_step``), from ``math.frexp``. A target
    with its own keeps its own. numba-cuda 0.30 overloads NumPy's ``row_stack``, which
    NumPy 2.5 removed, when it first compiles: the alias is given back then."""
    from numba import types
    from numba.core.extending import overload

    if not hasattr(np, REMOVED_ALIAS):
        setattr(np, REMOVED_ALIAS, np.vstack)

    def next_above(value, direction):
        if isinstance(value, types.Float) and isinstance(direction, types.Float):

            def implementation(value, direction):
                if value == 0.0:
                    return 5e-324
                _, exponent = math.frexp(value)
                return value + math.ldexp(1.0, exponent - 53)  # one ulp, for value > 0

            return implementation
        return None

    def larger(a, b):
        if isinstance(a, types.Number) and isinstance(b, types.Number):
            return lambda a, b: a if a >= b else b
        return None

    def smaller(a, b):
        if isinstance(a, types.Number) and isinstance(b, types.Number):
            return lambda a, b: a if a <= b else b
        return None

    for function, implementation in ((max, larger), (min, smaller), (np.nextafter, next_above)):
        try:
            overload(function, target="cuda")(implementation)
        except Exception:  # another numba's CUDA target: its own serves
            pass


@functools.cache
def _device_table(device_id: int) -> Any:
    """The elliptic contact's table (``friction_ellipse.COEFFICIENTS``) on the GPU
    ``device_id``, copied once per process and kept for it (the records hold its address)."""
    from celtstone.kernels.friction_ellipse import COEFFICIENTS

    return cuda.to_device(COEFFICIENTS)


def _with_device_table(params: np.ndarray) -> np.ndarray:
    """A copy of the records ``params`` whose ``ellipse_table`` is the address of the
    table on the current GPU, where the threads read it."""
    table = _device_table(cuda.get_current_device().id)
    records = np.array(params)
    records["ellipse_table"] = table.__cuda_array_interface__["data"][0]
    return records


def in_simulator() -> bool:
    """Whether numba's CUDA simulator stands in for a GPU (``NUMBA_ENABLE_CUDASIM=1``)."""
    from numba import config

    return bool(getattr(config, "ENABLE_CUDASIM", False))


def cuda_unavailable_reason() -> str | None:
    """Why no CUDA GPU can run a sweep here, or None if one can (numba's CUDA simulator,
    ``NUMBA_ENABLE_CUDASIM=1``, counts as one)."""
    if cuda is None:
        return "this numba has no CUDA target (install numba-cuda)"
    try:
        if cuda.is_available():
            return None
    except Exception as error:  # a driver that fails to load
        return f"the CUDA driver failed: {error}"
    return "no CUDA GPU or driver found: numba.cuda.is_available() is False"


def device_name() -> str:
    """The GPU's name ("NVIDIA H200"), or "numba's CUDA simulator"."""
    if in_simulator():
        return "numba's CUDA simulator"
    name = cuda.get_current_device().name
    return name.decode() if isinstance(name, bytes) else str(name)


def launch_points(
    n_samples: int, crossing_capacity: int, phase_capacity: int = 0, keeps_runs: bool = False
) -> int:
    """Points in one launch: what ``MEMORY_FRACTION`` of the GPU's free memory holds
    (``bytes_per_point``), at most ``MAX_LAUNCH_POINTS`` (``SIMULATOR_LAUNCH_POINTS`` in
    the simulator)."""
    if in_simulator():
        return SIMULATOR_LAUNCH_POINTS
    free, _ = cuda.current_context().get_memory_info()
    size = bytes_per_point(n_samples, crossing_capacity, phase_capacity, keeps_runs)
    fitting = int(MEMORY_FRACTION * free) // size
    return max(1, min(MAX_LAUNCH_POINTS, fitting))


def bytes_per_point(
    n_samples: int, crossing_capacity: int, phase_capacity: int = 0, keeps_runs: bool = False
) -> int:
    """GPU memory [bytes] a point of a launch takes: its samples, its ``_reduce``
    buffers, its crossings, its inputs, its method's records and its results; with a
    ``phase_capacity`` (the stick–slip contact), its phase log (:class:`PhaseArrays`).
    Where the launch ``keeps_runs``, a point has its own sample times and its run's end
    (:class:`RunEnds`) in place of the ``_reduce`` buffers and the results."""
    floats = n_samples * (N_STATE + 3) + crossing_capacity + N_STATE + 2 + N_FIELDS
    if keeps_runs:  # its sample times, its RunEnds row
        ends = sum(int(np.prod(shape)) for shape, _ in _end_shapes(1).values())
        floats = n_samples * (N_STATE + 1) + crossing_capacity + N_STATE + 2 + ends
    records = _radau.MEMORY.itemsize + _auto.RECORD.itemsize
    if phase_capacity > 0:  # phase times, the log's times and kinds; its phases; v_c
        floats += 2 * n_samples + 3 * phase_capacity + 1
        records += n_samples + phase_capacity + MAX_EVENT_ROWS * events.EVENT.itemsize
    return 8 * floats + records + 1024  # and its parameter record, at most 1 kB


def _phase_arrays(
    points: Points, n_samples: int, max_phases: int, is_hybrid: bool
) -> tuple[dict[str, np.ndarray], dict[str, tuple[tuple[int, ...], Any]]]:
    """:class:`PhaseArrays` of a launch: the inputs made here, and the shape and type of
    each array the threads fill. One row each, unread, without stick phases."""
    k, m, capacity = len(points.params), n_samples, max(1, int(max_phases))
    if not is_hybrid:
        k, m, capacity = 1, 1, 1
    speeds = points.capture_speeds[:k] if is_hybrid else np.ones(1)
    slip = [events.event_table(int(ModelCode.SLIDING), float(v)) for v in speeds]
    inputs: dict[str, np.ndarray] = {
        "capture_speeds": np.ascontiguousarray(speeds, dtype=np.float64),
        "slip_tables": np.stack(slip),
        "stick_table": events.event_table(int(ModelCode.STICK), 0.0),
    }
    shapes: dict[str, tuple[tuple[int, ...], Any]] = {
        "phase_times": ((k, m), np.float64),
        "log_sample_times": ((k, m), np.float64),
        "log_sample_phase": ((k, m), np.int8),
        "log_kind": ((k, capacity), np.int8),
        "log_start": ((k, capacity), np.float64),
        "log_end": ((k, capacity), np.float64),
        "log_energy_jump": ((k, capacity), np.float64),
    }
    return inputs, shapes


class Launch(NamedTuple):
    """What a launch of k points takes (:func:`launch_inputs`), on the host.

    Parameters
    ----------
    kernel : (model, method, stick method or ``ONE_MODEL``): its kernel (``_kernel``)
    run : :class:`Run`
    inputs : the arrays of :class:`Buffers` made on the host, by name
    shapes : the arrays of :class:`Buffers` the threads fill, by name: their shapes
    phase_inputs, phase_shapes : the same of :class:`PhaseArrays`, the shapes with
        their types
    end_shapes : the shapes and types of :class:`RunEnds`
    max_crossings : the crossings a kept run returns at most
    """

    kernel: tuple[int, int, int]
    run: Run
    inputs: dict[str, np.ndarray]
    shapes: dict[str, tuple[int, ...]]
    phase_inputs: dict[str, np.ndarray]
    phase_shapes: dict[str, tuple[tuple[int, ...], Any]]
    end_shapes: dict[str, tuple[tuple[int, ...], Any]]
    max_crossings: int

    def host_buffers(self) -> Buffers:
        """:class:`Buffers` of host arrays, those the threads fill zeroed."""
        phase_arrays = PhaseArrays(
            **self.phase_inputs,
            **{name: np.zeros(*shape) for name, shape in self.phase_shapes.items()},
        )
        ends = RunEnds(**{name: np.zeros(*shape) for name, shape in self.end_shapes.items()})
        filled = {name: np.zeros(shape) for name, shape in self.shapes.items()}
        return Buffers(**self.inputs, **filled, phases=phase_arrays, ends=ends)

    def device_buffers(self) -> Buffers:
        """:class:`Buffers` of device arrays: the inputs copied to the GPU, the others
        allocated there."""
        phase_arrays = PhaseArrays(
            **{name: cuda.to_device(values) for name, values in self.phase_inputs.items()},
            **{name: cuda.device_array(*shape) for name, shape in self.phase_shapes.items()},
        )
        ends = RunEnds(
            **{name: cuda.device_array(*shape) for name, shape in self.end_shapes.items()}
        )
        # the records carry the device's copy of the elliptic table, not the host's
        inputs = dict(self.inputs, params=_with_device_table(self.inputs["params"]))
        return Buffers(
            **{name: cuda.to_device(values) for name, values in inputs.items()},
            **{name: cuda.device_array(shape) for name, shape in self.shapes.items()},
            phases=phase_arrays,
            ends=ends,
        )


def launch_inputs(
    model: int,
    methods_of_phases: tuple[int, int],
    points: Points,
    t_end: float,
    controls: Controls,
    sample_times: np.ndarray,
    max_crossings: int,
    max_phases: int = DEFAULT_MAX_PHASES,
    keeps_runs: bool = False,
) -> Launch:
    """What :func:`run_points` launches, made on the host: ``points`` run with ``model``
    (one of ``CUDA_MODELS``) and the methods ``methods_of_phases`` (of slip, of stick; of
    ``CUDA_METHODS``) to ``t_end`` [s] with ``controls``, sampled at ``sample_times`` [s]
    (shape (m,), or (k, m): each point's), with ``max_crossings`` crossing times and
    ``max_phases`` phases a point kept; raises ``ValueError`` for a model, method or mix
    of points no thread runs. With ``keeps_runs``, what :func:`run_whole` launches: each
    point keeps its whole run (its samples, ``max_crossings`` crossings, its end), and
    is not reduced."""
    method, stick_method = methods_of_phases
    if model not in CUDA_MODELS or method not in CUDA_METHODS.values():
        raise ValueError(f"no CUDA thread for model {model} with method code {method}")
    hybrid_points = points.capture_speeds > 0.0
    is_hybrid = bool(np.any(hybrid_points))
    if is_hybrid and not (np.all(hybrid_points) and model == int(ModelCode.SLIDING)):
        raise ValueError("a launch runs the stick-slip contact at every point of it or none")
    if is_hybrid and stick_method not in CUDA_METHODS.values():
        raise ValueError(f"no CUDA thread for the stick method code {stick_method}")
    k = len(points.params)
    times = np.ascontiguousarray(np.atleast_2d(sample_times), dtype=np.float64)
    if times.ndim != 2 or times.shape[0] not in (1, k):
        raise ValueError(f"sample times of shape {times.shape}: (m,) or ({k}, m)")
    kept = keeps_runs or np.any(points.reversal_windows <= 0.0)  # the crossing times read
    capacity = max(1, int(max_crossings)) if kept else 1
    m = times.shape[1]
    reduced = 1 if keeps_runs else k  # points with ``_reduce``'s buffers and results
    params = np.ascontiguousarray(points.params)
    inputs = {
        "params": params,
        "initial_states": points.initial_states,
        "reversal_bands": points.reversal_bands,
        "reversal_windows": points.reversal_windows,
        "table": events.event_table(model, 0.0),
        "sample_times": times,
        # each point's records (``_radau.workspace``, ``_auto.workspace``), and Radau's
        # as every run and phase starts
        "radau_memory": np.tile(_radau.workspace(0).memory, (k, 1)),
        "radau_start": _radau.workspace(0).memory,
        "switching": np.tile(_auto.workspace(), (k, 1)),
    }
    shapes = {
        "samples": (k, m, N_STATE),
        "spins": (reduced, m),
        "averaged": (reduced, m),
        "cumulative": (reduced, m),
        "crossings": (k, capacity),
        "results": (reduced, N_FIELDS),
    }
    phase_inputs, phase_shapes = _phase_arrays(points, m, max_phases, is_hybrid)
    link = _system.rhs_link(params[0]) if in_simulator() and k > 0 else (0, 0)
    kernel = (model, method, stick_method if is_hybrid else ONE_MODEL)
    run = Run(float(t_end), controls, link, bool(keeps_runs))
    end_shapes = _end_shapes(k if keeps_runs else 1)
    return Launch(
        kernel, run, inputs, shapes, phase_inputs, phase_shapes, end_shapes, int(max_crossings)
    )


def run_points(launch: Launch) -> np.ndarray:
    """``batch.run_batch`` with ``device="cuda"``: the points of ``launch``
    (:func:`launch_inputs`), one thread each, into the same result array
    (``batch.FIELDS`` columns), shape (k, N_FIELDS).

    Points with a capture speed > 0 run the stick–slip contact, each with a phase log of
    capacity ``max_phases``, as ``batch.run_batch`` runs them; a launch runs either those
    or none. Each point keeps ``max_crossings`` crossing times only where its rocking
    window is 0 (the raw spin's reversals are timed by them); elsewhere the count alone
    is kept, as the CPU reduction reads no more. The caller sizes a launch by
    ``bytes_per_point``.
    """
    if len(launch.inputs["params"]) == 0:
        return np.empty((0, N_FIELDS))
    return _on_host(_launched(launch).results)


def run_whole(launch: Launch) -> list[RawSolution]:
    """``solvers.solve`` (or, for the stick–slip contact, ``solve_phases``) of each
    point of ``launch`` (:func:`launch_inputs` with ``keeps_runs``), one thread each: the
    same results, trimmed to what each thread filled by the same functions
    (``run.raw_solution``, ``run.raw_phases``). Of each run's crossings and phase log
    only what it filled comes back from the GPU (:func:`_filled_rows`)."""
    k = len(launch.inputs["params"])
    if k == 0:
        return []
    buffers = _launched(launch)
    ends = RunEnds(*(_on_host(values) for values in buffers.ends))
    times = _on_host(buffers.sample_times)
    samples = _on_host(buffers.samples)
    stored = np.minimum(ends.n_crossings, buffers.crossings.shape[1])
    crossings = _filled_rows(buffers.crossings, stored)
    is_hybrid = launch.kernel[2] != ONE_MODEL
    arrays = buffers.phases  # their log of each run: its samples' times and phases, its phases
    sample_times = _on_host(arrays.log_sample_times) if is_hybrid else times
    sample_phase = _on_host(arrays.log_sample_phase) if is_hybrid else times
    log_rows = (arrays.log_kind, arrays.log_start, arrays.log_end, arrays.log_energy_jump)
    logged = [_filled_rows(rows, ends.phases_logged) for rows in log_rows] if is_hybrid else []
    solutions: list[RawSolution] = []
    for point in range(k):
        output = Output(
            times[point if times.shape[0] > 1 else 0],
            samples[point],
            crossings[point],
            ends.statistics[point],
            ends.final_states[point],
        )
        end = RunEnd(
            int(ends.status[point]),
            int(ends.n_samples[point]),
            int(ends.n_crossings[point]),
            float(ends.t_stop[point]),
            float(ends.min_normal_force[point]),
            float(ends.t_min_normal_force[point]),
        )
        if not is_hybrid:
            solutions.append(raw_solution(end, output))
            continue
        log = PhaseLog(sample_times[point], sample_phase[point], *(rows[point] for rows in logged))
        counts = (end, int(ends.phases_logged[point]), int(ends.rejected_captures[point]))
        solutions.append(raw_phases(counts, output, log, launch.max_crossings))
    return solutions


def _filled_rows(values: Any, lengths: np.ndarray) -> list[np.ndarray]:
    """Each row's first ``lengths[i]`` entries of a launch's array of rows (k, capacity),
    on the host: the whole array copied where they fill half of it or more, else row by
    row (a run's crossings and phase log fill a few of their capacity's places, 100 000
    by default: 3.3 MB a stick–slip run)."""
    if isinstance(values, np.ndarray) or 2 * int(np.sum(lengths)) >= values.size:
        host = _on_host(values)
        return [host[point, :length] for point, length in enumerate(lengths)]
    return [
        values[point, :length].copy_to_host() if length > 0 else np.empty(0, values.dtype)
        for point, length in enumerate(lengths)
    ]


def solve_runs(
    model: int,
    method_name: str,
    params: np.ndarray,
    y0: np.ndarray,
    t_end: float,
    *,
    rtol: float,
    atol: float,
    sample_times: np.ndarray,
    max_crossings: int,
    max_steps: int,
    capture_speeds: np.ndarray | None = None,
    stick_method_name: str = "dop853",
    max_phases: int = DEFAULT_MAX_PHASES,
) -> list[RawSolution]:
    """``solvers.solve`` of each row of ``params``/``y0`` on the GPU, one thread each
    (:func:`run_whole`), in launches of as many runs as the GPU's memory holds
    (:func:`launch_points`); with ``capture_speeds`` > 0, ``solvers.solve_phases`` of
    each (the stick–slip contact). The same results as theirs, in order.

    Parameters
    ----------
    model : kernel model code (``kernels.layout``) of ``CUDA_MODELS``; the sliding
        model for the stick–slip contact
    method_name : a key of ``CUDA_METHODS`` (of the slip phases in the stick–slip contact)
    params : kernel parameter records, one per run, shape (k,)
    y0 : initial states, shape (k, N_STATE)
    t_end : duration [s]
    rtol, atol, max_crossings, max_steps : as ``solvers.solve`` takes them
    sample_times : [s], shape (m,) or (1, m): every run's; (k, m): each run's own
    capture_speeds : each run's v_c [m/s] > 0 for the stick–slip contact, shape (k,);
        None for runs of ``model`` alone
    stick_method_name : method of the stick phases
    max_phases : phase-log capacity of each stick–slip run
    """
    times = np.atleast_2d(np.asarray(sample_times, dtype=np.float64))
    k = len(params)
    speeds = np.zeros(k) if capture_speeds is None else np.asarray(capture_speeds, dtype=float)
    points = Points(
        np.array(params),
        np.array(y0, dtype=np.float64, order="C"),
        np.zeros(k),  # no reduction: no reversal band or window read
        np.zeros(k),
        speeds,
    )
    controls = Controls(float(rtol), float(atol), 0.0, 0.0, int(max_steps), True)
    methods_of_phases = (CUDA_METHODS[method_name], CUDA_METHODS[stick_method_name])
    is_hybrid = bool(np.any(speeds > 0.0))
    size = launch_points(
        times.shape[1], max(1, int(max_crossings)), max_phases if is_hybrid else 0, True
    )
    solutions: list[RawSolution] = []
    for start in range(0, k, size):
        part = slice(start, start + size)
        launch = launch_inputs(
            model,
            methods_of_phases,
            Points(*(values[part] for values in points)),
            float(t_end),
            controls,
            times if times.shape[0] == 1 else times[part],
            max_crossings,
            max_phases,
            keeps_runs=True,
        )
        solutions.extend(run_whole(launch))
    return solutions


def _launched(launch: Launch) -> Buffers:
    """The buffers of ``launch`` (at least one point) after its kernel ran: host arrays
    in numba's simulator, else device arrays."""
    k = len(launch.inputs["params"])
    kernel = _kernel(*launch.kernel)
    is_hybrid = launch.kernel[2] != ONE_MODEL
    blocks = (k + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
    if in_simulator():  # the simulator takes host arrays in a tuple as they are
        buffers = launch.host_buffers()
        with _phases_on_thread() if is_hybrid else contextlib.nullcontext():
            kernel[blocks, min(THREADS_PER_BLOCK, k)](launch.run, buffers)
        return buffers
    device = launch.device_buffers()
    with direct_rhs():  # the first launch compiles the kernel (or loads it from the cache)
        kernel[blocks, THREADS_PER_BLOCK](launch.run, device)
    cuda.synchronize()
    return device


def _on_host(values: Any) -> np.ndarray:
    """A launch's array on the host: a device array copied there."""
    return np.asarray(values) if isinstance(values, np.ndarray) else values.copy_to_host()
