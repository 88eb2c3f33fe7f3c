"""The one place in ``kernels`` that compiles with numba (``_cache`` holds its cache's files).

``kernel`` compiles a module-level function with ``njit(cache=True)`` (``cached_njit``). With
``NUMBA_DISABLE_JIT=1`` numba returns the Python function unchanged, so the
same kernels run (slowly) as plain Python for coverage and debugging.

A user's shape function reaches the compiled, cached kernels as a C function
pointer stored in the int64 field ``level_function`` of the parameter record:
``compile_level_function`` compiles F, ∇F and the Hessian into one C callback,
``call_level_function`` calls it from inside a kernel (docs/decisions.md section 18);
such shapes need the JIT (not ``NUMBA_DISABLE_JIT``).

The first run after installation compiles the kernels (2–3 minutes on a 2-core machine;
numba's on-disk cache serves every later process). So that a user at a terminal does not
take the silence for a hang, the first compilation of a celtstone kernel in a process
says so in one line on standard error when that is a terminal (never in a notebook,
a pipe or a test's captured output): ``COMPILING_NOTICE``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np
from llvmlite import ir
from numba import cfunc, njit, types
from numba.core import cgutils, event
from numba.core.errors import NumbaError
from numba.extending import intrinsic

from celtstone.kernels._cache import use_celtstone_cache

F = TypeVar("F", bound=Callable[..., Any])

LEVEL_OUTPUTS = 13  # F [1], ∇F [1/m] (3), Hessian row-major [1/m²] (9)
HESSIAN_STEP = 1e-5  # central-difference step of the Hessian, relative to the body size
_SIGNATURE = types.void(types.float64, types.float64, types.float64, types.CPointer(types.float64))


COMPILING_NOTICE = (
    "celtstone: compiling the numerical kernels for this machine, once (a few minutes; "
    "later runs read them from numba's cache)"
)


class _CompilingNotice(event.Listener):
    """Prints ``COMPILING_NOTICE`` when a celtstone kernel first compiles (a cache miss:
    numba's "numba:compile" event fires only then), once per process, to a terminal."""

    def __init__(self) -> None:
        self.shown = False

    def on_start(self, event: event.Event) -> None:
        if self.shown:
            return
        function = getattr(event.data.get("dispatcher"), "py_func", None)
        if not getattr(function, "__module__", "").startswith("celtstone."):
            return  # a user's shape function, or numba's own helpers
        self.shown = True
        stream = sys.stderr
        try:
            terminal = stream is not None and stream.isatty()
        except (ValueError, OSError):  # closed, or not a real stream
            terminal = False
        if terminal:
            print(COMPILING_NOTICE, file=stream, flush=True)

    def on_end(self, event: event.Event) -> None:
        pass


COMPILING = _CompilingNotice()
event.register("numba:compile", COMPILING)


def cached_njit(**options: Any) -> Callable[[F], F]:
    """``numba.njit(cache=True, nogil=True, error_model="numpy", **options)``, its on-disk
    cache saved so that processes compiling at once never mix entries, and loaded without
    loading numba's compiler (``_cache``)."""

    def compile_cached(function: F) -> F:
        compiled: F = use_celtstone_cache(
            njit(cache=True, nogil=True, error_model="numpy", **options)(function)
        )
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
