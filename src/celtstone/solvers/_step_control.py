"""Step-size helpers shared by the methods and the driver: error norm, first step, floor."""

from __future__ import annotations

import math

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.kernels.layout import RHS_OK
from celtstone.solvers._compile import inlined
from celtstone.solvers._system import rhs
from celtstone.solvers.codes import (
    STAT_NFEV,
    STAT_REJECTED,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
)

# SciPy's step-size factors for its explicit pairs (``scipy.integrate.DOP853``)
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0


@kernel
def rms_scaled(values, reference, other, rtol, atol):
    """RMS norm of values / (atol + max(|reference|, |other|) rtol) [1]."""
    total = 0.0
    for j in range(values.shape[0]):
        scale = atol + max(abs(reference[j]), abs(other[j])) * rtol
        total += (values[j] / scale) ** 2
    return math.sqrt(total / values.shape[0])


@kernel
def initial_step(model, params, y0, f0, order, rtol, atol, scratch, f1):
    """Hairer's starting step-size heuristic (Solving ODEs I, sec. II.4) [s].

    ``order`` is the method's error order; one right-hand-side evaluation, into ``f1``.
    """
    d0 = rms_scaled(y0, y0, y0, rtol, atol)
    d1 = rms_scaled(f0, y0, y0, rtol, atol)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    for j in range(y0.shape[0]):
        scratch[j] = y0[j] + h0 * f0[j]
    rhs(model, h0, scratch, params, f1)
    for j in range(y0.shape[0]):
        f1[j] -= f0[j]
    d2 = rms_scaled(f1, y0, y0, rtol, atol) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1)


@kernel
def smallest_step(t):
    """The step below which a method gives up at time t: ten units of round-off of t [s]."""
    return 10.0 * abs(np.nextafter(t, np.inf) - t)


@inlined
def explicit_step(error, h_try, rejected, exponent):
    """SciPy's rule for an explicit pair: whether the trial step of size h_try [s] with
    error norm ``error`` is accepted, and the step size to try next [s].

    The next step is h_try 0.9 error^exponent within [0.2, 10] h_try, and at most h_try
    right after a rejection (``rejected``); a non-finite error retries at 0.2 h_try.
    ``exponent`` is -1/(q + 1) for an error estimate of order q.
    """
    if not math.isfinite(error):
        return False, h_try * MIN_FACTOR
    if error < 1.0:
        factor = MAX_FACTOR
        if error != 0.0:
            factor = min(MAX_FACTOR, SAFETY * error**exponent)
        if rejected:
            factor = min(1.0, factor)
        return True, h_try * factor
    return False, h_try * max(MIN_FACTOR, SAFETY * error**exponent)


@inlined
def explicit_attempt(
    trial_step,
    n_stages,
    exponent,
    model,
    params,
    t,
    y,
    f,
    h,
    t_end,
    controls,
    stages,
    scratch,
    error_work,
    y_new,
    f_new,
    stats,
):
    """An explicit pair's step from (t, y) with f = f(t, y): trial steps of ``trial_step`` (the
    method's: ``n_stages`` evaluations, f(t + h, y_new) left in stage row ``n_stages``;
    ``stages``, ``scratch`` and ``error_work`` its workspace's arrays), from h [s] down
    until the error norm is below 1 by :func:`explicit_step` with ``exponent``; the step
    never passes ``t_end``.

    Returns (status, h_taken, h_next, rhs status, normal force [N] at y_new); ``y_new`` and
    ``f_new`` = f(t + h_taken, y_new).
    """
    min_step = smallest_step(t)
    status = STATUS_SUCCESS
    rejected = False
    h_next = h
    h_try = h
    code = RHS_OK
    normal_force = math.nan
    while True:
        if h < min_step:
            status = STATUS_STEP_TOO_SMALL
            break
        h_try = min(h, t_end - t)
        for j in range(f.shape[0]):  # loops, not slices: the same on the CPU, and CUDA
            stages[0, j] = f[j]  # code (benchmarks/gpu_rolling_sweep.py) has no slice copy
        error, code, normal_force = trial_step(
            model,
            params,
            t,
            y,
            h_try,
            controls.rtol,
            controls.atol,
            stages,
            y_new,
            scratch,
            error_work,
        )
        stats[STAT_NFEV] += n_stages
        if not controls.adaptive:
            h_next = h
            break
        accepted, h_proposed = explicit_step(error, h_try, rejected, exponent)
        if accepted:
            h_next = h_proposed
            break
        h = h_proposed
        stats[STAT_REJECTED] += 1
        rejected = True
    for j in range(f_new.shape[0]):
        f_new[j] = stages[n_stages, j]
    return status, h_try, h_next, code, normal_force
