"""Compiled ODE integrators: DOP853 (non-stiff) and Radau IIA order 5 (stiff).

``solve`` allocates the outputs and calls the compiled loop ``driver.integrate``.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from celtstone.errors import ParameterError
from celtstone.solvers.codes import (
    METHOD_DOP853 as METHOD_DOP853,
)
from celtstone.solvers.codes import (
    METHOD_RADAU5 as METHOD_RADAU5,
)
from celtstone.solvers.codes import (
    METHODS as METHODS,
)
from celtstone.solvers.codes import N_STATS, STAT_SAMPLES_WRITTEN
from celtstone.solvers.codes import (
    STATUS_LIFT_OFF as STATUS_LIFT_OFF,
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
    STATUS_SUCCESS as STATUS_SUCCESS,
)
from celtstone.solvers.driver import integrate as integrate

__all__ = [
    "METHODS",
    "METHOD_DOP853",
    "METHOD_RADAU5",
    "STATUS_LIFT_OFF",
    "STATUS_MAX_STEPS",
    "STATUS_MESSAGES",
    "STATUS_NON_CONVEX",
    "STATUS_NOT_FINITE",
    "STATUS_OFF_SHAPE",
    "STATUS_PHASE_CHANGE",
    "STATUS_SINGULAR",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_SUCCESS",
    "RawSolution",
    "integrate",
    "solve",
]


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
    final_state: np.ndarray


def solve(
    model: int,
    method_name: str,
    params: np.ndarray,
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

    ``capture_speed`` [m/s] > 0 stops a sliding run (status ``STATUS_PHASE_CHANGE``)
    when sqrt(|V1|² + ε²(ω·n)²) falls below it; a stick run (``MODEL_STICK``) always
    stops when its stick margin falls below zero. ``final_state`` is the state at
    ``t_stop``. ``progress``, if given, is called about ten times a second from this
    thread with the time [s] reached, while the compiled loop runs in another.
    """
    if method_name not in METHODS:
        raise ParameterError("method", method_name, "one of: " + ", ".join(METHODS))
    times = np.ascontiguousarray(sample_times, dtype=np.float64)
    samples = np.zeros((times.shape[0], y0.shape[0]))
    crossings = np.zeros(max(int(max_crossings), 1))
    stats = np.zeros(N_STATS, dtype=np.int64)
    final_state = np.empty(y0.shape[0])
    arguments = (
        int(model),
        METHODS[method_name],
        np.ascontiguousarray(params, dtype=np.float64),
        np.ascontiguousarray(y0, dtype=np.float64),
        float(t_end),
        float(rtol),
        float(atol),
        float(first_step),
        float(max_step),
        int(max_steps),
        bool(adaptive),
        times,
        samples,
        crossings,
        stats,
        float(capture_speed),
        final_state,
    )
    if progress is None:
        returned = integrate(*arguments)
    else:
        returned = _watched(arguments, times, stats, progress)
    status, n_samples, n_crossings, t_stop, min_normal, t_min_normal = returned
    stored = min(int(n_crossings), crossings.shape[0])
    return RawSolution(
        status=int(status),
        t_stop=float(t_stop),
        sample_times=times[:n_samples].copy(),
        samples=samples[:n_samples].copy(),
        crossings=crossings[:stored].copy(),
        n_crossings_total=int(n_crossings),
        min_normal_force=float(min_normal),
        t_min_normal_force=float(t_min_normal),
        nfev=int(stats[0]),
        njev=int(stats[1]),
        nlu=int(stats[2]),
        n_accepted=int(stats[3]),
        n_rejected=int(stats[4]),
        final_state=final_state,
    )


_POLL_INTERVAL = 0.1  # s between progress reports


def _watched(
    arguments: tuple[Any, ...],
    times: np.ndarray,
    stats: np.ndarray,
    progress: Callable[[float], None],
) -> tuple[Any, ...]:
    """``integrate(*arguments)`` in a daemon thread (the compiled loop releases the GIL),
    reporting the last sample time written; Ctrl-C here abandons the thread."""
    outcome: dict[str, Any] = {}

    def work() -> None:
        try:
            outcome["returned"] = integrate(*arguments)
        except BaseException as error:  # re-raised in the caller's thread
            outcome["error"] = error

    thread = threading.Thread(target=work, name="celtstone-run", daemon=True)
    thread.start()
    while thread.is_alive():
        thread.join(_POLL_INTERVAL)
        written = int(stats[STAT_SAMPLES_WRITTEN])
        progress(float(times[written - 1]) if written > 0 else 0.0)
    if "error" in outcome:
        raise outcome["error"]
    return outcome["returned"]
