"""Verner's efficient 9(8) pair: the high-order explicit method of the registry (``METHOD_VERN9``).

J. H. Verner, "Numerically optimal Runge–Kutta pairs with interpolants", Numer. Algorithms
53 (2010) 383–396: sixteen stages, a 9th-order solution, an embedded 8th-order one for the
error estimate, and an 8th-order interpolant from five more stages, the first of which is
f(t + h, y_new), evaluated anyway for the next step. ``solvers/tableaux.json`` holds the
coefficients; ``tests/test_tableaux.py`` checks their order conditions.

The step-size controller is DOP853's (SciPy's): factor 0.9 err^(-1/9) in [0.2, 10], no
growth right after a rejection. The module follows the method contract of
``solvers._methods``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.solvers._compile import inlined
from celtstone.solvers._step_control import explicit_attempt
from celtstone.solvers._system import rhs
from celtstone.solvers._tableaux import table
from celtstone.solvers.codes import (
    STAT_NFEV,
)

_TABLE = table("vern9")
N_STAGES = int(_TABLE["N_STAGES"])  # 16
N_STAGES_EXTENDED = int(_TABLE["N_STAGES_EXTENDED"])  # 21
A = _TABLE["A"]  # (21, 21); row 16 is B: stage 17 = f(t + h, y_new)
B = _TABLE["B"]  # (16,)
C = _TABLE["C"]  # (21,)
E = _TABLE["E"]  # (16,): the 8th-order weights minus the 9th-order ones
P = _TABLE["P"]  # (21, 8): the interpolant's weight of stage i is sum_j P[i, j] x^(j+1)
P_ROWS = np.ascontiguousarray(P.T)  # (8, 21): row j weighs the stages for x^(j+1)
ORDER = 9
ERROR_ORDER = 8
DENSE_ROWS = 8
DENSE_EVERY_STEP = False
ERROR_EXPONENT = -1.0 / (ERROR_ORDER + 1)


class Workspace(NamedTuple):
    """Arrays of one Verner run (n = state length)."""

    stages: np.ndarray  # (N_STAGES_EXTENDED, n); row 16 = f(t + h, y_new)
    dense: np.ndarray  # (DENSE_ROWS, n): the interpolant's coefficients of x, x², ..., x⁸
    scratch: np.ndarray  # (n,)
    error_term: np.ndarray  # (n,)


@inlined
def workspace(n):
    """A zeroed workspace for states of length n."""
    return Workspace(
        np.zeros((N_STAGES_EXTENDED, n)), np.zeros((DENSE_ROWS, n)), np.zeros(n), np.zeros(n)
    )


@kernel
def start(model, params, t, y, f, controls, work, stats):
    """Nothing to prepare: an explicit method keeps no state between runs."""
    return


@inlined
def weighted_sum(weights, count, stages, out):
    """out = Σ_k weights[k] stages[k] over the first ``count`` stages, in k's order; a zero
    weight's terms are skipped (79 of A's 210 stage weights, 69 of P's 168)."""
    out[:] = 0.0
    for k in range(count):
        weight = weights[k]
        if weight != 0.0:
            for j in range(out.shape[0]):
                out[j] += weight * stages[k, j]


@kernel
def evaluate_stage(model, params, s, t, y, h, stages, scratch):
    """Stage s: stages[s] = f(t + c_s h, y + h Σ_k a_sk stages[k])."""
    weighted_sum(A[s], s, stages, scratch)
    for j in range(y.shape[0]):
        scratch[j] = y[j] + h * scratch[j]
    rhs(model, t + C[s] * h, scratch, params, stages[s])


@kernel
def trial_step(model, params, t, y, h, rtol, atol, stages, y_new, scratch, error_term):
    """One trial step of size h from (t, y), ``stages[0]`` = f(t, y) on entry.

    Fills ``y_new`` and ``stages[16]`` = f(t + h, y_new); returns the scaled RMS error norm
    and the status code and normal force [N] of that last evaluation.
    """
    n = y.shape[0]
    for s in range(1, N_STAGES):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    y_new[:] = 0.0
    error_term[:] = 0.0
    for k in range(N_STAGES):  # both sums in one pass over the stages
        weight = B[k]
        error_weight = E[k]
        for j in range(n):
            y_new[j] += weight * stages[k, j]
            error_term[j] += error_weight * stages[k, j]
    for j in range(n):
        y_new[j] = y[j] + h * y_new[j]
    code, normal_force = rhs(model, t + h, y_new, params, stages[N_STAGES])
    error = 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        error += (error_term[j] / scale) ** 2
    return abs(h) * math.sqrt(error / n), code, normal_force


@inlined
def attempt(model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats):
    """Step from (t, y) with f = f(t, y), trying h [s] first and shrinking it until the
    error norm is below 1; the step never passes ``t_end``.

    Returns (status, h_taken, h_next, rhs status, normal force [N] at y_new); ``y_new`` and
    ``f_new`` = f(t + h_taken, y_new).
    """
    return explicit_attempt(
        trial_step,
        N_STAGES,
        ERROR_EXPONENT,
        model,
        params,
        t,
        y,
        f,
        h,
        t_end,
        controls,
        work.stages,
        work.scratch,
        work.error_term,
        y_new,
        f_new,
        stats,
    )


@inlined
def dense(model, params, t, y, y_new, h, work, stats):
    """Coefficients of the 8th-order interpolant over the accepted step [t, t + h] (4 extra
    stages) into ``work.dense``; the last is set so that the interpolant ends at y_new."""
    stages = work.stages
    dense = work.dense
    scratch = work.scratch
    n = y.shape[0]
    stats[STAT_NFEV] += N_STAGES_EXTENDED - N_STAGES - 1
    for s in range(N_STAGES + 1, N_STAGES_EXTENDED):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    for j in range(n):
        scratch[j] = y_new[j] - y[j]
    for i in range(DENSE_ROWS - 1):
        row = dense[i]
        weighted_sum(P_ROWS[i], N_STAGES_EXTENDED, stages, row)
        for j in range(n):
            row[j] = h * row[j]
            scratch[j] -= row[j]
    for j in range(n):
        dense[DENSE_ROWS - 1, j] = scratch[j]


@inlined
def interpolate(dense, y_old, x, out):
    """State at the fraction x in [0, 1] of the last accepted step, which began at y_old,
    from its interpolant's coefficients ``dense`` (``work.dense``)."""
    n = y_old.shape[0]
    out[:] = 0.0
    for i in range(DENSE_ROWS - 1, -1, -1):
        for j in range(n):
            out[j] = (out[j] + dense[i, j]) * x
    for j in range(n):
        out[j] = out[j] + y_old[j]
