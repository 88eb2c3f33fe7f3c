"""The batch driver on a CUDA GPU: one thread per point, the CPU driver's loop and fields.

``run_points`` is ``batch.run_batch`` with ``device="cuda"``: the same points and the
same result array (``batch.FIELDS`` columns, ``batch._reduce``'s numbers), for the
rolling model and the sliding model without stick phases (``CUDA_MODELS``), with every
method (``CUDA_METHODS``). Each thread integrates one point with the code the CPU runs,
compiled by numba for CUDA from the same Python source, so no equation, method, loop or
reduction is written twice:

* the run loop ``driver.run_loop``, which ``driver.integrate`` runs on the CPU: the
  methods' dispatch (``_methods``), so ``auto`` switches between DOP853 and Radau on the
  thread as on the CPU; the events of ``_events``, spin zero crossings located inside
  each step on the method's interpolant, pairs of crossings inside one step included,
  so the reversal counts agree exactly; the samples, filled from the same interpolant;
* the reduction ``batch._reduce`` (reversals with their band and rocking window, final
  spin, energy lost, tilt, normal force, energy budget).

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
CPU's compiled code, and there the thread passes the CPU's system, link included.

The sliding model's kernels choose the contact shape at run time, so every sliding
kernel holds the elliptic contact's table (``kernels.friction_ellipse``, 1.18 MB), which
numba freezes into the code. The CUDA target would put it into constant memory (64 kB);
``declare_for_cuda`` has it put every frozen array above ``CONSTANT_MEMORY_LIMIT`` into
global memory instead, read-only, so the kernel assembles and both contact shapes run.

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
from celtstone.solvers import _auto, _dop853, _radau, _stop, _system, _vern9
from celtstone.solvers import _events as events
from celtstone.solvers import _methods as methods
from celtstone.solvers._compile import inlined
from celtstone.solvers._structures import Controls, Output
from celtstone.solvers.batch import N_FIELDS, Points, _reduce
from celtstone.solvers.codes import (
    METHOD_AUTO,
    METHOD_DOP853,
    METHOD_RADAU5,
    METHOD_VERN9,
    N_STATS,
)
from celtstone.solvers.driver import LoopArrays, copy_into, run_loop

__all__ = [
    "CUDA_METHODS",
    "CUDA_MODELS",
    "CUDA_MODEL_NAMES",
    "KEPT_CROSSINGS",
    "THREADS_PER_BLOCK",
    "Buffers",
    "Run",
    "bytes_per_point",
    "cuda_unavailable_reason",
    "device_name",
    "in_simulator",
    "launch_points",
    "run_points",
]

CUDA_MODELS = (int(ModelCode.ROLLING), int(ModelCode.SLIDING))
"""Model codes a GPU thread runs: rolling, and sliding on its own (no stick phases)."""
CUDA_MODEL_NAMES = tuple(ModelCode(code).name.lower() for code in CUDA_MODELS)
"""Their names, as ``Sweep(model=...)`` takes them."""
CUDA_METHODS = {
    "vern9": METHOD_VERN9,
    "dop853": METHOD_DOP853,
    "radau5": METHOD_RADAU5,
    "auto": METHOD_AUTO,
}
"""Methods a GPU thread runs, by name: every method, Radau's workspace (Jacobian and LU
factors, 8 kB) in the thread's local memory."""
MAX_LAUNCH_POINTS = 262_144  # threads of one launch: more than fill a GPU (§44: 65 536 do)
SIMULATOR_LAUNCH_POINTS = 64  # numba's simulator runs a Python thread per GPU thread
MEMORY_FRACTION = 0.5  # of the GPU's free memory, for one launch's arrays
THREADS_PER_BLOCK = 64  # 32 to 256 made no difference (docs/decisions.md §44)
CONSTANT_MEMORY_LIMIT = 16_384  # [bytes]: a larger frozen array goes to global memory
KEPT_CROSSINGS = 100_000  # crossing times a point keeps where they time reversals, as on the CPU
MAX_EVENT_ROWS = 3  # lift-off, phase change, spin crossing (``_events.event_table``)
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
    (``_structures.Controls``: tolerances, step limit), and in numba's simulator the
    right-hand side's link (``_system.rhs_link``; (0, 0) on a GPU, where the kernels are
    called directly)."""

    t_end: float
    controls: Controls
    rhs_link: tuple[int, int]


class Buffers(NamedTuple):
    """A launch's arrays, k points (on the GPU: device arrays).

    Parameters
    ----------
    params : kernel parameter records, shape (k,)
    initial_states : shape (k, N_STATE)
    reversal_bands : each point's hysteresis half-width [rad/s], shape (k,)
    reversal_windows : each point's rocking window [s], shape (k,)
    table : the run's events (``_events.event_table``)
    sample_times : [s], shape (m,)
    samples : each point's states at the sample times, shape (k, m, N_STATE)
    spins, averaged, cumulative : each point's ``_reduce`` buffers, shape (k, m)
    crossings : each point's spin zero crossing times [s], shape (k, capacity)
    results : each point's result fields (``batch.FIELDS``), shape (k, N_FIELDS)
    radau_memory : each point's Radau scalars (``_radau.MEMORY``), shape (k, 1), as
        ``_radau.workspace`` sets them before a run
    switching : each point's ``auto`` switching record (``_auto.RECORD``), shape (k, 1)
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
    switching: Any


class ThreadWorkspace(NamedTuple):
    """The workspace of either explicit method (the fields of ``_vern9.Workspace`` and
    ``_dop853.Workspace``, which read theirs by name), so that one compiled loop takes
    both."""

    stages: Any  # (MAX_STAGES, N_STATE)
    dense: Any  # (MAX_DENSE_ROWS, N_STATE)
    scratch: Any  # (N_STATE,)
    error_term: Any  # (N_STATE,): Verner's
    error_terms: Any  # (2, N_STATE): DOP853's


def _thread_arrays(method, memory, switching):
    """The ``driver.LoopArrays`` of a thread, in its local memory, as ``driver.integrate``
    makes them before a run: the explicit methods share one ``ThreadWorkspace``; Radau's
    arrays are zeroed (CUDA's local arrays start undefined). Radau's scalars ``memory``
    and ``auto``'s switching record ``switching`` (shape (1,) each) are the launch's,
    set before it (``run_points``)."""
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
    if method == METHOD_RADAU5 or method == METHOD_AUTO:
        for i in range(N_STATE):
            for j in range(N_STATE):
                jacobian[i, j] = 0.0
                lu_real[i, j] = 0.0
                lu_complex[i, j] = 0.0
            pivots[0, i] = 0
            pivots[1, i] = 0
            for k in range(3):
                collocation[k, i] = 0.0
                transformed[k, i] = 0.0
                stage_rates[k, i] = 0.0
                radau_dense[k, i] = 0.0
            vectors[0, i] = 0.0  # the real right-hand side
            complex_rhs[i] = 0.0
    radau = _radau.Workspace(
        jacobian, lu_real, lu_complex, pivots[0], pivots[1], collocation, transformed,
        stage_rates, vectors[0], complex_rhs, vectors[1], vectors[2], vectors[3], vectors[4],
        radau_dense, vectors[5], memory,
    )  # fmt: skip
    # the explicit methods read their workspace's fields by name, which ThreadWorkspace has
    work = methods.Workspaces(explicit, radau, switching, explicit)  # type: ignore[arg-type]
    # by method code (dop853, radau5, auto, vern9), as ``_methods.dense_arrays``; auto
    # takes no step itself
    dense_of = (dense, radau_dense, dense, dense)
    return LoopArrays(loop[0], loop[1], loop[2], loop[3], loop[4], values, work, dense_of)


def _thread(model, method, point, run, buffers):
    """Integrate and reduce point ``point`` of the launch into ``buffers.results[point]``
    with the CPU's loop (``driver.run_loop``) and reduction (``batch._reduce``) (a CUDA
    device function; ``model`` and ``method`` are compile-time constants, so only their
    branches are compiled)."""
    y = cuda.local.array(N_STATE, float64)
    final_state = cuda.local.array(N_STATE, float64)
    stats = cuda.local.array(N_STATS, int64)
    first_time = cuda.local.array(1, float64)
    for j in range(N_STATS):
        stats[j] = 0
    y0 = buffers.initial_states[point]
    copy_into(y, y0)
    params = buffers.params[point]
    output = Output(
        buffers.sample_times, buffers.samples[point], buffers.crossings[point], stats, final_state
    )
    arrays = _arrays_device(method, buffers.radau_memory[point], buffers.switching[point])
    end = run_loop(
        model, method, _system_device(params, run), y, run.t_end, run.controls, buffers.table,
        output, arrays,
    )  # fmt: skip
    reversal = (
        buffers.reversal_bands[point],
        buffers.reversal_windows[point],
        buffers.averaged[point],
        first_time,
        buffers.cumulative[point],
    )
    _reduce(
        model,
        params,
        y0,
        end,
        buffers.sample_times,
        output.samples,
        output.crossings,
        reversal,
        buffers.spins[point],
        arrays.scratch,
        buffers.results[point],
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
    request reads False (``_not_asked``).

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
    }
    modules = [m for n, m in sorted(sys.modules.items()) if n.startswith("celtstone.solvers")]
    replaced: list[tuple[Any, str, Any]] = []
    with global_compiler_lock:
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


def _ensemble_source(model, method, key):  # pragma: no cover - the kernel's template
    """The kernel of ``model`` and ``method`` as a Python closure over three integers
    (numba's cache keys a closure on its cells, which must pickle the same in every
    process: ``key`` is ``SOURCE_KEY``)."""

    def ensemble(run, buffers):
        point: int = cuda.grid(1)  # type: ignore[call-arg]
        if key >= 0 and point < buffers.initial_states.shape[0]:
            _thread_device(model, method, point, run, buffers)

    return ensemble


# ``_thread``, ``_thread_arrays`` and the system's maker as CUDA device functions,
# made by ``_kernel`` (``declare_device_functions``)
_thread_device: Any = None
_arrays_device: Any = None
_system_device: Any = None


@functools.cache
def _kernel(model: int, method: int) -> Any:
    """The CUDA kernel of ``model`` and ``method``, compiled at its first launch or loaded
    from numba's cache."""
    declare_device_functions()
    return cuda.jit(cache=True)(_ensemble_source(model, method, SOURCE_KEY))


def declare_device_functions() -> None:
    """``declare_for_cuda``, and the thread's device functions, once per process."""
    global _thread_device, _arrays_device, _system_device
    declare_for_cuda()
    if _thread_device is None:
        making_system = _system_in_simulator if in_simulator() else _system_on_gpu
        _system_device = cuda.jit(device=True)(making_system)
        _arrays_device = cuda.jit(device=True)(_thread_arrays)
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
    _large_constants_in_global_memory()


def _large_constants_in_global_memory() -> None:
    """Make numba's CUDA target put a frozen array larger than ``CONSTANT_MEMORY_LIMIT``
    into global memory rather than constant memory: the elliptic contact's table
    (``kernels.friction_ellipse``, 1.18 MB) is part of every sliding kernel, since the
    contact shape is chosen at run time, and a GPU has 64 kB of constant memory, which
    ptxas refuses to exceed. The array stays read-only and initialised in the module; a
    smaller one (the methods' tableaux) stays in constant memory."""
    try:
        from numba.cuda import target
        from numba.cuda.cudadrv import nvvm
    except ImportError:  # pragma: no cover - a numba without a CUDA target
        return
    context = target.CUDATargetContext
    original = context.make_constant_array
    if getattr(original, "celtstone_global", False):
        return

    def make_constant_array(self, builder, aryty, arr):
        if np.asarray(arr).nbytes <= CONSTANT_MEMORY_LIMIT:
            return original(self, builder, aryty, arr)
        constant = nvvm.ADDRSPACE_CONSTANT  # read by the original as it emits the global
        nvvm.ADDRSPACE_CONSTANT = nvvm.ADDRSPACE_GLOBAL
        try:
            return original(self, builder, aryty, arr)
        finally:
            nvvm.ADDRSPACE_CONSTANT = constant

    make_constant_array.celtstone_global = True  # type: ignore[attr-defined]
    context.make_constant_array = make_constant_array  # type: ignore[method-assign]


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


def launch_points(n_samples: int, crossing_capacity: int) -> int:
    """Points in one launch: what ``MEMORY_FRACTION`` of the GPU's free memory holds
    (``bytes_per_point``), at most ``MAX_LAUNCH_POINTS`` (``SIMULATOR_LAUNCH_POINTS`` in
    the simulator)."""
    if in_simulator():
        return SIMULATOR_LAUNCH_POINTS
    free, _ = cuda.current_context().get_memory_info()
    fitting = int(MEMORY_FRACTION * free) // bytes_per_point(n_samples, crossing_capacity)
    return max(1, min(MAX_LAUNCH_POINTS, fitting))


def bytes_per_point(n_samples: int, crossing_capacity: int) -> int:
    """GPU memory [bytes] a point of a launch takes: its samples, its ``_reduce``
    buffers, its crossings, its inputs, its method's records and its results."""
    floats = n_samples * (N_STATE + 3) + crossing_capacity + N_STATE + 2 + N_FIELDS
    records = _radau.MEMORY.itemsize + _auto.RECORD.itemsize
    return 8 * floats + records + 1024  # and its parameter record, at most 1 kB


def run_points(
    model: int,
    methods_of_phases: tuple[int, int],
    points: Points,
    t_end: float,
    controls: Controls,
    sample_times: np.ndarray,
    max_crossings: int,
) -> np.ndarray:
    """``batch.run_batch`` with ``device="cuda"``: its points, one thread each, into the
    same result array (``batch.FIELDS`` columns), shape (k, N_FIELDS).

    ``model`` must be one of ``CUDA_MODELS`` and the method (``methods_of_phases[0]``)
    one of ``CUDA_METHODS``; a point of the stick–slip contact (a capture speed > 0) is
    refused. Each point keeps ``max_crossings`` crossing times only where its rocking
    window is 0 (the raw spin's reversals are timed by them); elsewhere the count alone
    is kept, as the CPU reduction reads no more. The caller sizes a launch by
    ``bytes_per_point``.
    """
    method = methods_of_phases[0]
    if model not in CUDA_MODELS or method not in CUDA_METHODS.values():
        raise ValueError(f"no CUDA thread for model {model} with method code {method}")
    if np.any(points.capture_speeds > 0.0):
        raise ValueError("the stick-slip contact has no CUDA thread")
    k = len(points.params)
    if k == 0:
        return np.empty((0, N_FIELDS))
    times = np.ascontiguousarray(sample_times, dtype=np.float64)
    capacity = max(1, int(max_crossings)) if np.any(points.reversal_windows <= 0.0) else 1
    m = times.shape[0]
    inputs = {
        "params": np.ascontiguousarray(points.params),
        "initial_states": points.initial_states,
        "reversal_bands": points.reversal_bands,
        "reversal_windows": points.reversal_windows,
        "table": events.event_table(model, 0.0),
        "sample_times": times,
        # each point's records as a run starts (``_radau.workspace``, ``_auto.workspace``)
        "radau_memory": np.tile(_radau.workspace(0).memory, (k, 1)),
        "switching": np.tile(_auto.workspace(), (k, 1)),
    }
    shapes = {
        "samples": (k, m, N_STATE),
        "spins": (k, m),
        "averaged": (k, m),
        "cumulative": (k, m),
        "crossings": (k, capacity),
        "results": (k, N_FIELDS),
    }
    link = _system.rhs_link(inputs["params"][0]) if in_simulator() else (0, 0)
    run = Run(float(t_end), controls, link)
    kernel = _kernel(model, method)
    blocks = (k + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
    if in_simulator():  # the simulator takes host arrays in a tuple as they are
        buffers = Buffers(**inputs, **{name: np.zeros(s) for name, s in shapes.items()})
        kernel[blocks, min(THREADS_PER_BLOCK, k)](run, buffers)
        return np.asarray(buffers.results)
    device = Buffers(
        **{name: cuda.to_device(values) for name, values in inputs.items()},
        **{name: cuda.device_array(s) for name, s in shapes.items()},
    )
    with direct_rhs():  # the first launch compiles the kernel (or loads it from the cache)
        kernel[blocks, THREADS_PER_BLOCK](run, device)
    cuda.synchronize()
    return device.results.copy_to_host()
