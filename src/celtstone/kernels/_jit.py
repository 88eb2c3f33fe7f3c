"""The one place in ``kernels`` that compiles with numba (``_cache`` holds its cache's files).

``kernel`` compiles a module-level function with ``njit(cache=True)`` (``cached_njit``). With
``NUMBA_DISABLE_JIT=1`` numba returns the Python function unchanged, so the
same kernels run (slowly) as plain Python for coverage and debugging.

A user's shape function reaches the compiled, cached kernels as a C function
pointer stored in the int64 field ``level_function`` of the parameter record:
``compile_level_function`` compiles F, ∇F and the Hessian into one C callback,
``call_level_function`` calls it from inside a kernel (docs/decisions.md section 18);
such shapes need the JIT (not ``NUMBA_DISABLE_JIT``). A table of numbers reaches them the
same way, as the address of its float64 array in an int64 field, read by
``table_entry`` (the elliptic contact's spline table, ``friction_ellipse``): numba
would freeze a global array into every compiled function that reads it.

The first run of a model and method after installation compiles what it calls (tens of
seconds on a 2-core machine; numba's on-disk cache serves every later process). So that
a user at a terminal does not take the silence for a hang, the first compilation of a
celtstone kernel says so in one line on standard error when that is a terminal (never in
a notebook, a pipe or a test's captured output): what compiles and about how long
inside :func:`compiling` (the run loop names its model and method), else
``COMPILING_NOTICE``.
"""

from __future__ import annotations

import contextlib
import ctypes
import sys
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import numpy as np
from llvmlite import ir
from numba import cfunc, njit, types
from numba.core import cgutils, config, event
from numba.core.errors import NumbaError
from numba.extending import intrinsic

from celtstone.kernels._cache import use_celtstone_cache
from celtstone.kernels._internals import internals_changed
from celtstone.kernels._pruning import CodePruningCompiler

F = TypeVar("F", bound=Callable[..., Any])

LEVEL_OUTPUTS = 13  # F [1], ∇F [1/m] (3), Hessian row-major [1/m²] (9)
HESSIAN_STEP = 1e-5  # central-difference step of the Hessian, relative to the body size
_SIGNATURE = types.void(types.float64, types.float64, types.float64, types.CPointer(types.float64))


COMPILING_NOTICE = (
    "celtstone: compiling the numerical kernels for this machine, once (up to a minute; "
    "later runs read them from numba's cache)"
)


def compiling_notice(subject: str, seconds: float) -> str:
    """The line that says what compiles: ``subject`` (e.g. "the sliding model with
    auto") and about how long [s] it takes on a 2-core machine."""
    return (
        f"celtstone: compiling {subject}, about {seconds:.0f} s, once "
        "(later runs read it from numba's cache)"
    )


class _CompilingNotice(event.Listener):
    """Prints a line when a celtstone kernel first compiles (a cache miss: numba's
    "numba:compile" event fires only then), to a terminal: inside :func:`compiling`
    its ``compiling_notice``, once per subject, else ``COMPILING_NOTICE``, once per
    process."""

    def __init__(self) -> None:
        self.shown = False
        self.subject: tuple[str, float] | None = None
        self.subjects_shown: set[str] = set()

    def on_start(self, event: event.Event) -> None:
        function = getattr(event.data.get("dispatcher"), "py_func", None)
        if not getattr(function, "__module__", "").startswith("celtstone."):
            return  # a user's shape function, or numba's own helpers
        if self.subject is not None:
            subject, seconds = self.subject
            if subject in self.subjects_shown:
                return
            self.subjects_shown.add(subject)
            text = compiling_notice(subject, seconds)
        elif self.shown:
            return
        else:
            text = COMPILING_NOTICE
        self.shown = True
        stream = sys.stderr
        try:
            terminal = stream is not None and stream.isatty()
        except (ValueError, OSError):  # closed, or not a real stream
            terminal = False
        if terminal:
            print(text, file=stream, flush=True)

    def on_end(self, event: event.Event) -> None:
        pass


COMPILING = _CompilingNotice()
event.register("numba:compile", COMPILING)


@contextlib.contextmanager
def compiling(subject: str, seconds: float) -> Iterator[None]:
    """Inside, a first compile of a celtstone kernel says it compiles ``subject``, about
    ``seconds`` [s] (``compiling_notice``), on a terminal."""
    previous = COMPILING.subject
    COMPILING.subject = (subject, seconds)
    try:
        yield
    finally:
        COMPILING.subject = previous


def kernel_options() -> dict[str, Any]:
    """The options every kernel compiles with, its cache and pipeline aside (also those of
    an ``overload`` compiled apart): no GIL, numpy's error model, and without numba's
    C-callable wrapper where numba's internals are the ones checked (``_internals``)."""
    options: dict[str, Any] = {"nogil": True, "error_model": "numpy"}
    if not internals_changed():
        options["no_cfunc_wrapper"] = True
    return options


def cached_njit(**options: Any) -> Callable[[F], F]:
    """``numba.njit(cache=True, nogil=True, error_model="numpy", **options)``, its on-disk
    cache saved so that processes compiling at once never mix entries, and loaded without
    loading numba's compiler (``_cache``); compiled without the branches on codes that
    its caller passes as constants (``_pruning``). Both rely on numba's private
    functions: with a numba other than the one they were checked with
    (``_internals``), numba's own cache and compiler.

    Compiled without numba's C-callable wrapper (the option ``no_cfunc_wrapper`` of its
    CPU target, ``_internals``), which only a first-class function value would call: it
    takes about a quarter of the compile of a small function, and a first run compiles a
    hundred or more. A link calls a kernel's own function (``solvers._linking``)."""

    if internals_changed():  # another numba: its own compiler and cache (``_internals``)
        pipeline: dict[str, Any] = {}
    else:
        pipeline = {"pipeline_class": CodePruningCompiler}

    def compile_cached(function: F) -> F:
        dispatcher = njit(cache=True, **kernel_options(), **pipeline, **options)
        compiled: F = dispatcher(function)
        if not internals_changed():
            compiled = use_celtstone_cache(compiled)
        return compiled

    return compile_cached


def kernel(function: F) -> F:
    """Compile ``function`` in nopython mode with the on-disk cache on; called from Python
    it releases the GIL, so a run in a thread leaves the caller free (a progress bar)."""
    return cached_njit()(function)


def inlined_kernel(function: F) -> F:
    """``kernel`` whose body numba inlines at every compiled call site (a thin wrapper
    called once per stage, where the call's reference counting costs more than its body)."""
    return cached_njit(inline="always")(function)


@intrinsic
def call_level_function(typingctx, address, x0, x1, x2):
    """(F, ∇F, H) at (x0, x1, x2) from the C callback at ``address`` (an int64)."""
    result = types.UniTuple(types.float64, LEVEL_OUTPUTS)
    signature = result(types.int64, types.float64, types.float64, types.float64)

    def codegen(context, builder, sig, args):
        pointer, a, b, c = args
        double = ir.DoubleType()
        buffer = cgutils.alloca_once(builder, double, size=LEVEL_OUTPUTS)
        function_type = ir.FunctionType(
            ir.VoidType(), [double, double, double, double.as_pointer()]
        )
        function = builder.inttoptr(pointer, function_type.as_pointer())
        builder.call(function, [a, b, c, buffer])
        index = ir.IntType(32)
        values = [
            builder.load(builder.gep(buffer, [ir.Constant(index, k)])) for k in range(LEVEL_OUTPUTS)
        ]
        return context.make_tuple(builder, result, values)

    return signature, codegen


def _table_entry_in_python(address: int, index: int) -> float:
    """``table_entry`` run as Python (``NUMBA_DISABLE_JIT=1``)."""
    return ctypes.c_double.from_address(address + 8 * index).value


@intrinsic
def _table_entry_compiled(typingctx, address, index):
    """``table_entry`` in compiled code: a load through the address, for numba's CPU and
    CUDA targets alike."""
    if not (isinstance(address, types.Integer) and isinstance(index, types.Integer)):
        return None
    signature = types.float64(types.int64, types.int64)

    def codegen(context, builder, sig, args):
        address, index = args
        start = builder.inttoptr(address, ir.DoubleType().as_pointer())
        value = builder.load(builder.gep(start, [index]))
        # the table never changes while a kernel runs: LLVM may reuse a load, and CUDA
        # may read it through the read-only cache
        value.set_metadata("invariant.load", builder.module.add_metadata([]))
        return value

    return signature, codegen


_PYTHON = bool(getattr(config, "DISABLE_JIT", 0))  # NUMBA_DISABLE_JIT=1: no compiled code
table_entry: Any = _table_entry_in_python if _PYTHON else _table_entry_compiled
"""``table_entry(address, index)``: the float64 at ``index`` (int64) of the C array at
``address`` (int64), a host address on the CPU, a device one on a GPU. The caller keeps
the array alive and the index inside it, and never passes the address 0."""


def jit_user_function(function: Callable[..., Any], parameter: str) -> Any:
    """``function`` compiled by numba (nopython), or a ValueError naming ``parameter``."""
    try:
        compiled = njit(error_model="numpy")(function)
        compiled(np.zeros(3))
    except NumbaError as error:
        lines = [line.strip() for line in str(error).splitlines() if line.strip()]
        reason = next((line for line in lines if not line.startswith("Failed in")), lines[0])
        raise ValueError(f"{parameter}: numba cannot compile it: {reason}") from None
    return compiled


def compile_batch_values(value: Any) -> Any:
    """A compiled loop: ``value`` at each row of points (k, 3) [m] -> (k,)."""

    @njit(error_model="numpy")
    def values(points):
        out = np.empty(points.shape[0])
        for k in range(points.shape[0]):
            out[k] = value(points[k].copy())
        return out

    return values


def differenced_hessian(gradient: Any, step: float) -> Any:
    """A compiled Hessian: the symmetrised central difference of ``gradient``, step [m]."""

    @njit(error_model="numpy")
    def hessian(x):
        shifted = x.copy()
        columns = np.empty((3, 3))
        for j in range(3):
            shifted[j] = x[j] + step
            ahead = gradient(shifted)
            shifted[j] = x[j] - step
            behind = gradient(shifted)
            shifted[j] = x[j]
            for i in range(3):
                columns[i, j] = (ahead[i] - behind[i]) / (2.0 * step)
        return 0.5 * (columns + columns.T)

    return hessian


def compile_level_function(value: Any, gradient: Any, hessian: Any | None, size: float) -> Any:
    """One C callback writing F, ∇F and H at x into a 13-vector (numba ``cfunc``).

    ``value``, ``gradient``, ``hessian`` are numba-compiled functions of x, an array
    of 3 [m]. Without ``hessian`` it is the central difference of ``gradient`` with
    step ``HESSIAN_STEP`` × ``size`` [m], symmetrised (error ~1e-10 relative).
    """
    second = hessian if hessian is not None else differenced_hessian(gradient, HESSIAN_STEP * size)

    @cfunc(_SIGNATURE, error_model="numpy")
    def evaluate(x0, x1, x2, out):
        x = np.empty(3)
        x[0], x[1], x[2] = x0, x1, x2
        out[0] = value(x)
        g = gradient(x)
        h = second(x)
        for i in range(3):
            out[1 + i] = g[i]
            for j in range(3):
                out[4 + 3 * i + j] = h[i, j]

    return evaluate
