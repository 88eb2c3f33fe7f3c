"""Dormand–Prince 8(5,3): the explicit method of the methods registry (``METHOD_DOP853``).

Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
sec. II.10 (code DOP853). The coefficient tables are SciPy's
(``scipy.integrate._ivp.dop853_coefficients``, kept in ``solvers/tableaux.json``), and the
step-size controller is SciPy's ``DOP853``, so both take the same steps.

The module follows the method contract of ``solvers._methods``: ``workspace``,
``start``, ``attempt``, ``dense``, ``interpolate``, ``ORDER``, ``ERROR_ORDER`` and
``DENSE_EVERY_STEP``.
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

_TABLE = table("dop853")
N_STAGES = int(_TABLE["N_STAGES"])  # 12
N_STAGES_EXTENDED = int(_TABLE["N_STAGES_EXTENDED"])  # 16
A = _TABLE["A"]
B = _TABLE["B"]
C = _TABLE["C"]
E3 = _TABLE["E3"]
E5 = _TABLE["E5"]
D = _TABLE["D"]
ORDER = 8  # of the method: global error O(h^8)
ERROR_ORDER = 7  # of its local error estimate (the 5th- and 3rd-order embedded pair, combined)
DENSE_ROWS = 7
DENSE_EVERY_STEP = False  # the interpolant's 3 stages only for a step that is read
ERROR_EXPONENT = -1.0 / (ERROR_ORDER + 1)  # -1/8, exact in binary


class Workspace(NamedTuple):
    """Arrays of one DOP853 run (n = state length)."""

    stages: np.ndarray  # (N_STAGES_EXTENDED, n): k_s = f(t + c_s h, ...), row 12 = f(t + h, y_new)
    dense: np.ndarray  # (DENSE_ROWS, n): interpolant coefficients of the last accepted step
    scratch: np.ndarray  # (n,)
    error_terms: np.ndarray  # (2, n): the 5th- and 3rd-order error estimates of the trial step


@inlined
def workspace(n):
    """A zeroed workspace for states of length n."""
    return Workspace(
        np.zeros((N_STAGES_EXTENDED, n)), np.zeros((DENSE_ROWS, n)), np.zeros(n), np.zeros((2, n))
    )


# The linear combinations below run their loop over the state's components innermost: the
# sums of different components are independent, so they pipeline (and vectorise), where a
# sum over the stages for one component at a time waits on its own additions. Each
# component's sum still adds its terms in the same order, so the results are the same to
# the last bit.


@kernel
def start(model, params, t, y, f, controls, work, stats):
    """Nothing to prepare: an explicit method keeps no state between runs."""
    return


@kernel
def evaluate_stage(model, params, s, t, y, h, stages, scratch):
    """Stage s: stages[s] = f(t + c_s h, y + h Σ_k a_sk stages[k])."""
    n = y.shape[0]
    scratch[:] = 0.0
    for k in range(s):
        weight = A[s, k]
        if weight != 0.0:  # 16 of the 66: a zero weight's terms are skipped
            for j in range(n):
                scratch[j] += weight * stages[k, j]
    for j in range(n):
        scratch[j] = y[j] + h * scratch[j]
    rhs(model, t + C[s] * h, scratch, params, stages[s])


@kernel
def trial_step(model, params, t, y, h, rtol, atol, stages, y_new, scratch, error_terms):
    """One trial step of size h from (t, y), ``stages[0]`` = f(t, y) on entry.

    Fills ``y_new`` and ``stages[12]`` = f(t + h, y_new); returns the scaled error norm
    and the status code and normal force [N] of that last evaluation.
    """
    n = y.shape[0]
    for s in range(1, N_STAGES):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    y_new[:] = 0.0
    for k in range(N_STAGES):
        weight = B[k]
        if weight != 0.0:
            for j in range(n):
                y_new[j] += weight * stages[k, j]
    for j in range(n):
        y_new[j] = y[j] + h * y_new[j]
    code, normal_force = rhs(model, t + h, y_new, params, stages[N_STAGES])
    error_terms[:, :] = 0.0
    for k in range(N_STAGES + 1):
        weight5 = E5[k]
        weight3 = E3[k]
        if weight5 == 0.0 and weight3 == 0.0:
            continue
        for j in range(n):
            error_terms[0, j] += weight5 * stages[k, j]
            error_terms[1, j] += weight3 * stages[k, j]
    error5 = 0.0
    error3 = 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        error5 += (error_terms[0, j] / scale) ** 2
        error3 += (error_terms[1, j] / scale) ** 2
    if error5 == 0.0 and error3 == 0.0:
        return 0.0, code, normal_force
    return abs(h) * error5 / math.sqrt((error5 + 0.01 * error3) * n), code, normal_force


@inlined
def attempt(model, params, t, y, f, h, t_end, controls, work, y_new, f_new, stats):
    """Step from (t, y) with f = f(t, y), trying h [s] first and shrinking it until the
    error norm is below 1 (SciPy's controller: factor 0.9 err^(-1/8) in [0.2, 10], no
    growth right after a rejection); the step never passes ``t_end``.

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
        work.error_terms,
        y_new,
        f_new,
        stats,
    )


@inlined
def dense(model, params, t, y, y_new, h, work, stats):
    """Coefficients of the 7th-order interpolant over the accepted step [t, t + h]
    (3 extra stages) into ``work.dense``."""
    stages = work.stages
    dense = work.dense
    scratch = work.scratch
    n = y.shape[0]
    stats[STAT_NFEV] += N_STAGES_EXTENDED - N_STAGES - 1
    for s in range(N_STAGES + 1, N_STAGES_EXTENDED):
        evaluate_stage(model, params, s, t, y, h, stages, scratch)
    for j in range(n):
        delta = y_new[j] - y[j]
        dense[0, j] = delta
        dense[1, j] = h * stages[0, j] - delta
        dense[2, j] = 2.0 * delta - h * (stages[N_STAGES, j] + stages[0, j])
    for i in range(4):
        row = dense[3 + i]
        row[:] = 0.0
        for k in range(N_STAGES_EXTENDED):
            weight = D[i, k]
            if weight != 0.0:
                for j in range(n):
                    row[j] += weight * stages[k, j]
        for j in range(n):
            row[j] = h * row[j]


@inlined
def interpolate(dense, y_old, x, out):
    """State at the fraction x in [0, 1] of the last accepted step, which began at y_old,
    from its interpolant's coefficients ``dense`` (``work.dense``)."""
    n = y_old.shape[0]
    out[:] = 0.0
    for i in range(DENSE_ROWS):
        factor = x if i % 2 == 0 else 1.0 - x
        for j in range(n):
            out[j] = (out[j] + dense[DENSE_ROWS - 1 - i, j]) * factor
    for j in range(n):
        out[j] = out[j] + y_old[j]
