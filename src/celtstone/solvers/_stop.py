"""A stop request from Python to a compiled loop that runs in another thread.

The caller of a long run (``solvers._run``, when its progress callback raises or Ctrl-C
arrives) sets the slot ``STAT_STOP_REQUESTED`` of the run's statistics array to 1
(:func:`request_stop`); the run loops (``driver.integrate``, and through it
``phases.run_phases``) read it before each step (:func:`stop_requested`) and return
with ``STATUS_STOPPED``. The read is an atomic load (acquire): a plain load of an array
slot that the loop itself never writes may legally be moved out of the loop by the
optimiser, and the loop would then never see the request. On x86-64 and AArch64 it is
the same instruction as a plain load.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, cast

import numpy as np
from numba import types
from numba.core import cgutils, config
from numba.extending import intrinsic

from celtstone.solvers.codes import STAT_STOP_REQUESTED

_PYTHON = bool(getattr(config, "DISABLE_JIT", 0))  # NUMBA_DISABLE_JIT=1: no compiled code


def request_stop(stats: np.ndarray) -> None:
    """Ask the run that adds to ``stats`` (``Output.stats``) to stop at its next step."""
    stats[STAT_STOP_REQUESTED] = 1


def _stop_requested_python(stats: np.ndarray) -> bool:
    """Whether :func:`request_stop` asked the run adding to ``stats`` to stop."""
    return bool(stats[STAT_STOP_REQUESTED] != 0)


@intrinsic
def _stop_requested(typingctx: Any, stats: Any) -> Any:
    """Whether :func:`request_stop` asked the run adding to ``stats`` (a 1-d int64
    array) to stop: its slot ``STAT_STOP_REQUESTED`` read by an atomic load."""
    if not (isinstance(stats, types.Array) and stats.dtype == types.int64 and stats.ndim == 1):
        return None

    def codegen(context: Any, builder: Any, signature: Any, values: Any) -> Any:
        array_type = signature.args[0]
        array = context.make_array(array_type)(context, builder, values[0])
        slot = context.get_constant(types.intp, STAT_STOP_REQUESTED)
        pointer = cgutils.get_item_pointer(context, builder, array_type, array, [slot])
        value = builder.load_atomic(pointer, "acquire", 8)
        return builder.icmp_signed("!=", value, value.type(0))

    return types.boolean(stats), codegen


stop_requested = cast(
    Callable[[np.ndarray], bool], _stop_requested_python if _PYTHON else _stop_requested
)
